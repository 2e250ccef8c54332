//! Random search: the baseline every method must beat.

use rayon::prelude::*;

use super::checkpoint::{Checkpoint, RunId, SavedState};
use super::progress::{Candidate, Progress, evaluate};
use super::scratch::ScratchPool;
use super::selection::rank_order;
use super::{Budget, Fitness, Observer, OptimizeError, Optimizer, RunResult, purpose};
use crate::graph::Graph;
use crate::ops::{InitLength, random_individual};
use crate::rng::stream;

/// Draws independent random individuals in batches and keeps the best.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RandomSearch {
    /// Individuals per generation (batch).
    pub batch: usize,
    /// Length of the random individuals.
    pub init: InitLength,
}

impl Optimizer for RandomSearch {
    fn name(&self) -> &'static str {
        "random"
    }

    fn run_from<F: Fitness>(
        &self,
        graph: &Graph,
        fitness: &F,
        budget: &Budget,
        seed: u64,
        start: Option<&Checkpoint>,
        observer: &mut dyn Observer,
    ) -> Result<RunResult, OptimizeError> {
        let problems = if self.batch == 0 {
            vec!["batch must be at least 1".to_string()]
        } else {
            Vec::new()
        };
        let id = RunId::new(graph, self.name(), self, seed);
        let mut progress = Progress::start(id, problems, *budget, observer)?;
        if let Some(cp) = start {
            // Batches are independent: the counters and the best are the state.
            progress.resume(cp)?;
            progress.take_resumed();
            let best = cp.best.restore(graph)?;
            if let Some(stop) = progress.budget_reached() {
                return Ok(progress.finish(stop, vec![best]));
            }
            progress.generation += 1;
        }
        let pool = ScratchPool::new();
        loop {
            let g = progress.generation;
            let batch: Vec<Candidate> = (0..self.batch as u64)
                .into_par_iter()
                .map(|i| {
                    let mut rng = stream(seed, &[g, i, purpose::INIT]);
                    random_individual(graph, &self.init, &mut rng).map(Candidate::new)
                })
                .collect::<Result<_, _>>()?;
            let (mut population, fresh) = evaluate(fitness, batch, &pool, progress.stop_flag());
            if progress.interrupted() && progress.generation > 0 {
                return Ok(progress.abandon(Vec::new()));
            }
            progress.evaluations += fresh;
            let save = || SavedState::Population {
                individuals: Vec::new(),
            };
            if let Some(stop) = progress.generation_done(&population, &save) {
                population.sort_by(|a, b| rank_order(a.fitness, b.fitness));
                population.truncate(1);
                return Ok(progress.finish(stop, population));
            }
            progress.generation += 1;
        }
    }
}
