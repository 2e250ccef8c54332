//! Alter: redraw all parameters of one gene.

use rand::{Rng, RngExt};

use crate::genome::{Chromosome, word};
use crate::graph::Graph;

use super::sample;

/// Alters one gene (paper §5): picks a gene uniformly among those with
/// parameters and redraws **all** of its parameters from the prior.
/// Returns the gene's position, or `None` if no gene has parameters.
pub fn alter<R: Rng + ?Sized>(graph: &Graph, c: &mut Chromosome, rng: &mut R) -> Option<u32> {
    let has_params =
        |pos: u32| u64::from(graph.layout(word::node(c.words[pos as usize])).param_words > 0);
    let pos = sample::weighted(
        rng,
        1,
        |rng: &mut R| Some(c.index[rng.random_range(0..c.len())]),
        has_params,
        |f| c.index.iter().for_each(|&p| f(p)),
    )?;
    c.redraw_params(graph, pos, rng);
    Some(pos)
}

/// Redraws all parameters of the gene at `pos`.
pub fn alter_at<R: Rng + ?Sized>(
    graph: &Graph,
    c: &mut Chromosome,
    pos: u32,
    rng: &mut R,
) -> Result<(), super::OpError> {
    super::check_gene(c, pos)?;
    c.redraw_params(graph, pos, rng);
    Ok(())
}
