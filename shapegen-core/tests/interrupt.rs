//! An interrupt flag set in the middle of a generation (Ctrl-C in the CLI)
//! stops the run at once: the unfinished generation is dropped, and the
//! result is the run's state after the last complete generation, exactly
//! as if the run had been budgeted to end there.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

use shapegen_core::demo::{BlocksTarget, blocks_graph};
use shapegen_core::genome::Chromosome;
use shapegen_core::optimize::{Interruptible, Rjmcmc, RjmcmcParams};
use shapegen_core::prelude::*;

/// The blocks fitness that sets `flag` at its `at`-th evaluation.
struct SetsFlag<'g> {
    inner: BlocksTarget<'g>,
    calls: AtomicU64,
    at: u64,
    flag: Arc<AtomicBool>,
}

impl Fitness for SetsFlag<'_> {
    type Scratch = ();

    fn scratch(&self) {}

    fn evaluate(&self, c: &Chromosome, scratch: &mut ()) -> f64 {
        if self.calls.fetch_add(1, Ordering::SeqCst) + 1 == self.at {
            self.flag.store(true, Ordering::SeqCst);
        }
        self.inner.evaluate(c, scratch)
    }
}

fn check<O: Optimizer>(opt: &O, at: u64) {
    let graph = blocks_graph();
    let inner = BlocksTarget {
        graph: &graph,
        blocks: 12,
    };
    let flag = Arc::new(AtomicBool::new(false));
    let fitness = SetsFlag {
        inner,
        calls: AtomicU64::new(0),
        at,
        flag: Arc::clone(&flag),
    };
    let mut observer = Interruptible {
        observer: NoObserver,
        flag,
    };
    let stopped = opt
        .run(
            &graph,
            &fitness,
            &Budget::generations(1000),
            3,
            &mut observer,
        )
        .unwrap();
    assert_eq!(stopped.stop, StopReason::Observer, "{}", opt.name());
    assert!(stopped.generations > 0 && stopped.generations < 1000);
    // The same run budgeted to end after that generation.
    let whole = opt
        .run(
            &graph,
            &inner,
            &Budget::generations(stopped.generations),
            3,
            &mut NoObserver,
        )
        .unwrap();
    assert_eq!(whole.generations, stopped.generations, "{}", opt.name());
    assert_eq!(whole.evaluations, stopped.evaluations, "{}", opt.name());
    assert_eq!(
        whole.best_fitness.to_bits(),
        stopped.best_fitness.to_bits(),
        "{}",
        opt.name()
    );
    assert_eq!(whole.best, stopped.best, "{}", opt.name());
}

#[test]
fn the_ga_stops_mid_generation_with_the_last_complete_one() {
    let ga = Ga::new(GaParams {
        population: 40,
        elites: 8,
        init: InitLength::Around { l0: 12 },
        ..GaParams::default()
    });
    // The 40 initial evaluations always finish; stop in generation 3 or so.
    check(&ga, 150);
}

#[test]
fn rjmcmc_stops_mid_generation_with_the_last_complete_one() {
    let rj = Rjmcmc::new(RjmcmcParams::paper(8, InitLength::Around { l0: 12 }));
    check(&rj, 60);
}

#[test]
fn the_island_ga_stops_mid_generation_with_the_last_complete_one() {
    let islands = shapegen_core::optimize::IslandGa::new(
        shapegen_core::optimize::IslandParams::split(GaParams {
            population: 40,
            elites: 8,
            init: InitLength::Around { l0: 12 },
            ..GaParams::default()
        }),
    );
    check(&islands, 150);
}

#[test]
fn the_hybrid_stops_mid_generation_in_either_phase() {
    let init = InitLength::Around { l0: 12 };
    let first_phases = [
        None,
        Some(shapegen_core::optimize::SmcParams::paper_sosmc(30)),
    ];
    for (patience, first_phase) in [
        (1, first_phases[0]),
        (1000, first_phases[0]),
        (1000, first_phases[1]),
    ] {
        let hybrid = shapegen_core::optimize::Hybrid::new(shapegen_core::optimize::HybridParams {
            ga: GaParams {
                population: 40,
                elites: 8,
                init,
                ..GaParams::default()
            },
            rjmcmc: RjmcmcParams::paper(8, init),
            patience,
            patience_share: shapegen_core::optimize::HYBRID_PATIENCE_SHARE,
            first_phase,
        });
        check(&hybrid, 150);
    }
}

#[test]
fn the_tandem_stops_mid_generation_with_the_last_complete_one() {
    let init = InitLength::Around { l0: 12 };
    let tandem = shapegen_core::optimize::Tandem::new(shapegen_core::optimize::TandemParams::new(
        GaParams {
            population: 40,
            elites: 8,
            init,
            ..GaParams::default()
        },
        RjmcmcParams::paper(8, init),
    ));
    check(&tandem, 150);
    // With a first phase of SOSMC.
    let tandem = shapegen_core::optimize::Tandem::new(shapegen_core::optimize::TandemParams {
        first_phase: Some(shapegen_core::optimize::SmcParams::paper_sosmc(30)),
        ..tandem.params
    });
    check(&tandem, 600);
}

#[test]
fn without_a_flag_nothing_changes() {
    // NoObserver has no flag: the run spends its whole budget.
    let graph = blocks_graph();
    let fitness = BlocksTarget {
        graph: &graph,
        blocks: 12,
    };
    let r = Ga::new(GaParams {
        population: 20,
        elites: 4,
        init: InitLength::Around { l0: 12 },
        ..GaParams::default()
    })
    .run(
        &graph,
        &fitness,
        &Budget::generations(5),
        1,
        &mut NoObserver,
    )
    .unwrap();
    assert_eq!((r.generations, r.stop), (5, StopReason::Generations));
}
