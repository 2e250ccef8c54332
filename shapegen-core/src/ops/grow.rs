//! Grow: add one child gene in an empty slot, chosen with probability `p_ij / Σ p`.

use rand::{Rng, RngExt};

use crate::genome::{Chromosome, word};
use crate::graph::{EdgeId, Graph};

use super::OpError;

/// What a grow did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Grown {
    /// Position of the parent gene.
    pub parent: u32,
    /// The slot of the parent that was filled.
    pub slot: u32,
    /// Position of the new gene (always the end of the buffer).
    pub child: u32,
}

/// Grows one gene (paper §5): over all pairs (gene `k`, empty slot `l`) with
/// `p(k, l) > 0`, picks one with probability `p(k, l) / Σ p`, appends a gene of
/// the slot's target node with parameters drawn from the prior and patches
/// the parent's link.
///
/// Pairs whose child would exceed the graph's `max_depth` are not candidates;
/// if the result would reach `L_max`, or there is no candidate, nothing
/// happens and `None` is returned. O(G) (plus O(depth) per open slot when
/// `max_depth` is set).
pub fn grow<R: Rng + ?Sized>(graph: &Graph, c: &mut Chromosome, rng: &mut R) -> Option<Grown> {
    let limits = graph.limits();
    if limits.max_len.is_some_and(|m| c.len() as u32 + 1 >= m) {
        return None;
    }
    // Weight of a gene's open slots, or 0 if its children would be too deep.
    let weight = |g: &crate::genome::Gene<'_>| -> f64 {
        let w: f64 = (0..g.slot_count())
            .filter(|&j| g.child(j).is_none())
            .map(|j| graph.edge(g.node(), j as u32).p)
            .sum();
        if w > 0.0 && limits.allows_depth(c.depth(g.pos()) + 1) {
            w
        } else {
            0.0
        }
    };
    let total: f64 = c.genes(graph).map(|g| weight(&g)).sum();
    if total <= 0.0 {
        return None;
    }
    let mut u = rng.random::<f64>() * total;
    let mut last = None;
    'genes: for g in c.genes(graph) {
        if weight(&g) == 0.0 {
            continue;
        }
        for j in 0..g.slot_count() {
            let p = graph.edge(g.node(), j as u32).p;
            if g.child(j).is_some() || p <= 0.0 {
                continue;
            }
            last = Some((g.pos(), j as u32));
            if u < p {
                break 'genes;
            }
            u -= p;
        }
    }
    // `last` is the chosen pair, or the final candidate if rounding ran past the end.
    let (parent, slot) = last?;
    Some(grow_unchecked(graph, c, parent, slot, rng))
}

/// Grows a gene in slot `slot` of the gene at `parent`, drawing its parameters.
///
/// Fails if `parent` is not a gene position of `c`, the slot does not exist
/// or is occupied, or the graph's depth or length limits would be broken.
pub fn grow_at<R: Rng + ?Sized>(
    graph: &Graph,
    c: &mut Chromosome,
    parent: u32,
    slot: u32,
    rng: &mut R,
) -> Result<Grown, OpError> {
    super::check_gene(graph, c, parent)?;
    let g = c.gene(graph, parent);
    if slot as usize >= g.slot_count() {
        return Err(OpError::NoSuchSlot { pos: parent, slot });
    }
    if g.child(slot as usize).is_some() {
        return Err(OpError::SlotOccupied { pos: parent, slot });
    }
    let limits = graph.limits();
    if !limits.allows_depth(c.depth(parent) + 1)
        || limits.max_len.is_some_and(|m| c.len() as u32 + 1 >= m)
    {
        return Err(OpError::Limits);
    }
    Ok(grow_unchecked(graph, c, parent, slot, rng))
}

pub(crate) fn grow_unchecked<R: Rng + ?Sized>(
    graph: &Graph,
    c: &mut Chromosome,
    parent: u32,
    slot: u32,
    rng: &mut R,
) -> Grown {
    let node = word::node(c.words[parent as usize]);
    let target = graph.edge(node, slot).to;
    let child = c.push_gene(graph, target, parent, slot, rng);
    Grown {
        parent,
        slot,
        child,
    }
}

/// Repeated grow with an index of open slots, so each step costs O(edges)
/// instead of O(G): the way to grow large individuals.
///
/// Each step picks (gene, empty slot) with exactly the probability of [`grow`]
/// (`p / Σ p` over the open slots allowed by `max_depth`), but consumes
/// randomness differently, so the two do not give identical results for one seed.
#[derive(Clone, Debug, Default)]
pub struct Grower {
    /// Per edge: the (gene position, depth) pairs whose slot on that edge is empty.
    open: Vec<Vec<(u32, u32)>>,
    /// Per edge: `p`.
    p: Vec<f64>,
}

impl Grower {
    /// A grower with no state; [`Grower::reset`] attaches it to a chromosome.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Indexes the open slots of `c` (O(G)); reuses the allocations.
    pub fn reset(&mut self, graph: &Graph, c: &Chromosome) {
        let edges = graph.edges();
        self.open.resize_with(edges.len(), Vec::new);
        self.open.iter_mut().for_each(Vec::clear);
        self.p.clear();
        self.p.extend(edges.iter().map(|e| e.p));
        let mut depth_at = vec![0u32; c.words().len()];
        for g in c.genes(graph) {
            let depth = g.parent().map_or(0, |p| depth_at[p as usize] + 1);
            depth_at[g.pos() as usize] = depth;
            self.add_gene(graph, c, g.pos(), depth);
        }
    }

    fn add_gene(&mut self, graph: &Graph, c: &Chromosome, pos: u32, depth: u32) {
        if !graph.limits().allows_depth(depth + 1) {
            return;
        }
        let g = c.gene(graph, pos);
        let first = graph.layout(g.node()).first_edge;
        for j in 0..g.slot_count() {
            let e = (first + j as EdgeId) as usize;
            if g.child(j).is_none() && self.p[e] > 0.0 {
                self.open[e].push((pos, depth));
            }
        }
    }

    /// Grows one gene of `c` (which must be the chromosome last passed to
    /// [`Grower::reset`] and changed only by this grower since). `None` when
    /// no slot is open or the length limit would be reached.
    pub fn grow<R: Rng + ?Sized>(
        &mut self,
        graph: &Graph,
        c: &mut Chromosome,
        rng: &mut R,
    ) -> Option<Grown> {
        if graph
            .limits()
            .max_len
            .is_some_and(|m| c.len() as u32 + 1 >= m)
        {
            return None;
        }
        let total: f64 = self
            .open
            .iter()
            .zip(&self.p)
            .map(|(o, p)| o.len() as f64 * p)
            .sum();
        if total <= 0.0 {
            return None;
        }
        let mut u = rng.random::<f64>() * total;
        let mut chosen = None;
        for (e, (o, &p)) in self.open.iter().zip(&self.p).enumerate() {
            if o.is_empty() {
                continue;
            }
            chosen = Some(e);
            let w = o.len() as f64 * p;
            if u < w {
                break;
            }
            u -= w;
        }
        let e = chosen?;
        let i = rng.random_range(0..self.open[e].len());
        let (parent, depth) = self.open[e].swap_remove(i);
        let slot = graph.edges()[e].slot as u32;
        let grown = grow_unchecked(graph, c, parent, slot, rng);
        self.add_gene(graph, c, grown.child, depth + 1);
        Some(grown)
    }

    /// Total weight `Σ p` of the open slots.
    #[must_use]
    pub fn open_weight(&self) -> f64 {
        self.open
            .iter()
            .zip(&self.p)
            .map(|(o, p)| o.len() as f64 * p)
            .sum()
    }
}
