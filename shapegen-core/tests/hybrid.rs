//! The hybrid (GA, then RJMCMC from the GA's best): switches when the GA
//! stalls, valid on random graphs, deterministic whatever the thread count,
//! reaching the blocks optimum and beating random search.

use proptest::prelude::*;
use shapegen_core::demo::blocks_graph;
use shapegen_core::optimize::{
    HYBRID_PATIENCE_SHARE, Hybrid, HybridParams, RjmcmcParams, SavedState, SmcParams,
};
use shapegen_core::prelude::*;

fn hybrid(patience: u64) -> Hybrid {
    let init = InitLength::Around { l0: 20 };
    Hybrid::new(HybridParams {
        ga: GaParams {
            population: 60,
            elites: 10,
            init,
            ..GaParams::paper_spaceship()
        },
        rjmcmc: RjmcmcParams::paper(12, init),
        patience,
        patience_share: HYBRID_PATIENCE_SHARE,
        first_phase: None,
    })
}

#[test]
fn a_stalled_ga_hands_over_to_chains_from_its_best() {
    let graph = blocks_graph();
    // A constant fitness: the GA never improves, so it switches after `patience`.
    let flat = FnFitness(|_: &Chromosome| 1.0);
    let mut sizes = Vec::new();
    let mut observer = |s: &GenerationStats<'_>| {
        sizes.push(s.generation);
        std::ops::ControlFlow::Continue(())
    };
    let r = hybrid(5)
        .run(&graph, &flat, &Budget::generations(12), 3, &mut observer)
        .unwrap();
    // 12 RJMCMC chains after the switch, not the GA's 60.
    assert_eq!(r.population.len(), 12);
    let r = hybrid(50)
        .run(&graph, &flat, &Budget::generations(12), 3, &mut NoObserver)
        .unwrap();
    assert_eq!(r.population.len(), 60);
    assert_eq!(sizes.len(), 13);
}

/// The hybrid with SOSMC of 30 particles as its first phase.
fn hybrid_after_sosmc(patience: u64) -> Hybrid {
    Hybrid::new(HybridParams {
        first_phase: Some(SmcParams::paper_sosmc(30)),
        ..hybrid(patience).params
    })
}

#[test]
fn a_first_phase_hands_the_ga_its_best_complete_models() {
    let graph = blocks_graph();
    let fitness = shapegen_core::demo::BlocksTarget {
        graph: &graph,
        blocks: 12,
    };
    // Per reported generation: whether the particles were still growing,
    // and the best so far.
    let mut seen: Vec<(bool, f64)> = Vec::new();
    let mut observer = |s: &GenerationStats<'_>| {
        let SavedState::Hybrid { state, .. } = s.checkpoint().state else {
            panic!("a hybrid saves a hybrid state");
        };
        seen.push((
            matches!(*state, SavedState::Particles { .. }),
            s.best_so_far,
        ));
        std::ops::ControlFlow::Continue(())
    };
    let r = hybrid_after_sosmc(1000)
        .run(&graph, &fitness, &Budget::generations(40), 5, &mut observer)
        .unwrap();
    assert_eq!(r.population.len(), 60, "it ends in the GA's population");
    // The particles' phase first, then the GA's; once.
    let switch = seen.iter().position(|&(smc, _)| !smc).unwrap();
    assert!(switch > 1, "the particles took {switch} generations");
    assert!(seen[..switch].iter().all(|&(smc, _)| smc), "{seen:?}");
    assert!(seen[switch..].iter().all(|&(smc, _)| !smc), "{seen:?}");
    // Generation 0 (root genes only) is not reported, as in SMC.
    assert_eq!(seen.len(), 40, "{seen:?}");
    for i in &r.population {
        i.chromosome.validate(&graph).unwrap();
    }
}

#[test]
fn a_first_phase_reaches_the_optimum_and_beats_random_search() {
    crate::common::reaches_the_blocks_optimum(|_| hybrid_after_sosmc(100), &[1, 2, 3]);
}

#[test]
fn a_first_phase_is_deterministic_whatever_the_thread_count() {
    let (one, other) =
        crate::common::same_result_whatever_the_thread_count(&hybrid_after_sosmc(3), 40);
    assert_ne!(one.population, other.population);
    let (plain, _) = crate::common::same_result_whatever_the_thread_count(&hybrid(3), 40);
    assert_ne!(one.population, plain.population);
}

#[test]
fn the_hybrid_reaches_the_optimum_and_beats_random_search() {
    // Switching early, late, and never.
    let patience = |seed| [5, 20, 1000][seed as usize - 1];
    crate::common::reaches_the_blocks_optimum(|seed| hybrid(patience(seed)), &[1, 2, 3]);
}

#[test]
fn same_seed_same_result_whatever_the_thread_count() {
    let (one, other) = crate::common::same_result_whatever_the_thread_count(&hybrid(3), 40);
    assert_ne!(one.population, other.population);
}

#[test]
fn a_hybrid_with_challengers_reaches_the_optimum_and_is_deterministic() {
    let challenged = |patience| {
        let mut h = hybrid(100);
        h.params.ga.challenge = patience;
        h
    };
    crate::common::reaches_the_blocks_optimum(challenged, &[1, 2, 3]);
    let (one, other) = crate::common::same_result_whatever_the_thread_count(&challenged(1), 60);
    assert_ne!(one.best, other.best);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, ..ProptestConfig::default() })]

    /// Every model of hybrid runs on random graphs, in either phase, is a valid chromosome.
    #[test]
    fn models_are_valid_chromosomes(graph in crate::common::graph(), seed in any::<u64>(), patience in 1u64..6, first in 0usize..3, challenge in 0u64..4) {
        let f = FnFitness(|c: &Chromosome| -(c.len() as f64 - 10.0).abs());
        let init = InitLength::Between { lo: 1, hi: 30 };
        let params = HybridParams {
            ga: GaParams { population: 10, elites: 2, init, challenge, ..GaParams::paper_spaceship() },
            rjmcmc: RjmcmcParams::paper(4, init),
            patience,
            patience_share: HYBRID_PATIENCE_SHARE,
            first_phase: [None, Some(SmcParams::paper(6)), Some(SmcParams::paper_sosmc(6))][first],
        };
        let mut check = |s: &GenerationStats<'_>| {
            // While SMC particles grow there may be no valid model to report yet.
            if s.best_so_far.is_finite() {
                s.best_chromosome.validate(&graph).unwrap();
            }
            std::ops::ControlFlow::Continue(())
        };
        let r = Hybrid::new(params).run(&graph, &f, &Budget::generations(15), seed, &mut check).unwrap();
        let min_len = graph.limits().min_len as usize;
        for i in &r.population {
            // Particles still growing at the end may be shorter than L_min;
            // every model of the GA's and the chains' phases is whole.
            if i.fitness.is_finite() || i.chromosome.len() >= min_len {
                i.chromosome.validate(&graph).map_err(|e| TestCaseError::fail(e.to_string()))?;
            }
        }
    }
}
