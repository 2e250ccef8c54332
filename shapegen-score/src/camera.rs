//! Cameras: the paper's orbit perspective camera and an orthographic one.

use glam::{DAffine3, DMat3, DVec2, DVec3};

use crate::error::ScoreError;

/// How world points map to pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Perspective with a vertical field of view (radians).
    Perspective {
        /// Vertical field of view.
        fov_y: f64,
    },
    /// Orthographic, showing `height` world units vertically.
    Orthographic {
        /// World height of the view.
        height: f64,
    },
}

/// A camera with an image size. View coordinates are `(X, Y, Z)` =
/// (right, up, forward) components of `p − eye`; only depths `Z` in
/// `[near, far]` are seen. Pixel `(c, r)` (column, row from the top) has its
/// centre at `(c + ½, r + ½)` in pixel coordinates: `right` points to
/// growing columns, `up` to the top row.
///
/// # Handedness
///
/// [`Camera::look_at`] is the usual right-handed camera of OpenGL and
/// Blender: `right = forward × up`, so a camera on +z looking at the origin
/// with +y up shows world +x on the right. [`Camera::orbit`] and
/// [`Camera::orthographic`] keep the paper's reference code,
/// `right = up × forward`: the mirror image, world +x on the *left* in that
/// view. The paper's targets were drawn for it; use `look_at` for new scenes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position.
    pub eye: DVec3,
    /// Unit right vector.
    pub right: DVec3,
    /// Unit up vector.
    pub up: DVec3,
    /// Unit viewing direction.
    pub forward: DVec3,
    /// Projection.
    pub projection: Projection,
    /// Nearest visible depth.
    pub near: f64,
    /// Farthest visible depth.
    pub far: f64,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
}

impl Camera {
    /// The largest image side, in pixels (scratch memory grows with the
    /// image: a 16384² target takes about 1 GB per worker thread).
    pub const MAX_SIDE: u32 = 16384;

    /// The paper's orbit camera (reference code): direction
    /// `d = (cos θ cos φ, sin θ, cos θ sin φ)`, eye `lookat + r·d`, forward `−d`,
    /// up `(−sin θ cos φ, cos θ, −sin θ sin φ)`, right `up × forward`.
    /// Angles in radians; `fov_y` is the vertical field of view.
    #[allow(clippy::too_many_arguments)]
    pub fn orbit(
        phi: f64,
        theta: f64,
        r: f64,
        lookat: DVec3,
        fov_y: f64,
        near: f64,
        far: f64,
        size: (u32, u32),
    ) -> Result<Self, ScoreError> {
        if !(r > 0.0 && r.is_finite()) {
            return Err(ScoreError::Camera(format!(
                "the orbit camera's r (its distance from look_at) is {r}: it must be a positive number, or the camera looks away from look_at"
            )));
        }
        let d = DVec3::new(
            theta.cos() * phi.cos(),
            theta.sin(),
            theta.cos() * phi.sin(),
        );
        let up = DVec3::new(
            -theta.sin() * phi.cos(),
            theta.cos(),
            -theta.sin() * phi.sin(),
        );
        let forward = -d;
        let cam = Self {
            eye: lookat + r * d,
            right: up.cross(forward),
            up,
            forward,
            projection: Projection::Perspective { fov_y },
            near,
            far,
            width: size.0,
            height: size.1,
        };
        cam.check()
    }

    /// A right-handed perspective camera (OpenGL, Blender) at `eye` looking
    /// at `target`, with `up` pointing up on screen (made orthogonal to the
    /// view direction) and `right = forward × up`. `fov_y` is the vertical
    /// field of view in radians.
    #[allow(clippy::too_many_arguments)]
    pub fn look_at(
        eye: DVec3,
        target: DVec3,
        up: DVec3,
        fov_y: f64,
        near: f64,
        far: f64,
        size: (u32, u32),
    ) -> Result<Self, ScoreError> {
        let forward = (target - eye).normalize_or_zero();
        let right = forward.cross(up).normalize_or_zero();
        if forward == DVec3::ZERO || right == DVec3::ZERO {
            return Err(ScoreError::Camera(
                "look_at needs eye ≠ target and an up vector not along the view direction".into(),
            ));
        }
        Self {
            eye,
            right,
            up: right.cross(forward),
            forward,
            projection: Projection::Perspective { fov_y },
            near,
            far,
            width: size.0,
            height: size.1,
        }
        .check()
    }

    /// An orthographic camera looking along `forward` from `eye`, with the
    /// paper's handedness (`right = up × forward`; see [`Camera`]).
    pub fn orthographic(
        eye: DVec3,
        forward: DVec3,
        up: DVec3,
        height: f64,
        near: f64,
        far: f64,
        size: (u32, u32),
    ) -> Result<Self, ScoreError> {
        let forward = forward.normalize();
        let right = up.cross(forward).normalize();
        let up = forward.cross(right);
        Self {
            eye,
            right,
            up,
            forward,
            projection: Projection::Orthographic { height },
            near,
            far,
            width: size.0,
            height: size.1,
        }
        .check()
    }

    fn check(self) -> Result<Self, ScoreError> {
        let bad = |m: String| Err(ScoreError::Camera(m));
        let fov_ok = match self.projection {
            Projection::Perspective { fov_y } => fov_y > 0.0 && fov_y < std::f64::consts::PI,
            Projection::Orthographic { height } => height > 0.0 && height.is_finite(),
        };
        if !fov_ok {
            return bad("the field of view (or orthographic height) is out of range".into());
        }
        if !(self.near > 0.0 && self.far > self.near && self.far.is_finite()) {
            return bad(format!(
                "need 0 < near < far, got near {} far {}",
                self.near, self.far
            ));
        }
        if self.width == 0 || self.height == 0 {
            return bad("the image has no pixels".into());
        }
        if self.width > Self::MAX_SIDE || self.height > Self::MAX_SIDE {
            return bad(format!(
                "{}×{} pixels: at most {} on a side",
                self.width,
                self.height,
                Self::MAX_SIDE
            ));
        }
        if ![self.eye, self.right, self.up, self.forward]
            .iter()
            .all(|v| v.is_finite())
            || self.right.length() < 0.5
        {
            return bad("the camera frame is degenerate or not finite".into());
        }
        Ok(self)
    }

    /// View coordinates `(X, Y, Z)` of world point `p`.
    #[inline]
    #[must_use]
    pub fn view(&self, p: DVec3) -> DVec3 {
        let q = p - self.eye;
        DVec3::new(self.right.dot(q), self.up.dot(q), self.forward.dot(q))
    }

    /// The view transform as an affine map: `view_affine().transform_point3(p)`
    /// is [`view`](Self::view)`(p)` up to rounding, and composes with a
    /// model transform into one map per instance.
    #[must_use]
    pub fn view_affine(&self) -> DAffine3 {
        let rows = DMat3::from_cols(self.right, self.up, self.forward).transpose();
        DAffine3 {
            matrix3: rows,
            translation: -(rows * self.eye),
        }
    }

    /// Pixel coordinates of a view-space point (`Z > 0` for perspective).
    #[inline]
    #[must_use]
    pub fn to_pixel(&self, v: DVec3) -> DVec2 {
        self.projector().to_pixel(v)
    }

    /// The projection's constants, computed once for many points.
    #[must_use]
    pub fn projector(&self) -> Projector {
        let (w, h) = (f64::from(self.width), f64::from(self.height));
        let (sx, sy, perspective) = match self.projection {
            Projection::Perspective { fov_y } => {
                let t = (0.5 * fov_y).tan();
                (0.5 * w / (t * (w / h)), 0.5 * h / t, true)
            }
            Projection::Orthographic { height } => (
                0.5 * w / (0.5 * height * (w / h)),
                0.5 * h / (0.5 * height),
                false,
            ),
        };
        Projector {
            cx: 0.5 * w,
            cy: 0.5 * h,
            sx,
            sy,
            perspective,
        }
    }

    /// The ray through the centre of pixel `(c, r)`: origin and direction
    /// with a forward component of 1, so the ray parameter is the depth `Z`.
    #[must_use]
    pub fn pixel_ray(&self, c: u32, r: u32) -> (DVec3, DVec3) {
        let (w, h) = (f64::from(self.width), f64::from(self.height));
        let x = 2.0 * (f64::from(c) + 0.5) / w - 1.0;
        let y = 1.0 - 2.0 * (f64::from(r) + 0.5) / h;
        match self.projection {
            Projection::Perspective { fov_y } => {
                let t = (0.5 * fov_y).tan();
                (
                    self.eye,
                    self.forward + x * t * (w / h) * self.right + y * t * self.up,
                )
            }
            Projection::Orthographic { height } => {
                let o =
                    self.eye + x * 0.5 * height * (w / h) * self.right + y * 0.5 * height * self.up;
                (o, self.forward)
            }
        }
    }
}

/// A camera's projection constants: view space to pixel coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projector {
    cx: f64,
    cy: f64,
    sx: f64,
    sy: f64,
    perspective: bool,
}

impl Projector {
    /// The constants `(cx, cy, sx, sy, perspective)`: pixel `x = cx + sx·X/Z`,
    /// `y = cy − sy·Y/Z` (without the division when orthographic).
    pub(crate) fn constants(&self) -> (f64, f64, f64, f64, bool) {
        (self.cx, self.cy, self.sx, self.sy, self.perspective)
    }

    /// Pixel coordinates of a view-space point (`Z > 0` for perspective).
    #[inline]
    #[must_use]
    pub fn to_pixel(&self, v: DVec3) -> DVec2 {
        let (x, y) = if self.perspective {
            // One division a point (x and y within an ulp of dividing each).
            let r = 1.0 / v.z;
            (v.x * r, v.y * r)
        } else {
            (v.x, v.y)
        };
        DVec2::new(self.cx + self.sx * x, self.cy - self.sy * y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    #[allow(clippy::approx_constant)] // −1.57080 is the paper config's value, not −π/2.
    fn the_tree_sketch_camera_sees_the_trunk_where_the_sketch_draws_it() {
        let cam = Camera::orbit(
            -1.57080,
            0.0,
            9.47160,
            DVec3::new(-0.680994, 3.25580, 2.46519e-06),
            60f64.to_radians(),
            0.1,
            100.0,
            (800, 600),
        )
        .unwrap();
        assert!(
            (cam.eye - DVec3::new(-0.681, 3.256, -9.472))
                .abs()
                .max_element()
                < 1e-3
        );
        let px = cam.to_pixel(cam.view(DVec3::ZERO));
        // The sketch's trunk is centred near column 436 (a mirrored camera would give about 363).
        assert!((px.x - 437.0).abs() < 2.0, "{px}");
        // Pixel rays and projection agree.
        let (o, d) = cam.pixel_ray(100, 200);
        let p = cam.to_pixel(cam.view(o + 3.0 * d));
        assert!((p - DVec2::new(100.5, 200.5)).length() < 1e-9);
    }

    #[test]
    fn which_way_world_x_points_on_screen() {
        let size = (101, 101);
        let x = |cam: &Camera| cam.to_pixel(cam.view(DVec3::X)).x - 50.5;
        let y = |cam: &Camera| cam.to_pixel(cam.view(DVec3::Y)).y - 50.5;
        // Both cameras on +z looking at the origin, +y up.
        let look = Camera::look_at(
            DVec3::new(0.0, 0.0, 5.0),
            DVec3::ZERO,
            DVec3::Y,
            1.0,
            0.1,
            100.0,
            size,
        )
        .unwrap();
        let orbit = Camera::orbit(
            std::f64::consts::FRAC_PI_2,
            0.0,
            5.0,
            DVec3::ZERO,
            1.0,
            0.1,
            100.0,
            size,
        )
        .unwrap();
        assert!((orbit.eye - look.eye).length() < 1e-12);
        assert!((look.forward - orbit.forward).length() < 1e-12);
        // look_at: +x to the right (growing columns), the OpenGL/Blender view.
        assert!(x(&look) > 5.0, "{}", x(&look));
        // orbit: the paper's mirror image, +x to the left.
        assert!(x(&orbit) < -5.0, "{}", x(&orbit));
        // Both: +y up on screen (smaller row numbers).
        assert!(y(&look) < -5.0 && y(&orbit) < -5.0);
        // A degenerate look_at is an error.
        assert!(Camera::look_at(DVec3::ZERO, DVec3::ZERO, DVec3::Y, 1.0, 0.1, 10.0, size).is_err());
        assert!(Camera::look_at(DVec3::ZERO, DVec3::Y, DVec3::Y, 1.0, 0.1, 10.0, size).is_err());
    }

    #[test]
    fn bad_cameras_are_errors() {
        let ok = |c: Result<Camera, ScoreError>| c.is_ok();
        assert!(!ok(Camera::orbit(
            0.0,
            0.0,
            5.0,
            DVec3::ZERO,
            0.0,
            0.1,
            100.0,
            (8, 8)
        )));
        assert!(!ok(Camera::orbit(
            0.0,
            0.0,
            5.0,
            DVec3::ZERO,
            1.0,
            1.0,
            0.5,
            (8, 8)
        )));
        assert!(!ok(Camera::orbit(
            0.0,
            0.0,
            5.0,
            DVec3::ZERO,
            1.0,
            0.1,
            100.0,
            (0, 8)
        )));
        assert!(!ok(Camera::orbit(
            f64::NAN,
            0.0,
            5.0,
            DVec3::ZERO,
            1.0,
            0.1,
            100.0,
            (8, 8)
        )));
        assert!(ok(Camera::orthographic(
            DVec3::ZERO,
            DVec3::Z,
            DVec3::Y,
            2.0,
            0.1,
            10.0,
            (8, 8)
        )));
    }
}
