//! [`Inside::WindingNumber`](crate::solid::Inside) spans.
//!
//! Cell by cell along each row of the instance's box,
//! `w = −Σ s − Σ_cone Ω / 4π`: the signed crossings of the mesh and its
//! reversed boundary cones at or before the centre (found by the scanline of
//! [`mesh`](super::mesh), in the world frame), plus the cones' solid angles;
//! inside iff `|w| ≥ ½`.
//!
//! The solid angles need not be summed at every cell. The cone triangles are
//! grouped into small clusters, each inside a ball `(c, R)`. From distance
//! `D > R`, a triangle of area `A` inside the ball subtends at most
//! `A / (D − R)²` (the integrand of the solid angle is at most `1/d²`), and
//! as a planar triangle at most the ball's cap `2π (1 − √(1 − R²/D²))`; so
//! a far cluster of `n` triangles of total area `A` changes `w` by at most
//! `min(A / (D − R)², 2π n (1 − √(1 − R²/D²))) / 4π`. Where the exact part
//! plus these bounds cannot reach ½ from either side, the cell is decided
//! without the far clusters' angles; elsewhere they are summed too.

use glam::{DAffine3, DVec3};

use super::mesh::RowKeys;
use super::{Rows, Span, Voxelizer};
use crate::grid::Grid;
use crate::solid::{MeshSolid, RowTri, Winding, solid_angle};

/// Cone triangles per cluster, at most.
const CLUSTER: usize = 8;

/// A ball holding `tris` (indices into the placed cone).
#[derive(Clone, Debug)]
pub(super) struct Cluster {
    centre: DVec3,
    radius: f64,
    radius_sq: f64,
    /// The triangles' total area over `4π`.
    area: f64,
    tris: std::ops::Range<usize>,
}

/// Sorts `cone` into spatially coherent runs of at most [`CLUSTER`]
/// triangles (median splits along the widest axis) and appends their balls.
fn cluster(cone: &mut [[DVec3; 3]], offset: usize, out: &mut Vec<Cluster>) {
    if cone.len() > CLUSTER {
        let centroid = |t: &[DVec3; 3]| t[0] + t[1] + t[2];
        let (lo, hi) = cone
            .iter()
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), t| {
                (lo.min(centroid(t)), hi.max(centroid(t)))
            });
        let axis = (hi - lo).max_position();
        let mid = cone.len() / 2;
        cone.select_nth_unstable_by(mid, |a, b| centroid(a)[axis].total_cmp(&centroid(b)[axis]));
        let (left, right) = cone.split_at_mut(mid);
        cluster(left, offset, out);
        cluster(right, offset + mid, out);
        return;
    }
    let (lo, hi) = cone
        .iter()
        .flatten()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &p| {
            (lo.min(p), hi.max(p))
        });
    let centre = (lo + hi) / 2.0;
    let radius_sq = cone
        .iter()
        .flatten()
        .map(|p| p.distance_squared(centre))
        .fold(0.0, f64::max);
    let area: f64 = cone
        .iter()
        .map(|t| (t[1] - t[0]).cross(t[2] - t[0]).length() / 2.0)
        .sum();
    out.push(Cluster {
        centre,
        radius: radius_sq.sqrt(),
        radius_sq,
        area: area / (4.0 * std::f64::consts::PI),
        tris: offset..offset + cone.len(),
    });
}

impl Voxelizer {
    /// The winding-number spans of `m` placed by `to_world`, over the rows
    /// and cells of its box `r`.
    pub(super) fn winding_spans(
        &mut self,
        grid: &Grid,
        m: &MeshSolid,
        w: &Winding,
        to_world: &DAffine3,
        r: &Rows,
        mut f: impl FnMut(Span),
    ) {
        // The cone is placed once: its triangles cross the rows with the
        // mesh's, and its clusters bound the solid angles.
        self.place(m, to_world);
        self.cone.clear();
        self.cone.extend(
            w.reversed_cone()
                .iter()
                .map(|t| t.map(|p| to_world.transform_point3(p))),
        );
        self.tris.extend(self.cone.iter().map(|&t| RowTri::new(t)));
        let mut keys = std::mem::take(&mut self.row_keys);
        keys.fill(grid, r);
        let n = self.cross_triangles(grid, &keys);
        self.sort_crossings(grid, &keys, n);
        self.clusters.clear();
        cluster(&mut self.cone, 0, &mut self.clusters);
        let x_cells = r.x_cells(grid);
        let mut next = 0;
        for z in r.z.clone() {
            let wz = grid.center_along(2, z);
            for y in r.y.clone() {
                let wy = grid.center_along(1, y);
                let row = keys.row(y, z);
                while next < self.keys.len() && self.keys[next] & !0xffff_ffff < row {
                    next += 1;
                }
                let first = next;
                while next < self.keys.len() && self.keys[next] & !0xffff_ffff == row {
                    next += 1;
                }
                let crossings = &self.keys[first..next];
                let (mut k, mut count) = (0, 0.0);
                let mut open = None;
                for x in x_cells.clone() {
                    while k < crossings.len() && keys.cell_of(crossings[k]) <= x {
                        count += RowKeys::sign_of(crossings[k]);
                        k += 1;
                    }
                    let p = DVec3::new(grid.center_along(0, x), wy, wz);
                    let inside = decide(-count, &self.cone, &self.clusters, p);
                    match (inside, open) {
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
                        x1: x_cells.end,
                    });
                }
            }
        }
        self.row_keys = keys;
    }
}

/// Whether `|base − Σ_cone Ω(p) / 4π| ≥ ½`, summing the solid angles of
/// the clusters near `p` and bounding the far ones (module docs).
fn decide(base: f64, cone: &[[DVec3; 3]], clusters: &[Cluster], p: DVec3) -> bool {
    let quarter_turns = 4.0 * std::f64::consts::PI;
    let (mut w, mut slack) = (base, 0.0);
    let mut far = false;
    for c in clusters {
        let d_sq = p.distance_squared(c.centre);
        if d_sq > c.radius_sq * 1.000_001 {
            let n = c.tris.len() as f64;
            let gap = d_sq.sqrt() - c.radius;
            let cap = n / 2.0 * (1.0 - (1.0 - c.radius_sq / d_sq).sqrt());
            slack += cap.min(c.area / (gap * gap));
            far = true;
        } else {
            w -= cone[c.tris.clone()]
                .iter()
                .map(|t| solid_angle(t, p))
                .sum::<f64>()
                / quarter_turns;
        }
    }
    // Rounding of the bounds themselves, far below any tie the tests allow.
    let slack = slack * (1.0 + 1e-9) + 1e-12;
    if !far {
        return w.abs() >= 0.5;
    }
    if w.abs() - slack >= 0.5 {
        return true;
    }
    if w.abs() + slack < 0.5 {
        return false;
    }
    for c in clusters {
        if p.distance_squared(c.centre) > c.radius_sq * 1.000_001 {
            w -= cone[c.tris.clone()]
                .iter()
                .map(|t| solid_angle(t, p))
                .sum::<f64>()
                / quarter_turns;
        }
    }
    w.abs() >= 0.5
}
