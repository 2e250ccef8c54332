//! On the blocks problem (optimum 1), at equal evaluations: SMC, SOSMC and
//! RJMCMC each beat random search, and the GA beats all of them, on several seeds.

use shapegen_core::demo::{BlocksTarget, blocks_graph};
use shapegen_core::optimize::{Rjmcmc, RjmcmcParams, Smc, SmcParams};
use shapegen_core::prelude::*;

#[test]
fn ga_beats_the_baselines_which_beat_random_search() {
    let graph = blocks_graph();
    let fitness = BlocksTarget {
        graph: &graph,
        blocks: 20,
    };
    let budget = Budget::evaluations(20_000);
    let init = InitLength::Around { l0: 20 };
    for seed in [1, 2, 3] {
        let best = |r: Result<RunResult, OptimizeError>| r.unwrap().best_fitness;
        let ga = best(
            Ga::new(GaParams {
                population: 100,
                elites: 20,
                init,
                ..GaParams::paper_spaceship()
            })
            .run(&graph, &fitness, &budget, seed, &mut NoObserver),
        );
        let smc = best(Smc::new(SmcParams::paper(500)).run(
            &graph,
            &fitness,
            &budget,
            seed,
            &mut NoObserver,
        ));
        let sosmc = best(Smc::new(SmcParams::paper_sosmc(500)).run(
            &graph,
            &fitness,
            &budget,
            seed,
            &mut NoObserver,
        ));
        let rj = best(Rjmcmc::new(RjmcmcParams::paper(70, init)).run(
            &graph,
            &fitness,
            &budget,
            seed,
            &mut NoObserver,
        ));
        let random = best(RandomSearch { batch: 100, init }.run(
            &graph,
            &fitness,
            &budget,
            seed,
            &mut NoObserver,
        ));
        eprintln!(
            "seed {seed}: ga {ga:.3} smc {smc:.3} sosmc {sosmc:.3} rjmcmc {rj:.3} random {random:.3}"
        );
        for (name, b) in [("smc", smc), ("sosmc", sosmc), ("rjmcmc", rj)] {
            assert!(
                b > random,
                "seed {seed}: {name} {b} does not beat random search {random}"
            );
            assert!(
                ga > b + 0.05,
                "seed {seed}: the GA {ga} does not clearly beat {name} {b}"
            );
        }
    }
}
