//! Crossover (paper Algorithm 2): swap subtrees hanging from compatible connections.

use rand::{Rng, RngExt};
use serde::{Deserialize, Serialize};

use crate::genome::{Chromosome, word};
use crate::graph::Graph;

use super::cut::cut_unchecked;
use super::sample;

use super::OpError;

/// Which connections of the second parent may receive the first parent's subtree.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EdgeMatch {
    /// The same generator-graph edge: same parent node and slot (the paper's definition).
    #[default]
    Strict,
    /// Any connection whose child has the same node (the reference code's rule).
    ChildType,
}

/// Crossover settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct CrossoverConfig {
    /// How many random connections of the first parent to try (`MaxRetries`).
    pub max_retries: u32,
    /// Which connections are compatible.
    pub edge_match: EdgeMatch,
}

impl Default for CrossoverConfig {
    fn default() -> Self {
        Self {
            max_retries: 3,
            edge_match: EdgeMatch::Strict,
        }
    }
}

/// Crosses two parents (paper Algorithm 2): up to `max_retries` times, draw a
/// connection `e1` of `a` uniformly, then a compatible connection `e2` of `b`
/// uniformly; if one exists, return the two children with the subtrees below
/// `e1` and `e2` swapped. Returns `None` (the caller keeps the parents) when no
/// try finds a compatible pair whose children respect the graph's limits.
/// O(G) per try.
pub fn crossover<R: Rng + ?Sized>(
    graph: &Graph,
    a: &Chromosome,
    b: &Chromosome,
    config: &CrossoverConfig,
    rng: &mut R,
) -> Option<(Chromosome, Chromosome)> {
    let (mut c1, mut c2) = (Chromosome::empty(), Chromosome::empty());
    crossover_into(graph, a, b, config, rng, &mut c1, &mut c2).then_some((c1, c2))
}

/// [`crossover`] writing the children into `out1` and `out2`, reusing their
/// allocations (their previous contents are discarded). Returns `false`, with
/// the outputs' contents unspecified, when no compatible pair was found.
pub fn crossover_into<R: Rng + ?Sized>(
    graph: &Graph,
    a: &Chromosome,
    b: &Chromosome,
    config: &CrossoverConfig,
    rng: &mut R,
    out1: &mut Chromosome,
    out2: &mut Chromosome,
) -> bool {
    if a.len() < 2 || b.len() < 2 {
        return false;
    }
    for _ in 0..config.max_retries {
        // A connection is identified by its child gene: every non-root gene has exactly one.
        let e1 = a.index[rng.random_range(1..a.len())];
        let key = Key::of(a, e1, config.edge_match);
        let e2 = sample::weighted(
            rng,
            1,
            |rng: &mut R| Some(b.index[rng.random_range(1..b.len())]),
            |e2| u64::from(Key::of(b, e2, config.edge_match) == key),
            |f| b.index[1..].iter().for_each(|&e2| f(e2)),
        );
        if e2.is_some_and(|e2| swap_into(graph, a, e1, b, e2, out1, out2)) {
            return true;
        }
    }
    false
}

/// Swaps the subtree at `a_pos` of `a` with the subtree at `b_pos` of `b`.
///
/// Fails unless both are non-root gene positions whose connections are
/// compatible under `edge_match`, and both children respect the graph's limits.
pub fn crossover_at(
    graph: &Graph,
    a: &Chromosome,
    a_pos: u32,
    b: &Chromosome,
    b_pos: u32,
    edge_match: EdgeMatch,
) -> Result<(Chromosome, Chromosome), OpError> {
    super::check_gene(a, a_pos)?;
    super::check_gene(b, b_pos)?;
    if a_pos == 0 || b_pos == 0 {
        return Err(OpError::Root);
    }
    if Key::of(a, a_pos, edge_match) != Key::of(b, b_pos, edge_match) {
        return Err(OpError::Incompatible);
    }
    let (mut c1, mut c2) = (Chromosome::empty(), Chromosome::empty());
    if swap_into(graph, a, a_pos, b, b_pos, &mut c1, &mut c2) {
        Ok((c1, c2))
    } else {
        Err(OpError::Limits)
    }
}

/// What two connections (named by their non-root child genes) must share to be swapped.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Key {
    /// Parent node and slot: the same generator-graph edge.
    Edge(u16, u32),
    /// The child's node.
    Child(u16),
}

impl Key {
    fn of(c: &Chromosome, child: u32, edge_match: EdgeMatch) -> Self {
        let w = &c.words;
        let child = child as usize;
        match edge_match {
            EdgeMatch::Strict => {
                let parent = word::follow(child, w[child + word::PARENT]);
                Self::Edge(word::node(w[parent]), word::slot(w[child]))
            }
            EdgeMatch::ChildType => Self::Child(word::node(w[child])),
        }
    }
}

/// Writes the two children of swapping the subtrees at `a_pos` and `b_pos`
/// into `out1` and `out2`; `false` if they would break the graph's limits
/// (the outputs' contents are then unspecified).
///
/// The limits are checked before anything is written, in O(subtree): the
/// parents respect them, so a child breaks the depth limit only if the
/// received subtree reaches too deep below the gene it replaces.
fn swap_into(
    graph: &Graph,
    a: &Chromosome,
    a_pos: u32,
    b: &Chromosome,
    b_pos: u32,
    out1: &mut Chromosome,
    out2: &mut Chromosome,
) -> bool {
    let limits = graph.limits();
    let (len_sa, words_sa, height_sa) = subtree_extent(graph, a, a_pos);
    let (len_sb, words_sb, height_sb) = subtree_extent(graph, b, b_pos);
    let len_a = a.len() - len_sa + len_sb;
    let len_b = b.len() - len_sb + len_sa;
    if !limits.allows_len(len_a as u32) || !limits.allows_len(len_b as u32) {
        return false;
    }
    if limits.max_depth.is_some()
        && (!limits.allows_depth(a.depth(a_pos) + height_sb)
            || !limits.allows_depth(b.depth(b_pos) + height_sa))
    {
        return false;
    }
    splice_into(graph, a, a_pos, b, b_pos, words_sb, out1);
    splice_into(graph, b, b_pos, a, a_pos, words_sa, out2);
    true
}

/// Genes and words in the subtree at `pos`, and how far below `pos` its
/// deepest gene lies.
fn subtree_extent(graph: &Graph, c: &Chromosome, pos: u32) -> (usize, usize, u32) {
    let mut stack = vec![(pos as usize, 0u32)];
    let (mut size, mut words, mut height) = (0, 0, 0);
    while let Some((p, d)) = stack.pop() {
        size += 1;
        height = height.max(d);
        let layout = graph.layout(word::node(c.words[p]));
        words += layout.gene_words as usize;
        let slots = layout.slots as usize;
        for &l in &c.words[p + word::SLOTS..p + word::SLOTS + slots] {
            if l != 0 {
                stack.push((word::follow(p, l), d + 1));
            }
        }
    }
    (size, words, height)
}

/// A copy of `dst` whose subtree at `at` is replaced by the subtree of `src`
/// at `from` (paper Alg. 2: `cloneUntil(dst, at)` then `cloneFrom(src, from)`),
/// written into `c` (its previous contents are discarded, its allocations reused).
///
/// `dst` is block-copied and the subtree at `at` removed by the cut sweep;
/// then the subtree of `src` at `from` is appended in pre-order (parents
/// before children, as every chromosome keeps them), hung in the slot that
/// `at` left empty. Only the donated genes are visited, not all of `src`;
/// `donated_words` (their size) is reserved up front.
fn splice_into(
    graph: &Graph,
    dst: &Chromosome,
    at: u32,
    src: &Chromosome,
    from: u32,
    donated_words: usize,
    c: &mut Chromosome,
) {
    c.words.clear();
    c.words
        .reserve(dst.words.len() + donated_words + SLACK_WORDS);
    c.words.extend_from_slice(&dst.words);
    c.index.clear();
    c.index.reserve(dst.index.len() + donated_words);
    c.index.extend_from_slice(&dst.index);
    let hole = cut_unchecked(graph, c, at);
    append_subtree(
        graph,
        c,
        src,
        from as usize,
        hole.parent as usize,
        hole.slot,
    );
}

/// Extra words reserved by crossover children, so a following grow does not reallocate.
const SLACK_WORDS: usize = 64;

/// Appends the subtree of `src` at `from` to `c` in pre-order (children in
/// slot order), hanging its root in slot `slot` of the gene at `parent` (the
/// slot index may differ from the one it had, under `EdgeMatch::ChildType`).
fn append_subtree(
    graph: &Graph,
    c: &mut Chromosome,
    src: &Chromosome,
    from: usize,
    parent: usize,
    slot: u32,
) {
    let Chromosome { words, index } = c;
    // (position in src, new parent, slot in it).
    let mut stack = vec![(from, parent, slot)];
    while let Some((sp, new_parent, s)) = stack.pop() {
        let w0 = src.words[sp];
        let layout = graph.layout(word::node(w0));
        let w = words.len();
        words.extend_from_slice(&src.words[sp..sp + layout.gene_words as usize]);
        words[w] = word::header(word::node(w0), s);
        words[w + word::PARENT] = word::link(w, new_parent);
        words[new_parent + word::SLOTS + s as usize] = word::link(new_parent, w);
        index.push(w as u32);
        // Children are linked when they are written; push them so that
        // slot 0 comes out first.
        for j in (0..layout.slots as usize).rev() {
            let l = src.words[sp + word::SLOTS + j];
            if l != 0 {
                words[w + word::SLOTS + j] = 0;
                stack.push((word::follow(sp, l), w, j as u32));
            }
        }
    }
}
