//! Slow reference implementations, for tests and debugging.

use glam::{Affine3A, DVec3, IVec3};

use super::convex::{convex_row, row_planes};
use super::{rows, to_f64};
use crate::grid::Grid;
use crate::solid::{MeshSolid, RowTri, Solid, solid_angle};

/// The parity rule at world `xc`: an odd number of the row's `crossings`
/// (world x) at or before it, and one after.
fn inside_by_parity(crossings: &[f64], xc: f64) -> bool {
    let before = crossings.iter().filter(|&&x| x <= xc).count();
    before % 2 == 1 && before < crossings.len()
}

/// The mesh's triangles in the world frame.
fn placed(m: &MeshSolid, transform: &Affine3A) -> Vec<RowTri> {
    let to_world = to_f64(transform);
    m.triangles()
        .map(|t| RowTri::new(t.map(|p| to_world.transform_point3(p))))
        .collect()
}

/// Every lattice cell inside the instance, decided cell by cell: the
/// crossings of the cell's row line with *every* placed triangle (no
/// rasterization, no spans) are counted up to the cell's centre, which is
/// inside iff the count is odd and some crossing lies beyond (the rule for
/// open meshes in the module docs). Convex solids: the row's interval from
/// the face planes, per cell. Same lines and tie rule as
/// [`Voxelizer`](super::Voxelizer).
#[must_use]
pub fn cells_by_parity(grid: &Grid, solid: &Solid, transform: &Affine3A) -> Vec<IVec3> {
    let Some(r) = rows(grid, solid, transform) else {
        return Vec::new();
    };
    let tris = match solid {
        Solid::Mesh(m) => placed(m, transform),
        Solid::Convex(_) => Vec::new(),
    };
    let mut out = Vec::new();
    let mut crossings = Vec::new();
    let mut planes = Vec::new();
    for z in r.z.clone() {
        for y in r.y.clone() {
            for x in r.x_cells(grid) {
                let (wy, wz) = (grid.center_along(1, y), grid.center_along(2, z));
                crossings.clear();
                match solid {
                    Solid::Convex(c) => {
                        row_planes(c, &r, &mut planes);
                        if let Some((a, b)) = convex_row(&planes, wy, wz, r.len) {
                            crossings.extend([r.x_start + a, r.x_start + b]);
                        }
                    }
                    Solid::Mesh(_) => crossings.extend(tris.iter().filter_map(|t| t.cross(wy, wz))),
                }
                if inside_by_parity(&crossings, grid.center_along(0, x)) {
                    out.push(IVec3::new(x as i32, y as i32, z as i32));
                }
            }
        }
    }
    out
}

/// The cells of [`cells_by_parity`] for a mesh solid, restricted to the
/// rows `z_rows` (world z cell indices), computing each row's crossings
/// with every triangle once instead of once per cell: still no
/// rasterization and no span filling, and affordable at 128³ for meshes of
/// ~10⁵ triangles (callers split the rows across threads). Convex solids
/// give nothing.
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
    let tris = placed(m, transform);
    let mut out = Vec::new();
    let mut crossings = Vec::new();
    for z in r.z.start.max(z_rows.start)..r.z.end.min(z_rows.end) {
        for y in r.y.clone() {
            let (wy, wz) = (grid.center_along(1, y), grid.center_along(2, z));
            crossings.clear();
            crossings.extend(tris.iter().filter_map(|t| t.cross(wy, wz)));
            for x in r.x_cells(grid) {
                if inside_by_parity(&crossings, grid.center_along(0, x)) {
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
    let to_world = to_f64(transform);
    let tris: Vec<[DVec3; 3]> = m
        .triangles()
        .map(|t| t.map(|p| to_world.transform_point3(p)))
        .collect();
    let mut out = Vec::new();
    for z in r.z.clone() {
        for y in r.y.clone() {
            for x in r.x_cells(grid) {
                let p = DVec3::new(
                    grid.center_along(0, x),
                    grid.center_along(1, y),
                    grid.center_along(2, z),
                );
                let w: f64 = tris.iter().map(|t| solid_angle(t, p)).sum();
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
    let inv = to_f64(transform).inverse();
    let mut out = Vec::new();
    for z in r.z.clone() {
        for y in r.y.clone() {
            for x in r.x_cells(grid) {
                let cell = IVec3::new(x as i32, y as i32, z as i32);
                if c.contains(inv.transform_point3(grid.center(cell))) {
                    out.push(cell);
                }
            }
        }
    }
    out
}
