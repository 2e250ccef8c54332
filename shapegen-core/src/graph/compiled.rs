//! [`Graph`]: a checked [`GraphSpec`] with the lookup tables the genome needs.

use std::collections::{HashMap, HashSet};

use super::error::{GraphError, GraphErrors};
use super::spec::{GraphSpec, Limits, NodeSpec};

/// Index of a node in its graph (a gene stores it in 16 bits).
pub type NodeId = u16;

/// Index of an edge (one child slot of one node) in its graph.
pub type EdgeId = u32;

/// Largest number of nodes a graph may have.
pub const MAX_NODES: usize = u16::MAX as usize;
/// Largest number of slots a node may have.
pub const MAX_SLOTS: usize = u8::MAX as usize;

/// Where things live inside the genes of one node.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct NodeLayout {
    /// Number of child slots `S`.
    pub slots: u32,
    /// Number of parameter words `P`.
    pub param_words: u32,
    /// Gene size in words: `2 + S + P`.
    pub gene_words: u32,
    /// Id of this node's first edge; slot `j` is edge `first_edge + j`.
    pub first_edge: EdgeId,
    /// Word offset of each parameter within the parameter block.
    pub param_offsets: Vec<u32>,
}

/// One edge of the graph: a slot of a node, resolved.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Edge {
    /// The node owning the slot.
    pub from: NodeId,
    /// The slot's index within its node.
    pub slot: u8,
    /// The node a child on this edge has.
    pub to: NodeId,
    /// The probability `p` that an uncontrolled generation expresses it.
    pub p: f64,
}

/// A checked generator graph, ready for genomes, operators and optimizers.
///
/// Build it once from a [`GraphSpec`]; it is immutable and `Sync`.
#[derive(Clone, Debug)]
pub struct Graph {
    spec: GraphSpec,
    layouts: Vec<NodeLayout>,
    edges: Vec<Edge>,
    /// Per edge: `p` in fixed point ([`WEIGHT_ONE`] = 1), the grow weight.
    grow_weights: Vec<u64>,
    /// Per edge: `1 − p` in fixed point, the cut weight.
    cut_weights: Vec<u64>,
    start: NodeId,
    max_slots: u32,
    fingerprint: u64,
}

/// Fixed-point one for operator weights: probabilities are used as integers
/// `round(p · 2³²)`, so weight sums are exact and need no floating-point
/// dependency chain (a relative error of at most 2⁻³³ per probability).
pub const WEIGHT_ONE: u64 = 1 << 32;

fn fixed(p: f64) -> u64 {
    (p.clamp(0.0, 1.0) * WEIGHT_ONE as f64).round() as u64
}

impl Graph {
    /// Checks `spec` and builds the lookup tables, reporting every problem at once.
    pub fn new(spec: GraphSpec) -> Result<Self, GraphErrors> {
        let errors = check(&spec);
        if !errors.is_empty() {
            return Err(GraphErrors(errors));
        }
        let ids: HashMap<&str, NodeId> = spec
            .nodes
            .iter()
            .enumerate()
            .map(|(i, n)| (n.name.as_ref(), i as NodeId))
            .collect();
        let mut layouts = Vec::with_capacity(spec.nodes.len());
        let mut edges = Vec::new();
        for (i, node) in spec.nodes.iter().enumerate() {
            let mut param_offsets = Vec::with_capacity(node.params.len());
            let mut param_words = 0u32;
            for p in node.params.iter() {
                param_offsets.push(param_words);
                param_words += p.dist.kind().words() as u32;
            }
            let slots = node.slots.len() as u32;
            layouts.push(NodeLayout {
                slots,
                param_words,
                gene_words: 2 + slots + param_words,
                first_edge: edges.len() as EdgeId,
                param_offsets,
            });
            for (j, s) in node.slots.iter().enumerate() {
                edges.push(Edge {
                    from: i as NodeId,
                    slot: j as u8,
                    to: ids[s.target.as_ref()],
                    p: s.p,
                });
            }
        }
        let start = ids[spec.start.as_ref()];
        let fingerprint = fingerprint(&spec);
        let layouts_max_slots = layouts.iter().map(|l| l.slots).max().unwrap_or(0);
        let grow_weights = edges.iter().map(|e| fixed(e.p)).collect();
        let cut_weights = edges.iter().map(|e| WEIGHT_ONE - fixed(e.p)).collect();
        Ok(Self {
            spec,
            layouts,
            edges,
            grow_weights,
            cut_weights,
            start,
            max_slots: layouts_max_slots,
            fingerprint,
        })
    }

    /// The declaration this graph was built from.
    #[must_use]
    pub fn spec(&self) -> &GraphSpec {
        &self.spec
    }

    /// The generator's name.
    #[must_use]
    pub fn name(&self) -> &str {
        &self.spec.name
    }

    /// Number of nodes.
    #[must_use]
    pub fn node_count(&self) -> usize {
        self.layouts.len()
    }

    /// The declaration of node `id`.
    #[must_use]
    pub fn node(&self, id: NodeId) -> &NodeSpec {
        &self.spec.nodes[id as usize]
    }

    /// The id of the node called `name`.
    #[must_use]
    pub fn node_id(&self, name: &str) -> Option<NodeId> {
        self.spec
            .nodes
            .iter()
            .position(|n| n.name == name)
            .map(|i| i as NodeId)
    }

    /// The gene layout of node `id`.
    #[inline]
    #[must_use]
    pub fn layout(&self, id: NodeId) -> &NodeLayout {
        &self.layouts[id as usize]
    }

    /// All edges, indexed by [`EdgeId`].
    #[must_use]
    pub fn edges(&self) -> &[Edge] {
        &self.edges
    }

    /// Gene size in words of node `id` (hot-path shortcut for `layout(id).gene_words`).
    #[inline]
    #[must_use]
    pub fn gene_words(&self, id: NodeId) -> usize {
        self.layouts[id as usize].gene_words as usize
    }

    /// Per edge, the fixed-point grow weight `p` (see [`WEIGHT_ONE`]).
    #[inline]
    #[must_use]
    pub fn grow_weights(&self) -> &[u64] {
        &self.grow_weights
    }

    /// Per edge, the fixed-point cut weight `1 − p` (see [`WEIGHT_ONE`]).
    #[inline]
    #[must_use]
    pub fn cut_weights(&self) -> &[u64] {
        &self.cut_weights
    }

    /// The largest number of slots of any node.
    #[inline]
    #[must_use]
    pub fn max_slots(&self) -> u32 {
        self.max_slots
    }

    /// The edge of slot `slot` of node `node`.
    #[inline]
    #[must_use]
    pub fn edge(&self, node: NodeId, slot: u32) -> &Edge {
        &self.edges[(self.layouts[node as usize].first_edge + slot) as usize]
    }

    /// The start node.
    #[must_use]
    pub fn start(&self) -> NodeId {
        self.start
    }

    /// The limits on derivation trees.
    #[must_use]
    pub fn limits(&self) -> &Limits {
        &self.spec.limits
    }

    /// Whether node `id` emits geometry.
    #[must_use]
    pub fn emits(&self, id: NodeId) -> bool {
        self.spec.nodes[id as usize].emits
    }

    /// A hash of the graph's structure (node names, parameter kinds, slots and
    /// their targets), stored with saved chromosomes to refuse foreign ones.
    #[must_use]
    pub fn fingerprint(&self) -> u64 {
        self.fingerprint
    }
}

pub(super) fn check(spec: &GraphSpec) -> Vec<GraphError> {
    let mut errors = Vec::new();
    let nodes = &spec.nodes;
    if nodes.is_empty() {
        errors.push(GraphError::NoNodes);
    }
    if nodes.len() > MAX_NODES {
        errors.push(GraphError::TooManyNodes {
            count: nodes.len(),
            max: MAX_NODES,
        });
    }
    let mut seen = HashSet::new();
    for n in nodes.iter() {
        if !seen.insert(n.name.as_ref()) {
            errors.push(GraphError::DuplicateNode {
                node: n.name.to_string(),
            });
        }
    }
    for n in nodes.iter() {
        let node = || n.name.to_string();
        let mut params = HashSet::new();
        for p in n.params.iter() {
            if !params.insert(p.name.as_ref()) {
                errors.push(GraphError::DuplicateParam {
                    node: node(),
                    param: p.name.to_string(),
                });
            }
            if let Some(reason) = p.dist.problem() {
                errors.push(GraphError::EmptySupport {
                    node: node(),
                    param: p.name.to_string(),
                    reason,
                });
            }
        }
        let mut tags = HashSet::new();
        for t in n.tags.iter() {
            if let Some(reason) = super::spec::check_tag(t) {
                errors.push(GraphError::BadTag {
                    node: node(),
                    tag: t.to_string(),
                    reason,
                });
            } else if !tags.insert(t.as_ref()) {
                errors.push(GraphError::DuplicateTag {
                    node: node(),
                    tag: t.to_string(),
                });
            }
        }
        if n.slots.len() > MAX_SLOTS {
            errors.push(GraphError::TooManySlots {
                node: node(),
                count: n.slots.len(),
                max: MAX_SLOTS,
            });
        }
        let mut slots = HashSet::new();
        for s in n.slots.iter() {
            if !slots.insert(s.name.as_ref()) {
                errors.push(GraphError::DuplicateSlot {
                    node: node(),
                    slot: s.name.to_string(),
                });
            }
            if !seen.contains(s.target.as_ref()) {
                errors.push(GraphError::UnknownTarget {
                    node: node(),
                    slot: s.name.to_string(),
                    target: s.target.to_string(),
                });
            }
            if !(0.0..=1.0).contains(&s.p) {
                errors.push(GraphError::BadProbability {
                    node: node(),
                    slot: s.name.to_string(),
                    p: s.p,
                });
            }
        }
    }
    if spec.start.is_empty() {
        errors.push(GraphError::NoStart);
    } else if !seen.contains(spec.start.as_ref()) {
        errors.push(GraphError::UnknownStart {
            start: spec.start.to_string(),
        });
    } else {
        // Reachability from the start node through slots.
        let index: HashMap<&str, usize> = nodes
            .iter()
            .enumerate()
            .map(|(i, n)| (n.name.as_ref(), i))
            .collect();
        let mut reached = vec![false; nodes.len()];
        let mut stack = vec![index[spec.start.as_ref()]];
        while let Some(i) = stack.pop() {
            if std::mem::replace(&mut reached[i], true) {
                continue;
            }
            stack.extend(
                nodes[i]
                    .slots
                    .iter()
                    .filter_map(|s| index.get(s.target.as_ref()).copied()),
            );
        }
        for (i, n) in nodes.iter().enumerate() {
            // A duplicate name maps to one index; report each distinct node once.
            if !reached[i] && index[n.name.as_ref()] == i {
                errors.push(GraphError::Unreachable {
                    node: n.name.to_string(),
                });
            }
        }
    }
    let l = &spec.limits;
    if l.min_len == 0 {
        errors.push(GraphError::BadLimits {
            reason: "min_len must be at least 1 (the root gene)".into(),
        });
    }
    if let Some(max) = l.max_len
        && max <= l.min_len
    {
        errors.push(GraphError::BadLimits {
            reason: format!(
                "max_len ({max}) must exceed min_len ({}): lengths satisfy min_len <= L < max_len",
                l.min_len
            ),
        });
    }
    errors
}

/// FNV-1a over the graph's structure.
fn fingerprint(spec: &GraphSpec) -> u64 {
    struct Fnv(u64);
    impl Fnv {
        fn bytes(&mut self, b: &[u8]) {
            for &x in b {
                self.0 = (self.0 ^ x as u64).wrapping_mul(0x0100_0000_01b3);
            }
            self.0 = (self.0 ^ 0xff).wrapping_mul(0x0100_0000_01b3);
        }
    }
    let mut h = Fnv(0xcbf2_9ce4_8422_2325);
    h.bytes(spec.start.as_bytes());
    for n in spec.nodes.iter() {
        h.bytes(n.name.as_bytes());
        for p in n.params.iter() {
            h.bytes(p.name.as_bytes());
            h.bytes(&[p.dist.kind() as u8]);
        }
        for s in n.slots.iter() {
            h.bytes(s.name.as_bytes());
            h.bytes(s.target.as_bytes());
        }
    }
    h.0
}
