//! Expressing a graph built at run time: one dynamically dispatched rule per node.

use std::borrow::Cow;

use glam::{Affine3A, Vec2, Vec3};

use crate::genome::{Chromosome, Gene};
use crate::graph::{Axis, Graph, ParamKind};

use super::{Scope, SplitSize};

use super::generator::Generator;
use super::node_out::{NodeOut, SlotRef};
use super::pending::Pending;
use super::sink::{ModelSink, ShapeId};

/// A node's operation at run time: reads the gene's parameters by name,
/// transforms the incoming state, emits geometry and schedules children.
pub type Rule<St> = Box<dyn Fn(&RuleInput<'_>, St, &mut RuleOutput<'_, St>) + Send + Sync>;

/// A [`Generator`] whose node operations are closures given at run time.
///
/// It is the counterpart of the `generator!` macro for graphs built with
/// [`GraphBuilder`](crate::graph::GraphBuilder): parameters and slots are
/// looked up by name and rules called through `dyn`, so it is slower than
/// macro-generated code, but needs no compile-time declaration.
///
/// ```
/// use shapegen_core::express::{Generator, Instances, Interpreter, Scope};
/// use shapegen_core::prelude::*;
///
/// let graph = GraphBuilder::new("tower")
///     .start("Floor")
///     .node("Floor", |n| n.emits().param_f32("height", Dist::uniform(1.0, 2.0)).slot("up", "Floor", 0.5))
///     .build()?;
/// let tower = Interpreter::new(graph, ["cube"], Scope::UNIT)
///     .rule("Floor", |input, mut scope, out| {
///         let h = input.f32("height");
///         scope.size.y = h;
///         scope.move_y(h / 2.0);
///         out.emit("cube", scope.instance());
///         scope.move_y(h / 2.0);
///         out.child("up", scope);
///     })
///     .build()?;
/// let mut rng = shapegen_core::rng::stream(1, &[]);
/// let c = random_individual(tower.graph(), &InitLength::Fixed { l0: 3 }, &mut rng)?;
/// let mut model = Instances::default();
/// tower.express(&c, &mut model);
/// assert_eq!(model.0.len(), c.len());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct Interpreter<St = super::Scope> {
    graph: Graph,
    shapes: Vec<Cow<'static, str>>,
    axiom: St,
    rules: Vec<Option<Rule<St>>>,
    errors: Vec<ExpressError>,
}

/// A problem with an [`Interpreter`]'s rules.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ExpressError {
    /// A rule names a node the graph does not have.
    #[error("a rule is given for `{0}`, which is not a node of the graph")]
    UnknownNode(String),
    /// Two rules for one node.
    #[error("node `{0}` has more than one rule")]
    DuplicateRule(String),
    /// A node without a rule.
    #[error("node `{0}` has no rule")]
    MissingRule(String),
}

/// Every problem found by [`Interpreter::build`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ExpressErrors(pub Vec<ExpressError>);

impl std::fmt::Display for ExpressErrors {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "invalid interpreter rules:")?;
        for e in &self.0 {
            write!(f, "\n  - {e}")?;
        }
        Ok(())
    }
}

impl std::error::Error for ExpressErrors {}

impl<St> std::fmt::Debug for Interpreter<St> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Interpreter")
            .field("graph", &self.graph.name())
            .field("shapes", &self.shapes)
            .finish()
    }
}

impl<St: Clone + Send + Sync> Interpreter<St> {
    /// An interpreter for `graph` emitting the named `shapes`, starting from `axiom`.
    pub fn new<S: Into<Cow<'static, str>>>(
        graph: Graph,
        shapes: impl IntoIterator<Item = S>,
        axiom: St,
    ) -> Self {
        let rules = (0..graph.node_count()).map(|_| None).collect();
        Self {
            graph,
            shapes: shapes.into_iter().map(Into::into).collect(),
            axiom,
            rules,
            errors: Vec::new(),
        }
    }

    /// Sets the rule of node `node`.
    #[must_use]
    pub fn rule(
        mut self,
        node: &str,
        rule: impl Fn(&RuleInput<'_>, St, &mut RuleOutput<'_, St>) + Send + Sync + 'static,
    ) -> Self {
        match self.graph.node_id(node) {
            None => self
                .errors
                .push(ExpressError::UnknownNode(node.to_string())),
            Some(id) => {
                if self.rules[id as usize].replace(Box::new(rule)).is_some() {
                    self.errors
                        .push(ExpressError::DuplicateRule(node.to_string()));
                }
            }
        }
        self
    }

    /// Checks that every node has exactly one rule.
    pub fn build(mut self) -> Result<Self, ExpressErrors> {
        for (i, r) in self.rules.iter().enumerate() {
            if r.is_none() {
                self.errors.push(ExpressError::MissingRule(
                    self.graph.node(i as u16).name.to_string(),
                ));
            }
        }
        if self.errors.is_empty() {
            Ok(self)
        } else {
            Err(ExpressErrors(self.errors))
        }
    }
}

impl<St: Clone + Send + Sync> Generator for Interpreter<St> {
    type State = St;

    fn graph(&self) -> &Graph {
        &self.graph
    }

    fn shapes(&self) -> &[Cow<'static, str>] {
        &self.shapes
    }

    fn axiom(&self) -> St {
        self.axiom.clone()
    }

    fn express_with<S: ModelSink>(
        &self,
        chromosome: &Chromosome,
        sink: &mut S,
        stack: &mut Pending<St>,
    ) {
        self.express_from(chromosome, 0, self.axiom.clone(), sink, stack);
    }

    fn express_gene<S: ModelSink>(
        &self,
        chromosome: &Chromosome,
        pos: u32,
        state: St,
        sink: &mut S,
        children: &mut Pending<St>,
    ) {
        let gene = chromosome.gene(&self.graph, pos);
        let Some(rule) = &self.rules[gene.node() as usize] else {
            return;
        };
        let input = RuleInput {
            graph: &self.graph,
            gene,
        };
        let mut out = RuleOutput {
            gene,
            graph: &self.graph,
            shapes: &self.shapes,
            sink,
            stack: children,
        };
        rule(&input, state, &mut out);
    }
}

fn kind_name(kind: ParamKind) -> &'static str {
    match kind {
        ParamKind::F32 => "an f32",
        ParamKind::Vec2 => "a vec2",
        ParamKind::Vec3 => "a vec3",
        ParamKind::Int => "an int",
        ParamKind::Choice => "a choice",
    }
}

fn accessor(kind: ParamKind) -> &'static str {
    match kind {
        ParamKind::F32 => "f32",
        ParamKind::Vec2 => "vec2",
        ParamKind::Vec3 => "vec3",
        ParamKind::Int => "int",
        ParamKind::Choice => "choice",
    }
}

/// What a rule reads: the gene's parameters, by name.
#[derive(Clone, Copy, Debug)]
pub struct RuleInput<'a> {
    graph: &'a Graph,
    gene: Gene<'a>,
}

impl RuleInput<'_> {
    /// The index of parameter `name`, which must be of kind `kind`: a rule
    /// reading a parameter as the wrong type would get its bits
    /// reinterpreted (an int 6 read as an `f32` is 8e-45), so it panics
    /// with what the parameter is and which accessor to use.
    fn index(&self, name: &str, kind: ParamKind) -> usize {
        let node = self.graph.node(self.gene.node());
        let (i, p) = node
            .params
            .iter()
            .enumerate()
            .find(|(_, p)| p.name == name)
            .unwrap_or_else(|| panic!("node `{}` has no parameter `{name}`", node.name));
        let found = p.dist.kind();
        if found != kind {
            panic!(
                "parameter `{name}` of node `{}` is {}, not {}: read it with `input.{}(\"{name}\")`",
                node.name,
                kind_name(found),
                kind_name(kind),
                accessor(found)
            );
        }
        i
    }

    /// The `f32` parameter `name`. Panics if the node has no such parameter
    /// or it is of another kind.
    #[must_use]
    pub fn f32(&self, name: &str) -> f32 {
        self.gene.param_f32(self.index(name, ParamKind::F32))
    }

    /// The vec2 parameter `name` (panics like [`f32`](Self::f32)).
    #[must_use]
    pub fn vec2(&self, name: &str) -> Vec2 {
        Vec2::from(self.gene.param_vec2(self.index(name, ParamKind::Vec2)))
    }

    /// The vec3 parameter `name` (panics like [`f32`](Self::f32)).
    #[must_use]
    pub fn vec3(&self, name: &str) -> Vec3 {
        Vec3::from(self.gene.param_vec3(self.index(name, ParamKind::Vec3)))
    }

    /// The integer parameter `name` (panics like [`f32`](Self::f32)).
    #[must_use]
    pub fn int(&self, name: &str) -> i32 {
        self.gene.param_int(self.index(name, ParamKind::Int))
    }

    /// The choice parameter `name`, an option index (panics like [`f32`](Self::f32)).
    #[must_use]
    pub fn choice(&self, name: &str) -> u32 {
        self.gene.param_choice(self.index(name, ParamKind::Choice))
    }

    /// The gene being expressed.
    #[must_use]
    pub fn gene(&self) -> Gene<'_> {
        self.gene
    }
}

/// What a rule produces: instances and the states of its expressed children.
pub struct RuleOutput<'a, St> {
    gene: Gene<'a>,
    graph: &'a Graph,
    shapes: &'a [Cow<'static, str>],
    sink: &'a mut dyn ModelSink,
    stack: &'a mut Pending<St>,
}

impl<St> RuleOutput<'_, St> {
    /// Emits shape `shape` (by name) placed by `transform`. Panics on an unknown shape.
    pub fn emit(&mut self, shape: &str, transform: Affine3A) {
        let id = self
            .shapes
            .iter()
            .position(|s| s == shape)
            .unwrap_or_else(|| panic!("unknown shape `{shape}`"));
        self.sink
            .emit_from(self.gene.node(), id as ShapeId, &transform);
    }

    /// Passes `state` to the child in slot `slot` (by name), if it is expressed.
    /// Panics on an unknown slot.
    pub fn child(&mut self, slot: &str, state: St) {
        self.express_child(
            SlotRef {
                index: usize::MAX,
                name: slot,
                element: 0,
            },
            state,
        );
    }

    /// Splits `scope` along `axis` into the parts of `sizes` (see
    /// [`Scope::split`]) and tells the sink, as `split!` does: a rule of a
    /// node built with [`NodeBuilder::split`](crate::graph::NodeBuilder::split)
    /// schedules its children as these parts, in order.
    pub fn split(&mut self, scope: &Scope, axis: Axis, sizes: &[SplitSize]) -> Vec<(usize, Scope)> {
        self.split_scope(axis, scope);
        scope.split(axis, sizes)
    }

    /// Whether the child in slot `slot` (by name) is expressed. Panics on an unknown slot.
    #[must_use]
    pub fn has_child(&self, slot: &str) -> bool {
        self.is_expressed(SlotRef {
            index: usize::MAX,
            name: slot,
            element: 0,
        })
    }

    /// The slot's index, found by name (`name`, or `name[0]` plus the
    /// element for a slot array).
    fn slot_by_name(&self, slot: SlotRef<'_>) -> usize {
        let node = self.graph.node(self.gene.node());
        let first = node.slots.iter().position(|s| {
            s.name == slot.name
                || (s.name.starts_with(slot.name) && &s.name[slot.name.len()..] == "[0]")
        });
        match first {
            Some(j) if j + slot.element < node.slots.len() => j + slot.element,
            _ => panic!("node `{}` has no slot `{}`", node.name, slot.name),
        }
    }
}

impl<St> NodeOut<St> for RuleOutput<'_, St> {
    /// Looks the shape up by name, as the interpreter does.
    fn emit_shape(&mut self, _: ShapeId, name: &str, transform: Affine3A) {
        self.emit(name, transform);
    }

    /// Looks the slot up by name, as the interpreter does.
    fn express_child(&mut self, slot: SlotRef<'_>, state: St) {
        let j = self.slot_by_name(slot);
        if let Some(pos) = self.gene.child(j) {
            self.stack.push(pos, state);
        }
    }

    fn is_expressed(&self, slot: SlotRef<'_>) -> bool {
        self.gene.child(self.slot_by_name(slot)).is_some()
    }

    fn split_scope(&mut self, axis: Axis, scope: &Scope) {
        self.sink.split(self.gene.node(), axis, scope);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::express::{Instances, Scope};
    use crate::graph::{GraphBuilder, IntDist};

    fn counter() -> Interpreter {
        let graph = GraphBuilder::new("counter")
            .start("Row")
            .node("Row", |n| {
                n.emits().param_int("count", IntDist::uniform(6, 6))
            })
            .build()
            .unwrap();
        Interpreter::new(graph, ["cube"], Scope::UNIT)
            .rule("Row", |input, scope, out| {
                // Reads the int as an f32: a mistake that must not pass silently.
                let width = input.f32("count");
                out.emit(
                    "cube",
                    scope.translated(Vec3::new(width, 0.0, 0.0)).instance(),
                );
            })
            .build()
            .unwrap()
    }

    #[test]
    #[should_panic(
        expected = "parameter `count` of node `Row` is an int, not an f32: read it with `input.int(\"count\")`"
    )]
    fn reading_a_parameter_as_another_kind_fails_loudly() {
        let g = counter();
        let c = crate::ops::default_model(g.graph()).unwrap();
        g.express(&c, &mut Instances::default());
    }

    #[test]
    fn int_distributions_have_constructors() {
        assert_eq!(IntDist::uniform(1, 3), IntDist::Uniform { lo: 1, hi: 3 });
        assert_eq!(IntDist::constant(4), IntDist::Constant { value: 4 });
    }
}
