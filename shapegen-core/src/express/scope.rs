//! [`Scope`]: the shape state the paper's generators pass along edges.

use glam::{Affine3A, Vec3, Vec3A};

/// An oriented box: an affine frame (rotation and translation) and a size.
///
/// Operations act in the local frame, as in the paper's generators:
/// translations (often by a fraction of the current size), rotations about a
/// local axis, and multiplicative resizing (`size ← size ∘ k`; the frame is
/// unchanged, so the box stays centred). Each child starts from its own copy
/// of its parent's scope. The axiom is [`Scope::UNIT`]: a unit box at the origin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scope {
    /// Local-to-world transform of the box centre.
    pub frame: Affine3A,
    /// Extent along the local axes (SIMD-aligned, so scopes copy in whole registers).
    pub size: Vec3A,
}

impl Default for Scope {
    fn default() -> Self {
        Self::UNIT
    }
}

impl Scope {
    /// A unit box at the origin with the identity frame.
    pub const UNIT: Self = Self {
        frame: Affine3A::IDENTITY,
        size: Vec3A::ONE,
    };

    /// Moves the frame by `v` in local coordinates.
    #[inline]
    pub fn translate(&mut self, v: Vec3) {
        self.frame *= Affine3A::from_translation(v);
    }

    /// Moves the frame by `d` along the local x axis.
    #[inline]
    pub fn move_x(&mut self, d: f32) {
        self.translate(Vec3::new(d, 0.0, 0.0));
    }

    /// Moves the frame by `d` along the local y axis.
    #[inline]
    pub fn move_y(&mut self, d: f32) {
        self.translate(Vec3::new(0.0, d, 0.0));
    }

    /// Moves the frame by `d` along the local z axis.
    #[inline]
    pub fn move_z(&mut self, d: f32) {
        self.translate(Vec3::new(0.0, 0.0, d));
    }

    /// Rotates the frame by `angle` radians about its local x axis.
    #[inline]
    pub fn rotate_x(&mut self, angle: f32) {
        self.frame *= Affine3A::from_rotation_x(angle);
    }

    /// Rotates the frame by `angle` radians about its local y axis
    /// (right-handed: x turns toward −z).
    #[inline]
    pub fn rotate_y(&mut self, angle: f32) {
        self.frame *= Affine3A::from_rotation_y(angle);
    }

    /// Rotates the frame by `angle` radians about its local z axis.
    #[inline]
    pub fn rotate_z(&mut self, angle: f32) {
        self.frame *= Affine3A::from_rotation_z(angle);
    }

    /// Multiplies the size component-wise by `k`.
    #[inline]
    pub fn resize(&mut self, k: Vec3) {
        self.size *= Vec3A::from(k);
    }

    /// Sets the size.
    #[inline]
    pub fn set_size(&mut self, size: Vec3) {
        self.size = size.into();
    }

    /// A copy moved by `v` in local coordinates.
    #[inline]
    #[must_use]
    pub fn translated(mut self, v: Vec3) -> Self {
        self.translate(v);
        self
    }

    /// A copy rotated about the local y axis.
    #[inline]
    #[must_use]
    pub fn rotated_y(mut self, angle: f32) -> Self {
        self.rotate_y(angle);
        self
    }

    /// The transform of a unit-box mesh filling this scope: `frame · scale(size)`.
    #[inline]
    #[must_use]
    pub fn instance(&self) -> Affine3A {
        self.frame * Affine3A::from_scale(self.size.into())
    }

    /// The world position of the box centre.
    #[inline]
    #[must_use]
    pub fn origin(&self) -> Vec3 {
        self.frame.translation.into()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::FRAC_PI_2;

    #[test]
    fn operations_act_in_the_local_frame() {
        let mut s = Scope::UNIT;
        s.rotate_y(FRAC_PI_2); // local x now points to world −z
        s.move_x(2.0);
        assert!(s.origin().abs_diff_eq(Vec3::new(0.0, 0.0, -2.0), 1e-6));
        s.resize(Vec3::new(2.0, 3.0, 4.0));
        assert_eq!(s.size, Vec3A::new(2.0, 3.0, 4.0));
        // The unit cube's corner (0.5, 0.5, 0.5) maps through scale then frame.
        let corner = s.instance().transform_point3(Vec3::splat(0.5));
        let expected = s.frame.transform_point3(Vec3::new(1.0, 1.5, 2.0));
        assert!(corner.abs_diff_eq(expected, 1e-6));
    }
}
