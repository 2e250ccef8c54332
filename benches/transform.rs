//! Design transformations (issue #57).
//!
//! `cargo bench --bench transform`; under `cargo test` each runs once as a
//! smoke test. One thread throughout (the co-derivation is sequential).
//!
//! Targets on this machine: at most 2 ms per transformed model of the
//! thesis's tree pair (Fig. 5.1; the thesis reports 110 ms) and 10 ms for
//! the farm and the castle (Fig. 5.10; the thesis: 180 ms), and a
//! 200-frame sequence with its pictures (360 px, one camera) in at most 5 s;
//! the split strings' edit search in at most 10 ms for strings of up to 25
//! symbols (issue #58).

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
    for name in [
        "tree_lsystems",
        "trees_v1_v2",
        "spaceships",
        "cities",
        "facades",
        "farm_castle",
    ] {
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

/// Split strings of up to 25 symbols: façade floors of pillars and
/// windows, a door crossing a row of windows, alternating patterns whose
/// counts and labels differ.
fn bench_edit_search(c: &mut Criterion) {
    use shapegen::transform::edits::edit_path;
    type L = (char, u8);
    let side = |s: &str, k: u8| -> Vec<L> { s.chars().map(|c| (c, k)).collect() };
    let matches = |a: L, b: L| a.0 == b.0 && a.1 != b.1;
    let cases = [
        // A.1's floor at 25 symbols: pillars and yellow tiles to plain tiles.
        (
            "floor_25_to_20",
            side("PPYPYPYPYPYPYPYPYPYPYPYPP", 1),
            side("YYYYYYYYYYYYYYYYYYYY", 2),
        ),
        // A door crossing 24 windows and changing style.
        ("door_across_25", side("DWWWWWWWWWWWWWWWWWWWWWWWW", 1), {
            let mut v = side("WWWWWWWWWWWWWWWWWWWWWWWW", 1);
            v.push(('D', 2));
            v
        }),
        // Alternating windows and pillars, one design, counts differ.
        (
            "alternating_25_to_23",
            side("WPWPWPWPWPWPWPWPWPWPWPWPW", 1),
            side("PWPWPWPWPWPWPWPWPWPWPWP", 1),
        ),
        // Balconies among windows, symmetric, to wider balconies.
        (
            "symmetric_25",
            side("WWBWWBWWBWWBWBWWBWWBWWBWW", 1),
            side("WBBWWBBWWWBBWWWBBWWBBW", 2),
        ),
    ];
    let mut group = c.benchmark_group("transform/edit_search");
    for (name, src, dst) in &cases {
        group.bench_function(*name, |b| {
            b.iter(|| edit_path(src, dst, matches).map(|p| p.edits.len()));
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).warm_up_time(std::time::Duration::from_millis(500)).measurement_time(std::time::Duration::from_secs(3));
    targets = bench_model, bench_sequence, bench_edit_search
}
criterion_main!(benches);
