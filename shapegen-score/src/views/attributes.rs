//! The eight view attributes of Lienhard's thesis (§3.3), computed from a
//! [`GBuffer`] alone.

use serde::{Deserialize, Serialize};

use crate::render::{GBuffer, RenderMeshes, Style, face_colour, luma};

/// The view attributes of one render (thesis §3.3), each in `[0, 1]`.
///
/// The renders are assumed to come from a camera fitted to the model's
/// bounding sphere ([`fit_camera`](crate::fit_camera)): its projection is
/// then a circle of diameter `D = min(width, height)` pixels, and `l = D/√2`
/// is the side of the largest square that could be rendered.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ViewAttributes {
    /// a1, pixel count: covered pixels over the area of the circle of
    /// diameter `D`, `4n / (π D²)`.
    pub pixel_count: f64,
    /// a2, surface: `log_M(A + 1)` with `A` the visible surface area (world
    /// units²) and `M = 10⁶`.
    pub surface: f64,
    /// a3, silhouette length: `log₁₆(s / l)` with `s` the silhouette's
    /// length in pixels (covered pixels with an uncovered 4-neighbour or on
    /// the image border), clamped to `[0, 1]`.
    pub silhouette: f64,
    /// a4, RMS contrast of the covered pixels' luminance.
    pub contrast: f64,
    /// a5, normal ratio for best views: `1 − |1 − 3/2 · a5'|`.
    pub normal_ratio: f64,
    /// a5', normal balance for comparing models: `l / (l + r)`, the pixels
    /// whose normal points left over those pointing left or right (½ if none).
    pub normal_balance: f64,
    /// a6, form for best views: `1 − |log_l(h / w)|` of the covered pixels'
    /// bounding box, clamped to `[0, 1]`.
    pub form: f64,
    /// a6', form ratio for comparing models: `(log_l(h / w) + 1) / 2`,
    /// clamped to `[0, 1]`.
    pub form_ratio: f64,
    /// a7, visible terminal types: `log₁₀₀ N_t`.
    pub terminal_types: f64,
    /// a8, terminal entropy: `−Σ p_i log₁₀₀ p_i` over the visible terminal
    /// types, `p_i` their share of the projected solid angle.
    pub terminal_entropy: f64,
}

/// The names of the eight attributes, in vector order.
pub const ATTRIBUTE_NAMES: [&str; 8] = [
    "pixel count",
    "surface",
    "silhouette",
    "contrast",
    "normal ratio",
    "form",
    "terminal types",
    "terminal entropy",
];

impl ViewAttributes {
    /// The attributes of the render in `g` of a model of `meshes`, whose
    /// luminance is that of `style`'s shading.
    #[must_use]
    pub fn of(g: &GBuffer, meshes: &RenderMeshes, style: &Style) -> Self {
        let (w, h) = (g.width() as usize, g.height() as usize);
        let n = g.covered_pixels();
        if n == 0 {
            return Self {
                normal_ratio: 0.75,
                normal_balance: 0.5,
                ..Self::default()
            };
        }
        let diameter = w.min(h) as f64;
        let l = diameter / std::f64::consts::SQRT_2;
        let clamp = |x: f64| {
            if x.is_finite() {
                x.clamp(0.0, 1.0)
            } else {
                0.0
            }
        };

        // Luminance of each face once.
        let palette = style.palette.for_names(meshes.names());
        let lum: Vec<f64> = g
            .faces()
            .iter()
            .map(|f| {
                let (c, k) = face_colour(f, style, &palette);
                f64::from(luma(c) * k)
            })
            .collect();

        let (mut sum, mut sum2) = (0.0, 0.0);
        let (mut left, mut right) = (0u64, 0u64);
        let mut silhouette = 0u64;
        let mut solid = vec![0.0f64; g.terminal_types()];
        for y in 0..h {
            for x in 0..w {
                let i = y * w + x;
                let Some(f) = g.face_index(i) else { continue };
                let face = &g.faces()[f as usize];
                let v = lum[f as usize];
                sum += v;
                sum2 += v * v;
                if face.normal.x < 0.0 {
                    left += 1;
                } else if face.normal.x > 0.0 {
                    right += 1;
                }
                let edge = x == 0
                    || y == 0
                    || x + 1 == w
                    || y + 1 == h
                    || !g.covered(i - 1)
                    || !g.covered(i + 1)
                    || !g.covered(i - w)
                    || !g.covered(i + w);
                silhouette += u64::from(edge);
                solid[face.terminal as usize] += g.pixel_solid_angle(i);
            }
        }
        let nf = n as f64;
        let mean = sum / nf;
        let contrast = (sum2 / nf - mean * mean).max(0.0).sqrt();
        let balance = if left + right == 0 {
            0.5
        } else {
            left as f64 / (left + right) as f64
        };
        let log_l = |x: f64| if l > 1.0 { x.ln() / l.ln() } else { 0.0 };
        let (x0, y0, x1, y1) = g.covered_bounds().expect("n > 0 pixels are covered");
        let aspect = log_l((y1 - y0 + 1) as f64 / (x1 - x0 + 1) as f64);
        let total: f64 = solid.iter().sum();
        let visible_types = solid.iter().filter(|&&t| t > 0.0).count();
        let entropy = -solid
            .iter()
            .filter(|&&t| t > 0.0)
            .map(|&t| {
                let p = t / total;
                p * p.ln() / 100f64.ln()
            })
            .sum::<f64>();
        let area: f64 = g.visible_area().iter().sum();
        Self {
            pixel_count: clamp(4.0 * nf / (std::f64::consts::PI * diameter * diameter)),
            surface: clamp((area + 1.0).ln() / 1e6f64.ln()),
            silhouette: clamp((silhouette as f64 / l).ln() / 16f64.ln()),
            contrast: clamp(contrast),
            normal_ratio: clamp(1.0 - (1.0 - 1.5 * balance).abs()),
            normal_balance: balance,
            form: clamp(1.0 - aspect.abs()),
            form_ratio: clamp(0.5 * (aspect + 1.0)),
            terminal_types: clamp((visible_types.max(1) as f64).ln() / 100f64.ln()),
            terminal_entropy: clamp(entropy),
        }
    }

    /// a1–a8 as best-view selection uses them (a5 and a6).
    #[must_use]
    pub fn for_best_view(&self) -> [f64; 8] {
        [
            self.pixel_count,
            self.surface,
            self.silhouette,
            self.contrast,
            self.normal_ratio,
            self.form,
            self.terminal_types,
            self.terminal_entropy,
        ]
    }

    /// a1–a8 as comparing models uses them (a5' and a6').
    #[must_use]
    pub fn for_clustering(&self) -> [f64; 8] {
        [
            self.pixel_count,
            self.surface,
            self.silhouette,
            self.contrast,
            self.normal_balance,
            self.form_ratio,
            self.terminal_types,
            self.terminal_entropy,
        ]
    }
}

/// Weights of the eight attributes (in [`ATTRIBUTE_NAMES`] order).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct AttributeWeights(pub [f64; 8]);

impl AttributeWeights {
    /// The thesis's best-view weights (Tab. 3.2, second column).
    pub const BEST_VIEW: Self = Self([0.15, 0.20, 0.05, 0.02, 0.10, 0.03, 0.25, 0.20]);
    /// The thesis's clustering weights (Tab. 3.2, third column).
    pub const CLUSTERING: Self = Self([0.10, 0.25, 0.30, 0.02, 0.05, 0.03, 0.05, 0.20]);

    /// `Σ wᵢ xᵢ`.
    #[must_use]
    pub fn dot(&self, x: &[f64; 8]) -> f64 {
        self.0.iter().zip(x).map(|(w, x)| w * x).sum()
    }

    /// Why these weights are unusable, if they are (negative, not finite,
    /// or all zero).
    #[must_use]
    pub fn problem(&self) -> Option<&'static str> {
        if self.0.iter().any(|w| !w.is_finite() || *w < 0.0) {
            Some("attribute weights must be finite and >= 0")
        } else if self.0.iter().all(|w| *w == 0.0) {
            Some("attribute weights are all 0")
        } else {
            None
        }
    }
}

/// Each column of `rows` mapped linearly onto `[0, 1]` (its smallest value
/// to 0, its largest to 1; a constant column to 0), as the thesis
/// normalizes attributes over the sampled viewpoints.
#[must_use]
pub fn normalize_columns(rows: &[[f64; 8]]) -> Vec<[f64; 8]> {
    let mut lo = [f64::INFINITY; 8];
    let mut hi = [f64::NEG_INFINITY; 8];
    for r in rows {
        for k in 0..8 {
            lo[k] = lo[k].min(r[k]);
            hi[k] = hi[k].max(r[k]);
        }
    }
    rows.iter()
        .map(|r| {
            let mut out = [0.0; 8];
            for k in 0..8 {
                let span = hi[k] - lo[k];
                out[k] = if span > 1e-12 {
                    (r[k] - lo[k]) / span
                } else {
                    0.0
                };
            }
            out
        })
        .collect()
}
