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
                // A row far from every cluster is decided by its crossings
                // alone (see `row_slack`).
                let by_crossings = !x_cells.is_empty() && {
                    let ends = [x_cells.start, x_cells.end - 1].map(|x| grid.center_along(0, x));
                    row_slack(&self.clusters, ends, wy, wz).is_some_and(|s| s < 0.5)
                };
                let (mut k, mut count) = (0, 0.0);
                let mut open = None;
                for x in x_cells.clone() {
                    while k < crossings.len() && keys.cell_of(crossings[k]) <= x {
                        count += RowKeys::sign_of(crossings[k]);
                        k += 1;
                    }
                    let inside = if by_crossings {
                        count != 0.0
                    } else {
                        let p = DVec3::new(grid.center_along(0, x), wy, wz);
                        decide(-count, &self.cone, &self.clusters, p)
                    };
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

/// Whether a cluster is far from a point at squared distance `d_sq` from
/// its centre: then its solid angle there is bounded by [`far_bound`].
#[inline]
fn is_far(c: &Cluster, d_sq: f64) -> bool {
    d_sq > c.radius_sq * 1.000_001
}

/// The bound on `|Ω / 4π|` of far cluster `c` at squared distance `d_sq`
/// (module docs). Every step is monotone, so in floating point too a
/// larger `d_sq` never gives a larger bound.
#[inline]
fn far_bound(c: &Cluster, d_sq: f64) -> f64 {
    let n = c.tris.len() as f64;
    let gap = d_sq.sqrt() - c.radius;
    let cap = n / 2.0 * (1.0 - (1.0 - c.radius_sq / d_sq).sqrt());
    cap.min(c.area / (gap * gap))
}

/// The summed bounds widened for their own rounding, far below any tie the
/// tests allow.
#[inline]
fn widened(slack: f64) -> f64 {
    slack * (1.0 + 1e-9) + 1e-12
}

/// The cone's bound for every cell of a row at once: the row's cell
/// centres run from `x[0]` to `x[1]` at `(y, z)`; `None` if a cluster is
/// near some of them. Each cluster's distance is taken to the nearest
/// point of that segment, at most its distance to any centre (the same
/// squared differences, each no larger), so the bound holds for every cell
/// and is at least the one [`decide`] sums there. When it is below ½, every
/// cell's `|w|` is its crossings' count within less than ½ of it, and
/// `decide` concludes from its bounds exactly as the count alone does:
/// inside iff the count is not 0.
fn row_slack(clusters: &[Cluster], x: [f64; 2], y: f64, z: f64) -> Option<f64> {
    let mut slack = 0.0;
    for c in clusters {
        let nearest = DVec3::new(c.centre.x.clamp(x[0], x[1]), y, z);
        let d_sq = nearest.distance_squared(c.centre);
        if !is_far(c, d_sq) {
            return None;
        }
        slack += far_bound(c, d_sq);
    }
    Some(widened(slack))
}

/// Whether `|base − Σ_cone Ω(p) / 4π| ≥ ½`, summing the solid angles of
/// the clusters near `p` and bounding the far ones (module docs).
fn decide(base: f64, cone: &[[DVec3; 3]], clusters: &[Cluster], p: DVec3) -> bool {
    let quarter_turns = 4.0 * std::f64::consts::PI;
    let (mut w, mut slack) = (base, 0.0);
    let mut far = false;
    for c in clusters {
        let d_sq = p.distance_squared(c.centre);
        if is_far(c, d_sq) {
            slack += far_bound(c, d_sq);
            far = true;
        } else {
            w -= cone[c.tris.clone()]
                .iter()
                .map(|t| solid_angle(t, p))
                .sum::<f64>()
                / quarter_turns;
        }
    }
    let slack = widened(slack);
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
        if is_far(c, p.distance_squared(c.centre)) {
            w -= cone[c.tris.clone()]
                .iter()
                .map(|t| solid_angle(t, p))
                .sum::<f64>()
                / quarter_turns;
        }
    }
    w.abs() >= 0.5
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;

    /// A coordinate on a coarse lattice or anywhere (clusters touching the
    /// rows, rows through cluster centres).
    fn coordinate() -> impl Strategy<Value = f64> {
        prop_oneof![(-6i32..7).prop_map(|i| f64::from(i) / 2.0), -3.0..3.0f64]
    }

    /// A UV sphere of radius `r` around `c` (`n` segments, `n` rings):
    /// from inside, its solid angle is a whole turn, though every cluster
    /// of its triangles may be far.
    fn sphere(c: DVec3, r: f64, n: usize) -> Vec<[DVec3; 3]> {
        let at = |i: usize, j: usize| {
            let (theta, phi) = (
                std::f64::consts::PI * i as f64 / n as f64,
                std::f64::consts::TAU * j as f64 / n as f64,
            );
            c + r * DVec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            )
        };
        let mut tris = Vec::new();
        for i in 0..n {
            for j in 0..n {
                let (a, b, cc, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                tris.push([a, b, cc]);
                tris.push([a, cc, d]);
            }
        }
        tris
    }

    proptest! {
        /// Where `row_slack` decides a row by its crossings, `decide`
        /// gives every cell of it the same answer for any crossing count:
        /// inside iff the count is not 0. Cones are random triangles at
        /// several scales, or spheres around a point of the row (whose
        /// whole turn no far cluster's bound may leave out).
        #[test]
        fn rows_decided_by_crossings_agree_with_decide(
            cone in prop::collection::vec(prop::array::uniform3(prop::array::uniform3(coordinate())), 1..40),
            ends in prop::array::uniform2(coordinate()),
            (y, z) in (coordinate(), coordinate()),
            scale in prop_oneof![Just(1.0), Just(0.05), 0.01..1.0f64],
            around in prop::option::of((0.0..1.0f64, 0.1..2.0f64, 16usize..24)),
            cells in 1usize..12,
        ) {
            let (x0, x1) = (ends[0].min(ends[1]), ends[0].max(ends[1]));
            let mut cone: Vec<[DVec3; 3]> = match around {
                // Far wider than the row, so that the row is inside it,
                // far from its clusters (of eight triangles: a sphere of
                // 2·16² triangles has 64 or more).
                Some((t, r, n)) => sphere(DVec3::new(x0 + t * (x1 - x0), y, z), 3.0 * (x1 - x0) + r, n),
                None => cone.iter().map(|t| t.map(|p| DVec3::from(p) * scale)).collect(),
            };
            let mut clusters = Vec::new();
            cluster(&mut cone, 0, &mut clusters);
            let Some(slack) = row_slack(&clusters, [x0, x1], y, z) else {
                return Ok(());
            };
            if slack >= 0.5 {
                return Ok(());
            }
            for i in 0..cells {
                let t = if cells == 1 { 0.0 } else { i as f64 / (cells - 1) as f64 };
                let x = (x0 + t * (x1 - x0)).clamp(x0, x1);
                for count in [-2.0, -1.0, 0.0, 1.0, 2.0f64] {
                    let p = DVec3::new(x, y, z);
                    prop_assert_eq!(decide(-count, &cone, &clusters, p), count != 0.0);
                }
            }
        }
    }
}
