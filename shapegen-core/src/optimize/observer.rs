//! Watching a run: progress, logs, early stops.

use std::ops::ControlFlow;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::Duration;

use super::Individual;
use super::checkpoint::{CHECKPOINT_VERSION, Checkpoint, RunId, SavedIndividual, SavedState};
use crate::genome::Chromosome;

/// What an optimizer reports after each generation.
#[derive(Clone, Copy, Debug)]
pub struct GenerationStats<'a> {
    /// Generation number (0 = the initial population).
    pub generation: u64,
    /// Fitness evaluations so far.
    pub evaluations: u64,
    /// Wall-clock time since the run started.
    pub elapsed: Duration,
    /// Best fitness in the current population (NaN if no evaluation succeeded).
    pub best: f64,
    /// Mean fitness over the successful evaluations of the population.
    pub mean: f64,
    /// Standard deviation of those fitnesses.
    pub std: f64,
    /// Individuals whose evaluation failed (non-finite fitness).
    pub failed: usize,
    /// Best fitness seen since the run started.
    pub best_so_far: f64,
    /// The chromosome with [`best_so_far`](Self::best_so_far).
    pub best_chromosome: &'a Chromosome,
    pub(crate) snapshot: Snapshot<'a>,
}

impl GenerationStats<'_> {
    /// A snapshot of the run after this generation, from which
    /// [`Optimizer::resume`](super::Optimizer::resume) continues exactly as
    /// if the run had never stopped. Costs a copy of the population.
    #[must_use]
    pub fn checkpoint(&self) -> Checkpoint {
        let s = &self.snapshot;
        Checkpoint {
            version: CHECKPOINT_VERSION,
            method: s.id.method.to_string(),
            params: format!("{:016x}", s.id.params),
            seed: s.id.seed,
            generation: self.generation,
            evaluations: self.evaluations,
            elapsed: self.elapsed,
            best: SavedIndividual::save(s.id.graph, s.best),
            state: (s.state)(),
        }
    }
}

/// What [`GenerationStats::checkpoint`] needs from the optimizer.
#[derive(Clone, Copy)]
pub(crate) struct Snapshot<'a> {
    pub id: RunId<'a>,
    pub best: &'a Individual,
    pub state: &'a dyn Fn() -> SavedState,
}

impl std::fmt::Debug for Snapshot<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Snapshot")
            .field("method", &self.id.method)
            .finish_non_exhaustive()
    }
}

/// Called once per generation; returning `ControlFlow::Break(())` stops the
/// run cleanly (the result so far is returned).
pub trait Observer {
    /// Sees one generation's statistics.
    fn generation(&mut self, stats: &GenerationStats<'_>) -> ControlFlow<()>;

    /// A flag the optimizer polls while it evaluates a generation: once it is
    /// set, the remaining evaluations are skipped, the unfinished
    /// generation is dropped and the run ends as if this observer had
    /// stopped it after the last complete generation
    /// ([`StopReason::Observer`](super::StopReason::Observer)). This lets
    /// Ctrl-C stop a run with slow evaluations within one evaluation. The
    /// initial population and SMC steps are always finished. None by default.
    fn interrupt(&self) -> Option<Arc<AtomicBool>> {
        None
    }
}

/// An observer with an interrupt flag (see [`Observer::interrupt`]).
#[derive(Debug)]
pub struct Interruptible<O> {
    /// The observer that sees each generation.
    pub observer: O,
    /// The flag that stops the run mid-generation.
    pub flag: Arc<AtomicBool>,
}

impl<O: Observer> Observer for Interruptible<O> {
    fn generation(&mut self, stats: &GenerationStats<'_>) -> ControlFlow<()> {
        self.observer.generation(stats)
    }

    fn interrupt(&self) -> Option<Arc<AtomicBool>> {
        Some(Arc::clone(&self.flag))
    }
}

impl<F: FnMut(&GenerationStats<'_>) -> ControlFlow<()>> Observer for F {
    fn generation(&mut self, stats: &GenerationStats<'_>) -> ControlFlow<()> {
        self(stats)
    }
}

/// An observer that watches nothing.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoObserver;

impl Observer for NoObserver {
    fn generation(&mut self, _: &GenerationStats<'_>) -> ControlFlow<()> {
        ControlFlow::Continue(())
    }
}

/// Mean and standard deviation of the finite values.
pub(crate) fn mean_std(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut n, mut sum, mut sq) = (0usize, 0.0, 0.0);
    for v in values.filter(|v| v.is_finite()) {
        n += 1;
        sum += v;
        sq += v * v;
    }
    if n == 0 {
        return (f64::NAN, f64::NAN);
    }
    let mean = sum / n as f64;
    (mean, (sq / n as f64 - mean * mean).max(0.0).sqrt())
}
