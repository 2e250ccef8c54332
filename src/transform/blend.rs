//! Blending two shapes (thesis §5.4.3): position and size linearly,
//! orientation by slerp, about a pivot that both shapes share.

use crate::glam::{Affine3A, Quat, Vec3, Vec3A};

use crate::express::Scope;

/// A state a design transformation can blend: it has a scope (an oriented
/// box) that pairing measures and blending moves, and can take another.
///
/// The default state, [`Scope`], is its own scope. A generator with a state
/// of its own says which part of it is the scope; everything else in the
/// state is kept from the design it comes from. Two generators with
/// different state types are co-derived through their scopes.
///
/// `state.with_scope(state.scope())` must equal `state`: the endpoints of a
/// transformation are then exactly the two designs.
///
/// ```
/// use shapegen::express::Scope;
/// use shapegen::transform::Blend;
///
/// /// A state with a scope and something of its own.
/// #[derive(Clone, Copy)]
/// struct Twig {
///     scope: Scope,
///     girth: f32,
/// }
///
/// impl Blend for Twig {
///     fn scope(&self) -> Scope {
///         self.scope
///     }
///
///     fn with_scope(&self, scope: Scope) -> Self {
///         Self { scope, ..*self }
///     }
/// }
/// ```
#[diagnostic::on_unimplemented(
    message = "`{Self}` does not say how a design transformation blends it",
    label = "a generator's state must implement `shapegen::transform::Blend`",
    note = "implement `Blend` for `{Self}`: `fn scope(&self) -> Scope` (which part is the box) and `fn with_scope(&self, scope: Scope) -> Self`; examples/custom_generator/topiary.rs shows it"
)]
pub trait Blend: Clone + Send + Sync + 'static {
    /// The oriented box of this state.
    fn scope(&self) -> Scope;
    /// This state with its scope replaced by `scope`.
    #[must_use]
    fn with_scope(&self, scope: Scope) -> Self;
}

impl Blend for Scope {
    fn scope(&self) -> Scope {
        *self
    }

    fn with_scope(&self, scope: Scope) -> Self {
        scope
    }
}

/// The point two blended shapes turn about and move with.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Pivot {
    /// The shapes' centres (the thesis's default, for buildings).
    #[default]
    Centre,
    /// The centre of the shapes' bottom faces (local `y = −½`): a branch's
    /// attachment point, so that blended branches stay on their parents
    /// (the thesis's choice for plants, §5.6).
    Base,
}

impl Pivot {
    /// The pivot in a unit shape's local coordinates.
    #[must_use]
    pub(crate) fn local(self) -> Vec3 {
        match self {
            Self::Centre => Vec3::ZERO,
            Self::Base => Vec3::new(0.0, -0.5, 0.0),
        }
    }

    /// The pivot of a placed unit shape, in world coordinates.
    #[must_use]
    pub(crate) fn of_instance(self, transform: &Affine3A) -> Vec3 {
        transform.transform_point3(self.local())
    }

    /// The pivot of a scope, in world coordinates.
    #[must_use]
    pub(crate) fn of_scope(self, scope: &Scope) -> Vec3 {
        scope
            .frame
            .transform_point3(self.local() * Vec3::from(scope.size))
    }
}

fn lerp(a: Vec3, b: Vec3, w: f32) -> Vec3 {
    a + (b - a) * w
}

/// Rotation of a rigid or scaled frame (no shear), normalized.
fn rotation(transform: &Affine3A) -> (Vec3, Quat) {
    let (scale, rotation, _) = transform.to_scale_rotation_translation();
    (scale, rotation.normalize())
}

/// Blends two placed unit shapes: `w = 0` is `a` and `w = 1` is `b`
/// exactly; between, the pivot moves on a straight line, the size changes
/// linearly and the orientation by slerp. Transforms are read as
/// translation · rotation · scale (instances of scopes have no shear).
#[must_use]
pub fn blend_instances(a: &Affine3A, b: &Affine3A, w: f32, pivot: Pivot) -> Affine3A {
    if w <= 0.0 {
        return *a;
    }
    if w >= 1.0 {
        return *b;
    }
    let (sa, ra) = rotation(a);
    let (sb, rb) = rotation(b);
    let p = lerp(pivot.of_instance(a), pivot.of_instance(b), w);
    let r = ra.slerp(rb, w);
    let s = lerp(sa, sb, w);
    // T · pivot_local = p: translate so that the scaled, rotated pivot lands on p.
    let offset = r * (s * pivot.local());
    Affine3A::from_scale_rotation_translation(s, r, p - offset)
}

/// Blends two scopes as [`blend_instances`] blends their boxes: the
/// blended scope's box is the blend of the two boxes.
#[must_use]
pub fn blend_scopes(a: &Scope, b: &Scope, w: f32, pivot: Pivot) -> Scope {
    if w <= 0.0 {
        return *a;
    }
    if w >= 1.0 {
        return *b;
    }
    let (_, ra) = rotation(&a.frame);
    let (_, rb) = rotation(&b.frame);
    let p = lerp(pivot.of_scope(a), pivot.of_scope(b), w);
    let r = ra.slerp(rb, w);
    let size = Vec3A::from(lerp(a.size.into(), b.size.into(), w));
    let offset = r * (pivot.local() * Vec3::from(size));
    Scope {
        frame: Affine3A::from_rotation_translation(r, p - offset),
        size,
    }
}

/// Scales a placed shape by `f` about the point `about` (a shape growing
/// out of, or shrinking into, its attachment point). `f = 1` is `t` exactly.
#[must_use]
pub fn scaled_about(t: &Affine3A, about: Vec3, f: f32) -> Affine3A {
    if f == 1.0 {
        return *t;
    }
    Affine3A::from_translation(about)
        * Affine3A::from_scale(Vec3::splat(f))
        * Affine3A::from_translation(-about)
        * *t
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scope(angle: f32, at: Vec3, size: Vec3) -> Scope {
        let mut s = Scope::UNIT;
        s.translate(at);
        s.rotate_z(angle);
        s.set_size(size);
        s
    }

    #[test]
    fn endpoints_are_exact_and_boxes_follow_scopes() {
        let a = scope(0.3, Vec3::new(1.0, 2.0, 0.0), Vec3::new(0.5, 2.0, 0.5));
        let b = scope(-0.8, Vec3::new(-1.0, 0.0, 3.0), Vec3::new(0.2, 1.0, 0.3));
        for pivot in [Pivot::Centre, Pivot::Base] {
            assert_eq!(blend_scopes(&a, &b, 0.0, pivot), a);
            assert_eq!(blend_scopes(&a, &b, 1.0, pivot), b);
            for w in [0.25, 0.5, 0.9] {
                let s = blend_scopes(&a, &b, w, pivot);
                let i = blend_instances(&a.instance(), &b.instance(), w, pivot);
                assert!(s.instance().abs_diff_eq(i, 1e-5), "{pivot:?} {w}");
                let expected = lerp(pivot.of_scope(&a), pivot.of_scope(&b), w);
                assert!(pivot.of_scope(&s).abs_diff_eq(expected, 1e-5));
                assert!(pivot.of_instance(&i).abs_diff_eq(expected, 1e-5));
            }
        }
    }

    #[test]
    fn scaling_about_a_point_keeps_it() {
        let t = scope(0.4, Vec3::new(0.0, 1.0, 0.0), Vec3::ONE).instance();
        let base = Pivot::Base.of_instance(&t);
        let half = scaled_about(&t, base, 0.5);
        assert!(Pivot::Base.of_instance(&half).abs_diff_eq(base, 1e-6));
        assert_eq!(scaled_about(&t, base, 1.0), t);
    }
}
