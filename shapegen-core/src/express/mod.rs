//! Turning a chromosome into geometry.
//!
//! A [`Generator`] walks a chromosome's derivation tree from the root,
//! applying each gene's operation to the state it receives (by default a
//! [`Scope`]: an oriented box) and emitting shape instances into a
//! [`ModelSink`]. The `generator!` macro writes generators as specialized
//! code; the [`Interpreter`] runs graphs built at run time.

mod generator;
mod interpreter;
mod node_out;
mod pending;
mod scope;
mod sink;
mod split;

/// The axis a split cuts along (see [`Scope::split`]).
pub use crate::graph::Axis;
pub use generator::Generator;
pub use interpreter::{ExpressError, ExpressErrors, Interpreter, Rule, RuleInput, RuleOutput};
pub use node_out::{NodeOut, SlotRef};
pub use pending::Pending;
pub use scope::Scope;
pub use sink::{CountingSink, Instance, Instances, ModelSink, ShapeId};
pub use split::{MAX_REPEATS, SplitPart, SplitSize, split_lengths};
