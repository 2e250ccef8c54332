//! Solid voxelization with centre sampling, by row spans.
//!
//! A lattice cell is inside an instance iff its centre is inside the
//! instance's solid. For every row of cells along x that meets the
//! instance's bounding box, one line through the row's centres is
//! intersected with the solid (in the solid's local frame): analytically for
//! convex solids, through the BVH for other meshes. The sorted crossings,
//! taken in pairs, give spans `[a, b)`; the cells whose centres lie in a span
//! are inside.
//!
//! Open meshes have no inside; their cells follow the same rule: where a
//! row meets the surface an odd number of times, its last crossing opens no
//! span (a cell is inside iff an odd number of crossings lie at or before
//! its centre and at least one after it).
//!
//! Ties (centres exactly on the surface): along a row, spans are half-open
//! (`[enter, leave)`); a centre on a face parallel to the rows counts as
//! inside for convex solids; for other meshes, a line through an edge or a
//! vertex is counted by exactly one of the triangles around it. These cases
//! need exact alignment of the model with the lattice; random placements
//! never meet them in the tests.

use glam::{Affine3A, DAffine3, DMat3, DVec3};

use crate::grid::Grid;
use crate::solid::{Solid, solid_angle};

/// A run of inside cells: row `(y, z)` of the lattice, cells `x0..x1` (exclusive).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Span {
    /// Lattice row index along y (may lie outside the grid).
    pub y: i64,
    /// Lattice row index along z (may lie outside the grid).
    pub z: i64,
    /// First cell along x.
    pub x0: i64,
    /// One past the last cell along x.
    pub x1: i64,
}

/// Reusable working memory for voxelizing instances.
#[derive(Clone, Debug, Default)]
pub struct Voxelizer {
    crossings: Vec<f64>,
    planes: Vec<RowPlane>,
    signed: Vec<(f64, f64)>,
    cone: Vec<[DVec3; 3]>,
}

/// A convex solid's face plane, rewritten for the rows of one instance:
/// along row `(y, z)` the line is inside the plane for `t` with
/// `at + y·ay + z·az + t·nv <= d`.
#[derive(Clone, Copy, Debug)]
struct RowPlane {
    at: f64,
    ay: f64,
    az: f64,
    nv: f64,
    d: f64,
}

fn row_planes(c: &crate::solid::Convex, r: &Rows, out: &mut Vec<RowPlane>) {
    out.clear();
    out.extend(c.planes().iter().map(|&(n, d)| RowPlane {
        at: n.dot(r.o0),
        ay: n.dot(r.ey),
        az: n.dot(r.ez),
        nv: n.dot(r.dir),
        d,
    }));
}

/// The inside interval `[a, b) ∩ [0, len]` of row `(y, z)` for a convex solid.
#[inline]
fn convex_row(planes: &[RowPlane], y: f64, z: f64, len: f64) -> Option<(f64, f64)> {
    let (mut a, mut b) = (0.0f64, len);
    for p in planes {
        let no = p.at + y * p.ay + z * p.az;
        if p.nv == 0.0 {
            if no > p.d {
                return None;
            }
        } else {
            let t = (p.d - no) / p.nv;
            if p.nv > 0.0 {
                b = b.min(t)
            } else {
                a = a.max(t)
            }
        }
    }
    (a < b).then_some((a, b))
}

/// The rows an instance covers, and how to cast along them.
struct Rows {
    /// Local position of the world point `(x_start, 0, 0)`, and local images
    /// of the world y and z axes: the line of row `(Y, Z)` starts at
    /// `o0 + Y·ey + Z·ez` (world centres `Y`, `Z`).
    o0: DVec3,
    ey: DVec3,
    ez: DVec3,
    /// Local direction of world +x.
    dir: DVec3,
    /// World x where each row's line starts, and its length.
    x_start: f64,
    len: f64,
    y: std::ops::Range<i64>,
    z: std::ops::Range<i64>,
}

/// The instance's transform in `f64` and the world box around its placed
/// local bounding box; `None` for a singular or non-finite transform.
pub(crate) fn placed_box(solid: &Solid, transform: &Affine3A) -> Option<(DAffine3, DVec3, DVec3)> {
    let to_world = to_f64(transform);
    if to_world.matrix3.determinant() == 0.0
        || !to_world.matrix3.is_finite()
        || !to_world.translation.is_finite()
    {
        return None;
    }
    let (lo, hi) = solid.bounds();
    let (mut wlo, mut whi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    for i in 0..8 {
        let corner = DVec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        );
        let w = to_world.transform_point3(corner);
        wlo = wlo.min(w);
        whi = whi.max(w);
    }
    Some((to_world, wlo, whi))
}

fn rows(grid: &Grid, solid: &Solid, transform: &Affine3A) -> Option<Rows> {
    let (to_world, wlo, whi) = placed_box(solid, transform)?;
    let inv = to_world.inverse();
    let cell = grid.cell_size();
    let x_start = wlo.x - cell.x;
    Some(Rows {
        o0: inv.transform_point3(DVec3::new(x_start, 0.0, 0.0)),
        ey: inv.matrix3 * DVec3::Y,
        ez: inv.matrix3 * DVec3::Z,
        dir: inv.matrix3 * DVec3::X,
        x_start,
        len: (whi.x - wlo.x) + 2.0 * cell.x,
        // Rows beyond one grid size outside are not walked (see Grid::walkable).
        y: grid.clamp_walk(1, grid.centres_in(1, wlo.y, whi.y)),
        z: grid.clamp_walk(2, grid.centres_in(2, wlo.z, whi.z)),
    })
}

impl Rows {
    /// The cells along x that every row of the instance looks at.
    fn x_cells(&self, grid: &Grid) -> std::ops::Range<i64> {
        grid.clamp_walk(
            0,
            grid.first_at_or_after(0, self.x_start)
                ..grid.first_at_or_after(0, self.x_start + self.len) + 1,
        )
    }

    /// Local start of the line of row `(y, z)` (world centre coordinates).
    #[inline]
    fn origin(&self, y: f64, z: f64) -> DVec3 {
        self.o0 + y * self.ey + z * self.ez
    }
}

/// The same transform in `f64`.
pub(crate) fn to_f64(a: &Affine3A) -> DAffine3 {
    DAffine3 {
        matrix3: DMat3::from_cols(
            a.matrix3.x_axis.as_dvec3(),
            a.matrix3.y_axis.as_dvec3(),
            a.matrix3.z_axis.as_dvec3(),
        ),
        translation: a.translation.as_dvec3(),
    }
}

impl Voxelizer {
    /// Empty working memory.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Calls `f` for every span of lattice cells inside `solid` placed by
    /// `transform` (local → world). Rows and cells outside the grid are
    /// reported too; an instance with a singular or non-finite transform has none.
    pub fn spans(
        &mut self,
        grid: &Grid,
        solid: &Solid,
        transform: &Affine3A,
        mut f: impl FnMut(Span),
    ) {
        let Some(r) = rows(grid, solid, transform) else {
            return;
        };
        if let Solid::Mesh(m) = solid
            && let Some(w) = m.winding()
        {
            self.winding_spans(grid, m, w, transform, &r, f);
            return;
        }
        if let Solid::Convex(c) = solid {
            row_planes(c, &r, &mut self.planes);
        }
        for z in r.z.clone() {
            let wz = grid.center_along(2, z);
            for y in r.y.clone() {
                let wy = grid.center_along(1, y);
                self.crossings.clear();
                match solid {
                    Solid::Convex(_) => {
                        if let Some((a, b)) = convex_row(&self.planes, wy, wz, r.len) {
                            self.crossings.extend([a, b]);
                        }
                    }
                    Solid::Mesh(m) => {
                        m.crossings(r.origin(wy, wz), r.dir, r.len, &mut self.crossings)
                    }
                }
                for pair in self.crossings.chunks_exact(2) {
                    let x0 = grid.first_at_or_after(0, r.x_start + pair[0]);
                    let x1 = grid.first_at_or_after(0, r.x_start + pair[1]);
                    if x0 < x1 {
                        f(Span { y, z, x0, x1 });
                    }
                }
            }
        }
    }
}

impl Voxelizer {
    /// [`Inside::WindingNumber`](crate::solid::Inside) spans: cell by cell
    /// along each row of the instance's bounding box, `w = −σ Σ s` over the
    /// signed crossings at or before the centre (`σ` the sign of the
    /// transform's determinant: crossings are found in the local frame)
    /// minus the reversed cone's solid angles over `4π` (in the world
    /// frame); inside iff `|w| ≥ ½`.
    fn winding_spans(
        &mut self,
        grid: &Grid,
        m: &crate::solid::MeshSolid,
        w: &crate::solid::Winding,
        transform: &Affine3A,
        r: &Rows,
        mut f: impl FnMut(Span),
    ) {
        let to_world = to_f64(transform);
        let sigma = to_world.matrix3.determinant().signum();
        self.cone.clear();
        self.cone.extend(
            w.reversed_cone()
                .iter()
                .map(|t| t.map(|p| to_world.transform_point3(p))),
        );
        let std::ops::Range {
            start: x_begin,
            end: x_end,
        } = r.x_cells(grid);
        for z in r.z.clone() {
            let wz = grid.center_along(2, z);
            for y in r.y.clone() {
                let wy = grid.center_along(1, y);
                self.signed.clear();
                m.signed_crossings(r.origin(wy, wz), r.dir, r.len, &mut self.signed);
                let (mut k, mut count) = (0, 0.0);
                let mut open = None;
                for x in x_begin..x_end {
                    let xc = grid.center_along(0, x);
                    while k < self.signed.len() && r.x_start + self.signed[k].0 <= xc {
                        count += self.signed[k].1;
                        k += 1;
                    }
                    let p = DVec3::new(xc, wy, wz);
                    let cone: f64 = self.cone.iter().map(|t| solid_angle(t, p)).sum();
                    let wn = -sigma * count - cone / (4.0 * std::f64::consts::PI);
                    match (wn.abs() >= 0.5, open) {
                        (true, None) => open = Some(x),
                        (false, Some(x0)) => {
                            f(Span { y, z, x0, x1: x });
                            open = None;
                        }
                        _ => {}
                    }
                }
                if let Some(x0) = open {
                    f(Span {
                        y,
                        z,
                        x0,
                        x1: x_end,
                    });
                }
            }
        }
    }
}

/// Slow reference implementations, for tests and debugging.
pub mod reference {
    use glam::{Affine3A, IVec3};

    use super::{convex_row, row_planes, rows};
    use crate::grid::Grid;
    use crate::solid::Solid;

    /// The parity rule at world `xc` on a row whose line starts at world
    /// `x_start` (module docs): an odd number of the `crossings` at or
    /// before it, and one after.
    fn inside_by_parity(crossings: &[f64], x_start: f64, xc: f64) -> bool {
        let before = crossings.iter().filter(|&&t| x_start + t <= xc).count();
        before % 2 == 1 && before < crossings.len()
    }

    /// Every lattice cell inside the instance, decided cell by cell: the
    /// crossings of the cell's row line with *every* triangle (no BVH, no
    /// spans) are counted up to the cell's centre, which is inside iff the
    /// count is odd and some crossing lies beyond (the rule for open meshes
    /// in the module docs). Same line and tie rule as
    /// [`Voxelizer`](super::Voxelizer).
    #[must_use]
    pub fn cells_by_parity(grid: &Grid, solid: &Solid, transform: &Affine3A) -> Vec<IVec3> {
        let Some(r) = rows(grid, solid, transform) else {
            return Vec::new();
        };
        let std::ops::Range {
            start: x_begin,
            end: x_end,
        } = r.x_cells(grid);
        let mut out = Vec::new();
        let mut crossings = Vec::new();
        let mut planes = Vec::new();
        for z in r.z.clone() {
            for y in r.y.clone() {
                for x in x_begin..x_end {
                    let (wy, wz) = (grid.center_along(1, y), grid.center_along(2, z));
                    crossings.clear();
                    match solid {
                        Solid::Convex(c) => {
                            row_planes(c, &r, &mut planes);
                            if let Some((a, b)) = convex_row(&planes, wy, wz, r.len) {
                                crossings.extend([a, b]);
                            }
                        }
                        Solid::Mesh(m) => {
                            m.crossings_brute_force(r.origin(wy, wz), r.dir, &mut crossings)
                        }
                    }
                    let xc = grid.center_along(0, x);
                    if inside_by_parity(&crossings, r.x_start, xc) {
                        out.push(IVec3::new(x as i32, y as i32, z as i32));
                    }
                }
            }
        }
        out
    }

    /// The cells of [`cells_by_parity`] for a mesh solid, restricted to the
    /// rows `z_rows` (world z cell indices), computing each row's crossings
    /// with every triangle once instead of once per cell: still no BVH and
    /// no span filling, and affordable at 128³ for meshes of ~10⁵ triangles
    /// (callers split the rows across threads). Convex solids give nothing.
    #[must_use]
    pub fn mesh_cells_by_row_parity(
        grid: &Grid,
        solid: &Solid,
        transform: &Affine3A,
        z_rows: std::ops::Range<i64>,
    ) -> Vec<IVec3> {
        let (Solid::Mesh(m), Some(r)) = (solid, rows(grid, solid, transform)) else {
            return Vec::new();
        };
        let std::ops::Range {
            start: x_begin,
            end: x_end,
        } = r.x_cells(grid);
        let mut out = Vec::new();
        let mut crossings = Vec::new();
        let z_rows = r.z.start.max(z_rows.start)..r.z.end.min(z_rows.end);
        for z in z_rows {
            for y in r.y.clone() {
                let (wy, wz) = (grid.center_along(1, y), grid.center_along(2, z));
                crossings.clear();
                m.crossings_brute_force(r.origin(wy, wz), r.dir, &mut crossings);
                for x in x_begin..x_end {
                    let xc = grid.center_along(0, x);
                    if inside_by_parity(&crossings, r.x_start, xc) {
                        out.push(IVec3::new(x as i32, y as i32, z as i32));
                    }
                }
            }
        }
        out
    }

    /// The generalized winding number of every cell of the instance's row
    /// box (the cells [`Voxelizer::spans`](super::Voxelizer::spans) looks
    /// at), summing the solid angles of *every* triangle of a mesh solid in
    /// the world frame: no crossings, no cone. Convex solids give nothing.
    #[must_use]
    pub fn winding_numbers(grid: &Grid, solid: &Solid, transform: &Affine3A) -> Vec<(IVec3, f64)> {
        let (Solid::Mesh(m), Some(r)) = (solid, rows(grid, solid, transform)) else {
            return Vec::new();
        };
        let to_world = super::to_f64(transform);
        let tris: Vec<[glam::DVec3; 3]> = m
            .triangles()
            .map(|t| t.map(|p| to_world.transform_point3(p)))
            .collect();
        let std::ops::Range {
            start: x_begin,
            end: x_end,
        } = r.x_cells(grid);
        let mut out = Vec::new();
        for z in r.z.clone() {
            for y in r.y.clone() {
                for x in x_begin..x_end {
                    let p = glam::DVec3::new(
                        grid.center_along(0, x),
                        grid.center_along(1, y),
                        grid.center_along(2, z),
                    );
                    let w: f64 = tris.iter().map(|t| crate::solid::solid_angle(t, p)).sum();
                    out.push((
                        IVec3::new(x as i32, y as i32, z as i32),
                        w / (4.0 * std::f64::consts::PI),
                    ));
                }
            }
        }
        out
    }

    /// Every lattice cell whose centre, mapped to the solid's local frame,
    /// satisfies every face plane: an independent test for convex solids
    /// (it can differ from the span rule only for centres on the surface).
    #[must_use]
    pub fn cells_by_planes(grid: &Grid, solid: &Solid, transform: &Affine3A) -> Vec<IVec3> {
        let Solid::Convex(c) = solid else {
            return Vec::new();
        };
        let Some(r) = rows(grid, solid, transform) else {
            return Vec::new();
        };
        let inv = super::to_f64(transform).inverse();
        let std::ops::Range {
            start: x_begin,
            end: x_end,
        } = r.x_cells(grid);
        let mut out = Vec::new();
        for z in r.z.clone() {
            for y in r.y.clone() {
                for x in x_begin..x_end {
                    let cell = IVec3::new(x as i32, y as i32, z as i32);
                    if c.contains(inv.transform_point3(grid.center(cell))) {
                        out.push(cell);
                    }
                }
            }
        }
        out
    }
}
