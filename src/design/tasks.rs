//! Design tasks on the paper's generators, each a program playing a user
//! with a known preference (the thesis's §4.7 evaluation, on our scenes).
//!
//! | task | generator | preference |
//! |---|---|---|
//! | `S1` | spaceship | exactly two wing pairs 70, one 30, others 0 |
//! | `S2` | spaceship | a tower on the first body segment and on no other 100, no tower at all 20, others 0 |
//! | `T1` | tree v2 | all three main branches 100, two 50, fewer 0 |
//! | `C1` | space-filling city | built on two opposite streets only (north and south, or east and west) 100, others 0 |
//!
//! and the toy grammar's tasks ([`shapegen_design::toy::tasks`]). Each
//! generator has the limits of its paper experiment.

use shapegen_design::evaluation::Task;

use crate::express::Generator;
use crate::genome::Chromosome;
use crate::graph::{Graph, Limits};
use crate::scenes::{SpaceFillingCity, Spaceship, TreeV2};

fn limited<G: Generator>(generator: &G, min_len: u32, max_len: u32, max_depth: u32) -> Graph {
    Graph::new(generator.graph().spec().clone().with_limits(Limits {
        max_depth: Some(max_depth),
        min_len,
        max_len: Some(max_len),
    }))
    .expect("a built-in graph with its paper limits is valid")
}

/// Genes of the node called `name`.
fn count(g: &Graph, m: &Chromosome, name: &str) -> usize {
    let id = g.node_id(name).expect("the task's node exists");
    m.genes(g).filter(|x| x.node() == id).count()
}

/// `S1`: exactly two wing pairs 70, one 30, others 0.
pub fn wing_pairs(g: &Graph, m: &Chromosome) -> f64 {
    match count(g, m, "W") {
        2 => 70.0,
        1 => 30.0,
        _ => 0.0,
    }
}

/// `S2`: a tower on the first body segment and on no other 100, no tower 20, others 0.
pub fn first_tower(g: &Graph, m: &Chromosome) -> f64 {
    let (b, t) = (g.node_id("B").expect("B"), g.node_id("T").expect("T"));
    let first = m.root_gene(g).child(0);
    let mut on_first = false;
    let mut elsewhere = false;
    for gene in m.genes(g).filter(|x| x.node() == t) {
        let parent = gene.parent().expect("a tower has a parent");
        if Some(parent) == first && m.gene(g, parent).node() == b {
            on_first = true;
        } else {
            elsewhere = true;
        }
    }
    match (on_first, elsewhere) {
        (true, false) => 100.0,
        (false, false) => 20.0,
        _ => 0.0,
    }
}

/// `T1`: all three main branches 100, two 50, fewer 0.
pub fn main_branches(g: &Graph, m: &Chromosome) -> f64 {
    let trunk = m.root_gene(g).child(0).map(|p| m.gene(g, p));
    match trunk.map_or(0, |t| t.children().count()) {
        3 => 100.0,
        2 => 50.0,
        _ => 0.0,
    }
}

/// `C1`: built on two opposite streets only (north and south, or east and west) 100, others 0.
pub fn opposite_streets(g: &Graph, m: &Chromosome) -> f64 {
    let root = m.root_gene(g);
    let built = |slot: usize| {
        root.child(slot)
            .is_some_and(|p| m.gene(g, p).child(0).is_some())
    };
    let [n, e, s, w] = [built(0), built(1), built(2), built(3)];
    if (n && s && !e && !w) || (e && w && !n && !s) {
        100.0
    } else {
        0.0
    }
}

/// The tasks on the paper's generators.
#[must_use]
pub fn scene_tasks() -> Vec<Task> {
    vec![
        Task {
            name: "S1".into(),
            description: "spaceship: exactly two wing pairs 70, one 30, others 0".into(),
            graph: limited(&Spaceship, 1, 100, 15),
            factors: vec![Box::new(wing_pairs)],
        },
        Task {
            name: "S2".into(),
            description:
                "spaceship: a tower on the first body segment only 100, no tower 20, others 0"
                    .into(),
            graph: limited(&Spaceship, 1, 100, 15),
            factors: vec![Box::new(first_tower)],
        },
        Task {
            name: "T1".into(),
            description: "tree v2: all three main branches 100, two 50, fewer 0".into(),
            graph: limited(&TreeV2, 1, 400, 12),
            factors: vec![Box::new(main_branches)],
        },
        Task {
            name: "C1".into(),
            description: "space-filling city: built on two opposite streets only 100, others 0"
                .into(),
            graph: limited(&SpaceFillingCity, 1, 300, 8),
            factors: vec![Box::new(opposite_streets)],
        },
    ]
}

/// Every task: the toy's two, then the scenes'.
#[must_use]
pub fn all() -> Vec<Task> {
    let mut tasks = shapegen_design::toy::tasks();
    tasks.extend(scene_tasks());
    tasks
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ops::uncontrolled;
    use crate::rng::stream;

    /// Every task scores some default samples above 0 and some at 0, so
    /// none is trivially constant.
    #[test]
    fn tasks_are_not_constant() {
        for task in all() {
            let scores: Vec<f64> = (0..400)
                .map(|i| task.truth(&uncontrolled(&task.graph, &mut stream(9, &[i])).unwrap()))
                .collect();
            assert!(scores.iter().any(|&s| s > 0.0), "{}", task.name);
            assert!(scores.contains(&0.0), "{}", task.name);
        }
    }
}
