//! What optimizers maximize.

use crate::genome::Chromosome;

/// A score to maximize, computed for one chromosome.
///
/// Evaluation must be pure (the same chromosome always gets the same score)
/// and may run on many threads at once: each worker owns one
/// [`Scratch`](Fitness::Scratch), reused from one evaluation to the next, so
/// the hot path allocates nothing.
///
/// A score that is not finite (NaN or ±∞) marks a failed evaluation: the
/// individual ranks last, is never an elite and gets no roulette weight.
pub trait Fitness: Sync {
    /// Per-thread working memory (voxel counts, pixel buffers, ...).
    type Scratch: Send;

    /// Fresh working memory for one worker.
    fn scratch(&self) -> Self::Scratch;

    /// The score of `chromosome`; higher is better.
    fn evaluate(&self, chromosome: &Chromosome, scratch: &mut Self::Scratch) -> f64;
}

/// A [`Fitness`] made from a closure, with no scratch.
///
/// ```
/// use shapegen_core::optimize::{Fitness, FnFitness};
/// let f = FnFitness(|c: &shapegen_core::genome::Chromosome| -(c.len() as f64));
/// # let _ = &f;
/// ```
#[derive(Clone, Copy, Debug)]
pub struct FnFitness<F>(pub F);

impl<F: Fn(&Chromosome) -> f64 + Sync> Fitness for FnFitness<F> {
    type Scratch = ();

    fn scratch(&self) {}

    fn evaluate(&self, chromosome: &Chromosome, (): &mut ()) -> f64 {
        (self.0)(chromosome)
    }
}

/// Whether a score counts as a successful evaluation.
#[inline]
#[must_use]
pub fn is_valid_score(f: f64) -> bool {
    f.is_finite()
}
