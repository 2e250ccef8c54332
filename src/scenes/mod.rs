//! The paper's generators, written with [`generator!`](crate::generator).
//!
//! Each scene re-creates a generator of *ShapeGenetics* (Haubenwallner et
//! al. 2017) with the nodes, parameter ranges, probabilities and placement
//! of the reference notes; angles are declared in degrees and converted when
//! expressed.

mod spaceship;

pub use spaceship::{ShipState, Spaceship};
