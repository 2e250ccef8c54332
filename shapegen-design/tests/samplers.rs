//! Property tests over random generator graphs: every learned sampler only
//! ever produces models the original graph can derive, learned pdfs survive
//! a file round trip, split graphs move models both ways, and EM never
//! lowers the training log-likelihood.

#[path = "../../shapegen-core/tests/common.rs"]
mod common;

use proptest::prelude::*;
use shapegen_core::prelude::*;
use shapegen_core::rng::stream;
use shapegen_design::{
    LearnedPdf, RejectionSampler, SplitGraph, StructureOptions, parameter_learning,
    structure_learning,
};

/// Models of `g` by uncontrolled generation, or `None` if it cannot reach `L_min`.
fn draw(g: &Graph, n: usize, seed: u64) -> Option<Vec<Chromosome>> {
    (0..n as u64)
        .map(|i| uncontrolled(g, &mut stream(seed, &[i])).ok())
        .collect()
}

/// A preference that depends on structure: even gene counts are preferred.
fn preference(m: &Chromosome) -> f64 {
    if m.len().is_multiple_of(2) { 1.0 } else { 0.2 }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn learned_samplers_only_make_models_of_the_original(g in common::graph(), seed in 0u64..1000) {
        let Some(_) = draw(&g, 2, seed) else { return Ok(()) };
        let mut rng = stream(seed, &[99]);
        let mut rejection = RejectionSampler::new(&g, &preference, 50, &mut rng).unwrap();
        let training: Vec<Chromosome> = (0..60).map(|_| rejection.sample(&mut rng).unwrap()).collect();
        for m in &training {
            m.validate(&g).unwrap();
        }
        // Split every node, twice: the deepest annotation the learners use.
        let all: Vec<u16> = (0..g.node_count() as u16).collect();
        let split = SplitGraph::identity(&g).split(&all).unwrap();
        let split = split.split(&(0..split.graph().node_count() as u16).collect::<Vec<_>>()).unwrap();
        for m in &training {
            let s = split.to_split(&g, m).unwrap();
            prop_assert_eq!(&split.to_base(&g, &s).unwrap(), m);
        }
        let distance = |i: usize, j: usize| (training[i].len() as f64 - training[j].len() as f64).abs();
        let options = StructureOptions { max_components: 4, em_iterations: 20, split_rounds: 2, ..StructureOptions::default() };
        let (structure, report) = structure_learning(&g, &training, &all, &distance, options).unwrap();
        // EM never lowers the training log-likelihood.
        for w in report.log_likelihood.windows(2) {
            prop_assert!(w[1] >= w[0] - 1e-7 * w[0].abs().max(1.0), "{:?}", report.log_likelihood);
        }
        for pdf in [parameter_learning(&g, &training).unwrap(), structure] {
            let sampler = pdf.sampler(&g).unwrap();
            for i in 0..20u64 {
                let m = sampler.sample(&mut stream(seed, &[7, i])).unwrap();
                m.validate(&g).unwrap();
            }
            for m in &training {
                prop_assert!(sampler.log_ratio(m).is_finite());
            }
            // A file round trip gives the same sampler.
            let text = serde_json::to_string(&pdf).unwrap();
            let back: LearnedPdf = serde_json::from_str(&text).unwrap();
            let again = back.sampler(&g).unwrap();
            for i in 0..5u64 {
                prop_assert_eq!(
                    sampler.sample(&mut stream(seed, &[8, i])).unwrap(),
                    again.sample(&mut stream(seed, &[8, i])).unwrap()
                );
            }
            // The optimizers' prior graph is the same generator, and grows models of it.
            if pdf.marginal.is_some() {
                let prior = pdf.prior_graph(&g).unwrap();
                prop_assert_eq!(prior.fingerprint(), g.fingerprint());
                for i in 0..5u64 {
                    if let Ok(m) = uncontrolled(&prior, &mut stream(seed, &[9, i])) {
                        m.validate(&g).unwrap();
                    }
                }
            }
        }
    }
}

/// A learned pdf is refused by another generator and when edited to leave
/// the original's support.
#[test]
fn foreign_and_tampered_pdfs_are_refused() {
    let g = shapegen_design::toy::graph();
    let training = draw(&g, 50, 1).unwrap();
    let pdf = parameter_learning(&g, &training).unwrap();
    let other = GraphBuilder::new("other")
        .start("A")
        .node("A", |n| n)
        .build()
        .unwrap();
    assert!(matches!(
        pdf.sampler(&other),
        Err(shapegen_design::DesignError::ForeignGraph { .. })
    ));
    // A float parameter's range widened: not the original's support.
    let mut bad = pdf.clone();
    let node = &mut bad.components[0].graph.nodes.to_mut()[1];
    node.params.to_mut()[0].dist = ParamDist::F32(Dist::uniform(0.0, 9.0));
    let e = bad.sampler(&g).unwrap_err().to_string();
    assert!(e.contains("support"), "{e}");
}
