//! Models without an optimizer: a generator's *default model* and
//! *uncontrolled generation* (every slot expressed with its probability),
//! the two ways Lienhard's thumbnail galleries sample a grammar.
//!
//! Both build the derivation tree breadth first, so every parent precedes
//! its children, and stay within the graph's limits: no gene deeper than
//! `max_depth`, fewer than `L_max` genes. A graph without `L_max` is capped
//! at [`UNBOUNDED_CAP`] genes (a slot with `p = 1` on a cycle would never
//! end). A tree shorter than `L_min` is grown, slot by slot in order of
//! decreasing probability (of equals, the first passed over), until it is
//! long enough.

use std::collections::VecDeque;

use rand::{Rng, RngExt};

use super::OpError;
use crate::genome::Chromosome;
use crate::graph::Graph;

/// Most genes a model of a graph without `L_max` gets.
pub const UNBOUNDED_CAP: u32 = 10_000;

/// The generator's default model: every parameter at its distribution's
/// centre ([`ParamDist::central_into`](crate::graph::ParamDist::central_into)),
/// every slot expressed iff its probability is at least ½, within the
/// graph's limits (breadth first: the shallowest slots first).
///
/// Fails only when the graph cannot reach its `L_min` (see
/// [`OpError::MinLength`]).
pub fn default_model(graph: &Graph) -> Result<Chromosome, OpError> {
    build(graph, |p| p >= 0.5, &mut |dist, out| dist.central_into(out))
}

/// Uncontrolled generation: the root, then every slot expressed
/// independently with its probability, breadth first, each parameter
/// drawn from its prior, within the graph's limits.
///
/// Fails only when the graph cannot reach its `L_min` (see
/// [`OpError::MinLength`]).
pub fn uncontrolled<R: Rng + ?Sized>(graph: &Graph, rng: &mut R) -> Result<Chromosome, OpError> {
    // One stream for both decisions and parameters: the closures share it.
    let rng = std::cell::RefCell::new(rng);
    build(
        graph,
        |p| p >= 1.0 || (p > 0.0 && rng.borrow_mut().random::<f64>() < p),
        &mut |dist, out| dist.sample_into(&mut **rng.borrow_mut(), out),
    )
}

/// The breadth-first construction shared by both: `express(p)` decides a
/// slot of probability `p`; `fill` sets parameters.
fn build(
    graph: &Graph,
    mut express: impl FnMut(f64) -> bool,
    fill: &mut dyn FnMut(&crate::graph::ParamDist, &mut [u32]),
) -> Result<Chromosome, OpError> {
    let limits = *graph.limits();
    let cap = limits.max_len.map_or(UNBOUNDED_CAP, |m| m - 1).max(1) as usize;
    let mut c = Chromosome::empty();
    c.push_gene_with(graph, graph.start(), 0, 0, &mut *fill);
    // Genes whose slots are still to be decided, with their depth.
    let mut queue = VecDeque::from([(0u32, 0u32)]);
    // Slots passed over (probability, gene, slot, depth), for L_min.
    let mut skipped = Vec::new();
    while let Some((pos, depth)) = queue.pop_front() {
        if !limits.allows_depth(depth + 1) {
            continue;
        }
        let node = c.gene(graph, pos).node();
        for (slot, spec) in graph.node(node).slots.iter().enumerate() {
            if c.len() >= cap {
                break;
            }
            if spec.p > 0.0 && express(spec.p) {
                let to = graph.edge(node, slot as u32).to;
                let child = c.push_gene_with(graph, to, pos, slot as u32, &mut *fill);
                queue.push_back((child, depth + 1));
            } else if spec.p > 0.0 {
                skipped.push((spec.p, pos, slot as u32, depth));
            }
        }
    }
    // Too short: express the passed-over slots, most likely first, and
    // whatever they open in turn.
    let min = limits.min_len as usize;
    while c.len() < min && c.len() < cap {
        // The most likely; of equals, the first passed over (the shallowest).
        let Some(best) = (0..skipped.len())
            .max_by(|&a, &b| skipped[a].0.total_cmp(&skipped[b].0).then(b.cmp(&a)))
        else {
            break;
        };
        let (_, pos, slot, depth) = skipped.remove(best);
        let node = c.gene(graph, pos).node();
        let to = graph.edge(node, slot).to;
        let child = c.push_gene_with(graph, to, pos, slot, &mut *fill);
        if limits.allows_depth(depth + 2) {
            for (s, spec) in graph.node(to).slots.iter().enumerate() {
                if spec.p > 0.0 {
                    skipped.push((spec.p, child, s as u32, depth + 1));
                }
            }
        }
    }
    if c.len() < min {
        return Err(OpError::MinLength {
            reached: c.len(),
            min,
        });
    }
    Ok(c)
}

/// The log-density of `c` under [`uncontrolled`] generation: for every gene,
/// the log-density of its parameters under their priors, and for every slot
/// that the gene's depth lets grow, `ln p` if it is expressed and `ln(1 − p)`
/// if not. This is the grammar's *default pdf* of Lienhard's thesis (§4.5:
/// the product of the probabilities of every choice made); the length limits'
/// truncation (`L_min`, `L_max`) is not part of it. `-inf` for a tree that
/// uncontrolled generation cannot make (a slot of `p = 0` expressed, one of
/// `p = 1` missing, a parameter outside its support).
#[must_use]
pub fn uncontrolled_log_density(graph: &Graph, c: &Chromosome) -> f64 {
    let limits = graph.limits();
    let mut depth_of = vec![0u32; c.len()];
    let mut total = 0.0;
    for (i, g) in c.genes(graph).enumerate() {
        let depth = match g.parent() {
            Some(p) => depth_of[c.positions().partition_point(|&x| x < p)] + 1,
            None => 0,
        };
        depth_of[i] = depth;
        let spec = graph.node(g.node());
        for (k, p) in spec.params.iter().enumerate() {
            total += p.dist.log_density(g.param(k));
        }
        if limits.allows_depth(depth + 1) {
            for (slot, s) in spec.slots.iter().enumerate() {
                total += if g.child(slot).is_some() {
                    s.p.ln()
                } else {
                    (1.0 - s.p).ln()
                };
            }
        }
    }
    total
}
