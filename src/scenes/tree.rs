//! The trees of the paper (Fig. 8a): v2 (tree sketch) and v1 (tree avoid).

use crate::express::Scope;
use crate::generator;
use crate::glam::{Affine3A, Vec3};

/// Width of the trunk, in world units (its height is a parameter).
const TRUNK_WIDTH: f32 = 0.8;

/// A branch from its parent's scope: turn by the azimuth about y, climb to
/// `attach · s_y` above the parent's centre, incline about z, shrink by `k`,
/// move up by half the new height and twist about y (angles in degrees).
pub(crate) fn branch(
    parent: Scope,
    azimuth: f32,
    attach: f32,
    inclination: f32,
    k: Vec3,
    twist: f32,
) -> Scope {
    let mut s = parent;
    s.rotate_y(azimuth.to_radians());
    s.move_y(attach * s.size.y);
    s.rotate_z(inclination.to_radians());
    s.resize(k);
    s.move_y(0.5 * s.size.y);
    s.rotate_y(twist.to_radians());
    s
}

/// Where a final branch carries its leaf: `0.75 · s_y` above its centre, at unit size.
pub(crate) fn leaf(branch: &Scope) -> Affine3A {
    let mut s = *branch;
    s.move_y(0.75 * s.size.y);
    s.frame
}

/// The trunk: a frustum of width 0.8 and height `h`, centred at `at`.
pub(crate) fn trunk(at: Vec3, h: f32) -> Scope {
    let mut s = Scope::UNIT;
    s.translate(at);
    s.set_size(Vec3::new(TRUNK_WIDTH, h, TRUNK_WIDTH));
    s
}

generator! {
    /// The paper's tree v2 (Fig. 8a, tree-sketch scene): a trunk at the
    /// origin and branches `b`, `n`, `m` fanned out by azimuth (0–120°,
    /// 120–240°, 240–360°), each attached 38 % of its parent's height above
    /// the parent's centre; every branch without a child branch carries a leaf.
    pub struct TreeV2;
    shapes: [frustum, leaf];
    start: S;

    node S {
        slots { trunk: T = 1.0 }
        |scope| { child!(trunk, scope); }
    }

    node T emits {
        tags { trunk }
        params { h: f32 = uniform(1.4, 1.8) }
        slots { b: b = 1.0 / 3.0, n: n = 1.0 / 3.0, m: m = 1.0 / 3.0 }
        |scope| {
            let s = trunk(Vec3::ZERO, h);
            emit!(frustum, s.instance());
            child!(b, s);
            child!(n, s);
            child!(m, s);
        }
    }

    /// The three branch types differ only in their azimuth range.
    node b, n, m emits {
        tags { branch }
        consts { attach: f32 = 0.38 }
        params {
            azimuth: f32 = each[uniform(0, 120), uniform(120, 240), uniform(240, 360)],
            inclination: f32 = uniform(35, 85),
            twist: f32 = uniform(-3, 3),
            k: vec3 = uniform([0.6, 0.6, 0.6], [0.7, 0.801, 0.7]),
        }
        slots { b: b = 1.0 / 3.0, n: n = 1.0 / 3.0, m: m = 1.0 / 3.0 }
        |scope| {
            let s = branch(scope, azimuth, attach, inclination, k, twist);
            emit!(frustum, s.instance());
            if !(expressed!(b) || expressed!(n) || expressed!(m)) {
                emit!(leaf, leaf(&s));
            }
            child!(b, s);
            child!(n, s);
            child!(m, s);
        }
    }
}

generator! {
    /// The paper's tree v1 (Fig. 8a, tree-avoid scenes): the trunk stands at
    /// a position `(x, z)` in [−2.5, 2.5]²; branches `b` and `n` fan out on
    /// opposite sides (0–180°, 180–360°) and `m` nearly continues its parent;
    /// each is attached at the top of its parent.
    pub struct TreeV1;
    shapes: [frustum, leaf];
    start: S;

    node S {
        slots { trunk: T = 1.0 }
        |scope| { child!(trunk, scope); }
    }

    node T emits {
        tags { trunk }
        params {
            position: vec2 = uniform([-2.5, -2.5], [2.5, 2.5]),
            h: f32 = uniform(1.4, 1.8),
        }
        slots { b: b = 1.0 / 3.0, n: n = 1.0 / 3.0, m: m = 1.0 / 3.0 }
        |scope| {
            let s = trunk(Vec3::new(position.x, 0.0, position.y), h);
            emit!(frustum, s.instance());
            child!(b, s);
            child!(n, s);
            child!(m, s);
        }
    }

    /// `b` and `n` fan out to either side; `m` continues its parent, twisted.
    node b, n, m emits {
        tags { branch }
        consts { attach: f32 = 0.5 }
        params {
            azimuth: f32 = each[uniform(0, 180), uniform(180, 360), uniform(0, 0)],
            inclination: f32 = each[uniform(35, 55), uniform(35, 55), uniform(0, 2)],
            twist: f32 = each[uniform(-3, 3), uniform(-3, 3), uniform(0, 30)],
            k: vec3 = uniform([0.6, 0.6, 0.6], [0.7, 0.801, 0.7]),
        }
        slots { b: b = 1.0 / 3.0, n: n = 1.0 / 3.0, m: m = 1.0 / 3.0 }
        |scope| {
            let s = branch(scope, azimuth, attach, inclination, k, twist);
            emit!(frustum, s.instance());
            if !(expressed!(b) || expressed!(n) || expressed!(m)) {
                emit!(leaf, leaf(&s));
            }
            child!(b, s);
            child!(n, s);
            child!(m, s);
        }
    }
}
