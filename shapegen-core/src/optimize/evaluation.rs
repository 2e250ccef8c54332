//! Evaluating fitness: candidates whose fitness may be known already, their
//! parallel evaluation (stoppable by an interrupt flag or a deadline), and the
//! [`ScratchPool`] of fitness working memory kept across evaluations and
//! generations.

use std::ops::{Deref, DerefMut};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use rayon::prelude::*;

use super::Individual;
use super::fitness::Fitness;
use crate::genome::Chromosome;

/// A chromosome whose fitness may not be known yet.
#[derive(Clone, Debug)]
pub(crate) struct Candidate {
    pub chromosome: Chromosome,
    /// Known fitness (e.g. an unchanged copy of an evaluated parent).
    pub fitness: Option<f64>,
}

impl Candidate {
    pub fn new(chromosome: Chromosome) -> Self {
        Self {
            chromosome,
            fitness: None,
        }
    }
}

/// Evaluates the candidates without a known fitness, in parallel.
///
/// Each rayon job borrows one scratch from `pool` (kept across generations).
/// Evaluation is pure, so the result does not depend on the number of threads.
///
/// Once `stop` is set the remaining evaluations are skipped (NaN): the
/// caller then drops the generation
/// ([`Progress::abandon`](super::progress::Progress::abandon)).
pub(crate) fn evaluate<F: Fitness>(
    fitness: &F,
    candidates: Vec<Candidate>,
    pool: &ScratchPool<F::Scratch>,
    stop: Option<&AtomicBool>,
) -> (Vec<Individual>, u64) {
    evaluate_until(fitness, candidates, pool, stop, None)
}

/// [`evaluate`], also skipping the evaluations not started by `deadline`:
/// for an initial population, which no generation end can stop and which
/// may take longer than the whole budget (a model covering the whole grid
/// at every instance). Only evaluations that were done are counted.
pub(crate) fn evaluate_until<F: Fitness>(
    fitness: &F,
    candidates: Vec<Candidate>,
    pool: &ScratchPool<F::Scratch>,
    stop: Option<&AtomicBool>,
    deadline: Option<Instant>,
) -> (Vec<Individual>, u64) {
    let done = std::sync::atomic::AtomicU64::new(0);
    let stopped = || {
        stop.is_some_and(|s| s.load(Ordering::Relaxed))
            || deadline.is_some_and(|d| Instant::now() >= d)
    };
    let individuals = candidates
        .into_par_iter()
        .map_init(
            || pool.take(|| fitness.scratch()),
            |scratch, c| {
                let f = c.fitness.unwrap_or_else(|| {
                    if stopped() {
                        f64::NAN
                    } else {
                        done.fetch_add(1, Ordering::Relaxed);
                        fitness.evaluate(&c.chromosome, scratch)
                    }
                });
                Individual {
                    chromosome: c.chromosome,
                    fitness: f,
                }
            },
        )
        .collect();
    (individuals, done.into_inner())
}

/// Working memory for a [`Fitness`], kept between parallel evaluations.
///
/// Each rayon task borrows one scratch for the chromosomes it evaluates and
/// returns it afterwards, so after the first generation no evaluation
/// allocates (a voxel grid's hit counts can be megabytes).
pub struct ScratchPool<S> {
    free: Mutex<Vec<S>>,
}

impl<S> Default for ScratchPool<S> {
    fn default() -> Self {
        Self::new()
    }
}

impl<S> std::fmt::Debug for ScratchPool<S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let n = self.free.lock().map(|v| v.len()).unwrap_or(0);
        f.debug_struct("ScratchPool").field("free", &n).finish()
    }
}

impl<S> ScratchPool<S> {
    /// An empty pool.
    #[must_use]
    pub const fn new() -> Self {
        Self {
            free: Mutex::new(Vec::new()),
        }
    }

    /// A scratch from the pool, or a new one from `make`; it returns to the pool when dropped.
    pub fn take(&self, make: impl FnOnce() -> S) -> Pooled<'_, S> {
        let reused = self
            .free
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .pop();
        Pooled {
            pool: self,
            scratch: Some(reused.unwrap_or_else(make)),
        }
    }
}

/// A scratch borrowed from a [`ScratchPool`].
pub struct Pooled<'a, S> {
    pool: &'a ScratchPool<S>,
    scratch: Option<S>,
}

impl<S> Deref for Pooled<'_, S> {
    type Target = S;
    fn deref(&self) -> &S {
        self.scratch.as_ref().expect("present until dropped")
    }
}

impl<S> DerefMut for Pooled<'_, S> {
    fn deref_mut(&mut self) -> &mut S {
        self.scratch.as_mut().expect("present until dropped")
    }
}

impl<S> Drop for Pooled<'_, S> {
    fn drop(&mut self) {
        if let Some(s) = self.scratch.take() {
            self.pool
                .free
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .push(s);
        }
    }
}

/// Evaluates `chromosomes` in parallel on the current rayon pool, reusing
/// scratch from `pool`. The result does not depend on the number of threads.
pub fn evaluate_all<F: Fitness>(
    fitness: &F,
    chromosomes: &[Chromosome],
    pool: &ScratchPool<F::Scratch>,
) -> Vec<f64> {
    chromosomes
        .par_iter()
        .map_init(
            || pool.take(|| fitness.scratch()),
            |scratch, c| fitness.evaluate(c, scratch),
        )
        .collect()
}
