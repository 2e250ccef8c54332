//! Designing a generator's pdf from preference scores (Dang et al. 2015;
//! Lienhard's thesis, chapter 4): the [`shapegen_design`] crate, re-exported,
//! with design tasks on the paper's generators ([`tasks`]).
//!
//! ```
//! use shapegen::design::{Factor, FactorOptions, toy};
//! use shapegen::ops::uncontrolled;
//! use shapegen::rng::stream;
//!
//! // Score 40 toy models by the thesis's colour task and learn it.
//! let g = toy::graph();
//! let models: Vec<_> = (0..40).map(|i| uncontrolled(&g, &mut stream(1, &[i])).unwrap()).collect();
//! let scores: Vec<f64> = models.iter().map(|m| toy::same_colour(&g, m)).collect();
//! let factor = Factor::fit("colour", &g, &models, &scores, FactorOptions::default())?;
//! let (mean, variance) = factor.predict(&g, &models[0]);
//! assert!((mean - scores[0]).abs() < 20.0 && variance >= 0.0);
//! # Ok::<(), shapegen::design::DesignError>(())
//! ```

#[cfg(feature = "cli")]
mod http;
#[cfg(feature = "cli")]
pub mod server;
pub mod session;
pub mod tasks;

pub use shapegen_design::*;
