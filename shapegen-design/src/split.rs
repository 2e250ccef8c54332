//! Split graphs: the thesis's *split* operation (§4.5, parent annotation).
//!
//! Splitting a node `S` replaces it by one copy per incoming edge: the copy
//! `S<P.slot` receives exactly the children that slot `slot` of node `P`
//! makes (and the start node keeps a copy for the root). Every copy has `S`'s
//! parameters and slots, so a split graph derives exactly the trees of its
//! original, only with more nodes; what it adds is freedom: each copy can
//! have its own slot probabilities and choice weights, so the top and the
//! bottom of a stack, or the first and the later levels of a recursion, need
//! no longer share them.
//!
//! A model of the original graph has exactly one derivation in a split graph
//! ([`SplitGraph::lift`]: each gene's copy follows from its parent's copy and
//! its slot), and a model of the split graph maps back by replacing every
//! copy by its original ([`SplitGraph::to_base`], validated).

use std::borrow::Cow;
use std::collections::BTreeSet;

use shapegen_core::genome::Chromosome;
use shapegen_core::graph::{Graph, GraphSpec, NodeId, NodeSpec, SlotSpec};

use crate::DesignError;

/// A graph whose every node is a copy of a node of a base graph.
#[derive(Clone, Debug)]
pub struct SplitGraph {
    graph: Graph,
    origin: Vec<NodeId>,
}

impl SplitGraph {
    /// The base graph itself, nothing split.
    #[must_use]
    pub fn identity(base: &Graph) -> Self {
        Self {
            graph: base.clone(),
            origin: (0..base.node_count() as NodeId).collect(),
        }
    }

    /// A split graph from a graph whose nodes are copies of `base`'s (e.g. a
    /// learned pdf's component), checking that every node has its
    /// original's parameters and slots, and that every slot leads to a copy
    /// of the original's target.
    pub fn from_parts(
        base: &Graph,
        graph: Graph,
        origin: Vec<NodeId>,
    ) -> Result<Self, DesignError> {
        if origin.len() != graph.node_count() {
            return Err(DesignError::Mismatch {
                what: "split nodes and their origins",
                left: graph.node_count(),
                right: origin.len(),
            });
        }
        for (i, &o) in origin.iter().enumerate() {
            let ours = graph.node(i as NodeId);
            let Some(theirs) = (usize::from(o) < base.node_count()).then(|| base.node(o)) else {
                return Err(DesignError::Invalid(format!(
                    "node `{}` copies unknown node {o}",
                    ours.name
                )));
            };
            let same_params = ours.params.len() == theirs.params.len()
                && ours
                    .params
                    .iter()
                    .zip(theirs.params.iter())
                    .all(|(a, b)| a.name == b.name && a.dist.kind() == b.dist.kind());
            let same_slots = ours.slots.len() == theirs.slots.len()
                && (0..ours.slots.len() as u32).all(|j| {
                    ours.slots[j as usize].name == theirs.slots[j as usize].name
                        && origin[usize::from(graph.edge(i as NodeId, j).to)] == base.edge(o, j).to
                });
            if !same_params || !same_slots || ours.emits != theirs.emits {
                return Err(DesignError::Invalid(format!(
                    "node `{}` is not a copy of `{}` (parameters, slots or targets differ)",
                    ours.name, theirs.name
                )));
            }
        }
        if origin[usize::from(graph.start())] != base.start() {
            return Err(DesignError::Invalid(
                "the start node is not a copy of the base's start".into(),
            ));
        }
        Ok(Self { graph, origin })
    }

    /// The split graph.
    #[must_use]
    pub fn graph(&self) -> &Graph {
        &self.graph
    }

    /// For each node of the split graph, the base node it copies.
    #[must_use]
    pub fn origin(&self) -> &[NodeId] {
        &self.origin
    }

    /// Splits `nodes` (ids of this split graph) all at once by their
    /// incoming edges. Nodes without incoming edges (only the start can be
    /// one) are left alone.
    pub fn split(&self, nodes: &[NodeId]) -> Result<Self, DesignError> {
        let g = &self.graph;
        let split: BTreeSet<NodeId> = nodes.iter().copied().collect();
        // Incoming edges of each split node, in edge order.
        let incoming = |s: NodeId| -> Vec<(NodeId, u32)> {
            g.edges()
                .iter()
                .filter(|e| e.to == s)
                .map(|e| (e.from, u32::from(e.slot)))
                .collect()
        };
        // New nodes: (old node, incoming edge or None for the kept/root copy).
        let mut copies: Vec<(NodeId, Option<(NodeId, u32)>)> = Vec::new();
        for n in 0..g.node_count() as NodeId {
            let inc = incoming(n);
            if split.contains(&n) && !inc.is_empty() {
                if n == g.start() {
                    copies.push((n, None));
                }
                copies.extend(inc.into_iter().map(|e| (n, Some(e))));
            } else {
                copies.push((n, None));
            }
        }
        let name_of = |(n, e): (NodeId, Option<(NodeId, u32)>)| -> String {
            let base = g.node(n).name.to_string();
            match e {
                None => base,
                Some((p, j)) => format!(
                    "{base}<{}.{}",
                    g.node(p).name,
                    g.node(p).slots[j as usize].name
                ),
            }
        };
        let names: Vec<String> = copies.iter().map(|&c| name_of(c)).collect();
        // The copy a slot leads to: the target's copy for this (old parent, slot).
        let target_of = |p: NodeId, j: u32| -> String {
            let t = g.edge(p, j).to;
            let key = if split.contains(&t) && !incoming(t).is_empty() {
                Some((p, j))
            } else {
                None
            };
            name_of((t, key))
        };
        let spec_nodes: Vec<NodeSpec> = copies
            .iter()
            .zip(&names)
            .map(|(&(n, _), name)| {
                let old = g.node(n);
                NodeSpec {
                    tags: old.tags.clone(),
                    name: Cow::Owned(name.clone()),
                    params: old.params.clone(),
                    slots: Cow::Owned(
                        old.slots
                            .iter()
                            .enumerate()
                            .map(|(j, s)| SlotSpec {
                                name: s.name.clone(),
                                target: Cow::Owned(target_of(n, j as u32)),
                                p: s.p,
                            })
                            .collect(),
                    ),
                    emits: old.emits,
                    split: old.split,
                }
            })
            .collect();
        let spec = GraphSpec {
            name: g.spec().name.clone(),
            nodes: Cow::Owned(spec_nodes),
            start: Cow::Owned(g.node(g.start()).name.to_string()),
            limits: *g.limits(),
        };
        let graph = Graph::new(spec)?;
        let origin = copies
            .iter()
            .map(|&(n, _)| self.origin[usize::from(n)])
            .collect();
        Ok(Self { graph, origin })
    }

    /// The split-graph node of every gene of `model` (a base-graph model), in
    /// gene (buffer) order: the model's unique derivation in this graph.
    #[must_use]
    pub fn lift(&self, base: &Graph, model: &Chromosome) -> Vec<NodeId> {
        let positions = model.positions();
        let mut ids: Vec<NodeId> = Vec::with_capacity(model.len());
        for g in model.genes(base) {
            let id = match g.parent() {
                None => self.graph.start(),
                Some(p) => {
                    let parent = ids[positions.partition_point(|&x| x < p)];
                    self.graph.edge(parent, g.slot_in_parent()).to
                }
            };
            debug_assert_eq!(self.origin[usize::from(id)], g.node());
            ids.push(id);
        }
        ids
    }

    /// `model` (a base-graph model) as a model of this split graph.
    pub fn to_split(&self, base: &Graph, model: &Chromosome) -> Result<Chromosome, DesignError> {
        let ids = self.lift(base, model);
        let mut next = ids.into_iter();
        Ok(model.relabel(&self.graph, |_| next.next().unwrap_or(NodeId::MAX))?)
    }

    /// A model of this split graph as a model of the base graph, validated
    /// against it.
    pub fn to_base(&self, base: &Graph, model: &Chromosome) -> Result<Chromosome, DesignError> {
        Ok(model.relabel(base, |n| {
            self.origin
                .get(usize::from(n))
                .copied()
                .unwrap_or(NodeId::MAX)
        })?)
    }
}
