//! The GA on a problem with a known optimum: it gets there, beats random
//! search at equal evaluations, and is deterministic whatever the thread count.

use shapegen_core::demo::{BlocksTarget, blocks_graph};
use shapegen_core::prelude::*;

fn ga() -> Ga {
    Ga::new(GaParams {
        population: 100,
        elites: 20,
        init: InitLength::Around { l0: 20 },
        ..GaParams::paper_spaceship()
    })
}

#[test]
fn ga_reaches_the_optimum_and_beats_random_search() {
    let graph = blocks_graph();
    for r in crate::common::reaches_the_blocks_optimum(|_| ga(), &[1, 2, 3]) {
        let blocks = r.best.genes(&graph).filter(|g| g.slot_count() == 2).count();
        assert_eq!(blocks, 20, "the optimum's structure");
    }
}

#[test]
fn same_seed_same_result_whatever_the_thread_count() {
    let (one, other) = crate::common::same_result_whatever_the_thread_count(&ga(), 40);
    // A different seed gives a different run.
    assert_ne!(one.best, other.best);
}

#[test]
fn target_fitness_and_observer_stop_the_run() {
    let graph = blocks_graph();
    let fitness = BlocksTarget {
        graph: &graph,
        blocks: 10,
    };
    let r = ga()
        .run(
            &graph,
            &fitness,
            &Budget::generations(10_000).and_target_fitness(0.5),
            1,
            &mut NoObserver,
        )
        .unwrap();
    assert_eq!(r.stop, StopReason::TargetFitness);
    assert!(r.best_fitness >= 0.5);
    let mut seen = 0;
    let mut stop_at_3 = |s: &GenerationStats<'_>| {
        seen += 1;
        if s.generation == 3 {
            std::ops::ControlFlow::Break(())
        } else {
            std::ops::ControlFlow::Continue(())
        }
    };
    let r = ga()
        .run(
            &graph,
            &fitness,
            &Budget::generations(100),
            1,
            &mut stop_at_3,
        )
        .unwrap();
    assert_eq!((r.stop, r.generations, seen), (StopReason::Observer, 3, 4));
}

/// The GA with local search on its elites: 10 of each generation's
/// children are one chain move from the 10 best distinct individuals.
fn ga_with_local_search() -> Ga {
    Ga::new(GaParams {
        local_search: 10,
        ..ga().params
    })
}

#[test]
fn local_search_reaches_the_optimum_and_beats_random_search() {
    crate::common::reaches_the_blocks_optimum(|_| ga_with_local_search(), &[1, 2, 3]);
}

#[test]
fn local_search_is_deterministic_whatever_the_thread_count() {
    let (one, other) =
        crate::common::same_result_whatever_the_thread_count(&ga_with_local_search(), 40);
    assert_ne!(one.best, other.best);
    // And it changes the run: local search is not a no-op.
    let (plain, _) = crate::common::same_result_whatever_the_thread_count(&ga(), 40);
    assert_ne!(one.population, plain.population);
}

#[test]
fn local_search_larger_than_the_children_is_refused() {
    let params = GaParams {
        local_search: 81,
        ..ga().params
    };
    let problems = params.problems();
    assert!(
        problems.iter().any(|p| p.contains("local_search (81)")),
        "{problems:?}"
    );
    assert!(
        GaParams {
            local_search: 80,
            ..ga().params
        }
        .problems()
        .is_empty()
    );
}

/// The GA with an adaptive mutation split.
fn adaptive_ga() -> Ga {
    Ga::new(GaParams {
        adaptive_split: true,
        ..ga().params
    })
}

#[test]
fn adaptive_split_reaches_the_optimum_and_beats_random_search() {
    crate::common::reaches_the_blocks_optimum(|_| adaptive_ga(), &[1, 2, 3]);
}

#[test]
fn adaptive_split_is_deterministic_whatever_the_thread_count() {
    let (one, other) = crate::common::same_result_whatever_the_thread_count(&adaptive_ga(), 40);
    assert_ne!(one.best, other.best);
    // And it changes the run.
    let (plain, _) = crate::common::same_result_whatever_the_thread_count(&ga(), 40);
    assert_ne!(one.population, plain.population);
}

fn ga_with_challengers(patience: u64) -> Ga {
    Ga::new(GaParams {
        challenge: patience,
        ..ga().params
    })
}

#[test]
fn challengers_reach_the_optimum_and_beat_random_search() {
    crate::common::reaches_the_blocks_optimum(ga_with_challengers, &[1, 2, 3]);
}

#[test]
fn challengers_are_deterministic_whatever_the_thread_count() {
    let (one, other) =
        crate::common::same_result_whatever_the_thread_count(&ga_with_challengers(1), 60);
    assert_ne!(one.best, other.best);
}

/// On a flat fitness a GA with challengers stalls, draws a challenger,
/// steps in turn with it and drops it when it stalls as long; the paper's
/// GA (patience 0) saves no challenge at all.
#[test]
fn a_stalled_ga_steps_in_turn_with_its_challenger() {
    use shapegen_core::optimize::SavedState;
    let graph = shapegen_core::demo::blocks_graph();
    let flat = FnFitness(|_: &Chromosome| 0.0);
    let lives = |ga: Ga| {
        let mut seen = Vec::new();
        let mut observer = |s: &GenerationStats<'_>| {
            let SavedState::Population { challenge, .. } = s.checkpoint().state else {
                panic!("a GA population");
            };
            seen.push(challenge.map(|c| c.challenger.is_some()));
            std::ops::ControlFlow::Continue(())
        };
        ga.run(&graph, &flat, &Budget::generations(14), 5, &mut observer)
            .unwrap();
        seen
    };
    // Generations 1–3 stall the GA; 4 draws the challenger, which steps in
    // turn with the GA until its own third stalled step (10) drops it.
    let seen = lives(ga_with_challengers(3));
    assert_eq!(seen[..4], [Some(false); 4]);
    assert_eq!(seen[4..10], [Some(true); 6]);
    assert_eq!(seen[10..13], [Some(false); 3]);
    assert!(lives(ga()).iter().all(Option::is_none));
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 32, ..Default::default() })]

    /// Every individual of GA runs with local search on random graphs is a
    /// valid chromosome, and a generation keeps the population's size.
    #[test]
    fn local_search_keeps_individuals_valid(
        graph in crate::common::graph(),
        seed in proptest::prelude::any::<u64>(),
        local_search in 1usize..=8,
        adaptive_split in proptest::prelude::any::<bool>(),
        challenge in 0u64..4,
    ) {
        let f = FnFitness(|c: &Chromosome| -(c.len() as f64 - 10.0).abs());
        let params = GaParams {
            population: 10,
            elites: 2,
            init: InitLength::Between { lo: 1, hi: 30 },
            local_search,
            adaptive_split,
            challenge,
            ..GaParams::paper_spaceship()
        };
        let mut check = |s: &GenerationStats<'_>| {
            s.best_chromosome.validate(&graph).unwrap();
            std::ops::ControlFlow::Continue(())
        };
        let r = Ga::new(params).run(&graph, &f, &Budget::generations(12), seed, &mut check).unwrap();
        // The GA's 10, and a living challenger's 10.
        proptest::prop_assert!([10, 20].contains(&r.population.len()), "{}", r.population.len());
        for i in &r.population {
            i.chromosome.validate(&graph).map_err(|e| proptest::test_runner::TestCaseError::fail(e.to_string()))?;
        }
    }
}
