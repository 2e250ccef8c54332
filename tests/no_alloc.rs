//! After warm-up, evaluating a volume fitness allocates nothing: the voxel
//! hit counts, touched runs, crossings and pending genes are all reused.

// A counting global allocator needs `unsafe`; the libraries forbid it.
#![allow(unsafe_code)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use shapegen::express::Generator;
use shapegen::glam::{UVec3, Vec3};
use shapegen::prelude::*;
use shapegen::rng::stream;
use shapegen::scenes::{Spaceship, TreeV2};
use shapegen::score::obj::ShapeMeshes;
use shapegen::score::score::{VolumeFitness, VolumeScore};
use shapegen::score::volume::{VolumeScene, VolumeTarget};
use shapegen::score::{Grid, Mesh};

struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
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
    let before = ALLOCATIONS.load(Ordering::Relaxed);
    let again: Vec<f64> = {
        let mut out = Vec::with_capacity(models.len());
        for c in &models {
            out.push(fitness.evaluate(c, &mut scratch));
        }
        out
    };
    let after = ALLOCATIONS.load(Ordering::Relaxed);
    // One allocation is the `out` vector above.
    assert_eq!(after - before, 1, "evaluations allocated");
    assert_eq!(first, again, "evaluation is pure");
}

#[test]
fn volume_evaluation_allocates_nothing_after_warm_up() {
    check(Spaceship, 50);
    check(TreeV2, 100);
}
