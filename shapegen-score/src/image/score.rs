//! The paper's image scores, and image targets as a [`Scene`].

use glam::Affine3A;
use shapegen_core::express::ShapeId;
use shapegen_core::graph::Limits;

use super::{ImageCounts, ImageScratch, ImageTarget};
use crate::error::ScoreError;
use crate::fitness::{Scene, smootherstep};
use crate::mesh::Mesh;
use crate::raster::RasterShape;

/// Which image score, with its weights.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ImageScore {
    /// The paper's linear score `s_img = Σ_i Σ_p covered_i(p) · I_i(p)`.
    Linear,
    /// The normalized form: `w_g·S(0,T,G) − w_b·S(0,T,B) − w_l·S(L_min,L_max,L)`.
    Normalized {
        /// `w_good`.
        w_good: f64,
        /// `w_bad`.
        w_bad: f64,
        /// `w_length`.
        w_length: f64,
    },
}

impl ImageScore {
    /// The score of a model with `counts`, `len` genes, and `t` target pixels.
    #[must_use]
    pub fn score(&self, counts: &ImageCounts, t: u64, len: usize, limits: &Limits) -> f64 {
        match *self {
            Self::Linear => counts.weight,
            Self::Normalized {
                w_good,
                w_bad,
                w_length,
            } => {
                let t = t as f64;
                let length = limits.max_len.map_or(0.0, |m| {
                    smootherstep(f64::from(limits.min_len), f64::from(m), len as f64)
                });
                w_good * smootherstep(0.0, t, counts.good as f64)
                    - w_bad * smootherstep(0.0, t, counts.bad as f64)
                    - w_length * length
            }
        }
    }
}

/// One or more image targets (each an image with its camera).
#[derive(Clone, Debug)]
pub struct ImageTargets {
    targets: Vec<ImageTarget>,
    target_pixels: u64,
}

impl ImageTargets {
    /// The targets; fails if there are none.
    pub fn new(targets: Vec<ImageTarget>) -> Result<Self, ScoreError> {
        if targets.is_empty() {
            return Err(ScoreError::Target(
                "an image scene needs at least one target".into(),
            ));
        }
        let target_pixels = targets.iter().map(ImageTarget::target_pixels).sum();
        Ok(Self {
            targets,
            target_pixels,
        })
    }

    /// The targets.
    #[must_use]
    pub fn targets(&self) -> &[ImageTarget] {
        &self.targets
    }

    /// `T`: pixels with positive weight, over all targets.
    #[must_use]
    pub fn target_pixels(&self) -> u64 {
        self.target_pixels
    }

    /// Per target: how the model in `scratch` (right after it was counted)
    /// covers its pixels of positive weight.
    #[must_use]
    pub fn quality(&self, scratch: &ImageScratch) -> Vec<crate::Quality> {
        self.targets
            .iter()
            .enumerate()
            .map(|(i, t)| {
                let covered = scratch.covered(i);
                let (mut both, mut model) = (0u64, 0u64);
                for (&c, &w) in covered.iter().zip(t.weights()) {
                    model += u64::from(c);
                    both += u64::from(c && w > 0.0);
                }
                crate::Quality::from_counts(both, model, t.target_pixels())
            })
            .collect()
    }
}

impl Scene for ImageTargets {
    type Shape = RasterShape;
    type Scratch = ImageScratch;
    type Counts = ImageCounts;
    type Score = ImageScore;

    fn prepare(&self, name: &str, mesh: &Mesh) -> Result<RasterShape, ScoreError> {
        RasterShape::new(name, mesh)
    }
    fn scratch(&self) -> ImageScratch {
        ImageScratch::new(&self.targets)
    }
    fn begin(scratch: &mut ImageScratch) {
        scratch.begin();
    }
    fn forget(scratch: &mut ImageScratch) {
        scratch.forget();
    }
    fn add(
        &self,
        scratch: &mut ImageScratch,
        id: ShapeId,
        shape: &RasterShape,
        transform: &Affine3A,
    ) {
        scratch.add_shape(&self.targets, id, shape, transform);
    }
    fn counts(&self, scratch: &ImageScratch) -> ImageCounts {
        scratch.counts_for(&self.targets)
    }
    fn score(&self, score: &ImageScore, counts: &ImageCounts, len: usize, limits: &Limits) -> f64 {
        score.score(counts, self.target_pixels, len, limits)
    }
}
