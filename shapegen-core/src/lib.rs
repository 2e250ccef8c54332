//! placeholder
pub mod genome;
pub mod graph;
pub mod ops;
pub mod optimize;
pub mod rng;
/// prelude
pub mod prelude {
    pub use crate::genome::*;
    pub use crate::graph::*;
    pub use crate::ops::*;
    pub use crate::optimize::*;
}
