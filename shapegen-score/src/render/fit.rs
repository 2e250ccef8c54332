//! A model's bounding sphere and the cameras it fits tightly (thesis §3.3:
//! "the camera is always placed at the distance where the model's minimal
//! bounding sphere fits tightly into the frustum").

use std::cmp::Ordering;

use glam::DVec3;

use super::GBuffer;
use crate::camera::{Camera, Projection};
use crate::error::ScoreError;

/// A sphere holding every vertex of a model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundingSphere {
    /// Centre.
    pub center: DVec3,
    /// Radius (> 0: a single point gets a tiny positive radius).
    pub radius: f64,
}

/// The largest squared distance of `points` from `center` (0 for none).
pub(super) fn farthest_squared(points: impl Iterator<Item = DVec3>, center: DVec3) -> f64 {
    points
        .map(|p| p.distance_squared(center))
        .fold(0.0, f64::max)
}

/// The points that may be the farthest from any point within `reach` of
/// `base`, in their order: those at least `m − 2·reach` from `base`, where
/// `m` is the greatest distance from it (less a margin for rounding). From
/// a point `c` within `reach` of `base`, the point at `m` is at least
/// `m − reach` away and every point left out less than that, so the
/// farthest point from `c` (the last of the greatest, as `Iterator::max_by`
/// takes it) is the same among the shell's points as among all.
#[derive(Clone, Debug, Default)]
struct Shell {
    base: Option<DVec3>,
    points: Vec<DVec3>,
}

impl Shell {
    /// The farthest of `points` from `from` (`from` itself for none), with
    /// the shell taken around `from` again if it lies beyond `reach` of
    /// the last base.
    fn farthest(&mut self, points: &[DVec3], from: DVec3, reach: f64) -> DVec3 {
        let within = |b: DVec3| {
            b.distance(from)
                .partial_cmp(&reach)
                .is_some_and(Ordering::is_le)
        };
        if !self.base.is_some_and(within) {
            self.take(points, from, reach);
        }
        farthest_of(&self.points, from)
    }

    /// Takes the shell of `points` around `base` for `reach`: every point
    /// when the bounds are not finite (no point left out then).
    fn take(&mut self, points: &[DVec3], base: DVec3, reach: f64) {
        self.base = Some(base);
        self.points.clear();
        let m = farthest_squared(points.iter().copied(), base).sqrt();
        let keep = m - 2.0 * reach - 1e-9 * (m + reach);
        if !(keep.is_finite() && keep > 0.0) {
            self.points.extend_from_slice(points);
            return;
        }
        let keep2 = keep * keep;
        // A NaN distance is kept, as `max_by` may pick it.
        let kept =
            |p: &&DVec3| p.distance_squared(base).partial_cmp(&keep2) != Some(Ordering::Less);
        self.points.extend(points.iter().filter(kept));
    }
}

/// The farthest of `points` from `from` (the last of the greatest
/// distances), or `from` itself for none.
fn farthest_of(points: &[DVec3], from: DVec3) -> DVec3 {
    points
        .iter()
        .copied()
        .max_by(|a, b| {
            a.distance_squared(from)
                .total_cmp(&b.distance_squared(from))
        })
        .unwrap_or(from)
}

/// Ritter's sphere around `points`: centre and radius, or `None` for no
/// points.
fn ritter(points: &[DVec3]) -> Option<(DVec3, f64)> {
    let first = *points.first()?;
    let a = farthest_of(points, first);
    let b = farthest_of(points, a);
    let mut center = 0.5 * (a + b);
    let mut radius = 0.5 * a.distance(b);
    for p in points {
        let d = p.distance(center);
        if d > radius {
            // Grow to hold p, keeping the far side where it was.
            let grown = 0.5 * (radius + d);
            center += (d - grown) / d * (*p - center);
            radius = grown;
        }
    }
    Some((center, radius))
}

/// The centre after 24 steps from `center` toward the farthest point,
/// each kept if the sphere that still holds everything is smaller than
/// `radius` so far; `farthest(c)` is the farthest point from `c`. The
/// farthest point from the centre changes only with the centre: a kept
/// candidate's farthest point is the next one's.
fn shrink(mut center: DVec3, mut radius: f64, mut farthest: impl FnMut(DVec3) -> DVec3) -> DVec3 {
    let mut step = 0.5;
    let mut far = farthest(center);
    for _ in 0..24 {
        let candidate = center + step * 0.1 * (far - center);
        let far_from_candidate = farthest(candidate);
        let r = far_from_candidate.distance(candidate);
        if r < radius {
            center = candidate;
            radius = r;
            far = far_from_candidate;
        } else {
            step *= 0.5;
        }
    }
    center
}

impl BoundingSphere {
    /// A small sphere around `points` (all finite): Ritter's construction,
    /// then passes that move the centre toward the farthest point while
    /// every point stays inside, which brings it within a few per cent of
    /// the minimal sphere. `None` for no points.
    #[must_use]
    pub fn of(points: &[DVec3]) -> Option<Self> {
        let center = Self::fit_center(points)?;
        let r2 = farthest_squared(points.iter().copied(), center);
        Some(Self::with_radius(center, r2.sqrt()))
    }

    /// [`of`](Self::of)'s centre for `points`: the centre of a sphere that
    /// holds them all, a few per cent larger than the minimal one. Any
    /// subset that holds the points' convex hull's vertices gives about the
    /// same centre (the farthest point from anywhere is such a vertex).
    pub(crate) fn fit_center(points: &[DVec3]) -> Option<DVec3> {
        let (center, radius) = ritter(points)?;
        // Each farthest point is found among the points of a shell that
        // holds every point that can be farthest from it (see `Shell`).
        let mut shell = Shell::default();
        let reach = 0.06 * radius;
        Some(shrink(center, radius, |from| {
            shell.farthest(points, from, reach)
        }))
    }

    /// The sphere about `center` with `radius`, made positive: a single
    /// point gets a tiny radius relative to its coordinates.
    pub(crate) fn with_radius(center: DVec3, radius: f64) -> Self {
        let scale = center.abs().max_element().max(1e-30);
        Self {
            center,
            radius: radius.max(scale * 1e-9).max(1e-12),
        }
    }

    /// The unit direction from the centre at `azimuth` (about +y, from +x
    /// toward +z) and `elevation` above the ground plane, in radians.
    #[must_use]
    pub fn direction(azimuth: f64, elevation: f64) -> DVec3 {
        DVec3::new(
            elevation.cos() * azimuth.cos(),
            elevation.sin(),
            elevation.cos() * azimuth.sin(),
        )
    }
}

/// A perspective camera (right-handed, +y up on screen) looking at the
/// sphere's centre from `direction` (from the centre toward the eye) at
/// the distance where the sphere just touches the frustum's narrower
/// sides: `d = R / sin(α/2)` with `α` the smaller of the two fields of view.
pub fn fit_camera(
    sphere: &BoundingSphere,
    direction: DVec3,
    fov_y: f64,
    size: (u32, u32),
) -> Result<Camera, ScoreError> {
    let aspect = f64::from(size.0) / f64::from(size.1.max(1));
    let fov_x = 2.0 * ((0.5 * fov_y).tan() * aspect).atan();
    let half = 0.5 * fov_y.min(fov_x);
    let d = sphere.radius / half.sin();
    let dir = direction.normalize_or_zero();
    let up = if dir.cross(DVec3::Y).length() < 1e-6 {
        DVec3::Z
    } else {
        DVec3::Y
    };
    let near = ((d - sphere.radius) * 0.98).max(d * 1e-4);
    let far = (d + sphere.radius) * 1.02;
    Camera::look_at(
        sphere.center + d * dir,
        sphere.center,
        up,
        fov_y,
        near,
        far,
        size,
    )
}

/// An orthographic camera looking at the sphere's centre from `direction`,
/// showing exactly the sphere's diameter across the narrower image side.
/// Its screen is mirrored like [`Camera::orthographic`]'s (see [`Camera`]).
pub fn fit_orthographic(
    sphere: &BoundingSphere,
    direction: DVec3,
    size: (u32, u32),
) -> Result<Camera, ScoreError> {
    let dir = direction.normalize_or_zero();
    let up = if dir.cross(DVec3::Y).length() < 1e-6 {
        DVec3::Z
    } else {
        DVec3::Y
    };
    let aspect = f64::from(size.0) / f64::from(size.1.max(1));
    // `height` is the vertical extent; the narrower side holds 2R.
    let height = 2.0 * sphere.radius / aspect.min(1.0);
    let d = 2.0 * sphere.radius;
    Camera::orthographic(
        sphere.center + d * dir,
        -dir,
        up,
        height,
        0.5 * sphere.radius,
        d + 1.5 * sphere.radius,
        size,
    )
}

/// `camera` turned and zoomed so that what `gbuffer` (rendered by
/// `camera`) covers fills the image, with `margin` (a fraction of the
/// extent, e.g. 0.08) on the wider side: for thumbnails that show a thin
/// or small model large. A perspective camera keeps its eye and narrows
/// its field of view (never widens it); an orthographic one moves
/// sideways and shows less. The camera itself if nothing is covered.
#[must_use]
pub fn frame_tightly(camera: &Camera, gbuffer: &GBuffer, margin: f64) -> Camera {
    let (w, h) = (gbuffer.width() as usize, gbuffer.height() as usize);
    let Some((x0, y0, x1, y1)) = gbuffer.covered_bounds() else {
        return *camera;
    };
    let (wf, hf) = (w as f64, h as f64);
    // The box's centre in normalized device coordinates, and its extent.
    let cx = (x0 + x1 + 1) as f64 / 2.0;
    let cy = (y0 + y1 + 1) as f64 / 2.0;
    let (nx, ny) = (2.0 * cx / wf - 1.0, 1.0 - 2.0 * cy / hf);
    let extent = ((x1 - x0 + 1) as f64 / wf)
        .max((y1 - y0 + 1) as f64 / hf)
        .min(1.0)
        * (1.0 + margin);
    let mut out = *camera;
    match camera.projection {
        Projection::Perspective { fov_y } => {
            let t = (0.5 * fov_y).tan();
            let aspect = wf / hf;
            let d = camera.forward + nx * t * aspect * camera.right + ny * t * camera.up;
            let f = d.normalize();
            // Keep the camera's handedness (look_at: up = right × forward).
            let look_at_like = camera.right.dot(camera.forward.cross(camera.up)) > 0.0;
            let mut r = f.cross(camera.up).normalize();
            if r.dot(camera.right) < 0.0 {
                r = -r;
            }
            let u = if look_at_like { r.cross(f) } else { f.cross(r) };
            let fov = 2.0 * (t * extent.min(1.0)).atan();
            out.forward = f;
            out.right = r;
            out.up = u;
            out.projection = Projection::Perspective {
                fov_y: fov.min(fov_y),
            };
        }
        Projection::Orthographic { height } => {
            let half_h = 0.5 * height;
            let half_w = half_h * wf / hf;
            out.eye += nx * half_w * camera.right + ny * half_h * camera.up;
            out.projection = Projection::Orthographic {
                height: height * extent.min(1.0),
            };
        }
    }
    if out.right.is_finite() && out.up.is_finite() && out.forward.is_finite() {
        out
    } else {
        *camera
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;
    use proptest::prelude::*;

    use super::{BoundingSphere, farthest_of, ritter, shrink};

    /// [`BoundingSphere::fit_center`] as first written: every shrinking
    /// step looks at every point.
    fn fit_center_reference(points: &[DVec3]) -> Option<DVec3> {
        let (center, radius) = ritter(points)?;
        Some(shrink(center, radius, |from| farthest_of(points, from)))
    }

    /// Points in a ball, on a sphere's surface, on a segment, on a lattice
    /// (many equal distances) or all in one place, far from the origin or
    /// not.
    fn cloud() -> impl Strategy<Value = Vec<DVec3>> {
        let point = || prop::array::uniform3(-1.0..1.0f64).prop_map(DVec3::from);
        (
            prop::collection::vec(point(), 0..300),
            0u8..5,
            prop_oneof![Just(0.0), -100.0..100.0f64],
            prop_oneof![Just(1.0), 1e-3..1e3f64],
        )
            .prop_map(|(ps, kind, offset, scale)| {
                ps.into_iter()
                    .map(|p| match kind {
                        0 => p,
                        1 => p.normalize_or_zero(),
                        2 => DVec3::new(p.x, 0.0, 0.0),
                        3 => (p * 3.0).round(),
                        _ => DVec3::ZERO,
                    })
                    .map(|p| p * scale + DVec3::splat(offset))
                    .collect()
            })
    }

    proptest! {
        /// The same centre, bit for bit, as passing over every point.
        #[test]
        fn fit_center_equals_the_reference(points in cloud()) {
            let fast = BoundingSphere::fit_center(&points).map(|c| c.to_array().map(f64::to_bits));
            let slow = fit_center_reference(&points).map(|c| c.to_array().map(f64::to_bits));
            prop_assert_eq!(fast, slow);
        }
    }
}
