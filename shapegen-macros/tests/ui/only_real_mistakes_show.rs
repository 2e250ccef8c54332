// A mistake in the declaration: code using the generator (its graph, its
// interpreter, the helpers and imports only its bodies use) still compiles,
// so the mistake is the only error and there are no follow-on warnings.
use shapegen::express::Scope;
use shapegen::glam::Vec3;
use shapegen::prelude::*;

fn lift(s: Scope) -> Scope {
    s.translated(Vec3::Y)
}

shapegen::generator! {
    pub struct Tower;
    shapes: [cube];
    start: Floor;
    node Floor emits {
        params { h: f32 = uniform(1, 2) }
        slots { up: Floor = 1.5 }
        |s| {
            emit!(cube, s.instance());
            child!(up, lift(s));
        }
    }
}

fn main() {
    let graph = Tower.graph();
    let _ = Tower::interpreter();
    println!("{} nodes", graph.spec().nodes.len());
}
