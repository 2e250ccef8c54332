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
        for z in r.z.clone() {
            let wz = grid.center_along(2, z);
            for y in r.y.clone() {
                let wy = grid.center_along(1, y);
                if let Some((a, b)) = convex_row(&self.planes, wy, wz, r.len) {
                    let x0 = grid.first_at_or_after(0, r.x_start + a).max(x_walk.start);
                    let x1 = grid.first_at_or_after(0, r.x_start + b).min(x_walk.end);
                    if x0 < x1 {
                        f(Span { y, z, x0, x1 });
                    }
                }
            }
        }
    }
}
