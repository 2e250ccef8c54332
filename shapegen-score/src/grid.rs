//! [`Grid`]: a regular lattice of voxels over a box.

use glam::{DVec3, IVec3, UVec3, Vec3};

use crate::error::ScoreError;

/// `dims` cells over `[min, max]`. Cell `(i, j, k)` is centred at
/// `min + (i + ½, j + ½, k + ½) · Δ` with `Δ = (max − min) / dims`; the same
/// spacing continues outside the grid (the *lattice*), so cells of a model
/// outside the grid can be counted too.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    min: DVec3,
    max: DVec3,
    dims: UVec3,
    cell: DVec3,
    /// `1 / cell`, for first guesses.
    inv_cell: DVec3,
}

impl Grid {
    /// The most cells a grid may have (2^27 = 512³): a scene keeps about
    /// 0.7 GB of weights and flags for it (see `VolumeScene::bytes_needed`),
    /// plus 134 MB per worker thread's scratch.
    /// Experiments also check a grid against the memory the machine has.
    pub const MAX_CELLS: u64 = 1 << 27;

    /// A grid over `[min, max]` with `dims` cells per axis (anisotropic cells allowed).
    pub fn new(min: Vec3, max: Vec3, dims: UVec3) -> Result<Self, ScoreError> {
        let (min, max) = (min.as_dvec3(), max.as_dvec3());
        if !min.is_finite() || !max.is_finite() || min.cmpge(max).any() {
            return Err(ScoreError::Grid(format!(
                "bounds {min} .. {max} are empty or not finite"
            )));
        }
        if dims.cmpeq(UVec3::ZERO).any() || dims.as_u64vec3().element_product() > Self::MAX_CELLS {
            return Err(ScoreError::Grid(format!(
                "{} × {} × {} cells: each axis needs at least one, and at most 2^27 (512³, 134 million) in all; a scene keeps about 6 bytes a cell, and one scratch per worker thread 1 byte",
                dims.x, dims.y, dims.z
            )));
        }
        let cell = (max - min) / dims.as_dvec3();
        if !(cell.cmpgt(DVec3::splat(0.0)).all() && cell.is_finite())
            || (max - min).max_element() / cell.min_element() > 1e12
        {
            return Err(ScoreError::Grid(format!(
                "bounds {min} .. {max} give cells too small to tell apart"
            )));
        }
        Ok(Self {
            min,
            max,
            dims,
            cell,
            inv_cell: 1.0 / cell,
        })
    }

    /// A cubic grid of `n³` cells over `[min, max]`.
    pub fn cube(min: Vec3, max: Vec3, n: u32) -> Result<Self, ScoreError> {
        Self::new(min, max, UVec3::splat(n))
    }

    /// Cells per axis.
    #[must_use]
    pub fn dims(&self) -> UVec3 {
        self.dims
    }

    /// Number of cells.
    #[must_use]
    pub fn len(&self) -> usize {
        self.dims.as_u64vec3().element_product() as usize
    }

    /// Always false (a grid has at least one cell).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Lower corner.
    #[must_use]
    pub fn min(&self) -> DVec3 {
        self.min
    }

    /// Upper corner.
    #[must_use]
    pub fn max(&self) -> DVec3 {
        self.max
    }

    /// Cell size `Δ`.
    #[must_use]
    pub fn cell_size(&self) -> DVec3 {
        self.cell
    }

    /// `1 / cell size` along `axis`.
    #[inline]
    pub(crate) fn inv_cell(&self, axis: usize) -> f64 {
        self.inv_cell[axis]
    }

    /// Centre of lattice cell `c` (any integers, inside the grid or not).
    #[inline]
    #[must_use]
    pub fn center(&self, c: IVec3) -> DVec3 {
        self.min + (c.as_dvec3() + 0.5) * self.cell
    }

    /// Centre coordinate of lattice cell `i` along `axis`.
    #[inline]
    #[must_use]
    pub fn center_along(&self, axis: usize, i: i64) -> f64 {
        self.min[axis] + (i as f64 + 0.5) * self.cell[axis]
    }

    /// The first lattice index along `axis` whose centre is `>= x`, with the
    /// exact rule of [`center_along`](Self::center_along) (no rounding surprises).
    #[inline]
    #[must_use]
    pub fn first_at_or_after(&self, axis: usize, x: f64) -> i64 {
        // A first guess by rounding up (without a libm call); the loops make
        // it exact and almost never run. Points farther than 2^40 cells away
        // (or NaN) get the bound itself: no caller walks that far (see
        // `Grid::walkable`), and the loops could not end.
        let guess = (x - self.min[axis]) * self.inv_cell[axis] - 0.5;
        if guess.is_nan() || guess.abs() >= Self::FAR {
            return if guess > 0.0 {
                Self::FAR as i64
            } else if guess < 0.0 {
                -(Self::FAR as i64)
            } else {
                0
            };
        }
        let mut i = guess as i64;
        if (i as f64) < guess {
            i += 1;
        }
        while self.center_along(axis, i - 1) >= x {
            i -= 1;
        }
        while self.center_along(axis, i) < x {
            i += 1;
        }
        i
    }

    /// Lattice indices farther than this from the grid are clamped to it by
    /// [`first_at_or_after`](Self::first_at_or_after).
    const FAR: f64 = (1u64 << 40) as f64;

    /// The lattice indices along `axis` that a voxelizer walks: the grid and
    /// one grid size beyond each face. Cells outside the grid are counted
    /// (for the out-of-grid term) within this margin only, so no geometry,
    /// however large or far, costs more than three grid sizes per axis.
    #[must_use]
    pub fn walkable(&self, axis: usize) -> std::ops::Range<i64> {
        let d = i64::from(self.dims[axis]);
        -d..2 * d
    }

    /// `range` cut to [`walkable`](Self::walkable) along `axis`.
    #[must_use]
    pub fn clamp_walk(&self, axis: usize, range: std::ops::Range<i64>) -> std::ops::Range<i64> {
        let w = self.walkable(axis);
        let start = range.start.max(w.start);
        start..range.end.min(w.end).max(start)
    }

    /// The lattice indices along `axis` whose centres lie in `[lo, hi]`.
    #[must_use]
    pub fn centres_in(&self, axis: usize, lo: f64, hi: f64) -> std::ops::Range<i64> {
        let mut end = self.first_at_or_after(axis, hi);
        if self.center_along(axis, end) <= hi {
            end += 1;
        }
        self.first_at_or_after(axis, lo)..end
    }

    /// Whether lattice cell `c` is inside the grid.
    #[inline]
    #[must_use]
    pub fn contains(&self, c: IVec3) -> bool {
        c.cmpge(IVec3::ZERO).all() && c.as_uvec3().cmplt(self.dims).all()
    }

    /// Linear index of an in-grid cell (x fastest, then y, then z).
    #[inline]
    #[must_use]
    pub fn index(&self, c: UVec3) -> usize {
        (c.x + self.dims.x * (c.y + self.dims.y * c.z)) as usize
    }
}

/// The centres of a range of lattice indices along one axis, each exactly
/// [`Grid::center_along`], computed once for the many lookups of one
/// instance (the voxelizer's rows and crossings).
#[derive(Clone, Debug, Default)]
pub(crate) struct Centres {
    axis: usize,
    start: i64,
    centres: Vec<f64>,
}

impl Centres {
    /// Takes the centres of `range` along `axis` of `grid`.
    pub(crate) fn fill(&mut self, grid: &Grid, axis: usize, range: std::ops::Range<i64>) {
        self.axis = axis;
        self.start = range.start;
        self.centres.clear();
        self.centres
            .extend(range.map(|i| grid.center_along(axis, i)));
    }

    /// [`Grid::center_along`] of `i`, which must lie in the range.
    #[inline]
    pub(crate) fn at(&self, i: i64) -> f64 {
        self.centres[(i - self.start) as usize]
    }

    /// [`Grid::first_at_or_after`] of `x`: found in the table when the
    /// answer lies strictly inside the range (a centre before it is below
    /// `x`), else asked of the grid.
    #[inline(always)]
    pub(crate) fn first_at_or_after(&self, grid: &Grid, x: f64) -> i64 {
        let c = &self.centres;
        let g = (x - grid.min[self.axis]) * grid.inv_cell[self.axis] - 0.5 - self.start as f64;
        // The grid's own first guess, within the table (NaN fails too).
        // Signed conversions: an unsigned one takes several instructions.
        if !(g > 0.0 && g < c.len() as i64 as f64) {
            return grid.first_at_or_after(self.axis, x);
        }
        // Rounded up: 1 <= k <= len.
        let t = g as i64;
        let k = (t + i64::from((t as f64) < g)) as usize;
        // The answer when c[k − 1] < x <= c[k]: almost always, as the guess
        // is off by rounding alone; else (or at the table's end) the grid's
        // exact search.
        match (c.get(k - 1), c.get(k)) {
            (Some(&before), Some(&at)) if before < x && x <= at => self.start + k as i64,
            _ => grid.first_at_or_after(self.axis, x),
        }
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn far_points_are_clamped_and_walks_bounded() {
        let g = super::Grid::new(
            glam::Vec3::ZERO,
            glam::Vec3::splat(1.0),
            glam::UVec3::new(10, 20, 30),
        )
        .unwrap();
        // Beyond 2^40 cells: the bound, at once (the loops would never end).
        assert_eq!(g.first_at_or_after(0, 1e20), 1 << 40);
        assert_eq!(g.first_at_or_after(0, -1e20), -(1 << 40));
        assert_eq!(g.first_at_or_after(0, f64::NAN), 0);
        assert_eq!(g.first_at_or_after(0, 0.55), 5);
        // Walks stay within one grid size of the grid on each axis.
        assert_eq!(g.walkable(1), -20..40);
        assert_eq!(g.clamp_walk(2, -1000..5), -30..5);
        assert_eq!(g.clamp_walk(0, 5..1 << 40), 5..20);
        assert_eq!(g.clamp_walk(0, 100..200), 100..100);
        assert!(g.clamp_walk(0, -200..-100).is_empty());
    }

    use super::*;

    #[test]
    fn centres_and_first_index_agree_exactly() {
        let g = Grid::new(
            Vec3::new(-5.0, -5.0, -2.0),
            Vec3::new(5.0, 5.0, 18.0),
            UVec3::new(100, 200, 100),
        )
        .unwrap();
        assert!(
            (g.cell_size() - DVec3::new(0.1, 0.05, 0.2))
                .abs()
                .max_element()
                < 1e-12
        );
        assert_eq!(g.center(IVec3::ZERO), DVec3::new(-4.95, -4.975, -1.9));
        for x in [-5.0, -4.95, -4.9500001, 0.0, 0.05, 4.95, 7.0, -12.3] {
            let i = g.first_at_or_after(0, x);
            assert!(
                g.center_along(0, i) >= x && g.center_along(0, i - 1) < x,
                "{x}"
            );
        }
        assert!(Grid::new(Vec3::ONE, Vec3::ONE, UVec3::ONE).is_err());
        assert!(Grid::new(Vec3::ZERO, Vec3::ONE, UVec3::new(0, 1, 1)).is_err());
        assert!(Grid::new(Vec3::ZERO, Vec3::splat(f32::NAN), UVec3::ONE).is_err());
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig { cases: 4096, ..Default::default() })]
        /// The table's answers equal the grid's, for points on, next to,
        /// between and far from the centres, inside and outside the table's
        /// range, and for NaN and infinities.
        #[test]
        fn centres_answer_as_the_grid(
            dims in (1u32..300, 1u32..300),
            lo in -50.0f32..50.0,
            size in 0.01f32..100.0,
            range in (-400i64..400, 0i64..60),
            at in -3i64..63,
            how in 0usize..7,
            frac in 0.0f64..1.0,
        ) {
            let g = Grid::new(
                Vec3::new(lo, 0.0, 0.0),
                Vec3::new(lo + size, 1.0, 1.0),
                UVec3::new(dims.0, dims.1, 1),
            ).unwrap();
            let mut c = Centres::default();
            c.fill(&g, 0, range.0..range.0 + range.1);
            let centre = g.center_along(0, range.0 + at);
            let x = match how {
                0 => centre,
                1 => centre.next_up(),
                2 => centre.next_down(),
                3 => centre + frac * g.cell_size().x,
                4 => f64::NAN,
                5 => f64::INFINITY,
                _ => f64::NEG_INFINITY,
            };
            proptest::prop_assert_eq!(c.first_at_or_after(&g, x), g.first_at_or_after(0, x));
            for i in range.0..range.0 + range.1 {
                proptest::prop_assert_eq!(c.at(i).to_bits(), g.center_along(0, i).to_bits());
            }
        }
    }
}
