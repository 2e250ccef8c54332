//! Random search: the baseline every method must beat.

use std::borrow::Cow;
use std::ops::ControlFlow;

use rayon::prelude::*;

use super::checkpoint::{Checkpoint, SavedState};
use super::driver::{Context, Method, Run, drive};
use super::evaluation::Candidate;
use super::selection::rank_order;
use super::{Fitness, Individual, OptimizeError, Optimizer, RunResult, purpose};
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

    fn run_from<F: Fitness>(&self, run: Run<'_, F>) -> Result<RunResult, OptimizeError> {
        drive(self, run)
    }
}

impl RandomSearch {
    /// Batch `g`, evaluated.
    fn batch<F: Fitness>(
        &self,
        cx: &Context<'_, '_, F>,
        g: u64,
    ) -> Result<Vec<Candidate>, OptimizeError> {
        let (graph, seed) = (cx.graph, cx.seed);
        Ok((0..self.batch as u64)
            .into_par_iter()
            .map(|i| {
                let mut rng = stream(seed, &[g, i, purpose::INIT]);
                random_individual(graph, &self.init, &mut rng).map(Candidate::new)
            })
            .collect::<Result<_, _>>()?)
    }
}

/// Batches are independent: the state is the last batch (after a resume,
/// the best so far alone).
impl Method for RandomSearch {
    type Params = Self;
    type State = Vec<Individual>;

    fn name(&self) -> &'static str {
        "random"
    }

    fn params(&self) -> &Self {
        self
    }

    fn problems(&self) -> Vec<String> {
        if self.batch == 0 {
            vec!["batch must be at least 1".to_string()]
        } else {
            Vec::new()
        }
    }

    fn init<F: Fitness>(
        &self,
        cx: &mut Context<'_, '_, F>,
    ) -> Result<Vec<Individual>, OptimizeError> {
        // An interrupt stops the batch but not the run: generation 0 is reported.
        let batch = self.batch(cx, 0)?;
        Ok(cx.evaluate_stoppable(batch))
    }

    fn restore(
        &self,
        graph: &Graph,
        checkpoint: &Checkpoint,
    ) -> Result<Vec<Individual>, OptimizeError> {
        Ok(vec![checkpoint.best.restore(graph)?])
    }

    fn save(&self, _graph: &Graph, _state: &Vec<Individual>) -> SavedState {
        SavedState::Population {
            individuals: Vec::new(),
            split_bits: None,
            challenge: None,
        }
    }

    fn report<'s>(&self, _graph: &Graph, state: &'s Vec<Individual>) -> Cow<'s, [Individual]> {
        Cow::Borrowed(state)
    }

    fn final_population(&self, _graph: &Graph, mut state: Vec<Individual>) -> Vec<Individual> {
        state.sort_by(|a, b| rank_order(a.fitness, b.fitness));
        state.truncate(1);
        state
    }

    fn step<F: Fitness>(
        &self,
        cx: &mut Context<'_, '_, F>,
        state: &mut Vec<Individual>,
    ) -> Result<ControlFlow<Vec<Individual>>, OptimizeError> {
        let batch = self.batch(cx, cx.generation())?;
        match cx.evaluate_interruptible(batch) {
            Some(population) => {
                *state = population;
                Ok(ControlFlow::Continue(()))
            }
            None => Ok(ControlFlow::Break(Vec::new())),
        }
    }
}
