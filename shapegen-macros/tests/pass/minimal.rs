use shapegen::prelude::*;
use shapegen::express::{CountingSink, Generator};

generator! {
    /// A tower of floors.
    pub struct Tower;
    shapes: [cube];
    start: Floor;
    limits: { max_depth: 10, min_len: 1, max_len: 50 };

    node Floor emits {
        params { height: f32 = uniform(1, 2), style: choice = choice([1.0, 2.0]), floors: int = uniform(1, 3) }
        slots { up: Floor = 0.5 }
        |mut scope| {
            scope.size.y = height * floors as f32 + style as f32;
            emit!(cube, scope.instance());
            scope.move_y(height);
            child!(up, scope);
        }
    }
}

fn main() {
    let mut rng = shapegen::rng::stream(1, &[]);
    let c = random_individual(Tower.graph(), &InitLength::Fixed { l0: 5 }, &mut rng).unwrap();
    let mut sink = CountingSink::default();
    Tower.express(&c, &mut sink);
    assert_eq!(sink.count as usize, c.len());
    assert_eq!(Tower::spec().limits.max_len, Some(50));
}
