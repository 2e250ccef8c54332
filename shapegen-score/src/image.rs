//! Image targets: signed weights per pixel seen through a camera, PNG
//! sketches, counting a model's silhouette against them, and overlays.

use std::path::Path;

use glam::Affine3A;

use crate::camera::Camera;
use crate::error::ScoreError;
use crate::raster::{Canvas, PixelRect, PixelSpan, RasterShape, Rasterizer};

/// One image target: a signed weight per pixel, seen through `camera`.
/// Positive weights attract the silhouette, negative repel, zero is "don't care".
#[derive(Clone, Debug, PartialEq)]
pub struct ImageTarget {
    /// The camera (its size is the image's).
    pub camera: Camera,
    /// Row-major weights, `width × height`, row 0 at the top.
    pub weights: Vec<f32>,
}

impl ImageTarget {
    /// A target from weights; fails if their count does not match the camera's image size.
    pub fn new(camera: Camera, weights: Vec<f32>) -> Result<Self, ScoreError> {
        let n = (camera.width * camera.height) as usize;
        if weights.len() != n {
            return Err(ScoreError::Target(format!(
                "{} weights for a {}×{} camera",
                weights.len(),
                camera.width,
                camera.height
            )));
        }
        if weights.iter().any(|w| !w.is_finite()) {
            return Err(ScoreError::Target("image weights must be finite".into()));
        }
        Ok(Self { camera, weights })
    }

    /// A target from a PNG sketch: pixels whose red channel is exactly 0
    /// are target (weight `target`), all others background (weight
    /// `background`, e.g. negative). The PNG must have the camera's size.
    pub fn from_png(
        path: &Path,
        camera: Camera,
        target: f32,
        background: f32,
    ) -> Result<Self, ScoreError> {
        let bad = |reason: String| ScoreError::Image {
            path: path.to_path_buf(),
            reason,
        };
        let img = image::open(path).map_err(|e| bad(e.to_string()))?.to_rgb8();
        if (img.width(), img.height()) != (camera.width, camera.height) {
            return Err(bad(format!(
                "the image is {}×{} but the camera renders {}×{}",
                img.width(),
                img.height(),
                camera.width,
                camera.height
            )));
        }
        let weights = img
            .pixels()
            .map(|p| if p.0[0] == 0 { target } else { background })
            .collect();
        Self::new(camera, weights)
    }

    /// A target from a float image in PFM format (the paper's signed float
    /// images): each pixel's value (the first channel of a colour `PF` file)
    /// is its weight. The image must have the camera's size; PFM stores rows
    /// bottom to top, the target keeps row 0 at the top.
    pub fn from_pfm(path: &Path, camera: Camera) -> Result<Self, ScoreError> {
        let bytes = std::fs::read(path).map_err(|source| ScoreError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let weights = read_pfm(&bytes, (camera.width, camera.height)).map_err(|reason| {
            ScoreError::Image {
                path: path.to_path_buf(),
                reason,
            }
        })?;
        Self::new(camera, weights)
    }

    /// Pixels with positive weight.
    #[must_use]
    pub fn target_pixels(&self) -> u64 {
        self.weights.iter().filter(|&&w| w > 0.0).count() as u64
    }

    /// Writes a PNG of target and model: target only in light blue, model
    /// only in red, both in green (0, 128, 0), the rest white.
    pub fn write_overlay(&self, path: &Path, covered: &[bool]) -> Result<(), ScoreError> {
        let (w, h) = (self.camera.width, self.camera.height);
        let img = image::RgbImage::from_fn(w, h, |c, r| {
            let i = (r * w + c) as usize;
            let (t, m) = (
                self.weights[i] > 0.0,
                covered.get(i).copied().unwrap_or(false),
            );
            image::Rgb(match (t, m) {
                (true, true) => [0, 128, 0],
                (true, false) => [150, 190, 240],
                (false, true) => [220, 40, 40],
                (false, false) => [255, 255, 255],
            })
        });
        img.save(path).map_err(|e| ScoreError::Image {
            path: path.to_path_buf(),
            reason: e.to_string(),
        })
    }
}

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

/// Per-thread working memory: a coverage mask per target (all clear between
/// evaluations), the extent of the covered part of each row, and the rasterizer.
///
/// Spans only set mask bytes and widen their row's extent; the counts are
/// taken once per model over the extents, and only they are cleared for the
/// next model, so an evaluation costs what the model covers. An instance
/// whose pixels are all covered already is not filled at all (see
/// [`hidden`](Self::hidden)): in a tree, most branches inside the canopy.
#[derive(Clone, Debug)]
pub struct ImageScratch {
    masks: Vec<Mask>,
    rasterizer: Rasterizer,
    /// Instances (per target) skipped since `begin` because every pixel
    /// they could cover already was.
    hidden: u64,
}

/// The coverage of one target.
#[derive(Clone, Debug)]
struct Mask {
    covered: Vec<bool>,
    /// Per row, the covered columns lie in `extent.0..extent.1` (empty: `(u32::MAX, 0)`).
    extent: Vec<(u32, u32)>,
    /// Rows with a non-empty extent.
    rows: Vec<u32>,
    width: u32,
}

impl Mask {
    fn new(width: u32, height: u32) -> Self {
        Self {
            covered: vec![false; (width * height) as usize],
            extent: vec![(u32::MAX, 0); height as usize],
            rows: Vec::new(),
            width,
        }
    }

    fn clear(&mut self) {
        for &r in &self.rows {
            let (c0, c1) = self.extent[r as usize];
            let base = (r * self.width) as usize;
            self.covered[base + c0 as usize..base + c1 as usize].fill(false);
            self.extent[r as usize] = (u32::MAX, 0);
        }
        self.rows.clear();
    }

    /// Adds the covered pixels' counts. The weights are summed in four
    /// independent lanes (then added in a fixed order): one running sum
    /// would make every covered pixel wait for the previous addition.
    fn count(&self, weights: &[f32], counts: &mut ImageCounts) {
        let mut lanes = [0.0f64; 4];
        let (mut good, mut bad) = (0u64, 0u64);
        let mut add = |lane: &mut f64, m: bool, wt: f32| {
            *lane += if m { f64::from(wt) } else { 0.0 };
            good += u64::from(m & (wt > 0.0));
            bad += u64::from(m & (wt < 0.0));
        };
        for &r in &self.rows {
            let (c0, c1) = self.extent[r as usize];
            let (a, b) = (
                (r * self.width + c0) as usize,
                (r * self.width + c1) as usize,
            );
            let mut covered = self.covered[a..b].chunks_exact(4);
            let mut wts = weights[a..b].chunks_exact(4);
            for (m, wt) in (&mut covered).zip(&mut wts) {
                for k in 0..4 {
                    add(&mut lanes[k], m[k], wt[k]);
                }
            }
            for (&m, &wt) in covered.remainder().iter().zip(wts.remainder()) {
                add(&mut lanes[0], m, wt);
            }
        }
        counts.weight += (lanes[0] + lanes[1]) + (lanes[2] + lanes[3]);
        counts.good += good;
        counts.bad += bad;
    }
}

impl Canvas for Mask {
    #[inline]
    fn cover(&mut self, s: PixelSpan) {
        let e = &mut self.extent[s.row as usize];
        if e.0 == u32::MAX {
            self.rows.push(s.row);
        }
        *e = (e.0.min(s.c0), e.1.max(s.c1));
        let base = (s.row * self.width) as usize;
        self.covered[base + s.c0 as usize..base + s.c1 as usize].fill(true);
    }

    fn covers(&self, rect: PixelRect) -> bool {
        let (c0, c1) = rect.cols;
        (rect.rows.0..rect.rows.1).all(|r| {
            let base = (r * self.width) as usize;
            !self.covered[base + c0 as usize..base + c1 as usize].contains(&false)
        })
    }
}

impl ImageScratch {
    /// Working memory for `targets`.
    #[must_use]
    pub fn new(targets: &[ImageTarget]) -> Self {
        Self {
            masks: targets
                .iter()
                .map(|t| Mask::new(t.camera.width, t.camera.height))
                .collect(),
            rasterizer: Rasterizer::new(),
            hidden: 0,
        }
    }

    /// Starts a new model.
    pub fn begin(&mut self) {
        self.masks.iter_mut().for_each(Mask::clear);
        self.hidden = 0;
    }

    /// Adds one instance.
    pub fn add(&mut self, targets: &[ImageTarget], shape: &RasterShape, transform: &Affine3A) {
        for (target, mask) in targets.iter().zip(&mut self.masks) {
            // An instance whose pixels are all covered adds nothing (the
            // coverage is a union): a branch inside a canopy is not filled.
            let drawn = self.rasterizer.draw(&target.camera, shape, transform, mask);
            self.hidden += u64::from(!drawn);
        }
    }

    /// The counts of the model added since [`begin`](Self::begin), over
    /// all targets (each covered pixel counted once per target).
    #[must_use]
    pub fn counts_for(&self, targets: &[ImageTarget]) -> ImageCounts {
        let mut counts = ImageCounts::default();
        for (target, mask) in targets.iter().zip(&self.masks) {
            mask.count(&target.weights, &mut counts);
        }
        counts
    }

    /// How many instances (counted once per target) added since
    /// [`begin`](Self::begin) were not filled because every pixel they
    /// can reach (off the image: none) was already covered, so that they
    /// could not change the coverage.
    #[must_use]
    pub fn hidden(&self) -> u64 {
        self.hidden
    }

    /// The coverage mask of target `i`.
    #[must_use]
    pub fn covered(&self, i: usize) -> &[bool] {
        &self.masks[i].covered
    }
}

/// Parses a PFM image of `size` into row-major values, row 0 at the top.
fn read_pfm(bytes: &[u8], size: (u32, u32)) -> Result<Vec<f32>, String> {
    // Header: three whitespace-separated tokens ("Pf"/"PF", "W H", scale), one byte, data.
    let mut tokens = Vec::new();
    let mut at = 0;
    while tokens.len() < 4 {
        while at < bytes.len() && bytes[at].is_ascii_whitespace() {
            at += 1;
        }
        let start = at;
        while at < bytes.len() && !bytes[at].is_ascii_whitespace() {
            at += 1;
        }
        if start == at {
            return Err("truncated PFM header".into());
        }
        tokens.push(String::from_utf8_lossy(&bytes[start..at]).into_owned());
    }
    at += 1; // the single whitespace byte before the data
    let channels = match tokens[0].as_str() {
        "Pf" => 1,
        "PF" => 3,
        other => return Err(format!("not a PFM file (magic `{other}`)")),
    };
    let number = |t: &str| {
        t.parse::<f64>()
            .map_err(|_| format!("bad PFM header value `{t}`"))
    };
    let (w, h, scale) = (
        number(&tokens[1])?,
        number(&tokens[2])?,
        number(&tokens[3])?,
    );
    if (w, h) != (f64::from(size.0), f64::from(size.1)) {
        return Err(format!(
            "the image is {w}×{h} but the camera renders {}×{}",
            size.0, size.1
        ));
    }
    if scale == 0.0 || !scale.is_finite() {
        return Err(format!("bad PFM scale {scale}"));
    }
    let (w, h) = (size.0 as usize, size.1 as usize);
    let data = bytes.get(at.min(bytes.len())..).unwrap_or_default();
    if data.len() < w * h * channels * 4 {
        return Err(format!(
            "{} bytes of pixel data, {} needed",
            data.len(),
            w * h * channels * 4
        ));
    }
    let value = |i: usize| {
        let b: [u8; 4] = data[4 * i..4 * i + 4].try_into().expect("four bytes");
        if scale < 0.0 {
            f32::from_le_bytes(b)
        } else {
            f32::from_be_bytes(b)
        }
    };
    let mut out = Vec::with_capacity(w * h);
    for row in (0..h).rev() {
        out.extend((0..w).map(|c| value((row * w + c) * channels)));
    }
    Ok(out)
}

#[cfg(test)]
mod pfm_tests {
    use super::read_pfm;

    #[test]
    fn reads_grey_and_colour_pfm_bottom_up() {
        let mut grey = b"Pf\n2 2\n-1.0\n".to_vec();
        for v in [1.0f32, 2.0, 3.0, 4.0] {
            grey.extend(v.to_le_bytes());
        }
        assert_eq!(read_pfm(&grey, (2, 2)).unwrap(), [3.0, 4.0, 1.0, 2.0]);
        let mut colour = b"PF 1 1 1.0 ".to_vec();
        for v in [-0.5f32, 9.0, 9.0] {
            colour.extend(v.to_be_bytes());
        }
        assert_eq!(read_pfm(&colour, (1, 1)).unwrap(), [-0.5]);
        assert!(read_pfm(&grey, (3, 2)).unwrap_err().contains("camera"));
        assert!(read_pfm(&grey[..20], (2, 2)).unwrap_err().contains("bytes"));
        assert!(
            read_pfm(b"P6 1 1 255 x", (1, 1))
                .unwrap_err()
                .contains("magic")
        );
        assert!(read_pfm(b"Pf 1", (1, 1)).unwrap_err().contains("truncated"));
    }
}
