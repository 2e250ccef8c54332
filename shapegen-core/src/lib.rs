//! # shapegen-core
//!
//! The engine of [shapegen](https://crates.io/crates/shapegen): generator
//! graphs, the packed derivation-tree genome, the genetic operators and the
//! optimizers of *ShapeGenetics: Using Genetic Algorithms for Procedural
//! Modeling* (Haubenwallner, Seidel, Steinberger, Computer Graphics Forum
//! 36(2), 2017). No I/O and no rendering live here.
//!
//! - [`graph`]: a procedural generator as a graph of parameterized
//!   operations; each child slot has the probability `p` that an
//!   uncontrolled generation produces it. Declare a [`graph::GraphSpec`]
//!   (statically, or with [`graph::GraphBuilder`]) and check it once into a
//!   [`graph::Graph`].
//! - [`genome`]: a [`genome::Chromosome`] is one derivation tree packed in
//!   one buffer (paper Fig. 5), with relative links so subtrees move as plain
//!   copies, and a validator for every invariant.
//! - [`ops`]: the paper's operators: probability-weighted [`ops::grow`] and
//!   [`ops::cut`], [`ops::alter`], subtree [`ops::crossover`] at compatible
//!   connections, and [`ops::random_individual`]s. None can produce a
//!   chromosome the graph could not derive.
//! - [`optimize`]: the [`optimize::Optimizer`] trait, [`optimize::Fitness`],
//!   [`optimize::Budget`], [`optimize::Observer`], the genetic algorithm
//!   [`optimize::Ga`] (paper Algorithm 1) and [`optimize::RandomSearch`].
//! - [`express`]: the [`express::Generator`] trait turning a chromosome into
//!   shape instances, the paper's [`express::Scope`], sinks, and a run-time
//!   [`express::Interpreter`].
//! - [`rng`]: the deterministic random streams behind reproducible runs.
//!
//! ## Example
//!
//! A generator of chains of blocks, each with a width; the fitness asks for
//! a total width of 10 with as few blocks as possible.
//!
//! ```
//! use shapegen_core::prelude::*;
//!
//! let graph = GraphBuilder::new("chain")
//!     .start("Root")
//!     .limits(Limits { max_depth: None, min_len: 2, max_len: Some(200) })
//!     .node("Root", |n| n.slot("first", "Block", 1.0))
//!     .node("Block", |n| {
//!         n.emits()
//!             .param_f32("width", Dist::uniform(0.5, 2.0))
//!             .slot("next", "Block", 0.7)
//!     })
//!     .build()?;
//!
//! // Maximize: total width close to 10, with few blocks.
//! let block = graph.node_id("Block").unwrap();
//! let fitness = FnFitness(|c: &Chromosome| {
//!     let width: f32 = c.genes(&graph).filter(|g| g.node() == block).map(|g| g.param_f32(0)).sum();
//!     -f64::from((width - 10.0).abs()) - 0.01 * c.len() as f64
//! });
//!
//! let ga = Ga::new(GaParams { population: 60, elites: 10, init: InitLength::Around { l0: 8 }, ..GaParams::default() });
//! let result = ga.run(&graph, &fitness, &Budget::generations(30), 42, &mut NoObserver)?;
//! assert!(result.best_fitness > -1.0);
//! result.best.validate(&graph)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod express;
pub mod genome;
pub mod graph;
pub mod ops;
pub mod optimize;
pub mod rng;

/// Lets this crate's own tests and docs name `::shapegen_core`.
extern crate self as shapegen_core;

/// Re-exported for generated code and for users of [`express`].
pub use glam;

/// The types and functions most programs need.
pub mod prelude {
    pub use crate::express::{Generator, Instances, ModelSink, Scope};
    pub use crate::genome::{Chromosome, ChromosomeData, Gene, GenomeError};
    pub use crate::graph::{
        Dist, Graph, GraphBuilder, GraphError, GraphErrors, GraphSpec, IntDist, Limits, NodeSpec,
        ParamDist, ParamKind, ParamSpec, SlotSpec,
    };
    pub use crate::ops::{
        CrossoverConfig, Cut, EdgeMatch, Grower, Grown, InitLength, Mutation, MutationSplit,
        OpError, alter, alter_at, crossover, crossover_at, crossover_into, cut, cut_at, grow,
        grow_at, mutate, random_individual, random_individual_with,
    };
    pub use crate::optimize::{
        Budget, Fitness, FnFitness, Ga, GaParams, GenerationStats, Individual, NoObserver,
        Observer, OptimizeError, Optimizer, RandomSearch, RunResult, StopReason,
    };
}
