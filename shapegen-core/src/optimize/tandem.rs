//! The tandem: the GA and RJMCMC chains side by side, trading their best.

use std::borrow::Cow;
use std::ops::ControlFlow;

use serde::{Deserialize, Serialize};

use super::balance::Balance;
use super::challenger::{Challenged, Lineage, best_of};
use super::checkpoint::{Checkpoint, SavedState};
use super::driver::{Context, Method, Run, drive};
use super::ga::GaState;
use super::rjmcmc::Chains;
use super::selection::{best_distinct, rank_order};
use super::smc::Particles;
use super::{
    Fitness, Ga, GaParams, Individual, OptimizeError, Optimizer, Rjmcmc, RjmcmcParams, RunResult,
    Smc, SmcParams,
};
use crate::graph::Graph;

/// The GA's streams in a tandem: island 0's, apart from the chains' (which
/// are RJMCMC's own). Its `k`-th challenger draws from island `k`'s.
const GA_STREAMS: Option<u64> = Some(0);

/// Parameters of the [`Tandem`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct TandemParams {
    /// The GA.
    pub ga: GaParams,
    /// The chains.
    pub rjmcmc: RjmcmcParams,
    /// Generations between two exchanges.
    pub interval: u64,
    /// Distinct models each side sends at an exchange.
    pub migrants: usize,
    /// A first phase: SOSMC (or SMC) with these parameters builds models
    /// until every particle is complete (the chains wait), and the GA
    /// starts from their best distinct valid ones instead of random
    /// individuals. `None` (the default): no first phase.
    #[serde(default)]
    pub first_phase: Option<SmcParams>,
    /// Whether the two sides' shares of the evaluations follow what each
    /// finds (see [`super::Balance`]): the side that pushes the best
    /// fitness further per evaluation over an exchange interval leans the
    /// run toward itself, and the other steps only every 2, 4 or 8
    /// generations. Off: both step every generation.
    #[serde(default)]
    pub balance: bool,
    /// Whether an exchange also sends the GA's best to the chains (to
    /// those holding the worst models, where better). Off: only the
    /// chains' best go to the GA, and the chains explore on their own;
    /// where the GA settles in one basin (a spaceship that must grow
    /// toward a volume to reach it), its models would pull every chain
    /// into it.
    #[serde(default = "yes")]
    pub to_chains: bool,
    /// GA steps without progress (its best rising by
    /// [`PROGRESS_SHARE`](super::PROGRESS_SHARE) of its gain since its first
    /// generation) after which a *challenger* starts: a second GA
    /// population from random models, which steps in turn with the GA,
    /// takes its place if its best overtakes the GA's, and is dropped if it
    /// stalls as long below it (see `challenger`). `0`: never, the value
    /// of [`new`](Self::new) and of saved parameters without the field;
    /// [`recommended`](Self::recommended) (what `--method tandem` runs)
    /// sets [`TANDEM_CHALLENGE`].
    #[serde(default)]
    pub challenge: u64,
}

/// `true`, the default of [`TandemParams::to_chains`] in older files.
fn yes() -> bool {
    true
}

/// The default [`TandemParams::interval`].
pub const TANDEM_INTERVAL: u64 = 10;
/// The default [`TandemParams::migrants`].
pub const TANDEM_MIGRANTS: usize = 2;
/// The GA's local search in [`TandemParams::recommended`] (children a
/// generation, at most the GA's non-elite places).
pub const TANDEM_LOCAL_SEARCH: usize = 30;
/// The [`TandemParams::challenge`] of [`TandemParams::recommended`]: GA
/// steps without progress before a challenger starts.
pub const TANDEM_CHALLENGE: u64 = super::DEFAULT_CHALLENGE;

impl TandemParams {
    /// The GA and the chains of `ga` and `rjmcmc`, with the default exchange.
    #[must_use]
    pub const fn new(ga: GaParams, rjmcmc: RjmcmcParams) -> Self {
        Self {
            ga,
            rjmcmc,
            interval: TANDEM_INTERVAL,
            migrants: TANDEM_MIGRANTS,
            first_phase: None,
            balance: false,
            to_chains: true,
            challenge: 0,
        }
    }

    /// The tandem as shapegen recommends it: the GA of `ga` with elite
    /// deduplication and [`TANDEM_LOCAL_SEARCH`] local-search children a
    /// generation (at most its non-elite places), beside the chains of
    /// `rjmcmc`, with the default exchange interval and migrants, the
    /// [`balance`](Self::balance) on, the chains' best going to the GA
    /// but not the GA's to the chains ([`to_chains`](Self::to_chains)
    /// off), and a challenger after [`TANDEM_CHALLENGE`] GA steps without
    /// progress ([`challenge`](Self::challenge)). `reproduction.md`
    /// (*Beyond the paper*) has the measurements behind these choices.
    #[must_use]
    pub fn recommended(ga: GaParams, rjmcmc: RjmcmcParams) -> Self {
        Self {
            balance: true,
            to_chains: false,
            challenge: TANDEM_CHALLENGE,
            ..Self::new(
                GaParams {
                    // The tandem's own `challenge` governs its GA.
                    challenge: 0,
                    elite_dedup: true,
                    local_search: TANDEM_LOCAL_SEARCH.min(ga.children()),
                    ..ga
                },
                rjmcmc,
            )
        }
    }

    /// Every problem with these parameters.
    pub fn problems(&self) -> Vec<String> {
        let mut p = self.ga.problems();
        p.extend(self.rjmcmc.problems());
        if let Some(first) = &self.first_phase {
            p.extend(first.problems());
        }
        if self.interval == 0 {
            p.push("interval must be at least 1 generation".into());
        }
        if self.migrants == 0 {
            p.push("migrants must be at least 1".into());
        }
        if self.migrants > self.ga.children() {
            p.push(format!(
                "migrants ({}) must not exceed the GA's non-elite places ({})",
                self.migrants,
                self.ga.children()
            ));
        }
        if self.migrants > self.rjmcmc.chains {
            p.push(format!(
                "migrants ({}) must not exceed the chains ({})",
                self.migrants, self.rjmcmc.chains
            ));
        }
        p
    }
}

/// The GA (paper Algorithm 1) and RJMCMC with parallel tempering, run side
/// by side: every generation the GA breeds and evaluates a generation and
/// every chain makes one proposal. Every `interval` generations the two
/// trade their best: the chains' `migrants` best distinct models replace the
/// GA's worst, and (if [`TandemParams::to_chains`]) the GA's `migrants` best
/// distinct models replace the states of the chains that hold the worst
/// models, where they are better. With [`TandemParams::balance`], the side
/// that finds more gets more of the evaluations (see `balance`).
///
/// The GA exploits a target fast but can collapse onto one model it cannot
/// leave, or spend its time on large models early; the tempered chains keep
/// crossing valleys and start small. Where one side stalls the other carries
/// the run, and what one finds the other refines. The GA draws from island
/// 0's streams and the chains from RJMCMC's, so the run is deterministic for
/// any thread count.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tandem {
    /// The parameters.
    pub params: TandemParams,
}

impl Tandem {
    /// A tandem with the given parameters.
    #[must_use]
    pub const fn new(params: TandemParams) -> Self {
        Self { params }
    }

    fn ga(&self) -> Ga {
        Ga::new(self.params.ga)
    }

    fn rjmcmc(&self) -> Rjmcmc {
        Rjmcmc::new(self.params.rjmcmc)
    }

    /// The GA's population `ga`, from island 0's streams, with no
    /// challenger yet.
    fn fresh(ga: GaState) -> Challenged {
        Challenged::new(ga, GA_STREAMS, Lineage::ALONE)
    }

    /// The exchange: the chains' best to the GA (replacing its worst), the
    /// GA's best to the chains holding the worst models, where better.
    fn exchange(&self, graph: &Graph, state: &mut TandemState) {
        let n = self.params.migrants;
        let TandemState { ga, chains, .. } = state;
        let ga = &mut ga.incumbent;
        let mut by_fitness: Vec<usize> = (0..chains.chains.len()).collect();
        by_fitness.sort_by(|&a, &b| rank_order(chains.chains[a].fitness, chains.chains[b].fitness));
        let from_chains: Vec<Individual> =
            best_distinct(graph, by_fitness.iter().map(|&i| &chains.chains[i]), n)
                .into_iter()
                .cloned()
                .collect();
        // The chains' worst first; each GA migrant takes one place if better.
        if self.params.to_chains {
            let from_ga: Vec<Individual> = best_distinct(graph, ga.population.iter(), n)
                .into_iter()
                .cloned()
                .collect();
            for (migrant, &place) in from_ga.into_iter().zip(by_fitness.iter().rev()) {
                if rank_order(migrant.fitness, chains.chains[place].fitness).is_lt() {
                    chains.chains[place] = migrant;
                }
            }
        }
        let mut population = std::mem::take(&mut ga.population);
        let keep = population.len() - from_chains.len();
        population.truncate(keep);
        population.extend(from_chains);
        ga.replace(population);
    }
}

impl Optimizer for Tandem {
    fn name(&self) -> &'static str {
        "tandem"
    }

    fn run_from<F: Fitness>(&self, run: Run<'_, F>) -> Result<RunResult, OptimizeError> {
        drive(self, run)
    }
}

/// The tandem's state: the GA's population and the chains, and while the
/// first phase runs, its particles (the GA's population is empty then).
pub(crate) struct TandemState {
    /// The GA's population, with its challenger ([`TandemParams::challenge`]).
    ga: Challenged,
    chains: Chains,
    first: Option<(Smc, Particles)>,
    /// How the sides share the evaluations (even unless
    /// [`TandemParams::balance`]).
    balance: Balance,
}

impl TandemState {
    /// The best fitness of the GA's populations (with its challenger's)
    /// and of the chains (−∞ for none; `f64::max` passes over NaN).
    fn bests(&self) -> [f64; 2] {
        [self.ga.best(), best_of(&self.chains.chains)]
    }

    /// Both sides' models, best first (stable: the GA's, or the first
    /// phase's, before the chains' on ties).
    fn merged(&self, graph: &Graph) -> Vec<Individual> {
        let mut all: Vec<Individual> = match &self.first {
            Some((smc, particles)) => smc.report(graph, particles).into_owned(),
            None => self.ga.incumbent.population.clone(),
        };
        all.extend(self.ga.challenger_models().iter().cloned());
        all.extend(self.chains.chains.iter().cloned());
        all.sort_by(|a, b| rank_order(a.fitness, b.fitness));
        all
    }
}

impl Method for Tandem {
    type Params = TandemParams;
    type State = TandemState;

    fn name(&self) -> &'static str {
        "tandem"
    }

    fn params(&self) -> &TandemParams {
        &self.params
    }

    fn problems(&self) -> Vec<String> {
        self.params.problems()
    }

    fn init<F: Fitness>(&self, cx: &mut Context<'_, '_, F>) -> Result<TandemState, OptimizeError> {
        let chains = self.rjmcmc().init(cx)?;
        if let Some(params) = self.params.first_phase {
            let smc = Smc::new(params);
            let particles = smc.init(cx)?;
            return Ok(TandemState {
                ga: Self::fresh(GaState::new(Vec::new())),
                chains,
                first: Some((smc, particles)),
                balance: Balance::new(),
            });
        }
        let initial = self
            .ga()
            .initial_population(cx.graph, cx.seed, GA_STREAMS)?;
        let ga = GaState::new(cx.evaluate_within_budget(initial));
        Ok(TandemState {
            ga: Self::fresh(ga),
            chains,
            first: None,
            balance: Balance::new(),
        })
    }

    fn restore(
        &self,
        graph: &Graph,
        checkpoint: &Checkpoint,
    ) -> Result<TandemState, OptimizeError> {
        let SavedState::Tandem {
            ga,
            chains,
            balance,
            challenge,
        } = &checkpoint.state
        else {
            return Err(OptimizeError::Checkpoint("it holds no tandem state".into()));
        };
        let chains = self.rjmcmc().restore_state(graph, chains)?;
        let balance = balance.unwrap_or_default();
        if let SavedState::Particles { .. } = ga.as_ref() {
            let Some(params) = self.params.first_phase else {
                return Err(OptimizeError::Checkpoint(
                    "it holds SMC particles, but this tandem has no first phase".into(),
                ));
            };
            let smc = Smc::new(params);
            return Ok(TandemState {
                ga: Self::fresh(GaState::new(Vec::new())),
                chains,
                first: Some((smc, smc.restore_state(graph, ga)?)),
                balance,
            });
        }
        let incumbent = self.ga().restore_state(graph, ga)?;
        let ga = Challenged::restore(
            &self.ga(),
            graph,
            incumbent,
            GA_STREAMS,
            Lineage::ALONE,
            challenge.as_ref(),
        )?;
        Ok(TandemState {
            ga,
            chains,
            first: None,
            balance,
        })
    }

    fn save(&self, graph: &Graph, state: &TandemState) -> SavedState {
        let ga = match &state.first {
            Some((smc, particles)) => smc.save(graph, particles),
            None => self.ga().save_state(graph, &state.ga.incumbent),
        };
        SavedState::Tandem {
            ga: Box::new(ga),
            chains: Box::new(self.rjmcmc().save_state(graph, &state.chains)),
            balance: self.params.balance.then_some(state.balance),
            challenge: (self.params.challenge > 0 && state.first.is_none())
                .then(|| state.ga.save(&self.ga(), graph)),
        }
    }

    fn report<'s>(&self, graph: &Graph, state: &'s TandemState) -> Cow<'s, [Individual]> {
        Cow::Owned(state.merged(graph))
    }

    fn final_population(&self, graph: &Graph, state: TandemState) -> Vec<Individual> {
        state.merged(graph)
    }

    fn step<F: Fitness>(
        &self,
        cx: &mut Context<'_, '_, F>,
        state: &mut TandemState,
    ) -> Result<ControlFlow<Vec<Individual>>, OptimizeError> {
        let generation = cx.generation();
        if let Some((smc, particles)) = &mut state.first {
            // The first phase: the particles grow, the chains wait.
            let smc = *smc;
            if let ControlFlow::Break(_) = smc.step(cx, particles)? {
                return Ok(ControlFlow::Break(state.merged(cx.graph)));
            }
            if smc.exhausted(particles) {
                let models = smc.report(cx.graph, particles).into_owned();
                state.ga = Self::fresh(self.ga().population_from(cx, &models, GA_STREAMS)?);
                state.first = None;
            }
            return Ok(ControlFlow::Continue(()));
        }
        // One evaluation for both sides, so an interrupt drops the whole
        // generation: the GA's children first, then the chains' proposals
        // (each side only in the generations where it steps).
        let rjmcmc = self.rjmcmc();
        let (ga_steps, chains_step) = (
            state.balance.ga_steps(generation),
            state.balance.chains_step(generation),
        );
        let (proposals, mut candidates) = if chains_step {
            rjmcmc.proposals(cx.graph, cx.seed, generation, &state.chains)
        } else {
            Default::default()
        };
        let chain_count = candidates.len();
        let side = ga_steps.then(|| state.ga.side());
        let mut next = match side {
            Some(side) => state
                .ga
                .candidates(&self.ga(), cx.graph, cx.seed, generation, side)?,
            None => Vec::new(),
        };
        next.append(&mut candidates);
        let Some(mut evaluated) = cx.evaluate_interruptible(next) else {
            return Ok(ControlFlow::Break(state.merged(cx.graph)));
        };
        let chains = evaluated.split_off(evaluated.len() - chain_count);
        state.balance.spent(evaluated.len(), chain_count);
        if let Some(side) = side {
            state.ga.settle(side, evaluated, self.params.challenge);
        }
        if chains_step {
            rjmcmc.accept(cx, &mut state.chains, chains, &proposals);
        }
        if generation.is_multiple_of(self.params.interval) {
            if self.params.balance {
                state.balance.judge(state.bests());
            }
            self.exchange(cx.graph, state);
            if self.params.balance {
                state.balance.start(state.bests());
            }
        }
        Ok(ControlFlow::Continue(()))
    }
}
