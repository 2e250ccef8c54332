//! Gaussian process regression of preference scores (thesis §4.4.2).
//!
//! A zero-mean Gaussian process over feature vectors with the anisotropic
//! kernel
//!
//! ```text
//! k(x, x') = θ₀ exp(−½ Σ_d θ_d (x_d − x'_d)²) + δ(x, x') β⁻¹
//! ```
//!
//! (`β⁻¹` = [`GpOptions::noise`], 0.01 by default as in the thesis). The
//! hyperparameters `θ` are chosen by *automatic relevance determination*:
//! minimizing the negative log marginal likelihood plus a lasso term
//! `λ Σ_{d ≥ 1} θ_d` (`λ` = [`GpOptions::lasso`], 0.1), over `ln θ` so that
//! they stay positive. The thesis minimizes with conjugate gradients; we use
//! argmin's L-BFGS with a Moré–Thuente line search on the same energy and its
//! analytic gradient. The lasso drives the weights of irrelevant features to
//! about zero ([`Gp::relevant`]).
//!
//! Scores are given on the thesis's scale 0–100 and regressed as
//! `score / 100`, so the noise term is relative to a preference of 1.

use argmin::core::{CostFunction, Executor, Gradient, State};
use argmin::solver::linesearch::MoreThuenteLineSearch;
use argmin::solver::quasinewton::LBFGS;
use nalgebra::{Cholesky, DMatrix, DVector, Dyn};
use serde::{Deserialize, Serialize};

use crate::DesignError;

/// Settings of the regression and its hyperparameter search.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct GpOptions {
    /// `β⁻¹`, added to the kernel's diagonal (on the 0–1 preference scale).
    pub noise: f64,
    /// `λ`, the weight of the lasso term on the feature weights.
    pub lasso: f64,
    /// Most L-BFGS iterations of the hyperparameter search.
    pub max_iters: u64,
    /// Searches from this many starting points (feature weights `2/D`,
    /// then 10× smaller, then 10× larger); the lowest energy wins.
    #[serde(default = "one")]
    pub restarts: usize,
}

fn one() -> usize {
    1
}

impl Default for GpOptions {
    /// The thesis's `β⁻¹ = 0.01` and `λ = 0.1`; 100 iterations.
    fn default() -> Self {
        Self {
            noise: 0.01,
            lasso: 0.1,
            max_iters: 100,
            restarts: RESTARTS_DEFAULT,
        }
    }
}

const RESTARTS_DEFAULT: usize = 1;

/// A fitted Gaussian process: training inputs, hyperparameters and the
/// factorization that predictions reuse.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(try_from = "Fit", into = "Fit")]
pub struct Gp {
    fit: Fit,
    /// `C⁻¹ y`.
    alpha: DVector<f64>,
    chol: Cholesky<f64, Dyn>,
}

/// What a [`Gp`] was fitted on and the hyperparameters found: all that is
/// stored; the factorization is recomputed from it.
#[derive(Clone, Debug, Serialize, Deserialize)]
struct Fit {
    x: Vec<Vec<f64>>,
    y: Vec<f64>,
    theta0: f64,
    theta: Vec<f64>,
    options: GpOptions,
    energy: f64,
}

impl TryFrom<Fit> for Gp {
    type Error = DesignError;

    /// Factorizes the covariance; a (hand-edited) fit whose covariance is
    /// not positive definite is an error.
    fn try_from(fit: Fit) -> Result<Self, DesignError> {
        if fit.x.len() != fit.y.len() {
            return Err(DesignError::Mismatch {
                what: "a process's training inputs and scores",
                left: fit.x.len(),
                right: fit.y.len(),
            });
        }
        if let Some(x) = fit.x.iter().find(|x| x.len() != fit.theta.len()) {
            return Err(DesignError::Mismatch {
                what: "a training input's features and the feature weights",
                left: x.len(),
                right: fit.theta.len(),
            });
        }
        let finite = fit.x.iter().flatten().chain(&fit.y).all(|v| v.is_finite());
        let weights = fit.theta.iter().all(|t| t.is_finite() && *t >= 0.0);
        let positive = |v: f64| v.is_finite() && v > 0.0;
        if !(finite && weights && positive(fit.theta0) && positive(fit.options.noise)) {
            return Err(DesignError::Invalid(
                "a process's inputs, scores, weights, amplitude or noise are not finite numbers of their sign".into(),
            ));
        }
        let (chol, alpha) = factor(&fit.x, &fit.y, fit.theta0, &fit.theta, fit.options.noise)
            .ok_or(DesignError::NotPositiveDefinite)?;
        Ok(Self { fit, alpha, chol })
    }
}

impl From<Gp> for Fit {
    fn from(g: Gp) -> Self {
        g.fit
    }
}

/// The kernel without its noise term.
fn kernel(a: &[f64], b: &[f64], theta0: f64, theta: &[f64]) -> f64 {
    let mut s = 0.0;
    for ((x, y), t) in a.iter().zip(b).zip(theta) {
        let d = x - y;
        s += t * d * d;
    }
    theta0 * (-0.5 * s).exp()
}

fn covariance(x: &[Vec<f64>], theta0: f64, theta: &[f64], noise: f64) -> DMatrix<f64> {
    let n = x.len();
    let mut c = DMatrix::zeros(n, n);
    for i in 0..n {
        for j in 0..=i {
            let k = kernel(&x[i], &x[j], theta0, theta);
            c[(i, j)] = k;
            c[(j, i)] = k;
        }
        c[(i, i)] += noise;
    }
    c
}

fn factor(
    x: &[Vec<f64>],
    y: &[f64],
    theta0: f64,
    theta: &[f64],
    noise: f64,
) -> Option<(Cholesky<f64, Dyn>, DVector<f64>)> {
    let chol = covariance(x, theta0, theta, noise).cholesky()?;
    let alpha = chol.solve(&DVector::from_column_slice(y));
    Some((chol, alpha))
}

/// The ARD energy over `φ = ln θ` (θ₀ first).
#[derive(Clone, Copy)]
struct Energy<'a> {
    x: &'a [Vec<f64>],
    y: &'a [f64],
    options: GpOptions,
}

/// `ln θ` is kept in this range so that no kernel overflows.
const LN_THETA: (f64, f64) = (-25.0, 12.0);

fn thetas(phi: &[f64]) -> (f64, Vec<f64>) {
    let t = |p: f64| p.clamp(LN_THETA.0, LN_THETA.1).exp();
    (t(phi[0]), phi[1..].iter().map(|&p| t(p)).collect())
}

impl Energy<'_> {
    /// Energy and (optionally) its gradient; `None` if `C` is not positive definite.
    fn eval(&self, phi: &[f64], with_gradient: bool) -> Option<(f64, Vec<f64>)> {
        let (theta0, theta) = thetas(phi);
        let n = self.x.len();
        let c = covariance(self.x, theta0, &theta, self.options.noise);
        let chol = c.cholesky()?;
        let y = DVector::from_column_slice(self.y);
        let alpha = chol.solve(&y);
        let log_det: f64 = 2.0
            * chol
                .l_dirty()
                .diagonal()
                .iter()
                .take(n)
                .map(|v| v.ln())
                .sum::<f64>();
        let lasso: f64 = theta.iter().sum::<f64>() * self.options.lasso;
        let energy = 0.5 * log_det
            + 0.5 * y.dot(&alpha)
            + 0.5 * n as f64 * (2.0 * std::f64::consts::PI).ln()
            + lasso;
        if !with_gradient {
            return Some((energy, Vec::new()));
        }
        // W = C⁻¹ − α αᵀ; ∂E/∂φ = ½ Σ W ⊙ ∂C/∂φ (+ lasso).
        let mut w = chol.inverse();
        w -= &alpha * alpha.transpose();
        let mut grad = vec![0.0; phi.len()];
        let d = theta.len();
        for i in 0..n {
            for j in 0..n {
                let kij = kernel(&self.x[i], &self.x[j], theta0, &theta);
                let wk = w[(i, j)] * kij;
                // ∂C/∂ln θ₀ = K (noise excluded).
                grad[0] += 0.5 * wk;
                if i != j {
                    for k in 0..d {
                        let diff = self.x[i][k] - self.x[j][k];
                        // ∂C/∂ln θ_k = K · (−½ θ_k Δ²).
                        grad[k + 1] -= 0.25 * wk * theta[k] * diff * diff;
                    }
                }
            }
        }
        for k in 0..d {
            grad[k + 1] += self.options.lasso * theta[k];
        }
        // Outside the clamped range the energy is flat.
        for (g, &p) in grad.iter_mut().zip(phi) {
            if !(LN_THETA.0..=LN_THETA.1).contains(&p) {
                *g = 0.0;
            }
        }
        Some((energy, grad))
    }
}

impl CostFunction for Energy<'_> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, phi: &Vec<f64>) -> Result<f64, argmin::core::Error> {
        Ok(self.eval(phi, false).map_or(f64::INFINITY, |e| e.0))
    }
}

impl Gradient for Energy<'_> {
    type Param = Vec<f64>;
    type Gradient = Vec<f64>;
    fn gradient(&self, phi: &Vec<f64>) -> Result<Vec<f64>, argmin::core::Error> {
        self.eval(phi, true)
            .map(|e| e.1)
            .ok_or_else(|| argmin::core::Error::msg("the covariance is not positive definite"))
    }
}

impl Gp {
    /// Fits a process to feature vectors `x` with scores `scores` (0–100),
    /// choosing the hyperparameters by ARD: `θ₀` starts at the mean squared
    /// preference and every `θ_d` at `2 / D` (and 10× smaller and larger
    /// with [`GpOptions::restarts`]).
    pub fn fit(x: Vec<Vec<f64>>, scores: &[f64], options: GpOptions) -> Result<Self, DesignError> {
        if x.is_empty() {
            return Err(DesignError::NoScores);
        }
        if x.len() != scores.len() {
            return Err(DesignError::Mismatch {
                what: "feature vectors and scores",
                left: x.len(),
                right: scores.len(),
            });
        }
        if let Some(&bad) = scores.iter().find(|s| !(0.0..=100.0).contains(*s)) {
            return Err(DesignError::ScoreRange(bad));
        }
        let d = x[0].len();
        if let Some(row) = x.iter().find(|r| r.len() != d) {
            return Err(DesignError::Mismatch {
                what: "feature dimensions",
                left: d,
                right: row.len(),
            });
        }
        let y: Vec<f64> = scores.iter().map(|s| s / 100.0).collect();
        let mean_sq = y.iter().map(|v| v * v).sum::<f64>() / y.len() as f64;
        let starts: Vec<Vec<f64>> = [1.0, 0.1, 10.0]
            .iter()
            .take(options.restarts.clamp(1, 3))
            .map(|&f| {
                std::iter::once(mean_sq.max(0.01).ln())
                    .chain(std::iter::repeat_n((f * 2.0 / d.max(1) as f64).ln(), d))
                    .collect()
            })
            .collect();
        let energy = Energy {
            x: &x,
            y: &y,
            options,
        };
        let mut best: Option<(Vec<f64>, f64)> = None;
        for phi in starts {
            let initial = energy.eval(&phi, false).map_or(f64::INFINITY, |e| e.0);
            let solver = LBFGS::new(MoreThuenteLineSearch::new(), 7);
            let found = Executor::new(energy, solver)
                .configure(|s| s.param(phi.clone()).max_iters(options.max_iters))
                .run()
                .ok()
                .and_then(|r| {
                    let st = r.state();
                    Some((st.get_best_param()?.clone(), st.get_best_cost()))
                });
            // Keep the start if the search failed or did not improve on it.
            let candidate = match found {
                Some((p, c)) if c.is_finite() && c <= initial => (p, c),
                _ => (phi, initial),
            };
            if best.as_ref().is_none_or(|b| candidate.1 < b.1) {
                best = Some(candidate);
            }
        }
        let (phi, energy) = best.expect("at least one start");
        let (theta0, theta) = thetas(&phi);
        Self::try_from(Fit {
            x,
            y,
            theta0,
            theta,
            options,
            energy,
        })
    }

    /// Fits with fixed hyperparameters (no search): the closed-form regression.
    pub fn with_hyperparameters(
        x: Vec<Vec<f64>>,
        scores: &[f64],
        theta0: f64,
        theta: Vec<f64>,
        options: GpOptions,
    ) -> Result<Self, DesignError> {
        if x.is_empty() {
            return Err(DesignError::NoScores);
        }
        let y: Vec<f64> = scores.iter().map(|s| s / 100.0).collect();
        let energy = Energy {
            x: &x,
            y: &y,
            options,
        }
        .eval(
            &std::iter::once(theta0.ln())
                .chain(theta.iter().map(|t| t.ln()))
                .collect::<Vec<_>>(),
            false,
        )
        .map_or(f64::NAN, |e| e.0);
        Self::try_from(Fit {
            x,
            y,
            theta0,
            theta,
            options,
            energy,
        })
    }

    /// The predicted score (0–100 scale) and its variance at feature vector `x`.
    #[must_use]
    pub fn predict(&self, x: &[f64]) -> (f64, f64) {
        let k = DVector::from_iterator(
            self.fit.x.len(),
            self.fit
                .x
                .iter()
                .map(|xi| kernel(xi, x, self.fit.theta0, &self.fit.theta)),
        );
        let mean = k.dot(&self.alpha);
        let v = self
            .chol
            .l_dirty()
            .solve_lower_triangular(&k)
            .unwrap_or_else(|| DVector::zeros(k.len()));
        let var = (self.fit.theta0 + self.fit.options.noise - v.dot(&v)).max(0.0);
        (100.0 * mean, 1e4 * var)
    }

    /// The kernel between two feature vectors (noise excluded): the similarity
    /// that sorting by resemblance and clustering use.
    #[must_use]
    pub fn similarity(&self, a: &[f64], b: &[f64]) -> f64 {
        kernel(a, b, self.fit.theta0, &self.fit.theta)
    }

    /// `θ₀`, the kernel's amplitude.
    #[must_use]
    pub fn amplitude(&self) -> f64 {
        self.fit.theta0
    }

    /// Number of features `D` the process reads.
    #[must_use]
    pub fn dimension(&self) -> usize {
        self.fit.theta.len()
    }

    /// The feature weights `θ_d`.
    #[must_use]
    pub fn weights(&self) -> &[f64] {
        &self.fit.theta
    }

    /// The indices of features whose weight is at least `threshold` (ARD's
    /// relevant features; see [`Factor::relevant_nodes`](crate::Factor::relevant_nodes)
    /// for the threshold structure learning uses).
    #[must_use]
    pub fn relevant(&self, threshold: f64) -> Vec<usize> {
        (0..self.fit.theta.len())
            .filter(|&d| self.fit.theta[d] >= threshold)
            .collect()
    }

    /// The minimized energy (negative log marginal likelihood plus lasso).
    #[must_use]
    pub fn energy(&self) -> f64 {
        self.fit.energy
    }

    /// Number of training points.
    #[must_use]
    pub fn len(&self) -> usize {
        self.fit.y.len()
    }

    /// Whether it has no training points (never, once fitted).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.fit.y.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// With fixed hyperparameters the mean and variance equal the closed form
    /// worked by hand for two points.
    #[test]
    fn two_points_match_the_closed_form() {
        let x = vec![vec![0.0], vec![1.0]];
        let options = GpOptions {
            noise: 0.01,
            ..GpOptions::default()
        };
        let gp = Gp::with_hyperparameters(x, &[100.0, 0.0], 1.0, vec![2.0], options).unwrap();
        // C = [[1.01, e⁻¹], [e⁻¹, 1.01]], y = [1, 0].
        let e = (-1.0f64).exp();
        let det = 1.01 * 1.01 - e * e;
        let alpha = [1.01 / det, -e / det];
        // At x* = 0.5: k = [e^{-1/4}, e^{-1/4}].
        let k = (-0.25f64).exp();
        let mean = 100.0 * k * (alpha[0] + alpha[1]);
        // kᵀ C⁻¹ k = k² (1.01 − e − e + 1.01) / det.
        let var = 1e4 * (1.0 + 0.01 - k * k * (2.02 - 2.0 * e) / det);
        let (m, v) = gp.predict(&[0.5]);
        assert!((m - mean).abs() < 1e-9, "{m} vs {mean}");
        assert!((v - var).abs() < 1e-6, "{v} vs {var}");
    }

    /// The analytic gradient equals central differences of the energy.
    #[test]
    fn gradient_matches_finite_differences() {
        let x: Vec<Vec<f64>> = (0..12)
            .map(|i| {
                let t = i as f64 / 11.0;
                vec![t, (3.0 * t).sin().abs(), ((i * 7) % 5) as f64 / 4.0]
            })
            .collect();
        let y: Vec<f64> = x
            .iter()
            .map(|v| (v[0] * 0.8 + 0.1 * v[2]).min(1.0))
            .collect();
        let e = Energy {
            x: &x,
            y: &y,
            options: GpOptions::default(),
        };
        let phi = vec![-0.3, 0.2, -1.0, 0.5];
        let (_, g) = e.eval(&phi, true).unwrap();
        for k in 0..phi.len() {
            let h = 1e-5;
            let mut a = phi.clone();
            let mut b = phi.clone();
            a[k] += h;
            b[k] -= h;
            let fd = (e.eval(&a, false).unwrap().0 - e.eval(&b, false).unwrap().0) / (2.0 * h);
            assert!(
                (fd - g[k]).abs() < 1e-5 * (1.0 + fd.abs()),
                "φ{k}: {fd} vs {}",
                g[k]
            );
        }
    }
}
