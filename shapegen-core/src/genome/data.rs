//! The serializable form of a chromosome, validated on load.

use serde::{Deserialize, Serialize};

use super::Chromosome;
use super::validate::{GenomeError, validate_words};
use crate::graph::Graph;

/// Current version of [`ChromosomeData`]'s format.
pub const FORMAT_VERSION: u32 = 1;

/// A chromosome as stored in files: the graph it belongs to and its raw words.
///
/// Serialize it with any serde format. A file from elsewhere is untrusted:
/// turn data back into a [`Chromosome`] only through
/// [`Chromosome::from_data`], which checks the graph and every invariant.
///
/// ```
/// # use shapegen_core::prelude::*;
/// # let graph = GraphBuilder::new("g").start("A").node("A", |n| n.slot("a", "A", 0.5)).build().unwrap();
/// # let mut rng = shapegen_core::rng::stream(7, &[]);
/// let c = Chromosome::root(&graph, &mut rng);
/// let data = c.to_data(&graph);
/// assert_eq!(Chromosome::from_data(&graph, &data).unwrap(), c);
/// ```
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ChromosomeData {
    /// Format version ([`FORMAT_VERSION`]).
    pub version: u32,
    /// Name of the generator graph.
    pub graph: String,
    /// The graph's [`fingerprint`](Graph::fingerprint), as 16 hex digits.
    pub fingerprint: String,
    /// Number of genes.
    pub genes: usize,
    /// The packed buffer.
    pub words: Vec<u32>,
}

impl Chromosome {
    /// The serializable form of this chromosome.
    #[must_use]
    pub fn to_data(&self, graph: &Graph) -> ChromosomeData {
        ChromosomeData {
            version: FORMAT_VERSION,
            graph: graph.name().to_string(),
            fingerprint: format!("{:016x}", graph.fingerprint()),
            genes: self.len(),
            words: self.words.clone(),
        }
    }

    /// Rebuilds a chromosome from its serialized form, refusing data made for
    /// another graph or breaking any invariant.
    pub fn from_data(graph: &Graph, data: &ChromosomeData) -> Result<Self, GenomeError> {
        Self::from_data_with(graph, data, false)
    }

    /// Like [`from_data`](Self::from_data) for a chromosome still being
    /// built (e.g. an SMC particle): it may be shorter than the graph's
    /// `L_min`; every other invariant is checked.
    pub fn from_partial_data(graph: &Graph, data: &ChromosomeData) -> Result<Self, GenomeError> {
        Self::from_data_with(graph, data, true)
    }

    fn from_data_with(
        graph: &Graph,
        data: &ChromosomeData,
        partial: bool,
    ) -> Result<Self, GenomeError> {
        if data.version != FORMAT_VERSION {
            return Err(GenomeError::Version(data.version));
        }
        let expected_fp = format!("{:016x}", graph.fingerprint());
        if data.fingerprint != expected_fp {
            return Err(GenomeError::ForeignGraph {
                found: data.graph.clone(),
                found_fp: data.fingerprint.clone(),
                expected: graph.name().to_string(),
                expected_fp,
            });
        }
        let index = validate_words(graph, &data.words, partial)?;
        let genes = index.len();
        if genes != data.genes {
            return Err(GenomeError::Count {
                stored: data.genes,
                actual: genes,
            });
        }
        Ok(Self {
            words: data.words.clone(),
            index,
        })
    }
}
