//! Image scenes: targets seen through cameras (PNG sketches or signed
//! weights), a model's silhouettes counted against them, the paper's image
//! scores, and overlays.

mod counts;
mod score;
mod target;

pub use counts::{ImageCounts, ImageScratch};
pub use score::{ImageScore, ImageTargets};
pub use target::{ImageTarget, MAX_DECODE_BYTES, PngMask};
