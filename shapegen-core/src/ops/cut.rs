//! Cut: remove a gene and its whole subtree, chosen with probability `(1 − p) / Σ (1 − p)`.

use rand::{Rng, RngExt};

use crate::genome::{Chromosome, word};
use crate::graph::Graph;

use super::OpError;

/// What a cut did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Cut {
    /// Position of the parent of the removed subtree (unchanged by the cut).
    pub parent: u32,
    /// The parent's slot that is now empty.
    pub slot: u32,
    /// Number of genes removed.
    pub removed: usize,
}

/// How many times [`cut`] redraws a victim whose removal would go below `L_min`
/// before it switches to an exact search among the allowed victims.
const REJECTION_TRIES: usize = 8;

/// Cuts one subtree (paper §5): over all non-root genes `i`, picks one with
/// probability `(1 − p(parent(i), slot(i))) / Σ (1 − p)` and removes it with
/// its subtree in one O(G) sweep. Children on `p = 1` slots are never cut.
///
/// Victims whose removal would leave fewer than `L_min` genes are excluded
/// (the choice is then proportional to `1 − p` among the rest). `None` when
/// nothing can be cut.
pub fn cut<R: Rng + ?Sized>(graph: &Graph, c: &mut Chromosome, rng: &mut R) -> Option<Cut> {
    let weight = |pos: u32| -> f64 {
        let g = c.gene(graph, pos);
        match g.parent() {
            None => 0.0,
            Some(p) => 1.0 - graph.edge(c.gene(graph, p).node(), g.slot_in_parent()).p,
        }
    };
    let total: f64 = c.genes(graph).map(|g| weight(g.pos())).sum();
    if total <= 0.0 {
        return None;
    }
    let min_len = graph.limits().min_len as usize;
    let pick = |rng: &mut R, allowed: &dyn Fn(u32) -> bool, total: f64| -> Option<u32> {
        let mut u = rng.random::<f64>() * total;
        let mut last = None;
        for g in c.genes(graph) {
            let w = weight(g.pos());
            if w <= 0.0 || !allowed(g.pos()) {
                continue;
            }
            last = Some(g.pos());
            if u < w {
                break;
            }
            u -= w;
        }
        last
    };
    let mut victim = None;
    for _ in 0..REJECTION_TRIES {
        let v = pick(rng, &|_| true, total)?;
        if min_len <= 1 || c.len() - c.subtree_len(graph, v) >= min_len {
            victim = Some(v);
            break;
        }
    }
    let victim = match victim {
        Some(v) => v,
        None => {
            // Exact fallback: restrict to victims whose subtree is small enough.
            let sizes = subtree_sizes(graph, c);
            let allowed = |pos: u32| c.len() - sizes[pos as usize] as usize >= min_len;
            let total: f64 = c
                .genes(graph)
                .filter(|g| allowed(g.pos()))
                .map(|g| weight(g.pos()))
                .sum();
            if total <= 0.0 {
                return None;
            }
            pick(rng, &allowed, total)?
        }
    };
    Some(cut_unchecked(graph, c, victim))
}

/// Cuts the gene at `pos` and its subtree, whatever its slot's probability.
///
/// Fails if `pos` is not a non-root gene position of `c`, or if the result
/// would have fewer than `L_min` genes.
pub fn cut_at(graph: &Graph, c: &mut Chromosome, pos: u32) -> Result<Cut, OpError> {
    super::check_gene(graph, c, pos)?;
    if pos == 0 {
        return Err(OpError::Root);
    }
    if c.len() - c.subtree_len(graph, pos) < graph.limits().min_len as usize {
        return Err(OpError::Limits);
    }
    Ok(cut_unchecked(graph, c, pos))
}

/// Subtree size per gene position (indexed by word position).
fn subtree_sizes(graph: &Graph, c: &Chromosome) -> Vec<u32> {
    let mut sizes = vec![0u32; c.words().len()];
    let positions: Vec<u32> = c.genes(graph).map(|g| g.pos()).collect();
    for &pos in positions.iter().rev() {
        sizes[pos as usize] += 1;
        if let Some(p) = c.gene(graph, pos).parent() {
            sizes[p as usize] += sizes[pos as usize];
        }
    }
    sizes
}

/// The paper's cut (Fig. 5c): one forward sweep from the victim that drops
/// dead genes, compacts survivors to the front and fixes their links.
///
/// No scratch memory: when a surviving gene moves from `r` to `w`, it writes
/// its new position into each child's parent link (children lie after `r`
/// and have not been overwritten yet), and a dead gene flags its children
/// dead the same way. A survivor therefore always finds its parent's new
/// position through its own parent link, and patches the parent's slot.
pub(crate) fn cut_unchecked(graph: &Graph, c: &mut Chromosome, victim: u32) -> Cut {
    let words = &mut c.words;
    let victim = victim as usize;
    let parent = word::follow(victim, words[victim + word::PARENT]);
    let slot = word::slot(words[victim]);
    words[parent + word::SLOTS + slot as usize] = 0;
    words[victim] |= word::DEAD;
    let (mut r, mut w, mut removed) = (victim, victim, 0usize);
    while r < words.len() {
        let w0 = words[r];
        let layout = graph.layout(word::node(w0));
        let size = layout.gene_words as usize;
        let slots = r + word::SLOTS..r + word::SLOTS + layout.slots as usize;
        if w0 & word::DEAD != 0 {
            for j in slots {
                if words[j] != 0 {
                    let child = word::follow(r, words[j]);
                    words[child] |= word::DEAD;
                }
            }
            removed += 1;
        } else {
            let new_parent = word::follow(r, words[r + word::PARENT]);
            for j in slots {
                if words[j] != 0 {
                    let child = word::follow(r, words[j]);
                    words[child + word::PARENT] = word::link(child, w);
                }
            }
            if w != r {
                words.copy_within(r..r + size, w);
            }
            words[w + word::PARENT] = word::link(w, new_parent);
            words[new_parent + word::SLOTS + word::slot(w0) as usize] = word::link(new_parent, w);
            w += size;
        }
        r += size;
    }
    words.truncate(w);
    c.len -= removed as u32;
    Cut {
        parent: parent as u32,
        slot,
        removed,
    }
}
