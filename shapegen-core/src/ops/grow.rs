//! Grow: add one child gene in an empty slot, chosen with probability `p_ij / Σ p`.

use rand::{Rng, RngExt};

use crate::genome::{Chromosome, word};
use crate::graph::{EdgeId, Graph, WEIGHT_ONE};

use super::OpError;
use super::sample;

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
/// happens and `None` is returned. The choice is exact and usually O(1)
/// (rejection from uniform (gene, slot) proposals, with an exact O(G)
/// sweep as fallback).
pub fn grow<R: Rng + ?Sized>(graph: &Graph, c: &mut Chromosome, rng: &mut R) -> Option<Grown> {
    let limits = graph.limits();
    if limits.max_len.is_some_and(|m| c.len() as u32 + 1 >= m) {
        return None;
    }
    let max_slots = graph.max_slots();
    let weights = graph.grow_weights();
    let words = &c.words;
    let weight = |(pos, slot): (u32, u32)| -> u64 {
        let layout = graph.layout(word::node(words[pos as usize]));
        if slot >= layout.slots || words[(pos + word::SLOTS as u32 + slot) as usize] != 0 {
            return 0;
        }
        let w = weights[(layout.first_edge + slot) as usize];
        if w > 0 && (limits.max_depth.is_none() || limits.allows_depth(c.depth(pos) + 1)) {
            w
        } else {
            0
        }
    };
    let (parent, slot) = sample::weighted(
        rng,
        if max_slots == 0 { 0 } else { WEIGHT_ONE },
        |rng: &mut R| {
            Some((
                c.index[rng.random_range(0..c.len())],
                rng.random_range(0..max_slots),
            ))
        },
        weight,
        |f| {
            for &pos in &c.index {
                for j in 0..graph.layout(word::node(words[pos as usize])).slots {
                    f((pos, j));
                }
            }
        },
    )?;
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
    super::check_gene(c, parent)?;
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
    /// Per edge: the fixed-point grow weight `p`.
    p: Vec<u64>,
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
        self.p.extend_from_slice(graph.grow_weights());
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
            if g.child(j).is_none() && self.p[e] > 0 {
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
        let total = self.open_weight();
        if total == 0 {
            return None;
        }
        let mut u = rng.random_range(0..total);
        let mut chosen = None;
        for (e, (o, &p)) in self.open.iter().zip(&self.p).enumerate() {
            if o.is_empty() {
                continue;
            }
            chosen = Some(e);
            let w = o.len() as u64 * p;
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

    /// Total fixed-point weight `Σ p` of the open slots (see [`WEIGHT_ONE`]).
    #[must_use]
    pub fn open_weight(&self) -> u64 {
        self.open
            .iter()
            .zip(&self.p)
            .map(|(o, &p)| o.len() as u64 * p)
            .sum()
    }
}
