//! Checkpoint and resume: a run stopped after generation `k` and resumed from
//! its checkpoint (through JSON, as the CLI stores it) ends bit-identically to
//! the run that was never stopped, for every optimizer; checkpoints of
//! another run are refused.

use std::ops::ControlFlow;

use shapegen_core::demo::{BlocksTarget, blocks_graph};
use shapegen_core::optimize::{
    Checkpoint, HYBRID_PATIENCE_SHARE, Hybrid, HybridParams, IslandGa, IslandParams, Rjmcmc,
    RjmcmcParams, Run, SavedChallenge, SavedState, Smc, SmcParams, Tandem, TandemParams, Topology,
};
use shapegen_core::prelude::*;

const TOTAL: u64 = 14;
const STOP_AT: u64 = 5;

/// Runs `opt` for `TOTAL` generations in one go, and again stopped at
/// `STOP_AT` then resumed from the JSON checkpoint; both must agree exactly.
fn check<O: Optimizer>(opt: &O, seed: u64) {
    let graph = blocks_graph();
    let fitness = BlocksTarget {
        graph: &graph,
        blocks: 12,
    };
    check_with(opt, &graph, &fitness, seed);
}

/// [`check`] with another fitness.
fn check_with<O: Optimizer, F: Fitness>(opt: &O, graph: &Graph, fitness: &F, seed: u64) {
    let budget = Budget::generations(TOTAL);
    let mut whole_curve = Vec::new();
    let mut observer = |s: &GenerationStats<'_>| {
        whole_curve.push((s.generation, s.evaluations, s.best.to_bits()));
        ControlFlow::Continue(())
    };
    let whole = opt
        .run(graph, fitness, &budget, seed, &mut observer)
        .unwrap();

    let mut saved: Option<String> = None;
    let mut first_curve = Vec::new();
    let mut stop_early = |s: &GenerationStats<'_>| {
        first_curve.push((s.generation, s.evaluations, s.best.to_bits()));
        if s.generation == STOP_AT {
            saved = Some(serde_json::to_string(&s.checkpoint()).unwrap());
            return ControlFlow::Break(());
        }
        ControlFlow::Continue(())
    };
    let first = opt
        .run(graph, fitness, &budget, seed, &mut stop_early)
        .unwrap();
    assert_eq!(first.stop, StopReason::Observer);
    let checkpoint: Checkpoint = serde_json::from_str(&saved.unwrap()).unwrap();
    assert_eq!(checkpoint.generation, STOP_AT);

    let mut rest_curve = Vec::new();
    let mut observer = |s: &GenerationStats<'_>| {
        rest_curve.push((s.generation, s.evaluations, s.best.to_bits()));
        ControlFlow::Continue(())
    };
    let resumed = opt
        .resume(graph, fitness, &budget, &checkpoint, &mut observer)
        .unwrap();

    let name = opt.name();
    assert_eq!(resumed.best, whole.best, "{name}: best chromosome");
    assert_eq!(
        resumed.best_fitness.to_bits(),
        whole.best_fitness.to_bits(),
        "{name}"
    );
    assert_eq!(resumed.evaluations, whole.evaluations, "{name}");
    assert_eq!(resumed.generations, whole.generations, "{name}");
    assert_eq!(resumed.stop, whole.stop, "{name}");
    assert_eq!(resumed.population, whole.population, "{name}: population");
    // The two halves of the curve make the whole one (no generation twice).
    first_curve.extend(rest_curve);
    assert_eq!(first_curve, whole_curve, "{name}: curve");
}

#[test]
fn every_optimizer_resumes_bit_identically() {
    let init = InitLength::Around { l0: 12 };
    for seed in [3, 11] {
        check(
            &Ga::new(GaParams {
                population: 40,
                elites: 8,
                init,
                ..GaParams::paper_spaceship()
            }),
            seed,
        );
        check(
            &Ga::new(GaParams {
                population: 40,
                elites: 8,
                init,
                local_search: 6,
                ..GaParams::paper_spaceship()
            }),
            seed,
        );
        check(
            &Ga::new(GaParams {
                population: 40,
                elites: 8,
                init,
                adaptive_split: true,
                ..GaParams::paper_spaceship()
            }),
            seed,
        );
        check(&Smc::new(SmcParams::paper(60)), seed);
        check(&Smc::new(SmcParams::paper_sosmc(60)), seed);
        check(&Rjmcmc::new(RjmcmcParams::paper(20, init)), seed);
        check(&RandomSearch { batch: 30, init }, seed);
        let ga = GaParams {
            population: 12,
            elites: 3,
            init,
            ..GaParams::paper_spaceship()
        };
        for topology in [Topology::Ring, Topology::Random] {
            let params = IslandParams {
                ga,
                islands: 3,
                interval: 2,
                migrants: 2,
                topology,
            };
            check(&IslandGa::new(params), seed);
        }
        // An adaptive split in every method that runs the GA: islands (one
        // split per island), the hybrid's GA phase and the tandem.
        let adaptive = GaParams {
            adaptive_split: true,
            ..ga
        };
        check(
            &IslandGa::new(IslandParams {
                ga: adaptive,
                islands: 3,
                interval: 2,
                migrants: 2,
                topology: Topology::Ring,
            }),
            seed,
        );
        check(
            &Hybrid::new(HybridParams {
                ga: adaptive,
                rjmcmc: RjmcmcParams::paper(6, init),
                patience: 100,
                patience_share: HYBRID_PATIENCE_SHARE,
                first_phase: None,
            }),
            seed,
        );
        check(
            &Tandem::new(TandemParams::new(adaptive, RjmcmcParams::paper(6, init))),
            seed,
        );
        // A first phase of SOSMC, then the GA: a checkpoint while the
        // particles grow (toward 12 blocks) and one after the switch (a
        // fitness for small models, whose particles finish within a few
        // generations).
        let small = FnFitness(|c: &Chromosome| -(c.len() as f64));
        let graph = blocks_graph();
        let blocks = BlocksTarget {
            graph: &graph,
            blocks: 12,
        };
        let hybrid = |particles| {
            Hybrid::new(HybridParams {
                ga,
                rjmcmc: RjmcmcParams::paper(6, init),
                patience: 100,
                patience_share: HYBRID_PATIENCE_SHARE,
                first_phase: Some(SmcParams::paper_sosmc(particles)),
            })
        };
        check_with(&hybrid(4), &graph, &blocks, seed);
        assert!(particles_at_checkpoint(&hybrid(4), &graph, &blocks, seed));
        check_with(&hybrid(40), &graph, &small, seed);
        assert!(!particles_at_checkpoint(&hybrid(40), &graph, &small, seed));
        // The same first phase in the tandem.
        let tandem = |particles| {
            Tandem::new(TandemParams {
                first_phase: Some(SmcParams::paper_sosmc(particles)),
                ..TandemParams::new(ga, RjmcmcParams::paper(6, init))
            })
        };
        check_with(&tandem(4), &graph, &blocks, seed);
        assert!(particles_at_checkpoint(&tandem(4), &graph, &blocks, seed));
        check_with(&tandem(40), &graph, &small, seed);
        assert!(!particles_at_checkpoint(&tandem(40), &graph, &small, seed));
        // On blocks the GA keeps improving: switching late or never.
        for patience in [2, 8, 100] {
            let params = HybridParams {
                ga,
                rjmcmc: RjmcmcParams::paper(6, init),
                patience,
                patience_share: HYBRID_PATIENCE_SHARE,
                first_phase: None,
            };
            check(&Hybrid::new(params), seed);
        }
        // Challengers: a checkpoint while one is due, while one lives, and
        // on blocks (where the GA progresses, so they come late or never).
        let flat = FnFitness(|_: &Chromosome| 0.0);
        for patience in [1, 2, 5] {
            let params = TandemParams {
                challenge: patience,
                balance: patience == 2,
                ..TandemParams::new(ga, RjmcmcParams::paper(6, init))
            };
            check(&Tandem::new(params), seed);
            check_with(&Tandem::new(params), &graph, &flat, seed);
        }
        // The GA's, the islands' and the hybrid's challengers alike.
        for patience in [1, 2, 5] {
            let ga = GaParams {
                challenge: patience,
                ..ga
            };
            check(&Ga::new(ga), seed);
            check_with(&Ga::new(ga), &graph, &flat, seed);
            let islands = IslandGa::new(IslandParams {
                ga: GaParams {
                    population: 10,
                    elites: 2,
                    ..ga
                },
                islands: 3,
                interval: 2,
                migrants: 1,
                topology: Topology::Random,
            });
            check(&islands, seed);
            check_with(&islands, &graph, &flat, seed);
            let hybrid = Hybrid::new(HybridParams {
                ga,
                rjmcmc: RjmcmcParams::paper(6, init),
                patience: 8,
                patience_share: HYBRID_PATIENCE_SHARE,
                first_phase: None,
            });
            check(&hybrid, seed);
            check_with(&hybrid, &graph, &flat, seed);
        }
        let due = |patience| {
            let params = TandemParams {
                challenge: patience,
                ..TandemParams::new(ga, RjmcmcParams::paper(6, init))
            };
            challenge_at_checkpoint(&Tandem::new(params), &graph, &flat, seed)
        };
        // Patience 5 on the flat fitness: stalled at generation 5, its
        // challenger to be drawn at 6; patience 2: drawn at 3, living at 5.
        assert!(due(5).pending && due(5).challenger.is_none());
        assert!(due(2).challenger.is_some());
        for interval in [1, 3] {
            let params = TandemParams {
                interval,
                ..TandemParams::new(ga, RjmcmcParams::paper(6, init))
            };
            check(&Tandem::new(params), seed);
            // Balanced: the lean and the interval's measures are saved.
            check(
                &Tandem::new(TandemParams {
                    balance: true,
                    ..params
                }),
                seed,
            );
        }
    }
}

/// The state `opt` saves at `STOP_AT`.
fn state_at_checkpoint<O: Optimizer, F: Fitness>(
    opt: &O,
    graph: &Graph,
    fitness: &F,
    seed: u64,
) -> SavedState {
    let mut saved = None;
    let mut observer = |s: &GenerationStats<'_>| {
        if s.generation == STOP_AT {
            saved = Some(s.checkpoint().state);
        }
        ControlFlow::Continue(())
    };
    opt.run(
        graph,
        fitness,
        &Budget::generations(TOTAL),
        seed,
        &mut observer,
    )
    .unwrap();
    saved.expect("a run of TOTAL generations passes STOP_AT")
}

/// The challenge a tandem with challengers saves at `STOP_AT`.
fn challenge_at_checkpoint<F: Fitness>(
    opt: &Tandem,
    graph: &Graph,
    fitness: &F,
    seed: u64,
) -> SavedChallenge {
    match state_at_checkpoint(opt, graph, fitness, seed) {
        SavedState::Tandem {
            challenge: Some(challenge),
            ..
        } => challenge,
        other => panic!("not a tandem state with challengers: {other:?}"),
    }
}

/// Whether `opt` (a hybrid or a tandem) is still in its particles' phase
/// at `STOP_AT`.
fn particles_at_checkpoint<O: Optimizer, F: Fitness>(
    opt: &O,
    graph: &Graph,
    fitness: &F,
    seed: u64,
) -> bool {
    let first = match state_at_checkpoint(opt, graph, fitness, seed) {
        SavedState::Hybrid { state, .. } => state,
        SavedState::Tandem { ga, .. } => ga,
        other => panic!("not a hybrid or tandem state: {other:?}"),
    };
    matches!(*first, SavedState::Particles { .. })
}

#[test]
fn the_hybrid_resumes_on_either_side_of_its_switch() {
    // A two-valued fitness whose best is reached at once: the GA hands over
    // `patience` generations later, before the checkpoint (3) or after it (8).
    let graph = blocks_graph();
    let flat = FnFitness(|c: &Chromosome| 1.0 / (1.0 + c.len() as f64 % 2.0));
    let init = InitLength::Around { l0: 12 };
    for patience in [3, 8] {
        let params = HybridParams {
            ga: GaParams {
                population: 12,
                elites: 3,
                init,
                ..GaParams::paper_spaceship()
            },
            rjmcmc: RjmcmcParams::paper(5, init),
            patience,
            patience_share: HYBRID_PATIENCE_SHARE,
            first_phase: None,
        };
        let result = Hybrid::new(params)
            .run(
                &graph,
                &flat,
                &Budget::generations(TOTAL),
                4,
                &mut NoObserver,
            )
            .unwrap();
        assert_eq!(result.population.len(), 5, "switched to the 5 chains");
        check_with(&Hybrid::new(params), &graph, &flat, 4);
    }
}

#[test]
fn foreign_checkpoints_are_refused() {
    let graph = blocks_graph();
    let fitness = BlocksTarget {
        graph: &graph,
        blocks: 12,
    };
    let init = InitLength::Around { l0: 12 };
    let ga = Ga::new(GaParams {
        population: 30,
        elites: 5,
        init,
        ..GaParams::paper_spaceship()
    });
    let mut saved = None;
    let mut observer = |s: &GenerationStats<'_>| {
        saved = Some(s.checkpoint());
        ControlFlow::Continue(())
    };
    ga.run(&graph, &fitness, &Budget::generations(2), 7, &mut observer)
        .unwrap();
    let cp = saved.unwrap();
    let budget = Budget::generations(4);
    let refused = |r: Result<RunResult, OptimizeError>| match r {
        Err(OptimizeError::Checkpoint(why)) => why,
        other => panic!("expected a refusal, got {other:?}"),
    };
    // Another method.
    let why = refused(Rjmcmc::new(RjmcmcParams::paper(30, init)).resume(
        &graph,
        &fitness,
        &budget,
        &cp,
        &mut NoObserver,
    ));
    assert!(why.contains("`ga`"), "{why}");
    // Other parameters.
    let other = Ga::new(GaParams {
        elites: 6,
        ..ga.params
    });
    let why = refused(other.resume(&graph, &fitness, &budget, &cp, &mut NoObserver));
    assert!(why.contains("parameters"), "{why}");
    // Another seed.
    let why = refused(ga.run_from(Run {
        graph: &graph,
        fitness: &fitness,
        budget,
        seed: 8,
        start: Some(&cp),
        observer: &mut NoObserver,
    }));
    assert!(why.contains("seed"), "{why}");
    // Another graph: the stored chromosomes do not belong to it.
    let other_graph = GraphBuilder::new("other")
        .start("S")
        .node("S", |n| n.slot("a", "S", 0.5))
        .build()
        .unwrap();
    let why = refused(ga.resume(&other_graph, &fitness, &budget, &cp, &mut NoObserver));
    assert!(why.contains("chromosome"), "{why}");
    // A tampered chromosome fails validation instead of panicking.
    let mut bad = cp.clone();
    let SavedState::Population { individuals, .. } = &mut bad.state else {
        panic!("a GA checkpoint holds a population")
    };
    individuals[0].chromosome.words[1] ^= 0xffff;
    refused(ga.resume(&graph, &fitness, &budget, &bad, &mut NoObserver));
    // The untouched checkpoint resumes.
    let r = ga
        .resume(&graph, &fitness, &budget, &cp, &mut NoObserver)
        .unwrap();
    assert_eq!(r.generations, 4);
}
