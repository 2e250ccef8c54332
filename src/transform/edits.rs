//! The edit path between two split strings (thesis §5.4.4): the cheapest
//! sequence of edits that turns one string of parts into the other, each
//! edit a gradual change, found by Dijkstra's algorithm over strings
//! expanded as they are reached.
//!
//! The edits and their costs are the thesis's: *delete* or *insert* one
//! symbol (only of a label both strings hold, toward the other's count),
//! *swap* two different neighbours, *delete all* of a label the target
//! lacks (with no match in it), *insert all* of a label the source lacks,
//! and a *semantic switch* of every symbol of a label to a matching label:
//! 1 each. On a symmetric string (a palindrome) the mirrored delete,
//! insert and swap change both halves at once for 2.5, and an edit that
//! makes a symmetric string asymmetric costs 100 more, so a path that keeps
//! the symmetry wins wherever one exists.
//!
//! Where the thesis leaves a choice open, this module chooses:
//! - **ties**: among paths of equal cost the one whose edits come first
//!   in the order delete all, delete, swap, semantic switch, insert,
//!   insert all (then the mirrored ones) wins, edit by edit: removals come
//!   first (intermediate strings stay short) and symbols move before they
//!   change. This reproduces the edit sequences of the thesis's Appendix
//!   A.1 and Fig. 5.7.
//! - **length**: strings longer than the longer input by more than two
//!   symbols are not expanded (the thesis penalizes such strings "to
//!   prevent the search from exploding"; no cheapest path needs them:
//!   deletions can always come before insertions at the same cost).
//! - **insert all** puts the label's symbols where the target has them.
//! - **budget**: a search that expands more than [`MAX_EXPANDED`] strings
//!   gives up ([`EditError`]); a transformation then switches from one
//!   string to the other at once.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};
use std::hash::Hash;

/// Most strings a search expands before it gives up.
pub const MAX_EXPANDED: usize = 100_000;

/// Costs in half units: 1 is 2, 2.5 is 5, 100 is 200.
const UNIT: u32 = 2;
const MIRRORED: u32 = 5;
const BREAKS_SYMMETRY: u32 = 200;
/// How much longer than the longer input a string may grow.
const SLACK: usize = 2;

/// One edit of a split string.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Edit<S> {
    /// Removes every symbol of the label (which the target lacks).
    DeleteAll(S),
    /// Removes the symbol at this position.
    Delete(usize),
    /// Replaces every symbol of the first label by the second (a semantic match).
    SemanticSwitch(S, S),
    /// Swaps the symbols at this position and the next.
    Swap(usize),
    /// Inserts the label before this position.
    Insert(usize, S),
    /// Inserts every symbol of the label (which the source lacks) where the target has them.
    InsertAll(S),
    /// The mirrored delete: the symbols at this position and its mirror.
    DeleteMirrored(usize),
    /// The mirrored insert: the label before this position and at its mirror.
    InsertMirrored(usize, S),
    /// The mirrored swap: at this position and at its mirror.
    SwapMirrored(usize),
}

impl<S> Edit<S> {
    /// The same edit with its labels mapped by `f`.
    fn map<T>(&self, f: impl Fn(S) -> T) -> Edit<T>
    where
        S: Copy,
    {
        match *self {
            Self::DeleteAll(x) => Edit::DeleteAll(f(x)),
            Self::Delete(i) => Edit::Delete(i),
            Self::SemanticSwitch(x, y) => Edit::SemanticSwitch(f(x), f(y)),
            Self::Swap(i) => Edit::Swap(i),
            Self::Insert(i, x) => Edit::Insert(i, f(x)),
            Self::InsertAll(x) => Edit::InsertAll(f(x)),
            Self::DeleteMirrored(i) => Edit::DeleteMirrored(i),
            Self::InsertMirrored(i, x) => Edit::InsertMirrored(i, f(x)),
            Self::SwapMirrored(i) => Edit::SwapMirrored(i),
        }
    }

    /// Where the edit comes in the order ties are broken by.
    fn rank(&self) -> u8 {
        match self {
            Self::DeleteAll(_) => 0,
            Self::Delete(_) => 1,
            Self::Swap(_) => 2,
            Self::SemanticSwitch(..) => 3,
            Self::Insert(..) => 4,
            Self::InsertAll(_) => 5,
            Self::DeleteMirrored(_) => 6,
            Self::SwapMirrored(_) => 7,
            Self::InsertMirrored(..) => 8,
        }
    }
}

impl<S: std::fmt::Display> std::fmt::Display for Edit<S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::DeleteAll(s) => write!(f, "delete all {s}"),
            Self::Delete(i) => write!(f, "delete at {i}"),
            Self::SemanticSwitch(a, b) => write!(f, "semantic switch {a} -> {b}"),
            Self::Swap(i) => write!(f, "swap {i} and {}", i + 1),
            Self::Insert(i, s) => write!(f, "insert {s} at {i}"),
            Self::InsertAll(s) => write!(f, "insert all {s}"),
            Self::DeleteMirrored(i) => write!(f, "delete mirrored at {i}"),
            Self::InsertMirrored(i, s) => write!(f, "insert mirrored {s} at {i}"),
            Self::SwapMirrored(i) => write!(f, "swap mirrored {i} and {}", i + 1),
        }
    }
}

/// The search gave up.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("no edit path found within {expanded} strings (split strings too long or too different)")]
pub struct EditError {
    /// Strings expanded.
    pub expanded: usize,
}

/// The cheapest edit path: the strings from the source to the target and
/// the edit between each and the next.
#[derive(Clone, Debug, PartialEq)]
pub struct EditPath<S> {
    /// `strings[0]` is the source, the last the target.
    pub strings: Vec<Vec<S>>,
    /// `edits[i]` turns `strings[i]` into `strings[i + 1]`.
    pub edits: Vec<Edit<S>>,
    /// The total cost (in the thesis's units).
    pub cost: f32,
}

impl<S> EditPath<S> {
    /// The string at blend weight `w ∈ [0, 1]`: string `round(w · edits)`
    /// of the path (the source below 1 / (2 · edits), the target above 1 − that).
    #[must_use]
    pub fn at(&self, w: f32) -> &[S] {
        let k = self.strings.len() - 1;
        let w = if w.is_nan() { 0.0 } else { w.clamp(0.0, 1.0) };
        let i = ((w * k as f32).round() as usize).min(k);
        &self.strings[i]
    }
}

fn is_palindrome<S: PartialEq>(s: &[S]) -> bool {
    let n = s.len();
    (0..n / 2).all(|i| s[i] == s[n - 1 - i])
}

/// A label, interned: the search runs on small numbers.
type L = u8;
/// Maps and sets of strings: hashed fast, the same way every run.
type Map<K, V> = HashMap<K, V, foldhash::fast::FixedState>;
type Set<K> = std::collections::HashSet<K, foldhash::fast::FixedState>;

/// Counts of each label.
fn counts(s: &[L]) -> [u16; 256] {
    let mut c = [0u16; 256];
    for &x in s {
        c[x as usize] += 1;
    }
    c
}

/// Adjacent swaps that turn `s` into `d`, which hold the same labels as
/// often: the inversions of the permutation that takes each symbol to the
/// same occurrence of its label in `d`.
fn inversions(s: &[L], d: &[L]) -> usize {
    let mut seen = [0u16; 256];
    let target: Vec<usize> = s
        .iter()
        .map(|&x| {
            let k = seen[x as usize];
            seen[x as usize] += 1;
            d.iter()
                .enumerate()
                .filter(|&(_, &y)| y == x)
                .nth(usize::from(k))
                .map_or(0, |(j, _)| j)
        })
        .collect();
    let mut count = 0;
    for i in 0..target.len() {
        for j in i + 1..target.len() {
            count += usize::from(target[i] > target[j]);
        }
    }
    count
}

/// The labels of `s` in order of first appearance.
fn labels(s: &[L]) -> Vec<L> {
    let mut seen = [false; 256];
    s.iter()
        .copied()
        .filter(|&x| !std::mem::replace(&mut seen[x as usize], true))
        .collect()
}

/// What a search needs to know about the target.
struct Target<'a> {
    dst: &'a [L],
    counts: [u16; 256],
    labels: Vec<L>,
    /// `matches[x * alphabet + y]`: label `x` matches `y`.
    matches: Vec<bool>,
    alphabet: usize,
    max_len: usize,
    /// Whether the search is A* (else Dijkstra's: the tests' reference).
    bounded: bool,
}

impl Target<'_> {
    fn count(&self, x: L) -> usize {
        usize::from(self.counts[x as usize])
    }

    fn matches(&self, x: L, y: L) -> bool {
        self.matches[x as usize * self.alphabet + y as usize]
    }

    /// Every string one edit from `s`, with the edit and its cost (half
    /// units), in the order ties are broken.
    fn neighbours(&self, s: &[L], out: &mut Vec<(Vec<L>, Edit<L>, u32)>) {
        out.clear();
        let n = s.len();
        let here = counts(s);
        let count = |x: L| usize::from(here[x as usize]);
        let symmetric = is_palindrome(s);
        let push = |t: Vec<L>, e: Edit<L>, cost: u32, out: &mut Vec<_>| {
            if t.len() > self.max_len {
                return;
            }
            let penalty = if symmetric && !is_palindrome(&t) {
                BREAKS_SYMMETRY
            } else {
                0
            };
            out.push((t, e, cost + penalty));
        };
        let own = labels(s);
        // Delete all: a label the target lacks, with no match in it.
        for &x in &own {
            if self.count(x) == 0 && !self.labels.iter().any(|&y| self.matches(x, y)) {
                let t: Vec<L> = s.iter().copied().filter(|&y| y != x).collect();
                push(t, Edit::DeleteAll(x), UNIT, out);
            }
        }
        // Delete one (of a label the target has fewer of).
        let mut seen: Set<Vec<L>> = Set::default();
        for i in 0..n {
            let x = s[i];
            if self.count(x) > 0 && count(x) > self.count(x) {
                let mut t = s.to_vec();
                t.remove(i);
                if seen.insert(t.clone()) {
                    push(t, Edit::Delete(i), UNIT, out);
                }
            }
        }
        // Swap two different neighbours.
        for i in 0..n.saturating_sub(1) {
            if s[i] != s[i + 1] {
                let mut t = s.to_vec();
                t.swap(i, i + 1);
                push(t, Edit::Swap(i), UNIT, out);
            }
        }
        // Semantic switch: a label the target lacks to a matching one it has.
        for &x in &own {
            if self.count(x) > 0 {
                continue;
            }
            for &y in &self.labels {
                if y != x && self.matches(x, y) {
                    let t = s.iter().map(|&z| if z == x { y } else { z }).collect();
                    push(t, Edit::SemanticSwitch(x, y), UNIT, out);
                }
            }
        }
        // Insert one (of a label both have, the target more often).
        seen.clear();
        for &x in &own {
            if self.count(x) > count(x) {
                for i in 0..=n {
                    let mut t = s.to_vec();
                    t.insert(i, x);
                    if seen.insert(t.clone()) {
                        push(t, Edit::Insert(i, x), UNIT, out);
                    }
                }
            }
        }
        // Insert all: a label the source lacks and no semantic switch can bring.
        for &y in &self.labels {
            let switchable = own
                .iter()
                .any(|&x| self.count(x) == 0 && self.matches(x, y));
            if count(y) == 0 && !switchable {
                push(self.insert_all(s, y), Edit::InsertAll(y), UNIT, out);
            }
        }
        if !symmetric {
            return;
        }
        // The mirrored edits keep a palindrome one.
        for i in 0..n / 2 {
            let x = s[i];
            if self.count(x) > 0 && count(x) >= self.count(x) + 2 {
                let mut t = s.to_vec();
                t.remove(n - 1 - i);
                t.remove(i);
                push(t, Edit::DeleteMirrored(i), MIRRORED, out);
            }
        }
        for &x in &own {
            if self.count(x) >= count(x) + 2 {
                for i in 0..=n / 2 {
                    let mut t = s.to_vec();
                    t.insert(n - i, x);
                    t.insert(i, x);
                    push(t, Edit::InsertMirrored(i, x), MIRRORED, out);
                }
            }
        }
        for i in 0..n / 2 {
            if i + 1 < n - 2 - i && s[i] != s[i + 1] {
                let mut t = s.to_vec();
                t.swap(i, i + 1);
                t.swap(n - 2 - i, n - 1 - i);
                push(t, Edit::SwapMirrored(i), MIRRORED, out);
            }
        }
    }

    /// A lower bound on the cost left (half units), never falling by more
    /// than an edit costs (so the search is A*, and a string's first
    /// expansion is along a cheapest path to it):
    /// - a label only one side has needs an edit (delete all, insert all or
    ///   a semantic switch, which settles one label of each side);
    /// - a target label needs one insert per copy that neither the string
    ///   nor every label that could switch into it holds;
    /// - a label both have, one delete per copy too many (nothing else
    ///   removes it);
    /// - a string with the target's labels, each as often, one swap per
    ///   inversion between it and the target (only swaps apply there).
    fn lower_bound(&self, s: &[L]) -> u32 {
        if !self.bounded {
            return 0;
        }
        let here = counts(s);
        let own = labels(s);
        let count = |x: L| usize::from(here[x as usize]);
        let extra = own.iter().filter(|&&x| self.count(x) == 0).count();
        let missing = self.labels.iter().filter(|&&y| count(y) == 0).count();
        let mut edits = extra.max(missing);
        for &y in &self.labels {
            let want = self.count(y);
            let have = count(y);
            let switchable: usize = own
                .iter()
                .filter(|&&x| self.count(x) == 0 && self.matches(x, y))
                .map(|&x| count(x))
                .sum();
            if have == 0 && switchable == 0 {
                continue; // insert all brings every copy
            }
            edits += want.saturating_sub(have + switchable) + have.saturating_sub(want);
        }
        if edits == 0 && s != self.dst {
            // The same labels, each as often: only swaps are left, and a
            // swap undoes one inversion (a mirrored one two, for 2.5).
            edits = inversions(s, self.dst).max(1);
        }
        UNIT * edits as u32
    }

    /// `s` with the symbols of `y` inserted where the target has them.
    fn insert_all(&self, s: &[L], y: L) -> Vec<L> {
        let mut t = s.to_vec();
        for (j, &z) in self.dst.iter().enumerate() {
            if z == y {
                t.insert(j.min(t.len()), y);
            }
        }
        t
    }
}

/// The cheapest edit path from `src` to `dst`, where `matches(a, b)` says
/// label `a` (of the source's labels) semantically matches `b` (of the
/// target's). See the module documentation for the edits and their costs.
///
/// # Errors
/// [`EditError`] when the search expands more than [`MAX_EXPANDED`] strings.
pub fn edit_path<S, M>(src: &[S], dst: &[S], matches: M) -> Result<EditPath<S>, EditError>
where
    S: Copy + Eq + Hash + Ord,
    M: Fn(S, S) -> bool,
{
    path_between(src, dst, matches, true)
}

/// [`edit_path`], by A* (`bounded`) or by Dijkstra's algorithm.
fn path_between<S, M>(
    src: &[S],
    dst: &[S],
    matches: M,
    bounded: bool,
) -> Result<EditPath<S>, EditError>
where
    S: Copy + Eq + Hash + Ord,
    M: Fn(S, S) -> bool,
{
    // Labels become small numbers, in their order: the search and its
    // tie-breaks see the same labels in the same order.
    let mut alphabet: Vec<S> = src.iter().chain(dst).copied().collect();
    alphabet.sort_unstable();
    alphabet.dedup();
    if alphabet.len() > 256 {
        return Err(EditError { expanded: 0 });
    }
    let id = |x: &S| alphabet.binary_search(x).expect("a label of the strings") as L;
    let (src_ids, dst_ids): (Vec<L>, Vec<L>) =
        (src.iter().map(id).collect(), dst.iter().map(id).collect());
    let n = alphabet.len();
    let mut table = vec![false; n * n];
    for (i, &x) in alphabet.iter().enumerate() {
        for (j, &y) in alphabet.iter().enumerate() {
            table[i * n + j] = matches(x, y);
        }
    }
    let path = search(&src_ids, &dst_ids, table, n, bounded)?;
    let label = |x: L| alphabet[x as usize];
    Ok(EditPath {
        strings: path
            .strings
            .iter()
            .map(|s| s.iter().map(|&x| label(x)).collect())
            .collect(),
        edits: path.edits.iter().map(|e| e.map(label)).collect(),
        cost: path.cost,
    })
}

/// [`edit_path`] on interned labels.
fn search(
    src: &[L],
    dst: &[L],
    matches: Vec<bool>,
    alphabet: usize,
    bounded: bool,
) -> Result<EditPath<L>, EditError> {
    let target = Target {
        dst,
        counts: counts(dst),
        labels: labels(dst),
        matches,
        alphabet,
        max_len: src.len().max(dst.len()) + SLACK,
        bounded,
    };
    // Strings by index; for each its best (cost, edit ranks), parent and edit.
    let mut strings: Vec<Vec<L>> = vec![src.to_vec()];
    let mut index: Map<Vec<L>, usize> = Map::default();
    index.insert(src.to_vec(), 0);
    let mut best: Vec<Key> = vec![(0, Vec::new())];
    let mut parent: Vec<Option<(usize, Edit<L>)>> = vec![None];
    let mut done: Vec<bool> = vec![false];
    let mut heap = BinaryHeap::from([Reverse((target.lower_bound(src), Vec::new(), 0usize))]);
    let mut expanded = 0usize;
    let mut next = Vec::new();
    while let Some(Reverse((_, ranks, i))) = heap.pop() {
        if done[i] || ranks != best[i].1 {
            continue;
        }
        let key = best[i].clone();
        done[i] = true;
        if strings[i] == dst {
            return Ok(unwind(i, &strings, &parent, key.0));
        }
        expanded += 1;
        if expanded > MAX_EXPANDED {
            return Err(EditError { expanded });
        }
        target.neighbours(&strings[i], &mut next);
        for (t, edit, cost) in next.drain(..) {
            let mut ranks = key.1.clone();
            ranks.push(edit.rank());
            let k: Key = (key.0 + cost, ranks);
            let j = match index.get(&t) {
                Some(&j) => {
                    if done[j] || k >= best[j] {
                        continue;
                    }
                    best[j] = k.clone();
                    parent[j] = Some((i, edit));
                    j
                }
                None => {
                    let j = strings.len();
                    index.insert(t.clone(), j);
                    strings.push(t);
                    best.push(k.clone());
                    parent.push(Some((i, edit)));
                    done.push(false);
                    j
                }
            };
            let bound = target.lower_bound(&strings[j]);
            heap.push(Reverse((k.0 + bound, k.1, j)));
        }
    }
    // Every label of the target can be reached (by insert all or a
    // semantic switch); only the length bound ends a search here.
    Err(EditError { expanded })
}

/// A path's cost (half units) and its edits' ranks: what orders paths.
type Key = (u32, Vec<u8>);

fn unwind<S: Copy>(
    mut i: usize,
    strings: &[Vec<S>],
    parent: &[Option<(usize, Edit<S>)>],
    cost: u32,
) -> EditPath<S> {
    let (mut path, mut edits) = (vec![strings[i].clone()], Vec::new());
    while let Some((p, e)) = &parent[i] {
        edits.push(e.clone());
        path.push(strings[*p].clone());
        i = *p;
    }
    path.reverse();
    edits.reverse();
    EditPath {
        strings: path,
        edits,
        cost: cost as f32 / UNIT as f32,
    }
}

#[cfg(test)]
mod tests;
