//! The GA's adaptive mutation split: how often a mutation is a grow, a cut
//! or an alter, learnt from how often each one's children beat their parent
//! (probability matching, Thierens 2005). The paper tuned the split per
//! scene; a user's own generator has no tuned split.

use super::Individual;
use super::fitness::is_valid_score;
use crate::ops::{Mutation, MutationSplit};

/// Each mutation keeps at least this share of the mutations, so that one
/// that has stopped paying off is still tried and can come back.
pub const MIN_SHARE: f64 = 0.05;

/// Weight of a generation's success rate in a mutation's running quality
/// (exponential smoothing): about the last 10 generations count.
pub const SMOOTHING: f64 = 0.1;

/// What made a candidate of a generation, for the adaptive split: the
/// mutation and its parent's fitness. Elites, crossovers and local-search
/// moves have none.
pub(crate) type Origin = Option<(Mutation, f64)>;

fn index(m: Mutation) -> usize {
    match m {
        Mutation::Grow => 0,
        Mutation::Cut => 1,
        Mutation::Alter => 2,
    }
}

/// The running qualities (smoothed success rates) of grow, cut and alter.
/// Each generation, a mutation's quality moves by [`SMOOTHING`] toward the
/// share of its children (of that generation) that were strictly better
/// than their parent; its share of the mutations is [`MIN_SHARE`] plus the
/// rest in proportion to the qualities. Crossover's rate
/// (`1 − mutation_rate`) does not adapt: its children rarely beat the better
/// parent, yet they carry the structure (`reproduction.md`, *Adaptive
/// mutation split*, measures what adapting it too cost).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AdaptiveSplit {
    quality: [f64; 3],
}

impl AdaptiveSplit {
    /// A split starting from `split`'s shares.
    #[must_use]
    pub fn new(split: &MutationSplit) -> Self {
        let sum = split.grow + split.cut + split.alter;
        Self {
            quality: [split.grow / sum, split.cut / sum, split.alter / sum],
        }
    }

    /// The current split among grow, cut and alter (shares summing to 1).
    #[must_use]
    pub fn split(&self) -> MutationSplit {
        let sum: f64 = self.quality.iter().sum();
        let [grow, cut, alter] = self.quality.map(|q| {
            if sum > 0.0 {
                MIN_SHARE + (1.0 - 3.0 * MIN_SHARE) * q / sum
            } else {
                1.0 / 3.0
            }
        });
        MutationSplit::new(grow, cut, alter)
    }

    /// Learns from one generation: `origins[i]` made `evaluated[i]`.
    pub(crate) fn learn(&mut self, origins: &[Origin], evaluated: &[Individual]) {
        let mut tried = [0u32; 3];
        let mut won = [0u32; 3];
        for (origin, child) in origins.iter().zip(evaluated) {
            let Some((mutation, parent)) = origin else {
                continue;
            };
            let k = index(*mutation);
            tried[k] += 1;
            let better = is_valid_score(child.fitness)
                && (!is_valid_score(*parent) || child.fitness > *parent);
            won[k] += u32::from(better);
        }
        for k in 0..3 {
            if tried[k] > 0 {
                let rate = f64::from(won[k]) / f64::from(tried[k]);
                self.quality[k] += SMOOTHING * (rate - self.quality[k]);
            }
        }
    }

    /// The qualities as IEEE-754 bits, for checkpoints.
    #[must_use]
    pub(crate) fn to_bits(self) -> [u64; 3] {
        self.quality.map(f64::to_bits)
    }

    /// The split saved by [`to_bits`](Self::to_bits).
    #[must_use]
    pub(crate) fn from_bits(bits: [u64; 3]) -> Self {
        Self {
            quality: bits.map(f64::from_bits),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optimize::test_support::with_fitness;

    fn shares(s: &MutationSplit) -> [f64; 3] {
        [s.grow, s.cut, s.alter]
    }

    #[test]
    fn shares_sum_to_one_keep_the_floor_and_start_near_the_given_split() {
        let split = AdaptiveSplit::new(&MutationSplit::new(10.5, 10.5, 9.0)).split();
        let s = shares(&split);
        assert!((s.iter().sum::<f64>() - 1.0).abs() < 1e-12, "{s:?}");
        assert!(s.iter().all(|&x| x >= MIN_SHARE), "{s:?}");
        assert_eq!(s[0], s[1]);
        assert!(s[2] < s[0] && (s[2] - 0.3).abs() < 0.02, "{s:?}");
        assert!(split.problem().is_none());
    }

    #[test]
    fn a_mutation_whose_children_win_gains_share_and_one_that_never_wins_falls_to_the_floor() {
        let child = with_fitness();
        let mut split = AdaptiveSplit::new(&MutationSplit::new(13.5, 13.5, 3.0));
        let alter_before = split.split().alter;
        // Alter's children beat their parents; grow's and cut's do not
        // (equal is not better; NaN never is); candidates without an
        // origin are not counted.
        let origins = [
            Some((Mutation::Alter, 1.0)),
            Some((Mutation::Grow, 1.0)),
            Some((Mutation::Cut, 1.0)),
            Some((Mutation::Cut, 1.0)),
            None,
        ];
        let evaluated = [
            child(2.0),
            child(1.0),
            child(f64::NAN),
            child(0.5),
            child(9.0),
        ];
        for _ in 0..200 {
            split.learn(&origins, &evaluated);
        }
        let after = split.split();
        assert!(
            after.alter > alter_before && after.alter > 0.85,
            "{after:?}"
        );
        assert!((after.grow - MIN_SHARE).abs() < 1e-6, "{after:?}");
        assert!((after.cut - MIN_SHARE).abs() < 1e-6, "{after:?}");
        assert_eq!(AdaptiveSplit::from_bits(split.to_bits()), split);
    }

    #[test]
    fn when_nothing_wins_every_mutation_keeps_a_chance() {
        let mut split = AdaptiveSplit { quality: [0.0; 3] };
        assert_eq!(shares(&split.split()), [1.0 / 3.0; 3]);
        split.learn(&[], &[]);
        assert_eq!(shares(&split.split()), [1.0 / 3.0; 3]);
    }
}
