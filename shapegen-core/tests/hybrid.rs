//! The hybrid (GA, then RJMCMC from the GA's best): switches when the GA
//! stalls, valid on random graphs, deterministic whatever the thread count,
//! reaching the blocks optimum and beating random search.

use proptest::prelude::*;
use shapegen_core::demo::blocks_graph;
use shapegen_core::optimize::{HYBRID_PATIENCE_SHARE, Hybrid, HybridParams, RjmcmcParams};
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

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, ..ProptestConfig::default() })]

    /// Every model of hybrid runs on random graphs, in either phase, is a valid chromosome.
    #[test]
    fn models_are_valid_chromosomes(graph in crate::common::graph(), seed in any::<u64>(), patience in 1u64..6) {
        let f = FnFitness(|c: &Chromosome| -(c.len() as f64 - 10.0).abs());
        let init = InitLength::Between { lo: 1, hi: 30 };
        let params = HybridParams {
            ga: GaParams { population: 10, elites: 2, init, ..GaParams::paper_spaceship() },
            rjmcmc: RjmcmcParams::paper(4, init),
            patience,
            patience_share: HYBRID_PATIENCE_SHARE,
        };
        let mut check = |s: &GenerationStats<'_>| {
            s.best_chromosome.validate(&graph).unwrap();
            std::ops::ControlFlow::Continue(())
        };
        let r = Hybrid::new(params).run(&graph, &f, &Budget::generations(15), seed, &mut check).unwrap();
        for i in &r.population {
            i.chromosome.validate(&graph).map_err(|e| TestCaseError::fail(e.to_string()))?;
        }
    }
}
