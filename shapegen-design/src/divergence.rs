//! Comparing pdfs: Jensen–Shannon divergence over a fixed model set, and the
//! score-weighted kernel density estimate of Talton et al. (2009) that the
//! thesis compares GPR with (§4.7).
//!
//! The thesis measures every learned pdf on a pre-sampled set of models from
//! the default pdf. With such a set `E` (drawn from `p`), a pdf `q` becomes a
//! distribution over `E` by the weights `q(m)/p(m)`: the target
//! `t = p·u/Z` gives weights `u(m)`; a preference estimate `û` gives `û(m)`;
//! a learned sampler gives its [`log_ratio`](crate::sampler::LearnedSampler::log_ratio);
//! the default pdf gives equal weights.

/// The Jensen–Shannon divergence (base 2, so in `[0, 1]`) between two
/// distributions given by non-negative weights over the same items (each
/// normalized here). `None` if either has no positive weight or their lengths differ.
#[must_use]
pub fn jensen_shannon(p: &[f64], q: &[f64]) -> Option<f64> {
    if p.len() != q.len() {
        return None;
    }
    let sp: f64 = p.iter().map(|v| v.max(0.0)).sum();
    let sq: f64 = q.iter().map(|v| v.max(0.0)).sum();
    if !(sp > 0.0 && sq > 0.0 && sp.is_finite() && sq.is_finite()) {
        return None;
    }
    let mut js = 0.0;
    for (&a, &b) in p.iter().zip(q) {
        let a = a.max(0.0) / sp;
        let b = b.max(0.0) / sq;
        let m = 0.5 * (a + b);
        if a > 0.0 {
            js += 0.5 * a * (a / m).log2();
        }
        if b > 0.0 {
            js += 0.5 * b * (b / m).log2();
        }
    }
    Some(js.clamp(0.0, 1.0))
}

/// Weights from log-weights, stably (the largest becomes 1).
#[must_use]
pub fn weights_from_logs(logs: &[f64]) -> Vec<f64> {
    let max = logs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    logs.iter()
        .map(|&l| {
            if max.is_finite() {
                (l - max).exp()
            } else {
                0.0
            }
        })
        .collect()
}

/// Talton et al.'s kernel density estimate with the scores as kernel weights
/// (as the thesis adapts it), over feature vectors, with an isotropic
/// Gaussian kernel of bandwidth `h`.
///
/// Its scored models come from the default pdf `p`, so the weighted estimate
/// approximates `p · u` in feature space; divided by the unweighted estimate
/// of `p` from the same models, it gives the weight over a model set drawn
/// from `p` ([`WeightedKde::weight`]).
#[derive(Clone, Copy, Debug)]
pub struct WeightedKde<'a> {
    x: &'a [Vec<f64>],
    scores: &'a [f64],
    bandwidth: f64,
}

impl<'a> WeightedKde<'a> {
    /// An estimate from feature vectors `x` with scores (0–100).
    #[must_use]
    pub fn new(x: &'a [Vec<f64>], scores: &'a [f64], bandwidth: f64) -> Self {
        Self {
            x,
            scores,
            bandwidth,
        }
    }

    /// The weight `q(m)/p(m)` at feature vector `x`: the score-weighted
    /// kernel sum over the unweighted one (0 far from every scored model).
    #[must_use]
    pub fn weight(&self, x: &[f64]) -> f64 {
        let h2 = 2.0 * self.bandwidth * self.bandwidth;
        let (mut num, mut den) = (0.0, 0.0);
        for (xi, &s) in self.x.iter().zip(self.scores) {
            let d2: f64 = xi.iter().zip(x).map(|(a, b)| (a - b) * (a - b)).sum();
            let k = (-d2 / h2).exp();
            num += s * k;
            den += k;
        }
        if den > 0.0 { num / den } else { 0.0 }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn js_of_known_distributions() {
        assert_eq!(jensen_shannon(&[1.0, 2.0], &[2.0, 4.0]), Some(0.0));
        // Disjoint supports: one bit.
        assert!((jensen_shannon(&[1.0, 0.0], &[0.0, 3.0]).unwrap() - 1.0).abs() < 1e-12);
        // (½,½) vs (1,0): ½·[½ log2(½/¾)·… ] worked by hand = 0.311278.
        let v = jensen_shannon(&[1.0, 1.0], &[1.0, 0.0]).unwrap();
        assert!((v - 0.311_278_124_459_132_8).abs() < 1e-12, "{v}");
        assert_eq!(jensen_shannon(&[0.0], &[1.0]), None);
    }
}
