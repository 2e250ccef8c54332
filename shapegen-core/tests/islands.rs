//! The island GA: valid on random graphs, deterministic whatever the thread
//! count, reaching the blocks optimum and beating random search.

use proptest::prelude::*;
use shapegen_core::optimize::{IslandGa, IslandParams, Topology};
use shapegen_core::prelude::*;

fn islands(topology: Topology) -> IslandGa {
    IslandGa::new(IslandParams {
        ga: GaParams {
            population: 25,
            elites: 5,
            init: InitLength::Around { l0: 20 },
            ..GaParams::paper_spaceship()
        },
        islands: 4,
        interval: 5,
        migrants: 2,
        topology,
    })
}

#[test]
fn islands_reach_the_optimum_and_beat_random_search() {
    let topology = |seed| {
        if seed == 2 {
            Topology::Random
        } else {
            Topology::Ring
        }
    };
    for r in crate::common::reaches_the_blocks_optimum(|seed| islands(topology(seed)), &[1, 2, 3]) {
        // The final population is every island's, best first.
        assert_eq!(r.population.len(), 100);
        assert_eq!(r.population[0].fitness.to_bits(), r.best_fitness.to_bits());
    }
}

#[test]
fn same_seed_same_result_whatever_the_thread_count() {
    for topology in [Topology::Ring, Topology::Random] {
        let (one, other) =
            crate::common::same_result_whatever_the_thread_count(&islands(topology), 30);
        assert_ne!(one.population, other.population);
    }
}

fn with_challengers(patience: u64) -> IslandGa {
    let mut i = islands(Topology::Ring);
    i.params.ga.challenge = patience;
    i
}

#[test]
fn islands_with_challengers_reach_the_optimum_and_are_deterministic() {
    crate::common::reaches_the_blocks_optimum(with_challengers, &[1, 2, 3]);
    let (one, other) =
        crate::common::same_result_whatever_the_thread_count(&with_challengers(1), 40);
    assert_ne!(one.population, other.population);
}

/// Each island's challengers draw from streams of their own: island `i`'s
/// `k`-th from island `k · 4 + i`'s, never another island's or another
/// challenger's.
#[test]
fn every_islands_challengers_draw_from_streams_of_their_own() {
    use shapegen_core::optimize::SavedState;
    let graph = shapegen_core::demo::blocks_graph();
    let flat = FnFitness(|_: &Chromosome| 0.0);
    let mut seen = Vec::new();
    let mut observer = |s: &GenerationStats<'_>| {
        if let SavedState::Islands { challenges, .. } = s.checkpoint().state {
            seen.push(challenges);
        }
        std::ops::ControlFlow::Continue(())
    };
    with_challengers(2)
        .run(&graph, &flat, &Budget::generations(30), 3, &mut observer)
        .unwrap();
    let mut streams = std::collections::BTreeSet::new();
    for challenges in &seen {
        assert_eq!(challenges.len(), 4);
        for (i, c) in challenges.iter().enumerate() {
            assert_eq!(c.island, Some(i as u64), "a flat fitness never promotes");
            if let Some(ch) = &c.challenger {
                assert_eq!(ch.island, c.spawned * 4 + i as u64);
                streams.insert(ch.island);
            }
        }
    }
    // Every island started several.
    assert!(streams.len() >= 8, "{streams:?}");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, ..ProptestConfig::default() })]

    /// Every individual of island runs on random graphs is a valid chromosome.
    #[test]
    fn individuals_are_valid_chromosomes(graph in crate::common::graph(), seed in any::<u64>(), random in any::<bool>(), challenge in 0u64..4) {
        let f = FnFitness(|c: &Chromosome| -(c.len() as f64 - 10.0).abs());
        let params = IslandParams {
            ga: GaParams { population: 8, elites: 2, init: InitLength::Between { lo: 1, hi: 30 }, challenge, ..GaParams::paper_spaceship() },
            islands: 3,
            interval: 2,
            migrants: 1,
            topology: if random { Topology::Random } else { Topology::Ring },
        };
        let r = IslandGa::new(params).run(&graph, &f, &Budget::generations(8), seed, &mut NoObserver).unwrap();
        // Three islands of 8, and 8 for each living challenger.
        prop_assert!(r.population.len() >= 24 && r.population.len() <= 48 && r.population.len() % 8 == 0, "{}", r.population.len());
        if challenge == 0 {
            prop_assert_eq!(r.population.len(), 24);
        }
        for i in &r.population {
            i.chromosome.validate(&graph).map_err(|e| TestCaseError::fail(e.to_string()))?;
        }
    }
}
