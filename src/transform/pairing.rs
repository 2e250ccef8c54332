//! Pairing two sets of shapes (thesis §5.4.3, Fig. 5.5): a distance between
//! boxes, then Munkres' assignment or mutual nearest neighbours.

use crate::glam::{Affine3A, Vec3};
use pathfinding::matrix::Matrix;

/// How the shapes of one co-derivation step are paired.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PairingMethod {
    /// The assignment of least total distance among the largest sets of
    /// compatible pairs (Munkres' algorithm): one-to-one, symmetric.
    #[default]
    Munkres,
    /// Pairs whose shapes are each other's nearest compatible shape; the
    /// others stay unpaired.
    MutualNearest,
}

/// The eight corners of a placed unit box.
#[must_use]
pub fn corners(t: &Affine3A) -> [Vec3; 8] {
    std::array::from_fn(|i| {
        let c = Vec3::new(
            if i & 1 == 0 { -0.5 } else { 0.5 },
            if i & 2 == 0 { -0.5 } else { 0.5 },
            if i & 4 == 0 { -0.5 } else { 0.5 },
        );
        t.transform_point3(c)
    })
}

/// The thesis's geometric distance: the sum of the distances of the eight
/// corresponding corners. Co-derivation measures it in the unit box of the
/// shape being derived, so that it depends neither on the model's units
/// nor on where that shape is blended to.
#[must_use]
pub fn distance(a: &[Vec3; 8], b: &[Vec3; 8]) -> f32 {
    a.iter().zip(b).map(|(p, q)| p.distance(*q)).sum()
}

/// Fixed-point scale of Munkres' integer weights.
const UNIT: f64 = 1e6;
/// The weight of an incompatible pair: more than any set of compatible pairs costs.
const FORBIDDEN: i64 = 1 << 50;
/// Largest weight of a compatible pair (distances are clamped to it).
const MAX_COST: f64 = (1u64 << 30) as f64;

/// Pairs `rows` shapes with `columns` shapes, where `cost(i, j)` is the
/// distance of a compatible pair and `None` for an incompatible one.
/// Returns the pairs `(i, j)` in row order.
/// One-to-many matches: `pairs` plus, for every row and every column left
/// without a partner, its nearest partner (lowest cost), shared. Pairs
/// are in the order rows then columns were given.
#[must_use]
pub fn with_nearest(
    mut pairs: Vec<(usize, usize)>,
    rows: usize,
    columns: usize,
    cost: &dyn Fn(usize, usize) -> Option<f32>,
) -> Vec<(usize, usize)> {
    let (mut row_used, mut col_used) = (vec![false; rows], vec![false; columns]);
    for &(i, j) in &pairs {
        row_used[i] = true;
        col_used[j] = true;
    }
    let nearest = |candidates: &mut dyn Iterator<Item = (usize, Option<f32>)>| {
        candidates
            .filter_map(|(k, c)| c.map(|c| (k, c)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(k, _)| k)
    };
    for i in (0..rows).filter(|&i| !row_used[i]) {
        if let Some(j) = nearest(&mut (0..columns).map(|j| (j, cost(i, j)))) {
            pairs.push((i, j));
        }
    }
    for j in (0..columns).filter(|&j| !col_used[j]) {
        if let Some(i) = nearest(&mut (0..rows).map(|i| (i, cost(i, j)))) {
            pairs.push((i, j));
        }
    }
    pairs
}

pub fn pair(
    method: PairingMethod,
    rows: usize,
    columns: usize,
    cost: &dyn Fn(usize, usize) -> Option<f32>,
) -> Vec<(usize, usize)> {
    if rows == 0 || columns == 0 {
        return Vec::new();
    }
    match method {
        PairingMethod::Munkres => munkres(rows, columns, cost),
        PairingMethod::MutualNearest => mutual_nearest(rows, columns, cost),
    }
}

fn weight(c: Option<f32>) -> i64 {
    match c {
        Some(d) if d.is_finite() => (f64::from(d.max(0.0)) * UNIT).min(MAX_COST) as i64,
        _ => FORBIDDEN,
    }
}

fn munkres(
    rows: usize,
    columns: usize,
    cost: &dyn Fn(usize, usize) -> Option<f32>,
) -> Vec<(usize, usize)> {
    // kuhn_munkres needs no more rows than columns.
    let flip = rows > columns;
    let (n, m) = if flip {
        (columns, rows)
    } else {
        (rows, columns)
    };
    let mut values = Vec::with_capacity(n * m);
    let mut any = false;
    for i in 0..n {
        for j in 0..m {
            let c = if flip { cost(j, i) } else { cost(i, j) };
            any |= c.is_some();
            values.push(weight(c));
        }
    }
    if !any {
        return Vec::new();
    }
    let matrix = Matrix::from_vec(n, m, values).expect("n · m values");
    let (_, assignment) = pathfinding::kuhn_munkres::kuhn_munkres_min(&matrix);
    let mut pairs: Vec<(usize, usize)> = assignment
        .into_iter()
        .enumerate()
        .filter(|&(i, j)| matrix[(i, j)] < FORBIDDEN)
        .map(|(i, j)| if flip { (j, i) } else { (i, j) })
        .collect();
    pairs.sort_unstable();
    pairs
}

fn mutual_nearest(
    rows: usize,
    columns: usize,
    cost: &dyn Fn(usize, usize) -> Option<f32>,
) -> Vec<(usize, usize)> {
    let mut row_best: Vec<Option<(f32, usize)>> = vec![None; rows];
    let mut column_best: Vec<Option<(f32, usize)>> = vec![None; columns];
    for (i, row) in row_best.iter_mut().enumerate() {
        for (j, column) in column_best.iter_mut().enumerate() {
            let Some(d) = cost(i, j) else { continue };
            if row.is_none_or(|(b, _)| d < b) {
                *row = Some((d, j));
            }
            if column.is_none_or(|(b, _)| d < b) {
                *column = Some((d, i));
            }
        }
    }
    (0..rows)
        .filter_map(|i| {
            let (_, j) = row_best[i]?;
            (column_best[j]?.1 == i).then_some((i, j))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Every matching of compatible pairs: the largest, then the cheapest
    /// (in Munkres' integer weights), by enumeration.
    fn brute_force(costs: &[Vec<Option<f32>>], columns: usize) -> (usize, i64) {
        fn go(
            i: usize,
            used: &mut Vec<bool>,
            costs: &[Vec<Option<f32>>],
            count: usize,
            total: i64,
            best: &mut (usize, i64),
        ) {
            if i == costs.len() {
                if count > best.0 || (count == best.0 && total < best.1) {
                    *best = (count, total);
                }
                return;
            }
            go(i + 1, used, costs, count, total, best);
            for j in 0..used.len() {
                if let Some(c) = costs[i][j]
                    && !used[j]
                {
                    used[j] = true;
                    go(i + 1, used, costs, count + 1, total + weight(Some(c)), best);
                    used[j] = false;
                }
            }
        }
        let mut best = (0, 0);
        go(0, &mut vec![false; columns], costs, 0, 0, &mut best);
        best
    }

    proptest! {
        #[test]
        fn munkres_finds_the_largest_then_cheapest_matching(
            rows in 0usize..6,
            columns in 0usize..6,
            seed in proptest::collection::vec((0.0f32..10.0, 0u8..4), 36),
        ) {
            // A quarter of the pairs are incompatible.
            let costs: Vec<Vec<Option<f32>>> = (0..rows)
                .map(|i| (0..columns).map(|j| {
                    let (d, k) = seed[i * 6 + j];
                    (k != 0).then_some(d)
                }).collect())
                .collect();
            let pairs = pair(PairingMethod::Munkres, rows, columns, &|i, j| costs[i][j]);
            let mut seen_rows = std::collections::HashSet::new();
            let mut seen_columns = std::collections::HashSet::new();
            for &(i, j) in &pairs {
                prop_assert!(costs[i][j].is_some());
                prop_assert!(seen_rows.insert(i) && seen_columns.insert(j));
            }
            let total: i64 = pairs.iter().map(|&(i, j)| weight(costs[i][j])).sum();
            prop_assert_eq!((pairs.len(), total), brute_force(&costs, columns));
        }

        #[test]
        fn mutual_nearest_pairs_are_mutual(
            rows in 0usize..6,
            columns in 0usize..6,
            seed in proptest::collection::vec((0.0f32..10.0, 0u8..4), 36),
        ) {
            let cost = |i: usize, j: usize| {
                let (d, k) = seed[i * 6 + j];
                (k != 0).then_some(d)
            };
            for (i, j) in pair(PairingMethod::MutualNearest, rows, columns, &cost) {
                let d = cost(i, j).unwrap();
                prop_assert!((0..columns).all(|k| cost(i, k).is_none_or(|e| e >= d)));
                prop_assert!((0..rows).all(|k| cost(k, j).is_none_or(|e| e >= d)));
            }
        }
    }

    #[test]
    fn distance_sums_corner_distances() {
        let a = corners(&Affine3A::IDENTITY);
        let b = corners(&Affine3A::from_translation(Vec3::X));
        assert!((distance(&a, &b) - 8.0).abs() < 1e-5);
        assert_eq!(distance(&a, &a), 0.0);
    }
}
