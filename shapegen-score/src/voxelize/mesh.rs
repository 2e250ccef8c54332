//! Mesh solids by scanline: every placed triangle is rasterized onto the
//! lattice rows whose centre lines pierce it, each crossing becomes the first
//! cell at or after it, and the packed `(row, cell)` keys, counted into
//! their rows and sorted within each, give every row's crossings in order. The cost is proportional to the
//! triangles' row footprints plus the crossings, whatever the mesh's shape.

use std::ops::Range;

use glam::{DAffine3, DVec3};

use super::{Rows, Span, Voxelizer};
use crate::grid::{Centres, Grid};
use crate::mesh::corners;
use crate::solid::{MeshSolid, RowFunctions, RowTri, row_edge};

/// An instance's rows (its box's, within the walkable lattice) and how a
/// crossing of one of them packs into a sortable `u64`: the row (z-major,
/// counted from the box's first) in the high 32 bits, then the cell (from
/// the walkable lattice's first), then the crossing's sign.
#[derive(Clone, Debug, Default)]
pub(super) struct RowKeys {
    x: Range<i64>,
    y: Range<i64>,
    z: Range<i64>,
    /// The centres of the box's cells along x, and of its rows along y.
    xs: Centres,
    ys: Centres,
}

/// Triangles up to this many rows wide along y test every row of their box
/// (cheaper than a cross-section per row for the small triangles of most
/// meshes).
const SECTION_ROWS: i64 = 8;

impl RowKeys {
    /// Takes the keys of the rows of box `r`.
    pub(super) fn fill(&mut self, grid: &Grid, r: &Rows) {
        self.x = grid.walkable(0);
        self.y = r.y.clone();
        self.z = r.z.clone();
        self.xs.fill(grid, 0, r.x_cells(grid));
        self.ys.fill(grid, 1, r.y.clone());
    }

    /// How many rows the box has.
    pub(super) fn rows(&self) -> usize {
        (self.y.end - self.y.start) as usize * (self.z.end - self.z.start) as usize
    }

    /// The key of row `(y, z)` (both in the box).
    #[inline]
    pub(super) fn row(&self, y: i64, z: i64) -> u64 {
        ((z - self.z.start) as u64 * (self.y.end - self.y.start) as u64 + (y - self.y.start) as u64)
            << 32
    }

    /// The row `(y, z)` of a key.
    #[inline]
    pub(super) fn row_of(&self, key: u64) -> (i64, i64) {
        let row = (key >> 32) as i64;
        let ny = self.y.end - self.y.start;
        (self.y.start + row % ny, self.z.start + row / ny)
    }

    /// The cell of a key: the first (walkable) cell at or after its crossing.
    #[inline]
    pub(super) fn cell_of(&self, key: u64) -> i64 {
        self.x.start + ((key & 0xffff_ffff) >> 1) as i64
    }

    /// The crossing's sign of a key: `+1` or `−1`.
    #[inline]
    pub(super) fn sign_of(key: u64) -> f64 {
        if key & 1 == 1 { 1.0 } else { -1.0 }
    }

    /// Writes every crossing of `t` with a walkable row to `hits` from
    /// index `n` on, as its key without the cell and its x; returns the new
    /// `n`. Candidate rows are written whether crossed or not and kept only
    /// if crossed (no branch on an outcome a third of the time true), so
    /// `hits` is grown to hold a line's candidates first.
    ///
    /// A triangle spanning more than [`SECTION_ROWS`] rows along y has,
    /// per row along z, its projection's cross-section give the candidate
    /// rows along y (one more on each side, against rounding); smaller ones
    /// test their whole box. [`RowLine::crossing`](crate::solid::RowLine::crossing) decides each candidate
    /// exactly, so the candidates only save work and never change a crossing.
    pub(super) fn rasterize(
        &self,
        grid: &Grid,
        t: &RowTri,
        hits: &mut Vec<(u64, f64)>,
        n: usize,
    ) -> usize {
        if t.parallel() {
            return n;
        }
        match self.candidates(grid, t.yz_bounds()) {
            Some((ys, zs)) => {
                let wide = (ys.end - ys.start > SECTION_ROWS).then_some(t);
                self.rasterize_rows(grid, &t.functions(), wide, (ys, zs), hits, n)
            }
            None => n,
        }
    }

    /// The candidate rows along y and z of a triangle whose projection
    /// has bounds `[y_lo, y_hi, z_lo, z_hi]`, if any.
    #[inline]
    fn candidates(&self, grid: &Grid, yz: [f64; 4]) -> Option<(Range<i64>, Range<i64>)> {
        let [y_lo, y_hi, z_lo, z_hi] = yz;
        // Rows beyond the box are never crossed (the reference looks at the
        // box's rows only, too).
        let ys = clamp(rows_between(grid, 1, y_lo, y_hi), &self.y);
        let zs = clamp(rows_between(grid, 2, z_lo, z_hi), &self.z);
        (!ys.is_empty() && !zs.is_empty()).then_some((ys, zs))
    }

    /// [`candidates`](Self::candidates) of the triangle whose vertices have
    /// rows `v` (the same rows: see [`VertexRows`]).
    #[inline]
    fn vertex_candidates(&self, v: [VertexRows; 3]) -> Option<(Range<i64>, Range<i64>)> {
        let [a, b, c] = v.map(|r| r.0);
        let between = |i: usize, rows: &Range<i64>| {
            let start = a[i].min(b[i]).min(c[i]).max(rows.start);
            start
                ..a[i + 1]
                    .max(b[i + 1])
                    .max(c[i + 1])
                    .saturating_add(1)
                    .min(rows.end)
        };
        let (ys, zs) = (between(0, &self.y), between(2, &self.z));
        (ys.start < ys.end && zs.start < zs.end).then_some((ys, zs))
    }

    /// [`rasterize`](Self::rasterize) over the candidate rows `ys` × `zs`
    /// of a triangle not parallel to the rows, with functions `t`; `wide`
    /// is the triangle if it spans more than [`SECTION_ROWS`] rows along y
    /// (for its cross-sections), else `None`.
    #[inline]
    fn rasterize_rows(
        &self,
        grid: &Grid,
        t: &RowFunctions,
        wide: Option<&RowTri>,
        (ys, zs): (Range<i64>, Range<i64>),
        hits: &mut Vec<(u64, f64)>,
        mut n: usize,
    ) -> usize {
        let sign = u64::from(t.sign() > 0.0);
        for z in zs {
            let cz = grid.center_along(2, z);
            let ys = if let Some(wide) = wide {
                let Some((lo, hi)) = wide.y_section(cz) else {
                    continue;
                };
                // One more row on each side: the section's ends are rounded.
                let r = rows_between(grid, 1, lo, hi);
                let start = (r.start - 1).max(ys.start);
                start..(r.end + 1).min(ys.end).max(start)
            } else {
                ys.clone()
            };
            let line = t.line(cz);
            let most = n + (ys.end - ys.start) as usize;
            if hits.len() < most {
                hits.resize(most.max(2 * hits.len()), (0, 0.0));
            }
            for y in ys {
                let (crossed, x) = line.crossing(self.ys.at(y));
                hits[n] = (self.row(y, z) | sign, x);
                n += usize::from(crossed);
            }
        }
        n
    }

    /// The key of a crossing at `x` of the row and sign in `prefix` (see
    /// [`rasterize`](Self::rasterize)).
    #[inline]
    pub(super) fn key(&self, grid: &Grid, (prefix, x): (u64, f64)) -> u64 {
        let cell = self
            .xs
            .first_at_or_after(grid, x)
            .clamp(self.x.start, self.x.end);
        prefix | ((cell - self.x.start) as u64) << 1
    }
}

/// `a ∩ b`.
fn clamp(a: Range<i64>, b: &Range<i64>) -> Range<i64> {
    let start = a.start.max(b.start);
    start..a.end.min(b.end).max(start)
}

/// The walkable rows along `axis` whose centres may lie in `[lo, hi]`: a
/// superset by up to one row on each side, computed without the exact
/// loops of [`Grid::centres_in`] (the crossing test is exact, so extra
/// candidates change nothing but the work).
#[inline]
fn rows_between(grid: &Grid, axis: usize, lo: f64, hi: f64) -> Range<i64> {
    let walk = grid.walkable(axis);
    let (first, last) = (row_ends(grid, axis, lo).0, row_ends(grid, axis, hi).1);
    if first > last {
        return 0..0;
    }
    let start = first.max(walk.start);
    start..(last + 1).min(walk.end).max(start)
}

/// The first row along `axis` at or after `v` and the last at or before
/// it, each widened by a millionth of a row (both from [`row_at`]), or
/// `(i64::MAX, i64::MIN)` for a NaN `v`: the rounding of
/// [`rows_between`]'s bounds, non-decreasing in `v`.
#[inline]
fn row_ends(grid: &Grid, axis: usize, v: f64) -> (i64, i64) {
    let at = row_at(grid, axis, v);
    if at.is_nan() {
        (i64::MAX, i64::MIN)
    } else {
        (ceil_small(at - 1e-6), floor_small(at + 1e-6))
    }
}

/// The fractional row index of `v` along `axis`: integers at the centres
/// (by the reciprocal, within a few ulps of the quotient: far inside the
/// margin of [`rows_between`]), clamped to one row before and after the
/// walkable ones before any conversion, so far or non-finite values cannot
/// overflow. Non-decreasing in `v` (and NaN for NaN).
#[inline]
fn row_at(grid: &Grid, axis: usize, v: f64) -> f64 {
    let walk = grid.walkable(axis);
    ((v - grid.min()[axis]) * grid.inv_cell(axis) - 0.5)
        .clamp(walk.start as f64 - 1.0, walk.end as f64)
}

/// What [`rows_between`] needs of one vertex: its [`row_ends`] along y,
/// then along z.
///
/// [`rows_between`] rounds its bounds by non-decreasing functions, so a
/// triangle's rows are those between the least first row and the greatest
/// last row of its vertices ([`RowKeys::vertex_candidates`]): the same rows, with
/// the rounding done once a vertex instead of once a triangle. NaN
/// coordinates are left out as `f64::min` and `max` leave them out of a
/// triangle's bounds.
#[derive(Clone, Copy, Debug)]
pub(super) struct VertexRows([i64; 4]);

impl VertexRows {
    /// The rows of world vertex `p`.
    #[inline]
    pub(super) fn new(grid: &Grid, p: DVec3) -> Self {
        let (y0, y1) = row_ends(grid, 1, p.y);
        let (z0, z1) = row_ends(grid, 2, p.z);
        Self([y0, y1, z0, z1])
    }
}

/// `v.ceil()` for a finite `v` of magnitude below 2⁵², by truncation:
/// without SSE4.1 the float method is a library call.
#[inline]
fn ceil_small(v: f64) -> i64 {
    let t = v as i64;
    t + i64::from((t as f64) < v)
}

/// `v.floor()` for a finite `v` of magnitude below 2⁵² (see [`ceil_small`]).
#[inline]
fn floor_small(v: f64) -> i64 {
    let t = v as i64;
    t - i64::from((t as f64) > v)
}

/// A mesh edge `i → j` placed in the world: its [`row_edge`] function, and
/// whether the canonical order runs against `i → j` and against `j → i`.
#[derive(Clone, Copy, Debug)]
pub(super) struct PlacedEdge {
    coefficients: [f64; 3],
    flips: [bool; 2],
}

/// A triangle's edges `k` of [`MeshSolid::triangle_edges`] (each the mesh
/// edge `k >> 1`, run forward or, if `k` is odd, backward): their placed
/// [`row_edge`] functions and flips, as [`RowTri::with_edges`] takes them.
/// (Built field by field: arrays of `([f64; 3], bool)` pairs went through
/// the stack in pieces that the loads could not take from the stores.)
#[inline]
fn placed_edges(edges: &[PlacedEdge], [k0, k1, k2]: [u32; 3]) -> ([&[f64; 3]; 3], [bool; 3]) {
    let (e0, e1, e2) = (
        &edges[(k0 >> 1) as usize],
        &edges[(k1 >> 1) as usize],
        &edges[(k2 >> 1) as usize],
    );
    (
        [&e0.coefficients, &e1.coefficients, &e2.coefficients],
        [
            e0.flips[(k0 & 1) as usize],
            e1.flips[(k1 & 1) as usize],
            e2.flips[(k2 & 1) as usize],
        ],
    )
}

impl Voxelizer {
    /// Places the triangles of `m` in the world: [`RowTri::new`] of each
    /// placed triangle, with each edge's function computed once for the
    /// two triangles that share it.
    pub(super) fn place(&mut self, m: &MeshSolid, to_world: &DAffine3) {
        self.place_edges(m, to_world);
        let (world, edges) = (&self.world, &self.edges);
        self.tris.clear();
        self.tris.extend(
            m.triangle_indices()
                .iter()
                .zip(m.triangle_edges())
                .map(|(t, &e)| {
                    let (coefficients, flips) = placed_edges(edges, e);
                    RowTri::with_edges(corners(world, *t), coefficients, flips)
                }),
        );
    }

    /// The first part of [`place`](Self::place): the placed vertices and
    /// each edge's function.
    pub(super) fn place_edges(&mut self, m: &MeshSolid, to_world: &DAffine3) {
        self.world.clear();
        self.world
            .extend(m.positions().iter().map(|&p| to_world.transform_point3(p)));
        let world = &self.world;
        self.edges.clear();
        self.edges.extend(m.edges().iter().map(|&[i, j]| {
            let (p, q) = (world[i as usize], world[j as usize]);
            let (coefficients, flip) = row_edge(p, q);
            // `q → p` has the same canonical order, so the other flip,
            // unless the endpoints compare equal (both flip then; the
            // coefficients, all zero, differ at most in their signs).
            PlacedEdge {
                coefficients,
                flips: [flip, !flip | (p == q)],
            }
        }));
    }

    /// [`cross_triangles`](Self::cross_triangles) of `m`'s triangles placed
    /// by [`place_edges`](Self::place_edges), each prepared only if its
    /// projection's bounds hold a candidate row (found from its vertices'
    /// [`VertexRows`], rounded once a vertex).
    fn cross_mesh(&mut self, grid: &Grid, keys: &RowKeys, m: &MeshSolid) -> usize {
        let Self {
            world,
            vertex_rows,
            edges,
            hits,
            ..
        } = self;
        vertex_rows.clear();
        vertex_rows.extend(world.iter().map(|&p| VertexRows::new(grid, p)));
        let mut n = 0;
        for (t, &e) in m.triangle_indices().iter().zip(m.triangle_edges()) {
            let Some((ys, zs)) = keys.vertex_candidates(corners(vertex_rows, *t)) else {
                continue;
            };
            let v = corners(world, *t);
            let (coefficients, flips) = placed_edges(edges, e);
            let t = RowFunctions::new(v, coefficients, flips);
            if !t.parallel() {
                let wide =
                    (ys.end - ys.start > SECTION_ROWS).then(|| RowTri::with_functions(v, &t));
                n = keys.rasterize_rows(grid, &t, wide.as_ref(), (ys, zs), hits, n);
            }
        }
        n
    }

    /// Every placed triangle's crossings with the rows of `keys`, written to
    /// `self.hits` (see [`RowKeys::rasterize`]); returns how many.
    pub(super) fn cross_triangles(&mut self, grid: &Grid, keys: &RowKeys) -> usize {
        let mut n = 0;
        for t in &self.tris {
            n = keys.rasterize(grid, t, &mut self.hits, n);
        }
        n
    }

    /// The first `n` crossings in `self.hits` (from
    /// [`cross_mesh`](Self::cross_mesh) or
    /// [`cross_triangles`](Self::cross_triangles)), as sorted keys in
    /// `self.keys`: counted into their rows, then each row sorted (a whole
    /// sort when the box has far more rows than crossings).
    pub(super) fn sort_crossings(&mut self, grid: &Grid, keys: &RowKeys, n: usize) {
        self.keys.clear();
        self.keys
            .extend(self.hits[..n].iter().map(|&hit| keys.key(grid, hit)));
        let rows = keys.rows();
        if rows > 4 * self.keys.len() + 4096 {
            self.keys.sort_unstable();
            return;
        }
        let ends = &mut self.row_ends;
        ends.clear();
        ends.resize(rows + 1, 0);
        for k in &self.keys {
            ends[(k >> 32) as usize + 1] += 1;
        }
        for r in 1..=rows {
            ends[r] += ends[r - 1];
        }
        self.sorted.clear();
        self.sorted.resize(self.keys.len(), 0);
        for &k in &self.keys {
            let slot = &mut ends[(k >> 32) as usize];
            self.sorted[*slot as usize] = k;
            *slot += 1;
        }
        // `ends[r]` is now where row r ends, and row r starts where r − 1 ends.
        let mut start = 0;
        for &end in &ends[..rows] {
            self.sorted[start..end as usize].sort_unstable();
            start = end as usize;
        }
        std::mem::swap(&mut self.keys, &mut self.sorted);
    }

    /// The spans of a mesh solid by parity: each row's sorted crossings in
    /// pairs; an odd last one opens no span. A box at most [`MASK_CELLS`]
    /// cells long along x keeps each row as bit masks instead of sorting
    /// ([`mask_spans`](Self::mask_spans)); longer ones sort their keys.
    pub(super) fn mesh_spans(
        &mut self,
        grid: &Grid,
        m: &MeshSolid,
        to_world: &DAffine3,
        r: &Rows,
        mut f: impl FnMut(Span),
    ) {
        self.place_edges(m, to_world);
        let mut keys = std::mem::take(&mut self.row_keys);
        keys.fill(grid, r);
        let cells = r.x_cells(grid);
        if cells.end - cells.start <= MASK_CELLS {
            self.mask_spans(grid, m, &keys, cells, f);
        } else {
            let n = self.cross_mesh(grid, &keys, m);
            self.sort_crossings(grid, &keys, n);
            for row in self.keys.chunk_by(|a, b| a >> 32 == b >> 32) {
                let (y, z) = keys.row_of(row[0]);
                for pair in row.chunks_exact(2) {
                    let (x0, x1) = (keys.cell_of(pair[0]), keys.cell_of(pair[1]));
                    if x0 < x1 {
                        f(Span { y, z, x0, x1 });
                    }
                }
            }
        }
        self.row_keys = keys;
    }

    /// [`mesh_spans`](Self::mesh_spans) for a box whose rows hold at most
    /// [`MASK_CELLS`] cells, `cells`: per row, a crossing toggles the bit
    /// of its cell (bit `i` for cell `cells.start + i`, the end itself
    /// included) and marks it reached. A cell is inside iff the crossings
    /// at or before it are odd in number (the toggles' prefix parity) and it
    /// lies before the row's last crossing: the pairs of sorted crossings
    /// exactly, as the cells from the last one on are either even (no span)
    /// or odd only by that unpaired crossing.
    fn mask_spans(
        &mut self,
        grid: &Grid,
        m: &MeshSolid,
        keys: &RowKeys,
        cells: Range<i64>,
        mut f: impl FnMut(Span),
    ) {
        let n = self.cross_mesh(grid, keys, m);
        let masks = &mut self.masks;
        masks.clear();
        masks.resize(keys.rows(), [0, 0]);
        for &(prefix, x) in &self.hits[..n] {
            let cell = keys
                .xs
                .first_at_or_after(grid, x)
                .clamp(cells.start, cells.end);
            let bit = 1u64 << (cell - cells.start);
            let [toggled, reached] = &mut masks[(prefix >> 32) as usize];
            *toggled ^= bit;
            *reached |= bit;
        }
        let mut masks = masks.iter();
        for z in keys.z.clone() {
            for y in keys.y.clone() {
                let Some(&[toggled, reached]) = masks.next() else {
                    return;
                };
                if reached == 0 {
                    continue;
                }
                let last = 63 - reached.leading_zeros();
                let inside = prefix_parity(toggled) & ((1u64 << last) - 1);
                // Each run's first and last bit, taken in pairs from the
                // low end (shifts by a constant: a shift by a register
                // costs three instructions on x86-64).
                let (mut firsts, mut lasts) = (inside & !(inside << 1), inside & !(inside >> 1));
                while firsts != 0 {
                    let (a, b) = (firsts.trailing_zeros(), lasts.trailing_zeros());
                    f(Span {
                        y,
                        z,
                        x0: cells.start + i64::from(a),
                        x1: cells.start + i64::from(b) + 1,
                    });
                    firsts &= firsts - 1;
                    lasts &= lasts - 1;
                }
            }
        }
    }
}

/// Boxes whose rows hold at most this many cells along x keep each row's
/// crossings as bit masks (bits `0..=MASK_CELLS`: the cells and the end).
const MASK_CELLS: i64 = 63;

/// Bit `i` of the result: the parity of bits `0..=i` of `v`.
#[inline]
fn prefix_parity(mut v: u64) -> u64 {
    v ^= v << 1;
    v ^= v << 2;
    v ^= v << 4;
    v ^= v << 8;
    v ^= v << 16;
    v ^= v << 32;
    v
}

#[cfg(test)]
mod tests {
    use glam::{DVec3, UVec3};
    use proptest::prelude::*;

    use super::*;

    /// [`rows_between`] as first written, with the float `ceil` and `floor`.
    fn rows_between_reference(grid: &Grid, axis: usize, lo: f64, hi: f64) -> Range<i64> {
        let (min, inv_cell) = (grid.min()[axis], grid.inv_cell(axis));
        let walk = grid.walkable(axis);
        let at =
            |v: f64| ((v - min) * inv_cell - 0.5).clamp(walk.start as f64 - 1.0, walk.end as f64);
        let first = (at(lo) - 1e-6).ceil();
        let last = (at(hi) + 1e-6).floor();
        if first.is_nan() || last.is_nan() || first > last {
            return 0..0;
        }
        let start = (first as i64).max(walk.start);
        start..(last as i64 + 1).min(walk.end).max(start)
    }

    proptest! {
        /// Equal to the float methods on integers, halves and any value.
        #[test]
        fn ceil_and_floor_by_truncation(
            v in prop_oneof![-1e6..1e6f64, (-1000i32..1000).prop_map(|i| f64::from(i) / 2.0),
                Just(0.0), Just(-0.0), Just(-1e-300), Just(1e-300)],
        ) {
            prop_assert_eq!(ceil_small(v), v.ceil() as i64);
            prop_assert_eq!(floor_small(v), v.floor() as i64);
        }

        /// The same rows as with `ceil` and `floor`, for bounds near and
        /// far, on and between centres, and not finite.
        #[test]
        fn rows_between_rounds_as_ceil_and_floor(
            n in 1u32..40,
            lo in prop_oneof![-200.0..200.0f64, (-80i32..80).prop_map(|i| f64::from(i) * 0.25),
                Just(f64::NAN), Just(f64::INFINITY), Just(f64::NEG_INFINITY), Just(1e300)],
            width in prop_oneof![0.0..50.0f64, Just(0.0), Just(f64::INFINITY)],
        ) {
            let grid = Grid::new(DVec3::splat(-3.0).as_vec3(), DVec3::splat(7.0).as_vec3(), UVec3::splat(n)).unwrap();
            let hi = lo + width;
            for axis in 0..3 {
                prop_assert_eq!(rows_between(&grid, axis, lo, hi), rows_between_reference(&grid, axis, lo, hi));
            }
        }

        /// Every walkable row whose centre lies in `[lo, hi]` is a
        /// candidate (the crossing tests decide only candidates), and no
        /// candidate lies more than one row beyond.
        #[test]
        fn rows_between_holds_every_centre_within(
            n in 1u32..40,
            lo in prop_oneof![-20.0..20.0f64, (-80i32..80).prop_map(|i| f64::from(i) * 0.125)],
            width in prop_oneof![0.0..12.0f64, Just(0.0)],
            min in prop_oneof![Just(-3.0f32), -10.0..0.0f32],
            size in prop_oneof![Just(10.0f32), 0.1..30.0f32],
        ) {
            let grid = Grid::new(DVec3::splat(f64::from(min)).as_vec3(), DVec3::splat(f64::from(min + size)).as_vec3(), UVec3::splat(n)).unwrap();
            let hi = lo + width;
            for axis in 0..3 {
                let rows = rows_between(&grid, axis, lo, hi);
                let walk = grid.walkable(axis);
                for i in walk.clone() {
                    let c = grid.center_along(axis, i);
                    if (lo..=hi).contains(&c) {
                        prop_assert!(rows.contains(&i), "row {i} (centre {c}) in [{lo}, {hi}] but not in {rows:?}");
                    }
                }
                if !rows.is_empty() {
                    prop_assert!(grid.center_along(axis, rows.start) >= lo - grid.cell_size()[axis]);
                    prop_assert!(grid.center_along(axis, rows.end - 1) <= hi + grid.cell_size()[axis]);
                }
            }
        }

        /// A triangle's candidate rows from its vertices' rows are those
        /// from its projection's bounds, for vertices near and far, on and
        /// between centres, and NaN, and for boxes anywhere in the walkable
        /// lattice.
        #[test]
        fn vertex_rows_give_the_same_candidates(
            n in 1u32..30,
            coords in prop::collection::vec(prop_oneof![
                4 => -12.0..12.0f64,
                4 => (-60i32..60).prop_map(|i| f64::from(i) * 0.25),
                1 => Just(f64::NAN), 1 => Just(f64::INFINITY), 1 => Just(f64::NEG_INFINITY),
                1 => Just(1e300), 1 => Just(-0.0)], 6),
            box_rows in prop::array::uniform4(0.0..1.0f64),
        ) {
            let grid = Grid::new(DVec3::splat(-3.0).as_vec3(), DVec3::splat(7.0).as_vec3(), UVec3::splat(n)).unwrap();
            let sub = |axis: usize, (a, b): (f64, f64)| {
                let walk = grid.walkable(axis);
                let len = (walk.end - walk.start) as f64;
                let (a, b) = (walk.start + (a * len) as i64, walk.start + (b * len) as i64);
                a.min(b)..a.max(b) + 1
            };
            let keys = RowKeys {
                y: sub(1, (box_rows[0], box_rows[1])),
                z: sub(2, (box_rows[2], box_rows[3])),
                ..RowKeys::default()
            };
            let v = [0, 1, 2].map(|i| DVec3::new(0.0, coords[2 * i], coords[2 * i + 1]));
            prop_assert_eq!(
                keys.vertex_candidates(v.map(|p| VertexRows::new(&grid, p))),
                keys.candidates(&grid, crate::solid::yz_bounds(v))
            );
        }

        /// Placing a mesh with each edge's function computed once for both
        /// of its triangles prepares exactly [`RowTri::new`] of each placed
        /// triangle (bit for bit, but for the sign of a zero), on vertices
        /// drawn from a coarse lattice (shared coordinates, repeated and
        /// coinciding vertices, degenerate triangles) and placements that
        /// mirror.
        #[test]
        fn placing_shares_edges_exactly(
            points in prop::collection::vec([-2i8..3, -2i8..3, -2i8..3], 3..12),
            corners in prop::collection::vec([0usize..64, 0usize..64, 0usize..64], 1..24),
            scale in prop_oneof![Just(1.0), 0.1..3.0f64, Just(-1.0), -3.0..-0.1f64],
            angle in 0.0..std::f64::consts::TAU,
            shift in prop_oneof![Just([0.0; 3]), prop::array::uniform3(-2.0..2.0f64)],
        ) {
            let positions = points.iter().map(|p| glam::Vec3::from(p.map(|c| f32::from(c) * 0.5))).collect::<Vec<_>>();
            let triangles = corners.iter().map(|t| t.map(|i| (i % positions.len()) as u32)).collect();
            let m = MeshSolid::new(&crate::Mesh { positions, triangles });
            let to_world = DAffine3::from_scale_rotation_translation(
                DVec3::new(scale, 1.0, 0.5),
                glam::DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), angle),
                DVec3::from(shift),
            );
            let mut v = Voxelizer::new();
            v.place(&m, &to_world);
            prop_assert_eq!(v.tris.len(), m.triangle_indices().len());
            for (placed, t) in v.tris.iter().zip(m.triangles()) {
                let reference = RowTri::new(t.map(|p| to_world.transform_point3(p)));
                prop_assert_eq!(placed.bits(), reference.bits());
            }
        }
    }
}
