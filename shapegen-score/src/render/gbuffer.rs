//! [`GBuffer`]: what each pixel of a render sees, and [`Face`]: what is
//! known of each rendered triangle.

use glam::{DVec3, Vec3};

use super::Plane;
use crate::camera::Camera;
use crate::raster::{PixelSpan, ceil_small, within};

/// No face: the background.
const NONE: u32 = u32::MAX;

/// Side of the square tiles whose farthest depth key is kept for
/// occlusion tests.
const TILE: usize = 8;

/// The most pixels a triangle's occlusion test looks at one by one
/// ([`GBuffer::hidden_pixels`]); larger ones are tested on tiles only.
const PIXEL_TEST_MAX: usize = 256;

/// The farthest key a pixel may hold for a face whose keys are at least
/// `k` to be hidden there: `k` less `10⁻⁶·|k|` for the rounding of
/// interpolated keys.
fn hiding_limit(k: f64) -> f64 {
    k - 1e-6 * k.abs()
}

/// Inclusive pixel box `(x0, y0, x1, y1)`, empty if `x0 > x1`.
pub(crate) type PixelBox = (usize, usize, usize, usize);

/// One rendered triangle (one instance's triangle placed in the world).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Face {
    /// Its terminal type: the shape id of the instance it belongs to.
    pub terminal: u16,
    /// Unit normal in view space (right, up, forward), turned to face the
    /// camera (meshes are seen from both sides); `(0, 0, −1)` for a
    /// degenerate triangle.
    pub normal: Vec3,
    /// Its area in world units².
    pub area: f64,
    /// Pixels it covers before occlusion (its centre-rule coverage).
    pub drawn: u32,
    /// Pixels where it is the nearest surface.
    pub visible: u32,
}

impl Face {
    /// The face of view-space triangle `v` (with `raw = (b − a) × (c − a)`)
    /// of terminal type `terminal`.
    pub(crate) fn new(raw: DVec3, v: [DVec3; 3], terminal: u16, perspective: bool) -> Self {
        let len = raw.length();
        // From the eye toward the triangle.
        let towards = if perspective {
            (v[0] + v[1] + v[2]) / 3.0
        } else {
            DVec3::Z
        };
        let normal = if len > 0.0 && len.is_finite() {
            let n = raw / len;
            if n.dot(towards) > 0.0 { -n } else { n }
        } else {
            DVec3::NEG_Z
        };
        Self {
            terminal,
            normal: normal.as_vec3(),
            area: 0.5 * len,
            drawn: 0,
            visible: 0,
        }
    }
}

/// What each pixel of a render sees: the depth and face of the nearest
/// surface at its centre (none for the background), and the table of
/// faces. Pixels are row-major from the top-left.
#[derive(Clone, Debug, Default)]
pub struct GBuffer {
    width: u32,
    height: u32,
    /// Depth keys (see `Plane`): smaller is nearer; +∞ for the background.
    depth: Vec<f64>,
    face: Vec<u32>,
    faces: Vec<Face>,
    terminals: usize,
    /// Per tile of `TILE²` pixels: the farthest depth key in it (+∞ while
    /// a pixel is uncovered), kept up to date as instances are drawn.
    tile_max: Vec<f64>,
    /// Tiles across.
    tiles_wide: usize,
    /// Whether `tile_max` is exact (not after an instance cut by the depth range).
    tiles_valid: bool,
    /// `(cx, cy, sx, sy)` of the camera, for pixel solid angles.
    projection: (f64, f64, f64, f64),
    perspective: bool,
}

impl GBuffer {
    /// Clears for a render by `camera` of models with `terminals` types.
    pub(crate) fn reset(&mut self, camera: &Camera, terminals: usize) {
        let n = camera.width as usize * camera.height as usize;
        self.width = camera.width;
        self.height = camera.height;
        self.depth.clear();
        self.depth.resize(n, f64::INFINITY);
        self.face.clear();
        self.face.resize(n, NONE);
        self.faces.clear();
        self.terminals = terminals;
        self.tiles_wide = (camera.width as usize).div_ceil(TILE);
        let tiles = self.tiles_wide * (camera.height as usize).div_ceil(TILE);
        self.tile_max.clear();
        self.tile_max.resize(tiles, f64::INFINITY);
        self.tiles_valid = true;
        let (cx, cy, sx, sy, perspective) = camera.projector().constants();
        self.projection = (cx, cy, sx, sy);
        self.perspective = perspective;
    }

    /// Adds a face; returns its index.
    pub(crate) fn push_face(&mut self, face: Face) -> u32 {
        self.faces.push(face);
        (self.faces.len() - 1) as u32
    }

    /// Draws face `index` over span `s` with depth keys from `plane`: a
    /// pixel takes the face if it is strictly nearer than what it holds
    /// (branch-free: the nearer key and its face are selected). The caller
    /// adds the span's length to the face with [`add_drawn`](Self::add_drawn).
    #[inline]
    pub(crate) fn span(&mut self, s: PixelSpan, index: u32, plane: &Plane) {
        let row = s.row as usize * self.width as usize;
        let (l0, b) = plane.row(f64::from(s.row) + 0.5);
        let range = row + s.c0 as usize..row + s.c1 as usize;
        let (depth, face) = (&mut self.depth[range.clone()], &mut self.face[range]);
        let x0 = f64::from(s.c0) + 0.5;
        // Every pixel is written, with what it held or the face: selects
        // on a mask rather than branches (whether a face is nearer changes
        // along a span where faces cross, and mispredicted), so the loop
        // runs on vectors. `x0 + i` is exact, as the pixel centres are.
        for (i, (d, f)) in depth.iter_mut().zip(face.iter_mut()).enumerate() {
            let k = plane.clamp(l0 + b * (x0 + i as f64));
            let nearer = k < *d;
            let mask = u32::from(nearer).wrapping_neg();
            *d = if nearer { k } else { *d };
            *f = (*f & !mask) | (index & mask);
        }
    }

    /// Adds `n` to face `index`'s pixels before occlusion (its spans' lengths).
    #[inline]
    pub(crate) fn add_drawn(&mut self, index: u32, n: u32) {
        self.faces[index as usize].drawn += n;
    }

    /// The pixels an instance whose vertices project into `[lo, hi]` can
    /// cover (one pixel more on each side for rounding), clamped to the image.
    pub(crate) fn pixel_box(&self, lo: glam::DVec2, hi: glam::DVec2) -> PixelBox {
        let (w, h) = (self.width as f64, self.height as f64);
        if !(lo.x < w + 1.0 && lo.y < h + 1.0 && hi.x > -1.0 && hi.y > -1.0) {
            return (1, 1, 0, 0);
        }
        // Plain comparisons (`f64::clamp` checks its bounds and NaN): `v`
        // is not NaN here (the test above failed for NaN bounds), and the
        // clamped value converts exactly.
        let clamp = |v: f64, max: f64| {
            let v = if v > 0.0 { v } else { 0.0 };
            (if v < max { v } else { max }) as u32 as usize
        };
        (
            clamp(lo.x - 1.0, w - 1.0),
            clamp(lo.y - 1.0, h - 1.0),
            clamp(hi.x + 1.0, w - 1.0),
            clamp(hi.y + 1.0, h - 1.0),
        )
    }

    /// Whether every pixel of `b` already holds a key at most `k` (less a
    /// margin of `10⁻⁶·|k|` for the rounding of interpolated keys): then
    /// no face with keys of at least `k` can take any of them.
    pub(crate) fn hidden(&self, b: PixelBox, k: f64) -> bool {
        let (x0, y0, x1, y1) = b;
        if x0 > x1 || y0 > y1 {
            return true; // nothing in the image
        }
        if !self.tiles_valid {
            return false;
        }
        let limit = hiding_limit(k);
        for ty in y0 / TILE..=y1 / TILE {
            for tx in x0 / TILE..=x1 / TILE {
                if self.tile_max[ty * self.tiles_wide + tx] > limit {
                    return false;
                }
            }
        }
        true
    }

    /// The pixels of the image whose centres lie in the box `[lo, hi]`
    /// (pixel coordinates) widened for rounding, or `None` if there are
    /// none (or a coordinate is not finite): a triangle whose vertices
    /// project into the box can cover no other pixel.
    ///
    /// Each of a triangle's crossings is an interpolation between two of
    /// its vertices, within a few ulps of their largest coordinate of the
    /// box; the box is widened by `10⁻⁹·(1 + that coordinate)`, far more.
    pub(crate) fn centres_in(&self, lo: glam::DVec2, hi: glam::DVec2) -> Option<PixelBox> {
        if !(lo.is_finite() && hi.is_finite()) {
            return None; // `fill_triangle` draws nothing either
        }
        let margin = |a: f64, b: f64| 1e-9 * (1.0 + a.abs().max(b.abs()));
        let (mx, my) = (margin(lo.x, hi.x), margin(lo.y, hi.y));
        let (w, h) = (self.width as i32, self.height as i32);
        // Pixel c's centre is c + 0.5: the first centre at or after v is
        // ⌈v − 0.5⌉, the last at or before it ⌊v − 0.5⌋ = −⌈0.5 − v⌉
        // (coordinates clamped to a pixel beyond the image, NaN to −1).
        let first = |v: f64, n: i32| ceil_small(within(v, f64::from(n)) - 0.5).max(0);
        let last = |v: f64, n: i32| (-ceil_small(0.5 - within(v, f64::from(n)))).min(n - 1);
        let (x0, x1) = (first(lo.x - mx, w), last(hi.x + mx, w));
        let (y0, y1) = (first(lo.y - my, h), last(hi.y + my, h));
        (x0 <= x1 && y0 <= y1).then_some((x0 as usize, y0 as usize, x1 as usize, y1 as usize))
    }

    /// Whether a triangle that can cover only the pixels of `b` (see
    /// [`centres_in`](Self::centres_in)), with keys of at least `k`, is
    /// hidden: tested on the tiles, then, for a box of at most
    /// [`PIXEL_TEST_MAX`] pixels, pixel by pixel (in foliage, with gaps
    /// among the leaves, the tiles rarely hide anything).
    pub(crate) fn hidden_triangle(&self, b: PixelBox, k: f64) -> bool {
        let (x0, y0, x1, y1) = b;
        let small = (x1 - x0 + 1) * (y1 - y0 + 1) <= PIXEL_TEST_MAX;
        self.hidden(b, k) || (small && self.hidden_pixels(b, k))
    }

    /// Whether every pixel of the non-empty box `b` already holds a key at
    /// most `k` (less the margin of [`hidden`](Self::hidden)), tested pixel
    /// by pixel.
    pub(crate) fn hidden_pixels(&self, b: PixelBox, k: f64) -> bool {
        let (x0, y0, x1, y1) = b;
        let limit = hiding_limit(k);
        let width = self.width as usize;
        (y0..=y1).all(|y| {
            self.depth[y * width + x0..=y * width + x1]
                .iter()
                .all(|&d| d <= limit)
        })
    }

    /// Recomputes the farthest key of the tiles overlapping `b`.
    pub(crate) fn update_tiles(&mut self, b: PixelBox) {
        let (x0, y0, x1, y1) = b;
        if x0 > x1 || y0 > y1 || !self.tiles_valid {
            return;
        }
        let (w, h) = (self.width as usize, self.height as usize);
        let larger = |a: f64, b: f64| if a > b { a } else { b };
        for ty in y0 / TILE..=y1 / TILE {
            for tx in x0 / TILE..=x1 / TILE {
                // Four running maxima, so that the loop runs on vectors
                // (a key is never NaN, so the order of comparisons does not
                // change the maximum).
                let mut max = [f64::NEG_INFINITY; 4];
                let (c0, c1) = (tx * TILE, ((tx + 1) * TILE).min(w));
                for y in ty * TILE..((ty + 1) * TILE).min(h) {
                    let row = &self.depth[y * w + c0..y * w + c1];
                    let mut quads = row.chunks_exact(4);
                    for q in &mut quads {
                        for i in 0..4 {
                            max[i] = larger(q[i], max[i]);
                        }
                    }
                    for (i, &d) in quads.remainder().iter().enumerate() {
                        max[i] = larger(d, max[i]);
                    }
                }
                self.tile_max[ty * self.tiles_wide + tx] =
                    larger(larger(max[0], max[1]), larger(max[2], max[3]));
            }
        }
    }

    /// Stops occlusion tests for this render (an instance was drawn whose
    /// pixels are not bounded by its vertices' box).
    pub(crate) fn forget_tiles(&mut self) {
        self.tiles_valid = false;
    }

    /// Counts each face's visible pixels.
    pub(crate) fn finish(&mut self) {
        for &f in &self.face {
            if f != NONE {
                self.faces[f as usize].visible += 1;
            }
        }
    }

    /// Width in pixels.
    #[must_use]
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    #[must_use]
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Number of pixels.
    #[must_use]
    pub fn len(&self) -> usize {
        self.face.len()
    }

    /// Whether the image has no pixels.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.face.is_empty()
    }

    /// Number of terminal types (shapes) the render could show.
    #[must_use]
    pub fn terminal_types(&self) -> usize {
        self.terminals
    }

    /// Whether pixel `i` sees the model.
    #[inline]
    #[must_use]
    pub fn covered(&self, i: usize) -> bool {
        self.face[i] != NONE
    }

    /// Every pixel's coverage, row-major.
    #[must_use]
    pub fn coverage(&self) -> Vec<bool> {
        self.face.iter().map(|&f| f != NONE).collect()
    }

    /// The covered pixels' bounding box `(x0, y0, x1, y1)`, inclusive;
    /// `None` if nothing is covered.
    #[must_use]
    pub fn covered_bounds(&self) -> Option<(usize, usize, usize, usize)> {
        let w = self.width as usize;
        let (mut x0, mut y0, mut x1, mut y1) = (usize::MAX, usize::MAX, 0, 0);
        for (y, row) in self.face.chunks_exact(w.max(1)).enumerate() {
            let Some(first) = row.iter().position(|&f| f != NONE) else {
                continue;
            };
            let last = row.iter().rposition(|&f| f != NONE).unwrap_or(first);
            x0 = x0.min(first);
            x1 = x1.max(last);
            y0 = y0.min(y);
            y1 = y1.max(y);
        }
        (x0 <= x1).then_some((x0, y0, x1, y1))
    }

    /// Number of covered pixels.
    #[must_use]
    pub fn covered_pixels(&self) -> usize {
        self.face.iter().filter(|&&f| f != NONE).count()
    }

    /// The depth (view-space `Z`) of the surface at pixel `i`'s centre.
    #[inline]
    #[must_use]
    pub fn depth(&self, i: usize) -> Option<f64> {
        self.covered(i)
            .then(|| super::depth_of(self.depth[i], self.perspective))
    }

    /// The face seen at pixel `i`.
    #[inline]
    #[must_use]
    pub fn face(&self, i: usize) -> Option<&Face> {
        self.faces.get(self.face[i] as usize)
    }

    /// The index (into [`faces`](Self::faces)) of the face seen at pixel `i`.
    #[inline]
    #[must_use]
    pub fn face_index(&self, i: usize) -> Option<u32> {
        self.covered(i).then(|| self.face[i])
    }

    /// The terminal type seen at pixel `i`.
    #[inline]
    #[must_use]
    pub fn terminal(&self, i: usize) -> Option<u16> {
        self.face(i).map(|f| f.terminal)
    }

    /// The view-space normal seen at pixel `i` (facing the camera).
    #[inline]
    #[must_use]
    pub fn normal(&self, i: usize) -> Option<Vec3> {
        self.face(i).map(|f| f.normal)
    }

    /// Every rendered face, in drawing order.
    #[must_use]
    pub fn faces(&self) -> &[Face] {
        &self.faces
    }

    /// Per terminal type: the visible surface area in world units², each
    /// face counted with the fraction of its pixels that are visible.
    #[must_use]
    pub fn visible_area(&self) -> Vec<f64> {
        let mut area = vec![0.0; self.terminals];
        for f in &self.faces {
            if f.visible > 0 {
                area[f.terminal as usize] += f.area * f64::from(f.visible) / f64::from(f.drawn);
            }
        }
        area
    }

    /// Per terminal type: the number of pixels where it is seen.
    #[must_use]
    pub fn terminal_pixels(&self) -> Vec<u64> {
        let mut n = vec![0u64; self.terminals];
        for f in &self.faces {
            n[f.terminal as usize] += u64::from(f.visible);
        }
        n
    }

    /// The solid angle of pixel `i` relative to the image centre's (1 for
    /// every pixel of an orthographic camera): `(1 + u² + v²)^(−3/2)` with
    /// `(u, v)` the pixel centre's direction on the plane `Z = 1`.
    #[must_use]
    pub fn pixel_solid_angle(&self, i: usize) -> f64 {
        if !self.perspective {
            return 1.0;
        }
        let (cx, cy, sx, sy) = self.projection;
        let w = self.width as usize;
        let (c, r) = ((i % w) as f64 + 0.5, (i / w) as f64 + 0.5);
        let (u, v) = ((c - cx) / sx, (r - cy) / sy);
        (1.0 + u * u + v * v).powf(-1.5)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    /// An empty G-buffer of `size` pixels.
    fn empty(size: (u32, u32)) -> GBuffer {
        let mut g = GBuffer::default();
        g.reset(&crate::raster::tests::orthographic(size), 1);
        g
    }

    /// The box `[lo, hi]` of pixel coordinates.
    fn b(x0: f64, y0: f64, x1: f64, y1: f64) -> (DVec2, DVec2) {
        (DVec2::new(x0, y0), DVec2::new(x1, y1))
    }

    /// The pixels whose centres lie in a box: a centre on its edge
    /// included, clamped to the image, none off the image or for NaN.
    #[test]
    fn centres_in_follows_the_centre_rule() {
        let g = empty((10, 8));
        let centres = |x0, y0, x1, y1| {
            let (lo, hi) = b(x0, y0, x1, y1);
            g.centres_in(lo, hi)
        };
        assert_eq!(centres(2.5, 1.5, 4.5, 2.5), Some((2, 1, 4, 2)));
        assert_eq!(centres(1.6, 0.6, 5.4, 3.4), Some((2, 1, 4, 2)));
        assert_eq!(centres(-5.0, -2.0, 1e12, 0.5), Some((0, 0, 9, 0)));
        // Within a pixel, between centres: none.
        assert_eq!(centres(2.6, 1.6, 3.4, 5.0), None);
        assert_eq!(centres(20.0, 1.0, 30.0, 2.0), None);
        assert_eq!(centres(f64::NAN, 1.0, 3.0, 2.0), None);
        assert_eq!(centres(1.0, 1.0, f64::INFINITY, 2.0), None);
        // Widened for rounding: a centre a rounding error outside counts.
        assert_eq!(
            centres(2.5 + 1e-12, 1.5, 4.5 - 1e-12, 1.5),
            Some((2, 1, 4, 1))
        );
    }

    /// The pixel test looks at each pixel of the box, with the margin of
    /// the tile test on the key.
    #[test]
    fn hidden_pixels_tests_every_pixel_of_the_box() {
        let mut g = empty((10, 8));
        // Pixels x 2..=4, y 1..=2 hold key 1; the rest is background.
        for y in 1..=2 {
            for x in 2..=4 {
                g.depth[y * 10 + x] = 1.0;
            }
        }
        assert!(g.hidden_pixels((2, 1, 4, 2), 2.0));
        // A key equal to what the pixels hold, or nearer, is not hidden.
        assert!(!g.hidden_pixels((2, 1, 4, 2), 1.0));
        assert!(!g.hidden_pixels((2, 1, 4, 2), 0.5));
        // One background pixel in the box is enough.
        assert!(!g.hidden_pixels((2, 1, 5, 2), 2.0));
        assert!(!g.hidden_pixels((2, 0, 4, 2), 2.0));
        assert!(!g.hidden_pixels((1, 2, 2, 3), 2.0));
    }
}
