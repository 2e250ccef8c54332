//! RJMCMC: at β = 1 without annealing it samples the posterior; chains are
//! valid chromosomes; runs are deterministic whatever the thread count.

use proptest::prelude::*;
use shapegen_core::optimize::{DelayedRejection, Ladder, LogLikelihood, Rjmcmc, RjmcmcParams};
use shapegen_core::prelude::*;

/// Root → A (p = 1), A → A (p = 0.5), max depth 5: lengths 2..=6.
fn chain() -> Graph {
    GraphBuilder::new("chain")
        .start("Root")
        .limits(Limits {
            max_depth: Some(5),
            min_len: 2,
            max_len: None,
        })
        .node("Root", |n| n.emits().slot("a", "A", 1.0))
        .node("A", |n| {
            n.emits()
                .param_f32("x", Dist::uniform(0.0, 1.0))
                .slot("next", "A", 0.5)
        })
        .build()
        .unwrap()
}

fn sampler(chains: usize, delayed_rejection: DelayedRejection) -> Rjmcmc {
    Rjmcmc::new(RjmcmcParams {
        chains,
        init: InitLength::Between { lo: 2, hi: 6 },
        jump_probability: 0.5,
        ladder: Ladder::Flat,
        annealing: None,
        log_likelihood: LogLikelihood::FitnessIsLogLik { tau: 1.0 },
        delayed_rejection,
    })
}

#[test]
fn samples_the_posterior_at_beta_one() {
    check_posterior(DelayedRejection::Off);
}

#[test]
fn exact_delayed_rejection_also_samples_the_posterior() {
    check_posterior(DelayedRejection::Exact);
}

fn check_posterior(dr: DelayedRejection) {
    let graph = chain();
    // log L = −|L − 4| (parameters do not matter), so the posterior of the length is
    // prior(L) · e^{−|L − 4|} with prior(2 + k) = 0.5^{k+1} for k < 4 and prior(6) = 0.5^4.
    let prior = [0.5, 0.25, 0.125, 0.0625, 0.0625];
    let post: Vec<f64> = prior
        .iter()
        .enumerate()
        .map(|(k, p)| p * (-((k as f64 + 2.0) - 4.0).abs()).exp())
        .collect();
    let z: f64 = post.iter().sum();
    let f = FnFitness(|c: &Chromosome| -(c.len() as f64 - 4.0).abs());
    // Independent chains run long: their final states are independent posterior samples.
    let n = 4000;
    let r = sampler(n, dr)
        .run(&graph, &f, &Budget::generations(150), 11, &mut NoObserver)
        .unwrap();
    let mut counts = [0u64; 5];
    for i in &r.population {
        i.chromosome.validate(&graph).unwrap();
        counts[i.chromosome.len() - 2] += 1;
    }
    let chi2: f64 = counts
        .iter()
        .zip(&post)
        .map(|(&o, &p)| {
            let e = n as f64 * p / z;
            (o as f64 - e).powi(2) / e
        })
        .sum();
    // 4 degrees of freedom, significance 0.001.
    assert!(
        chi2 < 18.47,
        "chi2 = {chi2}, counts {counts:?}, expected {:?}",
        post.iter().map(|p| n as f64 * p / z).collect::<Vec<_>>()
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
    let run = |threads| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let params = RjmcmcParams::paper(40, InitLength::Between { lo: 2, hi: 6 });
        pool.install(|| {
            Rjmcmc::new(params)
                .run(&graph, &f, &Budget::generations(30), 4, &mut NoObserver)
                .unwrap()
        })
    };
    let (a, b) = (run(1), run(2));
    assert_eq!(a.best, b.best);
    assert_eq!(a.population, b.population);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Every chain state on random graphs is a valid chromosome.
    #[test]
    fn chains_stay_valid(graph in crate::common::graph(), seed in any::<u64>(), dr in 0usize..3) {
        let f = FnFitness(|c: &Chromosome| -(c.len() as f64 - 12.0).abs());
        let delayed_rejection = [DelayedRejection::Off, DelayedRejection::Exact, DelayedRejection::ApproxAlter][dr];
        let params = RjmcmcParams { chains: 12, init: InitLength::Between { lo: 1, hi: 30 }, delayed_rejection, ..RjmcmcParams::paper(12, InitLength::Around { l0: 10 }) };
        let r = Rjmcmc::new(params).run(&graph, &f, &Budget::generations(40), seed, &mut NoObserver).unwrap();
        for i in &r.population {
            i.chromosome.validate(&graph).map_err(|e| TestCaseError::fail(e.to_string()))?;
        }
    }
}
