//! The declarative generator graph: nodes, parameters, child slots and limits.
//!
//! Every type here is `const`-constructible from `'static` data (the
//! `generator!` macro emits a `static GraphSpec`) and can also be built at run
//! time with [`GraphBuilder`](super::GraphBuilder). A spec is checked and
//! compiled into a [`Graph`](super::Graph) once, before any genome uses it.

use std::borrow::Cow;

use rand::Rng;
use serde::{Deserialize, Serialize};

use super::dist::{Dist, IntDist, choice_problem, sample_choice};

/// The type of a parameter, which fixes how many 32-bit words it occupies in a gene.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ParamKind {
    /// One `f32`.
    F32,
    /// Two `f32`s.
    Vec2,
    /// Three `f32`s.
    Vec3,
    /// One `i32`.
    Int,
    /// An index into a discrete set of options, stored as `u32`.
    Choice,
}

impl ParamKind {
    /// Number of 32-bit words a value of this kind occupies.
    #[must_use]
    pub const fn words(self) -> usize {
        match self {
            Self::F32 | Self::Int | Self::Choice => 1,
            Self::Vec2 => 2,
            Self::Vec3 => 3,
        }
    }
}

/// A parameter's distribution, which also fixes its [`ParamKind`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", content = "dist", rename_all = "snake_case")]
pub enum ParamDist {
    /// A scalar `f32`.
    F32(Dist),
    /// A 2-vector, one distribution per component.
    Vec2([Dist; 2]),
    /// A 3-vector, one distribution per component.
    Vec3([Dist; 3]),
    /// An integer.
    Int(IntDist),
    /// A discrete choice: index `i` is drawn with probability `weights[i] / Σ weights`.
    Choice(Cow<'static, [f64]>),
}

impl ParamDist {
    /// The parameter's kind.
    #[must_use]
    pub const fn kind(&self) -> ParamKind {
        match self {
            Self::F32(_) => ParamKind::F32,
            Self::Vec2(_) => ParamKind::Vec2,
            Self::Vec3(_) => ParamKind::Vec3,
            Self::Int(_) => ParamKind::Int,
            Self::Choice(_) => ParamKind::Choice,
        }
    }

    /// A vec3 that is uniform on the box `[lo, hi]` component-wise (the paper's scale ranges).
    #[must_use]
    pub const fn uniform_vec3(lo: [f32; 3], hi: [f32; 3]) -> Self {
        Self::Vec3([
            Dist::uniform(lo[0], hi[0]),
            Dist::uniform(lo[1], hi[1]),
            Dist::uniform(lo[2], hi[2]),
        ])
    }

    fn components(&self) -> &[Dist] {
        match self {
            Self::F32(d) => std::slice::from_ref(d),
            Self::Vec2(d) => d,
            Self::Vec3(d) => d,
            Self::Int(_) | Self::Choice(_) => &[],
        }
    }

    /// Why the support is empty or ill-defined, if it is.
    pub fn problem(&self) -> Option<&'static str> {
        match self {
            Self::Int(d) => d.problem(),
            Self::Choice(w) => choice_problem(w),
            _ => self.components().iter().find_map(Dist::problem),
        }
    }

    /// Draws a value into `out` (`out.len()` must equal the kind's word count).
    pub fn sample_into<R: Rng + ?Sized>(&self, rng: &mut R, out: &mut [u32]) {
        match self {
            Self::Int(d) => out[0] = d.sample(rng) as u32,
            Self::Choice(w) => out[0] = sample_choice(rng, w),
            _ => {
                for (o, d) in out.iter_mut().zip(self.components()) {
                    *o = d.sample(rng).to_bits();
                }
            }
        }
    }

    /// Writes the distribution's central value into `out` (`out.len()` must
    /// equal the kind's word count): a constant's value, a uniform's
    /// midpoint, a normal's mean (clamped into a truncated normal's range),
    /// an integer range's midpoint rounded down, a choice's most likely
    /// option (the first of equals). Always in the support; what a
    /// generator's default model uses.
    pub fn central_into(&self, out: &mut [u32]) {
        match self {
            Self::Int(d) => out[0] = d.central() as u32,
            Self::Choice(w) => {
                let mut best = 0;
                for (i, &x) in w.iter().enumerate() {
                    if x > w[best] {
                        best = i;
                    }
                }
                out[0] = best as u32;
            }
            _ => {
                for (o, d) in out.iter_mut().zip(self.components()) {
                    *o = d.central().to_bits();
                }
            }
        }
    }

    /// Whether the stored value `words` lies in the support.
    #[must_use]
    pub fn contains(&self, words: &[u32]) -> bool {
        match self {
            Self::Int(d) => d.contains(words[0] as i32),
            Self::Choice(w) => w.get(words[0] as usize).is_some_and(|&w| w > 0.0),
            _ => words
                .iter()
                .zip(self.components())
                .all(|(&x, d)| d.contains(f32::from_bits(x))),
        }
    }

    /// Log-density of the stored value `words` (sum over components); `-inf` outside the support.
    #[must_use]
    pub fn log_density(&self, words: &[u32]) -> f64 {
        match self {
            Self::Int(d) => d.log_density(words[0] as i32),
            Self::Choice(w) => match w.get(words[0] as usize) {
                Some(&wi) if wi > 0.0 => (wi / w.iter().sum::<f64>()).ln(),
                _ => f64::NEG_INFINITY,
            },
            _ => words
                .iter()
                .zip(self.components())
                .map(|(&x, d)| d.log_density(f32::from_bits(x)))
                .sum(),
        }
    }
}

/// One typed, named parameter of a node.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ParamSpec {
    /// Name, unique within its node.
    pub name: Cow<'static, str>,
    /// Distribution (and thereby type).
    pub dist: ParamDist,
}

impl ParamSpec {
    /// A parameter from `'static` data (usable in a `static`).
    #[must_use]
    pub const fn new(name: &'static str, dist: ParamDist) -> Self {
        Self {
            name: Cow::Borrowed(name),
            dist,
        }
    }
}

/// One child slot of a node: an object the node's operation may produce.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SlotSpec {
    /// Name, unique within its node.
    pub name: Cow<'static, str>,
    /// Name of the node that receives this object.
    pub target: Cow<'static, str>,
    /// Probability that an uncontrolled generation expresses this child, in `[0, 1]`.
    pub p: f64,
}

impl SlotSpec {
    /// A slot from `'static` data (usable in a `static`).
    #[must_use]
    pub const fn new(name: &'static str, target: &'static str, p: f64) -> Self {
        Self {
            name: Cow::Borrowed(name),
            target: Cow::Borrowed(target),
            p,
        }
    }
}

/// One node of the generator graph: a parameterized operation.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct NodeSpec {
    /// Name, unique within the graph.
    pub name: Cow<'static, str>,
    /// Parameters, in gene order.
    pub params: Cow<'static, [ParamSpec]>,
    /// Child slots, in gene order.
    pub slots: Cow<'static, [SlotSpec]>,
    /// Whether expressing this node emits geometry (SMC/SOSMC end a step on such a node).
    pub emits: bool,
    /// Semantic tags (`branching`, `segment`, `roof`): two generators' nodes
    /// that share a tag correspond in a design transformation (thesis §5.4.1).
    /// Each is a word of ASCII letters, digits and `_`; see [`check_tag`].
    /// They play no part in the genome: a graph's fingerprint ignores them.
    #[serde(default, skip_serializing_if = "<[_]>::is_empty")]
    pub tags: Cow<'static, [Cow<'static, str>]>,
    /// The axis along which the node's body splits its scope into the
    /// parts it schedules (a CGA split rule, `split!` in `generator!`), if
    /// it is a split node. Design transformations merge two split nodes'
    /// parts as strings (thesis §5.4.4). Not part of the genome: a graph's
    /// fingerprint ignores it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub split: Option<Axis>,
}

/// One of a scope's three local axes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Axis {
    /// The local x axis (width).
    X,
    /// The local y axis (height).
    Y,
    /// The local z axis (depth).
    Z,
}

impl Axis {
    /// The axis's index: x = 0, y = 1, z = 2.
    #[must_use]
    pub const fn index(self) -> usize {
        self as usize
    }
}

impl NodeSpec {
    /// A node from `'static` data (usable in a `static`).
    #[must_use]
    pub const fn new(
        name: &'static str,
        params: &'static [ParamSpec],
        slots: &'static [SlotSpec],
        emits: bool,
    ) -> Self {
        Self {
            name: Cow::Borrowed(name),
            params: Cow::Borrowed(params),
            slots: Cow::Borrowed(slots),
            emits,
            tags: Cow::Borrowed(&[]),
            split: None,
        }
    }
}

/// Optional bounds on derivation trees. Lengths count genes, the root included.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Limits {
    /// Deepest allowed gene (the root has depth 0); `None` = unbounded.
    pub max_depth: Option<u32>,
    /// Smallest allowed chromosome length `L_min` (at least 1).
    pub min_len: u32,
    /// Exclusive upper bound `L_max` on the length (`L < L_max`); `None` = unbounded.
    pub max_len: Option<u32>,
}

impl Limits {
    /// No limits (`L_min` = 1).
    pub const NONE: Self = Self {
        max_depth: None,
        min_len: 1,
        max_len: None,
    };

    /// Whether a chromosome of `len` genes satisfies the length limits.
    #[must_use]
    pub const fn allows_len(&self, len: u32) -> bool {
        len >= self.min_len
            && match self.max_len {
                Some(max) => len < max,
                None => true,
            }
    }

    /// Whether a gene at `depth` is allowed.
    #[must_use]
    pub const fn allows_depth(&self, depth: u32) -> bool {
        match self.max_depth {
            Some(max) => depth <= max,
            None => true,
        }
    }
}

impl Default for Limits {
    fn default() -> Self {
        Self::NONE
    }
}

/// The longest tag, in bytes.
pub const MAX_TAG_LEN: usize = 64;

/// Why `tag` is not a valid node tag, if it is not: a tag is 1 to
/// [`MAX_TAG_LEN`] ASCII letters, digits and `_`, not starting with a digit
/// (a word that reads the same in `generator!`, a builder and a file).
#[must_use]
pub fn check_tag(tag: &str) -> Option<&'static str> {
    if tag.is_empty() {
        Some("a tag cannot be empty")
    } else if tag.len() > MAX_TAG_LEN {
        Some("a tag is at most 64 characters long")
    } else if !tag.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_') {
        Some("a tag holds only ASCII letters, digits and `_`")
    } else if tag.as_bytes()[0].is_ascii_digit() {
        Some("a tag cannot start with a digit")
    } else {
        None
    }
}

/// A complete generator graph declaration.
///
/// Check and compile it with [`Graph::new`](super::Graph::new).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GraphSpec {
    /// Name of the generator (used in files and fingerprints).
    pub name: Cow<'static, str>,
    /// All nodes; a node's index is its node id.
    pub nodes: Cow<'static, [NodeSpec]>,
    /// Name of the start node (the axiom's operation; the root of every derivation tree).
    pub start: Cow<'static, str>,
    /// Bounds on derivation trees.
    pub limits: Limits,
}

impl GraphSpec {
    /// A graph spec from `'static` data (usable in a `static`).
    #[must_use]
    pub const fn new(
        name: &'static str,
        nodes: &'static [NodeSpec],
        start: &'static str,
        limits: Limits,
    ) -> Self {
        Self {
            name: Cow::Borrowed(name),
            nodes: Cow::Borrowed(nodes),
            start: Cow::Borrowed(start),
            limits,
        }
    }

    /// Checks the declaration, reporting every problem at once: duplicate
    /// names, unknown slot targets, probabilities outside `[0, 1]`, empty or
    /// inverted supports, a missing or unknown start node, unreachable nodes
    /// and contradictory limits. [`Graph::new`](super::Graph::new) runs the same checks.
    pub fn validate(&self) -> Result<(), super::GraphErrors> {
        let errors = super::compiled::check(self);
        if errors.is_empty() {
            Ok(())
        } else {
            Err(super::GraphErrors(errors))
        }
    }

    /// The same graph with other limits (e.g. an experiment's `L_min`, `L_max`, `max_depth`).
    #[must_use]
    pub fn with_limits(mut self, limits: Limits) -> Self {
        self.limits = limits;
        self
    }
}
