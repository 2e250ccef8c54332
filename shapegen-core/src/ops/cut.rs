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
/// No scratch memory: when a surviving gene's new position is known, it
/// writes it into each child's parent link (children lie after it and have
/// not moved yet), and a dead gene flags its children dead the same way. A
/// survivor therefore always finds its parent's new position through its own
/// parent link, and patches the parent's slot.
///
/// Survivors between two dead genes keep their order and move by the same
/// distance, so they are moved as one block when the next dead gene (or the
/// end) is reached; until then their links are patched where they still lie.
/// Once the last dead gene is passed (the sweep counts the dead genes still
/// ahead), the rest is one block: only links that reach back over the
/// removed genes are patched. The gene index is compacted in the same sweep.
pub(crate) fn cut_unchecked(graph: &Graph, c: &mut Chromosome, victim: u32) -> Cut {
    let Chromosome { words, index } = c;
    let first = index.partition_point(|&p| p < victim);
    let victim = victim as usize;
    let parent = word::follow(victim, words[victim + word::PARENT]);
    let slot = word::slot(words[victim]);
    words[parent + word::SLOTS + slot as usize] = 0;
    words[victim] |= word::DEAD;
    // Survivors not yet moved: old positions `run..r`, bound for `w..`.
    let mut w = victim;
    let mut run = victim;
    let mut kept = first;
    // Dead genes not reached yet.
    let mut dead_ahead = 1usize;
    let mut k = first;
    while dead_ahead > 0 {
        let r = index[k] as usize;
        k += 1;
        let w0 = words[r];
        let layout = graph.layout(word::node(w0));
        let slots = r + word::SLOTS..r + word::SLOTS + layout.slots as usize;
        if w0 & word::DEAD != 0 {
            words.copy_within(run..r, w);
            w += r - run;
            run = r + layout.gene_words as usize;
            dead_ahead -= 1;
            // An empty slot (link 0) "follows" to the gene itself, already
            // dead: no branch needed.
            for j in slots {
                let child = word::follow(r, words[j]);
                dead_ahead += usize::from(child != r);
                words[child] |= word::DEAD;
            }
        } else {
            // w < run here: the victim lies before.
            let shift = run - w;
            let new_pos = r - shift;
            let new_parent = word::follow(r, words[r + word::PARENT]);
            // An empty slot (link 0) writes into the gene's own parent link,
            // which is overwritten next: no branch needed.
            for j in slots {
                let child = word::follow(r, words[j]);
                words[child + word::PARENT] = word::link(child, new_pos);
            }
            words[r + word::PARENT] = word::link(new_pos, new_parent);
            // A parent in the pending block still lies `shift` further on.
            let parent_at = if new_parent >= w {
                new_parent + shift
            } else {
                new_parent
            };
            words[parent_at + word::SLOTS + word::slot(w0) as usize] =
                word::link(new_parent, new_pos);
            index[kept] = new_pos as u32;
            kept += 1;
        }
    }
    // The rest moves as one block. Survivors before it wrote their new
    // positions (< w) into their children's parent links, and parents before
    // the victim lie below w too; a parent inside the block (≥ run) still
    // has its old, relative link, which stays right.
    let shift = run - w;
    for k in k..index.len() {
        let r = index[k] as usize;
        let new_pos = r - shift;
        let old = words[r + word::PARENT];
        let parent_at = word::follow(r, old);
        // Branch-free (whether a link reaches back is unpredictable): a
        // link that does not writes its old value back, twice.
        let back = parent_at < w;
        let slot = word::slot(words[r]) as usize;
        let (at, value) = if back {
            (
                parent_at + word::SLOTS + slot,
                word::link(parent_at, new_pos),
            )
        } else {
            (r + word::PARENT, old)
        };
        words[at] = value;
        words[r + word::PARENT] = if back {
            word::link(new_pos, parent_at)
        } else {
            old
        };
        index[kept] = new_pos as u32;
        kept += 1;
    }
    let end = words.len();
    words.copy_within(run..end, w);
    w += end - run;
    let removed = index.len() - kept;
    words.truncate(w);
    index.truncate(kept);
    Cut {
        parent: parent as u32,
        slot,
        removed,
    }
}
