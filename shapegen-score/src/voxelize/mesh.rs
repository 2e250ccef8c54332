//! Mesh solids by scanline: every placed triangle is rasterized onto the
//! lattice rows whose centre lines pierce it, each crossing becomes the first
//! cell at or after it, and the packed `(row, cell)` keys, counted into
//! their rows and sorted within each, give every row's crossings in order. The cost is proportional to the
//! triangles' row footprints plus the crossings, whatever the mesh's shape.

use std::ops::Range;

use glam::DAffine3;

use super::{Rows, Span, Voxelizer};
use crate::grid::{Centres, Grid};
use crate::solid::{MeshSolid, RowTri};

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

    /// Appends the key of every crossing of `t` with a walkable row.
    ///
    /// A triangle spanning more than [`SECTION_ROWS`] rows along y has,
    /// per row along z, its projection's cross-section give the candidate
    /// rows along y (one more on each side, against rounding); smaller ones
    /// test their whole box. [`RowTri::cross`] decides each candidate
    /// exactly, so the candidates only save work and never change a crossing.
    pub(super) fn rasterize(&self, grid: &Grid, t: &RowTri, out: &mut Vec<u64>) {
        if t.parallel() {
            return;
        }
        let [y_lo, y_hi, z_lo, z_hi] = t.yz_bounds();
        // Rows beyond the box are never crossed (the reference looks at the
        // box's rows only, too).
        let ys = clamp(rows_between(grid, 1, y_lo, y_hi), &self.y);
        let zs = clamp(rows_between(grid, 2, z_lo, z_hi), &self.z);
        if ys.is_empty() {
            return;
        }
        let sign = u64::from(t.sign() > 0.0);
        for z in zs {
            let cz = grid.center_along(2, z);
            let ys = if ys.end - ys.start <= SECTION_ROWS {
                ys.clone()
            } else {
                let Some((lo, hi)) = t.y_section(cz) else {
                    continue;
                };
                // One more row on each side: the section's ends are rounded.
                let r = rows_between(grid, 1, lo, hi);
                let start = (r.start - 1).max(ys.start);
                start..(r.end + 1).min(ys.end).max(start)
            };
            let line = t.line(cz);
            for y in ys {
                if let Some(x) = line.cross(self.ys.at(y)) {
                    let cell = self
                        .xs
                        .first_at_or_after(grid, x)
                        .clamp(self.x.start, self.x.end);
                    out.push(self.row(y, z) | ((cell - self.x.start) as u64) << 1 | sign);
                }
            }
        }
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
    let (min, cell) = (grid.min()[axis], grid.cell_size()[axis]);
    let walk = grid.walkable(axis);
    // Fractional row index: integers at the centres. Clamped before the
    // conversion, so far or non-finite bounds cannot overflow.
    let at = |v: f64| ((v - min) / cell - 0.5).clamp(walk.start as f64 - 1.0, walk.end as f64);
    let first = (at(lo) - 1e-6).ceil();
    let last = (at(hi) + 1e-6).floor();
    if first.is_nan() || last.is_nan() || first > last {
        return 0..0;
    }
    let start = (first as i64).max(walk.start);
    start..(last as i64 + 1).min(walk.end).max(start)
}

impl Voxelizer {
    /// Places the triangles of `m` in the world.
    pub(super) fn place(&mut self, m: &MeshSolid, to_world: &DAffine3) {
        self.world.clear();
        self.world
            .extend(m.positions().iter().map(|&p| to_world.transform_point3(p)));
        self.tris.clear();
        let world = &self.world;
        self.tris.extend(
            m.triangle_indices()
                .iter()
                .map(|t| RowTri::new(t.map(|i| world[i as usize]))),
        );
    }

    /// Every placed triangle's crossings, as sorted keys in `self.keys`:
    /// counted into their rows, then each row sorted (a whole sort when the
    /// box has far more rows than crossings).
    pub(super) fn cross_rows(&mut self, grid: &Grid, keys: &RowKeys) {
        self.keys.clear();
        for t in &self.tris {
            keys.rasterize(grid, t, &mut self.keys);
        }
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
    /// pairs; an odd last one opens no span.
    pub(super) fn mesh_spans(
        &mut self,
        grid: &Grid,
        m: &MeshSolid,
        to_world: &DAffine3,
        r: &Rows,
        mut f: impl FnMut(Span),
    ) {
        self.place(m, to_world);
        let mut keys = std::mem::take(&mut self.row_keys);
        keys.fill(grid, r);
        self.cross_rows(grid, &keys);
        for row in self.keys.chunk_by(|a, b| a >> 32 == b >> 32) {
            let (y, z) = keys.row_of(row[0]);
            for pair in row.chunks_exact(2) {
                let (x0, x1) = (keys.cell_of(pair[0]), keys.cell_of(pair[1]));
                if x0 < x1 {
                    f(Span { y, z, x0, x1 });
                }
            }
        }
        self.row_keys = keys;
    }
}
