//! After warm-up, evaluating a volume fitness allocates nothing: the voxel
//! hit counts, touched runs, crossings and pending genes are all reused.

// A counting global allocator needs `unsafe`; the libraries forbid it.
#![allow(unsafe_code)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use shapegen::express::Generator;
use shapegen::glam::DVec3;
use shapegen::glam::{UVec3, Vec3};
use shapegen::prelude::*;
use shapegen::rng::stream;
use shapegen::scenes::{Spaceship, TreeV2};
use shapegen::score::Camera;
use shapegen::score::ImageTarget;
use shapegen::score::ShapeMeshes;
use shapegen::score::{Grid, Mesh};
use shapegen::score::{ImageFitness, ImageScore, ImageTargets, VolumeFitness, VolumeScore};
use shapegen::score::{VolumeScene, VolumeTarget};

struct Counting;

// Counted per thread, so tests running in parallel do not see each other's allocations.
thread_local! {
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

fn count() {
    // `try_with`: the thread-local may already be gone while a thread shuts down.
    let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
}

fn allocations() -> usize {
    ALLOCATIONS.with(Cell::get)
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn target() -> Mesh {
    let mut m = Mesh::unit_cube();
    for p in &mut m.positions {
        *p = *p * Vec3::new(4.0, 2.0, 8.0) + Vec3::new(0.0, 0.0, 4.0);
    }
    m
}

fn check<G: Generator>(generator: G, genes: u32)
where
    G::State: Send,
{
    let grid = Grid::new(
        Vec3::new(-5.0, -5.0, -2.0),
        Vec3::new(5.0, 5.0, 18.0),
        UVec3::new(50, 100, 50),
    )
    .unwrap();
    let scene = VolumeScene::new(
        grid,
        &[VolumeTarget {
            name: "box".into(),
            mesh: target(),
            fill: 1.0,
            outside: -0.5,
            inside: Default::default(),
        }],
    )
    .unwrap();
    let shapes = ShapeMeshes::builtin(&generator).unwrap();
    let score = VolumeScore::Normalized {
        w_good: 2.0,
        w_bad: 15.0,
        w_length: 0.1,
        separate_overlap: None,
    };
    let mut rng = stream(1, &[]);
    let graph = generator.graph().clone();
    let models: Vec<Chromosome> = (0..40)
        .map(|_| random_individual(&graph, &InitLength::Around { l0: genes }, &mut rng).unwrap())
        .collect();
    let fitness = VolumeFitness::new(generator, scene, &shapes, score).unwrap();
    let mut scratch = fitness.scratch();
    // Warm-up: buffers grow to what the largest model needs.
    let first: Vec<f64> = models
        .iter()
        .map(|c| fitness.evaluate(c, &mut scratch))
        .collect();
    let before = allocations();
    let again: Vec<f64> = {
        let mut out = Vec::with_capacity(models.len());
        for c in &models {
            out.push(fitness.evaluate(c, &mut scratch));
        }
        out
    };
    let after = allocations();
    // One allocation is the `out` vector above.
    assert_eq!(after - before, 1, "evaluations allocated");
    assert_eq!(first, again, "evaluation is pure");
}

/// Evaluates `models` twice and returns how many allocations the second pass made.
fn allocations_of_second_pass<F: Fitness>(fitness: &F, models: &[Chromosome]) -> usize {
    let mut scratch = fitness.scratch();
    let first: Vec<f64> = models
        .iter()
        .map(|c| fitness.evaluate(c, &mut scratch))
        .collect();
    let mut again = Vec::with_capacity(models.len());
    let before = allocations();
    for c in models {
        again.push(fitness.evaluate(c, &mut scratch));
    }
    let after = allocations();
    assert_eq!(first, again, "evaluation is pure");
    after - before
}

#[test]
fn volume_evaluation_allocates_nothing_after_warm_up() {
    check(Spaceship, 50);
    check(TreeV2, 100);
}

#[test]
fn image_evaluation_allocates_nothing_after_warm_up() {
    let camera = Camera::orbit(
        -std::f64::consts::FRAC_PI_2,
        0.2,
        9.0,
        DVec3::new(0.0, 2.0, 0.0),
        60f64.to_radians(),
        0.1,
        100.0,
        (160, 120),
    )
    .unwrap();
    // A disc of target pixels in the middle of the image.
    let weights = (0..160 * 120)
        .map(|i| {
            if ((i % 160) - 80i32).pow(2) + ((i / 160) - 50i32).pow(2) < 1600 {
                1.0
            } else {
                -1.0
            }
        })
        .collect();
    let target = ImageTarget::new(camera, weights).unwrap();
    let score = ImageScore::Normalized {
        w_good: 1.0,
        w_bad: 1.0,
        w_length: 0.01,
    };
    let fitness = ImageFitness::new(
        TreeV2,
        ImageTargets::new(vec![target]).unwrap(),
        &ShapeMeshes::builtin(&TreeV2).unwrap(),
        score,
    )
    .unwrap();
    let mut rng = stream(2, &[]);
    let models: Vec<Chromosome> = (0..30)
        .map(|_| {
            random_individual(TreeV2.graph(), &InitLength::Around { l0: 120 }, &mut rng).unwrap()
        })
        .collect();
    assert_eq!(allocations_of_second_pass(&fitness, &models), 0);
}
