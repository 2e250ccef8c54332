//! A challenger for a stalled GA: when the GA's best stops rising, a second
//! population starts from random models and steps in turn with it. It takes
//! the GA's place if it overtakes it, and is dropped if it stalls below it.
//!
//! A GA whose population has become one model can stay there for good (on
//! the tree sketch, a tree lacking one of the sketch's crowns: any crown
//! grown there at random loses its tournaments before it is tuned). A plain
//! restart escapes that but also throws away a good run's slow tuning at its
//! plateau; a challenger costs such a run half its GA steps while it lives,
//! and nothing once it is dropped. The rule reads fitness values only, so a
//! run stays deterministic for any thread count.

use serde::{Deserialize, Serialize};

use super::checkpoint::{SavedChallenge, SavedChallenger};
use super::evaluation::Candidate;
use super::ga::GaState;
use super::selection::rank_order;
use super::{Ga, Individual, OptimizeError};
use crate::graph::Graph;

/// The patience of challengers where experiment files name none: the
/// GA's, the island GA's and the hybrid's `challenge`, and the tandem's
/// ([`TANDEM_CHALLENGE`](super::TANDEM_CHALLENGE)).
pub const DEFAULT_CHALLENGE: u64 = 100;

/// The share of a population's gain since its first generation that its
/// best must rise by within the patience to count as progress.
pub const PROGRESS_SHARE: f64 = 0.01;

/// Whether a population is still making progress: its best at its first
/// generation, at its last progress, and the steps since (kept in
/// checkpoints; fitness values as IEEE-754 bits, so that −∞ and NaN
/// survive any format).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Stall {
    start_bits: u64,
    mark_bits: u64,
    since: u64,
}

impl Stall {
    /// A population whose first generation's best is `best`.
    pub(crate) fn new(best: f64) -> Self {
        Self {
            start_bits: best.to_bits(),
            mark_bits: best.to_bits(),
            since: 0,
        }
    }

    /// Records a step after which the population's best is `best`; returns
    /// whether it has now gone `patience` steps without progress: a rise of
    /// its best since the last progress by at least [`PROGRESS_SHARE`] of
    /// its gain since its first generation (and by more than nothing). A
    /// population with no finite best yet takes its first finite one as its
    /// start.
    pub(crate) fn step(&mut self, best: f64, patience: u64) -> bool {
        let (start, mark) = (
            f64::from_bits(self.start_bits),
            f64::from_bits(self.mark_bits),
        );
        if !start.is_finite() {
            if best.is_finite() {
                *self = Self::new(best);
            } else {
                self.since += 1;
            }
        } else {
            let gain = best - mark;
            if gain > 0.0 && gain >= PROGRESS_SHARE * (best - start) {
                self.mark_bits = best.to_bits();
                self.since = 0;
            } else {
                self.since += 1;
            }
        }
        self.since >= patience
    }

    /// Gives the population its whole patience again, from its best `best`.
    pub(crate) fn restart_patience(&mut self, best: f64) {
        if f64::from_bits(self.start_bits).is_finite() && best.is_finite() {
            self.mark_bits = best.to_bits();
        }
        self.since = 0;
    }

    /// Steps since the last progress.
    #[must_use]
    pub fn since(&self) -> u64 {
        self.since
    }
}

/// Where a population's challengers draw their random streams: the `k`-th
/// challenger (`k` ≥ 1) of a population draws from island
/// `k · stride + home`, so that challengers of different populations (the
/// islands of an island GA) never share a stream with each other or with an
/// island.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Lineage {
    /// The population's own island (0 for a lone GA).
    pub home: u64,
    /// The number of populations that start challengers (1 for a lone GA).
    pub stride: u64,
}

impl Lineage {
    /// A lone GA's (the GA, the hybrid's GA, the tandem's GA).
    pub const ALONE: Self = Self { home: 0, stride: 1 };

    /// The streams of challenger `k`.
    fn island(self, k: u64) -> u64 {
        k.saturating_mul(self.stride).saturating_add(self.home)
    }
}

/// A GA population, its stall bookkeeping and its challenger (see the
/// module's documentation): what the GA, each island of the island GA, the
/// hybrid's GA phase and the tandem's GA step. With a patience of 0 it is
/// the GA alone, draw for draw.
pub(crate) struct Challenged {
    /// The population that holds the GA's place.
    pub incumbent: GaState,
    /// The streams the incumbent breeds from.
    island: Option<u64>,
    lineage: Lineage,
    /// How the incumbent progresses.
    stall: Stall,
    /// Challengers started so far.
    spawned: u64,
    /// Whether the next step draws challenger `spawned`'s first population.
    pending: bool,
    /// Whether the challenger takes the next step.
    turn: bool,
    challenger: Option<Challenger>,
}

/// A second population started when the incumbent stalled.
struct Challenger {
    ga: GaState,
    stall: Stall,
    island: u64,
}

/// Which population takes a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Side {
    /// The incumbent breeds.
    Incumbent,
    /// The challenger breeds.
    Challenger,
    /// A challenger's first population is drawn.
    Fresh,
}

/// The best fitness of `models` (−∞ for none; `f64::max` passes over NaN).
pub(crate) fn best_of(models: &[Individual]) -> f64 {
    models
        .iter()
        .map(|m| m.fitness)
        .fold(f64::NEG_INFINITY, f64::max)
}

impl Challenged {
    /// `incumbent`, breeding from the streams of `island`, with no
    /// challenger yet.
    pub fn new(incumbent: GaState, island: Option<u64>, lineage: Lineage) -> Self {
        Self {
            stall: Stall::new(best_of(&incumbent.population)),
            incumbent,
            island,
            lineage,
            spawned: 0,
            pending: false,
            turn: false,
            challenger: None,
        }
    }

    /// Which population takes the next step: a challenger's first
    /// population if one is due, else the challenger and the incumbent in
    /// turn.
    pub fn side(&self) -> Side {
        if self.pending {
            Side::Fresh
        } else if self.turn && self.challenger.is_some() {
            Side::Challenger
        } else {
            Side::Incumbent
        }
    }

    /// The candidates of `side`'s step at `generation`: the incumbent's or
    /// the challenger's children, or a new challenger's random first
    /// population.
    pub fn candidates(
        &mut self,
        ga: &Ga,
        graph: &Graph,
        seed: u64,
        generation: u64,
        side: Side,
    ) -> Result<Vec<Candidate>, OptimizeError> {
        Ok(match (side, &mut self.challenger) {
            (Side::Challenger, Some(c)) => {
                ga.next_generation(graph, &mut c.ga, seed, generation, Some(c.island))
            }
            (Side::Fresh, _) => {
                ga.initial_population(graph, seed, Some(self.lineage.island(self.spawned)))?
            }
            _ => ga.next_generation(graph, &mut self.incumbent, seed, generation, self.island),
        })
    }

    /// Makes `evaluated` the population of `side`, then applies the
    /// challenge with `patience` (0: never): a stalled incumbent gets a
    /// challenger (drawn at its next step), a challenger that overtakes the
    /// incumbent takes its place, one that stalls below it is dropped.
    pub fn settle(&mut self, side: Side, evaluated: Vec<Individual>, patience: u64) {
        match side {
            Side::Incumbent => {
                self.incumbent.settle(evaluated);
                if patience == 0 {
                    return;
                }
                let stalled = self
                    .stall
                    .step(best_of(&self.incumbent.population), patience);
                if self.challenger.is_some() {
                    self.turn = true;
                } else if stalled {
                    self.spawned += 1;
                    self.pending = true;
                }
                return;
            }
            Side::Fresh => {
                let population = GaState::new(evaluated);
                self.challenger = Some(Challenger {
                    stall: Stall::new(best_of(&population.population)),
                    ga: population,
                    island: self.lineage.island(self.spawned),
                });
                self.pending = false;
            }
            Side::Challenger => {
                if let Some(c) = &mut self.challenger {
                    c.ga.settle(evaluated);
                }
            }
        }
        self.turn = false;
        let Some(c) = &mut self.challenger else {
            return;
        };
        let (best, incumbent) = (
            best_of(&c.ga.population),
            best_of(&self.incumbent.population),
        );
        let stalled = side == Side::Challenger && c.stall.step(best, patience);
        if best > incumbent {
            let c = self.challenger.take().expect("a challenger lives here");
            self.incumbent = c.ga;
            self.stall = c.stall;
            self.island = Some(c.island);
        } else if stalled {
            self.challenger = None;
            self.stall.restart_patience(incumbent);
        }
    }

    /// The best fitness of the incumbent and the challenger.
    pub fn best(&self) -> f64 {
        let challenger = self
            .challenger
            .as_ref()
            .map_or(f64::NEG_INFINITY, |c| best_of(&c.ga.population));
        best_of(&self.incumbent.population).max(challenger)
    }

    /// The challenger's models (none without one).
    pub fn challenger_models(&self) -> &[Individual] {
        self.challenger
            .as_ref()
            .map_or(&[], |c| c.ga.population.as_slice())
    }

    /// The incumbent's and the challenger's models, best first (stable:
    /// the incumbent's first on ties).
    pub fn models_best_first(&self) -> Vec<Individual> {
        let mut all = self.incumbent.population.clone();
        all.extend(self.challenger_models().iter().cloned());
        all.sort_by(|a, b| rank_order(a.fitness, b.fitness));
        all
    }

    /// The same, taken out (the populations are left empty).
    pub fn take_models(&mut self) -> Vec<Individual> {
        let mut all = std::mem::take(&mut self.incumbent.population);
        if let Some(c) = self.challenger.take() {
            all.extend(c.ga.population);
            all.sort_by(|a, b| rank_order(a.fitness, b.fitness));
        }
        all
    }

    /// The same, consuming the populations.
    pub fn into_models(mut self) -> Vec<Individual> {
        self.take_models()
    }

    /// The bookkeeping a checkpoint saves (the incumbent is saved apart).
    pub fn save(&self, ga: &Ga, graph: &Graph) -> SavedChallenge {
        SavedChallenge {
            island: self.island,
            stall: self.stall,
            spawned: self.spawned,
            pending: self.pending,
            turn: self.turn,
            challenger: self.challenger.as_ref().map(|c| SavedChallenger {
                population: Box::new(ga.save_state(graph, &c.ga)),
                stall: c.stall,
                island: c.island,
            }),
        }
    }

    /// `incumbent` with the bookkeeping of `saved` (none: a population
    /// with no challenger yet, breeding from `island`).
    pub fn restore(
        ga: &Ga,
        graph: &Graph,
        incumbent: GaState,
        island: Option<u64>,
        lineage: Lineage,
        saved: Option<&SavedChallenge>,
    ) -> Result<Self, OptimizeError> {
        let Some(saved) = saved else {
            return Ok(Self::new(incumbent, island, lineage));
        };
        let challenger = match &saved.challenger {
            Some(c) => Some(Challenger {
                ga: ga.restore_state(graph, &c.population)?,
                stall: c.stall,
                island: c.island,
            }),
            None => None,
        };
        Ok(Self {
            incumbent,
            island: saved.island,
            lineage,
            stall: saved.stall,
            spawned: saved.spawned,
            pending: saved.pending,
            turn: saved.turn,
            challenger,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rising_best_is_progress_and_a_flat_one_stalls_after_the_patience() {
        let mut s = Stall::new(0.0);
        // Gains of 0.1 on a gain so far of at most 1: progress every step.
        for k in 1..=10 {
            assert!(!s.step(0.1 * f64::from(k), 3));
            assert_eq!(s.since(), 0);
        }
        // Flat: stalled on the third step, not before.
        assert!(!s.step(1.0, 3));
        assert!(!s.step(1.0, 3));
        assert!(s.step(1.0, 3));
    }

    #[test]
    fn gains_below_the_share_of_the_gain_so_far_do_not_count_until_they_add_up() {
        let mut s = Stall::new(0.0);
        assert!(!s.step(1.0, 100));
        // 1 % of a gain of about 1 is about 0.01: steps of 0.004 count on
        // the third (0.012 above the mark), not before.
        assert!(!s.step(1.004, 100));
        assert_eq!(s.since(), 1);
        assert!(!s.step(1.008, 100));
        assert_eq!(s.since(), 2);
        assert!(!s.step(1.012, 100));
        assert_eq!(s.since(), 0);
    }

    #[test]
    fn a_start_without_a_finite_best_takes_the_first_finite_one() {
        let mut s = Stall::new(f64::NEG_INFINITY);
        assert!(!s.step(f64::NAN, 2));
        assert!(s.step(f64::NEG_INFINITY, 2));
        assert!(!s.step(0.5, 2));
        assert_eq!(s.since(), 0);
        assert!(!s.step(0.5, 2));
        assert!(s.step(0.5, 2));
        s.restart_patience(0.5);
        assert_eq!(s.since(), 0);
    }

    #[test]
    fn it_survives_a_checkpoint_with_infinite_and_nan_bests() {
        for best in [f64::NEG_INFINITY, f64::NAN, 0.25] {
            let mut s = Stall::new(best);
            s.step(best, 5);
            let json = serde_json::to_string(&s).unwrap();
            let back: Stall = serde_json::from_str(&json).unwrap();
            assert_eq!(back, s);
        }
    }
}
