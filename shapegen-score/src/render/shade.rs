//! How a [`GBuffer`] becomes a picture: three-point [`Lights`] fixed to the
//! camera, a [`Palette`] colour per terminal type, [`Shading`] and
//! [`Background`], gathered in a [`Style`].

use glam::Vec3;

use super::GBuffer;

/// One directional light: the direction *toward* it in view space (right,
/// up, forward) and its intensity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    /// Unit direction toward the light, in view space.
    pub direction: Vec3,
    /// Intensity.
    pub intensity: f32,
}

/// Three-point lighting fixed relative to the camera (thesis §3.3.2, after
/// Birn): a key light from the front left above, a weaker fill light from
/// the front right, a back light from behind above; plus ambient light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lights {
    /// Key, fill and back light.
    pub lights: [Light; 3],
    /// Ambient intensity.
    pub ambient: f32,
}

impl Default for Lights {
    fn default() -> Self {
        let light = |x: f32, y: f32, z: f32, intensity| Light {
            direction: Vec3::new(x, y, z).normalize(),
            intensity,
        };
        Self {
            lights: [
                light(-1.0, 1.0, -1.2, 0.7),
                light(1.2, 0.2, -1.0, 0.45),
                light(0.3, 1.0, 1.2, 0.35),
            ],
            ambient: 0.22,
        }
    }
}

impl Lights {
    /// Lambert intensity of a surface with unit normal `n` (view space),
    /// clamped to `[0, 1]`.
    #[must_use]
    pub fn lambert(&self, n: Vec3) -> f32 {
        let direct: f32 = self
            .lights
            .iter()
            .map(|l| l.intensity * n.dot(l.direction).max(0.0))
            .sum();
        (self.ambient + direct).clamp(0.0, 1.0)
    }
}

/// The colour of each terminal type.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum Palette {
    /// Readable defaults: shapes named like leaves or foliage green, trunks,
    /// branches and stems brown, the others from a colour-blind-safe
    /// qualitative palette (Tableau 10) in shape order (unnamed terminal
    /// types, which never show, take no colour from it).
    #[default]
    Named,
    /// These colours, by shape id (repeated when there are more shapes).
    Colors(Vec<[u8; 3]>),
}

/// Tableau 10, without its brown and green (kept for names).
const QUALITATIVE: [[u8; 3]; 8] = [
    [0x4e, 0x79, 0xa7],
    [0xf2, 0x8e, 0x2b],
    [0xe1, 0x57, 0x59],
    [0x76, 0xb7, 0xb2],
    [0xed, 0xc9, 0x48],
    [0xb0, 0x7a, 0xa1],
    [0xff, 0x9d, 0xa7],
    [0xba, 0xb0, 0xac],
];
const GREEN: [u8; 3] = [0x59, 0xa1, 0x4f];
const BROWN: [u8; 3] = [0x9c, 0x75, 0x5f];

impl Palette {
    /// The colour of each of the shapes `names`.
    #[must_use]
    pub fn for_names(&self, names: &[String]) -> Vec<[u8; 3]> {
        match self {
            Self::Colors(c) if !c.is_empty() => (0..names.len()).map(|i| c[i % c.len()]).collect(),
            _ => {
                let mut next = 0;
                names
                    .iter()
                    .map(|n| {
                        let n = n.to_lowercase();
                        if n.is_empty() {
                            QUALITATIVE[7]
                        } else if ["leaf", "leaves", "foliage", "ball"]
                            .iter()
                            .any(|k| n.contains(k))
                        {
                            GREEN
                        } else if ["trunk", "branch", "stem", "frustum"]
                            .iter()
                            .any(|k| n.contains(k))
                        {
                            BROWN
                        } else {
                            next += 1;
                            QUALITATIVE[(next - 1) % QUALITATIVE.len()]
                        }
                    })
                    .collect()
            }
        }
    }
}

/// How faces are lit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Shading {
    /// Each face its terminal colour times its Lambert intensity under the
    /// [`Lights`] (per face, so facets show).
    #[default]
    Lambert,
    /// Each face its terminal colour, unlit.
    Flat,
}

/// What the pixels without the model show.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Background {
    /// White.
    #[default]
    White,
    /// Fully transparent.
    Transparent,
}

/// Everything about how a picture looks.
#[derive(Clone, Debug, PartialEq)]
pub struct Style {
    /// The lights.
    pub lights: Lights,
    /// Colours per terminal type.
    pub palette: Palette,
    /// Lit or flat.
    pub shading: Shading,
    /// The background.
    pub background: Background,
    /// Samples per pixel along each axis (1 = none; at most 8).
    pub supersample: u32,
}

impl Default for Style {
    fn default() -> Self {
        Self {
            lights: Lights::default(),
            palette: Palette::Named,
            shading: Shading::Lambert,
            background: Background::White,
            supersample: 3,
        }
    }
}

impl Style {
    /// The default look without supersampling (for G-buffers and quick
    /// thumbnails).
    #[must_use]
    pub fn fast() -> Self {
        Self {
            supersample: 1,
            ..Self::default()
        }
    }

    /// The intensity of a face with unit normal `n`.
    #[must_use]
    pub fn intensity(&self, n: Vec3) -> f32 {
        match self.shading {
            Shading::Lambert => self.lights.lambert(n),
            Shading::Flat => 1.0,
        }
    }
}

/// A face's terminal colour (grey for a type without one) and its
/// intensity under `style`'s lighting.
pub(crate) fn face_colour(
    face: &super::Face,
    style: &Style,
    palette: &[[u8; 3]],
) -> ([u8; 3], f32) {
    let c = palette
        .get(face.terminal as usize)
        .copied()
        .unwrap_or([128; 3]);
    (c, style.intensity(face.normal))
}

/// Luminance (Rec. 709 weights) of an sRGB colour, in `[0, 1]`.
#[must_use]
pub(crate) fn luma(c: [u8; 3]) -> f32 {
    (0.2126 * f32::from(c[0]) + 0.7152 * f32::from(c[1]) + 0.0722 * f32::from(c[2])) / 255.0
}

/// The picture of `gbuffer` (rendered at a whole multiple of `size`),
/// each output pixel the mean of its samples.
pub(crate) fn picture(
    gbuffer: &GBuffer,
    style: &Style,
    palette: &[[u8; 3]],
    size: (u32, u32),
) -> image::RgbaImage {
    // Each face's colour once.
    let colors: Vec<[f32; 3]> = gbuffer
        .faces()
        .iter()
        .map(|f| {
            let (c, k) = face_colour(f, style, palette);
            c.map(|v| f32::from(v) * k)
        })
        .collect();
    let (w, h) = size;
    let sx = (gbuffer.width() / w).max(1);
    let sy = (gbuffer.height() / h).max(1);
    let gw = gbuffer.width() as usize;
    let samples = (sx * sy) as f32;
    let mut out = image::RgbaImage::new(w, h);
    for (x, y, px) in out.enumerate_pixels_mut() {
        let (mut rgb, mut alpha) = ([0.0f32; 3], 0.0f32);
        for j in 0..sy {
            for i in 0..sx {
                let idx = (y * sy + j) as usize * gw + (x * sx + i) as usize;
                if let Some(f) = gbuffer.face_index(idx) {
                    let c = colors[f as usize];
                    for k in 0..3 {
                        rgb[k] += c[k];
                    }
                    alpha += 1.0;
                }
            }
        }
        let p = match style.background {
            Background::White => {
                let white = 255.0 * (samples - alpha);
                rgb.map(|v| ((v + white) / samples).round().clamp(0.0, 255.0) as u8)
            }
            Background::Transparent if alpha > 0.0 => {
                rgb.map(|v| (v / alpha).round().clamp(0.0, 255.0) as u8)
            }
            Background::Transparent => [0; 3],
        };
        let a = match style.background {
            Background::White => 255,
            Background::Transparent => (255.0 * alpha / samples).round() as u8,
        };
        *px = image::Rgba([p[0], p[1], p[2], a]);
    }
    out
}
