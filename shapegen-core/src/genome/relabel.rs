//! Moving a derivation tree between graphs that share gene layouts.
//!
//! A *split* graph (Lienhard's thesis §4.5: a node copied once per incoming
//! edge, so the copies can get probabilities of their own) derives the same
//! trees as its original, only with other node ids. [`Chromosome::relabel`]
//! turns one into the other and checks the result against the graph it is
//! meant for, so a learned sampler can never hand out a model the original
//! generator could not derive.

use super::validate::validate_words;
use super::{Chromosome, GenomeError, word};
use crate::graph::{Graph, NodeId};

impl Chromosome {
    /// This derivation tree with every gene's node id `n` replaced by
    /// `map(n)` (called once per gene, in buffer order: parents before
    /// children), validated against `to` (every invariant of
    /// [`validate`](Self::validate), so a map between graphs whose nodes do
    /// not share parameters, slots and targets is an error, never a broken
    /// chromosome).
    ///
    /// ```
    /// # use shapegen_core::prelude::*;
    /// let a = GraphBuilder::new("g").start("A")
    ///     .node("A", |n| n.slot("b", "B", 0.5)).node("B", |n| n).build()?;
    /// // The same graph with its nodes in the other order.
    /// let b = GraphBuilder::new("g").start("A")
    ///     .node("B", |n| n).node("A", |n| n.slot("b", "B", 0.5)).build()?;
    /// let c = default_model(&a)?;
    /// let moved = c.relabel(&b, |n| 1 - n)?;
    /// assert_eq!(moved.relabel(&a, |n| 1 - n)?, c);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn relabel(
        &self,
        to: &Graph,
        mut map: impl FnMut(NodeId) -> NodeId,
    ) -> Result<Self, GenomeError> {
        let mut words = self.words.clone();
        for &pos in &self.index {
            let w0 = words[pos as usize];
            words[pos as usize] = word::header(map(word::node(w0)), word::slot(w0));
        }
        let index = validate_words(to, &words, false)?;
        Ok(Self { words, index })
    }
}
