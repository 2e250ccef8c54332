//! The paper's scenes as they were written before node families: one node
//! per copy (the tree's `b`/`n`/`m` three times per tree, the spaceship's
//! `T`/`t` and `W`/`w`, the city's four arms). Kept as the reference the
//! family definitions are compared against (`tests` below): the same graphs
//! and, on random chromosomes, the same geometry.

use super::city::{building, grid_lot, step, turn_and_step};
use super::spaceship::{ShipState, mirror_about_z, wing_segment};
use super::tree::{branch, leaf, trunk};
use crate::generator;
use crate::glam::{Affine3A, Vec3};

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

    /// The first tower segment on a body.
    node T emits {
        tags { top }
        params { k: vec3 = uniform([0.3, 0.1, 0.3], [0.8, 0.2, 0.8]) }
        slots { up: t = 1.0 }
        |state| {
            let mut s = state.scope;
            s.resize(k);
            s.move_y(0.5 * s.size.y);
            emit!(cube, s.instance());
            child!(up, ShipState { scope: s.translated(Vec3::new(0.0, 0.5 * s.size.y, 0.0)), ..state });
        }
    }

    /// A further tower segment.
    node t emits {
        tags { top }
        params { k: vec3 = uniform([0.6, 0.8, 0.6], [1.1, 1.1, 1.1]) }
        slots { up: t = 1.0 }
        |state| {
            let mut s = state.scope;
            s.resize(k);
            s.move_y(0.5 * s.size.y);
            emit!(cube, s.instance());
            child!(up, ShipState { scope: s.translated(Vec3::new(0.0, 0.5 * s.size.y, 0.0)), ..state });
        }
    }

    /// The first wing segment, emitted on both sides of its body.
    node W emits {
        tags { wing }
        params {
            k: vec3 = uniform([0.3, 0.2, 0.2], [1.2, 0.5, 1.0]),
            m: f32 = uniform(-0.5, 0.5),
        }
        slots { out: w = 1.0 }
        |state| {
            let s = wing_segment(state.scope, k, m);
            emit!(cube, s.instance());
            emit!(cube, state.mirror * s.instance());
            child!(out, ShipState { scope: s.translated(Vec3::new(0.5 * s.size.x, 0.0, 0.0)), ..state });
        }
    }

    /// A further wing segment, emitted on both sides.
    node w emits {
        tags { wing }
        params {
            k: vec3 = uniform([0.6, 0.9, 0.7], [1.2, 1.0, 1.2]),
            m: f32 = uniform(-0.5, 0.5),
        }
        slots { out: w = 0.9 }
        |state| {
            let s = wing_segment(state.scope, k, m);
            emit!(cube, s.instance());
            emit!(cube, state.mirror * s.instance());
            child!(out, ShipState { scope: s.translated(Vec3::new(0.5 * s.size.x, 0.0, 0.0)), ..state });
        }
    }
}

generator! {
    /// The paper's tree v2 (Fig. 8a, tree-sketch scene): a trunk at the
    /// origin and branches `b`, `n`, `m` fanned out by azimuth (0–120°,
    /// 120–240°, 240–360°), each attached 88 % up its parent; every branch
    /// without a child branch carries a leaf.
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

    node b emits {
        tags { branch }
        params {
            azimuth: f32 = uniform(0, 120),
            inclination: f32 = uniform(35, 85),
            twist: f32 = uniform(-3, 3),
            k: vec3 = uniform([0.6, 0.6, 0.6], [0.7, 0.801, 0.7]),
        }
        slots { b: b = 1.0 / 3.0, n: n = 1.0 / 3.0, m: m = 1.0 / 3.0 }
        |scope| {
            let s = branch(scope, azimuth, 0.38, inclination, k, twist);
            emit!(frustum, s.instance());
            if !(expressed!(b) || expressed!(n) || expressed!(m)) {
                emit!(leaf, leaf(&s));
            }
            child!(b, s);
            child!(n, s);
            child!(m, s);
        }
    }

    node n emits {
        tags { branch }
        params {
            azimuth: f32 = uniform(120, 240),
            inclination: f32 = uniform(35, 85),
            twist: f32 = uniform(-3, 3),
            k: vec3 = uniform([0.6, 0.6, 0.6], [0.7, 0.801, 0.7]),
        }
        slots { b: b = 1.0 / 3.0, n: n = 1.0 / 3.0, m: m = 1.0 / 3.0 }
        |scope| {
            let s = branch(scope, azimuth, 0.38, inclination, k, twist);
            emit!(frustum, s.instance());
            if !(expressed!(b) || expressed!(n) || expressed!(m)) {
                emit!(leaf, leaf(&s));
            }
            child!(b, s);
            child!(n, s);
            child!(m, s);
        }
    }

    node m emits {
        tags { branch }
        params {
            azimuth: f32 = uniform(240, 360),
            inclination: f32 = uniform(35, 85),
            twist: f32 = uniform(-3, 3),
            k: vec3 = uniform([0.6, 0.6, 0.6], [0.7, 0.801, 0.7]),
        }
        slots { b: b = 1.0 / 3.0, n: n = 1.0 / 3.0, m: m = 1.0 / 3.0 }
        |scope| {
            let s = branch(scope, azimuth, 0.38, inclination, k, twist);
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

    node b emits {
        tags { branch }
        params {
            azimuth: f32 = uniform(0, 180),
            inclination: f32 = uniform(35, 55),
            twist: f32 = uniform(-3, 3),
            k: vec3 = uniform([0.6, 0.6, 0.6], [0.7, 0.801, 0.7]),
        }
        slots { b: b = 1.0 / 3.0, n: n = 1.0 / 3.0, m: m = 1.0 / 3.0 }
        |scope| {
            let s = branch(scope, azimuth, 0.5, inclination, k, twist);
            emit!(frustum, s.instance());
            if !(expressed!(b) || expressed!(n) || expressed!(m)) {
                emit!(leaf, leaf(&s));
            }
            child!(b, s);
            child!(n, s);
            child!(m, s);
        }
    }

    node n emits {
        tags { branch }
        params {
            azimuth: f32 = uniform(180, 360),
            inclination: f32 = uniform(35, 55),
            twist: f32 = uniform(-3, 3),
            k: vec3 = uniform([0.6, 0.6, 0.6], [0.7, 0.801, 0.7]),
        }
        slots { b: b = 1.0 / 3.0, n: n = 1.0 / 3.0, m: m = 1.0 / 3.0 }
        |scope| {
            let s = branch(scope, azimuth, 0.5, inclination, k, twist);
            emit!(frustum, s.instance());
            if !(expressed!(b) || expressed!(n) || expressed!(m)) {
                emit!(leaf, leaf(&s));
            }
            child!(b, s);
            child!(n, s);
            child!(m, s);
        }
    }

    node m emits {
        tags { branch }
        params {
            azimuth: f32 = uniform(0, 0),
            inclination: f32 = uniform(0, 2),
            twist: f32 = uniform(0, 30),
            k: vec3 = uniform([0.6, 0.6, 0.6], [0.7, 0.801, 0.7]),
        }
        slots { b: b = 1.0 / 3.0, n: n = 1.0 / 3.0, m: m = 1.0 / 3.0 }
        |scope| {
            let s = branch(scope, azimuth, 0.5, inclination, k, twist);
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

    node N {
        slots { lot: LotDual = 0.9 }
        |scope| { child!(lot, turn_and_step(scope, 1)); }
    }

    node E {
        slots { lot: LotDual = 0.9 }
        |scope| { child!(lot, turn_and_step(scope, 0)); }
    }

    node S {
        slots { lot: LotDual = 0.9 }
        |scope| { child!(lot, turn_and_step(scope, -1)); }
    }

    node W {
        slots { lot: LotDual = 0.9 }
        |scope| { child!(lot, turn_and_step(scope, 2)); }
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

generator! {
    /// The grid city of the volume scene (`city_sep`): a 10 × 10 grid of
    /// lots 2.2 apart, each holding a building with probability 0.33. Lot
    /// `(i, j)` is slot `lots[i + 10 j]` (the reference code derived it from
    /// the node id, shifting the grid; fixed here).
    pub struct GridCity;
    shapes: [cube];
    start: Start;

    node Start {
        slots { lots[100]: Building = 0.33 }
        |scope| {
            for k in 0..100 {
                child!(lots[k], scope.translated(grid_lot(k)));
            }
        }
    }

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

#[cfg(test)]
mod tests {
    use proptest::prelude::*;
    use rand::RngExt;

    use crate::express::{Generator, Instances};
    use crate::genome::Chromosome;
    use crate::graph::Graph;
    use crate::ops::{InitLength, alter, grow, random_individual};

    /// A random chromosome: a random individual, grown and altered at random.
    fn random_chromosome(graph: &Graph, seed: u64, ops: usize) -> Chromosome {
        let mut rng = crate::rng::stream(seed, &[]);
        let init = InitLength::Between { lo: 1, hi: 150 };
        let mut c = random_individual(graph, &init, &mut rng).unwrap();
        for _ in 0..ops {
            if rng.random_range(0..2) == 0 {
                let _ = grow(graph, &mut c, &mut rng);
            } else {
                let _ = alter(graph, &mut c, &mut rng);
            }
        }
        c
    }

    /// The family definition `new` declares the same graph as the unrolled
    /// `old` and expresses the same geometry, instance for instance.
    fn same<G: Generator>(
        new: &G,
        old: &impl Generator<State = G::State>,
        seed: u64,
        ops: usize,
    ) -> Result<(), TestCaseError> {
        prop_assert_eq!(new.graph().spec(), old.graph().spec());
        prop_assert_eq!(new.shapes(), old.shapes());
        let c = random_chromosome(new.graph(), seed, ops);
        let (mut a, mut b) = (Instances::default(), Instances::default());
        new.express(&c, &mut a);
        old.express(&c, &mut b);
        prop_assert_eq!(a, b);
        Ok(())
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

        #[test]
        fn spaceship(seed in any::<u64>(), ops in 0usize..40) {
            same(&super::super::Spaceship, &super::Spaceship, seed, ops)?;
        }

        #[test]
        fn tree_v2(seed in any::<u64>(), ops in 0usize..40) {
            same(&super::super::TreeV2, &super::TreeV2, seed, ops)?;
        }

        #[test]
        fn tree_v1(seed in any::<u64>(), ops in 0usize..40) {
            same(&super::super::TreeV1, &super::TreeV1, seed, ops)?;
        }

        #[test]
        fn space_filling_city(seed in any::<u64>(), ops in 0usize..40) {
            same(&super::super::SpaceFillingCity, &super::SpaceFillingCity, seed, ops)?;
        }

        #[test]
        fn grid_city(seed in any::<u64>(), ops in 0usize..40) {
            same(&super::super::GridCity, &super::GridCity, seed, ops)?;
        }
    }
}
