//! CPU scoring for shapegen: solid voxelization, silhouette rasterization
//! and the paper's volume and image fitness functions.
//!
//! Not implemented yet: this crate is the scoring milestone. Until then, any
//! `shapegen_core::optimize::Fitness` implementation can drive the optimizers.
