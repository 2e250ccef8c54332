//! Volume counts and scores against a brute-force count from per-voxel references.

use std::collections::HashMap;

use crate::common::placement;
use glam::{Affine3A, IVec3, Quat, UVec3, Vec3};
use proptest::prelude::*;
use shapegen_core::graph::Limits;
use shapegen_score::reference;
use shapegen_score::{Grid, Mesh, Solid};
use shapegen_score::{OutsideCount, VolumeCounts, VolumeScene, VolumeScratch, VolumeTarget};
use shapegen_score::{OverlapCount, VolumeScore, smootherstep};

fn grid() -> Grid {
    Grid::new(
        Vec3::new(-2.0, -1.0, -2.0),
        Vec3::new(2.0, 2.0, 2.0),
        UVec3::new(21, 13, 17),
    )
    .unwrap()
}

/// A 2 × 1 × 2 box target standing on y = 0, filling with weight 2 and avoided outside with −1.
fn scene() -> VolumeScene {
    let mut mesh = Mesh::unit_cube();
    for p in &mut mesh.positions {
        *p = *p * Vec3::new(2.0, 1.0, 2.0) + Vec3::new(0.0, 0.5, 0.0);
    }
    VolumeScene::new(
        grid(),
        &[VolumeTarget {
            name: "box".into(),
            mesh,
            fill: 2.0,
            outside: -1.0,
            inside: Default::default(),
        }],
    )
    .unwrap()
}

/// [`scene`] with a second, overlapping box of other weights: the cell
/// weights no longer follow target membership alone (four values), so
/// counting reads them per cell.
fn two_target_scene() -> VolumeScene {
    let boxed = |scale: Vec3, at: Vec3| {
        let mut mesh = Mesh::unit_cube();
        for p in &mut mesh.positions {
            *p = *p * scale + at;
        }
        mesh
    };
    VolumeScene::new(
        grid(),
        &[
            VolumeTarget {
                name: "box".into(),
                mesh: boxed(Vec3::new(2.0, 1.0, 2.0), Vec3::new(0.0, 0.5, 0.0)),
                fill: 2.0,
                outside: -1.0,
                inside: Default::default(),
            },
            VolumeTarget {
                name: "other".into(),
                mesh: boxed(Vec3::splat(1.5), Vec3::new(0.7, 0.9, -0.4)),
                fill: 3.0,
                outside: -0.5,
                inside: Default::default(),
            },
        ],
    )
    .unwrap()
}

/// The counts recomputed from per-voxel reference cell sets.
fn brute_force(scene: &VolumeScene, solid: &Solid, instances: &[Affine3A]) -> VolumeCounts {
    let g = scene.grid();
    let mut hits: HashMap<IVec3, u64> = HashMap::new();
    let mut c = VolumeCounts::default();
    for t in instances {
        for cell in reference::cells_by_parity(g, solid, t) {
            if g.contains(cell) {
                *hits.entry(cell).or_default() += 1;
            } else {
                c.outside += 1;
            }
        }
    }
    for (cell, h) in hits {
        let i = g.index(cell.as_uvec3());
        let target = scene.is_target(i);
        if target {
            c.good += 1
        } else {
            c.bad += 1
        }
        c.weight += f64::from(scene.weights()[i]);
        if h >= 2 {
            c.overlap_cells += 1;
        }
        c.overlap_hits += h.saturating_sub(1);
    }
    c
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn counts_match_brute_force(instances in proptest::collection::vec(placement(0.3..2.0, Vec3::new(-2.5, -1.5, -2.5), Vec3::splat(2.5)), 1..5), frustum in any::<bool>(), two in any::<bool>()) {
        let scene = if two { two_target_scene() } else { scene() };
        let mesh = if frustum { Mesh::trunk() } else { Mesh::unit_cube() };
        let solid = Solid::new("shape", &mesh).unwrap();
        let mut scratch = VolumeScratch::new(&scene);
        // Two rounds: the sparse reset must leave no trace of the previous model.
        for round in 0..2 {
            scratch.begin();
            let used = &instances[..instances.len() - round.min(instances.len() - 1)];
            for t in used {
                scratch.add(&scene, &solid, t);
            }
            let fast = scratch.counts();
            let slow = brute_force(&scene, &solid, used);
            prop_assert_eq!((fast.good, fast.bad, fast.overlap_cells, fast.overlap_hits, fast.outside),
                            (slow.good, slow.bad, slow.overlap_cells, slow.overlap_hits, slow.outside));
            prop_assert!((fast.weight - slow.weight).abs() < 1e-9);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// `OutsideCount::Aabb`: each instance adds the lattice cells outside the
    /// grid whose centres lie in the world box around its placed local
    /// bounding box (counted here by
    /// enumerating a generous block of cells), and never fewer than the
    /// solid rule; the in-grid counts do not change.
    #[test]
    fn aabb_outside_counts_match_brute_force(instances in proptest::collection::vec(placement(0.3..2.0, Vec3::new(-2.5, -1.5, -2.5), Vec3::splat(2.5)), 1..4), frustum in any::<bool>()) {
        let solid_rule = scene();
        let aabb_rule = scene().with_outside_count(OutsideCount::Aabb);
        let mesh = if frustum { Mesh::trunk() } else { Mesh::unit_cube() };
        let solid = Solid::new("shape", &mesh).unwrap();
        let g = grid();
        let mut expected = 0u64;
        for t in &instances {
            // The world box around the placed local bounding box's corners.
            let (llo, lhi) = mesh.bounds();
            let m = glam::DAffine3::from_mat4(glam::Mat4::from(*t).as_dmat4());
            let corners: Vec<glam::DVec3> = (0..8)
                .map(|i| {
                    let pick = |bit: usize, a: f32, b: f32| f64::from(if i & bit == 0 { a } else { b });
                    m.transform_point3(glam::DVec3::new(
                        pick(1, llo.x, lhi.x),
                        pick(2, llo.y, lhi.y),
                        pick(4, llo.z, lhi.z),
                    ))
                })
                .collect();
            let lo = corners.iter().fold(glam::DVec3::INFINITY, |a, p| a.min(*p));
            let hi = corners.iter().fold(glam::DVec3::NEG_INFINITY, |a, p| a.max(*p));
            for z in -40..60 {
                for y in -40..60 {
                    for x in -40..60 {
                        let c = IVec3::new(x, y, z);
                        let p = g.center(c);
                        if p.cmpge(lo).all() && p.cmple(hi).all() && !g.contains(c) {
                            expected += 1;
                        }
                    }
                }
            }
        }
        let (mut a, mut b) = (VolumeScratch::new(&solid_rule), VolumeScratch::new(&aabb_rule));
        a.begin();
        b.begin();
        for t in &instances {
            a.add(&solid_rule, &solid, t);
            b.add(&aabb_rule, &solid, t);
        }
        let (a, b) = (a.counts(), b.counts());
        prop_assert_eq!(b.outside, expected);
        prop_assert!(b.outside >= a.outside);
        prop_assert_eq!((a.good, a.bad, a.overlap_cells), (b.good, b.bad, b.overlap_cells));
    }
}

/// A weight for [`scene_matches_the_targets_reference_cells`]: whole,
/// halves and tenths (whose sums depend on their order in `f64`).
fn weight() -> impl Strategy<Value = f64> {
    prop_oneof![
        (-3i32..4).prop_map(f64::from),
        (-30i32..31).prop_map(|i| f64::from(i) / 10.0),
        Just(0.5)
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// A scene's weights, target flags and per-group target cells equal a
    /// cell-by-cell combination of its targets' reference cells: each
    /// cell's weight summed over the targets in order in `f64`, then
    /// rounded to `f32`. Targets are placed cubes, star prisms and open
    /// boxes (parity), some reaching beyond the grid, in one to three
    /// groups.
    #[test]
    fn scene_matches_the_targets_reference_cells(
        parts in proptest::collection::vec(
            (placement(0.3..3.0, Vec3::new(-3.0, -2.0, -3.0), Vec3::splat(3.0)), 0u8..3, weight(), weight()),
            1..5,
        ),
        cut in 0usize..5,
    ) {
        let grid = grid();
        let targets: Vec<VolumeTarget> = parts
            .iter()
            .enumerate()
            .map(|(k, (t, kind, fill, outside))| {
                let mut mesh = match kind {
                    0 => Mesh::unit_cube(),
                    1 => crate::common::star_prism(),
                    _ => crate::common::open_box(),
                };
                for p in &mut mesh.positions {
                    *p = t.transform_point3(*p);
                }
                VolumeTarget { name: format!("part {k}"), mesh, fill: *fill, outside: *outside, inside: Default::default() }
            })
            .collect();
        // One group, or two split at `cut`, or one per target.
        let n = targets.len();
        let groups: Vec<std::ops::Range<usize>> = match cut {
            0 => std::iter::once(0..n).collect(),
            c if c < n => vec![0..c, c..n],
            _ => (0..n).map(|k| k..k + 1).collect(),
        };
        let Ok(scene) = VolumeScene::new_grouped(grid, &targets, &groups) else {
            // A group that covers no cell: checked elsewhere.
            return Ok(());
        };
        let cells: Vec<std::collections::HashSet<usize>> = targets
            .iter()
            .map(|t| {
                let solid = Solid::new(&t.name, &t.mesh).unwrap();
                reference::cells_by_parity(&grid, &solid, &Affine3A::IDENTITY)
                    .into_iter()
                    .filter(|c| grid.contains(*c))
                    .map(|c| grid.index(c.as_uvec3()))
                    .collect()
            })
            .collect();
        for i in 0..grid.len() {
            let mut w = 0.0f64;
            for (t, c) in targets.iter().zip(&cells) {
                w += if c.contains(&i) { t.fill } else { t.outside };
            }
            prop_assert_eq!(scene.weights()[i].to_bits(), (w as f32).to_bits(), "cell {}", i);
            prop_assert_eq!(scene.is_target(i), cells.iter().any(|c| c.contains(&i)), "cell {}", i);
        }
        // Per group, its cells: the share of a model covering the whole
        // grid that lies in the group.
        let mut scratch = VolumeScratch::new(&scene);
        scratch.begin();
        let all = Solid::new("all", &Mesh::unit_cube()).unwrap();
        scratch.add(&scene, &all, &Affine3A::from_scale(Vec3::splat(10.0)));
        let quality = scene.quality(&scratch);
        prop_assert_eq!(quality.len(), groups.len());
        for (q, g) in quality.iter().zip(&groups) {
            let union: std::collections::HashSet<usize> = cells[g.clone()].iter().flatten().copied().collect();
            prop_assert_eq!((q.precision * q.model as f64).round() as usize, union.len());
        }
    }
}

#[test]
fn the_target_itself_scores_the_optimum() {
    let scene = scene();
    assert!(scene.warnings().is_empty());
    let t = scene.target_cells();
    assert!(t > 0);
    let solid = Solid::new("cube", &Mesh::unit_cube()).unwrap();
    let mut scratch = VolumeScratch::new(&scene);
    scratch.begin();
    scratch.add(
        &scene,
        &solid,
        &Affine3A::from_scale_rotation_translation(
            Vec3::new(2.0, 1.0, 2.0),
            Quat::IDENTITY,
            Vec3::new(0.0, 0.5, 0.0),
        ),
    );
    let c = scratch.counts();
    assert_eq!((c.good, c.bad, c.overlap_cells, c.outside), (t, 0, 0, 0));
    let limits = Limits {
        max_depth: None,
        min_len: 4,
        max_len: Some(100),
    };
    let normalized = VolumeScore::Normalized {
        w_good: 2.0,
        w_bad: 15.0,
        w_length: 0.1,
        separate_overlap: None,
    };
    // At L = L_min the length term vanishes: exactly the optimum w_good.
    assert!((normalized.score(&c, &scene, 4, &limits) - 2.0).abs() < 1e-12);
    assert!(
        (normalized.score(&c, &scene, 52, &limits) - (2.0 - 0.1 * smootherstep(4.0, 100.0, 52.0)))
            .abs()
            < 1e-12
    );
    let linear = VolumeScore::Linear {
        w_self: 1.0,
        overlap: OverlapCount::Cells,
    };
    assert!((linear.score(&c, &scene, 4, &limits) - 2.0 * t as f64).abs() < 1e-9);
    // The same box twice: every cell overlaps.
    scratch.add(
        &scene,
        &solid,
        &Affine3A::from_scale_rotation_translation(
            Vec3::new(2.0, 1.0, 2.0),
            Quat::IDENTITY,
            Vec3::new(0.0, 0.5, 0.0),
        ),
    );
    let c2 = scratch.counts();
    assert_eq!((c2.good, c2.overlap_cells, c2.overlap_hits), (t, t, t));
    assert!((linear.score(&c2, &scene, 4, &limits) - (2.0 * t as f64 - t as f64)).abs() < 1e-9);
}

#[test]
fn non_finite_weights_and_bad_meshes_are_errors() {
    let bad = VolumeTarget {
        name: "x".into(),
        mesh: Mesh::unit_cube(),
        fill: f64::NAN,
        outside: 0.0,
        inside: Default::default(),
    };
    assert!(
        VolumeScene::new(grid(), &[bad])
            .unwrap_err()
            .to_string()
            .contains("non-finite")
    );
    let empty = VolumeTarget {
        name: "empty".into(),
        mesh: Mesh::default(),
        fill: 1.0,
        outside: 0.0,
        inside: Default::default(),
    };
    assert!(
        VolumeScene::new(grid(), &[empty])
            .unwrap_err()
            .to_string()
            .contains("no triangles")
    );
}

#[test]
fn quality_is_reported_per_target_or_per_group() {
    use shapegen_score::Quality;
    // A 10 × 10 × 10 grid of unit cells over [0, 10]³ and two box targets:
    // A = [0, 4] × [0, 10] × [0, 10] (400 cells), B = [2, 6] × ... (400,
    // 200 of them in A as well).
    let grid = Grid::new(Vec3::ZERO, Vec3::splat(10.0), UVec3::splat(10)).unwrap();
    let boxed = |x0: f32, x1: f32| {
        let transform = Affine3A::from_scale_rotation_translation(
            Vec3::new(x1 - x0, 10.0, 10.0),
            Quat::IDENTITY,
            Vec3::new(0.5 * (x0 + x1), 5.0, 5.0),
        );
        VolumeTarget {
            name: format!("box {x0}..{x1}"),
            mesh: Mesh::unit_cube().transformed(&transform),
            fill: 1.0,
            outside: 0.0,
            inside: shapegen_score::Inside::Parity,
        }
    };
    let targets = [boxed(0.0, 4.0), boxed(2.0, 6.0)];
    // The model: x ∈ [3, 8] (500 cells; 100 in A, 300 in B, 300 in A ∪ B).
    let solid = Solid::new("cube", &Mesh::unit_cube()).unwrap();
    let model = Affine3A::from_scale_rotation_translation(
        Vec3::new(5.0, 10.0, 10.0),
        Quat::IDENTITY,
        Vec3::new(5.5, 5.0, 5.0),
    );
    let measure = |scene: &VolumeScene| {
        let mut scratch = VolumeScratch::new(scene);
        scratch.begin();
        scratch.add(scene, &solid, &model);
        scene.quality(&scratch)
    };
    let each = VolumeScene::new(grid, &targets).unwrap();
    assert_eq!(
        measure(&each),
        [
            Quality::from_counts(100, 500, 400),
            Quality::from_counts(300, 500, 400)
        ]
    );
    let one =
        VolumeScene::new_grouped(grid, &targets, &[std::ops::Range { start: 0, end: 2 }]).unwrap();
    assert_eq!(measure(&one), [Quality::from_counts(300, 500, 600)]);
    // A target outside the grid is an error of its own, a warning as part
    // of a group that covers cells.
    let far = boxed(20.0, 24.0);
    let three = [boxed(0.0, 4.0), boxed(2.0, 6.0), far];
    let err = VolumeScene::new(grid, &three).unwrap_err();
    assert!(
        matches!(&err, shapegen_score::ScoreError::EmptyTarget { target: 2, reason } if reason.contains("outside the grid")),
        "{err}"
    );
    let grouped = VolumeScene::new_grouped(grid, &three, &[0..1, 1..3]).unwrap();
    assert!(
        grouped.warnings().iter().any(|w| w.contains("box 20..24")),
        "{:?}",
        grouped.warnings()
    );
    // Groups must split the targets in order.
    assert!(
        VolumeScene::new_grouped(grid, &targets, &[std::ops::Range { start: 0, end: 1 }]).is_err()
    );
    assert!(VolumeScene::new_grouped(grid, &targets, &[1..2, 0..1]).is_err());
}

/// Hit counts saturate at 127 without disturbing the counts: 200 copies of
/// one box hit each of its cells 200 times.
#[test]
fn many_instances_on_one_cell_saturate_the_hit_count_only() {
    let scene = scene();
    let solid = Solid::new("cube", &Mesh::unit_cube()).unwrap();
    let mut scratch = VolumeScratch::new(&scene);
    scratch.begin();
    let t = Affine3A::from_translation(Vec3::new(0.1, 0.4, 0.1));
    for _ in 0..200 {
        scratch.add(&scene, &solid, &t);
    }
    let c = scratch.counts();
    let cells = c.good + c.bad;
    assert!(cells > 0);
    assert_eq!(c.overlap_cells, cells);
    assert_eq!(c.overlap_hits, 199 * cells);
    assert_eq!(
        scratch.hits().iter().filter(|&&h| h == 127).count() as u64,
        cells
    );
    // The target flags survive the reset: the same model counts the same.
    scratch.begin();
    scratch.add(&scene, &solid, &t);
    assert_eq!(
        (scratch.counts().good, scratch.counts().bad),
        (c.good, c.bad)
    );
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Models made of instances seen before (the same shape and transform,
    /// in this model or an earlier one, as an optimizer's models are) count
    /// the same through the instance cache of `add_shape` as through `add`
    /// with a fresh scratch, for both outside rules and per-cell weights.
    #[test]
    fn cached_instances_count_as_fresh_ones(
        pool in proptest::collection::vec(placement(0.3..2.0, Vec3::new(-2.5, -1.5, -2.5), Vec3::splat(2.5)), 1..5),
        models in proptest::collection::vec(proptest::collection::vec((0usize..8, 0usize..2), 1..6), 1..5),
        two in any::<bool>(),
        aabb in any::<bool>(),
    ) {
        let mut scene = if two { two_target_scene() } else { scene() };
        if aabb {
            scene = scene.with_outside_count(OutsideCount::Aabb);
        }
        // Shape 0 convex, shape 1 a (non-convex) mesh: the same transform
        // on two shapes must not share an entry.
        let solids = [
            Solid::new("cube", &Mesh::unit_cube()).unwrap(),
            Solid::new("two cubes", &two_cubes()).unwrap(),
        ];
        prop_assert!(matches!(solids[1], Solid::Mesh(_)));
        let mut cached = VolumeScratch::new(&scene);
        for model in &models {
            cached.begin();
            let mut fresh = VolumeScratch::new(&scene);
            for &(k, shape) in model {
                let t = &pool[k % pool.len()];
                cached.add_shape(&scene, shape as u16, &solids[shape], t);
                fresh.add(&scene, &solids[shape], t);
            }
            prop_assert_eq!(cached.counts(), fresh.counts());
            prop_assert_eq!(cached.hits(), fresh.hits());
        }
    }
}

/// Two small cubes side by side in one mesh: closed, not convex.
fn two_cubes() -> Mesh {
    let cube = Mesh::unit_cube();
    let mut mesh = Mesh::unit_cube();
    mesh.positions.clear();
    mesh.triangles.clear();
    for dx in [-0.3f32, 0.3] {
        let n = mesh.positions.len() as u32;
        mesh.positions.extend(
            cube.positions
                .iter()
                .map(|p| *p * 0.4 + Vec3::new(dx, 0.0, 0.0)),
        );
        mesh.triangles
            .extend(cube.triangles.iter().map(|t| t.map(|i| i + n)));
    }
    mesh
}
