//! The tandem (GA and RJMCMC side by side): both sides run and trade,
//! valid on random graphs, deterministic whatever the thread count,
//! reaching the blocks optimum and beating random search.

use proptest::prelude::*;
use shapegen_core::demo::blocks_graph;
use shapegen_core::optimize::{RjmcmcParams, SavedState, Tandem, TandemParams};
use shapegen_core::prelude::*;

fn tandem(interval: u64) -> Tandem {
    let init = InitLength::Around { l0: 20 };
    Tandem::new(TandemParams {
        interval,
        ..TandemParams::new(
            GaParams {
                population: 60,
                elites: 10,
                init,
                ..GaParams::paper_spaceship()
            },
            RjmcmcParams::paper(12, init),
        )
    })
}

#[test]
fn both_sides_run_and_report_together() {
    let graph = blocks_graph();
    let f = FnFitness(|c: &Chromosome| -(c.len() as f64 - 30.0).abs());
    let mut sizes = Vec::new();
    let mut observer = |s: &GenerationStats<'_>| {
        let SavedState::Tandem { ga, chains } = s.checkpoint().state else {
            panic!("a tandem saves a tandem state");
        };
        let (SavedState::Population { individuals, .. }, SavedState::Chains { chains, .. }) =
            (*ga, *chains)
        else {
            panic!("a GA population and chains");
        };
        sizes.push((individuals.len(), chains.len()));
        std::ops::ControlFlow::Continue(())
    };
    let r = tandem(3)
        .run(&graph, &f, &Budget::generations(10), 5, &mut observer)
        .unwrap();
    // The GA's 60 and the chains' 12, every generation; the result holds
    // both, best first.
    assert_eq!(sizes.len(), 11);
    assert!(sizes.iter().all(|&n| n == (60, 12)), "{sizes:?}");
    assert_eq!(r.population.len(), 72);
    assert!(
        r.population
            .windows(2)
            .all(|w| w[0].fitness >= w[1].fitness)
    );
    // Each generation evaluates the GA's children and the chains' proposals.
    assert!(r.evaluations > 72 + 10 * 12, "{}", r.evaluations);
}

#[test]
fn the_tandem_reaches_the_optimum_and_beats_random_search() {
    // Trading often, rarely, and in effect never.
    let interval = |seed| [2, 10, 1000][seed as usize - 1];
    crate::common::reaches_the_blocks_optimum(|seed| tandem(interval(seed)), &[1, 2, 3]);
}

#[test]
fn same_seed_same_result_whatever_the_thread_count() {
    let (one, other) = crate::common::same_result_whatever_the_thread_count(&tandem(3), 30);
    assert_ne!(one.population, other.population);
}

#[test]
fn exchange_settings_are_checked() {
    let p = tandem(0).params;
    assert!(p.problems().iter().any(|e| e.contains("interval")));
    let p = TandemParams {
        migrants: 13,
        ..tandem(5).params
    };
    assert!(
        p.problems().iter().any(|e| e.contains("chains (12)")),
        "{:?}",
        p.problems()
    );
    assert!(tandem(5).params.problems().is_empty());
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, ..ProptestConfig::default() })]

    /// Every model of tandem runs on random graphs is a valid chromosome.
    #[test]
    fn models_are_valid_chromosomes(graph in crate::common::graph(), seed in any::<u64>(), interval in 1u64..4, local_search in 0usize..3, adaptive_split in any::<bool>()) {
        let f = FnFitness(|c: &Chromosome| -(c.len() as f64 - 10.0).abs());
        let init = InitLength::Between { lo: 1, hi: 30 };
        let params = TandemParams {
            interval,
            migrants: 2,
            ..TandemParams::new(
                GaParams { population: 10, elites: 2, init, local_search, adaptive_split, ..GaParams::paper_spaceship() },
                RjmcmcParams::paper(4, init),
            )
        };
        let mut check = |s: &GenerationStats<'_>| {
            s.best_chromosome.validate(&graph).unwrap();
            std::ops::ControlFlow::Continue(())
        };
        let r = Tandem::new(params).run(&graph, &f, &Budget::generations(12), seed, &mut check).unwrap();
        prop_assert_eq!(r.population.len(), 14);
        for i in &r.population {
            i.chromosome.validate(&graph).map_err(|e| TestCaseError::fail(e.to_string()))?;
        }
    }
}
