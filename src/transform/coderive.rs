//! Grammar co-derivation (thesis Alg. 5.1 and 5.2): two designs derived
//! together from their matched axioms, their outputs paired and blended at
//! every matched shape.

use std::collections::{HashMap, VecDeque};

use crate::glam::{Affine3A, Vec3};

use crate::express::{Instance, Instances, Scope, ShapeId};
use crate::graph::NodeId;

use super::blend::{Pivot, blend_instances, blend_scopes, scaled_about};
use super::design::{DynState, StateObj};
use super::pairing::{corners, distance, pair};
use super::{Mode, Placed, Source, Transformation};

/// When partners are chosen: halfway.
const REFERENCE_TIME: f32 = 0.5;

/// The partners of every co-derivation step, by the genes it co-derives:
/// `[instances, shapes with a match]`, each as pairs of indices in the
/// order the two designs derive them.
pub(crate) type Pairings = HashMap<(u32, u32), [Vec<(usize, usize)>; 2]>;

/// Partners being chosen (and kept), or replayed.
pub(super) enum Pairs<'a> {
    Record(&'a mut Pairings),
    Replay(&'a Pairings),
}

impl Pairs<'_> {
    /// The partners of list `which` of step `key`: recorded ones when
    /// replaying (chosen anew, should a step be new), else chosen now.
    fn get(
        &mut self,
        key: (u32, u32),
        which: usize,
        choose: impl FnOnce() -> Vec<(usize, usize)>,
    ) -> std::borrow::Cow<'_, [(usize, usize)]> {
        match self {
            Self::Replay(p) => match p.get(&key) {
                Some(lists) => std::borrow::Cow::Borrowed(&lists[which]),
                None => std::borrow::Cow::Owned(choose()),
            },
            Self::Record(p) => {
                let lists = p.entry(key).or_default();
                lists[which] = choose();
                std::borrow::Cow::Borrowed(&lists[which])
            }
        }
    }
}

/// Where an unpaired shape placed by `first` grows out of (or shrinks
/// into): with the base pivot, its base (a branch's attachment point);
/// with the centre pivot, the point of its box nearest the centre of the
/// shape being derived (where a box touches what it was attached to, not
/// its middle, which would leave it floating while it grows).
fn growth_point(pivot: Pivot, first: &Affine3A, parent_centre: Vec3) -> Vec3 {
    match pivot {
        Pivot::Base => pivot.of_instance(first),
        Pivot::Centre => {
            if first.matrix3.determinant().abs() < 1e-12 {
                return first.translation.into();
            }
            let local = first.inverse().transform_point3(parent_centre);
            first.transform_point3(local.clamp(Vec3::splat(-0.5), Vec3::splat(0.5)))
        }
    }
}

/// World to the frame of `scope`, in units of its size's length (below
/// 1e-6 it counts as 1e-6). One scale for all axes: dividing by each
/// axis's size would make a thin branch's width count ten times its length.
fn local_frame(scope: &crate::express::Scope) -> Affine3A {
    let size = Vec3::from(scope.size).length().max(1e-6);
    Affine3A::from_scale(Vec3::splat(size.recip())) * scope.frame.inverse()
}

/// A shape of the co-derivation tree still to derive.
pub(super) enum Work {
    /// A matched shape: derived by both designs from one blended scope.
    Pair {
        a: u32,
        b: u32,
        sa: DynState,
        sb: DynState,
        m: usize,
    },
    /// A shape of one design alone.
    Single(Single),
}

/// A shape of one design (the second if `second`), gene `pos` of node
/// `node` from `state`, derived by that design alone and scaled by `fade`
/// about `about`.
pub(super) struct Single {
    pub(super) second: bool,
    pub(super) pos: u32,
    pub(super) state: DynState,
    pub(super) fade: f32,
    pub(super) about: Vec3,
    pub(super) node: NodeId,
}

impl Single {
    /// Gene `pos` (of node `node`) of one design, shown whole in `scope`:
    /// a part of a merged split that the other design has no match for.
    pub(super) fn whole(
        second: bool,
        pos: u32,
        state: &DynState,
        scope: Scope,
        node: NodeId,
    ) -> Work {
        Work::Single(Self {
            second,
            pos,
            state: state.with_scope(scope),
            fade: 1.0,
            about: scope.origin(),
            node,
        })
    }
}

/// What one design makes of a matched shape (Alg. 5.1): instances, and the
/// shapes with a match where its derivation stopped.
#[derive(Default)]
struct Side {
    terminals: Instances,
    leaves: Vec<(u32, DynState, NodeId)>,
}

impl Transformation {
    /// The transformed design at time `t ∈ [0, 1]` (clamped): `t = 0` is
    /// the first design, `t = 1` the second, instance for instance.
    #[must_use]
    pub fn at(&self, t: f32) -> Vec<Placed> {
        let mut out = Vec::new();
        self.at_into(t, &mut out);
        out
    }

    /// [`at`](Self::at) into `out` (cleared first).
    pub fn at_into(&self, t: f32, out: &mut Vec<Placed>) {
        let pairings = self.pairings.get_or_init(|| {
            // Partners are chosen once, on the designs blended halfway, and
            // kept for every t: no shape changes partner mid-sequence.
            let mut recorded = Pairings::default();
            let mut scratch = Vec::new();
            self.derive_at(
                REFERENCE_TIME,
                &mut Pairs::Record(&mut recorded),
                &mut scratch,
            );
            recorded
        });
        self.derive_at(t, &mut Pairs::Replay(pairings), out);
    }

    /// The co-derivation at `t`, with partners recorded or replayed.
    fn derive_at(&self, t: f32, pairs: &mut Pairs<'_>, out: &mut Vec<Placed>) {
        out.clear();
        let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
        let (a, b) = (self.a.stepper(), self.b.stepper());
        let pivot = self.settings.pivot;
        let (sa, sb) = (a.axiom(), b.axiom());
        let w0 = self.matches.timelines()[0].weight(t);
        let root = blend_scopes(&sa.scope(), &sb.scope(), w0, pivot);
        let mut queue = VecDeque::from([Work::Pair {
            a: 0,
            b: 0,
            sa: sa.with_scope(root),
            sb: sb.with_scope(root),
            m: 0,
        }]);
        let mut scratch = Instances::default();
        while let Some(work) = queue.pop_front() {
            match work {
                Work::Single(single) => self.derive_single(&single, &mut scratch, out),
                Work::Pair {
                    a: pa,
                    b: pb,
                    sa,
                    sb,
                    m,
                } => {
                    self.pair_step(t, (pa, pb, m), (&*sa, &*sb), pairs, &mut queue, out);
                }
            }
        }
        if self.settings.merge {
            super::merge::merge_masses(out);
        }
    }

    /// Derives a shape of one design alone, scaled by `fade` about `about`.
    pub(super) fn derive_single(
        &self,
        single: &Single,
        scratch: &mut Instances,
        out: &mut Vec<Placed>,
    ) {
        let Single {
            second,
            pos,
            ref state,
            fade,
            about,
            node,
        } = *single;
        scratch.0.clear();
        let design = self.design(second);
        design
            .stepper()
            .subtree(design.chromosome(), pos, &**state, scratch);
        let source = Source::one(second, node);
        out.extend(scratch.0.iter().map(|i| Placed {
            shape: self.shape_of(second, i.shape),
            transform: scaled_about(&i.transform, about, fade),
            source,
        }));
    }

    /// The first design, or the second.
    pub(super) fn design(&self, second: bool) -> &super::Design {
        if second { &self.b } else { &self.a }
    }

    fn shape_of(&self, second: bool, shape: ShapeId) -> ShapeId {
        if second {
            self.shape_map_b[shape as usize]
        } else {
            self.shape_map_a[shape as usize]
        }
    }

    /// Derives a matched shape with one design until every leaf is a
    /// terminal or has a match (Alg. 5.1), breadth first.
    fn derive(&self, second: bool, pos: u32, state: &dyn StateObj) -> Side {
        let design = self.design(second);
        let (stepper, c) = (design.stepper(), design.chromosome());
        let matched = |n: NodeId| {
            if second {
                self.matches.matched_b(n)
            } else {
                self.matches.matched_a(n)
            }
        };
        let mut side = Side::default();
        let mut children = Vec::new();
        stepper.step(c, pos, state, &mut side.terminals, &mut children);
        let mut queue: VecDeque<(u32, DynState)> = VecDeque::new();
        loop {
            for (p, s) in children.drain(..) {
                let node = c.gene(stepper.graph(), p).node();
                if matched(node) {
                    side.leaves.push((p, s, node));
                } else {
                    queue.push_back((p, s));
                }
            }
            let Some((p, s)) = queue.pop_front() else {
                break;
            };
            stepper.step(c, p, &*s, &mut side.terminals, &mut children);
        }
        side
    }

    /// Where a leaf's subtree places its first instance (its own box if it
    /// places none in its first step): what pairing compares, since
    /// siblings may receive one and the same state from their parent.
    fn first_box(&self, second: bool, pos: u32, state: &dyn StateObj) -> Affine3A {
        let design = self.design(second);
        let mut out = Instances::default();
        design
            .stepper()
            .step(design.chromosome(), pos, state, &mut out, &mut Vec::new());
        out.0
            .first()
            .map_or_else(|| state.scope().instance(), |i| i.transform)
    }

    /// One co-derivation step (thesis Fig. 5.4): derive, pair, blend.
    fn pair_step(
        &self,
        t: f32,
        (pa, pb, m): (u32, u32, usize),
        (sa, sb): (&dyn StateObj, &dyn StateObj),
        pairs: &mut Pairs<'_>,
        queue: &mut VecDeque<Work>,
        out: &mut Vec<Placed>,
    ) {
        let timeline = self.matches.timelines()[m];
        let (w, switched) = (timeline.weight(t), timeline.switched(t));
        self.step_pair((w, switched, None), (pa, pb), (sa, sb), pairs, queue, out);
    }

    /// One co-derivation step at blend weight `w`, discrete choices from
    /// the second design if `switched`: the shapes it places go to `out`,
    /// the shapes still to derive to `queue`. With `each`, every pair of
    /// shapes blends with its own weight drawn from it instead (variations).
    pub(super) fn step_pair(
        &self,
        (w, switched, mut each): (f32, bool, Option<&mut dyn FnMut() -> f32>),
        (pa, pb): (u32, u32),
        (sa, sb): (&dyn StateObj, &dyn StateObj),
        pairs: &mut Pairs<'_>,
        queue: &mut VecDeque<Work>,
        out: &mut Vec<Placed>,
    ) {
        let key = (pa, pb);
        let pivot = self.settings.pivot;
        // Boxes are compared in the frame of the shape being derived, in
        // units of its size: what its rules place relative to it moves
        // little as the shape itself is blended, so the pairing holds over t.
        let mut split_terminals = [Instances::default(), Instances::default()];
        if self.split_step(w, (pa, pb), (sa, sb), queue, &mut split_terminals) {
            // A split node's own instances (if it emits any) blend in order.
            let [ta, tb] = &split_terminals;
            for (i, x) in ta.0.iter().enumerate() {
                match tb.0.get(i) {
                    Some(y) => out.push(Placed {
                        shape: self.shape_of(switched, if switched { y.shape } else { x.shape }),
                        transform: blend_instances(&x.transform, &y.transform, w, pivot),
                        source: Source::Both(x.node, y.node),
                    }),
                    None => {
                        if let Some(fade) = self.fade(false, w, switched) {
                            out.push(self.single(false, x, x.transform.translation.into(), fade));
                        }
                    }
                }
            }
            for y in tb.0.iter().skip(ta.0.len()) {
                if let Some(fade) = self.fade(true, w, switched) {
                    out.push(self.single(true, y, y.transform.translation.into(), fade));
                }
            }
            return;
        }
        let local = local_frame(&sa.scope());
        let parent_centre = sa.scope().origin();
        let side_a = self.derive(false, pa, sa);
        let side_b = self.derive(true, pb, sb);

        // Terminals: instances of matched emitting nodes pair; the same
        // shape is preferred (one box-distance unit) over another.
        let (ta, tb) = (&side_a.terminals.0, &side_b.terminals.0);
        let terminal_pairs = pairs.get(key, 0, || {
            let corners_a: Vec<_> = ta.iter().map(|i| corners(&(local * i.transform))).collect();
            let corners_b: Vec<_> = tb.iter().map(|i| corners(&(local * i.transform))).collect();
            let cost = |i: usize, j: usize| {
                self.matches.of(ta[i].node, tb[j].node)?;
                let same = self.shape_of(false, ta[i].shape) == self.shape_of(true, tb[j].shape);
                let penalty = if same { 0.0 } else { 1.0 };
                Some(distance(&corners_a[i], &corners_b[j]) + penalty)
            };
            self.pairs_of(ta.len(), tb.len(), &cost)
        });
        let (mut used_a, mut used_b) = (vec![false; ta.len()], vec![false; tb.len()]);
        for &(i, j) in terminal_pairs.iter() {
            used_a[i] = true;
            used_b[j] = true;
            let (x, y) = (&ta[i], &tb[j]);
            let (shape_a, shape_b) = (self.shape_of(false, x.shape), self.shape_of(true, y.shape));
            out.push(Placed {
                shape: if switched { shape_b } else { shape_a },
                transform: blend_instances(
                    &x.transform,
                    &y.transform,
                    each.as_mut().map_or(w, |f| f()),
                    pivot,
                ),
                source: Source::Both(x.node, y.node),
            });
        }
        for (second, list, used) in [(false, ta, &used_a), (true, tb, &used_b)] {
            for (x, _) in list.iter().zip(used.iter()).filter(|(_, u)| !**u) {
                if let Some(fade) = self.fade(second, w, switched) {
                    let about = growth_point(pivot, &x.transform, parent_centre);
                    out.push(self.single(second, x, about, fade));
                }
            }
        }

        // Shapes with a match: pair on where their subtrees start.
        let (la, lb) = (&side_a.leaves, &side_b.leaves);
        let leaf_pairs = pairs.get(key, 1, || {
            let boxes = |second: bool, list: &[(u32, DynState, NodeId)]| -> Vec<_> {
                list.iter()
                    .map(|(p, s, _)| corners(&(local * self.first_box(second, *p, &**s))))
                    .collect()
            };
            let (boxes_a, boxes_b) = (boxes(false, la), boxes(true, lb));
            let cost = |i: usize, j: usize| {
                self.matches.of(la[i].2, lb[j].2)?;
                Some(distance(&boxes_a[i], &boxes_b[j]))
            };
            self.pairs_of(la.len(), lb.len(), &cost)
        });
        let (mut used_a, mut used_b) = (vec![false; la.len()], vec![false; lb.len()]);
        for &(i, j) in leaf_pairs.iter() {
            used_a[i] = true;
            used_b[j] = true;
            let (x, y) = (&la[i], &lb[j]);
            let wi = each.as_mut().map_or(w, |f| f());
            let scope = blend_scopes(&x.1.scope(), &y.1.scope(), wi, pivot);
            queue.push_back(Work::Pair {
                a: x.0,
                b: y.0,
                sa: x.1.with_scope(scope),
                sb: y.1.with_scope(scope),
                m: self.matches.of(x.2, y.2).expect("paired shapes match"),
            });
        }
        for (second, list, used) in [(false, la, &used_a), (true, lb, &used_b)] {
            for ((pos, state, node), _) in list.iter().zip(used.iter()).filter(|(_, u)| !**u) {
                if let Some(fade) = self.fade(second, w, switched) {
                    // It grows out of (shrinks into) where its subtree starts.
                    let first = self.first_box(second, *pos, &**state);
                    queue.push_back(Work::Single(Single {
                        second,
                        pos: *pos,
                        about: growth_point(pivot, &first, parent_centre),
                        state: state.clone_box(),
                        fade,
                        node: *node,
                    }));
                }
            }
        }
    }

    /// Partners by the settings' method, with every shape left over given
    /// its nearest partner when matches are one-to-many.
    fn pairs_of(
        &self,
        rows: usize,
        columns: usize,
        cost: &dyn Fn(usize, usize) -> Option<f32>,
    ) -> Vec<(usize, usize)> {
        let pairs = pair(self.settings.pairing, rows, columns, cost);
        if self.settings.merge {
            super::pairing::with_nearest(pairs, rows, columns, cost)
        } else {
            pairs
        }
    }

    /// How much of an unpaired shape of the first (`second = false`) or
    /// second design is shown: `None` when it is absent.
    fn fade(&self, second: bool, w: f32, switched: bool) -> Option<f32> {
        match self.settings.mode {
            Mode::Grow => {
                let f = if second { w } else { 1.0 - w };
                (f > 0.0).then_some(f)
            }
            Mode::Thesis => (switched == second).then_some(1.0),
        }
    }

    fn single(&self, second: bool, x: &Instance, about: Vec3, fade: f32) -> Placed {
        Placed {
            shape: self.shape_of(second, x.shape),
            transform: scaled_about(&x.transform, about, fade),
            source: Source::one(second, x.node),
        }
    }
}
