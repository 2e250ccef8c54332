//! Volume targets and counting a model's voxels against them.
//!
//! Targets are voxelized once, with the same centre-sampled routine as the
//! model, and combined into one weight per cell as the paper does:
//! `C(v) = Σ_i (w_i · V_i(v) + w̃_i · (1 − V_i(v)))`. Evaluating a model
//! voxelizes each instance as it is emitted and accumulates the counts the
//! scores need; only the touched cells are reset afterwards, so an
//! evaluation costs what the model covers, not the grid's size.

mod counts;
mod score;
mod slice;
mod target;

pub use counts::{VolumeCounts, VolumeScratch, aabb_cells_outside};
pub use score::{OverlapCount, VolumeScore};
pub use target::{OutsideCount, VolumeScene, VolumeTarget};
