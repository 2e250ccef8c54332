//! CPU scoring for [shapegen](https://crates.io/crates/shapegen).
//!
//! So far this crate holds the geometry the generators instance: the
//! built-in [`mesh::Mesh`]es (unit cube, the paper's trunk frustum, a simple
//! leaf) and OBJ export of expressed models ([`obj`]). Voxel and silhouette
//! scoring against volume and image targets are the next milestone.

#![forbid(unsafe_code)]

pub mod camera;
pub mod error;
pub mod grid;
pub mod image;
pub mod mesh;
pub mod obj;
pub mod raster;
pub mod score;
pub mod solid;
pub mod volume;
pub mod voxelize;

pub use error::ScoreError;
pub use grid::Grid;
pub use mesh::Mesh;
pub use solid::Solid;
pub use voxelize::{Span, Voxelizer};
