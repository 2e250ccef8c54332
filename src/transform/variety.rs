//! Variety from several designs (thesis §5.5.1): new designs made by
//! co-deriving parts of several exemplars at random.
//!
//! A [`Variety`] holds two or more designs. A variation starts from two of
//! them chosen at random and co-derives their axioms; at every later step,
//! for each pair of matched shapes, it chooses two of the designs that
//! define the shape (the two that made it, and every other design with a
//! rule that matches, one of whose uses is taken at random) and co-derives
//! them with a random blend weight and threshold. Unpaired shapes follow
//! the thesis's rule: kept from the first design below the threshold, from
//! the second above it. Everything is drawn from the variation's seed, so
//! a seed is enough to make a variation again.

use std::borrow::Cow;
use std::collections::{HashMap, VecDeque};

use rand::RngExt;

use crate::express::{Instances, ShapeId};
use crate::graph::NodeId;

use super::coderive::{Pairings, Pairs, Work};
use super::design::DynState;
use super::{Design, Mode, Placed, Settings, TransformError, Transformation, blend_scopes};

/// How a variation mixes its designs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Mixing {
    /// Random blend weights: shapes in between the designs' (the thesis's).
    #[default]
    Blend,
    /// Weights 0 or 1 only: each step takes one design's rule whole (rule
    /// switching, the baseline blending is measured against).
    Switch,
}

/// Two or more designs and what their variations need.
#[derive(Clone, Debug)]
pub struct Variety {
    designs: Vec<Design>,
    /// `pairs[i][j - i - 1]`: design `i` into design `j`, for `i < j`.
    pairs: Vec<Vec<Transformation>>,
    shapes: Vec<Cow<'static, str>>,
    /// For each pair as in `pairs`, its shape ids to ours.
    shape_maps: Vec<Vec<Vec<ShapeId>>>,
    /// For each design, the genes of each node.
    genes: Vec<HashMap<NodeId, Vec<u32>>>,
}

impl Variety {
    /// The variety of `designs`, matched by their nodes' tags.
    ///
    /// # Errors
    /// [`TransformError::TooFewDesigns`] for fewer than two designs.
    pub fn new(designs: Vec<Design>) -> Result<Self, TransformError> {
        if designs.len() < 2 {
            return Err(TransformError::TooFewDesigns(designs.len()));
        }
        let mut shapes: Vec<Cow<'static, str>> = Vec::new();
        for d in &designs {
            for s in d.shapes() {
                if !shapes.contains(s) {
                    shapes.push(s.clone());
                }
            }
        }
        let settings = Settings {
            mode: Mode::Thesis,
            ..Settings::default()
        };
        let n = designs.len();
        let mut pairs = Vec::with_capacity(n);
        let mut shape_maps = Vec::with_capacity(n);
        for i in 0..n {
            let (mut row, mut maps) = (Vec::new(), Vec::new());
            for j in i + 1..n {
                let t = Transformation::new(designs[i].clone(), designs[j].clone())
                    .with_settings(settings);
                maps.push(
                    t.shapes()
                        .iter()
                        .map(|s| {
                            shapes.iter().position(|x| x == s).expect("every shape") as ShapeId
                        })
                        .collect(),
                );
                row.push(t);
            }
            pairs.push(row);
            shape_maps.push(maps);
        }
        let genes = designs
            .iter()
            .map(|d| {
                let mut by_node: HashMap<NodeId, Vec<u32>> = HashMap::new();
                for g in d.chromosome().genes(d.graph()) {
                    by_node.entry(g.node()).or_default().push(g.pos());
                }
                by_node
            })
            .collect();
        Ok(Self {
            designs,
            pairs,
            shapes,
            shape_maps,
            genes,
        })
    }

    /// The designs.
    #[must_use]
    pub fn designs(&self) -> &[Design] {
        &self.designs
    }

    /// The shape names [`Placed::shape`] indexes in a variation: every
    /// design's, in the order the designs are given.
    #[must_use]
    pub fn shapes(&self) -> &[Cow<'static, str>] {
        &self.shapes
    }

    /// Design `i` into design `j` (`i < j`) and its shape map.
    fn pair(&self, i: usize, j: usize) -> (&Transformation, &[ShapeId]) {
        (&self.pairs[i][j - i - 1], &self.shape_maps[i][j - i - 1])
    }

    /// The node of gene `pos` of design `d`.
    fn node(&self, d: usize, pos: u32) -> NodeId {
        let design = &self.designs[d];
        design.chromosome().gene(design.graph(), pos).node()
    }

    /// Whether node `x` of design `i` matches node `y` of design `k`.
    fn matches(&self, (i, x): (usize, NodeId), (k, y): (usize, NodeId)) -> bool {
        if i < k {
            self.pair(i, k).0.matches().of(x, y).is_some()
        } else {
            self.pair(k, i).0.matches().of(y, x).is_some()
        }
    }

    /// The variation of `seed`: the same seed gives the same variation.
    /// Shapes index [`shapes`](Self::shapes); a shape's source names the
    /// nodes of the two designs of the step that placed it.
    #[must_use]
    pub fn variation(&self, seed: u64, mixing: Mixing) -> Vec<Placed> {
        let mut rng = crate::rng::stream(seed, &[0x7661_7269]);
        let n = self.designs.len();
        let draw = |rng: &mut crate::rng::ShapeRng| -> (f32, bool) {
            let w: f32 = rng.random();
            let threshold: f32 = rng.random();
            match mixing {
                Mixing::Blend => (w, w >= threshold),
                Mixing::Switch => {
                    let second = w >= 0.5;
                    (if second { 1.0 } else { 0.0 }, second)
                }
            }
        };
        let two = |rng: &mut crate::rng::ShapeRng, k: usize| -> (usize, usize) {
            let x = rng.random_range(0..k);
            let y = (x + 1 + rng.random_range(0..k - 1)) % k;
            (x.min(y), x.max(y))
        };
        let (i, j) = two(&mut rng, n);
        let (ai, aj) = (
            self.designs[i].stepper().axiom(),
            self.designs[j].stepper().axiom(),
        );
        let (w, _) = draw(&mut rng);
        let root = blend_scopes(&ai.scope(), &aj.scope(), w, super::Pivot::Centre);
        let mut queue = VecDeque::from([Step {
            lo: i,
            hi: j,
            a: 0,
            b: 0,
            sa: ai.with_scope(root),
            sb: aj.with_scope(root),
        }]);
        let (mut out, mut placed, mut local) = (Vec::new(), Vec::new(), VecDeque::new());
        let mut scratch = Instances::default();
        while let Some(step) = queue.pop_front() {
            let (t, map) = self.pair(step.lo, step.hi);
            let mut chosen = Pairings::default();
            placed.clear();
            let (w, switched) = draw(&mut rng);
            // Blended variations give every pair of shapes its own weight.
            let mut own = crate::rng::stream(rng.random(), &[0x006f_776e]);
            let mut weight = || -> f32 { own.random() };
            let each: Option<&mut dyn FnMut() -> f32> = match mixing {
                Mixing::Blend => Some(&mut weight),
                Mixing::Switch => None,
            };
            t.step_pair(
                (w, switched, each),
                (step.a, step.b),
                (&*step.sa, &*step.sb),
                &mut Pairs::Record(&mut chosen),
                &mut local,
                &mut placed,
            );
            for work in local.drain(..) {
                match work {
                    Work::Pair { a, b, sa, sb, .. } => {
                        queue.push_back(self.next_step(
                            &mut rng,
                            (step.lo, a, sa),
                            (step.hi, b, sb),
                        ));
                    }
                    Work::Single(single) => t.derive_single(&single, &mut scratch, &mut placed),
                }
            }
            out.extend(placed.drain(..).map(|p| Placed {
                shape: map[p.shape as usize],
                ..p
            }));
        }
        out
    }

    /// The next step of a matched pair: two of the designs that define the
    /// shape, the pair's own or others' with a matching rule.
    fn next_step(
        &self,
        rng: &mut crate::rng::ShapeRng,
        (lo, a, sa): (usize, u32, DynState),
        (hi, b, sb): (usize, u32, DynState),
    ) -> Step {
        let scope = sa.scope();
        let node = self.node(lo, a);
        let mut candidates: Vec<(usize, u32, DynState)> = vec![(lo, a, sa), (hi, b, sb)];
        for k in (0..self.designs.len()).filter(|&k| k != lo && k != hi) {
            let mut uses: Vec<u32> = self.genes[k]
                .iter()
                .filter(|&(&y, _)| self.matches((lo, node), (k, y)))
                .flat_map(|(_, p)| p.iter().copied())
                .collect();
            if uses.is_empty() {
                continue;
            }
            uses.sort_unstable();
            let pos = uses[rng.random_range(0..uses.len())];
            let state = self.designs[k].stepper().axiom().with_scope(scope);
            candidates.push((k, pos, state));
        }
        let x = rng.random_range(0..candidates.len());
        let mut y = rng.random_range(0..candidates.len() - 1);
        if y >= x {
            y += 1;
        }
        let (x, y) = (x.min(y), x.max(y));
        let second = candidates.swap_remove(y);
        let first = candidates.swap_remove(x);
        let (first, second) = if first.0 < second.0 {
            (first, second)
        } else {
            (second, first)
        };
        Step {
            lo: first.0,
            hi: second.0,
            a: first.1,
            b: second.1,
            sa: first.2,
            sb: second.2,
        }
    }
}

/// A matched shape two designs co-derive next.
struct Step {
    lo: usize,
    hi: usize,
    a: u32,
    b: u32,
    sa: DynState,
    sb: DynState,
}
