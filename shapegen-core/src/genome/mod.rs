//! The genome: derivation trees packed into one buffer per individual.
//!
//! A [`Chromosome`] holds all genes of one derivation tree back to back
//! (paper Fig. 5): node id, relative parent link, one relative link per
//! child slot, then the parameters. [`Gene`] views read genes in place,
//! [`Chromosome::validate`] checks every invariant, and [`ChromosomeData`] is
//! the serializable form.

mod chromosome;
mod data;
mod relabel;
mod validate;
pub(crate) mod word;

pub use chromosome::{Chromosome, Gene, Genes, Subtree};
pub use data::{ChromosomeData, FORMAT_VERSION};
pub use validate::GenomeError;

#[cfg(test)]
mod tests;
