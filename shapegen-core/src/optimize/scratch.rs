//! [`ScratchPool`]: fitness working memory kept across evaluations and generations.

use std::ops::{Deref, DerefMut};
use std::sync::Mutex;

use rayon::prelude::*;

use super::fitness::Fitness;
use crate::genome::Chromosome;

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
