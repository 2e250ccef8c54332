//! The spaceship of the paper (Fig. 3, Fig. 4a).

use crate::express::Scope;
use crate::generator;
use crate::glam::{Affine3A, Vec3};

/// The spaceship's shape state: a scope, and for wings the world transform
/// that mirrors the right wing onto the left one (identity elsewhere).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShipState {
    /// The current box.
    pub scope: Scope,
    /// Maps the right-hand copy of a wing onto the left-hand one.
    pub mirror: Affine3A,
}

impl ShipState {
    /// The axiom: a unit box at the origin, no mirror.
    pub const AXIOM: Self = Self {
        scope: Scope::UNIT,
        mirror: Affine3A::IDENTITY,
    };
}

/// The rotation by π about the body's local z axis, in world space.
/// A transformation blends the scope; the mirror stays the design's own.
impl crate::transform::Blend for ShipState {
    fn scope(&self) -> Scope {
        self.scope
    }

    fn with_scope(&self, scope: Scope) -> Self {
        Self { scope, ..*self }
    }
}

pub(crate) fn mirror_about_z(body: &Scope) -> Affine3A {
    body.frame * Affine3A::from_rotation_z(std::f32::consts::PI) * body.frame.inverse()
}

generator! {
    /// The paper's spaceship (Fig. 4a): a chain of body boxes along +z, with
    /// towers (`T`, `t`) on top and mirrored wings (`W`, `w`), every part a
    /// box emitted as `cube`. `T → t` and `t → t` have p = 1: uncontrolled
    /// generation extends a tower up to `max_depth`.
    pub struct Spaceship;
    shapes: [cube];
    state: ShipState = ShipState::AXIOM;
    start: S;

    /// The start operation: hands the axiom to the first body segment.
    node S {
        slots { body: B = 1.0 }
        |state| {
            child!(body, state);
        }
    }

    /// A body segment: resized from its parent, placed to abut it along +z.
    node B emits {
        tags { body }
        params { k: vec3 = uniform([0.6, 0.6, 0.6], [1.5, 1.5, 1.5]) }
        slots { next: B = 1.0 / 3.0, wing: W = 1.0 / 3.0, top: T = 1.0 / 3.0 }
        |state| {
            let mut s = state.scope;
            s.resize(k);
            s.move_z(0.5 * s.size.z);
            emit!(cube, s.instance());
            let plain = |scope| ShipState { scope, mirror: Affine3A::IDENTITY };
            child!(next, plain(s.translated(Vec3::new(0.0, 0.0, 0.5 * s.size.z))));
            child!(top, plain(s.translated(Vec3::new(0.0, 0.5 * s.size.y, 0.0))));
            let right = s.translated(Vec3::new(0.5 * s.size.x, 0.0, 0.0));
            child!(wing, ShipState { scope: right, mirror: mirror_about_z(&s) });
        }
    }

    /// A tower segment: `T` on a body, `t` on a tower segment; they differ in their scale range.
    node T, t emits {
        tags { top }
        params { k: vec3 = each[uniform([0.3, 0.1, 0.3], [0.8, 0.2, 0.8]), uniform([0.6, 0.8, 0.6], [1.1, 1.1, 1.1])] }
        slots { up: t = 1.0 }
        |state| {
            let mut s = state.scope;
            s.resize(k);
            s.move_y(0.5 * s.size.y);
            emit!(cube, s.instance());
            child!(up, ShipState { scope: s.translated(Vec3::new(0.0, 0.5 * s.size.y, 0.0)), ..state });
        }
    }

    /// A wing segment, emitted on both sides of its body: `W` on a body (always
    /// followed by a `w`), `w` further out (continued with p = 0.9).
    node W, w emits {
        tags { wing }
        params {
            k: vec3 = each[uniform([0.3, 0.2, 0.2], [1.2, 0.5, 1.0]), uniform([0.6, 0.9, 0.7], [1.2, 1.0, 1.2])],
            m: f32 = uniform(-0.5, 0.5),
        }
        slots { out: w = each[1.0, 0.9] }
        |state| {
            let s = wing_segment(state.scope, k, m);
            emit!(cube, s.instance());
            emit!(cube, state.mirror * s.instance());
            child!(out, ShipState { scope: s.translated(Vec3::new(0.5 * s.size.x, 0.0, 0.0)), ..state });
        }
    }
}

/// A wing segment from the attachment point: resize, slide along z by
/// `m · s_z`, and move out by half its width.
pub(crate) fn wing_segment(mut s: Scope, k: Vec3, m: f32) -> Scope {
    s.resize(k);
    s.move_z(s.size.z * m);
    s.move_x(0.5 * s.size.x);
    s
}
