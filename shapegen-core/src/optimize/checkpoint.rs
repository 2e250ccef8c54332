//! Snapshots of a run between two generations, to resume it later.
//!
//! Every optimizer draws its random decisions from streams derived from
//! `(seed, generation, index)`, so the state between two generations is just
//! the population (GA), the particles with their open slots (SMC, SOSMC) or
//! the chains with their inverse temperatures (RJMCMC), plus the counters.
//! Resuming from a [`Checkpoint`] therefore continues **bit-identically** to
//! the run that was never interrupted (for budgets in generations or
//! evaluations; a wall-time budget counts the time before the checkpoint).
//!
//! A checkpoint is taken from the observer with
//! [`GenerationStats::checkpoint`](super::GenerationStats::checkpoint) and
//! passed to [`Optimizer::resume`](super::Optimizer::resume). It records the
//! method, a fingerprint of its parameters, the seed and (in every
//! chromosome) the generator graph's fingerprint; a resume with anything
//! else is refused with [`OptimizeError::Checkpoint`].

use std::time::Duration;

use serde::{Deserialize, Serialize};

use super::{Balance, Individual, OptimizeError, Stall};
use crate::genome::{Chromosome, ChromosomeData};
use crate::graph::Graph;

/// Current version of the [`Checkpoint`] format.
pub const CHECKPOINT_VERSION: u32 = 1;

/// The state of a run after a generation, enough to resume it exactly.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Checkpoint {
    /// Format version ([`CHECKPOINT_VERSION`]).
    pub version: u32,
    /// The optimizer's [`name`](super::Optimizer::name).
    pub method: String,
    /// Fingerprint of the optimizer's parameters (16 hex digits).
    pub params: String,
    /// The run's seed.
    pub seed: u64,
    /// The generation just finished.
    pub generation: u64,
    /// Fitness evaluations so far.
    pub evaluations: u64,
    /// Wall-clock time so far.
    pub elapsed: Duration,
    /// The best individual seen so far.
    pub best: SavedIndividual,
    /// The optimizer's own state.
    pub state: SavedState,
}

/// A chromosome and its fitness, as stored in a checkpoint.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct SavedIndividual {
    /// The chromosome.
    pub chromosome: ChromosomeData,
    /// The fitness as IEEE-754 bits, so that any format restores it exactly
    /// (including NaN for failed evaluations).
    pub fitness_bits: u64,
}

/// One SMC particle as stored in a checkpoint.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct SavedParticle {
    /// The chromosome and its fitness.
    pub individual: SavedIndividual,
    /// Open slots as `(gene position, slot, depth)`.
    pub open: Vec<(u32, u32, u32)>,
    /// The fitness after the previous step, as IEEE-754 bits.
    pub previous_bits: u64,
}

/// The optimizer-specific part of a [`Checkpoint`].
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum SavedState {
    /// A population, best first (GA, random search).
    Population {
        /// The individuals.
        individuals: Vec<SavedIndividual>,
        /// The GA's adaptive mutation split, if it uses one (IEEE-754 bits
        /// of [`AdaptiveSplit`](super::AdaptiveSplit)'s qualities).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        split_bits: Option<[u64; 3]>,
        /// The GA's stall and its challenger, if it starts challengers
        /// ([`GaParams::challenge`](super::GaParams::challenge)).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        challenge: Option<Box<SavedChallenge>>,
    },
    /// SMC/SOSMC particles before resampling.
    Particles {
        /// The particles.
        particles: Vec<SavedParticle>,
    },
    /// RJMCMC chains and their inverse temperatures (IEEE-754 bits).
    Chains {
        /// The chains' states, in ladder order.
        chains: Vec<SavedIndividual>,
        /// `β` of each chain, as IEEE-754 bits.
        betas_bits: Vec<u64>,
    },
    /// The island GA's populations, each best first.
    Islands {
        /// One population per island, in island order.
        islands: Vec<Vec<SavedIndividual>>,
        /// Each island's adaptive mutation split, if the GA uses one (see
        /// [`SavedState::Population`]); empty otherwise.
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        split_bits: Vec<[u64; 3]>,
        /// Each island's stall and challenger, in island order, if the
        /// islands start challengers
        /// ([`GaParams::challenge`](super::GaParams::challenge)); empty
        /// otherwise.
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        challenges: Vec<SavedChallenge>,
    },
    /// The hybrid: the current phase's state (a GA population or RJMCMC
    /// chains) and, in the GA phase, its best and how long it has stalled.
    Hybrid {
        /// The GA phase's best fitness, as IEEE-754 bits.
        best_bits: u64,
        /// Generations since the GA's best last improved.
        stalled: u64,
        /// The phase's own state.
        state: Box<SavedState>,
    },
    /// The tandem: the GA's population and the chains.
    Tandem {
        /// The GA's population ([`SavedState::Population`]).
        ga: Box<SavedState>,
        /// The chains ([`SavedState::Chains`]).
        chains: Box<SavedState>,
        /// How the two sides share the evaluations, if the tandem balances
        /// them ([`TandemParams::balance`](super::TandemParams::balance)).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        balance: Option<Balance>,
        /// The GA's stall and its challenger, if the tandem starts
        /// challengers ([`TandemParams::challenge`](super::TandemParams::challenge)).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        challenge: Option<SavedChallenge>,
    },
}

/// A tandem's stalled-GA bookkeeping as stored in a checkpoint (see
/// [`TandemParams::challenge`](super::TandemParams::challenge)).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct SavedChallenge {
    /// The random streams (island) the GA's population draws from (none:
    /// a lone GA's own).
    pub island: Option<u64>,
    /// How the GA's population progresses.
    pub stall: Stall,
    /// Challengers started so far (the last one drew from island `spawned`).
    pub spawned: u64,
    /// Whether a challenger's first population is to be drawn at the GA's next step.
    pub pending: bool,
    /// Whether the challenger takes the GA's next step.
    pub turn: bool,
    /// The challenger, if one lives.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub challenger: Option<SavedChallenger>,
}

/// A tandem's challenger population as stored in a checkpoint.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct SavedChallenger {
    /// Its population ([`SavedState::Population`]).
    pub population: Box<SavedState>,
    /// How it progresses.
    pub stall: Stall,
    /// The random streams (island) it draws from.
    pub island: u64,
}

impl SavedIndividual {
    /// Saves `chromosome` with `fitness`.
    #[must_use]
    pub fn new(graph: &Graph, chromosome: &Chromosome, fitness: f64) -> Self {
        Self {
            chromosome: chromosome.to_data(graph),
            fitness_bits: fitness.to_bits(),
        }
    }

    pub(crate) fn save(graph: &Graph, i: &Individual) -> Self {
        Self::new(graph, &i.chromosome, i.fitness)
    }

    /// Restores the individual, checking the chromosome against `graph`.
    pub fn restore(&self, graph: &Graph) -> Result<Individual, OptimizeError> {
        self.restore_with(graph, false)
    }

    /// [`restore`](Self::restore) of a chromosome still being built (an SMC
    /// particle), which may be shorter than the graph's `L_min`.
    pub fn restore_partial(&self, graph: &Graph) -> Result<Individual, OptimizeError> {
        self.restore_with(graph, true)
    }

    fn restore_with(&self, graph: &Graph, partial: bool) -> Result<Individual, OptimizeError> {
        let chromosome = if partial {
            Chromosome::from_partial_data(graph, &self.chromosome)
        } else {
            Chromosome::from_data(graph, &self.chromosome)
        }
        .map_err(|e| OptimizeError::Checkpoint(format!("a stored chromosome: {e}")))?;
        Ok(Individual {
            chromosome,
            fitness: f64::from_bits(self.fitness_bits),
        })
    }
}

/// What identifies a run for its checkpoints.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RunId<'g> {
    pub graph: &'g Graph,
    pub method: &'static str,
    pub params: u64,
    pub seed: u64,
}

impl<'g> RunId<'g> {
    /// The identity of a run of `method` with `params` and `seed` on `graph`.
    pub fn new(
        graph: &'g Graph,
        method: &'static str,
        params: &impl std::fmt::Debug,
        seed: u64,
    ) -> Self {
        Self {
            graph,
            method,
            params: params_fingerprint(params),
            seed,
        }
    }

    /// Refuses a checkpoint of another method, parameters, seed or format.
    pub fn check(&self, cp: &Checkpoint) -> Result<(), OptimizeError> {
        let bad = |what: String| Err(OptimizeError::Checkpoint(what));
        if cp.version != CHECKPOINT_VERSION {
            return bad(format!(
                "format version {} (this build reads {CHECKPOINT_VERSION})",
                cp.version
            ));
        }
        if cp.method != self.method {
            return bad(format!(
                "it was written by `{}`, not `{}`",
                cp.method, self.method
            ));
        }
        if cp.params != format!("{:016x}", self.params) {
            return bad("it was written with other optimizer parameters".into());
        }
        if cp.seed != self.seed {
            return bad(format!(
                "it was written with seed {}, not {}",
                cp.seed, self.seed
            ));
        }
        Ok(())
    }
}

/// A stable fingerprint of optimizer parameters (FNV-1a over their `Debug`
/// form, which prints every `f64` exactly).
pub(crate) fn params_fingerprint(params: &impl std::fmt::Debug) -> u64 {
    fnv1a(FNV1A_START, format!("{params:?}").as_bytes())
}

/// The FNV-1a offset basis: where [`fnv1a`] starts.
pub const FNV1A_START: u64 = 0xcbf2_9ce4_8422_2325;

/// 64-bit FNV-1a of `bytes`, continuing from `hash` (start with
/// [`FNV1A_START`]): the stable hash of checkpoint fingerprints, the same
/// on every platform and release.
#[must_use]
pub fn fnv1a(hash: u64, bytes: &[u8]) -> u64 {
    bytes.iter().fold(hash, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fingerprints_tell_parameters_apart() {
        assert_eq!(params_fingerprint(&(1, 0.5)), params_fingerprint(&(1, 0.5)));
        assert_ne!(
            params_fingerprint(&(1, 0.5)),
            params_fingerprint(&(1, 0.5000000001))
        );
    }
}
