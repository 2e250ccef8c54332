//! The thesis's toy grammar (Fig. 4.2) as a generator graph, and its design
//! tasks: two masses stacked, each with a height in `[1, 5]`, one of three
//! meshes (box, cylinder, star) and one of three colours (brown, blue,
//! turquoise), all uniform.

use shapegen_core::genome::Chromosome;
use shapegen_core::graph::{Dist, Graph, GraphBuilder};

use crate::evaluation::Task;

/// Mesh options of a mass.
pub const MESHES: [&str; 3] = ["box", "cylinder", "star"];
/// Colour options of a mass.
pub const COLOURS: [&str; 3] = ["brown", "blue", "turquoise"];

/// The toy graph: `Stack` (start) with slots `bottom` and `top` (p = 1),
/// each a `Mass` with parameters `h`, `mesh` and `colour`.
#[must_use]
pub fn graph() -> Graph {
    GraphBuilder::new("toy")
        .start("Stack")
        .node("Stack", |n| {
            n.slot("bottom", "Mass", 1.0).slot("top", "Mass", 1.0)
        })
        .node("Mass", |n| {
            n.emits()
                .param_f32("h", Dist::uniform(1.0, 5.0))
                .param_choice("mesh", vec![1.0, 1.0, 1.0])
                .param_choice("colour", vec![1.0, 1.0, 1.0])
        })
        .build()
        .expect("the toy graph is valid")
}

/// `(mesh, colour)` of the bottom and the top mass of a toy model.
#[must_use]
pub fn masses(g: &Graph, m: &Chromosome) -> [(u32, u32); 2] {
    let root = m.root_gene(g);
    let at = |slot| {
        root.child(slot).map_or((0, 0), |p| {
            let gene = m.gene(g, p);
            (gene.param_choice(1), gene.param_choice(2))
        })
    };
    [at(0), at(1)]
}

/// The thesis's colour factor (Fig. 4.5, 4.6): both brown 100, both blue or
/// both turquoise 50, mixed 0.
#[must_use]
pub fn same_colour(g: &Graph, m: &Chromosome) -> f64 {
    let [a, b] = masses(g, m);
    match (a.1, b.1) {
        (0, 0) => 100.0,
        (x, y) if x == y => 50.0,
        _ => 0.0,
    }
}

/// The thesis's geometry factor (Fig. 4.6): a box at the bottom 100, a
/// cylinder 50, a star 0.
#[must_use]
pub fn bottom_mesh(g: &Graph, m: &Chromosome) -> f64 {
    [100.0, 50.0, 0.0][masses(g, m)[0].0 as usize]
}

/// The toy's tasks: the colour task alone, and colour × geometry as two factors.
#[must_use]
pub fn tasks() -> Vec<Task> {
    vec![
        Task {
            name: "toy-colour".into(),
            description: "toy: both masses brown 100, both blue or both turquoise 50, mixed 0"
                .into(),
            graph: graph(),
            factors: vec![Box::new(same_colour)],
        },
        Task {
            name: "toy-2f".into(),
            description: "toy, two factors: the colour task × bottom box 100, cylinder 50, star 0"
                .into(),
            graph: graph(),
            factors: vec![Box::new(same_colour), Box::new(bottom_mesh)],
        },
    ]
}
