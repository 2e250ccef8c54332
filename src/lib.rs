//! # shapegen
//!
//! Controlled procedural modeling in Rust: declare a procedural generator
//! and a high-level goal, and shapegen evolves the generator's hidden
//! choices until the generated model meets it.
//!
//! shapegen implements *ShapeGenetics: Using Genetic Algorithms for
//! Procedural Modeling* (Haubenwallner, Seidel, Steinberger, Computer
//! Graphics Forum 36(2), 2017): a generator is a graph of parameterized
//! operations ([`graph`]); one model is a derivation tree packed in one buffer
//! ([`genome`]); grow, cut, alter and subtree crossover ([`ops`]) only ever
//! produce models the generator can derive; a genetic algorithm and
//! baselines ([`optimize`]) search for the best one.
//!
//! This crate is the facade: it re-exports [`shapegen_core`] and holds the
//! built-in problems and the `shapegen` command line.
//!
//! ## Example
//!
//! ```
//! use shapegen::demo::{BlocksTarget, blocks_graph};
//! use shapegen::prelude::*;
//!
//! let graph = blocks_graph();
//! let fitness = BlocksTarget { graph: &graph, blocks: 12 };
//! let ga = Ga::new(GaParams { population: 80, elites: 16, init: InitLength::Around { l0: 12 }, ..GaParams::default() });
//! let result = ga.run(&graph, &fitness, &Budget::generations(60), 7, &mut NoObserver)?;
//! println!("best fitness {:.3} after {} evaluations", result.best_fitness, result.evaluations);
//! assert!(result.best_fitness > 0.5); // the optimum is 1
//! # Ok::<(), OptimizeError>(())
//! ```

pub use shapegen_core::{genome, graph, ops, optimize, rng};

pub mod demo;

/// The README's code, compiled and run as a doctest so it cannot rot.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;

/// The types and functions most programs need.
pub mod prelude {
    pub use shapegen_core::prelude::*;
}
