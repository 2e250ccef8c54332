//! Crossover (paper Algorithm 2): swap subtrees hanging from compatible connections.

use rand::{Rng, RngExt};
use serde::{Deserialize, Serialize};

use crate::genome::{Chromosome, word};
use crate::graph::Graph;

use super::OpError;
use super::cut::cut_unchecked;

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
    if a.len() < 2 || b.len() < 2 {
        return None;
    }
    for _ in 0..config.max_retries {
        // A connection is identified by its child gene: every non-root gene has exactly one.
        let k = rng.random_range(1..a.len());
        let Some(e1) = a.genes(graph).nth(k) else {
            continue;
        };
        let key = connection_key(graph, a, e1.pos(), config.edge_match);
        let matching = || {
            b.genes(graph)
                .skip(1)
                .filter(|g| connection_key(graph, b, g.pos(), config.edge_match) == key)
        };
        let n = matching().count();
        if n == 0 {
            continue;
        }
        let e2 = matching().nth(rng.random_range(0..n))?.pos();
        if let Some(children) = swap_if_allowed(graph, a, e1.pos(), b, e2) {
            return Some(children);
        }
    }
    None
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
    super::check_gene(graph, a, a_pos)?;
    super::check_gene(graph, b, b_pos)?;
    if a_pos == 0 || b_pos == 0 {
        return Err(OpError::Root);
    }
    if connection_key(graph, a, a_pos, edge_match) != connection_key(graph, b, b_pos, edge_match) {
        return Err(OpError::Incompatible);
    }
    swap_if_allowed(graph, a, a_pos, b, b_pos).ok_or(OpError::Limits)
}

/// What must agree between two connections for them to be swapped.
fn connection_key(graph: &Graph, c: &Chromosome, child: u32, edge_match: EdgeMatch) -> (u32, u32) {
    let g = c.gene(graph, child);
    match edge_match {
        EdgeMatch::ChildType => (g.node() as u32, u32::MAX),
        EdgeMatch::Strict => {
            let parent = c.gene(graph, g.parent().unwrap_or(0)).node();
            (graph.layout(parent).first_edge + g.slot_in_parent(), 0)
        }
    }
}

fn swap_if_allowed(
    graph: &Graph,
    a: &Chromosome,
    a_pos: u32,
    b: &Chromosome,
    b_pos: u32,
) -> Option<(Chromosome, Chromosome)> {
    let limits = graph.limits();
    let len_a = a.len() - a.subtree_len(graph, a_pos) + b.subtree_len(graph, b_pos);
    let len_b = a.len() + b.len() - len_a;
    if !limits.allows_len(len_a as u32) || !limits.allows_len(len_b as u32) {
        return None;
    }
    let c1 = replace_subtree(graph, a, a_pos, b, b_pos);
    let c2 = replace_subtree(graph, b, b_pos, a, a_pos);
    if limits.max_depth.is_some()
        && (!limits.allows_depth(c1.max_depth(graph)) || !limits.allows_depth(c2.max_depth(graph)))
    {
        return None;
    }
    Some((c1, c2))
}

/// `cloneUntil(dst, at)` followed by `cloneFrom(src, from)` attached where `at` hung.
fn replace_subtree(
    graph: &Graph,
    dst: &Chromosome,
    at: u32,
    src: &Chromosome,
    from: u32,
) -> Chromosome {
    let mut c = dst.clone();
    let cut = cut_unchecked(graph, &mut c, at);
    append_subtree(graph, &mut c, cut.parent, cut.slot, src, from);
    c
}

/// Appends the subtree of `src` rooted at `root` to `dst`, hanging from slot
/// `slot` of the gene at `parent`. One forward sweep of `src` from `root`:
/// a gene is kept iff it is the root or its parent was kept. Each kept gene
/// is copied word for word; only its parent link and its parent's slot are
/// re-targeted (a child link copied from `src` is overwritten when that
/// child, always kept, is appended).
fn append_subtree(
    graph: &Graph,
    dst: &mut Chromosome,
    parent: u32,
    slot: u32,
    src: &Chromosome,
    root: u32,
) {
    const DROPPED: u32 = u32::MAX;
    let root = root as usize;
    let sw = &src.words;
    // New position of each kept source gene, indexed by (source position − root).
    let mut new_pos = vec![DROPPED; sw.len() - root];
    let mut r = root;
    let mut added = 0u32;
    while r < sw.len() {
        let w0 = sw[r];
        let size = graph.layout(word::node(w0)).gene_words as usize;
        let new_parent = if r == root {
            Some(parent as usize)
        } else {
            let p = word::follow(r, sw[r + word::PARENT]);
            (p >= root && new_pos[p - root] != DROPPED).then(|| new_pos[p - root] as usize)
        };
        if let Some(np) = new_parent {
            let w = dst.words.len();
            new_pos[r - root] = w as u32;
            dst.words.extend_from_slice(&sw[r..r + size]);
            let s = if r == root { slot } else { word::slot(w0) };
            dst.words[w] = word::header(word::node(w0), s);
            dst.words[w + word::PARENT] = word::link(w, np);
            dst.words[np + word::SLOTS + s as usize] = word::link(np, w);
            added += 1;
        }
        r += size;
    }
    dst.len += added;
}
