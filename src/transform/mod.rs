//! Design transformations (Lienhard's thesis, chapter 5): two procedural
//! designs derived *together*, so that a timeline `t ∈ [0, 1]` morphs one
//! into the other through designs both generators take part in.
//!
//! - [`Design`]: a generator and one derivation of it (a default model, a
//!   GA result, a sample). Any generator whose state is [`Blend`] (the
//!   default [`Scope`](crate::express::Scope) is) can be one side.
//! - [`Matches`]: which nodes of the two generators correspond (*semantic
//!   matches*), from the nodes' tags, with additions and removals, and the
//!   [`Timeline`] of each match.
//! - [`Transformation::at`]: the co-derivation (thesis Alg. 5.1, 5.2).
//!   From the matched axioms, each design derives breadth first until its
//!   leaves are instances or have a match; the two outputs are paired
//!   ([`PairingMethod`]: Munkres or mutual nearest, on the distance of box
//!   corners divided by the size of the shape being derived) and pairs are
//!   blended about a [`Pivot`]; paired shapes with a match co-derive further.
//! - Split rules (`split!`): two matched nodes that both split along one
//!   axis are merged as strings along their cheapest [`edits`] path and
//!   laid out again to partition the blended shape (thesis §5.4.4).
//! - One-to-many matches and merged masses ([`Settings::merge`], Fig. 5.12).
//! - [`Variety`]: variations of several designs (§5.5.1).
//! - Unpaired shapes: in the thesis's mode ([`Mode::Thesis`]) the first
//!   design's are shown before the match's threshold and the second's from
//!   it on, so they pop in and out. In [`Mode::Grow`] (the default) they
//!   shrink into, or grow out of, the point their subtree starts from over
//!   the match's time range, so a sequence has no jumps where the thesis's
//!   has them.
//!
//! ```
//! use shapegen::scenes::{MonopodialTree, SympodialTree};
//! use shapegen::transform::{Design, Transformation};
//!
//! let a = Design::default_model(MonopodialTree)?;
//! let b = Design::default_model(SympodialTree)?;
//! let morph = Transformation::new(a.clone(), b);
//! // The endpoints are the designs themselves.
//! assert_eq!(morph.at(0.0).len(), a.express().len());
//! let halfway = morph.at(0.5);
//! assert!(!halfway.is_empty());
//! # Ok::<(), shapegen::transform::TransformError>(())
//! ```
//!
//! Our trees are written turtle style (a parent places its children), so
//! siblings arrive with different states; pairing still compares where each
//! child's subtree places its first instance, which also tells apart the
//! siblings of generators whose children place themselves (the paper's
//! trees v1 and v2).

mod blend;
mod coderive;
mod design;
pub mod edits;
mod file;
mod matches;
mod merge;
mod pairing;
pub mod sequence;
mod split_merge;
mod variety;

use std::borrow::Cow;

use crate::glam::Affine3A;

use crate::express::{ModelSink, ShapeId};
use crate::graph::NodeId;

pub use blend::{Blend, Pivot, blend_instances, blend_scopes, scaled_about};
pub use design::Design;
pub use file::{Frames, TransformFile, TransformFileError};
pub use matches::{Matches, Timeline};
pub use pairing::PairingMethod;
pub use split_merge::DEFAULT_SPACER;
pub use variety::{Mixing, Variety};

/// What can go wrong setting up a transformation.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum TransformError {
    /// A chromosome is not a derivation of its generator.
    #[error("the chromosome is not a derivation of its generator: {0}")]
    Chromosome(String),
    /// No generator is registered under the name.
    #[error("no generator is registered as `{name}` (registered: {known})")]
    UnknownGenerator {
        /// The name given.
        name: String,
        /// The registered names.
        known: String,
    },
    /// A match names a node its generator does not have.
    #[error("the {which} generator has no node `{node}` (its nodes: {known})")]
    UnknownNode {
        /// `first` or `second`.
        which: &'static str,
        /// The name given.
        node: String,
        /// The generator's nodes.
        known: String,
    },
    /// A timeline or a removal names two nodes that do not match.
    #[error("`{a}` and `{b}` are not a semantic match (give both a tag, or add the match)")]
    NotAMatch {
        /// The first generator's node.
        a: String,
        /// The second generator's node.
        b: String,
    },
    /// The start nodes always match.
    #[error("the start nodes always match; their match cannot be removed")]
    StartMatch,
    /// A variety needs two designs at least.
    #[error("a variety needs at least two designs, got {0}")]
    TooFewDesigns(usize),
    /// The spacer tag is not a tag.
    #[error("the spacer `{tag}` is not a tag: {reason}")]
    BadSpacer {
        /// The tag given.
        tag: String,
        /// What is wrong.
        reason: String,
    },
    /// A timeline's times are unusable.
    #[error("the timeline of `{a}` and `{b}`: {reason}")]
    Timeline {
        /// The first generator's node.
        a: String,
        /// The second generator's node.
        b: String,
        /// What is wrong.
        reason: &'static str,
    },
}

/// What happens to shapes that find no partner.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Mode {
    /// They shrink into (first design) or grow out of (second design) the
    /// point their subtree starts from, over their match's time range: no
    /// shape appears or vanishes at a size above zero.
    #[default]
    Grow,
    /// The thesis's rule: the first design's are kept before the match's
    /// threshold, the second's from it on.
    Thesis,
}

/// How a transformation pairs and blends.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Settings {
    /// How shapes are paired.
    pub pairing: PairingMethod,
    /// What unpaired shapes do.
    pub mode: Mode,
    /// The point blended shapes turn about.
    pub pivot: Pivot,
    /// One-to-many matches and merged masses (thesis Fig. 5.12): a shape
    /// left without a partner takes its nearest, shared, and blended
    /// shapes of one kind (the same shape from the same pair of nodes)
    /// that intersect become one box around them.
    pub merge: bool,
}

/// Which design a placed shape comes from, with the node(s) that emitted it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// The first design alone.
    A(NodeId),
    /// The second design alone.
    B(NodeId),
    /// A blend of both (the first's node, the second's).
    Both(NodeId, NodeId),
}

impl Source {
    /// From one design alone: the second if `second`, else the first.
    pub(crate) fn one(second: bool, node: NodeId) -> Self {
        if second { Self::B(node) } else { Self::A(node) }
    }
}

/// One shape of a transformed design.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placed {
    /// Index into [`Transformation::shapes`].
    pub shape: ShapeId,
    /// Unit mesh to world.
    pub transform: Affine3A,
    /// Where it comes from.
    pub source: Source,
}

/// Sends placed shapes to a sink (a renderer, a voxelizer, an OBJ writer).
pub fn emit_into<S: ModelSink>(shapes: &[Placed], sink: &mut S) {
    for p in shapes {
        sink.emit(p.shape, &p.transform);
    }
}

/// Two designs and how they co-derive.
#[derive(Clone, Debug)]
pub struct Transformation {
    a: Design,
    b: Design,
    matches: Matches,
    settings: Settings,
    shapes: Vec<Cow<'static, str>>,
    shape_map_a: Vec<ShapeId>,
    shape_map_b: Vec<ShapeId>,
    /// Partners, chosen on first use and kept for every t.
    pairings: std::sync::OnceLock<coderive::Pairings>,
    /// The tag of the nodes split merging leaves out and puts back.
    spacer: String,
    /// Split statistics and edit paths, found on first use.
    splits: split_merge::SplitMemory,
}

impl Transformation {
    /// Transforms `a` into `b`, with the matches their tags give and the
    /// default settings (Munkres, [`Mode::Grow`], centre pivot).
    #[must_use]
    pub fn new(a: Design, b: Design) -> Self {
        let matches = Matches::from_tags(a.graph(), b.graph());
        let mut shapes: Vec<Cow<'static, str>> = a.shapes().to_vec();
        let shape_map_a = (0..shapes.len() as ShapeId).collect();
        let shape_map_b = b
            .shapes()
            .iter()
            .map(|s| match shapes.iter().position(|x| x == s) {
                Some(i) => i as ShapeId,
                None => {
                    shapes.push(s.clone());
                    (shapes.len() - 1) as ShapeId
                }
            })
            .collect();
        Self {
            a,
            b,
            matches,
            settings: Settings::default(),
            shapes,
            shape_map_a,
            shape_map_b,
            pairings: std::sync::OnceLock::new(),
            spacer: DEFAULT_SPACER.to_string(),
            splits: split_merge::SplitMemory::default(),
        }
    }

    /// The same transformation with the nodes tagged `tag` as the spacers
    /// of split rules (default [`DEFAULT_SPACER`], `wall`): merging two
    /// splits leaves them out of the strings and puts them back between
    /// the parts (thesis §5.4.4).
    ///
    /// # Errors
    /// [`TransformError::BadSpacer`] if `tag` is not a valid tag.
    pub fn with_spacer(mut self, tag: &str) -> Result<Self, TransformError> {
        if let Some(reason) = crate::graph::check_tag(tag) {
            return Err(TransformError::BadSpacer {
                tag: tag.to_string(),
                reason: reason.to_string(),
            });
        }
        self.spacer = tag.to_string();
        self.forget_partners();
        self.splits = split_merge::SplitMemory::default();
        Ok(self)
    }

    /// The tag of split rules' spacers.
    #[must_use]
    pub fn spacer(&self) -> &str {
        &self.spacer
    }

    /// Forgets the partners chosen (they depend on the settings, the
    /// matches and the timelines).
    fn forget_partners(&mut self) {
        self.pairings = std::sync::OnceLock::new();
    }

    /// Forgets the partners and the edit paths (which depend on the
    /// matches); the split statistics depend on the spacer alone.
    fn forget_matched(&mut self) {
        self.forget_partners();
        self.splits.forget_paths();
    }

    /// The same transformation with other settings.
    #[must_use]
    pub fn with_settings(mut self, settings: Settings) -> Self {
        self.settings = settings;
        self.forget_partners();
        self
    }

    /// The settings.
    #[must_use]
    pub fn settings(&self) -> Settings {
        self.settings
    }

    /// The first design.
    #[must_use]
    pub fn first(&self) -> &Design {
        &self.a
    }

    /// The second design.
    #[must_use]
    pub fn second(&self) -> &Design {
        &self.b
    }

    /// The semantic matches.
    #[must_use]
    pub fn matches(&self) -> &Matches {
        &self.matches
    }

    /// Adds the match of the first generator's node `a` with the second's `b`.
    pub fn add_match(&mut self, a: &str, b: &str) -> Result<(), TransformError> {
        self.forget_matched();
        self.matches.add(self.a.graph(), self.b.graph(), a, b)
    }

    /// Removes the match of `a` with `b`.
    pub fn remove_match(&mut self, a: &str, b: &str) -> Result<(), TransformError> {
        self.forget_matched();
        self.matches.remove(self.a.graph(), self.b.graph(), a, b)
    }

    /// Sets the timeline of the match of `a` with `b`.
    pub fn set_timeline(
        &mut self,
        a: &str,
        b: &str,
        timeline: Timeline,
    ) -> Result<(), TransformError> {
        self.forget_partners();
        self.matches
            .set_timeline(self.a.graph(), self.b.graph(), a, b, timeline)
    }

    /// Sets the timeline of every match.
    pub fn set_all_timelines(&mut self, timeline: Timeline) -> Result<(), TransformError> {
        self.matches.set_all_timelines(timeline)?;
        self.forget_partners();
        Ok(())
    }

    /// Rules (nodes) of both generators, and the share of them (in %) that
    /// have at least one match: the sparsity of the correspondences
    /// (thesis Tab. 5.1, "#Rules" and "%NT w. Match").
    #[must_use]
    pub fn matched_rules(&self) -> (usize, f64) {
        let (ga, gb) = (self.a.graph(), self.b.graph());
        let rules = ga.node_count() + gb.node_count();
        let matched = (0..ga.node_count() as NodeId)
            .filter(|&n| self.matches.matched_a(n))
            .count()
            + (0..gb.node_count() as NodeId)
                .filter(|&n| self.matches.matched_b(n))
                .count();
        (rules, 100.0 * matched as f64 / rules.max(1) as f64)
    }

    /// The shape names [`Placed::shape`] indexes: the first design's, then
    /// the second's that the first does not have.
    #[must_use]
    pub fn shapes(&self) -> &[Cow<'static, str>] {
        &self.shapes
    }
}
