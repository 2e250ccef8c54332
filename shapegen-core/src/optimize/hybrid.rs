//! The hybrid: optionally SOSMC (or SMC) to build the first models, the GA
//! while it improves, then RJMCMC chains started from the GA's best models
//! (the paper's future work).

use std::borrow::Cow;
use std::ops::ControlFlow;

use serde::{Deserialize, Serialize};

use super::challenger::Challenged;
use super::checkpoint::{Checkpoint, SavedState};
use super::driver::{Context, Method, Run, drive};
use super::rjmcmc::Chains;
use super::selection::{best_distinct_repeated, rank_order};
use super::smc::Particles;
use super::{
    Fitness, Ga, GaParams, Individual, OptimizeError, Optimizer, Rjmcmc, RjmcmcParams, RunResult,
    Smc, SmcParams,
};
use crate::graph::Graph;

/// Parameters of the [`Hybrid`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct HybridParams {
    /// The first phase's GA.
    pub ga: GaParams,
    /// The second phase's RJMCMC (its `chains` start from the GA's best
    /// distinct models; its `init` is not used).
    pub rjmcmc: RjmcmcParams,
    /// Generations without a gain of the GA's best before the switch, at
    /// least.
    pub patience: u64,
    /// The share of the generations run so far that the GA's best must
    /// also have gone without a gain (0 to 1; 0: `patience` alone). Where
    /// generations are fast, a GA that still improves in rare steps after
    /// long plateaus (the city skylines) keeps going; a GA collapsed early
    /// (within a few hundred generations) still hands over after about
    /// `patience`.
    #[serde(default = "default_patience_share")]
    pub patience_share: f64,
    /// A first phase: SOSMC (or SMC) with these parameters builds models
    /// until every particle is complete, and the GA starts from their best
    /// distinct valid ones (repeated in turn to fill its population) instead
    /// of random individuals. `None` (the default): no first phase.
    #[serde(default)]
    pub first_phase: Option<SmcParams>,
}

/// The default [`HybridParams::patience_share`].
pub const HYBRID_PATIENCE_SHARE: f64 = 0.5;

fn default_patience_share() -> f64 {
    HYBRID_PATIENCE_SHARE
}

impl HybridParams {
    /// Whether the GA hands over after `stalled` generations without a
    /// gain, at generation `generation` (the generations run, this one
    /// included).
    #[must_use]
    pub fn switches(&self, stalled: u64, generation: u64) -> bool {
        let share = (self.patience_share * generation as f64).ceil() as u64;
        stalled >= self.patience.max(share)
    }

    /// Every problem with these parameters.
    pub fn problems(&self) -> Vec<String> {
        let mut p = self.ga.problems();
        p.extend(self.rjmcmc.problems());
        if let Some(first) = &self.first_phase {
            p.extend(first.problems());
        }
        if self.patience == 0 {
            p.push("patience must be at least 1 generation".into());
        }
        if !(0.0..=1.0).contains(&self.patience_share) {
            p.push(format!(
                "patience_share must be between 0 and 1 (got {})",
                self.patience_share
            ));
        }
        p
    }
}

/// Optionally SOSMC (or SMC) until every particle is a complete model, then
/// the GA (paper Algorithm 1) from the particles' best distinct models, as
/// long as its best improves; once it has not
/// for `patience` generations and for `patience_share` of the generations
/// run so far, RJMCMC with parallel tempering continues from
/// the GA population's best distinct models (one chain each, the best on the
/// coldest chain) for the rest of the budget.
///
/// The GA exploits a target fast; when its population has collapsed onto one
/// model it cannot leave (a tree shrunk to its trunk, say), the chains'
/// tempered acceptance can cross the valley. Each phase draws from its own
/// method's streams, so the run is deterministic for any thread count.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hybrid {
    /// The parameters.
    pub params: HybridParams,
}

impl Hybrid {
    /// A hybrid with the given parameters.
    #[must_use]
    pub const fn new(params: HybridParams) -> Self {
        Self { params }
    }

    fn ga(&self) -> Ga {
        Ga::new(self.params.ga)
    }

    fn rjmcmc(&self) -> Rjmcmc {
        Rjmcmc::new(self.params.rjmcmc)
    }

    /// The first phase's SMC, if there is one.
    fn first_phase(&self) -> Option<Smc> {
        self.params.first_phase.map(Smc::new)
    }

    /// The chains the GA hands over: its best distinct valid models (the
    /// population is sorted best first), repeated when there are fewer.
    fn chains_from(&self, graph: &Graph, population: &[Individual]) -> Chains {
        let n = self.params.rjmcmc.chains;
        let mut chains = best_distinct_repeated(graph, population.iter(), n);
        if chains.is_empty() {
            chains = vec![population[0].clone(); n];
        }
        Chains {
            chains,
            betas: self.params.rjmcmc.ladder.betas(self.params.rjmcmc.chains),
        }
    }
}

/// The phase a hybrid run is in.
pub(crate) enum Phase {
    /// SOSMC (or SMC) building the GA's first models.
    Smc(Smc, Particles),
    /// The GA, with its best so far and the generations since it last improved.
    Ga {
        state: Box<Challenged>,
        best: f64,
        stalled: u64,
    },
    /// RJMCMC from the GA's best.
    Rjmcmc(Chains),
}

impl Phase {
    fn ga(state: Challenged) -> Self {
        let state = Box::new(state);
        let best = state
            .incumbent
            .population
            .first()
            .map_or(f64::NAN, |i| i.fitness);
        Self::Ga {
            state,
            best,
            stalled: 0,
        }
    }
}

impl Optimizer for Hybrid {
    fn name(&self) -> &'static str {
        "hybrid"
    }

    fn run_from<F: Fitness>(&self, run: Run<'_, F>) -> Result<RunResult, OptimizeError> {
        drive(self, run)
    }
}

impl Method for Hybrid {
    type Params = HybridParams;
    type State = Phase;

    fn name(&self) -> &'static str {
        "hybrid"
    }

    fn params(&self) -> &HybridParams {
        &self.params
    }

    fn problems(&self) -> Vec<String> {
        self.params.problems()
    }

    fn init<F: Fitness>(&self, cx: &mut Context<'_, '_, F>) -> Result<Phase, OptimizeError> {
        Ok(match self.first_phase() {
            Some(smc) => Phase::Smc(smc, smc.init(cx)?),
            None => Phase::ga(self.ga().init(cx)?),
        })
    }

    /// With a first phase, generation 0 holds only root genes (as SMC's).
    fn reports_initial(&self) -> bool {
        self.params.first_phase.is_none()
    }

    fn restore(&self, graph: &Graph, checkpoint: &Checkpoint) -> Result<Phase, OptimizeError> {
        let SavedState::Hybrid {
            best_bits,
            stalled,
            state,
        } = &checkpoint.state
        else {
            return Err(OptimizeError::Checkpoint("it holds no hybrid state".into()));
        };
        Ok(match state.as_ref() {
            SavedState::Chains { .. } => Phase::Rjmcmc(self.rjmcmc().restore_state(graph, state)?),
            SavedState::Particles { .. } => {
                let Some(smc) = self.first_phase() else {
                    return Err(OptimizeError::Checkpoint(
                        "it holds SMC particles, but this hybrid has no first phase".into(),
                    ));
                };
                Phase::Smc(smc, smc.restore_state(graph, state)?)
            }
            _ => Phase::Ga {
                state: Box::new(self.ga().restore_challenged(graph, state)?),
                best: f64::from_bits(*best_bits),
                stalled: *stalled,
            },
        })
    }

    fn save(&self, graph: &Graph, phase: &Phase) -> SavedState {
        let (best_bits, stalled, state) = match phase {
            Phase::Ga {
                state,
                best,
                stalled,
            } => (
                best.to_bits(),
                *stalled,
                self.ga().save_challenged(graph, state),
            ),
            Phase::Rjmcmc(chains) => (0, 0, self.rjmcmc().save_state(graph, chains)),
            Phase::Smc(smc, particles) => (0, 0, smc.save(graph, particles)),
        };
        SavedState::Hybrid {
            best_bits,
            stalled,
            state: Box::new(state),
        }
    }

    fn report<'s>(&self, graph: &Graph, phase: &'s Phase) -> Cow<'s, [Individual]> {
        match phase {
            Phase::Smc(smc, particles) => smc.report(graph, particles),
            Phase::Ga { state, .. } => self.ga().report(graph, state),
            Phase::Rjmcmc(chains) => Cow::Borrowed(&chains.chains),
        }
    }

    fn final_population(&self, graph: &Graph, phase: Phase) -> Vec<Individual> {
        match phase {
            Phase::Smc(smc, particles) => smc.final_population(graph, particles),
            Phase::Ga { state, .. } => self.ga().final_population(graph, *state),
            Phase::Rjmcmc(chains) => chains.chains,
        }
    }

    fn step<F: Fitness>(
        &self,
        cx: &mut Context<'_, '_, F>,
        phase: &mut Phase,
    ) -> Result<ControlFlow<Vec<Individual>>, OptimizeError> {
        let (state, best, stalled) = match phase {
            Phase::Rjmcmc(chains) => return self.rjmcmc().step(cx, chains),
            Phase::Smc(smc, particles) => {
                let smc = *smc;
                if let ControlFlow::Break(population) = smc.step(cx, particles)? {
                    return Ok(ControlFlow::Break(population));
                }
                if smc.exhausted(particles) {
                    let models = smc.report(cx.graph, particles).into_owned();
                    *phase = Phase::ga(Ga::alone(self.ga().population_from(cx, &models, None)?));
                }
                return Ok(ControlFlow::Continue(()));
            }
            Phase::Ga {
                state,
                best,
                stalled,
            } => (state, best, stalled),
        };
        if let ControlFlow::Break(population) = self.ga().step(cx, state)? {
            return Ok(ControlFlow::Break(population));
        }
        let now = state.incumbent.population[0].fitness;
        if rank_order(now, *best).is_lt() {
            (*best, *stalled) = (now, 0);
        } else {
            *stalled += 1;
        }
        if self.params.switches(*stalled, cx.generation()) {
            *phase = Phase::Rjmcmc(self.chains_from(cx.graph, &state.incumbent.population));
        }
        Ok(ControlFlow::Continue(()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params(patience: u64, patience_share: f64) -> HybridParams {
        HybridParams {
            ga: GaParams::default(),
            rjmcmc: RjmcmcParams::paper(12, crate::ops::InitLength::Around { l0: 20 }),
            patience,
            patience_share,
            first_phase: None,
        }
    }

    #[test]
    fn the_switch_waits_for_patience_and_for_the_share_of_the_run() {
        // Share 0: patience alone.
        assert!(!params(100, 0.0).switches(99, 5000));
        assert!(params(100, 0.0).switches(100, 5000));
        // Early (a collapse within the first hundreds): patience decides.
        assert!(!params(100, 0.5).switches(99, 150));
        assert!(params(100, 0.5).switches(100, 200));
        // Late, on a long plateau: half of the generations run.
        assert!(!params(100, 0.5).switches(100, 2000));
        assert!(!params(100, 0.5).switches(999, 1999));
        assert!(params(100, 0.5).switches(1000, 2000));
        // A GA that never improved switches at `patience` whatever the share.
        assert!(params(7, 1.0).switches(7, 7));
    }
}
