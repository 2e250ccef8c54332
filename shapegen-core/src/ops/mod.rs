//! The genetic operators, exactly as the paper defines them: probability-
//! weighted [`grow()`] and [`cut()`], [`alter()`], subtree [`crossover()`], and
//! [`random_individual`]s; and the models made without an optimizer: a
//! generator's [`default_model`] and [`uncontrolled`] generation.
//!
//! Every operator takes a valid chromosome and returns a valid one: a result
//! that would break the graph's limits is never produced (the operator picks
//! among allowed choices, retries, or does nothing). The `*_at` variants
//! apply an operator at a given place and report misuse as an [`OpError`].

mod alter;
mod crossover;
mod cut;
mod default;
mod grow;
mod init;
mod sample;

pub use alter::{alter, alter_at};
pub use crossover::{CrossoverConfig, EdgeMatch, crossover, crossover_at, crossover_into};
pub(crate) use cut::cut_unchecked;
pub use cut::{Cut, cut, cut_at};
pub use default::{UNBOUNDED_CAP, default_model, uncontrolled, uncontrolled_log_density};
pub(crate) use grow::grow_unchecked;
pub use grow::{Grower, Grown, grow, grow_at};
pub use init::{InitLength, random_individual, random_individual_with};

use rand::{Rng, RngExt};
use serde::{Deserialize, Serialize};

use crate::genome::Chromosome;
use crate::graph::Graph;

/// Misuse of an `*_at` operator.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum OpError {
    /// The position is not the start of a gene of this chromosome.
    #[error("word {0} is not a gene position of this chromosome")]
    NotAGene(u32),
    /// The gene has no such slot.
    #[error("the gene at word {pos} has no slot {slot}")]
    NoSuchSlot {
        /// Gene position.
        pos: u32,
        /// Requested slot.
        slot: u32,
    },
    /// The slot already holds a child.
    #[error("slot {slot} of the gene at word {pos} is already expressed")]
    SlotOccupied {
        /// Gene position.
        pos: u32,
        /// Requested slot.
        slot: u32,
    },
    /// The root cannot be cut or swapped.
    #[error("the root gene cannot be cut or swapped")]
    Root,
    /// The two connections are not compatible for crossover.
    #[error("the two connections are not on compatible edges")]
    Incompatible,
    /// The result would break the graph's depth or length limits.
    #[error("the result would break the graph's depth or length limits")]
    Limits,
    /// An initial individual stopped growing below `L_min`.
    #[error(
        "the graph stopped growing at {reached} genes, below its minimum length {min} (check slot probabilities and max_depth)"
    )]
    MinLength {
        /// Genes reached.
        reached: usize,
        /// `L_min`.
        min: usize,
    },
}

/// Checks that `pos` is a gene position of `c`. O(log G).
fn check_gene(c: &Chromosome, pos: u32) -> Result<(), OpError> {
    match c.positions().binary_search(&pos) {
        Ok(_) => Ok(()),
        Err(_) => Err(OpError::NotAGene(pos)),
    }
}

/// One of the three mutations.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Mutation {
    /// [`grow()`].
    Grow,
    /// [`cut()`].
    Cut,
    /// [`alter()`].
    Alter,
}

/// Relative weights of grow, cut and alter when a child is mutated.
///
/// The paper's "30 % = 13.5 % grow + 13.5 % cut + 3 % alter" is a mutation
/// probability of 0.3 with the split `MutationSplit::new(13.5, 13.5, 3.0)`;
/// only ratios matter.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct MutationSplit {
    /// Weight of grow.
    pub grow: f64,
    /// Weight of cut.
    pub cut: f64,
    /// Weight of alter.
    pub alter: f64,
}

impl MutationSplit {
    /// A split with the given weights (each finite and >= 0, not all 0).
    #[must_use]
    pub const fn new(grow: f64, cut: f64, alter: f64) -> Self {
        Self { grow, cut, alter }
    }

    /// Why the weights are unusable, if they are.
    pub fn problem(&self) -> Option<&'static str> {
        let w = [self.grow, self.cut, self.alter];
        if w.iter().any(|x| !x.is_finite() || *x < 0.0) {
            Some("mutation weights must be finite and >= 0")
        } else if w.iter().sum::<f64>() <= 0.0 {
            Some("mutation weights sum to 0")
        } else {
            None
        }
    }

    /// Draws a mutation kind.
    pub fn draw<R: Rng + ?Sized>(&self, rng: &mut R) -> Mutation {
        let u = rng.random::<f64>() * (self.grow + self.cut + self.alter);
        if u < self.grow {
            Mutation::Grow
        } else if u < self.grow + self.cut || self.alter <= 0.0 {
            Mutation::Cut
        } else {
            Mutation::Alter
        }
    }
}

impl Default for MutationSplit {
    /// The paper's spaceship and tree split: 13.5 / 13.5 / 3.
    fn default() -> Self {
        Self::new(13.5, 13.5, 3.0)
    }
}

/// Applies one mutation drawn from `split`. Returns which one, and whether it changed `c`.
pub fn mutate<R: Rng + ?Sized>(
    graph: &Graph,
    c: &mut Chromosome,
    split: &MutationSplit,
    rng: &mut R,
) -> (Mutation, bool) {
    let m = split.draw(rng);
    let changed = match m {
        Mutation::Grow => grow(graph, c, rng).is_some(),
        Mutation::Cut => cut(graph, c, rng).is_some(),
        Mutation::Alter => alter(graph, c, rng).is_some(),
    };
    (m, changed)
}
