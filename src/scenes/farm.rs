//! A farm and a castle after Lienhard's thesis, Fig. 5.10: six mass-model
//! parts (two house parts, two sheds, two silos) against eight (four
//! towers, two walls, a gate and a main hall). House parts, sheds, halls,
//! walls and the gate carry the tag `mass`, silos and towers `tower`, so
//! the thesis's matches hold: *Shed* and *MainBuilding* match *MainHall*,
//! *CastleWall* and *Gate*; *Silo* matches *Tower*. The fronts of houses
//! and the hall (tag `front`) are split rules of window bays (`bay`) with
//! `wall` spacers, merged as strings; the castle walls' merlons are a split.

use crate::express::Scope;
use crate::generator;
use crate::glam::Vec3;

/// A scope standing on the ground at `(x, z)`, `size` big.
fn block(mut s: Scope, x: f32, z: f32, size: Vec3) -> Scope {
    s.translate(Vec3::new(x, 0.5 * size.y, z));
    s.set_size(size);
    s
}

/// A thin slab on the front (+z) face of `s`: where window bays go.
fn front_of(s: Scope) -> Scope {
    let mut f = s.translated(Vec3::new(0.0, 0.0, 0.5 * s.size.z + 0.1));
    f.size.z = 0.2;
    f
}

/// Declares a generator with the given declaration plus the window front
/// both buildings use: `Front` splits along x into bays of about `bay`,
/// each `Bay` along y into wall, a window `window` high and wall (in the
/// ratio `sill` to `lintel`), each `Window` a pane `pane` of the bay wide.
macro_rules! with_front {
    (
        front { bay: $bay:expr, window: $window:expr, sill: $sill:expr, lintel: $lintel:expr, pane: $pane:expr }
        $($declaration:tt)*
    ) => {
        generator! {
            $($declaration)*

            /// A front: bays, a window in each.
            node Front {
                tags { front }
                slots { bay: Bay = 1.0 }
                |scope| { split!(scope, x, [bay: repeat($bay)]); }
            }

            node Bay {
                tags { bay }
                slots { window: Window = 1.0, wall: Wall = 1.0 }
                |scope| { split!(scope, y, [wall: rel($sill), window: $window, wall: rel($lintel)]); }
            }

            node Window emits {
                tags { window }
                |mut scope| {
                    scope.size.x *= $pane;
                    emit!(window, scope.instance());
                }
            }

            /// Spacing in a split; shows nothing (the block behind is the wall).
            node Wall {
                tags { wall }
                |scope| { let _ = scope; }
            }
        }
    };
}

/// [`block`] on a site whose plan is stretched by `spread` (x, z) and
/// whose buildings are scaled by `scale`.
fn placed(
    s: Scope,
    (x, z): (f32, f32),
    size: Vec3,
    spread: crate::glam::Vec2,
    scale: f32,
) -> Scope {
    block(s, x * spread.x, z * spread.y, size * scale)
}

/// The box above `s` of height `h` (a roof, a parapet).
fn above(s: Scope, h: f32) -> Scope {
    let mut r = s.translated(Vec3::new(0.0, 0.5 * (s.size.y + h), 0.0));
    r.size.y = h;
    r
}

with_front! {
    front { bay: 2.5, window: 1.5, sill: 0.5, lintel: 0.5, pane: 0.5 }
    /// A farm (thesis Fig. 5.10, left): a farmhouse and a barn, two sheds
    /// and two silos around a yard. The farmhouse's front is split into
    /// window bays.
    pub struct Farm;
    shapes: [cube, roof, frustum, window];
    start: Yard;

    /// The yard: its plan stretched by `spread`, its buildings scaled by `scale`.
    node Yard {
        tags { site }
        params {
            spread: vec2 = uniform([0.6, 0.6], [1.4, 1.4]),
            scale: f32 = uniform(0.7, 1.3),
        }
        slots {
            house[2]: MainBuilding = 1.0,
            shed[2]: Shed = 1.0,
            silo[2]: Silo = 1.0,
        }
        |scope| {
            let at = |xz, size| placed(scope, xz, size, spread, scale);
            child!(house[0], at((-4.0, 1.0), Vec3::new(11.0, 5.0, 6.0)));
            child!(house[1], at((6.5, -5.0), Vec3::new(8.0, 6.5, 7.0)));
            child!(shed[0], at((-8.0, 9.0), Vec3::new(5.0, 3.0, 4.0)));
            child!(shed[1], at((1.5, 9.5), Vec3::new(6.0, 3.0, 4.0)));
            child!(silo[0], at((11.5, 4.0), Vec3::new(3.0, 10.0, 3.0)));
            child!(silo[1], at((11.5, 9.0), Vec3::new(3.0, 8.0, 3.0)));
        }
    }

    /// A house part: a block with a gable roof and a front of window bays.
    node MainBuilding emits {
        tags { mass }
        params { roof: f32 = uniform(2.0, 3.0) }
        slots { front: Front = 1.0 }
        |scope| {
            emit!(cube, scope.instance());
            emit!(roof, above(scope, roof).instance());
            child!(front, front_of(scope));
        }
    }

    node Shed emits {
        tags { mass }
        params { roof: f32 = uniform(1.0, 2.0) }
        |scope| {
            emit!(cube, scope.instance());
            emit!(roof, above(scope, roof).instance());
        }
    }

    node Silo emits {
        tags { tower }
        |scope| { emit!(frustum, scope.instance()); }
    }
}

with_front! {
    front { bay: 3.0, window: 3.5, sill: 0.3, lintel: 0.6, pane: 0.4 }
    /// A castle (thesis Fig. 5.10, right): four corner towers, a back and a
    /// front wall with crenellations, a gate in the front wall and a main
    /// hall in the courtyard.
    pub struct Castle;
    shapes: [cube, roof, frustum, window];
    start: Court;

    /// The court: its plan stretched by `spread`, its buildings scaled by
    /// `scale` (walls follow the plan's width).
    node Court {
        tags { site }
        params {
            spread: vec2 = uniform([0.6, 0.6], [1.4, 1.4]),
            scale: f32 = uniform(0.7, 1.3),
        }
        slots {
            tower[4]: Tower = 1.0,
            wall[2]: CastleWall = 1.0,
            gate: Gate = 1.0,
            hall: MainHall = 1.0,
        }
        |scope| {
            let at = |xz, size| placed(scope, xz, size, spread, scale);
            for k in 0..4 {
                let (x, z) = ([-10.0, 10.0, -10.0, 10.0][k], [-10.0, -10.0, 10.0, 10.0][k]);
                child!(tower[k], at((x, z), Vec3::new(4.0, 13.0, 4.0)));
            }
            let wall = Vec3::new(20.0 * spread.x / scale, 7.0, 1.5);
            child!(wall[0], at((0.0, -10.0), wall));
            child!(wall[1], at((0.0, 10.0), wall));
            child!(gate, at((0.0, 10.5), Vec3::new(6.0, 9.0, 3.0)));
            child!(hall, at((0.0, -2.0), Vec3::new(12.0, 8.0, 8.0)));
        }
    }

    /// A round tower.
    node Tower emits {
        tags { tower }
        |scope| { emit!(frustum, scope.instance()); }
    }

    /// A wall with merlons of about 1.2 m along its top.
    node CastleWall emits {
        tags { mass }
        slots { top: Parapet = 1.0 }
        |scope| {
            emit!(cube, scope.instance());
            child!(top, above(scope, 1.0));
        }
    }

    /// Merlons and gaps along the top of a wall.
    node Parapet {
        slots { merlon: Merlon = 1.0 }
        |scope| { split!(scope, x, [merlon: repeat(2.4)]); }
    }

    node Merlon emits {
        |mut scope| {
            scope.size.x *= 0.5;
            emit!(cube, scope.instance());
        }
    }

    node Gate emits {
        tags { mass }
        |scope| {
            emit!(cube, scope.instance());
            let mut door = scope.translated(Vec3::new(0.0, -0.2 * scope.size.y, 0.5 * scope.size.z));
            door.size = Vec3::new(0.4 * scope.size.x, 0.6 * scope.size.y, 0.2).into();
            emit!(window, door.instance());
        }
    }

    /// The main hall: a block with a steep roof and a front of tall windows.
    node MainHall emits {
        tags { mass }
        params { roof: f32 = uniform(3.0, 5.0) }
        slots { front: Front = 1.0 }
        |scope| {
            emit!(cube, scope.instance());
            emit!(roof, above(scope, roof).instance());
            child!(front, front_of(scope));
        }
    }
}

generator! {
    /// Residential houses (thesis Fig. 5.12, left): two rows of three
    /// small houses with gable roofs, tagged `mass`.
    pub struct Houses;
    shapes: [cube, roof];
    start: Street;

    node Street {
        tags { site }
        slots { house[6]: House = 1.0 }
        |scope| {
            for k in 0..6 {
                let (x, z) = (-6.0 + 6.0 * (k % 3) as f32, if k < 3 { -5.0 } else { 5.0 });
                child!(house[k], block(scope, x, z, Vec3::new(4.0, 4.0, 5.0)));
            }
        }
    }

    node House emits {
        tags { mass }
        |scope| {
            emit!(cube, scope.instance());
            emit!(roof, above(scope, 2.0).instance());
        }
    }
}

generator! {
    /// Apartment blocks (thesis Fig. 5.12, middle): two tall blocks,
    /// tagged `mass`, where the houses stood.
    pub struct Apartments;
    shapes: [cube, roof];
    start: Street;

    node Street {
        tags { site }
        slots { block[2]: Block = 1.0 }
        |scope| {
            child!(block[0], block(scope, -3.0, 0.0, Vec3::new(10.0, 18.0, 8.0)));
            child!(block[1], block(scope, 6.0, 0.0, Vec3::new(5.0, 12.0, 15.0)));
        }
    }

    node Block emits {
        tags { mass }
        |scope| { emit!(cube, scope.instance()); }
    }
}
#[cfg(test)]
mod tests {
    use super::*;
    use crate::express::{Generator, Instances};

    fn count<G: Generator>(g: &G, shape: &str) -> usize {
        let c = crate::ops::default_model(g.graph()).unwrap();
        let mut out = Instances::default();
        g.express(&c, &mut out);
        let id = g.shapes().iter().position(|s| s == shape).unwrap();
        out.0.iter().filter(|i| i.shape as usize == id).count()
    }

    #[test]
    fn six_mass_parts_against_eight() {
        // House parts and sheds are boxes (with roofs), silos frusta.
        assert_eq!(count(&Farm, "frustum"), 2);
        assert_eq!(count(&Farm, "roof"), 4);
        // Four towers; two walls, a gate and a hall as boxes (and merlons).
        assert_eq!(count(&Castle, "frustum"), 4);
        assert_eq!(count(&Castle, "roof"), 1);
        assert!(count(&Castle, "cube") > 4 + 8);
        assert!(count(&Farm, "window") >= 6);
    }
}
