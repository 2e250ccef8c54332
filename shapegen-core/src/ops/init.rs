//! Random initial individuals (paper §6): grow from the root to a random length.

use rand::{Rng, RngExt};
use serde::{Deserialize, Serialize};

use crate::genome::Chromosome;
use crate::graph::Graph;

use super::OpError;
use super::grow::Grower;

/// How long an initial individual should be.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum InitLength {
    /// Uniform on `⌈L0/2⌉ ..= ⌊3·L0/2⌋` (shapegen's default; the paper only says "random").
    Around {
        /// The reference length `L0`.
        l0: u32,
    },
    /// Uniform on `lo ..= hi`.
    Between {
        /// Shortest.
        lo: u32,
        /// Longest (inclusive).
        hi: u32,
    },
    /// Exactly `L0` genes (the reference code).
    Fixed {
        /// The length.
        l0: u32,
    },
}

impl Default for InitLength {
    fn default() -> Self {
        Self::Around { l0: 50 }
    }
}

impl InitLength {
    /// Draws a target length, clamped to the graph's `[L_min, L_max)`.
    pub fn draw<R: Rng + ?Sized>(&self, graph: &Graph, rng: &mut R) -> u32 {
        let (lo, hi) = match *self {
            Self::Around { l0 } => (l0.div_ceil(2), l0 + l0 / 2),
            Self::Between { lo, hi } => (lo.min(hi), hi.max(lo)),
            Self::Fixed { l0 } => (l0, l0),
        };
        let target = rng.random_range(lo..=hi.max(lo));
        let limits = graph.limits();
        let max = limits.max_len.map_or(u32::MAX, |m| m - 1);
        target.clamp(limits.min_len, max.max(limits.min_len))
    }
}

/// A random individual: a root gene grown by repeated probability-weighted
/// grow (see [`Grower`]) until it has the drawn length or nothing can grow.
///
/// Fails only if the graph cannot grow to its `L_min` from this start (e.g.
/// every slot has `p = 0`, or `max_depth` is too small).
pub fn random_individual<R: Rng + ?Sized>(
    graph: &Graph,
    length: &InitLength,
    rng: &mut R,
) -> Result<Chromosome, OpError> {
    random_individual_with(graph, length, &mut Grower::new(), rng)
}

/// [`random_individual`] reusing a [`Grower`]'s allocations.
pub fn random_individual_with<R: Rng + ?Sized>(
    graph: &Graph,
    length: &InitLength,
    grower: &mut Grower,
    rng: &mut R,
) -> Result<Chromosome, OpError> {
    let target = length.draw(graph, rng) as usize;
    let mut c = Chromosome::root(graph, rng);
    grower.reset(graph, &c);
    while c.len() < target && grower.grow(graph, &mut c, rng).is_some() {}
    let min = graph.limits().min_len as usize;
    if c.len() < min {
        return Err(OpError::MinLength {
            reached: c.len(),
            min,
        });
    }
    Ok(c)
}
