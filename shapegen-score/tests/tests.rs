//! The scoring crate's integration tests, in one binary: one module per area.

/// Random placements and test meshes shared by the others.
mod common;

/// Image targets: PNG sketches and masks, counts against brute-force coverage.
mod image;
/// Mesh topology: welding and the boundary chain against map-based definitions.
mod mesh;
/// The silhouette rasterizer against per-pixel ray casting.
mod raster;
/// Every mesh of `../shared/data` voxelized at 128³ (skipped without the data).
mod real_data;
/// The renderer's G-buffer against the rasterizer and ray casting.
mod render;
/// View attributes by hand and best views with a known answer.
mod views;
/// Volume counts and scores against per-voxel references.
mod volume;
/// The span voxelizer against per-voxel references.
mod voxelize;
