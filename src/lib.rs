//! placeholder
pub use shapegen_core::{genome, graph, ops, rng};
/// prelude
pub mod prelude {
    pub use shapegen_core::prelude::*;
}
