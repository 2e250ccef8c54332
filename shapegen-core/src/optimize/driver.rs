//! The one run loop every optimizer shares.
//!
//! A method implements [`Method`]: how to build its first generation, how to
//! save and restore its state, what population each generation reports, and
//! one step. [`drive`] does the rest, the same way for every method: check
//! the parameters and the budget, start or resume from a checkpoint, report
//! each generation to the observer (which may save a checkpoint or stop the
//! run), stop on the budget, on exhaustion or on an interrupt, and finish.

use std::borrow::Cow;
use std::fmt::Debug;
use std::ops::ControlFlow;

use super::checkpoint::{Checkpoint, RunId, SavedState};
use super::evaluation::{Candidate, ScratchPool, evaluate, evaluate_until};
use super::progress::Progress;
use super::{Budget, Fitness, Individual, Observer, OptimizeError, RunResult, StopReason};
use crate::graph::Graph;

/// Everything a run needs besides the method: the problem, the budget, the
/// seed, where to start, and who watches.
pub struct Run<'a, F> {
    /// The generator graph whose chromosomes are searched.
    pub graph: &'a Graph,
    /// What is maximized.
    pub fitness: &'a F,
    /// When to stop (counted from the start of the original run when resuming).
    pub budget: Budget,
    /// The seed every random stream derives from.
    pub seed: u64,
    /// A checkpoint to continue from, or `None` to start afresh.
    pub start: Option<&'a Checkpoint>,
    /// Called after every generation.
    pub observer: &'a mut dyn Observer,
}

/// One optimization method's algorithm, run by [`drive`].
pub(crate) trait Method {
    /// What identifies the method's settings in a checkpoint (its `Debug` form is fingerprinted).
    type Params: Debug;
    /// The method's state between generations.
    type State;

    /// The method's name in checkpoints and results.
    fn name(&self) -> &'static str;

    /// The settings a checkpoint must match.
    fn params(&self) -> &Self::Params;

    /// Every problem with the settings (all reported at once).
    fn problems(&self) -> Vec<String>;

    /// Generation 0, with its evaluations counted in `cx`.
    fn init<F: Fitness>(&self, cx: &mut Context<'_, '_, F>) -> Result<Self::State, OptimizeError>;

    /// The state saved in `checkpoint`, whose identity and counters the
    /// driver has already checked and taken over.
    fn restore(&self, graph: &Graph, checkpoint: &Checkpoint)
    -> Result<Self::State, OptimizeError>;

    /// The state a checkpoint saves.
    fn save(&self, graph: &Graph, state: &Self::State) -> SavedState;

    /// The population the current generation reports (need not be sorted).
    fn report<'s>(&self, graph: &Graph, state: &'s Self::State) -> Cow<'s, [Individual]>;

    /// Whether generation 0 is reported (SMC's first generation is its first step).
    fn reports_initial(&self) -> bool {
        true
    }

    /// Whether the method has nothing left to do (every SMC particle finished).
    fn exhausted(&self, _state: &Self::State) -> bool {
        false
    }

    /// The population of the result.
    fn final_population(&self, graph: &Graph, state: Self::State) -> Vec<Individual>;

    /// Generation `cx.generation()` (already counted). `Break` when the
    /// observer's interrupt stopped it half-way: the run ends with the
    /// population given, the state after the previous generation.
    fn step<F: Fitness>(
        &self,
        cx: &mut Context<'_, '_, F>,
        state: &mut Self::State,
    ) -> Result<ControlFlow<Vec<Individual>>, OptimizeError>;
}

/// What a method's steps see of the run: the problem, the seed, fitness
/// evaluation (counted) and the generation number.
pub(crate) struct Context<'r, 'o, F: Fitness> {
    pub graph: &'r Graph,
    pub fitness: &'r F,
    pub seed: u64,
    pool: ScratchPool<F::Scratch>,
    progress: Progress<'o>,
}

impl<F: Fitness> Context<'_, '_, F> {
    /// The current generation.
    pub fn generation(&self) -> u64 {
        self.progress.generation
    }

    /// Evaluates the candidates without a known fitness, counting them.
    pub fn evaluate(&mut self, candidates: Vec<Candidate>) -> Vec<Individual> {
        let (evaluated, fresh) = evaluate(self.fitness, candidates, &self.pool, None);
        self.progress.evaluations += fresh;
        evaluated
    }

    /// [`evaluate`](Self::evaluate) unless the observer's interrupt is set
    /// during it: then `None`, and nothing is counted.
    pub fn evaluate_interruptible(
        &mut self,
        candidates: Vec<Candidate>,
    ) -> Option<Vec<Individual>> {
        let stop = self.progress.stop_flag();
        let (evaluated, fresh) = evaluate(self.fitness, candidates, &self.pool, stop);
        if self.progress.interrupted() {
            return None;
        }
        self.progress.evaluations += fresh;
        Some(evaluated)
    }

    /// Evaluates the candidates, skipping (NaN) those not started by the
    /// interrupt or the wall-clock budget's end: for a generation 0 that
    /// may take longer than the whole budget. Counts what was evaluated.
    pub fn evaluate_within_budget(&mut self, candidates: Vec<Candidate>) -> Vec<Individual> {
        let stop = self.progress.stop_flag();
        let deadline = self.progress.deadline();
        let (evaluated, fresh) =
            evaluate_until(self.fitness, candidates, &self.pool, stop, deadline);
        self.progress.evaluations += fresh;
        evaluated
    }

    /// [`evaluate_interruptible`](Self::evaluate_interruptible) that ignores
    /// an interrupt set before generation 1 (random search's first batch is
    /// its generation 0 and always reported).
    pub fn evaluate_stoppable(&mut self, candidates: Vec<Candidate>) -> Vec<Individual> {
        let stop = self.progress.stop_flag();
        let (evaluated, fresh) = evaluate(self.fitness, candidates, &self.pool, stop);
        self.progress.evaluations += fresh;
        evaluated
    }
}

/// Runs `method` on `run` (from its start or its checkpoint) until the
/// budget is spent, the observer stops it, or the method is exhausted.
pub(crate) fn drive<M: Method, F: Fitness>(
    method: &M,
    run: Run<'_, F>,
) -> Result<RunResult, OptimizeError> {
    let Run {
        graph,
        fitness,
        budget,
        seed,
        start,
        observer,
    } = run;
    let id = RunId::new(graph, method.name(), method.params(), seed);
    let progress = Progress::start(id, method.problems(), budget, observer)?;
    let mut cx = Context {
        graph,
        fitness,
        seed,
        pool: ScratchPool::new(),
        progress,
    };
    let mut state = match start {
        Some(cp) => {
            cx.progress.resume(cp)?;
            method.restore(graph, cp)?
        }
        None => method.init(&mut cx)?,
    };
    // A resumed run continues after a reported generation.
    let mut report = start.is_some() || method.reports_initial();
    loop {
        if report {
            let stop = if cx.progress.take_resumed() {
                // This generation was reported before the checkpoint.
                cx.progress.budget_reached()
            } else {
                let population = method.report(graph, &state);
                let save = || method.save(graph, &state);
                cx.progress.generation_done(&population, &save)
            };
            let stop = stop.or_else(|| method.exhausted(&state).then_some(StopReason::Exhausted));
            if let Some(stop) = stop {
                let population = method.final_population(graph, state);
                return Ok(cx.progress.finish(stop, population));
            }
        }
        report = true;
        cx.progress.generation += 1;
        if let ControlFlow::Break(population) = method.step(&mut cx, &mut state)? {
            return Ok(cx.progress.abandon(population));
        }
    }
}
