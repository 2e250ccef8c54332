//! Exact weighted choice of a gene (or gene slot) by rejection, with an
//! exact sweep as fallback.
//!
//! Each try proposes a uniformly random gene (O(1) through the chromosome's
//! gene index) and accepts it with probability `weight / max_weight`; an
//! accepted proposal is distributed exactly in proportion to the weights.
//! After [`TRIES`] rejections the choice is made by one exact sweep over
//! all candidates, which has the same distribution, so the mixture is exact
//! too. Typical operators accept within a few tries: O(1) instead of O(G).

use rand::{Rng, RngExt};

/// Proposals before falling back to the exact sweep.
pub(crate) const TRIES: usize = 32;

/// Draws a candidate with probability `weight(c) / Σ weight`, where `weight`
/// is at most `max`. `propose` draws a uniform candidate; `all` lists every
/// candidate with non-zero weight (for the fallback). `None` if all weights are 0.
pub(crate) fn weighted<R, T, P, W, A>(
    rng: &mut R,
    max: u64,
    mut propose: P,
    weight: W,
    all: A,
) -> Option<T>
where
    R: Rng + ?Sized,
    T: Copy,
    P: FnMut(&mut R) -> Option<T>,
    W: Fn(T) -> u64,
    A: Fn(&mut dyn FnMut(T)),
{
    if max > 0 {
        for _ in 0..TRIES {
            let Some(candidate) = propose(rng) else { break };
            let w = weight(candidate);
            if w > 0 && rng.random_range(0..max) < w {
                return Some(candidate);
            }
        }
    }
    // Exact fallback: Σ weights, then walk to the chosen one.
    let mut total = 0u64;
    all(&mut |c| total += weight(c));
    if total == 0 {
        return None;
    }
    let mut u = rng.random_range(0..total);
    let mut chosen = None;
    all(&mut |c| {
        if chosen.is_none() {
            let w = weight(c);
            if u < w {
                chosen = Some(c);
            } else {
                u -= w;
            }
        }
    });
    chosen
}
