//! The thesis's evaluation (§4.7): design tasks with a known preference,
//! played by a program, measured by Jensen–Shannon divergence to the target pdf.
//!
//! For a [`Task`] (a graph and one known score function per factor):
//!
//! 1. An evaluation set `E` is drawn from the default pdf; the target pdf
//!    over it has weights `u*(m)` (the product of the factors' scores over 100).
//! 2. *Sampling strategies* (the thesis's Table 4.3): a training set is drawn
//!    from the target by rejection sampling with the true preference;
//!    parameter learning and structure learning are fitted to it (structure
//!    learning splits the nodes that a GPR fitted on `fit_models` scored
//!    default samples finds relevant, and clusters with its kernel). Each
//!    pdf's JS divergence to the target is measured over `E`, beside the
//!    default pdf's.
//! 3. *Learning curves* (Fig. 4.13): for growing numbers of scored models
//!    (default samples, the same ones for both learners), the JS divergence
//!    of the pdf that GPR learns (weights `û(m)`) and of Talton et al.'s
//!    score-weighted kernel density estimate (with the best of several
//!    bandwidths chosen in hindsight, which favours it).
//! 4. *Interactive sampling* (the thesis's interface): GPR on models chosen
//!    as a user of the interface would see them, half from the current pdf
//!    and half from the complementary pdf, refitted after every batch.

use rand::SeedableRng;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use shapegen_core::genome::Chromosome;
use shapegen_core::graph::Graph;
use shapegen_core::ops::uncontrolled;
use shapegen_core::rng::stream;

use crate::DesignError;
use crate::divergence::{WeightedKde, jensen_shannon, weights_from_logs};
use crate::preference::{Factor, FactorOptions, Preference};
use crate::sampler::{
    LearnedPdf, Learner, RejectionSampler, StructureOptions, StructureReport, learn_pdf,
    parameter_learning,
};

/// A known score function (0–100) for one factor of a task.
pub type ScoreFn = Box<dyn Fn(&Graph, &Chromosome) -> f64 + Sync>;

/// A design task: a generator graph and the user it stands for.
pub struct Task {
    /// Short name (e.g. `S1`).
    pub name: String,
    /// What the user wants, in words.
    pub description: String,
    /// The generator (with the limits its models are drawn under).
    pub graph: Graph,
    /// One score function per factor.
    pub factors: Vec<ScoreFn>,
}

impl Task {
    /// `u*(m)` in `[0, 1]`.
    #[must_use]
    pub fn truth(&self, m: &Chromosome) -> f64 {
        self.factors
            .iter()
            .map(|f| (f(&self.graph, m) / 100.0).clamp(0.0, 1.0))
            .product()
    }
}

/// Sizes and seeds of an evaluation.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct EvalOptions {
    /// Models in the evaluation set `E`.
    pub eval_set: usize,
    /// Models drawn from the target to train the samplers.
    pub training: usize,
    /// Scored default samples the relevance (and kernel) for structure learning come from.
    pub fit_models: usize,
    /// The numbers of scored models on the learning curves.
    pub scored: Vec<usize>,
    /// Bandwidths tried for the kernel density estimate (features lie in about `[0, 1]`).
    pub kde_bandwidths: Vec<f64>,
    /// Factor fitting.
    pub factor: FactorOptions,
    /// Structure learning.
    pub structure: StructureOptions,
    /// Seed of every random stream.
    pub seed: u64,
}

impl Default for EvalOptions {
    fn default() -> Self {
        Self {
            eval_set: 5000,
            training: 2000,
            fit_models: 200,
            scored: vec![12, 24, 48, 96, 144, 192, 288, 384],
            kde_bandwidths: vec![0.05, 0.1, 0.2, 0.4, 0.8],
            factor: FactorOptions::default(),
            structure: StructureOptions::default(),
            seed: 1,
        }
    }
}

/// One point of a learning curve.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CurvePoint {
    /// Scored models.
    pub scored: usize,
    /// JS divergence of the GPR-learned pdf.
    pub gpr: f64,
    /// JS divergence of the weighted KDE (best bandwidth).
    pub kde: f64,
    /// That bandwidth.
    pub kde_bandwidth: f64,
}

/// What an evaluation measured for one task.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct EvalReport {
    /// The task's name.
    pub task: String,
    /// Its description.
    pub description: String,
    /// Fraction of the evaluation set with a positive target weight.
    pub positive_fraction: f64,
    /// JS divergence of the default pdf to the target.
    pub js_default: f64,
    /// JS divergence after parameter learning.
    pub js_parameter: f64,
    /// JS divergence after structure learning.
    pub js_structure: f64,
    /// Rejection sampling's acceptance rate while drawing the training set.
    pub acceptance: f64,
    /// What structure learning did.
    pub structure: StructureReport,
    /// Mixture components kept.
    pub components: usize,
    /// The learning curves.
    pub curve: Vec<CurvePoint>,
    /// Fewest scored models at which GPR's JS divergence is at most 0.01 (on the curve).
    pub gpr_reaches_001: Option<usize>,
    /// GPR with the thesis's interactive sampling: a first batch of 24 from
    /// the default pdf, then batches of 12 from the current pdf and 12 from
    /// the complementary pdf, refitted after each (scored models, JS).
    pub active: Vec<(usize, f64)>,
    /// Fewest scored models at which the interactive GPR reaches JS 0.01.
    pub active_reaches_001: Option<usize>,
    /// The same for the KDE.
    pub kde_reaches_001: Option<usize>,
}

fn draw(graph: &Graph, n: usize, seed: u64, path: u64) -> Result<Vec<Chromosome>, DesignError> {
    (0..n)
        .into_par_iter()
        .map(|i| {
            uncontrolled(graph, &mut stream(seed, &[path, i as u64])).map_err(DesignError::from)
        })
        .collect()
}

fn fit_preference(
    task: &Task,
    models: &[Chromosome],
    options: FactorOptions,
) -> Result<Preference, DesignError> {
    let factors = task
        .factors
        .iter()
        .enumerate()
        .map(|(i, f)| {
            let scores: Vec<f64> = models.iter().map(|m| f(&task.graph, m)).collect();
            Factor::fit(
                &format!("factor {i}"),
                &task.graph,
                models,
                &scores,
                options,
            )
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Preference { factors })
}

/// Runs the evaluation of one task (parallel over models with rayon; the
/// result does not depend on the thread count).
pub fn evaluate(task: &Task, options: &EvalOptions) -> Result<EvalReport, DesignError> {
    let g = &task.graph;
    let eval = draw(g, options.eval_set, options.seed, 1)?;
    let target: Vec<f64> = eval.par_iter().map(|m| task.truth(m)).collect();
    let positive_fraction =
        target.iter().filter(|&&t| t > 0.0).count() as f64 / target.len().max(1) as f64;
    let js = |q: &[f64]| jensen_shannon(&target, q).unwrap_or(1.0);
    let js_default = js(&vec![1.0; eval.len()]);

    // Training set from the target, by rejection with the true preference.
    let truth = |m: &Chromosome| task.truth(m);
    let mut rng = rand_pcg::Pcg64::seed_from_u64(options.seed ^ 0x5eed);
    let mut rejection = RejectionSampler::new(g, &truth, 2000, &mut rng)?;
    let training: Vec<Chromosome> = (0..options.training)
        .map(|_| rejection.sample(&mut rng))
        .collect::<Result<_, _>>()?;
    let acceptance = training.len() as f64 / rejection.proposals().max(1) as f64;

    // A learned sampler's pdf over the evaluation set: weights q(m)/p(m).
    let js_learned = |pdf: &LearnedPdf| -> Result<f64, DesignError> {
        let sampler = pdf.sampler(g)?;
        let logs: Vec<f64> = eval.par_iter().map(|m| sampler.log_ratio(m)).collect();
        Ok(js(&weights_from_logs(&logs)))
    };
    let js_parameter = js_learned(&parameter_learning(g, &training)?)?;

    // Relevance and kernel from a GPR on scored default samples.
    let fit_models = draw(g, options.fit_models, options.seed, 2)?;
    let preference = fit_preference(task, &fit_models, options.factor)?;
    let (pdf, structure) = learn_pdf(
        g,
        &training,
        &preference,
        Learner::Structure,
        options.structure,
    )?;
    let structure = structure.unwrap_or_default();
    let js_structure = js_learned(&pdf)?;

    // Learning curves on the same scored default samples.
    let max_scored = options.scored.iter().copied().max().unwrap_or(0);
    let scored = draw(g, max_scored, options.seed, 3)?;
    let truth_scored: Vec<f64> = scored.iter().map(|m| 100.0 * task.truth(m)).collect();
    let mut curve = Vec::new();
    for &n in &options.scored {
        let models = &scored[..n];
        let pref = fit_preference(task, models, options.factor)?;
        let q: Vec<f64> = eval.par_iter().map(|m| pref.value(g, m)).collect();
        let gpr = js(&q);
        // The KDE reads the first factor's features (the same map the GPR uses).
        let space = &pref.factors[0].space;
        let x: Vec<Vec<f64>> = models.iter().map(|m| space.features(g, m)).collect();
        let xe: Vec<Vec<f64>> = eval.par_iter().map(|m| space.features(g, m)).collect();
        let (kde, kde_bandwidth) = options
            .kde_bandwidths
            .iter()
            .map(|&h| {
                let k = WeightedKde::new(&x, &truth_scored[..n], h);
                let q: Vec<f64> = xe.par_iter().map(|v| k.weight(v)).collect();
                (js(&q), h)
            })
            .fold((f64::INFINITY, 0.0), |a, b| if b.0 < a.0 { b } else { a });
        curve.push(CurvePoint {
            scored: n,
            gpr,
            kde,
            kde_bandwidth,
        });
    }
    // Interactive sampling, as a user of the interface scores.
    let mut active = Vec::new();
    let mut models = draw(g, 24.min(max_scored), options.seed, 4)?;
    let mut round = 0u64;
    while models.len() <= max_scored {
        let pref = fit_preference(task, &models, options.factor)?;
        if options.scored.contains(&models.len()) {
            let q: Vec<f64> = eval.par_iter().map(|m| pref.value(g, m)).collect();
            active.push((models.len(), js(&q)));
        }
        if models.len() + 24 > max_scored {
            break;
        }
        round += 1;
        let mut rng = stream(options.seed, &[5, round]);
        for complementary in [false, true] {
            let u = |m: &Chromosome| {
                let v = pref.value(g, m);
                if complementary { 1.0 - v } else { v }
            };
            // A preference still 0 almost everywhere has no current pdf to
            // sample: the user is shown default samples instead.
            match RejectionSampler::new(g, &u, 200, &mut rng) {
                Ok(mut sampler) => {
                    for _ in 0..12 {
                        models.push(sampler.sample(&mut rng)?);
                    }
                }
                Err(DesignError::NoMass(_)) => {
                    for _ in 0..12 {
                        models.push(uncontrolled(g, &mut rng)?);
                    }
                }
                Err(e) => return Err(e),
            }
        }
    }
    let active_reaches_001 = active.iter().find(|p| p.1 <= 0.01).map(|p| p.0);
    let reaches = |f: fn(&CurvePoint) -> f64| curve.iter().find(|p| f(p) <= 0.01).map(|p| p.scored);
    Ok(EvalReport {
        task: task.name.clone(),
        description: task.description.clone(),
        positive_fraction,
        js_default,
        js_parameter,
        js_structure,
        acceptance,
        components: pdf.components.len(),
        structure,
        gpr_reaches_001: reaches(|p| p.gpr),
        kde_reaches_001: reaches(|p| p.kde),
        curve,
        active,
        active_reaches_001,
    })
}
