//! Bookkeeping shared by every optimizer: counting, best-so-far, observer
//! calls, checkpoints and budget checks.

use std::ops::ControlFlow;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use super::budget::{Budget, StopReason};
use super::checkpoint::{Checkpoint, RunId, SavedState};
use super::fitness::is_valid_score;
use super::observer::{GenerationStats, Observer, Snapshot, mean_std};
use super::selection::rank_order;
use super::{Individual, OptimizeError, RunResult};

/// Counts, best-so-far, observer and budget of one run.
pub(crate) struct Progress<'o> {
    id: RunId<'o>,
    start: Instant,
    /// Time spent before a resumed checkpoint.
    offset: Duration,
    budget: Budget,
    observer: &'o mut dyn Observer,
    /// The observer's interrupt flag, if any.
    interrupt: Option<Arc<AtomicBool>>,
    pub evaluations: u64,
    pub generation: u64,
    best: Option<Individual>,
    /// The current generation was reported before a checkpoint this run resumed from.
    resumed: bool,
}

impl<'o> Progress<'o> {
    /// Checks an optimizer's parameter `problems` (all reported at once) and
    /// the budget, then starts the clock.
    pub fn start(
        id: RunId<'o>,
        problems: Vec<String>,
        budget: Budget,
        observer: &'o mut dyn Observer,
    ) -> Result<Self, OptimizeError> {
        if !problems.is_empty() {
            return Err(OptimizeError::Params(problems.join("; ")));
        }
        if budget.is_unbounded() {
            return Err(OptimizeError::UnboundedBudget);
        }
        Ok(Self {
            id,
            start: Instant::now(),
            offset: Duration::ZERO,
            budget,
            interrupt: observer.interrupt(),
            observer,
            evaluations: 0,
            generation: 0,
            best: None,
            resumed: false,
        })
    }

    /// Continues the counters of `checkpoint` (refusing one of another run)
    /// and returns its optimizer state.
    pub fn resume<'c>(
        &mut self,
        checkpoint: &'c Checkpoint,
    ) -> Result<&'c SavedState, OptimizeError> {
        self.id.check(checkpoint)?;
        self.generation = checkpoint.generation;
        self.evaluations = checkpoint.evaluations;
        self.offset = checkpoint.elapsed;
        // SMC's best so far may be an unfinished particle (short, failed).
        self.best = Some(checkpoint.best.restore_partial(self.id.graph)?);
        self.resumed = true;
        Ok(&checkpoint.state)
    }

    fn elapsed(&self) -> Duration {
        // Saturating: a checkpoint may claim any time so far.
        self.offset.saturating_add(self.start.elapsed())
    }

    /// Whether this is the generation a resumed run starts from (already
    /// reported before the checkpoint); true once.
    pub fn take_resumed(&mut self) -> bool {
        std::mem::take(&mut self.resumed)
    }

    /// Whether the budget is spent.
    pub fn budget_reached(&self) -> Option<StopReason> {
        self.budget_reached_at(self.elapsed())
    }

    /// [`budget_reached`](Self::budget_reached) with the elapsed time given.
    fn budget_reached_at(&self, elapsed: Duration) -> Option<StopReason> {
        let best = self
            .best
            .as_ref()
            .map(|b| b.fitness)
            .filter(|f| is_valid_score(*f))
            .unwrap_or(f64::NEG_INFINITY);
        self.budget
            .reached(self.generation, self.evaluations, elapsed, best)
    }

    /// Records a finished generation (`population` need not be sorted) and
    /// tells whether to stop.
    /// `state` saves the optimizer's state when the observer asks for a checkpoint.
    pub fn generation_done(
        &mut self,
        population: &[Individual],
        state: &dyn Fn() -> SavedState,
    ) -> Option<StopReason> {
        let best = population
            .iter()
            .min_by(|a, b| rank_order(a.fitness, b.fitness));
        if let Some(b) = best {
            let improves = match &self.best {
                None => true,
                Some(old) => rank_order(b.fitness, old.fitness).is_lt(),
            };
            if improves {
                self.best = Some(b.clone());
            }
        }
        let best_so_far = self.best.as_ref().expect("a population is never empty");
        let (mean, std) = mean_std(population.iter().map(|i| i.fitness));
        let elapsed = self.elapsed();
        let stats = GenerationStats {
            generation: self.generation,
            evaluations: self.evaluations,
            elapsed,
            best: best.map_or(f64::NAN, |b| b.fitness),
            mean,
            std,
            failed: population
                .iter()
                .filter(|i| !is_valid_score(i.fitness))
                .count(),
            best_so_far: best_so_far.fitness,
            best_chromosome: &best_so_far.chromosome,
            snapshot: Snapshot {
                id: self.id,
                best: best_so_far,
                state,
            },
        };
        if let ControlFlow::Break(()) = self.observer.generation(&stats) {
            return Some(StopReason::Observer);
        }
        self.budget_reached_at(elapsed)
    }

    /// When the wall-clock budget runs out, if it has one.
    pub fn deadline(&self) -> Option<Instant> {
        let left = self.budget.wall_time?.saturating_sub(self.offset);
        self.start.checked_add(left)
    }

    /// The interrupt flag to pass to
    /// [`evaluate`](super::evaluation::evaluate).
    pub fn stop_flag(&self) -> Option<&AtomicBool> {
        self.interrupt.as_deref()
    }

    /// Whether the observer's interrupt flag is set.
    pub fn interrupted(&self) -> bool {
        self.stop_flag().is_some_and(|s| s.load(Ordering::Relaxed))
    }

    /// Ends a run interrupted in the generation after the last complete one
    /// (whose counters it keeps): `population` is the state after that
    /// generation.
    pub fn abandon(mut self, population: Vec<Individual>) -> RunResult {
        self.generation = self.generation.saturating_sub(1);
        self.finish(StopReason::Observer, population)
    }

    /// The result of the run.
    pub fn finish(self, stop: StopReason, mut population: Vec<Individual>) -> RunResult {
        population.sort_by(|a, b| rank_order(a.fitness, b.fitness));
        let elapsed = self.elapsed();
        let best = self.best.expect("a population is never empty");
        RunResult {
            best: best.chromosome,
            best_fitness: best.fitness,
            evaluations: self.evaluations,
            generations: self.generation,
            elapsed,
            stop,
            population,
        }
    }
}
