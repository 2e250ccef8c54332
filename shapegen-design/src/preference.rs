//! A preference function: one or several learned factors (thesis §4.4.3).
//!
//! A [`Factor`] is a Gaussian process over a [`FeatureSpace`] fitted on the
//! models a user scored for it. A [`Preference`] is the product of its
//! factors, each clamped to `[0, 1]` (scores over 100): "steel or wood" and
//! "round top" can be scored separately and combined.

use serde::{Deserialize, Serialize};
use shapegen_core::genome::Chromosome;
use shapegen_core::graph::{Graph, NodeId};

use crate::DesignError;
use crate::features::{FeatureOptions, FeatureSpace};
use crate::gp::{Gp, GpOptions};

/// How a factor is fitted.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct FactorOptions {
    /// The features to start with (`path_length` is where `k` starts).
    pub features: FeatureOptions,
    /// The regression.
    pub gp: GpOptions,
    /// The largest `k` the automatic growth may reach.
    pub max_path_length: u32,
    /// Two scored models whose features are this close (squared distance)
    /// but whose scores differ by more than [`FactorOptions::score_gap`]
    /// make `k` grow: the features cannot tell them apart.
    pub same_features: f64,
    /// See [`FactorOptions::same_features`] (score units, 0–100).
    pub score_gap: f64,
}

impl Default for FactorOptions {
    fn default() -> Self {
        Self {
            features: FeatureOptions::default(),
            gp: GpOptions::default(),
            max_path_length: 4,
            same_features: 1e-9,
            score_gap: 25.0,
        }
    }
}

/// One learned factor of a preference.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Factor {
    /// A name the user gave it (e.g. "colour").
    pub name: String,
    /// The features it reads.
    pub space: FeatureSpace,
    /// The fitted process.
    pub gp: Gp,
}

impl Factor {
    /// Fits a factor to `models` of `graph` scored `scores` (0–100). The
    /// effective path length starts at `options.features.path_length` and
    /// grows (up to `max_path_length`) while two models with the same
    /// features have very different scores.
    pub fn fit(
        name: &str,
        graph: &Graph,
        models: &[Chromosome],
        scores: &[f64],
        options: FactorOptions,
    ) -> Result<Self, DesignError> {
        if models.len() != scores.len() {
            return Err(DesignError::Mismatch {
                what: "scored models and scores",
                left: models.len(),
                right: scores.len(),
            });
        }
        let mut features = options.features;
        loop {
            let space = FeatureSpace::fit(graph, models, features);
            let x: Vec<Vec<f64>> = models.iter().map(|m| space.features(graph, m)).collect();
            let ambiguous = features.path_length < options.max_path_length
                && (0..x.len()).any(|i| {
                    (0..i).any(|j| {
                        (scores[i] - scores[j]).abs() > options.score_gap
                            && x[i]
                                .iter()
                                .zip(&x[j])
                                .map(|(a, b)| (a - b) * (a - b))
                                .sum::<f64>()
                                <= options.same_features
                    })
                });
            if ambiguous {
                features.path_length += 1;
                continue;
            }
            let gp = Gp::fit(x, scores, options.gp)?;
            return Ok(Self {
                name: name.to_string(),
                space,
                gp,
            });
        }
    }

    /// Predicted score (0–100) and its variance for `model`.
    #[must_use]
    pub fn predict(&self, graph: &Graph, model: &Chromosome) -> (f64, f64) {
        self.gp.predict(&self.space.features(graph, model))
    }

    /// The base nodes named by features whose ARD weight is at least
    /// `threshold` times the largest weight: the nodes structure learning
    /// splits. (Relative, because the lasso can trade small weights for a
    /// large amplitude θ₀: the weights' ratios are what ARD decides.)
    #[must_use]
    pub fn relevant_nodes(&self, threshold: f64) -> Vec<NodeId> {
        let max = self.gp.weights().iter().copied().fold(0.0, f64::max);
        let mut nodes: Vec<NodeId> = self
            .gp
            .relevant(threshold * max)
            .into_iter()
            .flat_map(|d| self.space.keys()[d].nodes())
            .collect();
        nodes.sort_unstable();
        nodes.dedup();
        nodes
    }

    /// The features with the largest weights, with their weights, largest first.
    #[must_use]
    pub fn top_features(&self, graph: &Graph, count: usize) -> Vec<(String, f64)> {
        let mut idx: Vec<usize> = (0..self.space.len()).collect();
        let w = self.gp.weights();
        idx.sort_by(|&a, &b| w[b].total_cmp(&w[a]));
        idx.into_iter()
            .take(count)
            .map(|d| (self.space.keys()[d].describe(graph), w[d]))
            .collect()
    }
}

/// The fraction of the largest ARD weight at or above which a feature counts as relevant.
pub const RELEVANCE: f64 = 0.05;

/// A preference: the product of factors.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Preference {
    /// The factors.
    pub factors: Vec<Factor>,
}

impl Preference {
    /// Whether the preference can read models of `graph`: every factor's
    /// features name what the graph has, and its process reads as many
    /// features as its space gives (a preference read from a file is checked
    /// so before it predicts anything).
    pub fn check(&self, graph: &Graph) -> Result<(), DesignError> {
        for f in &self.factors {
            if f.space.len() != f.gp.dimension() {
                return Err(DesignError::Mismatch {
                    what: "a factor's features and its process's weights",
                    left: f.space.len(),
                    right: f.gp.dimension(),
                });
            }
            for key in f.space.keys() {
                key.check(graph)
                    .map_err(|why| DesignError::Invalid(format!("factor `{}`: {why}", f.name)))?;
            }
        }
        Ok(())
    }

    /// A preference of one factor.
    #[must_use]
    pub fn single(factor: Factor) -> Self {
        Self {
            factors: vec![factor],
        }
    }

    /// `u(m)` in `[0, 1]`: the product of the factors' predicted scores over
    /// 100, each clamped to `[0, 1]`. 1 when there are no factors.
    #[must_use]
    pub fn value(&self, graph: &Graph, model: &Chromosome) -> f64 {
        self.factors
            .iter()
            .map(|f| (f.predict(graph, model).0 / 100.0).clamp(0.0, 1.0))
            .product()
    }

    /// Predicted score (0–100) and standard deviation of `model`: for one
    /// factor the process's; for several, the product of the clamped means
    /// and, to first order, the spread that their independent uncertainties
    /// give the product.
    #[must_use]
    pub fn predict(&self, graph: &Graph, model: &Chromosome) -> (f64, f64) {
        let parts: Vec<(f64, f64)> = self
            .factors
            .iter()
            .map(|f| {
                let (m, v) = f.predict(graph, model);
                ((m / 100.0).clamp(0.0, 1.0), v.sqrt() / 100.0)
            })
            .collect();
        let mean: f64 = parts.iter().map(|p| p.0).product();
        let var: f64 = (0..parts.len())
            .map(|i| {
                let others: f64 = parts
                    .iter()
                    .enumerate()
                    .filter(|(j, _)| *j != i)
                    .map(|(_, p)| p.0)
                    .product();
                (others * parts[i].1).powi(2)
            })
            .sum();
        (100.0 * mean, 100.0 * var.sqrt())
    }

    /// The base nodes any factor finds relevant.
    #[must_use]
    pub fn relevant_nodes(&self) -> Vec<NodeId> {
        let mut nodes: Vec<NodeId> = self
            .factors
            .iter()
            .flat_map(|f| f.relevant_nodes(RELEVANCE))
            .collect();
        nodes.sort_unstable();
        nodes.dedup();
        nodes
    }

    /// A kernel distance between two models: the largest over factors of
    /// `√(k(a,a) + k(b,b) − 2k(a,b))` (0 for models every factor sees alike).
    #[must_use]
    pub fn distance(&self, graph: &Graph, a: &Chromosome, b: &Chromosome) -> f64 {
        self.factors
            .iter()
            .map(|f| {
                let (x, y) = (f.space.features(graph, a), f.space.features(graph, b));
                let k = f.gp.similarity(&x, &y);
                (2.0 * f.gp.amplitude() - 2.0 * k).max(0.0).sqrt()
            })
            .fold(0.0, f64::max)
    }
}
