//! Filling a mesh from its contour: only the edges where the projected
//! surface folds or ends are swept, instead of every triangle's.
//!
//! Under the half-open centre rule a triangle covers a pixel iff the winding
//! number of its projected edges around the pixel's centre is ±1: crossings
//! of the centre's row at or left of it, +1 for an edge going down the
//! image, −1 going up; +1 inside if its pixel-space signed area is not
//! positive (*front* here), −1 if it is (*back*). Winding numbers add over
//! edges, and an edge shared by two triangles crosses every row at the same
//! number in both (same lower end, same slope), so sums of triangles are
//! winding numbers of the sums' boundaries:
//!
//! - `W_F`, the winding number of the front triangles' boundary (the
//!   contour edges between front and back, and the mesh's own boundary
//!   next to front triangles), counts the front triangles over a pixel;
//! - `W`, that of the whole mesh's boundary chain, is `#front − #back`.
//!
//! The pixel's triangle count is `#front + #back = 2·W_F − W`, so each
//! crossing adds `2·front − all` of its edge's multiplicities to the
//! running count of the row ([`Layers`]), and a pixel is covered iff the
//! count is positive. Only the edges where either multiplicity is non-zero
//! are swept, which for a smooth mesh are far fewer than all triangle
//! edges; the crossings, rows and pixel rounding are those of
//! triangle-by-triangle filling, so the pixels are the same (but where
//! rounding makes a near-degenerate triangle's two crossings of a row swap,
//! within an ulp of a pixel centre). Counts add over instances, so a whole
//! model adds into one [`Layers`].

use glam::DVec2;

use super::layers::Layers;
use super::row_range;
use crate::mesh::Mesh;

/// A mesh's edges with their incident triangles.
#[derive(Clone, Debug, Default)]
pub(super) struct EdgeTable {
    /// Edges between exactly two triangles running them in opposite
    /// directions (most edges of a clean mesh): ends `[a, b]` (`a < b`), the
    /// triangle running `a → b`, the one running `b → a`. Such an edge is
    /// on the contour iff exactly one of them is front, and never on the
    /// mesh's boundary.
    pairs: Vec<([u32; 2], u32, u32)>,
    /// Every other edge: ends, and its triangles
    /// `incident[start[e]..start[e + 1]]`, each with +1 if it runs `a → b`,
    /// −1 if `b → a`; `boundary[e]` is the sum of those signs (the mesh's
    /// boundary chain on the edge).
    ends: Vec<[u32; 2]>,
    start: Vec<u32>,
    incident: Vec<(u32, i32)>,
    boundary: Vec<i32>,
}

impl EdgeTable {
    /// The edges of `mesh`, vertices at the same position welded to the
    /// first index.
    pub(super) fn new(mesh: &Mesh) -> Self {
        let id = mesh.welded();
        let mut by_edge = std::collections::BTreeMap::<[u32; 2], Vec<(u32, i32)>>::new();
        for (t, tri) in mesh.triangles.iter().enumerate() {
            for (a, b) in [(tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0])] {
                let (a, b) = (id[a as usize], id[b as usize]);
                if a != b {
                    let sign = if a < b { 1 } else { -1 };
                    by_edge
                        .entry([a.min(b), a.max(b)])
                        .or_default()
                        .push((t as u32, sign));
                }
            }
        }
        let mut table = Self::default();
        table.start.push(0);
        for (ends, tris) in by_edge {
            match tris[..] {
                [(t0, 1), (t1, -1)] => table.pairs.push((ends, t0, t1)),
                [(t1, -1), (t0, 1)] => table.pairs.push((ends, t0, t1)),
                _ => {
                    table.ends.push(ends);
                    table.boundary.push(tris.iter().map(|&(_, s)| s).sum());
                    table.incident.extend(tris);
                    table.start.push(table.incident.len() as u32);
                }
            }
        }
        table
    }
}

/// Reusable working memory of [`fill_contour`].
#[derive(Clone, Debug, Default)]
pub(super) struct ContourScratch {
    /// Per triangle, whether it is front.
    front: Vec<bool>,
    /// Candidate edges (ends and count contribution `2·front − all` in
    /// the direction `ends[0] → ends[1]`), of which the first `n` are swept.
    candidates: Vec<([u32; 2], i32)>,
    /// The swept edges set up, and their indices grouped by how many rows
    /// they cross.
    edges: Vec<SweepEdge>,
    order: Vec<u32>,
}

/// Adds to `layers` the triangles `triangles` of a mesh whose vertices
/// project to `pixels` (all finite and in the depth range), through its
/// edge table.
pub(super) fn fill_contour(
    pixels: &[DVec2],
    triangles: &[[u32; 3]],
    table: &EdgeTable,
    s: &mut ContourScratch,
    layers: &mut Layers,
) {
    let h = f64::from(layers.size().1);
    // Working buffers only grow (clearing them per mesh would cost as much
    // as some of the passes below).
    grow(&mut s.front, triangles.len(), false);
    for (front, t) in s.front.iter_mut().zip(triangles) {
        let (a, b, c) = (
            pixels[t[0] as usize],
            pixels[t[1] as usize],
            pixels[t[2] as usize],
        );
        // Front: a signed area that is not positive (NaN, never for finite
        // pixels, would count as front).
        let area = (b - a).perp_dot(c - a);
        *front = area <= 0.0 || area.is_nan();
    }
    // The contour edges, gathered without a branch per edge (whether an
    // edge is on the contour is unpredictable).
    let front = &s.front[..triangles.len()];
    grow(
        &mut s.candidates,
        table.pairs.len() + table.ends.len(),
        ([0; 2], 0),
    );
    let mut n = 0;
    for &(ends, t0, t1) in &table.pairs {
        let f = i32::from(front[t0 as usize]) - i32::from(front[t1 as usize]);
        s.candidates[n] = (ends, 2 * f);
        n += usize::from(f != 0);
    }
    for (e, &ends) in table.ends.iter().enumerate() {
        let incident = &table.incident[table.start[e] as usize..table.start[e + 1] as usize];
        let f: i32 = incident
            .iter()
            .filter(|&&(t, _)| front[t as usize])
            .map(|&(_, sign)| sign)
            .sum();
        let count = 2 * f - table.boundary[e];
        s.candidates[n] = (ends, count);
        n += usize::from(count != 0);
    }
    // Each edge set up without a branch (it runs up or down at random),
    // then the edges swept grouped by how many rows they cross: a loop
    // whose length changes from edge to edge would be mispredicted at
    // almost every edge, and each misprediction would stall the chain of
    // arithmetic from the row to the column.
    grow(&mut s.edges, n, SweepEdge::default());
    grow(&mut s.order, n, 0);
    // Per group (row count, the last group more), one past its last index
    // in `order`; a counting sort, so `start[g]..start[g + 1]` after it.
    let mut start = [0u32; GROUPS + 2];
    for (e, &(ends, multiplicity)) in s.edges.iter_mut().zip(&s.candidates[..n]) {
        let (p, q) = (pixels[ends[0] as usize], pixels[ends[1] as usize]);
        let up = p.y < q.y;
        let (lo, hi) = (select(up, p, q), select(up, q, p));
        // A horizontal edge crosses no row centre line (and its slope,
        // not finite, is never used).
        let (r0, r1) = row_range(lo.y, hi.y, h);
        let rows = if r1 > r0 { (r1 - r0) as u32 } else { 0 };
        *e = SweepEdge {
            lo,
            slope: (hi.x - lo.x) / (hi.y - lo.y),
            first: r0 as u32,
            rows,
            delta: if up { multiplicity } else { -multiplicity },
        };
        start[(rows as usize).min(GROUPS) + 1] += 1;
    }
    for g in 1..start.len() {
        start[g] += start[g - 1];
    }
    let mut next = start;
    for (i, e) in s.edges[..n].iter().enumerate() {
        let slot = &mut next[(e.rows as usize).min(GROUPS)];
        s.order[*slot as usize] = i as u32;
        *slot += 1;
    }
    let edges = &s.edges[..n];
    let group = |g: usize| {
        s.order[start[g] as usize..start[g + 1] as usize]
            .iter()
            .map(|&i| &edges[i as usize])
    };
    // Group 0 crosses no row.
    sweep_rows::<1>(group(1), layers);
    sweep_rows::<2>(group(2), layers);
    sweep_rows::<3>(group(3), layers);
    sweep_rows::<4>(group(4), layers);
    sweep_rows::<5>(group(5), layers);
    sweep_rows::<6>(group(6), layers);
    sweep_rows::<7>(group(7), layers);
    sweep_rows::<8>(group(8), layers);
    for e in group(GROUPS) {
        for row in e.first..e.first + e.rows {
            layers.cross(row, e.crossing(row), e.delta);
        }
    }
}

/// `a` if `take_a`, else `b`, without a branch.
#[inline(always)]
fn select(take_a: bool, a: DVec2, b: DVec2) -> DVec2 {
    let mask = u64::from(take_a).wrapping_neg();
    let pick = |a: f64, b: f64| f64::from_bits((a.to_bits() & mask) | (b.to_bits() & !mask));
    DVec2::new(pick(a.x, b.x), pick(a.y, b.y))
}

/// Edges crossing `1..GROUPS` rows are swept in groups of one row count
/// (on the paper's leaf, 94% of its contour edges cross fewer than 9 rows).
const GROUPS: usize = 9;

/// Sweeps edges that cross exactly `K` rows each.
#[inline(always)]
fn sweep_rows<'a, const K: u32>(edges: impl Iterator<Item = &'a SweepEdge>, layers: &mut Layers) {
    for e in edges {
        for row in e.first..e.first + K {
            layers.cross(row, e.crossing(row), e.delta);
        }
    }
}

/// An edge set up for the sweep.
#[derive(Clone, Copy, Debug, Default)]
struct SweepEdge {
    /// Lower end (smaller y) and dx/dy.
    lo: DVec2,
    slope: f64,
    /// First row whose centre line it crosses, and how many it crosses.
    first: u32,
    rows: u32,
    /// What a crossing adds to the triangle count right of it.
    delta: i32,
}

impl SweepEdge {
    /// Where it crosses the centre line of row `row`: from the lower end,
    /// as triangle-by-triangle filling computes it.
    #[inline(always)]
    fn crossing(&self, row: u32) -> f64 {
        let yc = f64::from(row) + 0.5;
        self.lo.x + (yc - self.lo.y) * self.slope
    }
}

/// Makes `v` at least `len` long (new entries `fill`), never shorter.
fn grow<T: Clone>(v: &mut Vec<T>, len: usize, fill: T) {
    if v.len() < len {
        v.resize(len, fill);
    }
}
