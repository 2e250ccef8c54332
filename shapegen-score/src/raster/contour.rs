//! Filling a mesh from its contour: one scanline sweep over the edges where
//! the projected surface folds or ends, instead of every triangle.
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
//! A pixel is covered by some triangle iff `W_F ≥ 1`, or `W_F = 0` and
//! `#back = −W > 0`: iff `W_F ≥ 1 or W < 0`. Both are read off one sweep of
//! the edges where either multiplicity is non-zero, which for a smooth mesh
//! are far fewer than all triangle edges; the crossings, rows and pixel
//! rounding are those of triangle-by-triangle filling, so the pixels are the
//! same (but where rounding makes a near-degenerate triangle's two crossings
//! of a row swap, within an ulp of a pixel centre).
//!
//! A row's crossings are sorted by x when they are few (a box or a frustum
//! has two). A detailed mesh's contour zig-zags along its outline (the
//! paper's leaf: 16 crossings a row, 4 of which change the coverage, the
//! rest within a few pixels of those); its crossings are not sorted but
//! their contributions summed per column, since a crossing at x counts for
//! exactly the pixel centres of columns `⌈x − ½⌉` on, and a running sum
//! along the row gives both winding numbers at every centre.

use glam::DVec2;

use super::{PixelSpan, ceil_small, emit_row, row_range};
use crate::camera::Camera;
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

/// An edge set up for the sweep.
#[derive(Clone, Copy, Debug, Default)]
struct SweepEdge {
    /// Lower end (smaller y) and dx/dy.
    lo: DVec2,
    slope: f64,
    /// First row whose centre it crosses, and one past the last.
    first: u32,
    end: u32,
    /// Winding contributions of a crossing: to `W_F` and to `W`.
    front: i32,
    all: i32,
}

/// Reusable working memory of [`fill_contour`], and how it treats rows.
#[derive(Clone, Debug)]
pub(super) struct ContourScratch {
    /// Rows with at most this many crossings are sorted; others are summed
    /// per column, unless the last row's crossings spread over more than
    /// `columns_per_crossing` columns each (in a close-up, summing per
    /// column would cost the area instead of the crossings).
    max_sorted: usize,
    columns_per_crossing: usize,
    front: Vec<bool>,
    /// Candidate edges (ends and multiplicities), of which the first
    /// `n` are on the contour.
    candidates: Vec<([u32; 2], i32, i32)>,
    edges: Vec<SweepEdge>,
    count: Vec<u32>,
    order: Vec<u32>,
    /// The edges crossing the current row: crossing and edge index, in the
    /// previous row's order until sorted.
    active: Vec<(f64, u32)>,
    /// Per column of the image and one more (right of it), winding
    /// contributions to `W_F` and `W` of the current row; all zero between rows.
    columns: Vec<[i32; 2]>,
    /// Columns where a row's coverage turns.
    turns: Vec<u32>,
}

impl Default for ContourScratch {
    /// Sorting up to 4 crossings a row, and a row's crossings spread over up
    /// to 8 columns each summed per column: on the paper's tree sketch,
    /// any limit from 0 to 16 crossings measured the same.
    fn default() -> Self {
        Self::with_rows(4, 8)
    }
}

impl ContourScratch {
    /// Empty working memory with the given treatment of rows.
    pub(super) fn with_rows(max_sorted: usize, columns_per_crossing: usize) -> Self {
        Self {
            max_sorted,
            columns_per_crossing,
            front: Vec::new(),
            candidates: Vec::new(),
            edges: Vec::new(),
            count: Vec::new(),
            order: Vec::new(),
            active: Vec::new(),
            columns: Vec::new(),
            turns: Vec::new(),
        }
    }
}

/// Fills the triangles `triangles` of a mesh whose vertices project to
/// `pixels` (all finite and in the depth range), through its edge table.
pub(super) fn fill_contour(
    camera: &Camera,
    pixels: &[DVec2],
    triangles: &[[u32; 3]],
    table: &EdgeTable,
    s: &mut ContourScratch,
    f: &mut impl FnMut(PixelSpan),
) {
    let (w, h) = (f64::from(camera.width), f64::from(camera.height));
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
        ([0; 2], 0, 0),
    );
    let mut n = 0;
    for &(ends, t0, t1) in &table.pairs {
        let f = i32::from(front[t0 as usize]) - i32::from(front[t1 as usize]);
        s.candidates[n] = (ends, f, 0);
        n += usize::from(f != 0);
    }
    for (e, &ends) in table.ends.iter().enumerate() {
        let incident = &table.incident[table.start[e] as usize..table.start[e + 1] as usize];
        let f: i32 = incident
            .iter()
            .filter(|&&(t, _)| front[t as usize])
            .map(|&(_, sign)| sign)
            .sum();
        let all = table.boundary[e];
        s.candidates[n] = (ends, f, all);
        n += usize::from(f != 0 || all != 0);
    }
    grow(&mut s.edges, n, SweepEdge::default());
    let mut edges = 0;
    for &(ends, front, all) in &s.candidates[..n] {
        if let Some(e) = sweep_edge(pixels, ends, front, all, h) {
            s.edges[edges] = e;
            edges += 1;
        }
    }
    let edges = &s.edges[..edges];
    if edges.is_empty() {
        return;
    }
    // Edge indices by first row (a counting sort: rows are few).
    let top = edges.iter().map(|e| e.first).min().unwrap_or(0);
    let rows = (edges.iter().map(|e| e.first).max().unwrap_or(0) - top + 1) as usize;
    s.count.clear();
    s.count.resize(rows + 1, 0);
    for e in edges {
        s.count[(e.first - top) as usize + 1] += 1;
    }
    for r in 1..s.count.len() {
        s.count[r] += s.count[r - 1];
    }
    grow(&mut s.order, edges.len(), 0);
    for (i, e) in edges.iter().enumerate() {
        let slot = &mut s.count[(e.first - top) as usize];
        s.order[*slot as usize] = i as u32;
        *slot += 1;
    }
    let order = &s.order[..edges.len()];
    grow(&mut s.active, edges.len(), (0.0, 0));
    grow(&mut s.columns, camera.width as usize + 1, [0, 0]);
    grow(&mut s.turns, camera.width as usize + 2, 0);
    let mut active = 0;
    let mut next = 0;
    let mut row = top;
    // The columns spanned by the last row's crossings.
    let mut width = 0;
    loop {
        while next < order.len() && edges[order[next] as usize].first == row {
            s.active[active] = (0.0, order[next]);
            active += 1;
            next += 1;
        }
        let yc = f64::from(row) + 0.5;
        if active > s.max_sorted && width <= s.columns_per_crossing.saturating_mul(active) {
            // Many crossings close together (a detailed mesh's zig-zag
            // contour): their winding contributions summed per column
            // instead of sorted. A crossing at x counts for the pixel
            // centres at or right of it, those of columns `⌈x − ½⌉` on.
            let (mut lo, mut hi) = (w as usize, 0);
            let mut kept = 0;
            for k in 0..active {
                let i = s.active[k].1;
                let e = &edges[i as usize];
                let c = column(e.lo.x + (yc - e.lo.y) * e.slope, w);
                let sum = &mut s.columns[c];
                sum[0] += e.front;
                sum[1] += e.all;
                (lo, hi) = (lo.min(c), hi.max(c));
                s.active[kept].1 = i;
                kept += usize::from(e.end > row + 1);
            }
            active = kept;
            width = hi - lo + 1;
            emit_columns(
                &mut s.columns[lo..=hi],
                lo as u32,
                row,
                camera.width,
                &mut s.turns,
                f,
            );
        } else {
            let crossings = &mut s.active[..active];
            for (x, i) in crossings.iter_mut() {
                let e = &edges[*i as usize];
                *x = e.lo.x + (yc - e.lo.y) * e.slope;
            }
            // Few crossings, mostly in the last row's order.
            insertion_sort(crossings);
            if let (Some(first), Some(last)) = (crossings.first(), crossings.last()) {
                width = column(last.0, w).saturating_sub(column(first.0, w)) + 1;
            }
            active = emit_sorted(crossings, edges, row, w, f);
        }
        row += 1;
        if active == 0 {
            match order.get(next) {
                Some(&i) => row = edges[i as usize].first,
                None => return,
            }
        }
    }
}

/// Emits the covered pixels of row `row` from its crossings sorted by x:
/// covered between consecutive crossings iff W_F ≥ 1 or W < 0, and
/// consecutive covered intervals emitted as one span (the same pixels: the
/// centre rule is monotone). Edges ending at this row leave the list in
/// the same pass; returns how many stay.
#[inline]
fn emit_sorted(
    crossings: &mut [(f64, u32)],
    edges: &[SweepEdge],
    row: u32,
    w: f64,
    f: &mut impl FnMut(PixelSpan),
) -> usize {
    let (mut wf, mut wa) = (0, 0);
    let (mut open, mut x0) = (false, 0.0);
    let mut kept = 0;
    for k in 0..crossings.len() {
        let (x, i) = crossings[k];
        let e = &edges[i as usize];
        wf += e.front;
        wa += e.all;
        let covered = wf >= 1 || wa < 0;
        if covered != open {
            if covered {
                x0 = x;
            } else {
                emit_row(f64::from(row), x0, x, w, f);
            }
            open = covered;
        }
        crossings[kept] = (x, i);
        kept += usize::from(e.end > row + 1);
    }
    kept
}

/// Emits the covered pixels of row `row` from the winding contributions
/// summed per column (`sums[k]` for column `first + k`, cleared on the way):
/// covered where the running sums give W_F ≥ 1 or W < 0. The turns are
/// collected without a branch per column, then paired into spans.
#[inline]
fn emit_columns(
    sums: &mut [[i32; 2]],
    first: u32,
    row: u32,
    w: u32,
    turns: &mut [u32],
    f: &mut impl FnMut(PixelSpan),
) {
    let (mut wf, mut wa) = (0, 0);
    let mut open = false;
    let mut n = 0;
    for (c, sum) in (first..).zip(sums) {
        wf += sum[0];
        wa += sum[1];
        *sum = [0, 0];
        let covered = wf >= 1 || wa < 0;
        turns[n] = c;
        n += usize::from(covered != open);
        open = covered;
    }
    // Closed contours leave the sums at zero after the last crossing, so
    // the turns pair up (an odd one out, from absurd coordinates, is dropped).
    for pair in turns[..n & !1].chunks_exact(2) {
        let c1 = pair[1].min(w);
        if pair[0] < c1 {
            f(PixelSpan {
                row,
                c0: pair[0],
                c1,
            });
        }
    }
}

/// The first column whose pixel centre is at or right of `x`, clamped to
/// `0..=w` (`w`: right of the image).
#[inline(always)]
fn column(x: f64, w: f64) -> usize {
    let x = if x > -1.0 { x } else { -1.0 };
    let x = if x < w + 1.0 { x } else { w + 1.0 };
    ceil_small(x - 0.5).clamp(0, w as i32) as usize
}

/// Makes `v` at least `len` long (new entries `fill`), never shorter.
fn grow<T: Clone>(v: &mut Vec<T>, len: usize, fill: T) {
    if v.len() < len {
        v.resize(len, fill);
    }
}

/// Edge `ends` (with multiplicities `front` and `all` in the direction
/// `ends[0] → ends[1]`) set up for the sweep; `None` if it crosses no row
/// centre line of the image.
#[inline]
fn sweep_edge(pixels: &[DVec2], ends: [u32; 2], front: i32, all: i32, h: f64) -> Option<SweepEdge> {
    let (p, q) = (pixels[ends[0] as usize], pixels[ends[1] as usize]);
    if p.y == q.y {
        return None; // horizontal: crosses no row centre line
    }
    let (lo, hi, dir) = if p.y < q.y { (p, q, 1) } else { (q, p, -1) };
    let (r0, r1) = row_range(lo.y, hi.y, h);
    (r0 < r1).then(|| SweepEdge {
        lo,
        slope: (hi.x - lo.x) / (hi.y - lo.y),
        first: r0 as u32,
        end: r1 as u32,
        front: dir * front,
        all: dir * all,
    })
}

/// Sorts by x, shifting each out-of-place entry left over the larger ones
/// (the input is mostly sorted). A NaN crossing (only from absurd
/// coordinates, where `dx / dy` overflows) stays where it is, and the spans
/// around it are empty or partial; never a panic.
fn insertion_sort(v: &mut [(f64, u32)]) {
    for i in 1..v.len() {
        let cur = v[i];
        if cur.0 < v[i - 1].0 {
            let mut j = i;
            while j > 0 && cur.0 < v[j - 1].0 {
                v[j] = v[j - 1];
                j -= 1;
            }
            v[j] = cur;
        }
    }
}
