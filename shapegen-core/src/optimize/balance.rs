//! How the tandem shares its evaluations between its two sides.
//!
//! Each side (the GA, the chains) steps every generation by default. With
//! the balance on, every exchange interval credits the side that pushed
//! the best fitness further per evaluation: beyond the frontier, the best
//! either side held when the interval started (a side that lags behind
//! the other earns nothing by catching up). The side that gained more per
//! evaluation (or alone gained) takes one step of *lean* toward itself;
//! the other then steps only every 2, 4 or 8 generations ([`MAX_LEAN`]),
//! so it keeps a share from which it can win the lean back.
//! An interval where neither gains changes nothing. The rule reads fitness
//! values only, so a run stays deterministic for any thread count.

use serde::{Deserialize, Serialize};

/// The most a lean goes: the side leaned away from steps every
/// `2^MAX_LEAN` generations.
pub const MAX_LEAN: i8 = 3;

/// The balance between a tandem's GA and chains, and what the current
/// interval has measured (kept in the tandem's checkpoints).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Balance {
    /// Positive: the GA steps every `2^lean` generations (the chains
    /// every one); negative: the chains every `2^−lean` (the GA every one).
    lean: i8,
    /// Each side's best fitness when the interval started, as IEEE-754
    /// bits (`None` before the first exchange).
    start_bits: Option<[u64; 2]>,
    /// Evaluations each side has made since.
    evaluations: [u64; 2],
}

/// The sides, as indices into [`Balance`]'s pairs.
const GA: usize = 0;
const CHAINS: usize = 1;

impl Default for Balance {
    fn default() -> Self {
        Self::new()
    }
}

impl Balance {
    /// Even: both sides step every generation.
    pub(crate) const fn new() -> Self {
        Self {
            lean: 0,
            start_bits: None,
            evaluations: [0; 2],
        }
    }

    /// Where the run leans: `0` even; `k > 0` toward the chains (the GA
    /// steps every `2^k` generations); `k < 0` toward the GA (the chains
    /// step every `2^−k`); at most [`MAX_LEAN`] either way.
    #[must_use]
    pub fn lean(&self) -> i8 {
        self.lean
    }

    /// Whether the GA steps in `generation`.
    pub(crate) fn ga_steps(&self, generation: u64) -> bool {
        self.lean <= 0 || generation.is_multiple_of(1 << self.lean)
    }

    /// Whether the chains step in `generation`.
    pub(crate) fn chains_step(&self, generation: u64) -> bool {
        self.lean >= 0 || generation.is_multiple_of(1 << -self.lean)
    }

    /// Counts the evaluations of one generation.
    pub(crate) fn spent(&mut self, ga: usize, chains: usize) {
        self.evaluations[GA] += ga as u64;
        self.evaluations[CHAINS] += chains as u64;
    }

    /// Ends an interval at the exchange: `best` is each side's best fitness
    /// before it, and the lean moves toward the side that gained more
    /// beyond the frontier per evaluation since the last one.
    pub(crate) fn judge(&mut self, best: [f64; 2]) {
        if let Some(start) = self.start_bits {
            // The frontier: the best either side held at the start.
            let frontier = f64::from_bits(start[GA]).max(f64::from_bits(start[CHAINS]));
            let rate = |side: usize| {
                let gain = best[side] - frontier;
                // (Not for NaN or an infinite start either.)
                if gain > 0.0 && gain.is_finite() && self.evaluations[side] > 0 {
                    gain / self.evaluations[side] as f64
                } else {
                    0.0
                }
            };
            let (ga, chains) = (rate(GA), rate(CHAINS));
            if ga > chains {
                self.lean = (self.lean - 1).max(-MAX_LEAN);
            } else if chains > ga {
                self.lean = (self.lean + 1).min(MAX_LEAN);
            }
        }
        self.evaluations = [0; 2];
    }

    /// Starts an interval after the exchange, from each side's best.
    pub(crate) fn start(&mut self, best: [f64; 2]) {
        self.start_bits = Some(best.map(f64::to_bits));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An interval where one side gains from `[ga, chains]` to the bests given.
    fn interval(b: &mut Balance, start: [f64; 2], end: [f64; 2], spent: (usize, usize)) {
        b.start(start);
        b.spent(spent.0, spent.1);
        b.judge(end);
    }

    #[test]
    fn the_lean_follows_the_side_that_gains() {
        let mut b = Balance::new();
        assert!(b.ga_steps(1) && b.chains_step(1));
        // The first judgement has no start to compare with.
        b.spent(120, 70);
        b.judge([0.5, 0.4]);
        assert_eq!(b.lean(), 0);
        // The chains alone gain: toward them, at most MAX_LEAN.
        for k in 1..=5 {
            interval(&mut b, [0.5, 0.5], [0.5, 0.6], (120, 70));
            assert_eq!(b.lean(), k.min(MAX_LEAN));
        }
        // The GA steps every 8 generations, the chains every one.
        assert_eq!(
            (1..=16).filter(|&g| b.ga_steps(g)).collect::<Vec<_>>(),
            vec![8, 16]
        );
        assert!((1..=16).all(|g| b.chains_step(g)));
        // Neither gains (or loses): no change.
        interval(&mut b, [0.6, 0.6], [0.6, 0.55], (15, 70));
        assert_eq!(b.lean(), MAX_LEAN);
        // Both gain: per evaluation, the GA's 0.01 in 15 beats 0.02 in 70.
        interval(&mut b, [0.6, 0.6], [0.61, 0.62], (15, 70));
        assert_eq!(b.lean(), MAX_LEAN - 1);
        // Back to the GA's side, and past the middle.
        for _ in 0..6 {
            interval(&mut b, [0.7, 0.7], [0.8, 0.7], (120, 70));
        }
        assert_eq!(b.lean(), -MAX_LEAN);
        assert!((1..=16).all(|g| b.ga_steps(g)));
        assert_eq!(
            (1..=16).filter(|&g| b.chains_step(g)).collect::<Vec<_>>(),
            vec![8, 16]
        );
    }

    /// A side that only catches up with the other earns nothing.
    #[test]
    fn catching_up_is_no_gain() {
        let mut b = Balance::new();
        interval(&mut b, [0.9, 0.2], [0.9, 0.8], (120, 70));
        assert_eq!(b.lean(), 0);
        interval(&mut b, [0.9, 0.2], [0.9, 0.95], (120, 70));
        assert_eq!(b.lean(), 1);
        interval(&mut b, [0.5, 0.95], [0.97, 0.95], (120, 70));
        assert_eq!(b.lean(), 0);
    }

    #[test]
    fn no_evaluations_or_odd_values_give_no_credit() {
        let mut b = Balance::new();
        // A side that made no evaluation gains nothing it could be credited for.
        interval(&mut b, [0.5, 0.5], [0.9, 0.5], (0, 70));
        assert_eq!(b.lean(), 0);
        // No frontier (NaN or −∞ on both sides), or a NaN end: no credit.
        interval(&mut b, [f64::NAN; 2], [0.9, 0.5], (10, 10));
        interval(&mut b, [f64::NEG_INFINITY; 2], [0.9, 0.5], (10, 10));
        interval(&mut b, [0.5, 0.5], [f64::NAN, 0.5], (10, 10));
        assert_eq!(b.lean(), 0);
        // One side without models: the other's best is the frontier.
        interval(&mut b, [f64::NEG_INFINITY, 0.5], [0.9, 0.5], (10, 10));
        assert_eq!(b.lean(), -1);
    }
}
