//! Exactness of the span voxelizer against per-voxel references, on random
//! transforms of the cube, the trunk frustum and real meshes.

use std::collections::HashSet;

use crate::common::{
    mixed_orientation, open_box, open_star, placement, shared, star_prism, tube, wavy_sheet,
};
use glam::{Affine3A, IVec3, UVec3, Vec3};
use proptest::prelude::*;
use shapegen_score::reference;
use shapegen_score::{Grid, Mesh, Solid, Voxelizer};
use shapegen_score::{Inside, MeshSolid};

fn cells(grid: &Grid, solid: &Solid, t: &Affine3A) -> HashSet<IVec3> {
    let mut out = HashSet::new();
    Voxelizer::new().spans(grid, solid, t, |s| {
        for x in s.x0..s.x1 {
            assert!(
                out.insert(IVec3::new(x as i32, s.y as i32, s.z as i32)),
                "a cell in two spans"
            );
        }
    });
    out
}

fn grid() -> Grid {
    // Anisotropic cells; instances may reach outside the grid (lattice cells).
    Grid::new(
        Vec3::new(-2.0, -1.5, -2.0),
        Vec3::new(2.0, 1.5, 2.0),
        UVec3::new(23, 17, 29),
    )
    .unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    /// Convex solids (box, frustum): spans equal the per-voxel parity
    /// reference exactly, and the independent plane test except for centres
    /// on the surface (ties, |distance| < 1e-9).
    #[test]
    fn convex_spans_are_exact(t in placement(0.2..2.5, Vec3::splat(-2.5), Vec3::splat(2.5)), frustum in any::<bool>()) {
        let mesh = if frustum { Mesh::trunk() } else { Mesh::unit_cube() };
        let solid = Solid::new("shape", &mesh).unwrap();
        prop_assert!(matches!(solid, Solid::Convex(_)));
        let g = grid();
        let spans = cells(&g, &solid, &t);
        let parity: HashSet<IVec3> = reference::cells_by_parity(&g, &solid, &t).into_iter().collect();
        prop_assert_eq!(&spans, &parity);
        let planes: HashSet<IVec3> = reference::cells_by_planes(&g, &solid, &t).into_iter().collect();
        let Solid::Convex(c) = &solid else { unreachable!() };
        let inv = t.inverse();
        for cell in spans.symmetric_difference(&planes) {
            let local = inv.transform_point3(g.center(*cell).as_vec3()).as_dvec3();
            prop_assert!(c.plane_distance(local) < 1e-5, "cell {cell} differs away from the surface");
        }
    }

    /// The scanline path on the cube mesh equals the parity reference, and the
    /// analytic convex path except at ties.
    #[test]
    fn mesh_spans_are_exact_on_the_cube(t in placement(0.2..2.5, Vec3::splat(-2.5), Vec3::splat(2.5))) {
        let cube = Mesh::unit_cube();
        let bvh = Solid::Mesh(MeshSolid::new(&cube));
        let g = grid();
        let spans = cells(&g, &bvh, &t);
        let parity: HashSet<IVec3> = reference::cells_by_parity(&g, &bvh, &t).into_iter().collect();
        prop_assert_eq!(&spans, &parity);
        let convex = cells(&g, &Solid::new("cube", &cube).unwrap(), &t);
        let differ = spans.symmetric_difference(&convex).count();
        prop_assert!(differ <= 2, "{} cells differ between the scanline and the analytic cube", differ);
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    /// Boxes placed without rotation take the shortcut that computes the
    /// row interval once, and tests each y and each z once: equal to the
    /// per-row reference, also when faces sit exactly on cell centres
    /// (translations and sizes on the lattice's half cells) and when the box
    /// reaches far beyond the grid. Turned about x (rows still cross only
    /// the two end faces), the rows' interval is still shared but the side
    /// faces test y and z together.
    #[test]
    fn unrotated_boxes_equal_the_reference(
        size in (1i32..40, 1i32..40, 1i32..40),
        at in (-60i32..60, -60i32..60, -60i32..60),
        jitter in (0.0f32..1.0, 0.0f32..1.0, 0.0f32..1.0),
        snapped in any::<bool>(),
        mirror in any::<bool>(),
        about_x in prop_oneof![Just(0.0f32), 0.1f32..3.0],
    ) {
        let g = grid();
        // Half cells of the grid: (4/23, 3/17, 4/29) / 2.
        let half = g.cell_size().as_vec3() / 2.0;
        let j = if snapped { Vec3::ZERO } else { Vec3::new(jitter.0, jitter.1, jitter.2) };
        let scale = (Vec3::new(size.0 as f32, size.1 as f32, size.2 as f32) + j) * half;
        let scale = if mirror { scale * Vec3::new(-1.0, 1.0, 1.0) } else { scale };
        let t = Affine3A::from_scale_rotation_translation(
            scale,
            glam::Quat::from_rotation_x(about_x),
            (Vec3::new(at.0 as f32, at.1 as f32, at.2 as f32) + j) * half,
        );
        let solid = Solid::new("cube", &Mesh::unit_cube()).unwrap();
        let spans = cells(&g, &solid, &t);
        let parity: HashSet<IVec3> = reference::cells_by_parity(&g, &solid, &t).into_iter().collect();
        prop_assert_eq!(spans, parity);
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]

    /// A real watertight mesh from `../shared/data/models/`.
    #[test]
    fn mesh_spans_are_exact_on_a_real_mesh(t in placement(0.2..2.5, Vec3::splat(-2.5), Vec3::splat(2.5))) {
        let Some(path) = shared("data/models/spot.obj") else {
            eprintln!("skipping: ../shared/data/models/spot.obj is not there");
            return Ok(());
        };
        let mesh = Mesh::load_obj(&path).unwrap().normalized();
        let solid = Solid::new("spot", &mesh).unwrap();
        let Solid::Mesh(m) = &solid else { panic!("spot is not convex") };
        prop_assert_eq!(m.boundary_edges(), 0);
        let g = Grid::cube(Vec3::splat(-2.0), Vec3::splat(2.0), 24).unwrap();
        let spans = cells(&g, &solid, &t);
        let parity: HashSet<IVec3> = reference::cells_by_parity(&g, &solid, &t).into_iter().collect();
        prop_assert_eq!(spans, parity);
    }
}

#[test]
fn a_unit_cube_on_the_lattice_fills_exactly_its_cells() {
    // Cells of size 0.25: a cube [0, 1]³ (centred at ½) holds 4³ centres.
    let g = Grid::cube(Vec3::ZERO, Vec3::splat(4.0), 16).unwrap();
    let solid = Solid::new("cube", &Mesh::unit_cube()).unwrap();
    let t = Affine3A::from_translation(Vec3::splat(0.5));
    assert_eq!(cells(&g, &solid, &t).len(), 64);
    // Moved half a cell, centres lie exactly on all six faces. The documented
    // tie rule: along a row (x) spans are half-open, [enter, leave); a face
    // parallel to the rows counts as inside. So 4 cells along x, 5 along y and z.
    let t = Affine3A::from_translation(Vec3::splat(0.5 + 0.125));
    assert_eq!(cells(&g, &solid, &t).len(), 4 * 5 * 5);
    // A singular transform covers nothing.
    assert!(cells(&g, &solid, &Affine3A::from_scale(Vec3::new(1.0, 0.0, 1.0))).is_empty());
}

/// Cells inside by the brute-force winding number (`|w| ≥ ½`), and the
/// cells too close to the threshold to call (`||w| − ½| < 1e-9`).
fn winding_reference(g: &Grid, solid: &Solid, t: &Affine3A) -> (HashSet<IVec3>, HashSet<IVec3>) {
    let (mut inside, mut ties) = (HashSet::new(), HashSet::new());
    for (cell, w) in reference::winding_numbers(g, solid, t) {
        if (w.abs() - 0.5).abs() < 1e-9 {
            ties.insert(cell);
        } else if w.abs() >= 0.5 {
            inside.insert(cell);
        }
    }
    (inside, ties)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Winding-number mode on open meshes (a box without a face, a cup, a
    /// wavy sheet, a mesh with flipped triangles), placed at random and
    /// sometimes mirrored: the fast path (signed crossings plus the cone
    /// over the holes) equals the brute-force sum of every triangle's solid
    /// angle, except for centres at the ½ threshold.
    #[test]
    fn winding_number_spans_equal_the_solid_angle_sum(t in placement(0.5..2.5, Vec3::splat(-1.0), Vec3::splat(1.0)), k in 0usize..5, mirror in any::<bool>()) {
        let mesh = [open_box(), open_star(), wavy_sheet(), mixed_orientation(), tube()][k].clone();
        let solid = Solid::with_inside("open", &mesh, Inside::WindingNumber).unwrap();
        let Solid::Mesh(m) = &solid else { panic!("an open mesh became convex") };
        prop_assert!(m.winding().is_some_and(|w| !w.reversed_cone().is_empty()));
        let t = if mirror { t * Affine3A::from_scale(Vec3::new(-1.0, 1.0, 1.0)) } else { t };
        let g = Grid::cube(Vec3::splat(-2.0), Vec3::splat(2.0), 14).unwrap();
        let fast = cells(&g, &solid, &t);
        let (slow, ties) = winding_reference(&g, &solid, &t);
        let differ: Vec<&IVec3> = fast.symmetric_difference(&slow).filter(|c| !ties.contains(*c)).collect();
        prop_assert!(differ.is_empty(), "{} cells differ, e.g. {:?}", differ.len(), &differ[..differ.len().min(4)]);
    }

    /// On closed meshes both modes give the same cells.
    #[test]
    fn winding_number_equals_parity_on_closed_meshes(t in placement(0.5..2.5, Vec3::splat(-1.0), Vec3::splat(1.0))) {
        let mesh = star_prism();
        let parity = Solid::new("star", &mesh).unwrap();
        let winding = Solid::with_inside("star", &mesh, Inside::WindingNumber).unwrap();
        let Solid::Mesh(m) = &winding else { panic!("the star prism is not convex") };
        prop_assert!(m.winding().is_some_and(|w| w.reversed_cone().is_empty()));
        let g = Grid::cube(Vec3::splat(-2.0), Vec3::splat(2.0), 20).unwrap();
        prop_assert_eq!(cells(&g, &parity, &t), cells(&g, &winding, &t));
    }
}

/// A box without one face, in both modes: every centre sees the hole under
/// less than half the sphere, so the winding number fills the whole box;
/// parity loses the rows that cross the surface once.
#[test]
fn an_open_box_is_filled_by_the_winding_number() {
    let mesh = open_box();
    let g = Grid::cube(Vec3::splat(-0.5), Vec3::splat(0.5), 16).unwrap();
    let winding = Solid::with_inside("box", &mesh, Inside::WindingNumber).unwrap();
    assert_eq!(cells(&g, &winding, &Affine3A::IDENTITY).len(), 16 * 16 * 16);
    let parity = Solid::new("box", &mesh).unwrap();
    assert!(
        matches!(parity, Solid::Mesh(_)),
        "an open box is not convex"
    );
    let n = cells(&g, &parity, &Affine3A::IDENTITY).len();
    assert!(n < 16 * 16 * 16, "{n} cells by parity");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Meshes by parity, closed and open (a box without a face, a wavy
    /// sheet: rows with an odd number of crossings), on a coarse grid where
    /// every box is at most 63 cells long (rows kept as bit masks) and a
    /// fine one where most are longer (rows sorted; the smaller placements
    /// still take the masks): both equal the per-row parity reference.
    #[test]
    fn mesh_spans_equal_the_reference_on_short_and_long_rows(
        t in placement(0.5..2.5, Vec3::splat(-1.0), Vec3::splat(1.0)),
        k in 0usize..5,
        fine in any::<bool>(),
    ) {
        let mesh = [open_box(), wavy_sheet(), star_prism(), tube(), Mesh::unit_cube()][k].clone();
        let solid = Solid::Mesh(MeshSolid::new(&mesh));
        let n = if fine { 90 } else { 14 };
        let g = Grid::cube(Vec3::splat(-2.0), Vec3::splat(2.0), n).unwrap();
        let spans = cells(&g, &solid, &t);
        // Every walkable row along z.
        let z_rows = -i64::from(n)..2 * i64::from(n);
        let parity: HashSet<IVec3> = reference::mesh_cells_by_row_parity(&g, &solid, &t, z_rows)
            .into_iter()
            .collect();
        prop_assert_eq!(spans, parity);
    }
}
