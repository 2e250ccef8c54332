//! The cities of the paper: the space-filling city (Fig. 8b) and the grid city.

use crate::express::Scope;
use crate::generator;
use crate::glam::{Affine3A, Vec2, Vec3, Vec3A};

/// Distance between neighbouring lots (0.1 × 22).
pub const LOT_STEP: f32 = 2.2;

/// A building on the lot at `lot`: turned by `rotation` about the lot
/// centre, a box of footprint `footprint` and height `height` standing on
/// y = 0. Sizes are declared ×10 (as the paper's configs) and scaled by 0.1.
pub(crate) fn building(lot: Scope, footprint: Vec2, height: f32, rotation: f32) -> Affine3A {
    let mut s = lot;
    s.rotate_y(rotation);
    let size = Vec3::new(footprint.x, height, footprint.y) * 0.1;
    s.set_size(size);
    s.move_y(0.5 * size.y);
    s.instance()
}

/// One lot further along the local x axis.
pub(crate) fn step(mut s: Scope) -> Scope {
    s.move_x(LOT_STEP);
    s
}

/// Exact rotations about y by `k` quarter turns (k = 0..4), as columns:
/// `R_y(θ)` maps x to (cos θ, 0, −sin θ) and z to (sin θ, 0, cos θ).
const QUARTER_TURNS: [Affine3A; 4] = [
    Affine3A::IDENTITY,
    Affine3A::from_cols(
        Vec3A::new(0.0, 0.0, -1.0),
        Vec3A::Y,
        Vec3A::new(1.0, 0.0, 0.0),
        Vec3A::ZERO,
    ),
    Affine3A::from_cols(
        Vec3A::new(-1.0, 0.0, 0.0),
        Vec3A::Y,
        Vec3A::new(0.0, 0.0, -1.0),
        Vec3A::ZERO,
    ),
    Affine3A::from_cols(
        Vec3A::new(0.0, 0.0, 1.0),
        Vec3A::Y,
        Vec3A::new(-1.0, 0.0, 0.0),
        Vec3A::ZERO,
    ),
];

/// The lot reached by turning `quarters` quarter turns about y (counter-clockwise
/// seen from above for positive values) and stepping once.
pub(crate) fn turn_and_step(mut s: Scope, quarters: i32) -> Scope {
    s.frame *= QUARTER_TURNS[quarters.rem_euclid(4) as usize];
    step(s)
}

/// Declares a city: the declaration given plus the `Building` node both
/// cities share (one set of ranges, one body), placed on the lot it is
/// given. Sizes are declared ×10 as in the paper's configurations.
macro_rules! city {
    ($($declaration:tt)*) => {
        generator! {
            $($declaration)*

            node Building emits {
                tags { building }
                params {
                    footprint: vec2 = uniform([0.2 * 22.0, 0.2 * 22.0], [0.9 * 22.0, 0.9 * 22.0]),
                    height: f32 = uniform(1.2 * 3.0, 100.0),
                    floor_height: f32 = uniform(2.4, 3.6),
                    rotation: f32 = uniform(0.0, std::f32::consts::PI),
                }
                |scope| {
                    emit!(cube, building(scope, footprint, height, rotation));
                }
            }
        }
    };
}

city! {
    /// The paper's space-filling city (Fig. 8b): four arms of lots leave the
    /// centre; a dual lot continues straight and may branch off a single lot
    /// to its right; every lot may carry a building (a box emitted as `cube`).
    /// All four arms are expressed (the reference code never expressed W).
    pub struct SpaceFillingCity;
    shapes: [cube];
    start: Start;

    node Start {
        slots { north: N = 1.0, east: E = 1.0, south: S = 1.0, west: W = 1.0, building: Building = 0.33 }
        |scope| {
            child!(building, scope);
            child!(north, scope);
            child!(east, scope);
            child!(south, scope);
            child!(west, scope);
        }
    }

    /// The four arms leave the centre a quarter turn apart.
    node N, E, S, W {
        consts { quarter_turns: i32 = each[1, 0, -1, 2] }
        slots { lot: LotDual = 0.9 }
        |scope| { child!(lot, turn_and_step(scope, quarter_turns)); }
    }

    node LotDual {
        slots { dual: LotDual = 0.9, single: LotSingle = 0.9, building: Building = 0.33 }
        |scope| {
            child!(building, scope);
            child!(dual, step(scope));
            child!(single, turn_and_step(scope, -1));
        }
    }

    node LotSingle {
        slots { single: LotSingle = 0.9, building: Building = 0.33 }
        |scope| {
            child!(building, scope);
            child!(single, step(scope));
        }
    }
}

/// Number of lots along each side of the grid city.
pub const GRID: usize = 10;

/// The centre of lot `index` (= i + 10 j) of the grid city.
pub fn grid_lot(index: usize) -> Vec3 {
    let (i, j) = ((index % GRID) as f32, (index / GRID) as f32);
    Vec3::new(-9.9 + LOT_STEP * i, 0.0, -9.9 + LOT_STEP * j)
}

city! {
    /// The grid city of the volume scene (`city_sep`): a 10 × 10 grid of
    /// lots 2.2 apart, each holding a building with probability 0.33. Lot
    /// `(i, j)` is slot `lots[i + 10 j]` (the reference code derived it from
    /// the node id, shifting the grid; fixed here).
    pub struct GridCity;
    shapes: [cube];
    start: Start;

    node Start {
        slots { lots[GRID * GRID]: Building = 0.33 }
        |scope| {
            for k in 0..GRID * GRID {
                child!(lots[k], scope.translated(grid_lot(k)));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quarter_turns_are_the_exact_rotations() {
        for (k, turn) in QUARTER_TURNS.iter().enumerate() {
            let exact = Affine3A::from_rotation_y(k as f32 * std::f32::consts::FRAC_PI_2);
            assert!(turn.abs_diff_eq(exact, 1e-6), "{k}");
        }
    }
}
