//! SMC and SOSMC: the prior is reproduced under a constant likelihood, slots
//! are visited in the documented orders, every particle is a valid
//! chromosome, and runs are deterministic whatever the thread count.

use proptest::prelude::*;
use shapegen_core::optimize::{Resampling, SlotOrder, Smc, SmcParams, SmcWeights};
use shapegen_core::prelude::*;

/// Root → A (p = 0.6), A → A (p = 0.6), max depth 8: L = 1 + the chain's length.
fn chain() -> Graph {
    GraphBuilder::new("chain")
        .start("Root")
        .limits(Limits {
            max_depth: Some(8),
            min_len: 1,
            max_len: None,
        })
        .node("Root", |n| n.emits().slot("a", "A", 0.6))
        .node("A", |n| {
            n.emits()
                .param_f32("x", Dist::uniform(0.0, 1.0))
                .slot("next", "A", 0.6)
        })
        .build()
        .unwrap()
}

#[test]
fn incremental_weights_with_a_constant_likelihood_reproduce_the_prior() {
    let graph = chain();
    // Exact prior of the length: P(L = k) = 0.6^(k−1) · 0.4 for k < 9, P(L = 9) = 0.6^8.
    let mut prior: Vec<f64> = (1..9).map(|k| 0.6f64.powi(k - 1) * 0.4).collect();
    prior.push(0.6f64.powi(8));
    let n = 20_000;
    let params = SmcParams {
        particles: n,
        order: SlotOrder::Program,
        weights: SmcWeights::IncrementalExp { tau: 1.0 },
        resampling: Resampling::Systematic,
    };
    let constant = FnFitness(|_: &Chromosome| 1.0);
    let r = Smc::new(params)
        .run(
            &graph,
            &constant,
            &Budget::generations(100),
            5,
            &mut NoObserver,
        )
        .unwrap();
    assert_eq!(r.stop, StopReason::Exhausted);
    let mut counts = [0u64; 9];
    for i in &r.population {
        counts[i.chromosome.len() - 1] += 1;
    }
    let chi2: f64 = counts
        .iter()
        .zip(&prior)
        .map(|(&o, &p)| (o as f64 - n as f64 * p).powi(2) / (n as f64 * p))
        .sum();
    // 8 degrees of freedom, significance 0.001.
    assert!(chi2 < 26.12, "chi2 = {chi2}, counts {counts:?}");
}

/// All slots have p = 1; every node emits, so each step adds exactly one gene.
fn full_tree() -> Graph {
    GraphBuilder::new("full")
        .start("R")
        .limits(Limits {
            max_depth: Some(3),
            min_len: 1,
            max_len: None,
        })
        .node("R", |n| n.emits().slot("l", "N", 1.0).slot("r", "N", 1.0))
        .node("N", |n| n.emits().slot("l", "N", 1.0).slot("r", "N", 1.0))
        .build()
        .unwrap()
}

#[test]
fn smc_expands_in_program_order_and_sosmc_does_not() {
    let graph = full_tree();
    let f = FnFitness(|_: &Chromosome| 1.0);
    let run = |order| {
        let params = SmcParams {
            particles: 64,
            order,
            weights: SmcWeights::AbsoluteShifted,
            resampling: Resampling::Systematic,
        };
        Smc::new(params)
            .run(&graph, &f, &Budget::generations(100), 9, &mut NoObserver)
            .unwrap()
    };
    // Genes are appended as they are expanded, so buffer order is expansion order.
    let buffer_is_preorder = |c: &Chromosome| {
        let pre: Vec<u32> = c.subtree(&graph, 0).map(|g| g.pos()).collect();
        pre == c.positions()
    };
    let smc = run(SlotOrder::Program);
    assert!(
        smc.population
            .iter()
            .all(|i| i.chromosome.len() == 15 && buffer_is_preorder(&i.chromosome))
    );
    let sosmc = run(SlotOrder::Random);
    assert!(sosmc.population.iter().all(|i| i.chromosome.len() == 15));
    assert!(
        sosmc
            .population
            .iter()
            .any(|i| !buffer_is_preorder(&i.chromosome)),
        "SOSMC followed program order every time"
    );
}

#[test]
fn same_seed_same_run_whatever_the_thread_count() {
    let graph = chain();
    let f = FnFitness(|c: &Chromosome| {
        c.genes(&graph)
            .skip(1)
            .map(|g| f64::from(g.param_f32(0)))
            .sum::<f64>()
    });
    for order in [SlotOrder::Program, SlotOrder::Random] {
        let run = |threads| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                Smc::new(SmcParams {
                    order,
                    ..SmcParams::paper(300)
                })
                .run(&graph, &f, &Budget::generations(6), 3, &mut NoObserver)
                .unwrap()
            })
        };
        let (a, b) = (run(1), run(2));
        assert_eq!(a.best, b.best);
        assert_eq!(a.population, b.population);
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Every particle of SMC and SOSMC runs on random graphs is a valid chromosome
    /// (once it reaches `L_min`; shorter particles are partial models).
    #[test]
    fn particles_are_valid_chromosomes(graph in crate::common::graph(), seed in any::<u64>(), random in any::<bool>()) {
        let order = if random { SlotOrder::Random } else { SlotOrder::Program };
        let f = FnFitness(|c: &Chromosome| -(c.len() as f64 - 10.0).abs());
        let params = SmcParams { particles: 24, order, weights: SmcWeights::AbsoluteShifted, resampling: Resampling::Multinomial };
        let mut seen = 0;
        let mut check = |s: &GenerationStats<'_>| {
            // Until some particle reaches L_min there is no valid model to report.
            if s.best_so_far.is_finite() {
                s.best_chromosome.validate(&graph).unwrap();
            }
            seen += 1;
            std::ops::ControlFlow::Continue(())
        };
        let r = Smc::new(params).run(&graph, &f, &Budget::generations(30), seed, &mut check).unwrap();
        for i in &r.population {
            if i.chromosome.len() >= graph.limits().min_len as usize {
                i.chromosome.validate(&graph).map_err(|e| TestCaseError::fail(e.to_string()))?;
            }
        }
        prop_assert!(seen >= 1);
    }
}
