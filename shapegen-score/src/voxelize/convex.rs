//! Convex solids: each row's inside interval straight from the face planes.

use super::{Rows, Span, Voxelizer};
use crate::grid::Grid;
use crate::solid::Convex;

/// A convex solid's face plane, rewritten for the rows of one instance:
/// along row `(y, z)` the line is inside the plane for `t` with
/// `at + y·ay + z·az + t·nv <= d`; `inv = 1 / nv`.
#[derive(Clone, Copy, Debug)]
pub(super) struct RowPlane {
    at: f64,
    ay: f64,
    az: f64,
    nv: f64,
    inv: f64,
    d: f64,
}

/// The face planes of `c`, in the row frame of `r`.
pub(super) fn row_planes(c: &Convex, r: &Rows, out: &mut Vec<RowPlane>) {
    out.clear();
    out.extend(c.planes().iter().map(|&(n, d)| RowPlane {
        at: n.dot(r.o0),
        ay: n.dot(r.ey),
        az: n.dot(r.ez),
        nv: n.dot(r.dir),
        inv: 1.0 / n.dot(r.dir),
        d,
    }));
}

/// The inside interval `[a, b) ∩ [0, len]` of row `(y, z)` for a convex
/// solid. Stops at the first plane that empties it (most rows of a thin,
/// slanted solid's box miss it).
#[inline]
pub(super) fn convex_row(planes: &[RowPlane], y: f64, z: f64, len: f64) -> Option<(f64, f64)> {
    let (mut a, mut b) = (0.0f64, len);
    for p in planes {
        let no = p.at + y * p.ay + z * p.az;
        if p.nv == 0.0 {
            if no > p.d {
                return None;
            }
        } else {
            let t = (p.d - no) * p.inv;
            if p.nv > 0.0 {
                b = b.min(t)
            } else {
                a = a.max(t)
            }
            if a >= b {
                return None;
            }
        }
    }
    (a < b).then_some((a, b))
}

impl Voxelizer {
    /// The spans of a convex solid: one interval per row of its box.
    pub(super) fn convex_spans(
        &mut self,
        grid: &Grid,
        c: &Convex,
        r: &Rows,
        mut f: impl FnMut(Span),
    ) {
        row_planes(c, r, &mut self.planes);
        let x_walk = grid.walkable(0);
        let cells = |(a, b): (f64, f64)| {
            let x0 = grid.first_at_or_after(0, r.x_start + a).max(x_walk.start);
            let x1 = grid.first_at_or_after(0, r.x_start + b).min(x_walk.end);
            (x0, x1)
        };
        // When every plane the rows cross has its normal along x (a box
        // placed without rotation), each cuts every row at the same t, so
        // [`convex_row`] gives every row the same interval or none: it is
        // computed once, and each row only checks the planes parallel to it.
        if self
            .planes
            .iter()
            .all(|p| p.nv == 0.0 || (p.ay == 0.0 && p.az == 0.0))
        {
            let (mut a, mut b) = (0.0f64, r.len);
            for p in self.planes.iter().filter(|p| p.nv != 0.0) {
                let t = (p.d - p.at) * p.inv;
                if p.nv > 0.0 {
                    b = b.min(t)
                } else {
                    a = a.max(t)
                }
            }
            let (x0, x1) = cells((a, b));
            if a.partial_cmp(&b) != Some(std::cmp::Ordering::Less) || x0 >= x1 {
                return;
            }
            // A plane parallel to x whose normal has no z (or no y)
            // component tests y (or z) alone: `wz * 0.0` adds a zero, so
            // the test of a row is the same number either way. Then each
            // y and each z is tested once, not each row.
            let parallel = || self.planes.iter().filter(|p| p.nv == 0.0);
            if parallel().all(|p| p.ay == 0.0 || p.az == 0.0) {
                self.rows_in.clear();
                self.rows_in.extend(r.y.clone().map(|y| {
                    let wy = grid.center_along(1, y);
                    parallel()
                        .filter(|p| p.az == 0.0)
                        .all(|p| p.at + wy * p.ay <= p.d)
                }));
                for z in r.z.clone() {
                    let wz = grid.center_along(2, z);
                    let z_in = parallel()
                        .filter(|p| p.az != 0.0)
                        .all(|p| p.at + wz * p.az <= p.d);
                    if !z_in {
                        continue;
                    }
                    for (y, &y_in) in r.y.clone().zip(&self.rows_in) {
                        if y_in {
                            f(Span { y, z, x0, x1 });
                        }
                    }
                }
                return;
            }
            for z in r.z.clone() {
                let wz = grid.center_along(2, z);
                for y in r.y.clone() {
                    let wy = grid.center_along(1, y);
                    let inside = self
                        .planes
                        .iter()
                        .filter(|p| p.nv == 0.0)
                        .all(|p| p.at + wy * p.ay + wz * p.az <= p.d);
                    if inside {
                        f(Span { y, z, x0, x1 });
                    }
                }
            }
            return;
        }
        for z in r.z.clone() {
            let wz = grid.center_along(2, z);
            for y in r.y.clone() {
                let wy = grid.center_along(1, y);
                if let Some(ab) = convex_row(&self.planes, wy, wz, r.len) {
                    let (x0, x1) = cells(ab);
                    if x0 < x1 {
                        f(Span { y, z, x0, x1 });
                    }
                }
            }
        }
    }
}
