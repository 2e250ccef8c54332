//! Built-in problems that need no files.
//!
//! - [`spaceship_target`]: a ship-shaped volume made of boxes, the target of
//!   `cargo run` (the paper's spaceship generator evolves toward it).
//! - The *blocks* problem, with a known optimum, used by the tests.
//!
//! The *blocks* generator grows a binary tree of blocks, each with a
//! parameter `x` in `[0, 1]`. The [`BlocksTarget`] fitness asks for exactly
//! `n` blocks, each with `x = 0.5`:
//!
//! `F = (Σ_i exp(−((x_i − 0.5) / 0.1)²) − 2 |blocks − n|) / n`
//!
//! Its optimum, reached only by `n` blocks all at `x = 0.5`, is exactly 1.

pub use shapegen_core::demo::{BlocksTarget, blocks_graph};

use crate::glam::Vec3;
use crate::score::Mesh;
use crate::score::VolumeTarget;

/// The built-in target of `cargo run`: a ship-shaped volume (a hull along +z
/// with a cockpit on top and wings on both sides), as abutting boxes, one
/// [`VolumeTarget`] each (filled with weight 1, nothing penalized outside).
#[must_use]
pub fn spaceship_target() -> Vec<VolumeTarget> {
    // (centre, size) of each box, in world units; z is the ship's length.
    let boxes = [
        (Vec3::new(0.0, 0.0, 3.0), Vec3::new(1.6, 1.0, 6.0)), // hull
        (Vec3::new(0.0, 0.9, 2.5), Vec3::new(0.8, 0.8, 1.6)), // cockpit
        (Vec3::new(1.8, 0.0, 2.0), Vec3::new(2.0, 0.3, 2.4)), // right wing
        (Vec3::new(-1.8, 0.0, 2.0), Vec3::new(2.0, 0.3, 2.4)), // left wing
    ];
    boxes
        .iter()
        .enumerate()
        .map(|(i, &(centre, size))| {
            let mut mesh = Mesh::unit_cube();
            for p in &mut mesh.positions {
                *p = *p * size + centre;
            }
            VolumeTarget {
                name: format!("ship part {i}"),
                mesh,
                fill: 1.0,
                outside: 0.0,
                inside: Default::default(),
            }
        })
        .collect()
}
