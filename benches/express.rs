//! Expression speed: genes expressed per second into a counting sink, for the
//! paper's generators, macro-generated code vs the run-time interpreter.
//!
//! `cargo bench --bench express`; under `cargo test` each runs once as a smoke test.
//! Targets (issue #3): >= 20 million genes/s on one core for the macro path,
//! and the macro path at least 2x faster than the interpreter.

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use shapegen::express::{CountingSink, Generator};
use shapegen::prelude::*;
use shapegen::rng::stream;
use shapegen::scenes::{SpaceFillingCity, Spaceship, TreeV2};

/// Random individuals of about `genes` genes, as the GA's population holds.
fn population(graph: &Graph, genes: u32, n: usize) -> Vec<Chromosome> {
    let mut rng = stream(5, &[]);
    (0..n)
        .map(|_| random_individual(graph, &InitLength::Around { l0: genes }, &mut rng).unwrap())
        .collect()
}

fn bench_pair<G, I>(c: &mut Criterion, name: &str, generator: &G, interpreter: &I, genes: u32)
where
    G: Generator,
    I: Generator<State = G::State>,
{
    let pop = population(generator.graph(), genes, 64);
    let total: usize = pop.iter().map(Chromosome::len).sum();
    let mut group = c.benchmark_group(format!("express/{name}"));
    group.throughput(Throughput::Elements(total as u64));
    let mut stack = shapegen::express::Pending::new();
    group.bench_function(BenchmarkId::new("macro", genes), |b| {
        b.iter(|| {
            let mut sink = CountingSink::default();
            for c in &pop {
                generator.express_with(c, &mut sink, &mut stack);
            }
            black_box(sink.count)
        })
    });
    group.bench_function(BenchmarkId::new("interpreter", genes), |b| {
        b.iter(|| {
            let mut sink = CountingSink::default();
            for c in &pop {
                interpreter.express_with(c, &mut sink, &mut stack);
            }
            black_box(sink.count)
        })
    });
    group.finish();
}

fn bench_express(c: &mut Criterion) {
    bench_pair::<Spaceship, _>(c, "spaceship", &Spaceship, &Spaceship::interpreter(), 50);
    bench_pair::<TreeV2, _>(c, "tree_v2", &TreeV2, &TreeV2::interpreter(), 250);
    bench_pair::<SpaceFillingCity, _>(
        c,
        "city",
        &SpaceFillingCity,
        &SpaceFillingCity::interpreter(),
        50,
    );
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(30).warm_up_time(std::time::Duration::from_millis(500)).measurement_time(std::time::Duration::from_secs(2));
    targets = bench_express
}
criterion_main!(benches);
