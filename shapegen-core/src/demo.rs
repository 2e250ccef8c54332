//! The *blocks* problem: a generator and a fitness with a known optimum,
//! for tests, examples and docs of the optimizers (no files, no geometry).
//!
//! The *blocks* generator grows a binary tree of blocks, each with a
//! parameter `x` in `[0, 1]`. The [`BlocksTarget`] fitness asks for exactly
//! `n` blocks, each with `x = 0.5`:
//!
//! `F = (Σ_i exp(−((x_i − 0.5) / 0.1)²) − 2 |blocks − n|) / n`
//!
//! Its optimum, reached only by `n` blocks all at `x = 0.5`, is exactly 1.

use crate::genome::Chromosome;
use crate::graph::{Dist, Graph, GraphBuilder, Limits};
use crate::optimize::Fitness;

/// The blocks generator: `Start → Block`, each `Block` with parameter `x`
/// and two optional child blocks (`p = 0.4` each).
#[must_use]
pub fn blocks_graph() -> Graph {
    GraphBuilder::new("blocks")
        .start("Start")
        .limits(Limits {
            max_depth: Some(64),
            min_len: 2,
            max_len: Some(1000),
        })
        .node("Start", |n| n.slot("first", "Block", 1.0))
        .node("Block", |n| {
            n.emits()
                .param_f32("x", Dist::uniform(0.0, 1.0))
                .slot("left", "Block", 0.4)
                .slot("right", "Block", 0.4)
        })
        .build()
        .expect("the blocks graph is valid")
}

/// Fitness of the blocks problem: exactly `blocks` blocks, all at `x = 0.5`. Optimum 1.
#[derive(Clone, Copy, Debug)]
pub struct BlocksTarget<'g> {
    /// The blocks graph (from [`blocks_graph`]).
    pub graph: &'g Graph,
    /// The wanted number of blocks `n` (at least 1).
    pub blocks: usize,
}

impl Fitness for BlocksTarget<'_> {
    type Scratch = ();

    fn scratch(&self) {}

    fn evaluate(&self, c: &Chromosome, (): &mut ()) -> f64 {
        let (mut count, mut sum) = (0usize, 0.0f64);
        for g in c.genes(self.graph).filter(|g| g.slot_count() == 2) {
            let x = f64::from(g.param_f32(0));
            sum += (-((x - 0.5) / 0.1).powi(2)).exp();
            count += 1;
        }
        let n = self.blocks.max(1) as f64;
        (sum - 2.0 * (count as f64 - n).abs()) / n
    }
}
