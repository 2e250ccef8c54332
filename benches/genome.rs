//! Genome operator benchmarks at G = 100, 1k, 10k and 100k genes.
//!
//! `cargo bench --bench genome`; under `cargo test` each runs once as a smoke test.
//! Targets (issue #2): a 10k-gene individual built by repeated grow in < 5 ms;
//! cut and crossover linear in G and < 50 µs for 10k-gene parents.

use std::hint::black_box;

use criterion::{BatchSize, BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use shapegen::prelude::*;
use shapegen::rng::stream;

const SIZES: [usize; 4] = [100, 1_000, 10_000, 100_000];

/// The paper's spaceship graph (Fig. 4a): realistic gene sizes and probabilities.
fn spaceship() -> Graph {
    let scale = |lo: [f32; 3], hi: [f32; 3]| ParamDist::uniform_vec3(lo, hi);
    GraphBuilder::new("spaceship")
        .start("S")
        .node("S", |n| n.slot("body", "B", 1.0))
        .node("B", |n| {
            n.emits()
                .param("scale", scale([0.6; 3], [1.5; 3]))
                .slot("body", "B", 1.0 / 3.0)
                .slot("wing", "W", 1.0 / 3.0)
                .slot("top", "T", 1.0 / 3.0)
        })
        .node("T", |n| {
            n.emits()
                .param("scale", scale([0.3, 0.1, 0.3], [0.8, 0.2, 0.8]))
                .slot("seg", "t", 1.0)
        })
        .node("t", |n| {
            n.emits()
                .param("scale", scale([0.6, 0.8, 0.6], [1.1, 1.1, 1.1]))
                .slot("seg", "t", 1.0)
        })
        .node("W", |n| {
            n.emits()
                .param("scale", scale([0.3, 0.2, 0.2], [1.2, 0.5, 1.0]))
                .param_f32("move", Dist::uniform(-0.5, 0.5))
                .slot("seg", "w", 1.0)
        })
        .node("w", |n| {
            n.emits()
                .param("scale", scale([0.6, 0.9, 0.7], [1.2, 1.0, 1.2]))
                .param_f32("move", Dist::uniform(-0.5, 0.5))
                .slot("seg", "w", 0.9)
        })
        .build()
        .unwrap()
}

fn individual(graph: &Graph, genes: usize, seed: u64) -> Chromosome {
    let mut rng = stream(seed, &[]);
    random_individual(graph, &InitLength::Fixed { l0: genes as u32 }, &mut rng).unwrap()
}

fn bench_genome(c: &mut Criterion) {
    let graph = spaceship();
    let mut rng = stream(99, &[]);

    let mut group = c.benchmark_group("random_individual");
    for g in SIZES {
        group.throughput(Throughput::Elements(g as u64));
        let mut grower = Grower::new();
        let len = InitLength::Fixed { l0: g as u32 };
        group.bench_function(BenchmarkId::from_parameter(g), |b| {
            b.iter(|| random_individual_with(&graph, &len, &mut grower, &mut rng).unwrap())
        });
    }
    group.finish();

    let parents: Vec<(Chromosome, Chromosome)> = SIZES
        .iter()
        .map(|&g| (individual(&graph, g, 1), individual(&graph, g, 2)))
        .collect();

    for (name, op) in [("grow", 0u8), ("cut", 1), ("alter", 2)] {
        let mut group = c.benchmark_group(name);
        for (g, (a, _)) in SIZES.iter().zip(&parents) {
            group.throughput(Throughput::Elements(*g as u64));
            group.bench_function(BenchmarkId::from_parameter(g), |b| {
                b.iter_batched_ref(
                    || a.clone(),
                    |x| match op {
                        0 => black_box(grow(&graph, x, &mut rng).is_some()),
                        1 => black_box(cut(&graph, x, &mut rng).is_some()),
                        _ => black_box(alter(&graph, x, &mut rng).is_some()),
                    },
                    BatchSize::LargeInput,
                )
            });
        }
        group.finish();
    }

    let mut group = c.benchmark_group("crossover");
    let config = CrossoverConfig::default();
    for (g, (a, b)) in SIZES.iter().zip(&parents) {
        group.throughput(Throughput::Elements(*g as u64));
        group.bench_function(BenchmarkId::from_parameter(g), |bench| {
            bench.iter(|| black_box(crossover(&graph, a, b, &config, &mut rng)))
        });
    }
    group.finish();

    // The same, writing into reused children (as an allocation-free GA does).
    let mut group = c.benchmark_group("crossover_into");
    let (mut c1, mut c2) = (Chromosome::empty(), Chromosome::empty());
    for (g, (a, b)) in SIZES.iter().zip(&parents) {
        group.throughput(Throughput::Elements(*g as u64));
        group.bench_function(BenchmarkId::from_parameter(g), |bench| {
            bench.iter(|| {
                black_box(crossover_into(
                    &graph, a, b, &config, &mut rng, &mut c1, &mut c2,
                ))
            })
        });
    }
    group.finish();

    let mut group = c.benchmark_group("validate");
    for (g, (a, _)) in SIZES.iter().zip(&parents) {
        group.throughput(Throughput::Elements(*g as u64));
        group.bench_function(BenchmarkId::from_parameter(g), |b| {
            b.iter(|| a.validate(&graph).unwrap())
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(30).warm_up_time(std::time::Duration::from_millis(500)).measurement_time(std::time::Duration::from_secs(2));
    targets = bench_genome
}
criterion_main!(benches);
