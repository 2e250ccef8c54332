use super::*;
use proptest::prelude::*;

/// Labels of two designs: a letter and a side, written `Yt1` and `Wt2`
/// in the thesis; labels match by their letters.
type L = (&'static str, u8);

fn matches(a: L, b: L) -> bool {
    a.0 == b.0 && a.1 != b.1
}

/// Semantic matches named by pairs of labels (the thesis's A.1 lists them).
fn matched(pairs: &'static [(&'static str, &'static str)]) -> impl Fn(&str, &str) -> bool {
    move |a, b| {
        pairs
            .iter()
            .any(|&(x, y)| (x, y) == (a, b) || (y, x) == (a, b))
    }
}

fn strings<'a>(p: &EditPath<&'a str>) -> Vec<Vec<&'a str>> {
    p.strings.clone()
}

#[test]
fn appendix_a1_facade() {
    // ⟨YellowFacade, Facade⟩: {Floor1, Ledge} → {Floor2, Floor2}.
    let m = matched(&[("Floor1", "Floor2")]);
    let p = edit_path(&["Floor1", "Ledge"], &["Floor2", "Floor2"], &m).unwrap();
    assert_eq!(
        strings(&p),
        [
            vec!["Floor1", "Ledge"],
            vec!["Floor1"],
            vec!["Floor2"],
            vec!["Floor2", "Floor2"],
        ]
    );
    assert_eq!(p.edits[0], Edit::DeleteAll("Ledge"));
    assert_eq!(p.edits[1], Edit::SemanticSwitch("Floor1", "Floor2"));
    assert!(matches!(p.edits[2], Edit::Insert(_, "Floor2")));
    assert_eq!(p.cost, 3.0);
}

#[test]
fn appendix_a1_floor() {
    // ⟨Floor, Floor⟩: pillars and yellow window tiles → seven window tiles.
    // The thesis prints the source with four Yt but deletes its pillars to
    // five Yt (then two inserts reach seven): five it is.
    let m = matched(&[("Yt", "Wt")]);
    let src = [
        "P", "P", "Yt", "P", "Yt", "P", "Yt", "P", "Yt", "P", "Yt", "P", "P",
    ];
    let dst = ["Wt"; 7];
    let p = edit_path(&src, &dst, &m).unwrap();
    assert_eq!(
        strings(&p),
        [
            src.to_vec(),
            vec!["Yt"; 5],
            vec!["Wt"; 5],
            vec!["Wt"; 6],
            vec!["Wt"; 7],
        ]
    );
    assert_eq!(p.edits[0], Edit::DeleteAll("P"));
    assert_eq!(p.edits[1], Edit::SemanticSwitch("Yt", "Wt"));
    assert!(
        p.edits[2..]
            .iter()
            .all(|e| matches!(e, Edit::Insert(_, "Wt")))
    );
    assert_eq!(p.cost, 4.0);
}

#[test]
fn appendix_a1_window_tile() {
    // A window tile's string is one window: a single semantic switch.
    let m = matched(&[("Window1", "Window2")]);
    let p = edit_path(&["Window1"], &["Window2"], &m).unwrap();
    assert_eq!(p.edits, [Edit::SemanticSwitch("Window1", "Window2")]);
}

#[test]
fn figure_5_7_pillars_then_windows() {
    // All pillars go first, then windows one by one down to three.
    let p = edit_path(
        &["W", "P", "W", "P", "W", "P", "W", "P", "W"],
        &["W", "W", "W"],
        |_, _| false,
    )
    .unwrap();
    assert_eq!(strings(&p)[1..], [vec!["W"; 5], vec!["W"; 4], vec!["W"; 3]]);
    assert_eq!(p.edits[0], Edit::DeleteAll("P"));
}

#[test]
fn figure_5_7_a_door_moves_then_changes_style() {
    let m = matched(&[("D1", "D2")]);
    let p = edit_path(&["D1", "W", "W", "W"], &["W", "W", "W", "D2"], |a, b| {
        m(a, b)
    })
    .unwrap();
    assert_eq!(
        strings(&p),
        [
            vec!["D1", "W", "W", "W"],
            vec!["W", "D1", "W", "W"],
            vec!["W", "W", "D1", "W"],
            vec!["W", "W", "W", "D1"],
            vec!["W", "W", "W", "D2"],
        ]
    );
}

#[test]
fn a_symmetric_string_changes_symmetrically() {
    // A window in the middle of pillars becomes three: a mirrored insert
    // (2.5) rather than two inserts, the first of which breaks the symmetry.
    let p = edit_path(&["P", "W", "P"], &["P", "W", "W", "W", "P"], |_, _| false).unwrap();
    assert!(p.strings.iter().all(|s| is_palindrome(s)), "{p:?}");
    // And a pillar pair around a window moves outward symmetrically.
    let p = edit_path(
        &["W", "P", "D", "P", "W"],
        &["P", "W", "D", "W", "P"],
        |_, _| false,
    )
    .unwrap();
    assert_eq!(p.edits, [Edit::SwapMirrored(0)]);
    assert_eq!(p.cost, 2.5);
}

#[test]
fn the_weight_picks_a_string_along_the_path() {
    let p = edit_path(&["a"; 1], &["a"; 5], |_, _| false).unwrap();
    assert_eq!(p.edits.len(), 4);
    assert_eq!(p.at(0.0).len(), 1);
    assert_eq!(p.at(0.5).len(), 3);
    assert_eq!(p.at(1.0).len(), 5);
    assert_eq!(p.at(f32::NAN).len(), 1);
    // Identical strings: an empty path.
    let p = edit_path(&["a", "b"], &["a", "b"], |_, _| false).unwrap();
    assert!(p.edits.is_empty());
    assert_eq!(p.at(0.7), ["a", "b"]);
}

/// Applies `e` to `s` as the thesis defines it (the reference the search's
/// own edits are checked against).
fn apply(e: &Edit<L>, s: &[L], dst: &[L]) -> Vec<L> {
    let mut t = s.to_vec();
    let n = s.len();
    match *e {
        Edit::DeleteAll(x) => t.retain(|&y| y != x),
        Edit::Delete(i) => {
            t.remove(i);
        }
        Edit::SemanticSwitch(x, y) => t.iter_mut().filter(|z| **z == x).for_each(|z| *z = y),
        Edit::Swap(i) => t.swap(i, i + 1),
        Edit::Insert(i, x) => t.insert(i, x),
        Edit::InsertAll(x) => {
            for (j, &z) in dst.iter().enumerate() {
                if z == x {
                    t.insert(j.min(t.len()), x);
                }
            }
        }
        Edit::DeleteMirrored(i) => {
            t.remove(n - 1 - i);
            t.remove(i);
        }
        Edit::InsertMirrored(i, x) => {
            t.insert(n - i, x);
            t.insert(i, x);
        }
        Edit::SwapMirrored(i) => {
            t.swap(i, i + 1);
            t.swap(n - 2 - i, n - 1 - i);
        }
    }
    t
}

fn cost(e: &Edit<L>, s: &[L], t: &[L]) -> f32 {
    let base = match e {
        Edit::DeleteMirrored(_) | Edit::InsertMirrored(..) | Edit::SwapMirrored(_) => 2.5,
        _ => 1.0,
    };
    let breaks = is_palindrome(s) && !is_palindrome(t);
    base + if breaks { 100.0 } else { 0.0 }
}

fn string(side: u8, max: usize) -> impl Strategy<Value = Vec<L>> {
    prop::collection::vec(prop::sample::select(vec!["a", "b", "c"]), 0..=max)
        .prop_map(move |v| v.into_iter().map(|x| (x, side)).collect())
}

/// A palindrome over `a`, `b`, `c` of the given side.
fn palindrome(side: u8) -> impl Strategy<Value = Vec<L>> {
    (
        string(side, 4),
        prop::option::of(prop::sample::select(vec!["a", "b", "c"])),
    )
        .prop_map(move |(half, mid)| {
            let mut s = half.clone();
            s.extend(mid.map(|m| (m, side)));
            s.extend(half.iter().rev());
            s
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Every path starts at the source, ends at the target, each edit is
    /// the thesis's edit applied to the string before, and the cost adds up.
    #[test]
    fn paths_are_made_of_edits(src in string(1, 7), dst in string(2, 7), same in any::<bool>()) {
        // Half the cases share labels (one design), half match across designs.
        let dst: Vec<L> = if same { dst.iter().map(|&(x, _)| (x, 1)).collect() } else { dst };
        let p = edit_path(&src, &dst, matches).unwrap();
        prop_assert_eq!(&p.strings[0], &src);
        prop_assert_eq!(p.strings.last().unwrap(), &dst);
        prop_assert_eq!(p.edits.len() + 1, p.strings.len());
        let mut total = 0.0;
        for (k, e) in p.edits.iter().enumerate() {
            let next = apply(e, &p.strings[k], &dst);
            prop_assert_eq!(&next, &p.strings[k + 1], "edit {:?}", e);
            total += cost(e, &p.strings[k], &next);
        }
        prop_assert!((total - p.cost).abs() < 1e-4, "{} vs {}", total, p.cost);
    }

    /// The bound only speeds the search up: A* finds paths as cheap as
    /// Dijkstra's algorithm without it.
    #[test]
    fn the_bound_keeps_paths_cheapest(src in string(1, 7), dst in string(2, 7), same in any::<bool>()) {
        let dst: Vec<L> = if same { dst.iter().map(|&(x, _)| (x, 1)).collect() } else { dst };
        let fast = edit_path(&src, &dst, matches).unwrap();
        let reference = path_between(&src, &dst, matches, false).unwrap();
        prop_assert!((fast.cost - reference.cost).abs() < 1e-4, "{} vs {}", fast.cost, reference.cost);
    }

    /// Between palindromes that mirrored edits connect, the path keeps
    /// every string a palindrome.
    #[test]
    fn symmetric_strings_stay_symmetric(dst in palindrome(2), ops in prop::collection::vec((0..3u8, 0..5usize), 0..3)) {
        // The source: the target's labels switched to the first design's,
        // then mirrored inserts and deletes (each undone by its mirror).
        let mut src: Vec<L> = dst.iter().map(|&(x, _)| (x, 1)).collect();
        for (op, i) in ops {
            let n = src.len();
            match op {
                0 if n > 0 => {
                    let i = i % (n / 2 + 1);
                    let x = src[i.min(n - 1)];
                    src.insert(n - i, x);
                    src.insert(i, x);
                }
                1 if n >= 2 => {
                    let i = i % (n / 2);
                    let x = src[i];
                    // Keep every label: delete only a label with more copies.
                    if src.iter().filter(|&&y| y == x).count() > 2 {
                        src.remove(n - 1 - i);
                        src.remove(i);
                    }
                }
                _ => {}
            }
        }
        prop_assert!(is_palindrome(&src));
        let p = edit_path(&src, &dst, matches).unwrap();
        prop_assert!(p.cost < 100.0, "{:?}", p);
        for s in &p.strings {
            prop_assert!(is_palindrome(s), "{:?}", p);
        }
    }
}
