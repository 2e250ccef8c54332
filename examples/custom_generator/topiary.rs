//! The topiary generator of the custom-generator example: a pot, a stem,
//! forking branches and clipped foliage balls. Shared by the example
//! program and the tests that run it through the command line.

use shapegen::express::Scope;
use shapegen::generator;
use shapegen::glam::Vec3;

/// What each part hands to the next: where it ends, and how thick the wood
/// is there (branches thin out as they fork).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Twig {
    /// The part's box; children start from its top.
    pub scope: Scope,
    /// Width of the wood at the part's top.
    pub girth: f32,
}

impl Twig {
    /// The axiom: a unit box at the origin, a stem 0.25 thick.
    pub const ROOT: Self = Self {
        scope: Scope::UNIT,
        girth: 0.25,
    };
}

/// How a design transformation (`shapegen transform`) blends two twigs:
/// through their boxes; the girth stays the design's own.
impl shapegen::transform::Blend for Twig {
    fn scope(&self) -> Scope {
        self.scope
    }

    fn with_scope(&self, scope: Scope) -> Self {
        Self { scope, ..*self }
    }
}

/// A piece of wood of `length` leaving `from`'s top, turned by `azimuth`
/// about the vertical and leaning `lean` degrees away from it.
fn wood(from: &Twig, azimuth: f32, lean: f32, length: f32, girth: f32) -> Scope {
    let mut s = from.scope;
    s.move_y(0.5 * s.size.y);
    s.rotate_y(azimuth.to_radians());
    s.rotate_z(lean.to_radians());
    s.set_size(Vec3::new(girth, length, girth));
    s.move_y(0.5 * length);
    s
}

generator! {
    /// A potted topiary: a pot (an OBJ mesh, or a square planter), a stem,
    /// forks of two or three branches, and clipped balls of foliage in one
    /// to three tiers. Shapes `pot` and `ball` have no built-in mesh: the
    /// experiment file gives them (`[shapes.pot]`, `[shapes.ball]`).
    pub struct Topiary;
    shapes: [pot, cube, frustum, ball];
    state: Twig = Twig::ROOT;
    start: Pot;

    /// The pot: an octagonal pot or a square planter, standing on y = 0.
    node Pot emits {
        params {
            height: f32 = uniform(0.6, 1.0),
            width: f32 = uniform(0.8, 1.4),
            planter: choice([2.0, 1.0]),
        }
        slots { stem: Stem = 1.0 }
        |twig| {
            let mut s = Scope::UNIT;
            s.set_size(Vec3::new(width, height, width));
            s.move_y(0.5 * height);
            if planter == 0 { emit!(pot, s.instance()) } else { emit!(cube, s.instance()) }
            child!(stem, Twig { scope: s, ..twig });
        }
    }

    /// The stem out of the pot, nearly upright.
    node Stem emits {
        params { length: f32 = uniform(0.8, 2.4), lean: f32 = uniform(-8, 8) }
        slots { fork: Fork = 0.5, crown: Ball = 0.5 }
        |twig| {
            let s = wood(&twig, 0.0, lean, length, twig.girth);
            emit!(frustum, s.instance());
            let top = Twig { scope: s, girth: twig.girth };
            child!(fork, top);
            child!(crown, top);
        }
    }

    /// Where the wood divides: up to three branches around the vertical.
    node Fork {
        params { spin: f32 = uniform(0, 360) }
        slots { a: Branch = 0.9, b: Branch = 0.9, c: Branch = 0.4 }
        |twig| {
            let thinner = Twig { girth: 0.7 * twig.girth, ..twig };
            let mut s = twig.scope;
            s.rotate_y(spin.to_radians());
            let at = |k: f32| Twig { scope: s.rotated_y((120.0 * k).to_radians()), ..thinner };
            child!(a, at(0.0));
            child!(b, at(1.0));
            child!(c, at(2.0));
        }
    }

    /// A branch leaning out from a fork; it forks again or carries a ball.
    node Branch emits {
        params { length: f32 = uniform(0.5, 1.4), lean: f32 = uniform(15, 60) }
        slots { fork: Fork = 0.3, crown: Ball = 0.8 }
        |twig| {
            let s = wood(&twig, 0.0, lean, length, twig.girth);
            emit!(frustum, s.instance());
            // Children grow upright again from the branch's tip.
            let mut end = Scope::UNIT;
            end.translate(s.frame.transform_point3(Vec3::new(0.0, 0.5 * s.size.y, 0.0)));
            end.set_size(Vec3::ZERO);
            let top = Twig { scope: end, girth: twig.girth };
            child!(fork, top);
            child!(crown, top);
        }
    }

    /// A clipped ball of foliage on the wood's end, in one to three tiers
    /// of shrinking balls stacked upward.
    node Ball emits {
        params { size: f32 = uniform(0.6, 1.8), tiers: int = uniform(1, 3), squash: f32 = uniform(0.7, 1.0) }
        |twig| {
            let mut s = twig.scope;
            s.move_y(0.5 * s.size.y);
            let mut d = size;
            for _ in 0..tiers {
                let mut b = s;
                b.set_size(Vec3::new(d, squash * d, d));
                b.move_y(0.4 * squash * d);
                emit!(ball, b.instance());
                s.move_y(0.8 * squash * d);
                d *= 0.7;
            }
        }
    }
}
