//! CPU scoring for [shapegen](https://crates.io/crates/shapegen): turns an
//! expressed model into a fitness, exactly, with no GPU.
//!
//! - Geometry: [`mesh::Mesh`] (built-in unit cube, the paper's trunk
//!   frustum, a simple leaf; OBJ loading with clear errors) and OBJ export of
//!   models ([`obj`]).
//! - Volumes: a voxel [`grid::Grid`], [`solid::Solid`]s (convex meshes as
//!   half-spaces, other meshes through an obvhs BVH), the centre-sampled
//!   span [`voxelize`]r, and [`volume`] targets combined into one weight grid
//!   with per-evaluation counts of good, bad, overlapping and out-of-grid cells.
//! - Images: the paper's orbit [`camera::Camera`] (and an orthographic one),
//!   the exact centre-sampled silhouette [`raster`]izer, and [`image`]
//!   targets (PNG sketches or signed weights) with overlay output.
//! - [`score`]: the paper's linear scores and the normalized form of its
//!   code, as `Fitness` implementations for any generator:
//!   [`score::VolumeFitness`] and [`score::ImageFitness`].
//!
//! Each fast path has a brute-force reference (`voxelize::reference`,
//! `raster::reference_coverage`) that the property tests compare it with.

#![forbid(unsafe_code)]

pub mod camera;
pub mod error;
pub mod files;
pub mod grid;
pub mod image;
pub mod mesh;
pub mod obj;
pub mod quality;
pub mod raster;
pub mod score;
pub mod solid;
pub mod volume;
pub mod voxelize;

pub use error::ScoreError;
pub use grid::Grid;
pub use mesh::{Mesh, Placement, fit_transform};
pub use obj::ShapeMeshes;
pub use quality::Quality;
pub use score::{
    ImageFitness, ImageScore, ImageTargets, ModelFitness, Scene, VolumeFitness, VolumeScore,
};
pub use solid::{Inside, Solid};
pub use voxelize::{Span, Voxelizer};
