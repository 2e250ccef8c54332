//! Rendering, best views and galleries (issue #19).
//!
//! `cargo bench --bench gallery`; under `cargo test` each runs once as a
//! smoke test. Reads the paper's leaf from `../shared/data/paper/` (or
//! `$SHAPEGEN_DATA`); without it the built-in leaf is used.
//!
//! Targets on this machine: a 500×500 render of a 250-gene tree with the
//! paper's leaf in at most 5 ms on one core; a 200-sample gallery of each
//! paper generator in at most 10 s on two cores (the thesis: 30 to 120 s of
//! attribute computation on a GPU for 200 samples).

use std::path::PathBuf;

use criterion::{Criterion, criterion_group, criterion_main};
use shapegen::express::{Generator, Instances};
use shapegen::gallery::{Gallery, GalleryOptions, Models};
use shapegen::prelude::*;
use shapegen::rng::stream;
use shapegen::scenes::{GridCity, SpaceFillingCity, Spaceship, TreeV1, TreeV2};
use shapegen::score::{
    AttributeWeights, BoundingSphere, Mesh, RenderMeshes, Renderer, ShapeMeshes, Style,
    ViewSampling, best_view, fit_camera,
};

fn data(rel: &str) -> Option<PathBuf> {
    let root = std::env::var_os("SHAPEGEN_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data"));
    let p = root.join(rel);
    p.exists().then_some(p)
}

/// The generator's built-in meshes, with the paper's leaf if it is there.
fn meshes<G: Generator>(generator: &G) -> ShapeMeshes {
    let mut shapes = ShapeMeshes::builtin(generator).unwrap();
    if let Some(leaf) = data("paper/leaf.obj").or_else(|| data("leaf.obj")) {
        if generator.shapes().iter().any(|s| s == "leaf") {
            shapes
                .set("leaf", Mesh::load_obj(&leaf).unwrap().normalized())
                .unwrap();
        }
    } else {
        eprintln!("gallery bench: no paper/leaf.obj; using the built-in leaf");
    }
    shapes
}

fn bench_render(c: &mut Criterion) {
    let shapes = meshes(&TreeV2);
    let prepared = RenderMeshes::new(&shapes).unwrap();
    let mut rng = stream(4, &[]);
    let tree = random_individual(TreeV2.graph(), &InitLength::Fixed { l0: 250 }, &mut rng).unwrap();
    let mut model = Instances::default();
    TreeV2.express(&tree, &mut model);
    let sphere = prepared.bounding_sphere(&model.0).unwrap();
    let camera = fit_camera(
        &sphere,
        BoundingSphere::direction(0.8, 0.4),
        40f64.to_radians(),
        (500, 500),
    )
    .unwrap();
    let mut renderer = Renderer::new();
    let mut group = c.benchmark_group("render");
    group.bench_function("tree_250_genes_500x500_gbuffer", |b| {
        b.iter(|| {
            renderer
                .render(&prepared, &model.0, &camera)
                .covered_pixels()
        })
    });
    group.bench_function("tree_250_genes_500x500_shaded", |b| {
        b.iter(|| {
            renderer
                .picture(&prepared, &model.0, &camera, &Style::fast())
                .len()
        })
    });
    let default = default_model(TreeV2.graph()).unwrap();
    let mut model = Instances::default();
    TreeV2.express(&default, &mut model);
    group.bench_function("best_view_tree_v2_default_32_views", |b| {
        b.iter(|| {
            best_view(
                &mut renderer,
                &prepared,
                &model.0,
                &ViewSampling::default(),
                &AttributeWeights::BEST_VIEW,
                &Style::fast(),
            )
            .unwrap()
            .index
        })
    });
    group.finish();
}

fn gallery_of<G: Generator + Send + Sync>(
    c: &mut Criterion,
    name: &str,
    generator: G,
    pool: &rayon::ThreadPool,
) {
    let models = (generator, meshes_for_name(name));
    let options = GalleryOptions::default();
    let mut group = c.benchmark_group("gallery_200_samples_2_threads");
    group.sample_size(10);
    group.bench_function(name, |b| {
        b.iter(|| {
            pool.install(|| Gallery::sample(&models as &dyn Models, &options, &|_| {}))
                .unwrap()
                .models
                .len()
        })
    });
    group.finish();
}

fn meshes_for_name(name: &str) -> ShapeMeshes {
    match name {
        "spaceship" => meshes(&Spaceship),
        "tree_v1" => meshes(&TreeV1),
        "tree_v2" => meshes(&TreeV2),
        "space_filling_city" => meshes(&SpaceFillingCity),
        _ => meshes(&GridCity),
    }
}

fn bench_gallery(c: &mut Criterion) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    gallery_of(c, "spaceship", Spaceship, &pool);
    gallery_of(c, "tree_v1", TreeV1, &pool);
    gallery_of(c, "tree_v2", TreeV2, &pool);
    gallery_of(c, "space_filling_city", SpaceFillingCity, &pool);
    gallery_of(c, "grid_city", GridCity, &pool);
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).warm_up_time(std::time::Duration::from_millis(500)).measurement_time(std::time::Duration::from_secs(3));
    targets = bench_render, bench_gallery
}
criterion_main!(benches);
