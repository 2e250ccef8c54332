use shapegen::prelude::*;
use shapegen::express::{Generator, Instances};
use shapegen::glam::Affine3A;

#[derive(Clone, Copy)]
pub struct Pos(f32);

generator! {
    struct Row;
    shapes: [cube, sphere];
    state: Pos = Pos(0.0);
    start: Root;

    node Root {
        slots { cells[4]: Cell = 0.5 }
        |p| {
            for k in 0..4 {
                if expressed!(cells[k]) {
                    child!(cells[k], Pos(p.0 + k as f32));
                }
            }
        }
    }

    node Cell emits {
        params { round: choice = choice([1.0, 1.0]) }
        |p| {
            let t = Affine3A::from_translation([p.0, 0.0, 0.0].into());
            if round == 0 { emit!(cube, t) } else { emit!(sphere, t) }
        }
    }
}

fn main() {
    let mut rng = shapegen::rng::stream(3, &[]);
    let c = random_individual(Row.graph(), &InitLength::Fixed { l0: 5 }, &mut rng).unwrap();
    let (mut a, mut b) = (Instances::default(), Instances::default());
    Row.express(&c, &mut a);
    Row::interpreter().express(&c, &mut b);
    assert_eq!(a, b);
    assert_eq!(a.0.len(), c.len() - 1);
}
