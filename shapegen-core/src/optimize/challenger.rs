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
