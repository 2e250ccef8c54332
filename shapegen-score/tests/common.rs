//! Shared test support: random placements and the shared data folder.
#![allow(dead_code)]

use std::ops::Range;
use std::path::PathBuf;

use glam::{Affine3A, DVec3, Quat, Vec3};
use proptest::prelude::*;
use shapegen_score::{Camera, Mesh};

/// A random placement: any rotation, a non-uniform scale with components in
/// `scale`, and a translation in the box `[lo, hi]`.
pub fn placement(scale: Range<f32>, lo: Vec3, hi: Vec3) -> impl Strategy<Value = Affine3A> {
    (
        (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0),
        (scale.clone(), scale.clone(), scale),
        (lo.x..hi.x, lo.y..hi.y, lo.z..hi.z),
    )
        .prop_map(|((a, b, c, d), (sx, sy, sz), (x, y, z))| {
            let q = Quat::from_xyzw(a, b, c, d + 1e-3).normalize();
            Affine3A::from_scale_rotation_translation(Vec3::new(sx, sy, sz), q, Vec3::new(x, y, z))
        })
}

/// A file of the repository's shared data folder (beside the checkout), if present.
pub fn shared(rel: &str) -> Option<PathBuf> {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../shared")
        .join(rel);
    p.exists().then_some(p)
}

/// A closed star-shaped prism: non-convex, 10 points, 60 triangles.
pub fn star_prism() -> Mesh {
    let n = 10u32;
    let mut positions = Vec::new();
    for z in [-0.3f32, 0.3] {
        positions.push(Vec3::new(0.0, 0.0, z));
        for i in 0..n {
            let a = i as f32 / n as f32 * std::f32::consts::TAU;
            let r = if i % 2 == 0 { 1.0 } else { 0.4 };
            positions.push(Vec3::new(r * a.cos(), r * a.sin(), z));
        }
    }
    let top = n + 1;
    let mut triangles = Vec::new();
    for i in 0..n {
        let (a, b) = (1 + i, 1 + (i + 1) % n);
        triangles.push([0, b, a]);
        triangles.push([top, top + a, top + b]);
        triangles.push([a, b, top + a]);
        triangles.push([b, top + b, top + a]);
    }
    Mesh {
        positions,
        triangles,
    }
}

/// The unit cube without one face: open, so drawn with the boundary rule.
pub fn open_box() -> Mesh {
    let mut m = Mesh::unit_cube();
    m.triangles.truncate(10);
    m
}

/// The unit cube without its ±z faces: a square tube, open at both ends
/// (convex vertices, but not a convex solid).
pub fn tube() -> Mesh {
    let mut m = Mesh::unit_cube();
    m.triangles.drain(0..4);
    m
}

/// The star prism without its top: an open, non-convex cup.
pub fn open_star() -> Mesh {
    let mut m = star_prism();
    m.triangles = m
        .triangles
        .chunks(4)
        .flat_map(|q| [q[0], q[2], q[3]])
        .collect();
    m
}

/// Two cubes of side 0.6 crossing each other in one mesh: a closed,
/// consistently wound, self-intersecting surface (like the paper's leaf,
/// whose two sheets cross).
pub fn crossing_cubes() -> Mesh {
    let cube = Mesh::unit_cube().with_welded_vertices();
    let n = cube.positions.len() as u32;
    let mut positions: Vec<Vec3> = cube.positions.iter().map(|p| *p * 0.6 - 0.1).collect();
    positions.extend(cube.positions.iter().map(|p| *p * 0.6 + 0.1));
    let mut triangles = cube.triangles.clone();
    triangles.extend(cube.triangles.iter().map(|t| t.map(|i| i + n)));
    Mesh {
        positions,
        triangles,
    }
}

/// A wavy open sheet, like a leaf blade: 8 × 8 quads, all one way round.
pub fn wavy_sheet() -> Mesh {
    let n = 9u32;
    let positions = (0..n * n)
        .map(|i| {
            let (u, v) = ((i % n) as f32 / 8.0 - 0.5, (i / n) as f32 / 8.0 - 0.5);
            Vec3::new(u, v, 0.3 * (5.0 * u).sin() * (4.0 * v).cos())
        })
        .collect();
    let mut triangles = Vec::new();
    for y in 0..n - 1 {
        for x in 0..n - 1 {
            let i = y * n + x;
            triangles.push([i, i + 1, i + n + 1]);
            triangles.push([i, i + n + 1, i + n]);
        }
    }
    Mesh {
        positions,
        triangles,
    }
}

/// The star prism with every third triangle turned round: its boundary
/// chain has edges counted twice.
pub fn mixed_orientation() -> Mesh {
    let mut m = star_prism();
    for t in m.triangles.iter_mut().step_by(3) {
        t.swap(1, 2);
    }
    m
}

/// Random cameras for exactness tests at 64×48: perspective orbits (a near
/// plane of up to 3 clips models that come close) and orthographic views.
pub fn camera() -> impl Strategy<Value = Camera> {
    prop_oneof![
        (-3.2f64..3.2, -1.2f64..1.2, 2.0f64..8.0, 0.05f64..3.0).prop_map(
            |(phi, theta, r, near)| {
                Camera::orbit(
                    phi,
                    theta,
                    r,
                    DVec3::ZERO,
                    60f64.to_radians(),
                    near,
                    near + 6.0,
                    (64, 48),
                )
                .unwrap()
            }
        ),
        (-1.0f64..1.0, -1.0f64..1.0).prop_map(|(x, y)| {
            Camera::orthographic(
                DVec3::new(x, y, -6.0),
                DVec3::Z,
                DVec3::Y,
                6.0,
                0.1,
                12.0,
                (64, 48),
            )
            .unwrap()
        }),
    ]
}
