//! The tandem (GA and RJMCMC side by side): both sides run and trade,
//! valid on random graphs, deterministic whatever the thread count,
//! reaching the blocks optimum and beating random search.

use proptest::prelude::*;
use shapegen_core::demo::blocks_graph;
use shapegen_core::optimize::{
    RjmcmcParams, SavedChallenge, SavedState, SmcParams, Tandem, TandemParams,
};
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
        let SavedState::Tandem { ga, chains, .. } = s.checkpoint().state else {
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

/// The tandem with SOSMC of 30 particles as its first phase.
fn tandem_after_sosmc(interval: u64) -> Tandem {
    Tandem::new(TandemParams {
        first_phase: Some(SmcParams::paper_sosmc(30)),
        ..tandem(interval).params
    })
}

#[test]
fn a_first_phase_grows_particles_while_the_chains_wait_then_seeds_the_ga() {
    let graph = blocks_graph();
    let fitness = shapegen_core::demo::BlocksTarget {
        graph: &graph,
        blocks: 12,
    };
    // Per reported generation: the GA side's kind and size, the chains' states.
    let mut seen = Vec::new();
    let mut observer = |s: &GenerationStats<'_>| {
        let SavedState::Tandem { ga, chains, .. } = s.checkpoint().state else {
            panic!("a tandem saves a tandem state");
        };
        let SavedState::Chains { chains, .. } = *chains else {
            panic!("chains");
        };
        let side = match *ga {
            SavedState::Particles { particles } => ("particles", particles.len()),
            SavedState::Population { individuals, .. } => ("ga", individuals.len()),
            _ => panic!("particles or a GA population"),
        };
        seen.push((side, chains));
        std::ops::ControlFlow::Continue(())
    };
    let r = tandem_after_sosmc(3)
        .run(&graph, &fitness, &Budget::generations(40), 5, &mut observer)
        .unwrap();
    let switch = seen.iter().position(|(side, _)| side.0 == "ga").unwrap();
    assert!(switch > 1, "the particles took {switch} generations");
    assert!(
        seen[..switch]
            .iter()
            .all(|(side, _)| *side == ("particles", 30))
    );
    assert!(seen[switch..].iter().all(|(side, _)| *side == ("ga", 60)));
    // The chains do not move while the particles grow.
    assert!(seen[..switch].iter().all(|(_, c)| *c == seen[0].1));
    assert_ne!(seen[switch + 2].1, seen[0].1, "the chains move afterwards");
    assert_eq!(r.population.len(), 72);
    for i in &r.population {
        i.chromosome.validate(&graph).unwrap();
    }
}

#[test]
fn a_first_phase_reaches_the_optimum_and_beats_random_search() {
    crate::common::reaches_the_blocks_optimum(|_| tandem_after_sosmc(10), &[1, 2, 3]);
}

#[test]
fn a_first_phase_is_deterministic_whatever_the_thread_count() {
    let (one, other) =
        crate::common::same_result_whatever_the_thread_count(&tandem_after_sosmc(3), 30);
    assert_ne!(one.population, other.population);
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

/// The tandem of [`tandem`] with the balance on.
fn balanced(interval: u64) -> Tandem {
    Tandem::new(TandemParams {
        balance: true,
        ..tandem(interval).params
    })
}

/// With the balance on, the lean moves with what each side finds, and a
/// generation evaluates only the sides that step in it: the GA's 50
/// children and the chains' 12 proposals when both step, one side's alone
/// otherwise.
#[test]
fn a_balanced_tandem_gives_the_evaluations_to_the_side_that_finds_more() {
    let graph = blocks_graph();
    let blocks = shapegen_core::demo::BlocksTarget {
        graph: &graph,
        blocks: 40,
    };
    let (mut leans, mut evaluations) = (Vec::new(), Vec::new());
    let mut observer = |s: &GenerationStats<'_>| {
        let SavedState::Tandem { balance, .. } = s.checkpoint().state else {
            panic!("a tandem saves a tandem state");
        };
        leans.push(balance.expect("a balanced tandem saves its balance").lean());
        evaluations.push(s.evaluations);
        std::ops::ControlFlow::Continue(())
    };
    balanced(2)
        .run(&graph, &blocks, &Budget::generations(200), 3, &mut observer)
        .unwrap();
    assert!(leans.iter().any(|&l| l != 0), "{leans:?}");
    // Generation g's evaluations, with the lean it started with (the
    // lean of generation g − 1's end; the exchange after it moves it).
    let made: Vec<u64> = evaluations.windows(2).map(|w| w[1] - w[0]).collect();
    for (g, (&lean, &n)) in (1u64..).zip(leans.iter().zip(&made)) {
        let ga = lean <= 0 || g.is_multiple_of(1 << lean);
        let chains = lean >= 0 || g.is_multiple_of(1 << -lean);
        let expected = 50 * u64::from(ga) + 12 * u64::from(chains);
        // (Local search adds none here; the GA's children are its 50.)
        assert_eq!(n, expected, "generation {g}, lean {lean}");
    }
    // Off, nothing is saved and every generation evaluates both.
    let mut saved = Vec::new();
    let mut observer = |s: &GenerationStats<'_>| {
        let SavedState::Tandem { balance, .. } = s.checkpoint().state else {
            panic!("a tandem saves a tandem state");
        };
        saved.push(balance);
        std::ops::ControlFlow::Continue(())
    };
    tandem(2)
        .run(&graph, &blocks, &Budget::generations(20), 3, &mut observer)
        .unwrap();
    assert!(saved.iter().all(Option::is_none));
}

#[test]
fn a_balanced_tandem_reaches_the_optimum_and_beats_random_search() {
    crate::common::reaches_the_blocks_optimum(|seed| balanced(2 + seed), &[1, 2, 3]);
}

#[test]
fn a_balanced_tandem_is_deterministic_whatever_the_thread_count() {
    let (one, other) = crate::common::same_result_whatever_the_thread_count(&balanced(2), 60);
    assert_ne!(one.population, other.population);
}

/// The tandem of [`tandem`] whose GA gets a challenger after `patience`
/// steps without progress.
fn challenged(patience: u64) -> Tandem {
    Tandem::new(TandemParams {
        challenge: patience,
        ..tandem(3).params
    })
}

/// The saved challenge of each generation's checkpoint, from generation 0.
fn challenges<F: Fitness>(
    opt: &Tandem,
    fitness: &F,
    generations: u64,
    seed: u64,
) -> Vec<SavedChallenge> {
    let graph = blocks_graph();
    let mut seen = Vec::new();
    let mut observer = |s: &GenerationStats<'_>| {
        let SavedState::Tandem { challenge, .. } = s.checkpoint().state else {
            panic!("a tandem saves a tandem state");
        };
        seen.push(challenge.expect("a tandem with challengers saves them"));
        std::ops::ControlFlow::Continue(())
    };
    opt.run(
        &graph,
        fitness,
        &Budget::generations(generations),
        seed,
        &mut observer,
    )
    .unwrap();
    seen
}

/// On a flat fitness nothing progresses: the GA stalls after its patience,
/// a challenger's first population is drawn at the next step, the two then
/// step in turn, and the challenger, never better, is dropped when it has
/// stalled as long; the GA gets its whole patience again.
#[test]
fn a_stalled_ga_gets_a_challenger_that_is_dropped_when_it_stalls_below_it() {
    let flat = FnFitness(|_: &Chromosome| 0.0);
    let seen = challenges(&challenged(3), &flat, 14, 5);
    let at = |g: usize| &seen[g];
    // Generations 1–3 stall the GA; the third asks for a challenger.
    assert!((0..3).all(|g| !at(g).pending && at(g).challenger.is_none()));
    assert!(at(3).pending && at(3).spawned == 1 && at(3).challenger.is_none());
    // Generation 4 draws its first population (the GA's 60, from island 1),
    // then the GA (5) and the challenger (6) step in turn.
    for g in 4..=9 {
        let c = at(g)
            .challenger
            .as_ref()
            .unwrap_or_else(|| panic!("a challenger after {g}"));
        assert_eq!(c.island, 1);
        let SavedState::Population { individuals, .. } = c.population.as_ref() else {
            panic!("a GA population");
        };
        assert_eq!(individuals.len(), 60);
        assert!(!at(g).pending);
        // After the GA's step the challenger takes the next one.
        assert_eq!(at(g).turn, g % 2 == 1, "generation {g}");
    }
    // Its third step without progress (generation 10) drops it; the GA
    // (still island 0) stalls again after 3 more steps.
    assert!((10..=12).all(|g| at(g).challenger.is_none() && !at(g).pending));
    assert!(at(13).pending && at(13).spawned == 2);
    assert!(at(14).challenger.as_ref().is_some_and(|c| c.island == 2));
    assert!(seen.iter().all(|c| c.island == Some(0)));
}

/// On a fitness without structure (a stable hash of the chromosome) a fresh
/// population is as good as an old one, so challengers overtake the GA
/// and take its place (its streams become the challenger's).
#[test]
fn a_challenger_that_overtakes_the_ga_takes_its_place() {
    use shapegen_core::optimize::{FNV1A_START, fnv1a};
    let noise = FnFitness(|c: &Chromosome| {
        let bytes: Vec<u8> = c.words().iter().flat_map(|w| w.to_le_bytes()).collect();
        (fnv1a(FNV1A_START, &bytes) >> 11) as f64 / (1u64 << 53) as f64
    });
    for seed in [1, 2, 3] {
        let seen = challenges(&challenged(2), &noise, 150, seed);
        let islands: std::collections::BTreeSet<u64> =
            seen.iter().filter_map(|c| c.island).collect();
        assert!(
            islands.len() > 1,
            "seed {seed}: the GA kept island 0's streams"
        );
        // The GA only ever takes the place of a challenger that was started.
        let last = seen.last().unwrap();
        assert!(islands.iter().all(|&i| i <= last.spawned));
    }
}

#[test]
fn a_tandem_with_challengers_reaches_the_optimum_and_beats_random_search() {
    crate::common::reaches_the_blocks_optimum(|seed| challenged(5 * seed), &[1, 2, 3]);
}

#[test]
fn a_tandem_with_challengers_is_deterministic_whatever_the_thread_count() {
    let (one, other) = crate::common::same_result_whatever_the_thread_count(&challenged(2), 60);
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
    fn models_are_valid_chromosomes(graph in crate::common::graph(), seed in any::<u64>(), interval in 1u64..4, local_search in 0usize..3, adaptive_split in any::<bool>(), first in 0usize..3, balance in any::<bool>(), challenge in 0u64..4) {
        let f = FnFitness(|c: &Chromosome| -(c.len() as f64 - 10.0).abs());
        let init = InitLength::Between { lo: 1, hi: 30 };
        let params = TandemParams {
            interval,
            migrants: 2,
            first_phase: [None, Some(SmcParams::paper(6)), Some(SmcParams::paper_sosmc(6))][first],
            balance,
            challenge,
            ..TandemParams::new(
                GaParams { population: 10, elites: 2, init, local_search, adaptive_split, ..GaParams::paper_spaceship() },
                RjmcmcParams::paper(4, init),
            )
        };
        let mut check = |s: &GenerationStats<'_>| {
            if s.best_so_far.is_finite() {
                s.best_chromosome.validate(&graph).unwrap();
            }
            std::ops::ControlFlow::Continue(())
        };
        let r = Tandem::new(params).run(&graph, &f, &Budget::generations(12), seed, &mut check).unwrap();
        // The GA's 10 (and a challenger's 10) and the chains' 4; the first
        // phase's 6 particles instead of the GA's 10 if they are still growing.
        prop_assert!(
            [14, 24].contains(&r.population.len()) || (first > 0 && r.population.len() == 10),
            "{} models", r.population.len()
        );
        let min_len = graph.limits().min_len as usize;
        for i in &r.population {
            if i.fitness.is_finite() || i.chromosome.len() >= min_len {
                i.chromosome.validate(&graph).map_err(|e| TestCaseError::fail(e.to_string()))?;
            }
        }
    }
}
