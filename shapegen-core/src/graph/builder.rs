//! Building a generator graph at run time.

use std::borrow::Cow;

use super::compiled::Graph;
use super::dist::{Dist, IntDist};
use super::error::GraphErrors;
use super::spec::{Axis, GraphSpec, Limits, NodeSpec, ParamDist, ParamSpec, SlotSpec};

/// Builds a [`GraphSpec`] (and a [`Graph`]) at run time.
///
/// ```
/// use shapegen_core::graph::{Dist, GraphBuilder};
///
/// let graph = GraphBuilder::new("chain")
///     .start("Root")
///     .node("Root", |n| n.slot("first", "Link", 1.0))
///     .node("Link", |n| {
///         n.emits()
///             .param_f32("length", Dist::uniform(0.5, 2.0))
///             .slot("next", "Link", 0.8)
///     })
///     .build()
///     .expect("a valid graph");
/// assert_eq!(graph.node_count(), 2);
/// ```
#[derive(Clone, Debug)]
#[must_use]
pub struct GraphBuilder {
    spec: GraphSpec,
    nodes: Vec<NodeSpec>,
}

impl GraphBuilder {
    /// Starts a graph called `name` with no nodes and no limits.
    pub fn new(name: impl Into<String>) -> Self {
        Self {
            spec: GraphSpec {
                name: Cow::Owned(name.into()),
                nodes: Cow::Borrowed(&[]),
                start: Cow::Borrowed(""),
                limits: Limits::NONE,
            },
            nodes: Vec::new(),
        }
    }

    /// Names the start node.
    pub fn start(mut self, node: impl Into<String>) -> Self {
        self.spec.start = Cow::Owned(node.into());
        self
    }

    /// Sets the limits on derivation trees.
    pub fn limits(mut self, limits: Limits) -> Self {
        self.spec.limits = limits;
        self
    }

    /// Adds a node, configured by `f`.
    pub fn node(
        mut self,
        name: impl Into<String>,
        f: impl FnOnce(NodeBuilder) -> NodeBuilder,
    ) -> Self {
        let node = f(NodeBuilder {
            node: NodeSpec {
                name: Cow::Owned(name.into()),
                params: Cow::Borrowed(&[]),
                slots: Cow::Borrowed(&[]),
                emits: false,
                tags: Cow::Borrowed(&[]),
                split: None,
            },
            params: Vec::new(),
            slots: Vec::new(),
            tags: Vec::new(),
        });
        self.nodes.push(node.finish());
        self
    }

    /// The declaration, unchecked.
    pub fn into_spec(self) -> GraphSpec {
        GraphSpec {
            nodes: Cow::Owned(self.nodes),
            ..self.spec
        }
    }

    /// Checks the declaration and compiles it.
    pub fn build(self) -> Result<Graph, GraphErrors> {
        Graph::new(self.into_spec())
    }
}

/// Configures one node inside [`GraphBuilder::node`].
#[derive(Clone, Debug)]
#[must_use]
pub struct NodeBuilder {
    node: NodeSpec,
    params: Vec<ParamSpec>,
    slots: Vec<SlotSpec>,
    tags: Vec<Cow<'static, str>>,
}

impl NodeBuilder {
    /// Adds a semantic tag (see [`NodeSpec::tags`]); a malformed or repeated
    /// tag is reported by [`GraphBuilder::build`].
    pub fn tag(mut self, tag: impl Into<String>) -> Self {
        self.tags.push(Cow::Owned(tag.into()));
        self
    }

    /// Marks the node as a split node along `axis`: its rule schedules its
    /// children as the parts of [`Scope::split`](crate::express::Scope::split)
    /// (see [`NodeSpec::split`]).
    pub fn split(mut self, axis: Axis) -> Self {
        self.node.split = Some(axis);
        self
    }

    /// Marks the node as emitting geometry.
    pub fn emits(mut self) -> Self {
        self.node.emits = true;
        self
    }

    /// Adds a parameter with any distribution.
    pub fn param(mut self, name: impl Into<String>, dist: ParamDist) -> Self {
        self.params.push(ParamSpec {
            name: Cow::Owned(name.into()),
            dist,
        });
        self
    }

    /// Adds an `f32` parameter.
    pub fn param_f32(self, name: impl Into<String>, dist: Dist) -> Self {
        self.param(name, ParamDist::F32(dist))
    }

    /// Adds a vec2 parameter.
    pub fn param_vec2(self, name: impl Into<String>, dist: [Dist; 2]) -> Self {
        self.param(name, ParamDist::Vec2(dist))
    }

    /// Adds a vec3 parameter.
    pub fn param_vec3(self, name: impl Into<String>, dist: [Dist; 3]) -> Self {
        self.param(name, ParamDist::Vec3(dist))
    }

    /// Adds an integer parameter.
    pub fn param_int(self, name: impl Into<String>, dist: IntDist) -> Self {
        self.param(name, ParamDist::Int(dist))
    }

    /// Adds a discrete-choice parameter with the given option weights.
    pub fn param_choice(self, name: impl Into<String>, weights: impl Into<Vec<f64>>) -> Self {
        self.param(name, ParamDist::Choice(Cow::Owned(weights.into())))
    }

    /// Adds a child slot targeting node `target`, expressed with probability `p`.
    pub fn slot(mut self, name: impl Into<String>, target: impl Into<String>, p: f64) -> Self {
        self.slots.push(SlotSpec {
            name: Cow::Owned(name.into()),
            target: Cow::Owned(target.into()),
            p,
        });
        self
    }

    fn finish(self) -> NodeSpec {
        NodeSpec {
            params: Cow::Owned(self.params),
            slots: Cow::Owned(self.slots),
            tags: Cow::Owned(self.tags),
            ..self.node
        }
    }
}
