//! Merged masses (thesis Fig. 5.12): with one-to-many matches, several
//! shapes of one design blend toward one shape of the other, and where
//! the blended shapes intersect they become one. Intersecting pairs come
//! from a bounding volume hierarchy over the shapes' boxes (`obvhs`), not
//! from testing every pair.

use obvhs::aabb::Aabb;
use obvhs::bvh2::builder::build_bvh2;
use obvhs::{Boundable, BvhBuildParams};

use crate::glam::{Affine3A, Mat3A, Vec3, Vec3A};

use super::pairing::corners;
use super::{Placed, Source};

/// A box and its index, for the hierarchy.
struct Item(Aabb);

impl Boundable for Item {
    fn aabb(&self) -> Aabb {
        self.0
    }
}

/// Whether two boxes overlap by more than a sliver (`1e-6` of their size)
/// along every axis: boxes that only touch do not.
fn overlap(a: &Aabb, b: &Aabb) -> bool {
    let size = (a.max - a.min).max(b.max - b.min).max_element().max(1e-12);
    let lo = a.min.max(b.min);
    let hi = a.max.min(b.max);
    (hi - lo).min_element() > 1e-6 * size
}

/// Every pair `(i, j)`, `i < j`, of `boxes` that overlap (more than
/// touch), in increasing order, found through a BVH.
#[must_use]
pub fn overlapping_pairs(boxes: &[Aabb]) -> Vec<(usize, usize)> {
    if boxes.len() < 2 {
        return Vec::new();
    }
    let items: Vec<Item> = boxes.iter().map(|b| Item(*b)).collect();
    let mut took = std::time::Duration::ZERO;
    let bvh = build_bvh2(&items, BvhBuildParams::fastest_build(), &mut took);
    let mut pairs = Vec::new();
    for (i, b) in boxes.iter().enumerate() {
        bvh.aabb_traverse(*b, |bvh, node| {
            let node = &bvh.nodes[node as usize];
            let first = node.first_index as usize;
            for k in first..first + node.prim_count as usize {
                let j = bvh.primitive_indices[k] as usize;
                if j > i && overlap(b, &boxes[j]) {
                    pairs.push((i, j));
                }
            }
            true
        });
    }
    pairs.sort_unstable();
    pairs
}

/// The world box of a placed unit box.
fn world_box(t: &Affine3A) -> Aabb {
    let c = corners(t);
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for p in c {
        lo = lo.min(p);
        hi = hi.max(p);
    }
    Aabb::new(lo.into(), hi.into())
}

fn find(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

/// Merges intersecting blended shapes: shapes of the same kind that both
/// designs placed together (the same shape, the same pair of nodes) and
/// whose boxes overlap become one, the box around them all in the frame
/// of the largest. Others are kept as they are; order is kept (a merged
/// shape takes its first member's place).
pub(crate) fn merge_masses(shapes: &mut Vec<Placed>) {
    let candidates: Vec<usize> = (0..shapes.len())
        .filter(|&i| matches!(shapes[i].source, Source::Both(..)))
        .collect();
    let boxes: Vec<Aabb> = candidates
        .iter()
        .map(|&i| world_box(&shapes[i].transform))
        .collect();
    let mut parent: Vec<usize> = (0..candidates.len()).collect();
    for (x, y) in overlapping_pairs(&boxes) {
        let (p, q) = (&shapes[candidates[x]], &shapes[candidates[y]]);
        if p.shape == q.shape && p.source == q.source {
            let (rx, ry) = (find(&mut parent, x), find(&mut parent, y));
            if rx != ry {
                parent[rx.max(ry)] = rx.min(ry);
            }
        }
    }
    let mut groups: std::collections::BTreeMap<usize, Vec<usize>> = Default::default();
    for (x, &shape) in candidates.iter().enumerate() {
        let r = find(&mut parent, x);
        groups.entry(r).or_default().push(shape);
    }
    let mut drop = vec![false; shapes.len()];
    for members in groups.values().filter(|m| m.len() > 1) {
        let volume = |i: usize| shapes[i].transform.matrix3.determinant().abs();
        let largest = *members
            .iter()
            .max_by(|&&a, &&b| volume(a).total_cmp(&volume(b)))
            .expect("a group has members");
        let frame = shapes[largest].transform;
        // The largest member's orientation, without its scale.
        let axes = [
            frame.matrix3.x_axis.normalize_or_zero(),
            frame.matrix3.y_axis.normalize_or_zero(),
            frame.matrix3.z_axis.normalize_or_zero(),
        ];
        let rotation = Mat3A::from_cols(axes[0], axes[1], axes[2]);
        let to_local = rotation.transpose();
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for &m in members {
            for c in corners(&shapes[m].transform) {
                let l = Vec3::from(to_local * Vec3A::from(c));
                lo = lo.min(l);
                hi = hi.max(l);
            }
        }
        let centre = rotation * Vec3A::from(0.5 * (lo + hi));
        let first = members[0];
        shapes[first].transform = Affine3A {
            matrix3: rotation * Mat3A::from_diagonal(hi - lo),
            translation: centre,
        };
        for &m in &members[1..] {
            drop[m] = true;
        }
    }
    let mut k = 0;
    shapes.retain(|_| {
        k += 1;
        !drop[k - 1]
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn aabb() -> impl Strategy<Value = Aabb> {
        (
            prop::array::uniform3(-10.0f32..10.0),
            prop::array::uniform3(0.0f32..4.0),
        )
            .prop_map(|(c, s)| {
                let (c, s) = (Vec3A::from(c), Vec3A::from(s));
                Aabb::new(c - s, c + s)
            })
    }

    proptest! {
        /// The hierarchy finds exactly the pairs testing every pair finds.
        #[test]
        fn bvh_pairs_equal_all_pairs(boxes in prop::collection::vec(aabb(), 0..60)) {
            let mut brute = Vec::new();
            for i in 0..boxes.len() {
                for j in i + 1..boxes.len() {
                    if overlap(&boxes[i], &boxes[j]) {
                        brute.push((i, j));
                    }
                }
            }
            prop_assert_eq!(overlapping_pairs(&boxes), brute);
        }
    }

    fn placed(centre: Vec3, size: Vec3, source: Source) -> Placed {
        Placed {
            shape: 0,
            transform: Affine3A::from_scale_rotation_translation(size, Default::default(), centre),
            source,
        }
    }

    #[test]
    fn intersecting_blends_of_one_kind_merge() {
        let both = Source::Both(1, 2);
        let mut shapes = vec![
            placed(Vec3::ZERO, Vec3::ONE, both),
            placed(Vec3::new(0.5, 0.0, 0.0), Vec3::ONE, both),
            // Touching only: kept apart.
            placed(Vec3::new(2.0, 0.0, 0.0), Vec3::ONE, both),
            // Overlapping but from other nodes, or one design alone: kept.
            placed(Vec3::new(0.2, 0.0, 0.0), Vec3::ONE, Source::Both(1, 3)),
            placed(Vec3::new(0.2, 0.0, 0.0), Vec3::ONE, Source::A(1)),
        ];
        merge_masses(&mut shapes);
        assert_eq!(shapes.len(), 4);
        let m = shapes[0].transform;
        assert!(Vec3::from(m.translation).abs_diff_eq(Vec3::new(0.25, 0.0, 0.0), 1e-6));
        assert!((m.matrix3.x_axis.x - 1.5).abs() < 1e-6);
        // Identical boxes merge into the box itself.
        let mut same = vec![placed(Vec3::ONE, Vec3::splat(2.0), both); 3];
        let expected = same[0].transform;
        merge_masses(&mut same);
        assert_eq!(same.len(), 1);
        assert!(same[0].transform.abs_diff_eq(expected, 1e-6));
    }
}
