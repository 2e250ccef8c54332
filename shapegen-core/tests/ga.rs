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
