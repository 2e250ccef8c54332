//! Shared test support: random placements and the shared data folder.
#![allow(dead_code)]

use std::ops::Range;
use std::path::PathBuf;

use glam::{Affine3A, Quat, Vec3};
use proptest::prelude::*;

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
