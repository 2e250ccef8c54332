//! Solid voxelization with centre sampling, by row spans.
//!
//! A lattice cell is inside an instance iff its centre is inside the
//! instance's solid. The lattice's rows are the lines along x through the
//! cell centres `(y, z)`. Convex solids give each row of the instance's box
//! its interval analytically ([`convex`]). Other meshes are placed in the
//! world and rasterized by scanline ([`mesh`]): each triangle's projection
//! onto the yz plane gives the rows whose lines pierce it, the crossing's x
//! gives the first cell at or after it, and the crossings, counted into
//! their rows and sorted within each, come out in order; no acceleration
//! structure is built or walked. The
//! sorted crossings, taken in pairs, give spans `[a, b)`; the cells whose
//! centres lie in a span are inside. [`winding`] decides meshes with holes
//! by their generalized winding number instead.
//!
//! Open meshes have no inside; their cells follow the same rule: where a
//! row meets the surface an odd number of times, its last crossing opens no
//! span (a cell is inside iff an odd number of crossings lie at or before
//! its centre and at least one after it).
//!
//! Ties (centres exactly on the surface): along a row, spans are half-open
//! (`[enter, leave)`); a centre on a face parallel to the rows counts as
//! inside for convex solids and crosses nothing for other meshes; for other
//! meshes, a line through an edge or a vertex is counted by exactly one of
//! the triangles around it ([`RowTri`](crate::solid::RowTri)). These cases
//! need exact alignment of the model with the lattice; random placements
//! never meet them in the tests.
//!
//! Only the walkable part of the lattice ([`Grid::walkable`]: the grid and
//! one grid size beyond each face) is ever visited, so no geometry, however
//! far or large, costs more than the rows and cells of three grid sizes per
//! axis.

mod convex;
mod mesh;
pub mod reference;
mod winding;

use glam::{Affine3A, DAffine3, DMat3, DVec3};

use crate::grid::Grid;
use crate::solid::Solid;

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
    /// A convex instance's face planes, by what they bound along a row.
    split: convex::SplitPlanes,
    /// Which rows along y of a box lie inside its planes parallel to x.
    rows_in: Vec<bool>,
    /// The placed mesh: vertices, then triangles (with any cone).
    world: Vec<DVec3>,
    /// The placed vertices' candidate rows (see `mesh::VertexRows`).
    vertex_rows: Vec<mesh::VertexRows>,
    /// The placed mesh's edges (see `mesh::PlacedEdge`).
    edges: Vec<mesh::PlacedEdge>,
    tris: Vec<crate::solid::RowTri>,
    /// Crossings as found: the key without the cell, and x (see
    /// `mesh::RowKeys::rasterize`).
    hits: Vec<(u64, f64)>,
    /// The crossings packed (see `mesh::RowKeys`) and sorted; room to sort
    /// them by rows.
    keys: Vec<u64>,
    sorted: Vec<u64>,
    row_ends: Vec<u32>,
    /// Per row of a short box, the cells its crossings toggle and reach
    /// (see `mesh::Voxelizer::mask_spans`).
    masks: Vec<[u64; 2]>,
    /// The rows of the instance being voxelized (kept for their memory).
    row_keys: mesh::RowKeys,
    /// The placed winding cone and its clusters.
    cone: Vec<[DVec3; 3]>,
    clusters: Vec<winding::Cluster>,
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
    pub(crate) fn x_cells(&self, grid: &Grid) -> std::ops::Range<i64> {
        grid.clamp_walk(
            0,
            grid.first_at_or_after(0, self.x_start)
                ..grid.first_at_or_after(0, self.x_start + self.len) + 1,
        )
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
    /// `transform` (local → world). Spans are within the walkable lattice
    /// ([`Grid::walkable`]), so rows and cells outside the grid are reported
    /// too, up to one grid size beyond it; an instance with a singular or
    /// non-finite transform has none.
    pub fn spans(&mut self, grid: &Grid, solid: &Solid, transform: &Affine3A, f: impl FnMut(Span)) {
        let Some(r) = rows(grid, solid, transform) else {
            return;
        };
        match solid {
            Solid::Convex(c) => self.convex_spans(grid, c, &r, f),
            Solid::Mesh(m) => {
                let to_world = to_f64(transform);
                match m.winding() {
                    Some(w) => self.winding_spans(grid, m, w, &to_world, &r, f),
                    None => self.mesh_spans(grid, m, &to_world, &r, f),
                }
            }
        }
    }
}
