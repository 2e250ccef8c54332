//! Scoring speed on the paper's scenes.
//!
//! `cargo bench --bench score`; under `cargo test` each runs once as a smoke test.
//! Reads the paper's targets from `../shared/data/paper/` (or `$SHAPEGEN_DATA`);
//! benchmarks whose data is missing are skipped with a message.
//! Targets (issue #4): spaceship volume scene (100×200×100 grid, 50-gene
//! ships) >= 10,000 evaluations/s on one core; evaluation of a population
//! scales >= 1.8x from 1 to 2 threads.

use std::hint::black_box;
use std::path::PathBuf;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use shapegen::express::Generator;
use shapegen::glam::{UVec3, Vec3};
use shapegen::optimize::{ScratchPool, evaluate_all};
use shapegen::prelude::*;
use shapegen::rng::stream;
use shapegen::scenes::Spaceship;
use shapegen::score::obj::ShapeMeshes;
use shapegen::score::score::{VolumeFitness, VolumeScore};
use shapegen::score::volume::{VolumeScene, VolumeTarget};
use shapegen::score::{Grid, Mesh};

fn data(rel: &str) -> Option<PathBuf> {
    let root = std::env::var_os("SHAPEGEN_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data"));
    let p = root.join(rel);
    if p.exists() {
        Some(p)
    } else {
        eprintln!("skipping: {} not found", p.display());
        None
    }
}

/// The spaceship volume scene of paper Fig. 7 (left), normalized score 2 / 15 / 0.1.
fn spaceship_fitness() -> Option<VolumeFitness<Spaceship>> {
    let target = Mesh::load_obj(&data("paper/spaceship_target.obj")?).ok()?;
    let grid = Grid::new(
        Vec3::new(-5.0, -5.0, -2.0),
        Vec3::new(5.0, 5.0, 18.0),
        UVec3::new(100, 200, 100),
    )
    .ok()?;
    let scene = VolumeScene::new(
        grid,
        &[VolumeTarget {
            name: "spaceship".into(),
            mesh: target,
            fill: 1.0,
            outside: 0.0,
        }],
    )
    .ok()?;
    let score = VolumeScore::Normalized {
        w_good: 2.0,
        w_bad: 15.0,
        w_length: 0.1,
        separate_overlap: None,
    };
    let limits = Limits {
        max_depth: Some(15),
        min_len: 4,
        max_len: Some(100),
    };
    VolumeFitness::new(
        Spaceship,
        scene,
        &ShapeMeshes::builtin(&Spaceship).ok()?,
        score,
    )
    .ok()
    .map(|f| f.with_limits(limits))
}

fn bench_score(c: &mut Criterion) {
    if let Some(fitness) = spaceship_fitness() {
        let mut rng = stream(3, &[]);
        let ships: Vec<Chromosome> = (0..150)
            .map(|_| {
                random_individual(Spaceship.graph(), &InitLength::Around { l0: 50 }, &mut rng)
                    .unwrap()
            })
            .collect();
        let mut group = c.benchmark_group("score/spaceship_volume");
        group.throughput(Throughput::Elements(ships.len() as u64));
        let mut scratch = fitness.scratch();
        group.bench_function("evaluate_150_ships_1_thread", |b| {
            b.iter(|| {
                ships
                    .iter()
                    .map(|s| fitness.evaluate(s, &mut scratch))
                    .sum::<f64>()
            })
        });
        // As the optimizers evaluate a population: in parallel, scratch kept in a pool.
        for threads in [1, 2] {
            let threads_pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let scratch = ScratchPool::new();
            group.bench_function(BenchmarkId::new("population_150", threads), |b| {
                b.iter(|| threads_pool.install(|| evaluate_all(&fitness, &ships, &scratch)))
            });
        }
        group.finish();
    }

    if let Some(path) = data("models/stanford-bunny.obj") {
        let bunny = Mesh::load_obj(&path).unwrap().normalized();
        let grid = Grid::cube(Vec3::splat(-0.5), Vec3::splat(0.5), 128).unwrap();
        let mut group = c.benchmark_group("score/voxelize");
        group.sample_size(10);
        group.bench_function("stanford_bunny_128", |b| {
            b.iter(|| {
                let target = VolumeTarget {
                    name: "bunny".into(),
                    mesh: bunny.clone(),
                    fill: 1.0,
                    outside: 0.0,
                };
                black_box(VolumeScene::new(grid, &[target]).unwrap().target_cells())
            })
        });
        group.finish();
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).warm_up_time(std::time::Duration::from_millis(500)).measurement_time(std::time::Duration::from_secs(3));
    targets = bench_score
}
criterion_main!(benches);
