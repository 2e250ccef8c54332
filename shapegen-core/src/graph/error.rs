//! Problems found when checking a [`GraphSpec`](super::GraphSpec).

use std::fmt;

/// One problem in a generator graph declaration.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum GraphError {
    /// The graph has no nodes.
    #[error("the graph has no nodes")]
    NoNodes,
    /// More nodes than a gene's 16-bit node id can address.
    #[error("the graph has {count} nodes; at most {max} are supported")]
    TooManyNodes {
        /// Number of nodes declared.
        count: usize,
        /// Largest supported number.
        max: usize,
    },
    /// Two nodes share a name.
    #[error("node `{node}` is declared more than once")]
    DuplicateNode {
        /// The repeated name.
        node: String,
    },
    /// Two parameters of one node share a name.
    #[error("node `{node}` declares parameter `{param}` more than once")]
    DuplicateParam {
        /// The node.
        node: String,
        /// The repeated parameter name.
        param: String,
    },
    /// Two slots of one node share a name.
    #[error("node `{node}` declares slot `{slot}` more than once")]
    DuplicateSlot {
        /// The node.
        node: String,
        /// The repeated slot name.
        slot: String,
    },
    /// A node has more slots than a gene's 8-bit slot index can address.
    #[error("node `{node}` has {count} slots; at most {max} are supported")]
    TooManySlots {
        /// The node.
        node: String,
        /// Number of slots declared.
        count: usize,
        /// Largest supported number.
        max: usize,
    },
    /// A slot names a node that does not exist.
    #[error("slot `{slot}` of node `{node}` targets unknown node `{target}`")]
    UnknownTarget {
        /// The node owning the slot.
        node: String,
        /// The slot.
        slot: String,
        /// The unknown target name.
        target: String,
    },
    /// A slot probability is not in `[0, 1]`.
    #[error("slot `{slot}` of node `{node}` has probability {p}, which is not in [0, 1]")]
    BadProbability {
        /// The node owning the slot.
        node: String,
        /// The slot.
        slot: String,
        /// The offending value.
        p: f64,
    },
    /// A parameter's distribution has an empty or ill-defined support.
    #[error("parameter `{param}` of node `{node}`: {reason}")]
    EmptySupport {
        /// The node.
        node: String,
        /// The parameter.
        param: String,
        /// What is wrong.
        reason: &'static str,
    },
    /// The start node name is empty.
    #[error("the graph has no start node")]
    NoStart,
    /// The start node name matches no node.
    #[error("start node `{start}` is not a node of the graph")]
    UnknownStart {
        /// The unknown name.
        start: String,
    },
    /// A node cannot be reached from the start node through slots.
    #[error("node `{node}` cannot be reached from the start node")]
    Unreachable {
        /// The unreachable node.
        node: String,
    },
    /// A node's tag is malformed (see [`check_tag`](super::check_tag)).
    #[error("node `{node}` has tag `{tag}`: {reason}")]
    BadTag {
        /// The node.
        node: String,
        /// The tag as given.
        tag: String,
        /// What is wrong.
        reason: &'static str,
    },
    /// A node carries one tag twice.
    #[error("node `{node}` has tag `{tag}` more than once")]
    DuplicateTag {
        /// The node.
        node: String,
        /// The repeated tag.
        tag: String,
    },
    /// The limits are contradictory.
    #[error("bad limits: {reason}")]
    BadLimits {
        /// What is wrong.
        reason: String,
    },
}

/// Every problem found in a graph declaration, reported at once.
#[derive(Clone, Debug, PartialEq)]
pub struct GraphErrors(pub Vec<GraphError>);

impl GraphErrors {
    /// The individual problems.
    #[must_use]
    pub fn errors(&self) -> &[GraphError] {
        &self.0
    }
}

impl fmt::Display for GraphErrors {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0.as_slice() {
            [one] => write!(f, "invalid generator graph: {one}"),
            many => {
                write!(f, "invalid generator graph ({} problems):", many.len())?;
                for e in many {
                    write!(f, "\n  - {e}")?;
                }
                Ok(())
            }
        }
    }
}

impl std::error::Error for GraphErrors {}
