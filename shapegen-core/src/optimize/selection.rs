//! Ranking and parent selection: stable sorting, roulette wheel, k-tournament.

use std::cmp::Ordering;
use std::collections::HashSet;

use rand::{Rng, RngExt};
use serde::{Deserialize, Serialize};

use super::Individual;
use super::fitness::is_valid_score;
use crate::graph::Graph;

/// Orders fitness values best first; failed (non-finite) scores last.
#[must_use]
pub fn rank_order(a: f64, b: f64) -> Ordering {
    match (is_valid_score(a), is_valid_score(b)) {
        (true, true) => b.partial_cmp(&a).unwrap_or(Ordering::Equal),
        (true, false) => Ordering::Less,
        (false, true) => Ordering::Greater,
        (false, false) => Ordering::Equal,
    }
}

/// The `n` best valid individuals of `sorted` (best first), each structure
/// (by [`Chromosome::structural_hash`](crate::genome::Chromosome::structural_hash)) once.
pub(crate) fn best_distinct<'a>(
    graph: &Graph,
    sorted: impl Iterator<Item = &'a Individual>,
    n: usize,
) -> Vec<&'a Individual> {
    let mut seen = HashSet::new();
    sorted
        .filter(|i| is_valid_score(i.fitness))
        .filter(|i| seen.insert(i.chromosome.structural_hash(graph)))
        .take(n)
        .collect()
}

/// `n` individuals: the best distinct valid ones of `sorted` (see
/// [`best_distinct`]), repeated in turn when there are fewer; empty if none
/// is valid. A new population or set of chains started from another's best.
pub(crate) fn best_distinct_repeated<'a>(
    graph: &Graph,
    sorted: impl Iterator<Item = &'a Individual>,
    n: usize,
) -> Vec<Individual> {
    let best = best_distinct(graph, sorted, n);
    if best.is_empty() {
        return Vec::new();
    }
    (0..n).map(|k| best[k % best.len()].clone()).collect()
}

/// How roulette weights are made from fitness values that may be negative.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RouletteShift {
    /// `w = f − f_min` only when `f_min < 0` (the worst then gets weight 0), else `w = f`.
    #[default]
    IfNegative,
    /// Always `w = f − f_min` (the reference code).
    Always,
}

/// A roulette wheel over a population: `P(i) = w_i / Σ w`.
///
/// Failed scores get weight 0. If every weight is 0, or the sum is not
/// finite, every individual is equally likely.
#[derive(Clone, Debug, Default)]
pub struct Roulette {
    cumulative: Vec<f64>,
}

impl Roulette {
    /// Builds the wheel for `fitness` (reusing this wheel's memory).
    pub fn rebuild(&mut self, fitness: &[f64], shift: RouletteShift) {
        let min = fitness
            .iter()
            .copied()
            .filter(|f| is_valid_score(*f))
            .fold(f64::INFINITY, f64::min);
        let offset = match shift {
            _ if !min.is_finite() => 0.0,
            RouletteShift::IfNegative if min >= 0.0 => 0.0,
            _ => min,
        };
        self.cumulative.clear();
        let mut acc = 0.0;
        for &f in fitness {
            acc += if is_valid_score(f) {
                (f - offset).max(0.0)
            } else {
                0.0
            };
            self.cumulative.push(acc);
        }
    }

    /// Draws an index.
    pub fn pick<R: Rng + ?Sized>(&self, rng: &mut R) -> usize {
        let n = self.cumulative.len();
        let total = self.cumulative.last().copied().unwrap_or(0.0);
        if !(total > 0.0 && total.is_finite()) {
            return rng.random_range(0..n);
        }
        let u = rng.random::<f64>() * total;
        // First index whose cumulative weight exceeds u (never a zero-weight one).
        self.cumulative.partition_point(|&c| c <= u).min(n - 1)
    }
}

/// k-tournament on a population sorted best first: `k` uniform draws with
/// replacement, the best-ranked wins. `P(rank r from the bottom) = (r^k − (r−1)^k) / N^k`.
pub fn tournament<R: Rng + ?Sized>(n: usize, k: usize, rng: &mut R) -> usize {
    (0..k.max(1))
        .map(|_| rng.random_range(0..n))
        .min()
        .unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::stream;

    #[test]
    fn rank_order_puts_failures_last_and_is_stable() {
        let mut v = [
            (1.0, 0),
            (f64::NAN, 1),
            (3.0, 2),
            (f64::INFINITY, 3),
            (1.0, 4),
            (-2.0, 5),
        ];
        v.sort_by(|a, b| rank_order(a.0, b.0));
        let order: Vec<usize> = v.iter().map(|x| x.1).collect();
        assert_eq!(order, [2, 0, 4, 5, 1, 3]);
    }

    #[test]
    fn roulette_handles_negative_equal_and_nan() {
        let mut rng = stream(1, &[]);
        let mut wheel = Roulette::default();
        // Negative: shifted so the worst gets 0.
        wheel.rebuild(&[-1.0, -3.0, 1.0, f64::NAN], RouletteShift::IfNegative);
        let mut counts = [0u32; 4];
        for _ in 0..40_000 {
            counts[wheel.pick(&mut rng)] += 1;
        }
        assert_eq!(counts[1], 0, "the worst has weight 0");
        assert_eq!(counts[3], 0, "NaN has weight 0");
        let ratio = counts[2] as f64 / counts[0] as f64; // weights 4 : 2
        assert!((ratio - 2.0).abs() < 0.1, "{ratio}");
        // All equal to zero: uniform.
        wheel.rebuild(&[0.0; 4], RouletteShift::IfNegative);
        let mut counts = [0u32; 4];
        for _ in 0..40_000 {
            counts[wheel.pick(&mut rng)] += 1;
        }
        assert!(
            counts.iter().all(|&c| (9_000..11_000).contains(&c)),
            "{counts:?}"
        );
        // All NaN: uniform, no panic.
        wheel.rebuild(&[f64::NAN; 3], RouletteShift::Always);
        assert!(wheel.pick(&mut rng) < 3);
        // Positive, no shift by default; shift always with the reference option.
        wheel.rebuild(&[1.0, 3.0], RouletteShift::IfNegative);
        let p1 = (0..40_000).filter(|_| wheel.pick(&mut rng) == 1).count() as f64 / 40_000.0;
        assert!((p1 - 0.75).abs() < 0.01, "{p1}");
        wheel.rebuild(&[1.0, 3.0], RouletteShift::Always);
        assert!((0..1000).all(|_| wheel.pick(&mut rng) == 1));
    }

    #[test]
    fn tournament_matches_closed_form() {
        // N = 150, k = 10: the best wins with probability 1 − (149/150)^10 ≈ 6.5 %.
        let mut rng = stream(2, &[]);
        let trials = 200_000;
        let wins = (0..trials)
            .filter(|_| tournament(150, 10, &mut rng) == 0)
            .count() as f64
            / trials as f64;
        let expected = 1.0 - (149.0f64 / 150.0).powi(10);
        assert!((expected - 0.0648).abs() < 1e-3);
        assert!((wins - expected).abs() < 0.003, "{wins} vs {expected}");
    }
}
