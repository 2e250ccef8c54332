// Node families with per-member values, the short `choice` form, a slot
// array of constant-expression length, every parameter kind, and a
// `macro_rules!` wrapper passing bodies as `block` fragments.
use shapegen::express::Instances;
use shapegen::prelude::*;

const SIDE: usize = 3;

// Names the body uses come from the invocation (macro hygiene).
macro_rules! hedge {
    ($name:ident, $h:ident = $height:expr, |$scope:pat_param| $body:block) => {
        shapegen::generator! {
            pub struct $name;
            shapes: [cube];
            start: Row;

            node Row {
                slots { cells[SIDE * SIDE]: Cell = 0.5 }
                |scope| {
                    for k in 0..SIDE * SIDE {
                        child!(cells[k], scope.translated([k as f32, 0.0, 0.0].into()));
                    }
                }
            }

            node Cell emits {
                params { $h: f32 = constant($height) }
                |$scope| $body
            }
        }
    };
}

hedge!(Hedge, h = 1.5, |scope| {
    let mut s = scope;
    s.size.y = h;
    emit!(cube, s.instance());
});

shapegen::generator! {
    /// A plant whose stems share one body.
    pub struct Plant;
    shapes: [cube];
    start: Root;

    node Root {
        params { habit: choice([3, 2, 1]), count: int = uniform(1, 3) }
        slots { left: Left = 1.0, right: Right = 1.0, tip: Tip = each_is_not_a_keyword_here() }
        |scope| {
            let _ = (habit, count);
            child!(left, scope);
            child!(right, scope);
            child!(tip, scope);
        }
    }

    /// Left and right stems: mirrored by a constant, with their own ranges.
    node Left, Right emits {
        consts { side: f32 = each[-1.0, 1.0], label: &'static str = each["left", "right"] }
        params {
            lean: f32 = each[uniform(0, 10), normal(5, 1)],
            offset: vec2 = uniform([0.0, 0.0], [1.0, 0.5]),
            scale: vec3 = truncated_normal(1.0, 0.1, 0.8, 1.2),
            leaves: int = each[constant(2), uniform(0, 4)],
            shape: choice = each[choice([1, 1]), choice([0, 2])],
        }
        slots { again: Left = each[0.5, 0.25] }
        |scope| {
            let _ = (label, leaves, shape, offset);
            let s = scope.translated([side * lean, 1.0, 0.0].into());
            emit!(cube, s.instance() * shapegen::glam::Affine3A::from_scale(scale));
            child!(again, s);
        }
    }

    node Tip emits {
        |scope| { emit!(cube, scope.instance()); }
    }
}

const fn each_is_not_a_keyword_here() -> f64 {
    0.5
}

fn main() {
    let spec = Plant::spec();
    let names: Vec<&str> = spec.nodes.iter().map(|n| n.name.as_ref()).collect();
    assert_eq!(names, ["Root", "Left", "Right", "Tip"]);
    assert_eq!(spec.nodes[1].slots[0].p, 0.5);
    assert_eq!(spec.nodes[2].slots[0].p, 0.25);
    assert_eq!(spec.nodes[0].params[0].dist, ParamDist::Choice(vec![3.0, 2.0, 1.0].into()));
    assert_eq!(Hedge::spec().nodes[0].slots.len(), 9);
    assert_eq!(Hedge::spec().nodes[0].slots[8].name, "cells[8]");

    for seed in 0..20 {
        let mut rng = shapegen::rng::stream(seed, &[]);
        let c = random_individual(Plant.graph(), &InitLength::Around { l0: 8 }, &mut rng).unwrap();
        let (mut a, mut b) = (Instances::default(), Instances::default());
        Plant.express(&c, &mut a);
        Plant::interpreter().express(&c, &mut b);
        assert_eq!(a, b);
        let c = random_individual(Hedge.graph(), &InitLength::Around { l0: 5 }, &mut rng).unwrap();
        let (mut a, mut b) = (Instances::default(), Instances::default());
        Hedge.express(&c, &mut a);
        Hedge::interpreter().express(&c, &mut b);
        assert_eq!(a, b);
        assert_eq!(a.0.len(), c.len() - 1);
    }
}
