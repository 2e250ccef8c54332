//! [`Chromosome`]: one derivation tree packed in one buffer, and read-only gene views.

use rand::Rng;

use super::word;
use crate::graph::{Graph, NodeId, NodeLayout};

/// One individual: a derivation tree stored as genes packed back to back in
/// one contiguous buffer of 32-bit words (paper Fig. 5).
///
/// Genes are addressed by the word position of their first word (a *gene
/// position*, as yielded by [`Chromosome::genes`]). The root (a gene of the
/// graph's start node) is at position 0, and every parent precedes its
/// children, so a forward sweep always meets a parent before its children.
/// All links are relative offsets, which makes a subtree position-independent.
///
/// Beside the buffer, a chromosome keeps the positions of its genes in
/// buffer order (one `u32` per gene). Without it every walk over the genes
/// is a chain of dependent loads (a gene's size is known only once its node
/// is read); with it, walks are independent loads and a uniformly random
/// gene is O(1), which the operators' exact rejection samplers rely on.
///
/// A `Chromosome` only ever comes from the operators in [`crate::ops`] or from
/// [`Chromosome::from_data`], which validates it: it always derives from its graph.
#[derive(Debug, PartialEq, Eq, Hash)]
pub struct Chromosome {
    pub(crate) words: Vec<u32>,
    /// Gene positions in buffer order.
    pub(crate) index: Vec<u32>,
}

/// Words and genes a clone reserves beyond its length, so that the grow
/// which usually follows a clone (a GA child) does not reallocate.
const CLONE_SLACK: usize = 64;

impl Clone for Chromosome {
    fn clone(&self) -> Self {
        let mut words = Vec::with_capacity(self.words.len() + CLONE_SLACK);
        words.extend_from_slice(&self.words);
        let mut index = Vec::with_capacity(self.index.len() + CLONE_SLACK / 8);
        index.extend_from_slice(&self.index);
        Self { words, index }
    }
}

#[allow(clippy::len_without_is_empty)] // A chromosome always holds its root gene.
impl Chromosome {
    /// A chromosome holding only a root gene of the start node, with parameters drawn from the prior.
    pub fn root<R: Rng + ?Sized>(graph: &Graph, rng: &mut R) -> Self {
        let mut c = Self {
            words: Vec::new(),
            index: Vec::new(),
        };
        c.push_gene(graph, graph.start(), 0, 0, rng);
        c
    }

    /// A chromosome with no genes: only a target for `*_into` operators,
    /// which overwrite it. It is not valid until then.
    #[must_use]
    pub const fn empty() -> Self {
        Self {
            words: Vec::new(),
            index: Vec::new(),
        }
    }

    /// Number of genes `L` (the root included).
    #[inline]
    #[must_use]
    pub fn len(&self) -> usize {
        self.index.len()
    }

    /// The positions of all genes, in buffer order (parents before children).
    #[inline]
    #[must_use]
    pub fn positions(&self) -> &[u32] {
        &self.index
    }

    /// The raw buffer.
    #[inline]
    #[must_use]
    pub fn words(&self) -> &[u32] {
        &self.words
    }

    /// The gene at position `pos`, which must be a gene position of this chromosome.
    #[inline]
    #[must_use]
    pub fn gene<'a>(&'a self, graph: &'a Graph, pos: u32) -> Gene<'a> {
        let node = word::node(self.words[pos as usize]);
        let layout = graph.layout(node);
        let start = pos as usize;
        Gene {
            pos,
            words: &self.words[start..start + layout.gene_words as usize],
            layout,
        }
    }

    /// The root gene.
    #[must_use]
    pub fn root_gene<'a>(&'a self, graph: &'a Graph) -> Gene<'a> {
        self.gene(graph, 0)
    }

    /// All genes in buffer order (parents before children).
    #[must_use]
    pub fn genes<'a>(&'a self, graph: &'a Graph) -> Genes<'a> {
        Genes {
            chromosome: self,
            graph,
            positions: self.index.iter(),
        }
    }

    /// The genes of the subtree rooted at `pos`, in depth-first pre-order.
    #[must_use]
    pub fn subtree<'a>(&'a self, graph: &'a Graph, pos: u32) -> Subtree<'a> {
        Subtree {
            chromosome: self,
            graph,
            stack: vec![pos],
        }
    }

    /// Number of genes in the subtree rooted at `pos`.
    #[must_use]
    pub fn subtree_len(&self, graph: &Graph, pos: u32) -> usize {
        self.subtree(graph, pos).count()
    }

    /// Depth of the gene at `pos` (the root has depth 0). O(depth).
    #[must_use]
    pub fn depth(&self, pos: u32) -> u32 {
        let mut pos = pos as usize;
        let mut depth = 0;
        while pos != 0 {
            pos = word::follow(pos, self.words[pos + word::PARENT]);
            depth += 1;
        }
        depth
    }

    /// Depth of the deepest gene. O(G).
    #[must_use]
    pub fn max_depth(&self, graph: &Graph) -> u32 {
        let mut depth_at = vec![0u32; self.words.len()];
        let mut max = 0;
        for g in self.genes(graph) {
            if let Some(p) = g.parent() {
                let d = depth_at[p as usize] + 1;
                depth_at[g.pos() as usize] = d;
                max = max.max(d);
            }
        }
        max
    }

    /// A hash of the tree's structure and parameters that does not depend on
    /// the order of genes in the buffer (pre-order node ids, slots and parameter bits).
    #[must_use]
    pub fn structural_hash(&self, graph: &Graph) -> u64 {
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        let mut mix = |x: u32| {
            h = (h ^ x as u64).wrapping_mul(0x0000_0100_0000_01b3);
            h ^= h >> 29;
        };
        for g in self.subtree(graph, 0) {
            mix(g.node() as u32 | g.slot_in_parent() << 16);
            g.params().iter().for_each(|&w| mix(w));
        }
        h
    }

    /// Appends a gene of `node` under `parent`'s slot `slot` (`parent` is
    /// ignored for the root), draws its parameters and patches the parent's link.
    /// Returns the new gene's position.
    pub(crate) fn push_gene<R: Rng + ?Sized>(
        &mut self,
        graph: &Graph,
        node: NodeId,
        parent: u32,
        slot: u32,
        rng: &mut R,
    ) -> u32 {
        self.push_gene_with(graph, node, parent, slot, |dist, out| {
            dist.sample_into(rng, out);
        })
    }

    /// [`push_gene`](Self::push_gene) with each parameter's words set by
    /// `fill` (which must write a value in the parameter's support).
    pub(crate) fn push_gene_with(
        &mut self,
        graph: &Graph,
        node: NodeId,
        parent: u32,
        slot: u32,
        mut fill: impl FnMut(&crate::graph::ParamDist, &mut [u32]),
    ) -> u32 {
        let pos = self.words.len();
        let layout = graph.layout(node);
        let is_root = pos == 0;
        self.words
            .push(word::header(node, if is_root { 0 } else { slot }));
        self.words.push(if is_root {
            0
        } else {
            word::link(pos, parent as usize)
        });
        self.words
            .extend(std::iter::repeat_n(0, layout.slots as usize));
        let params_at = self.words.len();
        self.words
            .extend(std::iter::repeat_n(0, layout.param_words as usize));
        for (p, &off) in graph.node(node).params.iter().zip(&layout.param_offsets) {
            let start = params_at + off as usize;
            let n = p.dist.kind().words();
            fill(&p.dist, &mut self.words[start..start + n]);
        }
        if !is_root {
            self.words[parent as usize + word::SLOTS + slot as usize] =
                word::link(parent as usize, pos);
        }
        self.index.push(pos as u32);
        pos as u32
    }

    /// Redraws every parameter of the gene at `pos` from the prior.
    pub(crate) fn redraw_params<R: Rng + ?Sized>(&mut self, graph: &Graph, pos: u32, rng: &mut R) {
        let node = word::node(self.words[pos as usize]);
        let layout = graph.layout(node);
        let params_at = pos as usize + word::SLOTS + layout.slots as usize;
        for (p, &off) in graph.node(node).params.iter().zip(&layout.param_offsets) {
            let start = params_at + off as usize;
            let n = p.dist.kind().words();
            p.dist.sample_into(rng, &mut self.words[start..start + n]);
        }
    }
}

/// A read-only view of one gene.
#[derive(Clone, Copy, Debug)]
pub struct Gene<'a> {
    pos: u32,
    words: &'a [u32],
    layout: &'a NodeLayout,
}

impl<'a> Gene<'a> {
    /// This gene's position in its chromosome.
    #[inline]
    #[must_use]
    pub fn pos(&self) -> u32 {
        self.pos
    }

    /// The generator-graph node this gene instantiates.
    #[inline]
    #[must_use]
    pub fn node(&self) -> NodeId {
        word::node(self.words[0])
    }

    /// Index of the slot of the parent this gene hangs from (0 for the root).
    #[inline]
    #[must_use]
    pub fn slot_in_parent(&self) -> u32 {
        word::slot(self.words[0])
    }

    /// The parent's position, or `None` for the root.
    #[inline]
    #[must_use]
    pub fn parent(&self) -> Option<u32> {
        match self.words[word::PARENT] {
            0 => None,
            l => Some(word::follow(self.pos as usize, l) as u32),
        }
    }

    /// Number of child slots.
    #[inline]
    #[must_use]
    pub fn slot_count(&self) -> usize {
        self.layout.slots as usize
    }

    /// Position of the child in slot `slot`, or `None` if the slot is empty.
    #[inline]
    #[must_use]
    pub fn child(&self, slot: usize) -> Option<u32> {
        match self.words[word::SLOTS + slot] {
            0 => None,
            l => Some(word::follow(self.pos as usize, l) as u32),
        }
    }

    /// The expressed children as `(slot, position)` pairs, in slot order.
    pub fn children(&self) -> impl Iterator<Item = (usize, u32)> + 'a {
        let pos = self.pos as usize;
        let links = &self.words[word::SLOTS..word::SLOTS + self.layout.slots as usize];
        links
            .iter()
            .enumerate()
            .filter(|(_, l)| **l != 0)
            .map(move |(j, &l)| (j, word::follow(pos, l) as u32))
    }

    /// All parameter words.
    #[inline]
    #[must_use]
    pub fn params(&self) -> &'a [u32] {
        &self.words[word::SLOTS + self.layout.slots as usize..]
    }

    /// The words of parameter `index` (in declaration order).
    #[inline]
    #[must_use]
    pub fn param(&self, index: usize) -> &'a [u32] {
        let params = self.params();
        let start = self.layout.param_offsets[index] as usize;
        let end = self
            .layout
            .param_offsets
            .get(index + 1)
            .map_or(params.len(), |&e| e as usize);
        &params[start..end]
    }

    /// Parameter `index` read as `f32` (its first component for vectors).
    #[inline]
    #[must_use]
    pub fn param_f32(&self, index: usize) -> f32 {
        f32::from_bits(self.param(index)[0])
    }

    /// Parameter `index` read as a vec2.
    #[inline]
    #[must_use]
    pub fn param_vec2(&self, index: usize) -> [f32; 2] {
        let w = self.param(index);
        [f32::from_bits(w[0]), f32::from_bits(w[1])]
    }

    /// Parameter `index` read as a vec3.
    #[inline]
    #[must_use]
    pub fn param_vec3(&self, index: usize) -> [f32; 3] {
        let w = self.param(index);
        [
            f32::from_bits(w[0]),
            f32::from_bits(w[1]),
            f32::from_bits(w[2]),
        ]
    }

    /// Parameter `index` read as an integer.
    #[inline]
    #[must_use]
    pub fn param_int(&self, index: usize) -> i32 {
        self.param(index)[0] as i32
    }

    /// Parameter `index` read as a choice index.
    #[inline]
    #[must_use]
    pub fn param_choice(&self, index: usize) -> u32 {
        self.param(index)[0]
    }

    /// All words of the gene.
    #[inline]
    #[must_use]
    pub fn words(&self) -> &'a [u32] {
        self.words
    }
}

/// Iterator over the genes of a chromosome in buffer order.
#[derive(Clone, Debug)]
pub struct Genes<'a> {
    chromosome: &'a Chromosome,
    graph: &'a Graph,
    positions: std::slice::Iter<'a, u32>,
}

impl<'a> Iterator for Genes<'a> {
    type Item = Gene<'a>;

    #[inline]
    fn next(&mut self) -> Option<Gene<'a>> {
        self.positions
            .next()
            .map(|&pos| self.chromosome.gene(self.graph, pos))
    }

    #[inline]
    fn size_hint(&self) -> (usize, Option<usize>) {
        self.positions.size_hint()
    }
}

impl ExactSizeIterator for Genes<'_> {}

impl DoubleEndedIterator for Genes<'_> {
    #[inline]
    fn next_back(&mut self) -> Option<Self::Item> {
        self.positions
            .next_back()
            .map(|&pos| self.chromosome.gene(self.graph, pos))
    }
}

/// Iterator over a subtree in depth-first pre-order (children in slot order).
#[derive(Clone, Debug)]
pub struct Subtree<'a> {
    chromosome: &'a Chromosome,
    graph: &'a Graph,
    stack: Vec<u32>,
}

impl<'a> Iterator for Subtree<'a> {
    type Item = Gene<'a>;

    fn next(&mut self) -> Option<Gene<'a>> {
        let pos = self.stack.pop()?;
        let g = self.chromosome.gene(self.graph, pos);
        let before = self.stack.len();
        self.stack.extend(g.children().map(|(_, c)| c));
        self.stack[before..].reverse();
        Some(g)
    }
}
