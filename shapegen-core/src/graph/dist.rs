//! Parameter distributions: sampling, log-density and support.

use std::f64::consts::PI;

use rand::{Rng, RngExt};
use rand_distr::{Distribution as _, StandardNormal};
use serde::{Deserialize, Serialize};

/// A distribution over one `f32` component of a parameter.
///
/// Every distribution can draw a value, give the log-density of a value and
/// say whether a value lies in its support.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Dist {
    /// Always the same value (support: that value).
    Constant {
        /// The value.
        value: f32,
    },
    /// Uniform on the closed interval `[lo, hi]`; `lo == hi` is a constant.
    Uniform {
        /// Lower bound.
        lo: f32,
        /// Upper bound.
        hi: f32,
    },
    /// Normal with the given mean and standard deviation (support: all finite values).
    Normal {
        /// Mean.
        mean: f32,
        /// Standard deviation, > 0.
        std: f32,
    },
    /// Normal restricted to `[lo, hi]` and renormalized.
    TruncatedNormal {
        /// Mean of the untruncated normal.
        mean: f32,
        /// Standard deviation of the untruncated normal, > 0.
        std: f32,
        /// Lower bound.
        lo: f32,
        /// Upper bound.
        hi: f32,
    },
}

impl Dist {
    /// Uniform on `[lo, hi]`.
    #[must_use]
    pub const fn uniform(lo: f32, hi: f32) -> Self {
        Self::Uniform { lo, hi }
    }

    /// A constant.
    #[must_use]
    pub const fn constant(value: f32) -> Self {
        Self::Constant { value }
    }

    /// Normal with mean and standard deviation.
    #[must_use]
    pub const fn normal(mean: f32, std: f32) -> Self {
        Self::Normal { mean, std }
    }

    /// Normal truncated to `[lo, hi]`.
    #[must_use]
    pub const fn truncated_normal(mean: f32, std: f32, lo: f32, hi: f32) -> Self {
        Self::TruncatedNormal { mean, std, lo, hi }
    }

    /// The central value: the constant, the uniform's midpoint, the mean
    /// (clamped into a truncated normal's range). Always in the support.
    #[must_use]
    pub fn central(&self) -> f32 {
        match *self {
            Self::Constant { value } => value,
            Self::Uniform { lo, hi } => (0.5 * (f64::from(lo) + f64::from(hi))) as f32,
            Self::Normal { mean, .. } => mean,
            Self::TruncatedNormal { mean, lo, hi, .. } => mean.clamp(lo, hi),
        }
        .clamp(self.lower(), self.upper())
    }

    /// The support's smallest value (−∞ for a normal).
    fn lower(&self) -> f32 {
        match *self {
            Self::Constant { value } => value,
            Self::Uniform { lo, .. } | Self::TruncatedNormal { lo, .. } => lo,
            Self::Normal { .. } => f32::NEG_INFINITY,
        }
    }

    /// The support's largest value (+∞ for a normal).
    fn upper(&self) -> f32 {
        match *self {
            Self::Constant { value } => value,
            Self::Uniform { hi, .. } | Self::TruncatedNormal { hi, .. } => hi,
            Self::Normal { .. } => f32::INFINITY,
        }
    }

    /// Why this distribution has an empty or ill-defined support, if it does.
    pub fn problem(&self) -> Option<&'static str> {
        let finite = |xs: &[f32]| xs.iter().all(|x| x.is_finite());
        match *self {
            Self::Constant { value } => (!value.is_finite()).then_some("constant is not finite"),
            Self::Uniform { lo, hi } => {
                if !finite(&[lo, hi]) {
                    Some("uniform bounds are not finite")
                } else if lo > hi {
                    Some("uniform range is inverted (lo > hi)")
                } else {
                    None
                }
            }
            Self::Normal { mean, std } => {
                if !finite(&[mean, std]) {
                    Some("normal parameters are not finite")
                } else if std <= 0.0 {
                    Some("normal standard deviation must be > 0")
                } else {
                    None
                }
            }
            Self::TruncatedNormal { mean, std, lo, hi } => {
                if !finite(&[mean, std, lo, hi]) {
                    Some("truncated normal parameters are not finite")
                } else if std <= 0.0 {
                    Some("truncated normal standard deviation must be > 0")
                } else if lo > hi {
                    Some("truncated normal range is inverted (lo > hi)")
                } else if truncated_mass(mean, std, lo, hi) <= 0.0 {
                    Some("truncated normal range holds no probability mass")
                } else {
                    None
                }
            }
        }
    }

    /// Draws one value. The distribution must be valid ([`Dist::problem`] is `None`).
    pub fn sample<R: Rng + ?Sized>(&self, rng: &mut R) -> f32 {
        match *self {
            Self::Constant { value } => value,
            Self::Uniform { lo, hi } => {
                if lo == hi {
                    lo
                } else {
                    // Closed interval: the paper's ranges include both ends.
                    let u: f64 = rng.random();
                    let x = lo as f64 + u * (hi as f64 - lo as f64);
                    (x as f32).clamp(lo, hi)
                }
            }
            Self::Normal { mean, std } => {
                let z: f64 = StandardNormal.sample(rng);
                (mean as f64 + std as f64 * z) as f32
            }
            Self::TruncatedNormal { mean, std, lo, hi } => {
                sample_truncated(rng, mean as f64, std as f64, lo as f64, hi as f64)
            }
        }
    }

    /// Whether `x` lies in the support.
    #[must_use]
    pub fn contains(&self, x: f32) -> bool {
        match *self {
            Self::Constant { value } => x == value,
            Self::Uniform { lo, hi } | Self::TruncatedNormal { lo, hi, .. } => x >= lo && x <= hi,
            Self::Normal { .. } => x.is_finite(),
        }
    }

    /// Log-density of `x` (log-probability for a constant); `-inf` outside the support.
    #[must_use]
    pub fn log_density(&self, x: f32) -> f64 {
        if !self.contains(x) {
            return f64::NEG_INFINITY;
        }
        match *self {
            Self::Constant { .. } => 0.0,
            Self::Uniform { lo, hi } => {
                if lo == hi {
                    0.0
                } else {
                    -((hi as f64) - (lo as f64)).ln()
                }
            }
            Self::Normal { mean, std } => normal_log_pdf(x as f64, mean as f64, std as f64),
            Self::TruncatedNormal { mean, std, lo, hi } => {
                normal_log_pdf(x as f64, mean as f64, std as f64)
                    - truncated_mass(mean, std, lo, hi).ln()
            }
        }
    }
}

/// A distribution over the integers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum IntDist {
    /// Always the same value.
    Constant {
        /// The value.
        value: i32,
    },
    /// Uniform over `lo..=hi`.
    Uniform {
        /// Smallest value.
        lo: i32,
        /// Largest value (inclusive).
        hi: i32,
    },
}

impl IntDist {
    /// Uniform over `lo..=hi` (both included).
    #[must_use]
    pub const fn uniform(lo: i32, hi: i32) -> Self {
        Self::Uniform { lo, hi }
    }

    /// Always `value`.
    #[must_use]
    pub const fn constant(value: i32) -> Self {
        Self::Constant { value }
    }

    /// Why the support is empty, if it is.
    pub fn problem(&self) -> Option<&'static str> {
        match *self {
            Self::Uniform { lo, hi } if lo > hi => Some("integer range is inverted (lo > hi)"),
            _ => None,
        }
    }

    /// The central value: the constant, or the range's midpoint rounded
    /// down. Always in the support.
    #[must_use]
    pub fn central(&self) -> i32 {
        match *self {
            Self::Constant { value } => value,
            Self::Uniform { lo, hi } => ((i64::from(lo) + i64::from(hi)).div_euclid(2)) as i32,
        }
    }

    /// Draws one value.
    pub fn sample<R: Rng + ?Sized>(&self, rng: &mut R) -> i32 {
        match *self {
            Self::Constant { value } => value,
            Self::Uniform { lo, hi } => rng.random_range(lo..=hi),
        }
    }

    /// Whether `x` lies in the support.
    #[must_use]
    pub fn contains(&self, x: i32) -> bool {
        match *self {
            Self::Constant { value } => x == value,
            Self::Uniform { lo, hi } => (lo..=hi).contains(&x),
        }
    }

    /// Log-probability of `x`; `-inf` outside the support.
    #[must_use]
    pub fn log_density(&self, x: i32) -> f64 {
        match *self {
            _ if !self.contains(x) => f64::NEG_INFINITY,
            Self::Constant { .. } => 0.0,
            Self::Uniform { lo, hi } => -((hi as f64 - lo as f64) + 1.0).ln(),
        }
    }
}

/// Why a discrete choice's weights are unusable, if they are.
pub(crate) fn choice_problem(weights: &[f64]) -> Option<&'static str> {
    if weights.is_empty() {
        Some("choice has no options")
    } else if weights.iter().any(|w| !w.is_finite() || *w < 0.0) {
        Some("choice weights must be finite and >= 0")
    } else if weights.iter().sum::<f64>() <= 0.0 {
        Some("choice weights sum to 0")
    } else if weights.len() > u32::MAX as usize {
        Some("choice has too many options")
    } else {
        None
    }
}

/// Draws an index with probability proportional to `weights` (which must be valid).
pub(crate) fn sample_choice<R: Rng + ?Sized>(rng: &mut R, weights: &[f64]) -> u32 {
    let total: f64 = weights.iter().sum();
    let mut u = rng.random::<f64>() * total;
    let mut last_positive = 0;
    for (i, &w) in weights.iter().enumerate() {
        if w > 0.0 {
            if u < w {
                return i as u32;
            }
            u -= w;
            last_positive = i;
        }
    }
    last_positive as u32
}

fn normal_log_pdf(x: f64, mean: f64, std: f64) -> f64 {
    let z = (x - mean) / std;
    -0.5 * z * z - std.ln() - 0.5 * (2.0 * PI).ln()
}

/// Probability mass of `N(mean, std)` inside `[lo, hi]`.
fn truncated_mass(mean: f32, std: f32, lo: f32, hi: f32) -> f64 {
    let (mean, std) = (mean as f64, std as f64);
    normal_cdf((hi as f64 - mean) / std) - normal_cdf((lo as f64 - mean) / std)
}

fn normal_cdf(z: f64) -> f64 {
    0.5 * erfc(-z / std::f64::consts::SQRT_2)
}

/// Complementary error function (the Chebyshev fit `erfcc` of Numerical
/// Recipes; fractional error < 1.2e-7 everywhere).
fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let r = t
        * (-z * z - 1.265_512_23
            + t * (1.000_023_68
                + t * (0.374_091_96
                    + t * (0.096_784_18
                        + t * (-0.186_288_06
                            + t * (0.278_868_07
                                + t * (-1.135_203_98
                                    + t * (1.488_515_87
                                        + t * (-0.822_152_23 + t * 0.170_872_77)))))))))
            .exp();
    if x >= 0.0 { r } else { 2.0 - r }
}

/// Rejection sampling from a truncated normal: plain rejection when the
/// interval holds enough mass, otherwise uniform proposals with the normal
/// density as acceptance (the interval is then narrow or far in a tail).
fn sample_truncated<R: Rng + ?Sized>(rng: &mut R, mean: f64, std: f64, lo: f64, hi: f64) -> f32 {
    if lo == hi {
        return lo as f32;
    }
    let mass = normal_cdf((hi - mean) / std) - normal_cdf((lo - mean) / std);
    if mass > 0.25 {
        loop {
            let z: f64 = StandardNormal.sample(rng);
            let x = mean + std * z;
            if x >= lo && x <= hi {
                return (x as f32).clamp(lo as f32, hi as f32);
            }
        }
    }
    // The density's maximum on [lo, hi] is at the point closest to the mean.
    let peak = mean.clamp(lo, hi);
    let log_peak = -0.5 * ((peak - mean) / std).powi(2);
    loop {
        let x = lo + rng.random::<f64>() * (hi - lo);
        let log_acc = -0.5 * ((x - mean) / std).powi(2) - log_peak;
        if rng.random::<f64>().ln() <= log_acc {
            return (x as f32).clamp(lo as f32, hi as f32);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_pcg::Pcg64;
    use std::borrow::Cow;

    #[test]
    fn uniform_samples_stay_in_closed_range() {
        let d = Dist::uniform(0.6, 1.5);
        let mut rng = Pcg64::seed_from_u64(1);
        for _ in 0..10_000 {
            let x = d.sample(&mut rng);
            assert!(d.contains(x), "{x}");
        }
        assert!((d.log_density(1.0) - (-(0.9f64).ln())).abs() < 1e-6);
        assert_eq!(d.log_density(2.0), f64::NEG_INFINITY);
    }

    #[test]
    fn normal_cdf_matches_known_values() {
        assert!((normal_cdf(0.0) - 0.5).abs() < 1e-7);
        assert!((normal_cdf(1.0) - 0.841_344_746).abs() < 1e-6);
        assert!((normal_cdf(-2.0) - 0.022_750_132).abs() < 1e-6);
    }

    #[test]
    fn truncated_normal_stays_in_range_and_tails_work() {
        let mut rng = Pcg64::seed_from_u64(2);
        for d in [
            Dist::truncated_normal(0.0, 1.0, -0.5, 2.0),
            Dist::truncated_normal(0.0, 1.0, 4.0, 4.5),
        ] {
            assert!(d.problem().is_none());
            for _ in 0..2000 {
                assert!(d.contains(d.sample(&mut rng)));
            }
        }
        // Density integrates to ~1 over the support (trapezoid rule).
        let d = Dist::truncated_normal(0.3, 0.7, -0.5, 2.0);
        let n = 20_000;
        let h = 2.5 / n as f64;
        let integral: f64 = (0..=n)
            .map(|i| {
                let x = -0.5 + i as f64 * h;
                let w = if i == 0 || i == n { 0.5 } else { 1.0 };
                w * d.log_density(x as f32).exp()
            })
            .sum::<f64>()
            * h;
        assert!((integral - 1.0).abs() < 1e-3, "{integral}");
    }

    #[test]
    fn problems_are_detected() {
        assert!(Dist::uniform(2.0, 1.0).problem().is_some());
        assert!(Dist::uniform(f32::NAN, 1.0).problem().is_some());
        assert!(Dist::normal(0.0, 0.0).problem().is_some());
        assert!(
            Dist::truncated_normal(0.0, 1.0, 100.0, 101.0)
                .problem()
                .is_some()
        );
        assert!(IntDist::Uniform { lo: 3, hi: 2 }.problem().is_some());
        assert!(choice_problem(&[]).is_some());
        assert!(choice_problem(&[0.0, 0.0]).is_some());
        assert!(choice_problem(&[1.0, -1.0]).is_some());
        assert!(choice_problem(&[0.0, 2.0]).is_none());
    }

    #[test]
    fn choice_never_draws_zero_weight() {
        let w: Cow<'static, [f64]> = Cow::Owned(vec![0.0, 1.0, 0.0, 3.0]);
        let mut rng = Pcg64::seed_from_u64(3);
        let mut counts = [0u32; 4];
        for _ in 0..40_000 {
            counts[sample_choice(&mut rng, &w) as usize] += 1;
        }
        assert_eq!(counts[0] + counts[2], 0);
        let ratio = counts[3] as f64 / counts[1] as f64;
        assert!((ratio - 3.0).abs() < 0.15, "{ratio}");
    }
}
