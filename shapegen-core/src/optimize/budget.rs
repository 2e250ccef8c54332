//! When an optimization stops.

use std::time::Duration;

use serde::{Deserialize, Serialize};

/// Limits on a run; it stops at whichever comes first. At least one must be set.
///
/// Limits are checked after each generation, so a run may overshoot an
/// evaluation or time budget by up to one generation. Runs bounded by
/// generations, evaluations or target fitness are reproducible from the seed;
/// a wall-time bound is not (the generation reached is reported).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Budget {
    /// Number of generations after the initial one.
    pub generations: Option<u64>,
    /// Number of fitness evaluations.
    pub evaluations: Option<u64>,
    /// Wall-clock time.
    pub wall_time: Option<Duration>,
    /// Stop as soon as the best fitness reaches this value.
    pub target_fitness: Option<f64>,
}

impl Budget {
    /// The longest wall-clock budget, in seconds: a century (a longer one
    /// is a mistake, and would overflow `Duration` and `Instant`).
    pub const MAX_SECONDS: f64 = 100.0 * 365.25 * 86_400.0;

    /// `seconds` as a wall-clock duration, if it is in `(0, MAX_SECONDS]`
    /// (NaN is not).
    #[must_use]
    pub fn seconds(seconds: f64) -> Option<std::time::Duration> {
        (seconds > 0.0 && seconds <= Self::MAX_SECONDS)
            .then(|| std::time::Duration::from_secs_f64(seconds))
    }

    /// Stop after `n` generations.
    #[must_use]
    pub const fn generations(n: u64) -> Self {
        Self {
            generations: Some(n),
            evaluations: None,
            wall_time: None,
            target_fitness: None,
        }
    }

    /// Stop after `n` evaluations.
    #[must_use]
    pub const fn evaluations(n: u64) -> Self {
        Self {
            generations: None,
            evaluations: Some(n),
            wall_time: None,
            target_fitness: None,
        }
    }

    /// Stop after `t` of wall-clock time.
    #[must_use]
    pub const fn wall_time(t: Duration) -> Self {
        Self {
            generations: None,
            evaluations: None,
            wall_time: Some(t),
            target_fitness: None,
        }
    }

    /// Also stop after `n` generations.
    #[must_use]
    pub const fn and_generations(mut self, n: u64) -> Self {
        self.generations = Some(n);
        self
    }

    /// Also stop after `n` evaluations.
    #[must_use]
    pub const fn and_evaluations(mut self, n: u64) -> Self {
        self.evaluations = Some(n);
        self
    }

    /// Also stop after `t`.
    #[must_use]
    pub const fn and_wall_time(mut self, t: Duration) -> Self {
        self.wall_time = Some(t);
        self
    }

    /// Also stop once the best fitness reaches `f`.
    #[must_use]
    pub const fn and_target_fitness(mut self, f: f64) -> Self {
        self.target_fitness = Some(f);
        self
    }

    /// Whether no limit is set (such a budget is refused).
    #[must_use]
    pub const fn is_unbounded(&self) -> bool {
        self.generations.is_none() && self.evaluations.is_none() && self.wall_time.is_none()
    }

    /// Which limit, if any, the progress so far has reached.
    #[must_use]
    pub fn reached(
        &self,
        generation: u64,
        evaluations: u64,
        elapsed: Duration,
        best: f64,
    ) -> Option<StopReason> {
        if self.target_fitness.is_some_and(|t| best >= t) {
            Some(StopReason::TargetFitness)
        } else if self.generations.is_some_and(|g| generation >= g) {
            Some(StopReason::Generations)
        } else if self.evaluations.is_some_and(|e| evaluations >= e) {
            Some(StopReason::Evaluations)
        } else if self.wall_time.is_some_and(|t| elapsed >= t) {
            Some(StopReason::WallTime)
        } else {
            None
        }
    }
}

/// Why a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StopReason {
    /// The generation limit was reached.
    Generations,
    /// The evaluation limit was reached.
    Evaluations,
    /// The wall-time limit was reached.
    WallTime,
    /// The target fitness was reached.
    TargetFitness,
    /// The observer asked to stop.
    Observer,
    /// The optimizer had nothing left to do (e.g. every SMC particle finished).
    Exhausted,
}
