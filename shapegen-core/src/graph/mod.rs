//! The generator graph: which operations exist, their parameters, and which
//! objects each may produce with what probability.
//!
//! Declare a graph as a [`GraphSpec`] (the `generator!` macro emits one as a
//! `static`) or with a [`GraphBuilder`], then check it once with
//! [`Graph::new`]. Every genome, operator and optimizer works on a [`Graph`].

mod builder;
mod compiled;
mod dist;
mod error;
mod spec;

pub use builder::{GraphBuilder, NodeBuilder};
pub use compiled::{Edge, EdgeId, Graph, MAX_NODES, MAX_SLOTS, NodeId, NodeLayout, WEIGHT_ONE};
pub use dist::{Dist, IntDist};
pub use error::{GraphError, GraphErrors};
pub use spec::{
    Axis, GraphSpec, Limits, MAX_TAG_LEN, NodeSpec, ParamDist, ParamKind, ParamSpec, SlotSpec,
    check_tag,
};

#[cfg(test)]
mod tests;
