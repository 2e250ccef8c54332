//! Cut: remove a gene and its whole subtree, chosen with probability `(1 − p) / Σ (1 − p)`.

use rand::{Rng, RngExt};

use crate::genome::{Chromosome, word};
use crate::graph::{Graph, WEIGHT_ONE};

use super::OpError;
use super::sample;

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

/// Cuts one subtree (paper §5): over all non-root genes `i`, picks one with
/// probability `(1 − p(parent(i), slot(i))) / Σ (1 − p)` and removes it with
/// its subtree in one sweep. Children on `p = 1` slots are never cut.
///
/// Victims whose removal would leave fewer than `L_min` genes are excluded
/// (the choice is then proportional to `1 − p` among the rest). `None` when
/// nothing can be cut. The choice is exact and usually O(1) (see
/// `sample::weighted`); the sweep is O(G) from the victim on.
pub fn cut<R: Rng + ?Sized>(graph: &Graph, c: &mut Chromosome, rng: &mut R) -> Option<Cut> {
    if c.len() < 2 {
        return None;
    }
    let min_len = graph.limits().min_len as usize;
    let weights = graph.cut_weights();
    let cw = |child: u32| {
        let pos = child as usize;
        let parent = word::follow(pos, c.words[pos + word::PARENT]);
        let layout = graph.layout(word::node(c.words[parent]));
        weights[(layout.first_edge + word::slot(c.words[pos])) as usize]
    };
    let allowed = |child: u32| min_len <= 1 || c.len() - c.subtree_len(graph, child) >= min_len;
    let victim = sample::weighted(
        rng,
        WEIGHT_ONE,
        |rng: &mut R| Some(c.index[rng.random_range(1..c.len())]),
        |child| {
            if cw(child) > 0 && allowed(child) {
                cw(child)
            } else {
                0
            }
        },
        |f| c.index[1..].iter().for_each(|&child| f(child)),
    )?;
    Some(cut_unchecked(graph, c, victim))
}

/// Cuts the gene at `pos` and its subtree, whatever its slot's probability.
///
/// Fails if `pos` is not a non-root gene position of `c`, or if the result
/// would have fewer than `L_min` genes.
pub fn cut_at(graph: &Graph, c: &mut Chromosome, pos: u32) -> Result<Cut, OpError> {
    super::check_gene(c, pos)?;
    if pos == 0 {
        return Err(OpError::Root);
    }
    if c.len() - c.subtree_len(graph, pos) < graph.limits().min_len as usize {
        return Err(OpError::Limits);
    }
    Ok(cut_unchecked(graph, c, pos))
}

/// The paper's cut (Fig. 5c): one forward sweep from the victim that drops
/// dead genes, compacts survivors to the front and fixes their links.
///
/// No scratch memory: when a surviving gene moves from `r` to `w`, it writes
/// its new position into each child's parent link (children lie after `r`
/// and have not been overwritten yet), and a dead gene flags its children
/// dead the same way. A survivor therefore always finds its parent's new
/// position through its own parent link, and patches the parent's slot.
/// The gene index is compacted in the same sweep.
pub(crate) fn cut_unchecked(graph: &Graph, c: &mut Chromosome, victim: u32) -> Cut {
    let Chromosome { words, index } = c;
    let first = index.partition_point(|&p| p < victim);
    let victim = victim as usize;
    let parent = word::follow(victim, words[victim + word::PARENT]);
    let slot = word::slot(words[victim]);
    words[parent + word::SLOTS + slot as usize] = 0;
    words[victim] |= word::DEAD;
    let mut w = victim;
    let mut kept = first;
    for k in first..index.len() {
        let r = index[k] as usize;
        let w0 = words[r];
        let layout = graph.layout(word::node(w0));
        let slots = r + word::SLOTS..r + word::SLOTS + layout.slots as usize;
        if w0 & word::DEAD != 0 {
            for j in slots {
                if words[j] != 0 {
                    let child = word::follow(r, words[j]);
                    words[child] |= word::DEAD;
                }
            }
        } else {
            let new_parent = word::follow(r, words[r + word::PARENT]);
            for j in slots {
                if words[j] != 0 {
                    let child = word::follow(r, words[j]);
                    words[child + word::PARENT] = word::link(child, w);
                }
            }
            // w < r here: the victim lies before.
            let size = layout.gene_words as usize;
            words.copy_within(r..r + size, w);
            words[w + word::PARENT] = word::link(w, new_parent);
            words[new_parent + word::SLOTS + word::slot(w0) as usize] = word::link(new_parent, w);
            index[kept] = w as u32;
            kept += 1;
            w += size;
        }
    }
    let removed = index.len() - kept;
    words.truncate(w);
    index.truncate(kept);
    Cut {
        parent: parent as u32,
        slot,
        removed,
    }
}
