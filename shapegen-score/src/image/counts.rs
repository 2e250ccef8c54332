//! Counting one model's silhouettes against image targets.

use glam::Affine3A;

use super::ImageTarget;
use crate::raster::{Layers, RasterShape, Rasterizer, View};

/// What one model's silhouettes cover, summed over the targets.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ImageCounts {
    /// `Σ I(p)` over covered pixels (the paper's `s_img`).
    pub weight: f64,
    /// `G`: covered pixels with positive weight.
    pub good: u64,
    /// `B`: covered pixels with negative weight.
    pub bad: u64,
}

/// Per-thread working memory: per target, how many triangles of the model
/// cover each pixel centre, and the rasterizer.
///
/// Every instance adds its triangles' edges to per-row differences of the
/// counts (see [`Rasterizer`](crate::Rasterizer)); no instance paints over
/// another. The counts are read once per model, over the part of each row
/// the model touched, and only that part is cleared for the next model, so
/// an evaluation costs what the model's silhouettes cross.
#[derive(Clone, Debug)]
pub struct ImageScratch {
    layers: Vec<Layers>,
    views: Vec<View>,
    rasterizer: Rasterizer,
}

impl ImageScratch {
    /// Working memory for `targets`.
    #[must_use]
    pub fn new(targets: &[ImageTarget]) -> Self {
        Self {
            layers: targets
                .iter()
                .map(|t| Layers::new(t.camera.width, t.camera.height))
                .collect(),
            views: targets.iter().map(|t| View::new(&t.camera)).collect(),
            rasterizer: Rasterizer::new(),
        }
    }

    /// Starts a new model.
    pub fn begin(&mut self) {
        self.layers.iter_mut().for_each(Layers::clear);
    }

    /// Adds one instance, seen by each of `targets` (those the scratch was
    /// made for; others are taken in, at the cost of preparing them).
    pub fn add(&mut self, targets: &[ImageTarget], shape: &RasterShape, transform: &Affine3A) {
        for ((target, layers), view) in targets.iter().zip(&mut self.layers).zip(&mut self.views) {
            if view.camera() != &target.camera {
                *view = View::new(&target.camera);
                if layers.size() != (target.camera.width, target.camera.height) {
                    *layers = Layers::new(target.camera.width, target.camera.height);
                }
            }
            self.rasterizer.draw(view, shape, transform, layers);
        }
    }

    /// The counts of the model added since [`begin`](Self::begin), over
    /// all targets (each covered pixel counted once per target).
    ///
    /// Reads the counts over the part of each row the model touched; the
    /// weights are summed in a fixed order, so the same model gives the
    /// same sum.
    #[must_use]
    pub fn counts_for(&self, targets: &[ImageTarget]) -> ImageCounts {
        let mut counts = ImageCounts::default();
        for (target, layers) in targets.iter().zip(&self.layers) {
            let width = target.camera.width as usize;
            let mut lanes = [0.0f64; 4];
            let (mut good, mut bad) = (0u64, 0u64);
            layers.rows(|row, c0, diff| {
                // The last cell (right of the image) counts for no pixel.
                let diff = &diff[..diff.len().min(width - c0 as usize)];
                let at = row as usize * width + c0 as usize;
                let (l, g, b) = count_row(diff, &target.weights[at..at + diff.len()]);
                for k in 0..4 {
                    lanes[k] += l[k];
                }
                (good, bad) = (good + g, bad + b);
            });
            counts.weight += (lanes[0] + lanes[1]) + (lanes[2] + lanes[3]);
            counts.good += good;
            counts.bad += bad;
        }
        counts
    }

    /// Which pixels of target `i` (row-major, row 0 at the top) the model
    /// added since [`begin`](Self::begin) covers.
    #[must_use]
    pub fn covered(&self, i: usize) -> Vec<bool> {
        let layers = &self.layers[i];
        let (w, h) = layers.size();
        let mut out = vec![false; (w * h) as usize];
        layers.covered_spans(|s| {
            out[(s.row * w + s.c0) as usize..(s.row * w + s.c1) as usize].fill(true);
        });
        out
    }
}

/// The weight sums (in four lanes), `G` and `B` of the covered pixels of
/// one row part from its count differences and weights. Kept in locals (a
/// closure adding to its caller's sums would go through memory at every
/// pixel), the weights in four independent lanes: one running sum would
/// make every covered pixel wait for the previous addition.
#[inline]
fn count_row(diff: &[i32], weights: &[f32]) -> ([f64; 4], u64, u64) {
    let mut lanes = [0.0f64; 4];
    let (mut good, mut bad) = (0u64, 0u64);
    let mut count = 0;
    let mut diff4 = diff.chunks_exact(4);
    let mut weights4 = weights.chunks_exact(4);
    for (d, wt) in (&mut diff4).zip(&mut weights4) {
        for k in 0..4 {
            count += d[k];
            let m = count > 0;
            lanes[k] += if m { f64::from(wt[k]) } else { 0.0 };
            good += u64::from(m & (wt[k] > 0.0));
            bad += u64::from(m & (wt[k] < 0.0));
        }
    }
    for (d, &wt) in diff4.remainder().iter().zip(weights4.remainder()) {
        count += d;
        let m = count > 0;
        lanes[0] += if m { f64::from(wt) } else { 0.0 };
        good += u64::from(m & (wt > 0.0));
        bad += u64::from(m & (wt < 0.0));
    }
    (lanes, good, bad)
}
