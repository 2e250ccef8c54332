//! Build a generator graph at run time, define a fitness and evolve it.
//!
//! `cargo run --release --example quickstart`
//!
//! The generator grows towers of stacked boxes with optional side branches;
//! the fitness asks for a tower whose stacked heights add up to 12 and
//! rewards using few boxes.

use std::ops::ControlFlow;

use shapegen::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let graph = GraphBuilder::new("towers")
        .start("Ground")
        .limits(Limits {
            max_depth: Some(40),
            min_len: 2,
            max_len: Some(300),
        })
        .node("Ground", |n| n.slot("base", "Box", 1.0))
        .node("Box", |n| {
            n.emits()
                .param_f32("height", Dist::uniform(0.2, 1.5))
                .param_vec2(
                    "footprint",
                    [Dist::uniform(0.5, 1.0), Dist::uniform(0.5, 1.0)],
                )
                .slot("up", "Box", 0.8)
                .slot("side", "Box", 0.2)
        })
        .build()?;
    let boxes = graph.node_id("Box").expect("declared above");

    // Sum of heights along the chain of `up` children from the base.
    let fitness = FnFitness(|c: &Chromosome| {
        let mut height = 0.0f64;
        let mut gene = c.root_gene(&graph).child(0).map(|p| c.gene(&graph, p));
        while let Some(g) = gene {
            height += f64::from(g.param_f32(0));
            gene = g.child(0).map(|p| c.gene(&graph, p));
        }
        let count = c.genes(&graph).filter(|g| g.node() == boxes).count();
        -(height - 12.0).abs() - 0.01 * count as f64
    });

    let ga = Ga::new(GaParams {
        population: 100,
        elites: 20,
        init: InitLength::Around { l0: 10 },
        ..GaParams::default()
    });
    let mut observer = |s: &GenerationStats<'_>| {
        if s.generation.is_multiple_of(20) {
            println!(
                "generation {:>3}: best {:.4}, mean {:.4}",
                s.generation, s.best, s.mean
            );
        }
        ControlFlow::Continue(())
    };
    let result = ga.run(
        &graph,
        &fitness,
        &Budget::generations(100),
        2024,
        &mut observer,
    )?;
    println!(
        "best fitness {:.4} with {} genes",
        result.best_fitness,
        result.best.len()
    );
    Ok(())
}
