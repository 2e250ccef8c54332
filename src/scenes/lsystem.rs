//! The thesis's tree pair (Lienhard, Fig. 5.1 and §A.2): Honda's monopodial
//! tree and Aono and Kunii's sympodial tree, from *The Algorithmic Beauty
//! of Plants* (Prusinkiewicz and Lindenmayer 1990, Figs. 2.6a and 2.7a),
//! written turtle style: a parent places each child's segment at its own
//! tip, so a node's state is the box of the segment it draws (heading along
//! local y, size `(w, l, w)`).
//!
//! The L-systems' constants are parameters here, centred on the book's
//! values (a default model is the book's tree), so the generators can also
//! be searched. Nine levels of segments: 511 per tree, as the thesis's
//! "0.5 k terminals" (Tab. 5.1).

use crate::express::Scope;
use crate::generator;
use crate::glam::{Affine3A, Mat3A, Vec3, Vec3A};

/// Width of the trunk per unit of its length (the book's `!(10)` for `F(1)`, scaled).
const TRUNK_WIDTH: f32 = 0.1;
/// Width decrease rate per branching (`wr`).
const WIDTH_RATE: f32 = 0.707;

/// The trunk's segment: length 1, standing on the origin.
pub(crate) fn trunk() -> Scope {
    let mut s = Scope::UNIT;
    s.set_size(Vec3::new(TRUNK_WIDTH, 1.0, TRUNK_WIDTH));
    s.move_y(0.5);
    s
}

/// The turtle at the tip of segment `s`, heading on.
fn tip(s: &Scope) -> Scope {
    let mut t = *s;
    t.move_y(0.5 * s.size.y);
    t
}

/// The book's `$`: rolls the turtle about its heading so that its left
/// vector is horizontal (kept when the heading is vertical).
fn roll_to_horizontal(t: &mut Scope) {
    let heading = t.frame.matrix3.y_axis;
    let left = Vec3A::Y.cross(heading);
    if left.length_squared() < 1e-12 {
        return;
    }
    let left = left.normalize();
    let third = left.cross(heading);
    t.frame.matrix3 = Mat3A::from_cols(left, heading, third);
}

/// The segment a turtle at `t` draws next: length `l`, width `w`.
fn segment(mut t: Scope, l: f32, w: f32) -> Scope {
    t.set_size(Vec3::new(w, l, w));
    t.move_y(0.5 * l);
    t
}

/// A child's segment: from the tip of `s`, after `turn` (the turtle's
/// rotations, angles in degrees), contracted by `r`.
fn child(s: &Scope, turn: impl FnOnce(&mut Scope), r: f32) -> Scope {
    let mut t = tip(s);
    turn(&mut t);
    segment(t, r * s.size.y, WIDTH_RATE * s.size.x)
}

/// The book's `+(a) $` (`a` in degrees; `−(a)` is a negative `a`): a turn
/// to the side, then the roll that keeps the turtle's left horizontal.
fn side(t: &mut Scope, a: f32) {
    t.rotate_z(a.to_radians());
    roll_to_horizontal(t);
}

/// The segments `B` and `C` grow from `s`: a lateral turned by `a2` to
/// one side and kept horizontal (contracted by `r2`), and the axis straight
/// on (contracted by `r1`).
fn alternate(s: &Scope, a2: f32, r1: f32, r2: f32) -> (Scope, Scope) {
    (child(s, |t| side(t, a2), r2), child(s, |_| {}, r1))
}

/// Where the unit frustum of a segment goes.
fn drawn(s: &Scope) -> Affine3A {
    s.instance()
}

generator! {
    /// Honda's monopodial tree (ABOP Fig. 2.6a): the axis `A` grows on
    /// (contracted by `r1`, rolled by the divergence angle) and sends out
    /// a lateral `B` (contracted by `r2`, pitched down by `a0`); `B` and `C`
    /// alternate their laterals to either side (`a2`), kept horizontal.
    /// Tags: `branching` on `A`, `B`, `C`.
    pub struct MonopodialTree;
    shapes: [frustum];
    start: S;
    limits: { max_depth: 9 };

    node S {
        slots { trunk: A = 1.0 }
        |_scope| { child!(trunk, trunk()); }
    }

    node A emits {
        tags { branching }
        params {
            r1: f32 = uniform(0.85, 0.95),
            r2: f32 = uniform(0.5, 0.7),
            a0: f32 = uniform(35, 55),
            divergence: f32 = uniform(127.5, 147.5),
        }
        slots { lateral: B = 1.0, axis: A = 1.0 }
        |s| {
            emit!(frustum, drawn(&s));
            child!(lateral, child(&s, |t| t.rotate_x(a0.to_radians()), r2));
            child!(axis, child(&s, |t| t.rotate_y(divergence.to_radians()), r1));
        }
    }

    node B emits {
        tags { branching }
        params {
            r1: f32 = uniform(0.85, 0.95),
            r2: f32 = uniform(0.5, 0.7),
            a2: f32 = uniform(-55, -35),
        }
        slots { lateral: C = 1.0, axis: C = 1.0 }
        |s| {
            emit!(frustum, drawn(&s));
            let (lateral_segment, axis_segment) = alternate(&s, a2, r1, r2);
            child!(lateral, lateral_segment);
            child!(axis, axis_segment);
        }
    }

    node C emits {
        tags { branching }
        params {
            r1: f32 = uniform(0.85, 0.95),
            r2: f32 = uniform(0.5, 0.7),
            a2: f32 = uniform(35, 55),
        }
        slots { lateral: B = 1.0, axis: B = 1.0 }
        |s| {
            emit!(frustum, drawn(&s));
            let (lateral_segment, axis_segment) = alternate(&s, a2, r1, r2);
            child!(lateral, lateral_segment);
            child!(axis, axis_segment);
        }
    }
}

generator! {
    /// Aono and Kunii's sympodial tree (ABOP Fig. 2.7a): every apex ends in
    /// two laterals, one nearly straight on (`a1`, contracted by `r1`) and
    /// one wide (`a2`, contracted by `r2`); the trunk's two are rolled
    /// half a turn apart, later ones kept horizontal.
    /// Tags: `branching` on `A`, `B`.
    pub struct SympodialTree;
    shapes: [frustum];
    start: S;
    limits: { max_depth: 9 };

    node S {
        slots { trunk: A = 1.0 }
        |_scope| { child!(trunk, trunk()); }
    }

    node A emits {
        tags { branching }
        params {
            r1: f32 = uniform(0.85, 0.95),
            r2: f32 = uniform(0.6, 0.8),
            a1: f32 = uniform(0, 20),
            a2: f32 = uniform(50, 70),
        }
        slots { near: B = 1.0, wide: B = 1.0 }
        |s| {
            emit!(frustum, drawn(&s));
            child!(near, child(&s, |t| t.rotate_x(a1.to_radians()), r1));
            child!(wide, child(&s, |t| { t.rotate_y(std::f32::consts::PI); t.rotate_x(a2.to_radians()); }, r2));
        }
    }

    node B emits {
        tags { branching }
        params {
            r1: f32 = uniform(0.85, 0.95),
            r2: f32 = uniform(0.6, 0.8),
            a1: f32 = uniform(0, 20),
            a2: f32 = uniform(50, 70),
        }
        slots { near: B = 1.0, wide: B = 1.0 }
        |s| {
            emit!(frustum, drawn(&s));
            child!(near, child(&s, |t| side(t, a1), r1));
            child!(wide, child(&s, |t| side(t, -a2), r2));
        }
    }
}
