//! # shapegen-design
//!
//! Designing a procedural generator's probability density from preference
//! scores: *Interactive design of probability density functions for shape
//! grammars* (Dang, Lienhard, Ceylan, Neubert, Wonka, Pauly 2015; chapter 4
//! of Lienhard's thesis). A user scores sample models from 0 to 100; a
//! Gaussian process learns the preference over the whole model space; the
//! generator is adapted to sample according to it.
//!
//! Our generator graphs are the thesis's stochastic grammars: a node is a
//! rule, a slot is a child index, a choice parameter is a choice between
//! rules, and slot probabilities and parameter distributions are its Θ.
//!
//! - [`features`]: Φ(m), a model's feature vector from its derivation tree.
//! - [`gp`]: Gaussian process regression with automatic relevance
//!   determination and a lasso term.
//! - [`preference`]: a preference function, the product of learned factors.
//! - [`split`]: split graphs (nodes copied per incoming edge, the thesis's
//!   parent annotation) and the mapping of models into them.
//! - [`sampler`]: sampling by the learned pdf: rejection sampling, parameter
//!   learning and structure learning (a mixture of split graphs fitted by EM),
//!   and the [`sampler::LearnedPdf`] file that other tools read.
//! - [`evaluation`]: the thesis's evaluation protocol (design tasks played
//!   by a program, JS divergences, learning curves against the KDE), and
//!   [`toy`], the thesis's toy grammar and its tasks.
//! - [`divergence`]: Jensen–Shannon divergence and the weighted kernel density
//!   estimate of Talton et al. that the thesis compares with.
//!
//! ## The target pdf
//!
//! Uncontrolled generation of a graph defines its *default pdf* `p(m)`
//! ([`shapegen_core::ops::uncontrolled_log_density`]). A preference `u(m)` in
//! `[0, 1]` (scores over 100, clamped) defines the *target pdf*
//! `t(m) = p(m) u(m) / Z`: the default pdf reweighted by the preference, so a
//! model twice as preferred is twice as likely as it was, and a model scored
//! 0 is never drawn. (The thesis normalizes `u` alone, which is the same
//! thing on its finite pre-sampled model sets; over a recursive grammar's
//! infinite model space only the reweighted form is a density.)
//!
//! Every sampler here returns chromosomes of the original graph, checked by
//! [`Chromosome::relabel`](shapegen_core::genome::Chromosome::relabel) or
//! made by its own uncontrolled generation: a learned pdf never produces a
//! model the generator could not derive.

pub mod divergence;
pub mod evaluation;
pub mod features;
pub mod gp;
pub mod preference;
pub mod sampler;
pub mod split;
pub mod toy;

pub use features::{FeatureKey, FeatureOptions, FeatureSpace};
pub use gp::{Gp, GpOptions};
pub use preference::{Factor, FactorOptions, Preference};
pub use sampler::{
    LearnedPdf, LearnedSampler, Learner, RejectionSampler, StructureOptions, StructureReport,
    learn_pdf, parameter_learning, structure_learning,
};
pub use split::SplitGraph;

/// What can go wrong while learning or sampling a pdf.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DesignError {
    /// Nothing was scored yet.
    #[error("no scored models: score some models before learning")]
    NoScores,
    /// A score outside 0–100.
    #[error("score {0} is outside 0..=100")]
    ScoreRange(f64),
    /// Two lists that must have one entry each do not.
    #[error("{what} disagree in number ({left} vs {right})")]
    Mismatch {
        /// What was compared.
        what: &'static str,
        /// One count.
        left: usize,
        /// The other.
        right: usize,
    },
    /// The kernel matrix could not be factorized.
    #[error("the kernel matrix is not positive definite (raise the noise term)")]
    NotPositiveDefinite,
    /// The preference is 0 on every probe model: the pdf it defines has
    /// (almost) no mass where the generator samples.
    #[error(
        "the preference is 0 on all {0} probe models: the pdf it defines has nothing to sample (score some models above 0, or sample from the default pdf)"
    )]
    NoMass(usize),
    /// Rejection sampling accepted nothing within its proposal budget.
    #[error(
        "rejection sampling accepted no model in {0} proposals: the preference is (almost) 0 everywhere the generator samples"
    )]
    NoAcceptance(u64),
    /// A graph operation failed.
    #[error(transparent)]
    Graph(#[from] shapegen_core::graph::GraphErrors),
    /// A model could not be made or moved between graphs.
    #[error(transparent)]
    Genome(#[from] shapegen_core::genome::GenomeError),
    /// Uncontrolled generation failed.
    #[error(transparent)]
    Op(#[from] shapegen_core::ops::OpError),
    /// A learned pdf was made for another generator.
    #[error(
        "the learned pdf is for generator `{found}` (fingerprint {found_fp}), not `{expected}` (fingerprint {expected_fp})"
    )]
    ForeignGraph {
        /// The generator named in the file.
        found: String,
        /// Its fingerprint.
        found_fp: String,
        /// The generator given.
        expected: String,
        /// Its fingerprint.
        expected_fp: String,
    },
    /// A learned pdf is inconsistent.
    #[error("invalid learned pdf: {0}")]
    Invalid(String),
}
