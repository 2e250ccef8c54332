//! CPU scoring for [shapegen](https://crates.io/crates/shapegen): turns an
//! expressed model into a fitness, exactly, with no GPU.
//!
//! Every item is at the crate's root; the modules behind them, one per
//! concern:
//!
//! - Geometry: [`Mesh`] (built-in unit cube, the paper's trunk frustum, a
//!   simple leaf; OBJ loading with clear errors, [`Placement`]), the
//!   [`ShapeMeshes`] of a generator's shapes, and OBJ export of models
//!   ([`write_obj`], [`write_model`]).
//! - Volume scenes: a voxel [`Grid`]; [`Solid`]s (convex meshes as
//!   half-spaces, other meshes as placed triangles, [`RowTri`]); the
//!   centre-sampled span [`Voxelizer`] (analytic rows for convex solids, a
//!   scanline over the triangles for other meshes, the winding number for
//!   meshes with holes); [`VolumeScene`]: targets combined into one weight
//!   grid, [`VolumeScratch`] counts of good, bad, overlapping and
//!   out-of-grid cells, and the paper's [`VolumeScore`]s.
//! - Image scenes: the paper's orbit [`Camera`] (and an orthographic one),
//!   the exact centre-sampled silhouette [`Rasterizer`], [`ImageTarget`]s
//!   (PNG sketches or signed weights) with overlays, [`ImageTargets`] and
//!   the paper's [`ImageScore`]s.
//! - Pictures: a z-buffered [`Renderer`] of expressed models into a
//!   [`GBuffer`] (depth, face, normal, terminal type per pixel; the same
//!   covered pixels as the [`Rasterizer`]), shaded with three-point
//!   [`Lights`] in a [`Style`]; cameras fitted to a model's
//!   [`BoundingSphere`]; the thesis's eight [`ViewAttributes`] of a render
//!   and the [`best_view`] of a model.
//! - [`ModelFitness`]: a generator's models scored against either scene, the
//!   `Fitness` the optimizers run ([`VolumeFitness`], [`ImageFitness`]).
//!
//! Each fast path has a brute-force [`reference`](mod@reference) that the property tests
//! compare it with.

#![forbid(unsafe_code)]

mod camera;
mod error;
mod files;
mod fitness;
mod grid;
mod image;
mod instance_cache;
mod mesh;
mod obj;
mod quality;
mod raster;
mod render;
mod shapes;
mod solid;
mod views;
mod volume;
mod voxelize;

pub use camera::{Camera, Projection, Projector};
pub use error::ScoreError;
pub use files::{png_bytes, write_atomically, write_png, write_png_rgba};
pub use fitness::{ImageFitness, ModelFitness, Scene, VolumeFitness, smootherstep};
pub use grid::Grid;
pub use image::{
    ImageCounts, ImageScore, ImageScratch, ImageTarget, ImageTargets, MAX_DECODE_BYTES, PngMask,
};
pub use mesh::{Mesh, Placement, fit_transform};
pub use obj::{write_model, write_obj};
pub use quality::Quality;
pub use raster::{PixelSpan, RasterShape, Rasterizer};
pub use render::{
    Background, BoundingSphere, Face, GBuffer, Light, Lights, Palette, RenderMeshes, Renderer,
    Shading, Style, fit_camera, fit_orthographic, frame_tightly,
};
pub use shapes::ShapeMeshes;
pub use solid::{Convex, Inside, MeshSolid, RowLine, RowTri, Solid, Winding, solid_angle};
pub use views::{
    ATTRIBUTE_NAMES, AttributeWeights, BestView, ViewAttributes, ViewSampling, Viewpoint,
    best_view, best_view_around, normalize_columns,
};
pub use volume::{
    OutsideCount, OverlapCount, VolumeCounts, VolumeScene, VolumeScore, VolumeScratch,
    VolumeTarget, aabb_cells_outside,
};
pub use voxelize::{Span, Voxelizer};

/// Slow, obviously correct versions of the fast paths, for tests and
/// debugging: voxel cells decided one by one, winding numbers summed over
/// every triangle, pixel coverage by one ray per pixel.
pub mod reference {
    pub use crate::raster::reference_coverage;
    pub use crate::voxelize::reference::{
        cells_by_parity, cells_by_planes, mesh_cells_by_row_parity, winding_numbers,
    };
}
