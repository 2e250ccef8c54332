//! Exactness of the silhouette rasterizer against per-pixel ray casting.

use crate::common::{
    camera, mixed_orientation, open_box, open_star, placement, star_prism, tube, wavy_sheet,
};
use glam::{Affine3A, Vec3};
use proptest::prelude::*;
use shapegen_score::Camera;
use shapegen_score::Mesh;
use shapegen_score::{RasterShape, Rasterizer, reference::reference_coverage};

/// Two disjoint cubes: a non-convex mesh, filled from its contour (or triangle by triangle when clipped).
fn two_cubes() -> Mesh {
    let mut m = Mesh::unit_cube();
    let n = m.positions.len() as u32;
    let second: Vec<Vec3> = m
        .positions
        .iter()
        .map(|p| *p * 0.5 + Vec3::new(1.2, 0.3, 0.0))
        .collect();
    let tris: Vec<[u32; 3]> = m.triangles.iter().map(|t| t.map(|i| i + n)).collect();
    m.positions.extend(second);
    m.triangles.extend(tris);
    m
}

/// Three boxes (36 triangles).
fn three_cubes() -> Mesh {
    let mut m = two_cubes();
    let n = m.positions.len() as u32;
    let cube = Mesh::unit_cube();
    m.positions.extend(
        cube.positions
            .iter()
            .map(|p| *p * Vec3::new(0.3, 1.4, 0.6) + Vec3::new(-0.9, 0.2, 0.4)),
    );
    m.triangles
        .extend(cube.triangles.iter().map(|t| t.map(|i| i + n)));
    m
}

/// The rasterizer's pixels of `instances` are exactly those of per-pixel ray casting.
fn equals_ray_casting(
    cam: &Camera,
    instances: &[(&RasterShape, Affine3A)],
) -> Result<(), TestCaseError> {
    let mut fast = vec![false; (cam.width * cam.height) as usize];
    let mut rasterizer = Rasterizer::new();
    for (shape, t) in instances {
        rasterizer.spans(cam, shape, t, |s| {
            for c in s.c0..s.c1 {
                fast[(s.row * cam.width + c) as usize] = true;
            }
        });
    }
    let slow = reference_coverage(cam, instances);
    let differ: Vec<usize> = (0..fast.len()).filter(|&i| fast[i] != slow[i]).collect();
    prop_assert!(
        differ.is_empty(),
        "{} pixels differ, e.g. {:?}",
        differ.len(),
        &differ[..differ.len().min(5)]
    );
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

    #[test]
    fn silhouettes_equal_ray_casting(cam in camera(), placements in proptest::collection::vec((placement(0.2..2.0, Vec3::splat(-2.0), Vec3::splat(2.0)), 0usize..6), 1..4)) {
        let shapes = [Mesh::unit_cube(), Mesh::trunk(), Mesh::leaf(), two_cubes(), three_cubes(), star_prism()]
            .map(|m| RasterShape::new("shape", &m).unwrap());
        let instances: Vec<(&RasterShape, Affine3A)> = placements.iter().map(|(t, k)| (&shapes[*k], *t)).collect();
        equals_ray_casting(&cam, &instances)?;
    }
}

/// Open meshes (filled from their contour, which includes their own
/// boundary, when wholly in the depth range) and the paper's leaf, if the
/// shared data is present.
fn open_shapes() -> Vec<RasterShape> {
    let mut meshes = vec![
        open_box(),
        open_star(),
        wavy_sheet(),
        mixed_orientation(),
        tube(),
    ];
    if let Some(leaf) = crate::common::shared("data/paper/leaf.obj") {
        meshes.push(Mesh::load_obj(&leaf).unwrap().normalized());
    }
    meshes
        .iter()
        .map(|m| RasterShape::new("shape", m).unwrap())
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    #[test]
    fn open_mesh_silhouettes_equal_ray_casting(cam in camera(), placements in proptest::collection::vec((placement(0.2..2.0, Vec3::splat(-2.0), Vec3::splat(2.0)), 0usize..6), 1..3)) {
        let shapes = open_shapes();
        let instances: Vec<(&RasterShape, Affine3A)> = placements.iter().map(|(t, k)| (&shapes[*k % shapes.len()], *t)).collect();
        equals_ray_casting(&cam, &instances)?;
    }
}
