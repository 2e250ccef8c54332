//! Convex solids: each row's inside interval straight from the face planes.

use glam::DVec3;

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
    out.extend(c.planes().iter().map(|&p| RowPlane::new(p, r)));
}

impl RowPlane {
    /// The face plane `n · p <= d` in the row frame of `r`.
    #[inline]
    fn new((n, d): (DVec3, f64), r: &Rows) -> Self {
        Self {
            at: n.dot(r.o0),
            ay: n.dot(r.ey),
            az: n.dot(r.ez),
            nv: n.dot(r.dir),
            inv: 1.0 / n.dot(r.dir),
            d,
        }
    }
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

/// An instance's [`RowPlane`]s sorted by what they bound along a row: its
/// start (`nv < 0`), its end (`nv > 0`), or neither (parallel to the rows).
#[derive(Clone, Debug, Default)]
pub(super) struct SplitPlanes {
    starts: Vec<RowPlane>,
    ends: Vec<RowPlane>,
    parallel: Vec<RowPlane>,
}

impl SplitPlanes {
    /// Takes the face planes of `c` in the row frame of `r`, sorted.
    pub(super) fn fill(&mut self, c: &Convex, r: &Rows) {
        self.clear();
        for &p in c.planes() {
            self.push(RowPlane::new(p, r));
        }
    }

    /// Takes `planes`, sorted.
    #[cfg(test)]
    fn take(&mut self, planes: &[RowPlane]) {
        self.clear();
        for &p in planes {
            self.push(p);
        }
    }

    fn clear(&mut self) {
        self.starts.clear();
        self.ends.clear();
        self.parallel.clear();
    }

    /// Adds `p` to the planes of its kind.
    #[inline]
    fn push(&mut self, p: RowPlane) {
        if p.nv > 0.0 {
            self.ends.push(p);
        } else if p.nv < 0.0 {
            self.starts.push(p);
        } else {
            self.parallel.push(p);
        }
    }

    /// [`convex_row`] of `N` rows at once (at `y[i]` and `z`), each plane
    /// read once for all, with the same results bit for bit: every plane
    /// evaluated, without a branch (most rows of a slanted solid's box miss
    /// it after an unpredictable number of planes), the start's maximum
    /// and the end's minimum taken apart. A maximum or minimum is exact in
    /// any order, and a NaN `t` (a plane nearly parallel to the rows, met
    /// exactly) is skipped as `f64::max` skips it.
    #[inline]
    pub(super) fn rows<const N: usize>(
        &self,
        y: [f64; N],
        z: f64,
        len: f64,
    ) -> [Option<(f64, f64)>; N] {
        let no = |p: &RowPlane| y.map(|y| p.at + y * p.ay + z * p.az);
        let t = |p: &RowPlane| no(p).map(|no| (p.d - no) * p.inv);
        let mut a = [0.0f64; N];
        for p in &self.starts {
            for (a, t) in a.iter_mut().zip(t(p)) {
                *a = if t > *a { t } else { *a };
            }
        }
        let mut b = [len; N];
        for p in &self.ends {
            for (b, t) in b.iter_mut().zip(t(p)) {
                *b = if t < *b { t } else { *b };
            }
        }
        let mut outside = [false; N];
        for p in &self.parallel {
            for (o, no) in outside.iter_mut().zip(no(p)) {
                *o |= no > p.d;
            }
        }
        std::array::from_fn(|i| (!outside[i] && a[i] < b[i]).then_some((a[i], b[i])))
    }
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
        self.split.fill(c, r);
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
        let split = &self.split;
        if split
            .starts
            .iter()
            .chain(&split.ends)
            .all(|p| p.ay == 0.0 && p.az == 0.0)
        {
            let (mut a, mut b) = (0.0f64, r.len);
            for p in &split.starts {
                a = a.max((p.d - p.at) * p.inv);
            }
            for p in &split.ends {
                b = b.min((p.d - p.at) * p.inv);
            }
            let (x0, x1) = cells((a, b));
            if a.partial_cmp(&b) != Some(std::cmp::Ordering::Less) || x0 >= x1 {
                return;
            }
            // A plane parallel to x whose normal has no z (or no y)
            // component tests y (or z) alone: `wz * 0.0` adds a zero, so
            // the test of a row is the same number either way. Then each
            // y and each z is tested once, not each row.
            let parallel = || split.parallel.iter();
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
                    let inside = split
                        .parallel
                        .iter()
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
            let mut emit = |y: i64, row: Option<(f64, f64)>| {
                if let Some(ab) = row {
                    let (x0, x1) = cells(ab);
                    if x0 < x1 {
                        f(Span { y, z, x0, x1 });
                    }
                }
            };
            let mut y = r.y.start;
            while y + 1 < r.y.end {
                let wy = [grid.center_along(1, y), grid.center_along(1, y + 1)];
                let [first, second] = split.rows(wy, wz, r.len);
                emit(y, first);
                emit(y + 1, second);
                y += 2;
            }
            if y < r.y.end {
                let [row] = split.rows([grid.center_along(1, y)], wz, r.len);
                emit(y, row);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;

    /// A plane with whole or fractional coefficients, a sixth of them
    /// parallel to the rows, some nearly so (`inv` huge or infinite).
    fn plane() -> impl Strategy<Value = RowPlane> {
        let c = || prop_oneof![(-4i32..5).prop_map(f64::from), -3.0..3.0f64];
        let nv = prop_oneof![
            Just(0.0),
            (-4i32..5).prop_map(f64::from),
            -3.0..3.0f64,
            Just(1e-310),
            Just(-1e-300)
        ];
        (c(), c(), c(), nv, c()).prop_map(|(at, ay, az, nv, d)| RowPlane {
            at,
            ay,
            az,
            nv,
            inv: 1.0 / nv,
            d,
        })
    }

    proptest! {
        /// The split planes give [`convex_row`]'s interval bit for bit,
        /// one row or two at a time, on rows on and off the planes.
        #[test]
        fn split_rows_equal_convex_row(
            planes in prop::collection::vec(plane(), 0..20),
            y in prop::array::uniform2(prop_oneof![(-8i32..9).prop_map(|i| f64::from(i) / 2.0), -5.0..5.0f64]),
            z in prop_oneof![(-8i32..9).prop_map(|i| f64::from(i) / 2.0), -5.0..5.0f64],
            len in prop_oneof![Just(4.0), 0.1..10.0f64],
        ) {
            let mut split = SplitPlanes::default();
            split.take(&planes);
            let bits = |r: Option<(f64, f64)>| r.map(|(a, b)| ((a + 0.0).to_bits(), (b + 0.0).to_bits()));
            let expected = y.map(|y| bits(convex_row(&planes, y, z, len)));
            prop_assert_eq!(bits(split.rows([y[0]], z, len)[0]), expected[0]);
            prop_assert_eq!(split.rows(y, z, len).map(bits), expected);
        }
    }
}
