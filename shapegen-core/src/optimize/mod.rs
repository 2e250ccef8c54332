//! Optimizers over chromosomes: the genetic algorithm ([`Ga`], paper
//! Algorithm 1) and the paper's baselines — [`Smc`] (SMC and SOSMC, Ritchie
//! et al. 2015) and [`Rjmcmc`] (Talton et al. 2011, with parallel tempering)
//! — plus [`RandomSearch`], all behind one [`Optimizer`] trait with the same
//! [`Fitness`], [`Budget`] and [`Observer`]. Beyond the paper: the
//! [`IslandGa`], the [`Hybrid`] (GA, then RJMCMC once it stalls) and the
//! [`Tandem`] (GA and RJMCMC side by side, trading their best; with
//! [`TandemParams::recommended`] the most robust method measured so far),
//! and the GA's optional local search on elites ([`GaParams::local_search`]).
//!
//! Runs are deterministic: every random decision comes from a stream derived
//! from `(seed, generation, index, purpose)` (see [`crate::rng`]), fitness
//! evaluation is pure, and sorts are stable, so the same seed gives the same
//! result whatever the number of threads. Fitness is evaluated in parallel on
//! the current rayon pool; run inside `ThreadPool::install` to choose threads.

mod adaptive_split;
mod balance;
mod budget;
mod challenger;
mod checkpoint;
mod driver;
mod evaluation;
mod fitness;
mod ga;
mod hybrid;
mod island;
mod method;
mod observer;
mod progress;
mod random;
mod rjmcmc;
mod selection;
mod smc;
mod tandem;

use std::time::Duration;

pub use adaptive_split::{AdaptiveSplit, MIN_SHARE, SMOOTHING};
pub use balance::{Balance, MAX_LEAN};
pub use budget::{Budget, StopReason};
pub use challenger::{DEFAULT_CHALLENGE, PROGRESS_SHARE, Stall};
pub use checkpoint::{
    CHECKPOINT_VERSION, Checkpoint, FNV1A_START, SavedChallenge, SavedChallenger, SavedIndividual,
    SavedParticle, SavedState, fnv1a,
};
pub use driver::Run;
pub use evaluation::{Pooled, ScratchPool, evaluate_all};
pub use fitness::{Fitness, FnFitness, is_valid_score};
pub use ga::{Ga, GaParams};
pub use hybrid::{HYBRID_PATIENCE_SHARE, Hybrid, HybridParams};
pub use island::{IslandGa, IslandParams, Topology};
pub use method::MethodParams;
pub use observer::{GenerationStats, Interruptible, NoObserver, Observer};
pub use random::RandomSearch;
pub use rjmcmc::{DelayedRejection, Ladder, LogLikelihood, Rjmcmc, RjmcmcParams};
pub use selection::{Roulette, RouletteShift, rank_order, tournament};
pub use smc::{MAX_STEP_GENES, Resampling, SlotOrder, Smc, SmcParams, SmcWeights};
pub use tandem::{
    TANDEM_CHALLENGE, TANDEM_INTERVAL, TANDEM_LOCAL_SEARCH, TANDEM_MIGRANTS, Tandem, TandemParams,
};

use crate::genome::Chromosome;
use crate::graph::Graph;
use crate::ops::OpError;

/// A chromosome with its fitness.
#[derive(Clone, Debug, PartialEq)]
pub struct Individual {
    /// The chromosome.
    pub chromosome: Chromosome,
    /// Its fitness (non-finite = failed evaluation).
    pub fitness: f64,
}

/// What a run produced.
#[derive(Clone, Debug)]
pub struct RunResult {
    /// The best chromosome seen.
    pub best: Chromosome,
    /// Its fitness.
    pub best_fitness: f64,
    /// Fitness evaluations performed.
    pub evaluations: u64,
    /// Generations performed after the initial one.
    pub generations: u64,
    /// Wall-clock time.
    pub elapsed: Duration,
    /// Why the run ended.
    pub stop: StopReason,
    /// The final population, best first.
    pub population: Vec<Individual>,
}

/// Why a run could not start.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum OptimizeError {
    /// The parameters are unusable.
    #[error("invalid optimizer parameters: {0}")]
    Params(String),
    /// The budget sets no limit.
    #[error("the budget sets no limit: give generations, evaluations or wall time")]
    UnboundedBudget,
    /// The initial population could not be built.
    #[error("cannot build the initial population: {0}")]
    Init(#[from] OpError),
    /// A checkpoint that does not belong to this run.
    #[error("cannot resume from this checkpoint: {0}")]
    Checkpoint(String),
}

/// An optimization method over the chromosomes of a generator graph.
///
/// Every method runs in the same loop (`driver`): parameter and budget
/// checks, start or resume, one report per generation, stop, finish; a
/// method's file holds only its algorithm.
pub trait Optimizer {
    /// Short name of the method (`"ga"`, `"smc"`, ...).
    fn name(&self) -> &'static str;

    /// Maximizes `fitness` over chromosomes of `graph` until `budget` is spent,
    /// calling `observer` after every generation.
    fn run<F: Fitness>(
        &self,
        graph: &Graph,
        fitness: &F,
        budget: &Budget,
        seed: u64,
        observer: &mut dyn Observer,
    ) -> Result<RunResult, OptimizeError> {
        self.run_from(Run {
            graph,
            fitness,
            budget: *budget,
            seed,
            start: None,
            observer,
        })
    }

    /// Continues the run saved in `checkpoint` (see
    /// [`GenerationStats::checkpoint`]) until `budget` is spent — counted
    /// from the start of the original run — exactly as the uninterrupted run
    /// would have. Refuses a checkpoint of another method, parameter set,
    /// seed or generator graph.
    fn resume<F: Fitness>(
        &self,
        graph: &Graph,
        fitness: &F,
        budget: &Budget,
        checkpoint: &Checkpoint,
        observer: &mut dyn Observer,
    ) -> Result<RunResult, OptimizeError> {
        self.run_from(Run {
            graph,
            fitness,
            budget: *budget,
            seed: checkpoint.seed,
            start: Some(checkpoint),
            observer,
        })
    }

    /// [`run`](Self::run) from the beginning (`run.start = None`) or
    /// [`resume`](Self::resume) from a checkpoint.
    fn run_from<F: Fitness>(&self, run: Run<'_, F>) -> Result<RunResult, OptimizeError>;
}

/// What the optimizers' unit tests share.
#[cfg(test)]
pub(crate) mod test_support {
    use super::Individual;
    use crate::genome::Chromosome;
    use crate::graph::GraphBuilder;

    /// A maker of individuals that differ only in fitness (the root gene of
    /// a one-node graph), for tests where only fitness matters.
    pub fn with_fitness() -> impl Fn(f64) -> Individual {
        let graph = GraphBuilder::new("t")
            .start("S")
            .node("S", |n| n)
            .build()
            .unwrap();
        let root = Chromosome::root(&graph, &mut crate::rng::stream(0, &[]));
        move |fitness| Individual {
            chromosome: root.clone(),
            fitness,
        }
    }
}

/// Stream purposes, so that streams for different decisions never coincide.
pub(crate) mod purpose {
    pub const INIT: u64 = 1;
    pub const BREED: u64 = 2;
    pub const MIGRATE: u64 = 3;
    pub const LOCAL: u64 = 4;
}
