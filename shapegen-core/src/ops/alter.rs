//! Alter: redraw all parameters of one gene.

use rand::{Rng, RngExt};

use crate::genome::Chromosome;
use crate::graph::Graph;

/// Alters one gene (paper §5): picks a gene uniformly among those with
/// parameters and redraws **all** of its parameters from the prior.
/// Returns the gene's position, or `None` if no gene has parameters. O(G).
pub fn alter<R: Rng + ?Sized>(graph: &Graph, c: &mut Chromosome, rng: &mut R) -> Option<u32> {
    let has_params = |node| graph.layout(node).param_words > 0;
    let n = c.genes(graph).filter(|g| has_params(g.node())).count();
    if n == 0 {
        return None;
    }
    let k = rng.random_range(0..n);
    let pos = c
        .genes(graph)
        .filter(|g| has_params(g.node()))
        .nth(k)?
        .pos();
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
    super::check_gene(graph, c, pos)?;
    c.redraw_params(graph, pos, rng);
    Ok(())
}
