//! Design transformations (issue #57).
//!
//! `cargo bench --bench transform`; under `cargo test` each runs once as a
//! smoke test. One thread throughout (the co-derivation is sequential).
//!
//! Targets on this machine: at most 2 ms per transformed model of the
//! thesis's tree pair (Fig. 5.1; the thesis reports 110 ms), and a
//! 200-frame sequence with its pictures (360 px, one camera) in at most 5 s.

use criterion::{Criterion, criterion_group, criterion_main};
use shapegen::registry::Registry;
use shapegen::score::Viewpoint;
use shapegen::transform::sequence::{Painter, frame_times};
use shapegen::transform::{TransformFile, Transformation};

fn load(name: &str) -> Transformation {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("transformations")
        .join(format!("{name}.toml"));
    TransformFile::load(&path, &Registry::builtin())
        .expect("the shipped transformation files load")
        .transformation
}

fn bench_model(c: &mut Criterion) {
    let mut group = c.benchmark_group("transform/model");
    for name in ["tree_lsystems", "trees_v1_v2", "spaceships", "cities"] {
        let t = load(name);
        let mut out = Vec::new();
        group.bench_function(name, |b| {
            b.iter(|| {
                t.at_into(std::hint::black_box(0.5), &mut out);
                out.len()
            });
        });
    }
    group.finish();
}

fn bench_sequence(c: &mut Criterion) {
    let t = load("tree_lsystems");
    let viewpoint = Viewpoint {
        azimuth: 35f64.to_radians(),
        elevation: 10f64.to_radians(),
    };
    let mut painter = Painter::new(&t, viewpoint, 360).unwrap();
    let times = frame_times(200);
    let mut out = Vec::new();
    let mut group = c.benchmark_group("transform/sequence");
    group.sample_size(10);
    group.bench_function("tree_lsystems_200_frames_360px", |b| {
        b.iter(|| {
            let mut inked = 0u64;
            for &time in &times {
                t.at_into(time, &mut out);
                let picture = painter.paint(&out);
                inked += u64::from(picture.get_pixel(180, 180).0[0]);
            }
            inked
        });
    });
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).warm_up_time(std::time::Duration::from_millis(500)).measurement_time(std::time::Duration::from_secs(3));
    targets = bench_model, bench_sequence
}
criterion_main!(benches);
