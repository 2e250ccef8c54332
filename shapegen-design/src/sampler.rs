//! Sampling according to a learned pdf (thesis §4.5).
//!
//! - [`RejectionSampler`]: exact. Proposes models by uncontrolled generation
//!   (the default pdf `p`) and accepts one with probability `u(m) / M`; the
//!   target `p · u / Z` is then sampled exactly as long as `u ≤ M`. `M` is
//!   estimated as the largest preference over a probe sample and raised
//!   whenever a proposal exceeds it (preferences are at most 1, so `M = 1`
//!   is always a valid bound; the estimate only saves proposals).
//! - [`parameter_learning`]: the graph unchanged, its slot probabilities and
//!   choice weights set to their relative frequencies in training models.
//! - [`structure_learning`]: the nodes that relevant features name are
//!   split ([`SplitGraph`]), then a mixture of `K` copies of the split graph,
//!   each with its own probabilities, is fitted to the training models by
//!   expectation–maximization, initialized from a clustering of the training
//!   models under the learned kernel.
//!
//! Both learners return a [`LearnedPdf`]: component graphs (ordinary
//! [`GraphSpec`]s over split nodes) with mixture weights, which samples
//! without rejection, saves to and loads from a file (serde), and returns
//! models of the original graph.
//!
//! What is learned: the probability of each optional slot (`0 < p < 1`) and
//! the weights of each choice parameter with more than one option, per node
//! of the split graph. Float, vector and integer parameters keep their
//! distributions (the thesis's learners change rule probabilities only).
//! Learned probabilities stay within the original support: an option of
//! weight 0 or a slot of probability 0 or 1 is never changed.

use std::borrow::Cow;

use rand::{Rng, RngExt};
use serde::{Deserialize, Serialize};
use shapegen_core::genome::Chromosome;
use shapegen_core::graph::{Graph, GraphSpec, NodeId, ParamDist};
use shapegen_core::ops::uncontrolled;

use crate::DesignError;
use crate::split::SplitGraph;

/// Exact sampling of `p · u / Z` by rejection from the default pdf.
pub struct RejectionSampler<'a> {
    graph: &'a Graph,
    preference: &'a (dyn Fn(&Chromosome) -> f64 + Sync),
    bound: f64,
    proposals: u64,
    max_proposals: u64,
}

impl<'a> RejectionSampler<'a> {
    /// A sampler for `graph` reweighted by `preference` (values in `[0, 1]`;
    /// outside values are clamped), with `M` estimated from `probe` proposals.
    /// Fails with [`DesignError::NoMass`] if the preference is 0 on every
    /// probe: the reweighted pdf has (almost) nothing to sample.
    pub fn new<R: Rng + ?Sized>(
        graph: &'a Graph,
        preference: &'a (dyn Fn(&Chromosome) -> f64 + Sync),
        probe: usize,
        rng: &mut R,
    ) -> Result<Self, DesignError> {
        let mut bound: f64 = 0.0;
        for _ in 0..probe {
            let m = uncontrolled(graph, rng)?;
            bound = bound.max(preference(&m).clamp(0.0, 1.0));
        }
        if bound <= 0.0 && probe > 0 {
            return Err(DesignError::NoMass(probe));
        }
        Ok(Self {
            graph,
            preference,
            bound: if bound > 0.0 { bound } else { 1.0 },
            proposals: 0,
            max_proposals: 1_000_000,
        })
    }

    /// At most this many proposals for one sample before giving up (default 10⁶).
    #[must_use]
    pub fn with_max_proposals(mut self, max: u64) -> Self {
        self.max_proposals = max.max(1);
        self
    }

    /// The current bound `M`.
    #[must_use]
    pub fn bound(&self) -> f64 {
        self.bound
    }

    /// Proposals made so far (for the acceptance rate).
    #[must_use]
    pub fn proposals(&self) -> u64 {
        self.proposals
    }

    /// One model of the target pdf.
    pub fn sample<R: Rng + ?Sized>(&mut self, rng: &mut R) -> Result<Chromosome, DesignError> {
        for _ in 0..self.max_proposals {
            self.proposals += 1;
            let m = uncontrolled(self.graph, rng)?;
            let u = (self.preference)(&m).clamp(0.0, 1.0);
            if u > self.bound {
                self.bound = u;
            }
            if rng.random::<f64>() * self.bound < u {
                return Ok(m);
            }
        }
        Err(DesignError::NoAcceptance(self.max_proposals))
    }
}

/// One stochastic decision of a node of a split graph: an optional slot
/// (outcomes: expressed, not) or a choice parameter (outcomes: its options of
/// positive weight).
#[derive(Clone, Debug)]
struct Group {
    node: NodeId,
    kind: GroupKind,
    /// Index of the first outcome in the flat probability table.
    offset: usize,
}

#[derive(Clone, Debug)]
enum GroupKind {
    Slot(u32),
    Choice { param: usize, options: Vec<u32> },
}

impl Group {
    fn outcomes(&self) -> usize {
        match &self.kind {
            GroupKind::Slot(_) => 2,
            GroupKind::Choice { options, .. } => options.len(),
        }
    }
}

/// The learnable decisions of a split graph and the counting of their outcomes in models.
#[derive(Clone, Debug)]
struct Events {
    groups: Vec<Group>,
    /// Per split node, the indices of its groups.
    by_node: Vec<Vec<usize>>,
    outcomes: usize,
}

/// A model's outcome counts: (outcome index, count), sorted by index.
type Counts = Vec<(u32, f64)>;

impl Events {
    fn new(graph: &Graph) -> Self {
        let mut groups = Vec::new();
        let mut by_node = vec![Vec::new(); graph.node_count()];
        let mut offset = 0;
        for n in 0..graph.node_count() as NodeId {
            let spec = graph.node(n);
            for (j, s) in spec.slots.iter().enumerate() {
                if s.p > 0.0 && s.p < 1.0 {
                    by_node[usize::from(n)].push(groups.len());
                    groups.push(Group {
                        node: n,
                        kind: GroupKind::Slot(j as u32),
                        offset,
                    });
                    offset += 2;
                }
            }
            for (k, p) in spec.params.iter().enumerate() {
                if let ParamDist::Choice(w) = &p.dist {
                    let options: Vec<u32> = (0..w.len() as u32)
                        .filter(|&i| w[i as usize] > 0.0)
                        .collect();
                    if options.len() > 1 {
                        let g = Group {
                            node: n,
                            kind: GroupKind::Choice { param: k, options },
                            offset,
                        };
                        offset += g.outcomes();
                        by_node[usize::from(n)].push(groups.len());
                        groups.push(g);
                    }
                }
            }
        }
        Self {
            groups,
            by_node,
            outcomes: offset,
        }
    }

    /// Nodes that have at least one learnable decision.
    fn has_decisions(&self, node: NodeId) -> bool {
        !self.by_node[usize::from(node)].is_empty()
    }

    /// The outcome counts of `model` (a base-graph model) in `split`.
    fn count(&self, split: &SplitGraph, base: &Graph, model: &Chromosome) -> Counts {
        let ids = split.lift(base, model);
        let limits = base.limits();
        let positions = model.positions();
        let mut depth = vec![0u32; model.len()];
        let mut raw: Vec<u32> = Vec::new();
        for (i, g) in model.genes(base).enumerate() {
            if let Some(p) = g.parent() {
                depth[i] = depth[positions.partition_point(|&x| x < p)] + 1;
            }
            let can_grow = limits.allows_depth(depth[i] + 1);
            for &gi in &self.by_node[usize::from(ids[i])] {
                let group = &self.groups[gi];
                match &group.kind {
                    GroupKind::Slot(j) => {
                        if can_grow {
                            let expressed = g.child(*j as usize).is_some();
                            raw.push((group.offset + usize::from(!expressed)) as u32);
                        }
                    }
                    GroupKind::Choice { param, options } => {
                        let v = g.param_choice(*param);
                        if let Some(o) = options.iter().position(|&x| x == v) {
                            raw.push((group.offset + o) as u32);
                        }
                    }
                }
            }
        }
        raw.sort_unstable();
        let mut out: Counts = Vec::new();
        for r in raw {
            match out.last_mut() {
                Some((i, c)) if *i == r => *c += 1.0,
                _ => out.push((r, 1.0)),
            }
        }
        out
    }

    /// The probability table of a graph with this structure.
    fn probabilities(&self, graph: &Graph) -> Vec<f64> {
        let mut p = vec![0.0; self.outcomes];
        for g in &self.groups {
            let spec = graph.node(g.node);
            match &g.kind {
                GroupKind::Slot(j) => {
                    let q = spec.slots[*j as usize].p;
                    p[g.offset] = q;
                    p[g.offset + 1] = 1.0 - q;
                }
                GroupKind::Choice { param, options } => {
                    let ParamDist::Choice(w) = &spec.params[*param].dist else {
                        unreachable!("a choice group is on a choice parameter")
                    };
                    let total: f64 = options.iter().map(|&o| w[o as usize]).sum();
                    for (i, &o) in options.iter().enumerate() {
                        p[g.offset + i] = w[o as usize] / total;
                    }
                }
            }
        }
        p
    }

    /// `template` with the probabilities of `table`.
    fn apply(&self, template: &GraphSpec, table: &[f64]) -> GraphSpec {
        let mut spec = template.clone();
        let nodes = spec.nodes.to_mut();
        for g in &self.groups {
            let node = &mut nodes[usize::from(g.node)];
            match &g.kind {
                GroupKind::Slot(j) => {
                    // Kept strictly inside (0, 1): a learned 0 or 1 would make
                    // the slot deterministic for grow and cut, which the
                    // original graph's models need not be.
                    let q = table[g.offset].clamp(1e-9, 1.0 - 1e-9);
                    node.slots.to_mut()[*j as usize].p = q;
                }
                GroupKind::Choice { param, options } => {
                    let params = node.params.to_mut();
                    let ParamDist::Choice(w) = &params[*param].dist else {
                        unreachable!("a choice group is on a choice parameter")
                    };
                    let mut w = w.to_vec();
                    for (i, &o) in options.iter().enumerate() {
                        // A tiny floor keeps every original option possible.
                        w[o as usize] = table[g.offset + i].max(1e-9);
                    }
                    params[*param].dist = ParamDist::Choice(Cow::Owned(w));
                }
            }
        }
        spec
    }

    /// Log-probability of the counted outcomes under `log_table`.
    fn log_likelihood(counts: &Counts, log_table: &[f64]) -> f64 {
        counts.iter().map(|&(i, c)| c * log_table[i as usize]).sum()
    }

    /// Relative frequencies of weighted counts; groups without observations keep `fallback`.
    fn frequencies(&self, counts: &[Counts], weights: &[f64], fallback: &[f64]) -> Vec<f64> {
        let mut acc = vec![0.0; self.outcomes];
        for (c, &w) in counts.iter().zip(weights) {
            if w > 0.0 {
                for &(i, n) in c {
                    acc[i as usize] += w * n;
                }
            }
        }
        let mut table = fallback.to_vec();
        for g in &self.groups {
            let range = g.offset..g.offset + g.outcomes();
            let total: f64 = acc[range.clone()].iter().sum();
            if total > 0.0 {
                for i in range {
                    table[i] = acc[i] / total;
                }
            }
        }
        table
    }
}

/// One component of a learned mixture.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Component {
    /// Mixture weight `α`.
    pub weight: f64,
    /// The component's graph: the split graph with this component's probabilities.
    pub graph: GraphSpec,
}

/// Current version of the [`LearnedPdf`] file format.
pub const LEARNED_VERSION: u32 = 1;

/// A learned generator: a mixture of component graphs over split nodes, each
/// node a copy of a node of the original generator (`origin`), which samples
/// models of the original generator without rejection.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct LearnedPdf {
    /// Format version ([`LEARNED_VERSION`]).
    pub version: u32,
    /// The original generator's name.
    pub generator: String,
    /// The original graph's fingerprint, 16 hex digits.
    pub fingerprint: String,
    /// How it was learned (`parameter` or `structure`).
    pub method: String,
    /// For each node of the component graphs, the name of the original node it copies.
    pub origin: Vec<String>,
    /// The mixture.
    pub components: Vec<Component>,
    /// The original graph with the relative frequencies of the training
    /// models (parameter learning on the same models): the context-free
    /// approximation of this pdf that optimizers grow with
    /// ([`LearnedPdf::prior_graph`]).
    #[serde(default)]
    pub marginal: Option<GraphSpec>,
}

/// A [`LearnedPdf`] checked against its original graph, ready to sample.
#[derive(Clone, Debug)]
pub struct LearnedSampler {
    base: Graph,
    split: SplitGraph,
    components: Vec<(f64, Graph)>,
    events: Events,
    /// Per component, the log probability table.
    log_tables: Vec<Vec<f64>>,
    /// The default pdf's log probability table over the same outcomes.
    log_default: Vec<f64>,
    /// Cumulative mixture weights.
    cumulative: Vec<f64>,
}

impl LearnedPdf {
    /// Checks this pdf against `base` (the generator it was learned for) and
    /// prepares it for sampling.
    pub fn sampler(&self, base: &Graph) -> Result<LearnedSampler, DesignError> {
        let fp = format!("{:016x}", base.fingerprint());
        if self.fingerprint != fp {
            return Err(DesignError::ForeignGraph {
                found: self.generator.clone(),
                found_fp: self.fingerprint.clone(),
                expected: base.name().to_string(),
                expected_fp: fp,
            });
        }
        if self.version != LEARNED_VERSION {
            return Err(DesignError::Invalid(format!(
                "format version {} (this build reads {LEARNED_VERSION})",
                self.version
            )));
        }
        if self.components.is_empty() {
            return Err(DesignError::Invalid("no components".into()));
        }
        let origin: Vec<NodeId> = self
            .origin
            .iter()
            .map(|n| {
                base.node_id(n)
                    .ok_or_else(|| DesignError::Invalid(format!("unknown node `{n}`")))
            })
            .collect::<Result<_, _>>()?;
        let mut components = Vec::with_capacity(self.components.len());
        let mut split = None;
        for c in &self.components {
            if !(c.weight.is_finite() && c.weight >= 0.0) {
                return Err(DesignError::Invalid(format!(
                    "component weight {}",
                    c.weight
                )));
            }
            let graph = Graph::new(c.graph.clone().with_limits(*base.limits()))?;
            let s = checked_copy(base, graph.clone(), origin.clone())?;
            if split.is_none() {
                split = Some(s);
            }
            components.push((c.weight, graph));
        }
        let split = split.expect("at least one component");
        // Every component must share the first one's structure.
        for (_, g) in &components {
            if g.fingerprint() != split.graph().fingerprint() {
                return Err(DesignError::Invalid(
                    "components differ in structure".into(),
                ));
            }
        }
        let events = Events::new(split.graph());
        let log_tables = components
            .iter()
            .map(|(_, g)| events.probabilities(g).iter().map(|p| p.ln()).collect())
            .collect();
        // The default pdf's table: the base graph's probabilities copied to every split node.
        let base_spec = {
            let mut spec = split.graph().spec().clone();
            let nodes = spec.nodes.to_mut();
            for (i, n) in nodes.iter_mut().enumerate() {
                let o = base.node(split.origin()[i]);
                n.params = o.params.clone();
                for (s, t) in n.slots.to_mut().iter_mut().zip(o.slots.iter()) {
                    s.p = t.p;
                }
            }
            Graph::new(spec)?
        };
        let log_default = events
            .probabilities(&base_spec)
            .iter()
            .map(|p| p.ln())
            .collect();
        let total: f64 = components.iter().map(|c| c.0).sum();
        if total <= 0.0 {
            return Err(DesignError::Invalid("the mixture weights sum to 0".into()));
        }
        let mut acc = 0.0;
        let cumulative = components
            .iter()
            .map(|c| {
                acc += c.0 / total;
                acc
            })
            .collect();
        Ok(LearnedSampler {
            base: base.clone(),
            split,
            components,
            events,
            log_tables,
            log_default,
            cumulative,
        })
    }

    /// The graph an optimizer grows and alters with under this pdf:
    /// `base` (with its limits) with the learned slot probabilities and
    /// choice weights of [`LearnedPdf::marginal`]. It has `base`'s nodes, so
    /// its chromosomes are `base`'s (same fingerprint) and every model it
    /// makes is one `base` can derive.
    pub fn prior_graph(&self, base: &Graph) -> Result<Graph, DesignError> {
        self.sampler(base)?;
        let marginal = self
            .marginal
            .as_ref()
            .ok_or_else(|| DesignError::Invalid("no marginal graph (export it again)".into()))?;
        let graph = Graph::new(marginal.clone().with_limits(*base.limits()))?;
        if graph.fingerprint() != base.fingerprint() {
            return Err(DesignError::Invalid(
                "the marginal graph is not the generator's".into(),
            ));
        }
        checked_copy(
            base,
            graph.clone(),
            (0..base.node_count() as NodeId).collect(),
        )?;
        Ok(graph)
    }
}

impl LearnedSampler {
    /// One model of the original graph, drawn from the mixture.
    pub fn sample<R: Rng + ?Sized>(&self, rng: &mut R) -> Result<Chromosome, DesignError> {
        let u: f64 = rng.random();
        let k = self
            .cumulative
            .partition_point(|&c| c <= u)
            .min(self.components.len() - 1);
        let m = uncontrolled(&self.components[k].1, rng)?;
        self.split.to_base(&self.base, &m)
    }

    /// `ln(q(m) / p(m))`: how much more likely the learned pdf makes `m`
    /// than the default pdf (the parameters it does not learn cancel).
    #[must_use]
    pub fn log_ratio(&self, model: &Chromosome) -> f64 {
        let counts = self.events.count(&self.split, &self.base, model);
        let ll0 = Events::log_likelihood(&counts, &self.log_default);
        let total: f64 = self.components.iter().map(|c| c.0).sum();
        let terms: Vec<f64> = self
            .components
            .iter()
            .zip(&self.log_tables)
            .map(|((w, _), t)| (w / total).ln() + Events::log_likelihood(&counts, t) - ll0)
            .collect();
        log_sum_exp(&terms)
    }

    /// Number of mixture components.
    #[must_use]
    pub fn components(&self) -> usize {
        self.components.len()
    }

    /// Nodes of the split graph.
    #[must_use]
    pub fn split_nodes(&self) -> usize {
        self.split.graph().node_count()
    }
}

/// `graph` as a copy of `base` (see [`SplitGraph::from_parts`]) whose
/// learned distributions keep to the original's supports, and whose slots of
/// probability 0 or 1 are unchanged: what every graph of a [`LearnedPdf`]
/// must be.
fn checked_copy(
    base: &Graph,
    graph: Graph,
    origin: Vec<NodeId>,
) -> Result<SplitGraph, DesignError> {
    let split = SplitGraph::from_parts(base, graph, origin)?;
    let graph = split.graph();
    for (i, &o) in split.origin().iter().enumerate() {
        let (ours, theirs) = (graph.node(i as NodeId), base.node(o));
        for (a, b) in ours.params.iter().zip(theirs.params.iter()) {
            if !within_support(&a.dist, &b.dist) {
                return Err(DesignError::Invalid(format!(
                    "parameter `{}` of `{}` leaves the original's support",
                    a.name, ours.name
                )));
            }
        }
        for (a, b) in ours.slots.iter().zip(theirs.slots.iter()) {
            if (b.p == 0.0 || b.p == 1.0) && a.p != b.p {
                return Err(DesignError::Invalid(format!(
                    "slot `{}` of `{}` changed a certain probability",
                    a.name, ours.name
                )));
            }
        }
    }
    Ok(split)
}

/// Whether a learned parameter distribution keeps to the original's support:
/// a choice may reweight only options the original has; anything else must
/// be unchanged.
fn within_support(learned: &ParamDist, original: &ParamDist) -> bool {
    match (learned, original) {
        (ParamDist::Choice(x), ParamDist::Choice(y)) => {
            x.len() == y.len() && x.iter().zip(y.iter()).all(|(p, q)| *p == 0.0 || *q > 0.0)
        }
        (x, y) => x == y,
    }
}

fn log_sum_exp(xs: &[f64]) -> f64 {
    let max = xs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if max == f64::NEG_INFINITY {
        return max;
    }
    max + xs.iter().map(|x| (x - max).exp()).sum::<f64>().ln()
}

/// Parameter learning: `base` with every optional slot's probability and
/// every choice's weights set to their relative frequencies in `training`
/// (models of `base`, e.g. drawn by a [`RejectionSampler`]).
pub fn parameter_learning(
    base: &Graph,
    training: &[Chromosome],
) -> Result<LearnedPdf, DesignError> {
    if training.is_empty() {
        return Err(DesignError::NoScores);
    }
    let split = SplitGraph::identity(base);
    let events = Events::new(split.graph());
    let counts: Vec<Counts> = training
        .iter()
        .map(|m| events.count(&split, base, m))
        .collect();
    let table = events.frequencies(
        &counts,
        &vec![1.0; counts.len()],
        &events.probabilities(split.graph()),
    );
    let spec = events.apply(split.graph().spec(), &table);
    let mut pdf = learned(base, &split, "parameter", vec![(1.0, spec.clone())]);
    pdf.marginal = Some(spec);
    Ok(pdf)
}

fn learned(
    base: &Graph,
    split: &SplitGraph,
    method: &str,
    components: Vec<(f64, GraphSpec)>,
) -> LearnedPdf {
    LearnedPdf {
        version: LEARNED_VERSION,
        generator: base.name().to_string(),
        fingerprint: format!("{:016x}", base.fingerprint()),
        method: method.to_string(),
        origin: split
            .origin()
            .iter()
            .map(|&o| base.node(o).name.to_string())
            .collect(),
        components: components
            .into_iter()
            .map(|(weight, graph)| Component { weight, graph })
            .collect(),
        marginal: None,
    }
}

/// Settings of [`structure_learning`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct StructureOptions {
    /// Most mixture components `K` (the clustering decides how many, up to this).
    pub max_components: usize,
    /// Most EM iterations.
    pub em_iterations: usize,
    /// EM stops when an iteration raises the log-likelihood by less than this (per model).
    pub tolerance: f64,
    /// Two models are neighbours in the initial clustering when their kernel
    /// distance is at most this fraction of the largest (the thesis's 0.001).
    pub neighbourhood: f64,
    /// Rounds of splitting (1: by parent; 2: then by the parent's copy, …).
    pub split_rounds: u32,
}

impl Default for StructureOptions {
    fn default() -> Self {
        Self {
            max_components: 16,
            em_iterations: 100,
            tolerance: 1e-6,
            neighbourhood: 0.001,
            split_rounds: 1,
        }
    }
}

/// What [`structure_learning`] did.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct StructureReport {
    /// The base nodes that were split.
    pub split_nodes: Vec<String>,
    /// Nodes of the split graph.
    pub split_graph_nodes: usize,
    /// Clusters found before capping at `max_components`.
    pub clusters: usize,
    /// Training log-likelihood (learned decisions only) after initialization and after each EM step.
    pub log_likelihood: Vec<f64>,
}

/// Structure learning: split the nodes in `relevant` (base node ids; those
/// without learnable decisions are skipped), cluster `training` with
/// `distance` (a kernel distance between training models `i` and `j`), fit
/// one component per cluster by relative frequencies, then refine the
/// mixture by EM on the training log-likelihood.
pub fn structure_learning(
    base: &Graph,
    training: &[Chromosome],
    relevant: &[NodeId],
    distance: &(dyn Fn(usize, usize) -> f64 + Sync),
    options: StructureOptions,
) -> Result<(LearnedPdf, StructureReport), DesignError> {
    if training.is_empty() {
        return Err(DesignError::NoScores);
    }
    let base_events = Events::new(base);
    let mut wanted: Vec<NodeId> = relevant
        .iter()
        .copied()
        .filter(|&n| usize::from(n) < base.node_count() && base_events.has_decisions(n))
        .collect();
    wanted.sort_unstable();
    wanted.dedup();
    let mut split = SplitGraph::identity(base);
    for _ in 0..options.split_rounds {
        let ids: Vec<NodeId> = (0..split.graph().node_count() as NodeId)
            .filter(|&n| wanted.contains(&split.origin()[usize::from(n)]))
            .collect();
        split = split.split(&ids)?;
    }
    let events = Events::new(split.graph());
    let counts: Vec<Counts> = training
        .iter()
        .map(|m| events.count(&split, base, m))
        .collect();
    let n = training.len();
    let fallback = events.probabilities(split.graph());
    let overall = events.frequencies(&counts, &vec![1.0; n], &fallback);

    // Initial clustering (thesis §4.5): neighbours within a fraction of the
    // largest distance; repeatedly take the model with most neighbours left.
    let mut d = vec![0.0f64; n * n];
    let mut max_d: f64 = 0.0;
    for i in 0..n {
        for j in 0..i {
            let v = distance(i, j);
            d[i * n + j] = v;
            d[j * n + i] = v;
            max_d = max_d.max(v);
        }
    }
    let threshold = options.neighbourhood * max_d;
    let mut left = vec![true; n];
    let mut clusters: Vec<Vec<usize>> = Vec::new();
    loop {
        let best = (0..n).filter(|&i| left[i]).max_by_key(|&i| {
            (
                (0..n)
                    .filter(|&j| left[j] && d[i * n + j] <= threshold)
                    .count(),
                std::cmp::Reverse(i),
            )
        });
        let Some(seed) = best else { break };
        let members: Vec<usize> = (0..n)
            .filter(|&j| left[j] && (j == seed || d[seed * n + j] <= threshold))
            .collect();
        for &m in &members {
            left[m] = false;
        }
        clusters.push(members);
    }
    let found = clusters.len();
    // Cap K: keep the largest clusters; members of the others join the kept
    // cluster whose seed (first member) is nearest.
    clusters.sort_by_key(|c| std::cmp::Reverse(c.len()));
    let k = options.max_components.max(1).min(clusters.len());
    let rest: Vec<usize> = clusters.drain(k..).flatten().collect();
    for m in rest {
        let nearest = (0..k)
            .min_by(|&a, &b| d[clusters[a][0] * n + m].total_cmp(&d[clusters[b][0] * n + m]))
            .expect("k >= 1");
        clusters[nearest].push(m);
    }
    // Responsibilities from the clusters; components by weighted frequencies.
    let mut resp: Vec<Vec<f64>> = clusters
        .iter()
        .map(|c| {
            let mut w = vec![0.0; n];
            for &m in c {
                w[m] = 1.0;
            }
            w
        })
        .collect();
    let mut alpha: Vec<f64> = clusters.iter().map(|c| c.len() as f64 / n as f64).collect();
    let mut tables: Vec<Vec<f64>> = resp
        .iter()
        .map(|w| events.frequencies(&counts, w, &overall))
        .collect();
    let mut report = StructureReport {
        split_nodes: wanted
            .iter()
            .map(|&w| base.node(w).name.to_string())
            .collect(),
        split_graph_nodes: split.graph().node_count(),
        clusters: found,
        log_likelihood: Vec::new(),
    };
    let mut previous = f64::NEG_INFINITY;
    for step in 0..=options.em_iterations {
        // E-step (and the log-likelihood of the current parameters).
        let logs: Vec<Vec<f64>> = tables
            .iter()
            .map(|t| t.iter().map(|p| p.ln()).collect())
            .collect();
        let mut ll = 0.0;
        for m in 0..n {
            let terms: Vec<f64> = (0..k)
                .map(|c| alpha[c].ln() + Events::log_likelihood(&counts[m], &logs[c]))
                .collect();
            let total = log_sum_exp(&terms);
            ll += total;
            for c in 0..k {
                resp[c][m] = if total.is_finite() {
                    (terms[c] - total).exp()
                } else {
                    1.0 / k as f64
                };
            }
        }
        report.log_likelihood.push(ll);
        if step == options.em_iterations || (ll - previous) < options.tolerance * n as f64 {
            break;
        }
        previous = ll;
        // M-step.
        for c in 0..k {
            alpha[c] = resp[c].iter().sum::<f64>() / n as f64;
            tables[c] = events.frequencies(&counts, &resp[c], &tables[c]);
        }
    }
    let components = tables
        .iter()
        .zip(&alpha)
        .filter(|(_, a)| **a > 0.0)
        .map(|(t, &a)| (a, events.apply(split.graph().spec(), t)))
        .collect();
    Ok((learned(base, &split, "structure", components), report))
}

/// Which learner turns training models into a [`LearnedPdf`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Learner {
    /// [`parameter_learning`].
    Parameter,
    /// [`structure_learning`] (the thesis's default).
    Structure,
}

/// Fits a [`LearnedPdf`] to `training` (models drawn from the target, e.g.
/// by a [`RejectionSampler`] with `preference`): parameter learning, or
/// structure learning splitting the nodes `preference` finds relevant and
/// clustering with its kernel. Also returns structure learning's report.
pub fn learn_pdf(
    base: &Graph,
    training: &[Chromosome],
    preference: &crate::Preference,
    learner: Learner,
    options: StructureOptions,
) -> Result<(LearnedPdf, Option<StructureReport>), DesignError> {
    use rayon::prelude::*;
    let marginal = parameter_learning(base, training)?;
    match learner {
        Learner::Parameter => Ok((marginal, None)),
        Learner::Structure => {
            // Kernel distances from features computed once per factor.
            let feats: Vec<Vec<Vec<f64>>> = preference
                .factors
                .iter()
                .map(|f| {
                    training
                        .par_iter()
                        .map(|m| f.space.features(base, m))
                        .collect()
                })
                .collect();
            let distance = |i: usize, j: usize| -> f64 {
                preference
                    .factors
                    .iter()
                    .zip(&feats)
                    .map(|(f, x)| {
                        (2.0 * f.gp.amplitude() - 2.0 * f.gp.similarity(&x[i], &x[j]))
                            .max(0.0)
                            .sqrt()
                    })
                    .fold(0.0, f64::max)
            };
            let (pdf, report) = structure_learning(
                base,
                training,
                &preference.relevant_nodes(),
                &distance,
                options,
            )?;
            Ok((
                LearnedPdf {
                    marginal: marginal.marginal,
                    ..pdf
                },
                Some(report),
            ))
        }
    }
}
