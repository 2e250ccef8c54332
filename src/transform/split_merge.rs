//! Merging two split rules (thesis §5.4.4). Shapes a split makes cannot
//! be blended one by one: a part grows only if another shrinks. So when
//! both designs split a matched shape along the same axis, their parts
//! are read as strings (spacers, the nodes tagged [`DEFAULT_SPACER`] or as
//! set, left out), the cheapest edit path between the strings is found
//! ([`edit_path`]), the match's blend weight picks a string on it, and the
//! string is laid out to partition the shape again: each part the length
//! its symbol has on average where the designs split (interpolated toward
//! its match's), spacers put back between them with the average gaps their
//! neighbours have, stretched alike to fill.
//!
//! At weight 0 and 1 the split is the design's own, part for part.

use std::collections::{HashMap, VecDeque};
use std::sync::{Arc, Mutex};

use crate::express::{Instances, Scope, SplitSize};
use crate::graph::{Axis, NodeId};

use super::Transformation;
use super::coderive::{Single, Work};
use super::design::DynState;
use super::edits::{EditError, EditPath, edit_path};

/// The tag of spacer nodes unless a transformation names another.
pub const DEFAULT_SPACER: &str = "wall";

/// A symbol of a split string: a node of one of the designs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(crate) struct Sym {
    second: bool,
    node: NodeId,
}

/// A running mean.
#[derive(Clone, Copy, Debug, Default)]
struct Mean {
    sum: f64,
    n: u32,
}

impl Mean {
    fn add(&mut self, x: f32) {
        self.sum += f64::from(x);
        self.n += 1;
    }

    fn get(self) -> Option<f32> {
        (self.n > 0).then(|| (self.sum / f64::from(self.n)) as f32)
    }
}

/// Lengths and gaps of split parts, by symbol (a gap by its neighbours;
/// `None` is the end of the split shape).
#[derive(Clone, Debug, Default)]
pub(crate) struct SplitStats {
    lengths: HashMap<Sym, Mean>,
    gaps: HashMap<(Option<Sym>, Option<Sym>), Mean>,
    beside: HashMap<Sym, Mean>,
    all_gaps: Mean,
    all_lengths: Mean,
}

impl SplitStats {
    fn add(&mut self, made: &Made) {
        for p in &made.parts {
            self.lengths.entry(p.sym).or_default().add(p.length);
            self.all_lengths.add(p.length);
        }
        let n = made.parts.len();
        for (i, &g) in made.gaps.iter().enumerate() {
            let l = i.checked_sub(1).map(|j| made.parts[j].sym);
            let r = made.parts.get(i).map(|p| p.sym);
            debug_assert!(i <= n);
            self.gaps.entry((l, r)).or_default().add(g);
            for s in [l, r].into_iter().flatten() {
                self.beside.entry(s).or_default().add(g);
            }
            self.all_gaps.add(g);
        }
    }

    fn of(made: &Made) -> Self {
        let mut s = Self::default();
        s.add(made);
        s
    }
}

/// One split as a design made it: the parts that are symbols, in order,
/// the spacers, and the gaps (`gaps[i]` before part `i`, the last after
/// the last part).
pub(crate) struct Made {
    parts: Vec<MadePart>,
    spacers: Vec<(u32, DynState)>,
    gaps: Vec<f32>,
    /// What fills each gap, in order: spacers (by index into `spacers`)
    /// and empty stretches (`None`), with their lengths.
    fills: Vec<Vec<(Option<usize>, f32)>>,
    /// Every child, as scheduled.
    children: Vec<(u32, DynState)>,
}

struct MadePart {
    sym: Sym,
    length: f32,
}

/// A merged split's layout before it is fitted: part lengths, gaps, and
/// the side whose own gap fillings are reused (when the string stands part
/// for part where that side's split does).
struct Layout {
    lengths: Vec<f32>,
    gaps: Vec<f32>,
    fills: Option<usize>,
}

/// The statistics a merged split is laid out from: the two splits being
/// merged, and the designs' whole derivations.
struct Stats<'a> {
    local: [SplitStats; 2],
    global: &'a [SplitStats; 2],
}

/// Edit paths between split strings, found once per pair of strings.
#[derive(Default)]
pub(crate) struct EditCache(Mutex<HashMap<PathKey, PathResult>>);

type PathKey = (Vec<Sym>, Vec<Sym>);
type PathResult = Result<Arc<EditPath<Sym>>, EditError>;

impl Clone for EditCache {
    fn clone(&self) -> Self {
        Self::default()
    }
}

impl std::fmt::Debug for EditCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("EditCache")
    }
}

/// The two designs' split statistics, and found edit paths.
#[derive(Clone, Debug, Default)]
pub(crate) struct SplitMemory {
    stats: std::sync::OnceLock<[SplitStats; 2]>,
    paths: EditCache,
}

impl SplitMemory {
    /// Forgets the edit paths (the matches changed).
    pub(crate) fn forget_paths(&mut self) {
        self.paths = EditCache::default();
    }
}

impl Transformation {
    fn is_spacer(&self, second: bool, node: NodeId) -> bool {
        self.design(second)
            .graph()
            .node(node)
            .tags
            .iter()
            .any(|t| t == self.spacer.as_str())
    }

    /// Reads the split a gene of one design made of `scope` along `axis`
    /// from the children it scheduled.
    fn read_split(
        &self,
        second: bool,
        axis: Axis,
        scope: &Scope,
        children: Vec<(u32, DynState)>,
    ) -> Made {
        let k = axis.index();
        let extent = scope.size[k].abs();
        let to_local = scope.frame.inverse();
        let design = self.design(second);
        let (mut parts, mut spacers, mut gaps) = (Vec::new(), Vec::new(), Vec::new());
        let (mut fills, mut fill) = (Vec::new(), Vec::new());
        // The end of the last part, and of the last child of any kind.
        let (mut end, mut at) = (0.0f32, 0.0f32);
        // Round-off, not a gap.
        let tiny = 1e-4 * extent;
        for (pos, state) in &children {
            let node = design.chromosome().gene(design.graph(), *pos).node();
            let s = state.scope();
            let length = s.size[k].abs();
            let centre = to_local.transform_point3(s.origin())[k] + 0.5 * extent;
            let start = centre - 0.5 * length;
            if start > at + tiny {
                fill.push((None, start - at));
            }
            let gap = start - end;
            at = at.max(start + length);
            if self.is_spacer(second, node) {
                fill.push((Some(spacers.len()), length));
                spacers.push((*pos, state.clone_box()));
                continue;
            }
            gaps.push(if gap > tiny { gap } else { 0.0 });
            fills.push(std::mem::take(&mut fill));
            end = start + length;
            parts.push(MadePart {
                sym: Sym { second, node },
                length,
            });
        }
        if extent > at + tiny {
            fill.push((None, extent - at));
        }
        let gap = extent - end;
        gaps.push(if gap > tiny { gap } else { 0.0 });
        fills.push(fill);
        Made {
            parts,
            spacers,
            gaps,
            fills,
            children,
        }
    }

    /// Part lengths and gaps over each design's whole derivation.
    fn split_stats(&self) -> &[SplitStats; 2] {
        self.splits
            .stats
            .get_or_init(|| [self.collect_stats(false), self.collect_stats(true)])
    }

    fn collect_stats(&self, second: bool) -> SplitStats {
        let design = self.design(second);
        let (stepper, c) = (design.stepper(), design.chromosome());
        let mut stats = SplitStats::default();
        let mut queue: VecDeque<(u32, DynState)> = VecDeque::from([(0, stepper.axiom())]);
        let (mut children, mut scratch) = (Vec::new(), Instances::default());
        while let Some((pos, state)) = queue.pop_front() {
            scratch.0.clear();
            if let Some((axis, scope)) = stepper.step(c, pos, &*state, &mut scratch, &mut children)
            {
                let copies = children.iter().map(|(p, s)| (*p, s.clone_box())).collect();
                stats.add(&self.read_split(second, axis, &scope, copies));
            }
            queue.extend(children.drain(..));
        }
        stats
    }

    /// The cheapest edit path from `src` to `dst`, found once.
    fn path(&self, src: &[Sym], dst: &[Sym]) -> PathResult {
        let key = (src.to_vec(), dst.to_vec());
        let mut cache = self
            .splits
            .paths
            .0
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        cache
            .entry(key)
            .or_insert_with(|| {
                let matches = |x: Sym, y: Sym| {
                    x.second != y.second
                        && if x.second {
                            self.matches.of(y.node, x.node).is_some()
                        } else {
                            self.matches.of(x.node, y.node).is_some()
                        }
                };
                edit_path(src, dst, matches).map(Arc::new)
            })
            .clone()
    }

    /// One co-derivation step of two matched split nodes (thesis §5.4.4):
    /// both designs step their gene; if both split along the same axis,
    /// the merged split's parts are queued (paired with their matches'
    /// parts) and `true` is returned; otherwise nothing is queued and the
    /// caller blends as for any shape.
    pub(super) fn split_step(
        &self,
        w: f32,
        (pa, pb): (u32, u32),
        (sa, sb): (&dyn super::design::StateObj, &dyn super::design::StateObj),
        queue: &mut VecDeque<Work>,
        terminals: &mut [Instances; 2],
    ) -> bool {
        let (da, db) = (self.design(false), self.design(true));
        let is_split = |d: &super::Design, pos: u32| {
            d.graph()
                .node(d.chromosome().gene(d.graph(), pos).node())
                .split
        };
        let (Some(axis_a), Some(axis_b)) = (is_split(da, pa), is_split(db, pb)) else {
            return false;
        };
        if axis_a != axis_b {
            return false;
        }
        let (mut ca, mut cb) = (Vec::new(), Vec::new());
        let split_a = da
            .stepper()
            .step(da.chromosome(), pa, sa, &mut terminals[0], &mut ca);
        let split_b = db
            .stepper()
            .step(db.chromosome(), pb, sb, &mut terminals[1], &mut cb);
        let (Some((axis, scope_a)), Some((_, scope_b))) = (split_a, split_b) else {
            // A split node that did not split this time: its children are
            // whatever it scheduled; blend them as any shape's.
            terminals[0].0.clear();
            terminals[1].0.clear();
            return false;
        };
        let made = [
            self.read_split(false, axis, &scope_a, ca),
            self.read_split(true, axis, &scope_b, cb),
        ];
        if w <= 0.0 || w >= 1.0 {
            self.queue_made(&made, w >= 1.0, queue);
            return true;
        }
        let src: Vec<Sym> = made[0].parts.iter().map(|p| p.sym).collect();
        let dst: Vec<Sym> = made[1].parts.iter().map(|p| p.sym).collect();
        let string: Vec<Sym> = match self.path(&src, &dst) {
            Ok(path) => path.at(w).to_vec(),
            // No path within the search's budget: switch halfway.
            Err(_) => {
                if w < 0.5 {
                    src
                } else {
                    dst
                }
            }
        };
        let scope = super::blend::blend_scopes(&scope_a, &scope_b, w, self.settings.pivot);
        self.lay_out(&string, w, axis, &scope, &made, queue);
        true
    }

    /// Queues one design's own split, part for part, each part paired
    /// with its match's part in the other design where there is one.
    fn queue_made(&self, made: &[Made; 2], second: bool, queue: &mut VecDeque<Work>) {
        let own = &made[usize::from(second)];
        let mut seen: HashMap<Sym, usize> = HashMap::new();
        let design = self.design(second);
        for (pos, state) in &own.children {
            let node = design.chromosome().gene(design.graph(), *pos).node();
            let sym = Sym { second, node };
            let q = seen.entry(sym).or_insert(0);
            queue.push_back(self.part_work(sym, *q, state.scope(), made));
            *q += 1;
        }
    }

    /// The work deriving the `q`-th part of symbol `sym` with `scope`:
    /// paired with the `q`-th part (or the last) of a matching symbol of
    /// the other design, if it has one, else derived alone.
    fn part_work(&self, sym: Sym, q: usize, scope: Scope, made: &[Made; 2]) -> Work {
        let own = self
            .nth(
                &made[usize::from(sym.second)].children,
                sym.second,
                q,
                &|n| n == sym.node,
            )
            .expect("a symbol of a string is a part of its design's split");
        let matches_other = |n: NodeId| {
            if sym.second {
                self.matches.of(n, sym.node).is_some()
            } else {
                self.matches.of(sym.node, n).is_some()
            }
        };
        let other = self.nth(
            &made[usize::from(!sym.second)].children,
            !sym.second,
            q,
            &matches_other,
        );
        match other {
            Some((pos, state)) => {
                let design = self.design(!sym.second);
                let node = design.chromosome().gene(design.graph(), *pos).node();
                let (a, b) = if sym.second {
                    ((*pos, state, node), (own.0, &own.1, sym.node))
                } else {
                    ((own.0, &own.1, sym.node), (*pos, state, node))
                };
                Work::Pair {
                    a: a.0,
                    b: b.0,
                    sa: a.1.with_scope(scope),
                    sb: b.1.with_scope(scope),
                    m: self.matches.of(a.2, b.2).expect("paired parts match"),
                }
            }
            None => Single::whole(sym.second, own.0, &own.1, scope, sym.node),
        }
    }

    /// The `q`-th (or the last) of the children in `list` whose node
    /// satisfies `pred`.
    fn nth<'a>(
        &self,
        list: &'a [(u32, DynState)],
        second: bool,
        q: usize,
        pred: &dyn Fn(NodeId) -> bool,
    ) -> Option<&'a (u32, DynState)> {
        let design = self.design(second);
        let found: Vec<&(u32, DynState)> = list
            .iter()
            .filter(|(p, _)| pred(design.chromosome().gene(design.graph(), *p).node()))
            .collect();
        found.get(q.min(found.len().saturating_sub(1))).copied()
    }

    /// Whether symbol `x` stands where `y` stood: the same, or a match.
    fn corresponds(&self, x: Sym, y: Sym) -> bool {
        x == y
            || (x.second != y.second
                && if x.second {
                    self.matches.of(y.node, x.node).is_some()
                } else {
                    self.matches.of(x.node, y.node).is_some()
                })
    }

    /// The length of symbol `s` on average where its design splits (this
    /// split first), or of its match in the other design if `s` has none.
    fn average_length(s: Sym, stats: &Stats<'_>) -> Option<f32> {
        let side = usize::from(s.second);
        [&stats.local[side], &stats.global[side]]
            .iter()
            .find_map(|t| t.lengths.get(&s).and_then(|m| m.get()))
    }

    /// The length of a symbol matching `s` in the other design.
    fn partner_length(&self, s: Sym, made: &[Made; 2], stats: &Stats<'_>) -> Option<f32> {
        let other = usize::from(!s.second);
        made[other]
            .parts
            .iter()
            .map(|p| p.sym)
            .chain(stats.global[other].lengths.keys().copied())
            .find(|&o| self.corresponds(o, s))
            .and_then(|o| Self::average_length(o, stats))
    }

    /// The lengths of `string`'s parts and the gaps around them (before
    /// fitting): where the string stands part for part where a design's
    /// split does (the same symbols or their matches), that split's own
    /// lengths and gaps, blended with the other's where both do; else the
    /// averages of the designs' splits (thesis §5.4.4).
    fn lengths_and_gaps(&self, string: &[Sym], w: f32, made: &[Made; 2]) -> Layout {
        let stats = Stats {
            local: [SplitStats::of(&made[0]), SplitStats::of(&made[1])],
            global: self.split_stats(),
        };
        let aligned = |side: usize| {
            let parts = &made[side].parts;
            parts.len() == string.len()
                && parts
                    .iter()
                    .zip(string)
                    .all(|(p, &s)| self.corresponds(s, p.sym))
        };
        let lerp = |a: f32, b: f32| a + (b - a) * w;
        let own = |side: usize| -> (Vec<f32>, Vec<f32>) {
            (
                made[side].parts.iter().map(|p| p.length).collect(),
                made[side].gaps.clone(),
            )
        };
        match (aligned(0), aligned(1)) {
            (true, true) => {
                let ((la, ga), (lb, gb)) = (own(0), own(1));
                Layout {
                    lengths: la.iter().zip(&lb).map(|(&a, &b)| lerp(a, b)).collect(),
                    gaps: ga.iter().zip(&gb).map(|(&a, &b)| lerp(a, b)).collect(),
                    fills: Some(usize::from(w >= 0.5)),
                }
            }
            (true, false) | (false, true) => {
                let side = usize::from(aligned(1));
                let (lengths, gaps) = own(side);
                let lengths = lengths
                    .iter()
                    .zip(string)
                    .map(|(&l, &s)| {
                        // The other design's length for this symbol: its
                        // own if it is the other's, else its match's.
                        let other = if usize::from(s.second) == side {
                            self.partner_length(s, made, &stats)
                        } else {
                            Self::average_length(s, &stats)
                        };
                        let p = other.unwrap_or(l);
                        if side == 0 { lerp(l, p) } else { lerp(p, l) }
                    })
                    .collect();
                Layout {
                    lengths,
                    gaps,
                    fills: Some(side),
                }
            }
            (false, false) => {
                let (lengths, gaps) = self.average_layout(string, w, made, &stats);
                Layout {
                    lengths,
                    gaps,
                    fills: None,
                }
            }
        }
    }

    /// Lengths from the designs' average part lengths (blended with their
    /// matches'), gaps from the average gaps between the same neighbours,
    /// else beside either neighbour, else anywhere.
    fn average_layout(
        &self,
        string: &[Sym],
        w: f32,
        made: &[Made; 2],
        stats: &Stats<'_>,
    ) -> (Vec<f32>, Vec<f32>) {
        let (local, global) = (&stats.local, stats.global);
        let tables = [&local[0], &local[1], &global[0], &global[1]];
        let lengths: Vec<f32> = string
            .iter()
            .map(|&s| {
                let own = Self::average_length(s, stats)
                    .or_else(|| tables.iter().find_map(|t| t.all_lengths.get()))
                    .unwrap_or(1.0);
                match self.partner_length(s, made, stats) {
                    Some(p) if s.second => p + (own - p) * w,
                    Some(p) => own + (p - own) * w,
                    None => own,
                }
            })
            .collect();
        let n = string.len();
        let gaps: Vec<f32> = (0..=n)
            .map(|i| {
                let l = i.checked_sub(1).map(|j| string[j]);
                let r = string.get(i).copied();
                tables
                    .iter()
                    .find_map(|t| t.gaps.get(&(l, r)).and_then(|m| m.get()))
                    .or_else(|| {
                        let beside: Vec<f32> = [l, r]
                            .into_iter()
                            .flatten()
                            .filter_map(|s| tables.iter().find_map(|t| t.beside.get(&s)?.get()))
                            .collect();
                        (!beside.is_empty())
                            .then(|| beside.iter().sum::<f32>() / beside.len() as f32)
                    })
                    .or_else(|| tables.iter().find_map(|t| t.all_gaps.get()))
                    .unwrap_or(0.0)
            })
            .collect();
        (lengths, gaps)
    }

    /// Lays `string` out along `axis` of `scope` and queues its parts and
    /// the spacers between them.
    fn lay_out(
        &self,
        string: &[Sym],
        w: f32,
        axis: Axis,
        scope: &Scope,
        made: &[Made; 2],
        queue: &mut VecDeque<Work>,
    ) {
        let Layout {
            lengths,
            gaps,
            fills,
        } = self.lengths_and_gaps(string, w, made);
        let n = string.len();
        // Spacers stretch alike to fill; parts shrink alike if they overflow.
        let extent = scope.size[axis.index()].abs();
        let (sum_l, sum_g) = (lengths.iter().sum::<f32>(), gaps.iter().sum::<f32>());
        let (scale_l, scale_g) = if sum_g > 0.0 && sum_l < extent {
            (1.0, (extent - sum_l) / sum_g)
        } else if sum_l > 0.0 {
            (extent / sum_l, 0.0)
        } else {
            (0.0, if sum_g > 0.0 { extent / sum_g } else { 0.0 })
        };
        let mut sizes = Vec::with_capacity(2 * n + 1);
        for i in 0..=n {
            sizes.push(SplitSize::Absolute(gaps[i] * scale_g));
            if i < n {
                sizes.push(SplitSize::Absolute(lengths[i] * scale_l));
            }
        }
        let mut occurrences: HashMap<Sym, usize> = HashMap::new();
        for (entry, part) in scope.split(axis, &sizes) {
            if entry % 2 == 1 {
                let sym = string[entry / 2];
                let q = occurrences.entry(sym).or_insert(0);
                queue.push_back(self.part_work(sym, *q, part, made));
                *q += 1;
            } else {
                self.fill_gap(made, fills.map(|side| (side, entry / 2)), part, axis, queue);
            }
        }
    }

    /// Fills a gap: as the design's own gap `gap` of side `side` was filled
    /// (its spacers and empty stretches, stretched alike), or else with
    /// one spacer.
    fn fill_gap(
        &self,
        made: &[Made; 2],
        own: Option<(usize, usize)>,
        scope: Scope,
        axis: Axis,
        queue: &mut VecDeque<Work>,
    ) {
        let Some((side, gap)) = own else {
            if let Some(work) = self.spacer_work(made, None, scope) {
                queue.push_back(work);
            }
            return;
        };
        let fill = &made[side].fills[gap];
        if fill.is_empty() {
            // The design left no gap here, the blend does: one spacer.
            if let Some(work) = self.spacer_work(made, None, scope) {
                queue.push_back(work);
            }
            return;
        }
        let sizes: Vec<SplitSize> = fill.iter().map(|&(_, l)| SplitSize::Relative(l)).collect();
        for (entry, part) in scope.split(axis, &sizes) {
            if let Some(k) = fill[entry].0 {
                let spacer = (side == 1, &made[side].spacers[k]);
                if let Some(work) = self.spacer_work(made, Some(spacer), part) {
                    queue.push_back(work);
                }
            }
        }
    }

    /// A spacer filling `scope`: `own` (of the second design if its flag
    /// is set) or the first design's first spacer, paired with the other
    /// design's first if they match, else whichever design has one.
    fn spacer_work(
        &self,
        made: &[Made; 2],
        own: Option<(bool, &(u32, DynState))>,
        scope: Scope,
    ) -> Option<Work> {
        let node = |second: bool, pos: u32| {
            let d = self.design(second);
            d.chromosome().gene(d.graph(), pos).node()
        };
        let (mut a, mut b) = (made[0].spacers.first(), made[1].spacers.first());
        match own {
            Some((true, s)) => b = Some(s),
            Some((false, s)) => a = Some(s),
            None => {}
        }
        if own.is_some_and(|(second, _)| second) && a.is_some() {
            // Paired below only if they match; else the second's own.
            let (pa, pb) = (a.expect("checked").0, b.expect("own").0);
            if self.matches.of(node(false, pa), node(true, pb)).is_none() {
                a = None;
            }
        }
        match (a, b) {
            (Some((pa, sa)), Some((pb, sb))) => {
                let (na, nb) = (node(false, *pa), node(true, *pb));
                match self.matches.of(na, nb) {
                    Some(m) => Some(Work::Pair {
                        a: *pa,
                        b: *pb,
                        sa: sa.with_scope(scope),
                        sb: sb.with_scope(scope),
                        m,
                    }),
                    None => Some(Single::whole(false, *pa, sa, scope, na)),
                }
            }
            (Some((p, s)), None) => Some(Single::whole(false, *p, s, scope, node(false, *p))),
            (None, Some((p, s))) => Some(Single::whole(true, *p, s, scope, node(true, *p))),
            (None, None) => None,
        }
    }
}
