//! Image targets: signed weights per pixel seen through a camera, from PNG
//! sketches, masks or weight files; overlays of a model on them.

use std::path::Path;

use crate::camera::Camera;
use crate::error::ScoreError;
use crate::raster::WORD;

/// The most memory decoding one target image may take (a 16-bit RGBA
/// image of 8192 × 4096 pixels).
pub const MAX_DECODE_BYTES: u64 = 512 << 20;

/// Which pixels of a PNG are target. Every rule reads transparency: the
/// colour rules see each pixel composited over white, so a transparent
/// pixel is never target by its colour alone.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PngMask {
    /// Red channel exactly 0 (after compositing over white): the paper's
    /// sketches (black or blue strokes on white).
    Red0,
    /// Luminance (Rec. 709, of the colour composited over white) below
    /// `threshold` in `[0, 1]`: a dark drawing or shaded render on a light
    /// background.
    Dark {
        /// Luminance threshold (0.5 is a good default).
        threshold: f32,
    },
    /// Opacity at least `threshold` in `[0, 1]`, whatever the colour: a
    /// cut-out on a transparent background.
    Alpha {
        /// Opacity threshold (0.5 is a good default).
        threshold: f32,
    },
    /// Opaque (opacity at least ½) and dark (luminance of the colour itself
    /// below `threshold`): dark strokes on a transparent background with
    /// light opaque parts that are not target.
    AlphaDark {
        /// Luminance threshold (0.5 is a good default).
        threshold: f32,
    },
}

impl PngMask {
    /// The rule's name in experiment files (`red0`, `dark`, `alpha`, `alpha_dark`).
    #[must_use]
    pub fn name(&self) -> &'static str {
        match self {
            Self::Red0 => "red0",
            Self::Dark { .. } => "dark",
            Self::Alpha { .. } => "alpha",
            Self::AlphaDark { .. } => "alpha_dark",
        }
    }

    /// Whether an RGBA pixel is target.
    #[must_use]
    pub fn selects(&self, [r, g, b, a]: [u8; 4]) -> bool {
        let unit = |c: u8| f32::from(c) / 255.0;
        let alpha = unit(a);
        // Over white: c' = α c + (1 − α).
        let over_white = |c: u8| alpha * unit(c) + (1.0 - alpha);
        let luminance = |r: f32, g: f32, b: f32| 0.2126 * r + 0.7152 * g + 0.0722 * b;
        match *self {
            // Exactly 0 over white needs an opaque pixel with red 0.
            Self::Red0 => a == 255 && r == 0,
            Self::Dark { threshold } => {
                luminance(over_white(r), over_white(g), over_white(b)) < threshold
            }
            Self::Alpha { threshold } => alpha >= threshold,
            Self::AlphaDark { threshold } => {
                alpha >= 0.5 && luminance(unit(r), unit(g), unit(b)) < threshold
            }
        }
    }

    fn hint(&self) -> &'static str {
        match self {
            Self::Red0 => {
                "the paper's rule wants strokes with red 0 on white; for a drawing or render use mask = \"dark\", for a transparent background mask = \"alpha\""
            }
            Self::Dark { .. } | Self::AlphaDark { .. } => {
                "change `threshold` (luminance 0 to 1), or use mask = \"alpha\" for a cut-out on a transparent background"
            }
            Self::Alpha { .. } => {
                "the image has no transparent (or no opaque) part: use mask = \"dark\" or \"red0\""
            }
        }
    }
}

/// One image target: a signed weight per pixel, seen through `camera`.
/// Positive weights attract the silhouette, negative repel, zero is "don't care".
#[derive(Clone, Debug, PartialEq)]
pub struct ImageTarget {
    camera: Camera,
    weights: Vec<f32>,
    /// The weights as bit masks, if they take few values.
    classes: Option<WeightClasses>,
}

/// Distinct non-zero weights a target may have for [`WeightClasses`].
pub(crate) const CLASSES: usize = 4;

/// A target's weights as one bit mask a distinct non-zero weight, when
/// there are at most [`CLASSES`] of them (a sketch has two: its target and
/// background weights): the weights of covered pixels are then counted 64
/// pixels at a time, by class.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct WeightClasses {
    /// The weight of each class (unused classes: 0, with empty masks).
    pub(crate) values: [f32; CLASSES],
    /// Per word of the image (rows of `⌈width / 64⌉` words, bit `c % 64`
    /// of word `c / 64` for column `c`), the mask of each class.
    pub(crate) masks: Vec<[u64; CLASSES]>,
}

impl WeightClasses {
    /// The classes of `weights` (`width` a row), if they are few enough.
    fn new(width: u32, weights: &[f32]) -> Option<Self> {
        let mut values: Vec<f32> = Vec::with_capacity(CLASSES);
        for &w in weights {
            // Bit equality: −0 is a zero weight too, and is skipped.
            if w != 0.0 && !values.iter().any(|v| v.to_bits() == w.to_bits()) {
                if values.len() == CLASSES {
                    return None;
                }
                values.push(w);
            }
        }
        let (word, row_len) = (WORD as usize, (width as usize).max(1));
        let words = row_len.div_ceil(word);
        let mut masks = vec![[0u64; CLASSES]; words * (weights.len() / row_len)];
        for (row, ws) in weights.chunks_exact(row_len).enumerate() {
            for (c, &w) in ws.iter().enumerate() {
                if let Some(k) = values.iter().position(|v| v.to_bits() == w.to_bits()) {
                    masks[row * words + c / word][k] |= 1 << (c % word);
                }
            }
        }
        let mut all = [0.0; CLASSES];
        all[..values.len()].copy_from_slice(&values);
        Some(Self { values: all, masks })
    }
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
        let classes = WeightClasses::new(camera.width, &weights);
        Ok(Self {
            camera,
            weights,
            classes,
        })
    }

    /// The camera (its size is the image's).
    #[must_use]
    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    /// Row-major weights, `width × height`, row 0 at the top.
    #[must_use]
    pub fn weights(&self) -> &[f32] {
        &self.weights
    }

    /// The weights as bit masks, if they take at most [`CLASSES`] non-zero
    /// values.
    pub(crate) fn classes(&self) -> Option<&WeightClasses> {
        self.classes.as_ref()
    }

    /// A target from a PNG sketch with the paper's rule ([`PngMask::Red0`]):
    /// pixels whose red channel is exactly 0 are target (weight `target`),
    /// all others background (weight `background`, e.g. negative).
    pub fn from_png(
        path: &Path,
        camera: Camera,
        target: f32,
        background: f32,
    ) -> Result<Self, ScoreError> {
        Self::from_png_masked(path, camera, PngMask::Red0, target, background)
    }

    /// A target from a PNG: the pixels `mask` selects are target (weight
    /// `target`), all others background (weight `background`). The PNG must
    /// have the camera's size; transparency is always read (see
    /// [`PngMask`]). An image with no target pixel, or only target pixels,
    /// is an error: the score could not tell models apart.
    pub fn from_png_masked(
        path: &Path,
        camera: Camera,
        mask: PngMask,
        target: f32,
        background: f32,
    ) -> Result<Self, ScoreError> {
        let bad = |reason: String| ScoreError::Image {
            path: path.to_path_buf(),
            reason,
        };
        // The size comes from the header, before anything is decoded (a
        // small file may claim a huge image).
        let open = || {
            image::ImageReader::open(path)
                .and_then(image::ImageReader::with_guessed_format)
                .map_err(|e| bad(e.to_string()))
        };
        let mut header = open()?;
        header.no_limits(); // only the header is read
        let (w, h) = header.into_dimensions().map_err(|e| bad(e.to_string()))?;
        if (w, h) != (camera.width, camera.height) {
            return Err(bad(format!(
                "the image is {w}×{h} pixels but the scene renders {}×{} (its width × height)",
                camera.width, camera.height
            )));
        }
        let mut reader = open()?;
        let mut limits = image::Limits::default();
        limits.max_image_width = Some(camera.width);
        limits.max_image_height = Some(camera.height);
        limits.max_alloc = Some(MAX_DECODE_BYTES);
        reader.limits(limits);
        let img = reader.decode().map_err(|e| bad(e.to_string()))?.to_rgba8();
        let selected: Vec<bool> = img.pixels().map(|p| mask.selects(p.0)).collect();
        let count = selected.iter().filter(|&&s| s).count();
        if count == 0 || count == selected.len() {
            let what = if count == 0 {
                "no pixel"
            } else {
                "every pixel"
            };
            return Err(bad(format!(
                "the mask `{}` makes {what} a target pixel: {}",
                mask.name(),
                mask.hint()
            )));
        }
        let weights = selected
            .into_iter()
            .map(|s| if s { target } else { background })
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
        crate::files::write_png(path, &img)
    }
}

impl ImageTarget {
    /// Draws the target's outline (target pixels with a 4-neighbour outside
    /// the target or on the image border) over `picture` (of the camera's
    /// size) in dark red, two pixels wide, so a render can be compared
    /// with what it should match.
    pub fn draw_outline(&self, picture: &mut image::RgbaImage) {
        let (w, h) = (self.camera.width as usize, self.camera.height as usize);
        if picture.dimensions() != (self.camera.width, self.camera.height) {
            return;
        }
        let inside = |x: isize, y: isize| {
            x >= 0
                && y >= 0
                && (x as usize) < w
                && (y as usize) < h
                && self.weights[y as usize * w + x as usize] > 0.0
        };
        for y in 0..h as isize {
            for x in 0..w as isize {
                if !inside(x, y) {
                    continue;
                }
                // Two pixels wide: any pixel within 2 of the outside.
                let edge = (-2..=2).any(|d| !inside(x + d, y) || !inside(x, y + d));
                if edge {
                    picture.put_pixel(x as u32, y as u32, image::Rgba([170, 20, 30, 255]));
                }
            }
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Weights of at most four non-zero values become one mask each (a
    /// bit a pixel, rows of whole words; zeros, of either sign, in none);
    /// five do not.
    #[test]
    fn few_weights_become_masks_by_value() {
        let (w, h) = (70u32, 3u32);
        let value = |i: usize| [0.5, -1.0, 0.0, 2.0, -0.0][i % 5];
        let weights: Vec<f32> = (0..(w * h) as usize).map(value).collect();
        let classes = WeightClasses::new(w, &weights).unwrap();
        assert_eq!(classes.values, [0.5, -1.0, 2.0, 0.0]);
        assert_eq!(classes.masks.len(), 2 * h as usize);
        for row in 0..h as usize {
            for c in 0..128 {
                let bit = |k: usize| classes.masks[row * 2 + c / 64][k] >> (c % 64) & 1 == 1;
                let weight = (c < w as usize).then(|| weights[row * w as usize + c]);
                for (k, &v) in classes.values.iter().enumerate() {
                    let expected = weight.is_some_and(|x| x == v && v != 0.0);
                    assert_eq!(bit(k), expected, "row {row}, column {c}, class {k}");
                }
            }
        }
        let four: Vec<f32> = (0..(w * h) as usize).map(|i| (i % 5) as f32).collect();
        assert!(WeightClasses::new(w, &four).is_some());
        let five: Vec<f32> = (0..(w * h) as usize).map(|i| (i % 6) as f32).collect();
        assert!(WeightClasses::new(w, &five).is_none());
    }
}
