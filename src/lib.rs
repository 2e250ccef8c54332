//! placeholder
pub use shapegen_core::{genome, graph, ops, optimize, rng};
pub mod demo;
/// prelude
pub mod prelude {
    pub use shapegen_core::prelude::*;
}
