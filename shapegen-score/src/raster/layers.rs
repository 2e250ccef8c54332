//! How many triangles cover each pixel centre of an image, kept as
//! differences along each row: a crossing of a row by an edge adds its
//! winding contribution at the first column right of it, and a running sum
//! along the row gives every centre's count. Counts add over instances, so
//! a whole model is filled without ever sorting crossings or painting a
//! span, and read once: a pixel is covered iff its count is positive.

use super::{PixelSpan, ceil_small};

/// One write into [`Layers`], as recorded for a replay (see
/// [`Layers::move_into`]): the same writes give the same counts, in any
/// order (extents widen by min and max, counts add as integers).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Write {
    /// Row `row`'s part that may hold non-zero differences widened to the
    /// cells `cols.0..cols.1`.
    Widen { row: u32, cols: (u32, u32) },
    /// `delta` added to the difference in cell `cell` (row-major, `width + 1`
    /// cells a row).
    Add { cell: u32, delta: i32 },
    /// The writes that follow are to the layers of target `i` of the
    /// image scratch's (a marker of its records; layers neither make nor
    /// redo it).
    Target(u32),
}

impl Write {
    /// Whether layers of `width × height` pixels have their writes
    /// [packed](Self::pack): rows and columns in 16 and 17 bits, cells in
    /// 31.
    pub(crate) fn fits(width: u32, height: u32) -> bool {
        width < 1 << 16 && height < 1 << 16 && (u64::from(width) + 1) * u64::from(height) < 1 << 31
    }

    /// The write in 8 bytes (half the enum's): an add as its cell over its
    /// difference; a widen as its row and columns; a marker as its target.
    /// The top two bits tell them apart. Rows, columns and cells must be of
    /// layers that [`fits`](Self::fits).
    pub(crate) fn pack(self) -> u64 {
        match self {
            Self::Add { cell, delta } => u64::from(cell) << 32 | u64::from(delta as u32),
            Self::Widen { row, cols } => {
                WIDEN | u64::from(row) << 34 | u64::from(cols.0) << 17 | u64::from(cols.1)
            }
            Self::Target(i) => TARGET | u64::from(i),
        }
    }

    /// The write `bits` [packs](Self::pack).
    #[inline]
    pub(crate) fn unpack(bits: u64) -> Self {
        const COL: u64 = (1 << 17) - 1;
        match bits & TARGET {
            TARGET => Self::Target(bits as u32),
            WIDEN => Self::Widen {
                row: (bits >> 34) as u32 & 0xffff,
                cols: ((bits >> 17 & COL) as u32, (bits & COL) as u32),
            },
            _ => Self::Add {
                cell: (bits >> 32) as u32,
                delta: bits as u32 as i32,
            },
        }
    }
}

/// The top two bits of a packed widen, and of a packed target marker.
const WIDEN: u64 = 0b10 << 62;
const TARGET: u64 = 0b11 << 62;

/// Cells [`Layers::move_into`] tests at once.
const BLOCK: usize = 16;

/// Per-row differences of the triangle count over an image.
#[derive(Clone, Debug, Default)]
pub(crate) struct Layers {
    width: u32,
    height: u32,
    /// Row-major, `width + 1` cells a row: cell `c` holds the count at
    /// column `c` minus that at column `c − 1`; the last cell (right of the
    /// image) takes crossings that count for no pixel. All zero outside the
    /// extents.
    diff: Vec<i32>,
    /// Per row, the cells `extent.0..extent.1` that may be non-zero
    /// (empty: `(u32::MAX, 0)`).
    extent: Vec<(u32, u32)>,
    /// The rows that may have a non-empty extent: `rows.0..rows.1`.
    rows: (u32, u32),
}

impl Layers {
    /// All-zero counts for a `width × height` image.
    pub(crate) fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            diff: vec![0; (width as usize + 1) * height as usize],
            extent: vec![(u32::MAX, 0); height as usize],
            rows: (height, 0),
        }
    }

    /// The image's width and height.
    pub(crate) fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// Sets every count back to zero, at the cost of what was touched.
    pub(crate) fn clear(&mut self) {
        let stride = self.width as usize + 1;
        for r in self.rows.0..self.rows.1 {
            let (c0, c1) = std::mem::replace(&mut self.extent[r as usize], (u32::MAX, 0));
            if c0 < c1 {
                let base = r as usize * stride;
                self.diff[base + c0 as usize..base + c1 as usize].fill(0);
            }
        }
        self.rows = (self.height, 0);
    }

    /// Widens the part that may hold non-zero differences to the cells
    /// `cols.0..cols.1` of the rows `rows.0..rows.1` (`cols.1 <= width + 1`).
    pub(crate) fn widen(&mut self, rows: (u32, u32), cols: (u32, u32)) {
        if rows.0 >= rows.1 {
            return;
        }
        self.rows = (self.rows.0.min(rows.0), self.rows.1.max(rows.1));
        for e in &mut self.extent[rows.0 as usize..rows.1 as usize] {
            *e = (e.0.min(cols.0), e.1.max(cols.1));
        }
    }

    /// Adds `delta` to the counts of the pixels of row `row` whose centres
    /// are at or right of `x`: those of columns `⌈x − ½⌉` on (`row` in the
    /// image). The cell must lie in a part [widened](Self::widen) before:
    /// elsewhere it would be neither read nor cleared.
    #[inline(always)]
    pub(crate) fn cross(&mut self, row: u32, x: f64, delta: i32) {
        let c = column(x, f64::from(self.width));
        let stride = self.width as usize + 1;
        self.diff[row as usize * stride + c as usize] += delta;
    }

    /// Adds one to the counts of the pixels of `span`.
    pub(crate) fn span(&mut self, s: PixelSpan) {
        self.widen((s.row, s.row + 1), (s.c0, s.c1 + 1));
        let base = s.row as usize * (self.width as usize + 1);
        self.diff[base + s.c0 as usize] += 1;
        self.diff[base + s.c1 as usize] -= 1;
    }

    /// Adds these counts' *coverage* (one instance's: 1 where its count is
    /// positive, else 0) to `into` (of the same size, which
    /// [`Write::fits`]), appends the writes that did so to `log`
    /// ([packed](Write::pack)), and sets these counts back to zero: per row
    /// with covered pixels, the part from its first to one past its last
    /// change of coverage widened, and a difference of ±1 added where
    /// the coverage changes. Only whether a count is positive is ever read
    /// (`ImageScratch::counts_for`, [`covered_spans`](Self::covered_spans)),
    /// and every instance's counts are at least zero, so `into` is covered
    /// where it would be had the instance been drawn into it directly; the
    /// record holds two writes a run of covered pixels instead of one a
    /// change of the instance's own count (a leaf's hundreds of
    /// overlapping triangles change it at most of its cells).
    pub(crate) fn move_into(&mut self, into: &mut Layers, log: &mut Vec<u64>) {
        let stride = self.width as usize + 1;
        for r in self.rows.0..self.rows.1 {
            let (c0, c1) = std::mem::replace(&mut self.extent[r as usize], (u32::MAX, 0));
            if c0 >= c1 {
                continue;
            }
            let base = r as usize * stride;
            let cells = base + c0 as usize..base + c1 as usize;
            let (from, to) = (&mut self.diff[cells.clone()], &mut into.diff[cells]);
            // The row's widen is written before its adds, once they are
            // known; at most one per row.
            let mark = log.len();
            let (mut first, mut last) = (u32::MAX, 0);
            let (mut count, mut covered) = (0i32, false);
            // Most of a bounding box is zero: blocks of it are tested at
            // once (the test vectorizes), and only the non-zero ones read
            // cell by cell (a block of zeros changes neither the count
            // nor the coverage).
            let mut col = c0;
            for (from, to) in from.chunks_mut(BLOCK).zip(to.chunks_mut(BLOCK)) {
                if from.iter().fold(0, |any, &d| any | d) != 0 {
                    for (j, (d, t)) in from.iter_mut().zip(to).enumerate() {
                        count += std::mem::take(d);
                        if (count > 0) != covered {
                            covered = !covered;
                            let delta = if covered { 1 } else { -1 };
                            *t += delta;
                            let c = col + j as u32;
                            (first, last) = (first.min(c), c);
                            log.push(
                                Write::Add {
                                    cell: (base + c as usize) as u32,
                                    delta,
                                }
                                .pack(),
                            );
                        }
                    }
                }
                col += BLOCK as u32;
            }
            if covered {
                // Covered to the end (crossings past the image's right edge
                // are counted in its last cell, so a closed outline always
                // ends uncovered): as far as the instance's own part.
                last = c1 - 1;
            }
            if first <= last {
                let w = Write::Widen {
                    row: r,
                    cols: (first, last + 1),
                };
                into.redo(w);
                log.insert(mark, w.pack());
            }
        }
        self.rows = (self.height, 0);
    }

    /// Makes a recorded write again (a [`Write::Target`] marker does
    /// nothing).
    #[inline]
    pub(crate) fn redo(&mut self, w: Write) {
        match w {
            Write::Widen { row, cols } => self.widen((row, row + 1), cols),
            Write::Add { cell, delta } => self.diff[cell as usize] += delta,
            Write::Target(_) => {}
        }
    }

    /// Calls `f` with each row that may hold covered pixels, its first
    /// column, and the differences from there (to one past the last cell
    /// that may be non-zero; the count is zero left of them).
    pub(crate) fn rows(&self, mut f: impl FnMut(u32, u32, &[i32])) {
        let stride = self.width as usize + 1;
        for r in self.rows.0..self.rows.1 {
            let (c0, c1) = self.extent[r as usize];
            if c0 < c1 {
                let base = r as usize * stride;
                f(r, c0, &self.diff[base + c0 as usize..base + c1 as usize]);
            }
        }
    }

    /// Calls `f` with the runs of covered pixels (positive count), row by
    /// row, left to right.
    pub(crate) fn covered_spans(&self, mut f: impl FnMut(PixelSpan)) {
        let w = self.width;
        self.rows(|row, c0, diff| {
            let mut count = 0;
            let mut start = None;
            for (c, d) in (c0..).zip(diff) {
                count += d;
                match (count > 0, start) {
                    (true, None) => start = Some(c),
                    (false, Some(s)) => {
                        if s < c.min(w) {
                            f(PixelSpan {
                                row,
                                c0: s,
                                c1: c.min(w),
                            });
                        }
                        start = None;
                    }
                    _ => {}
                }
            }
            if let Some(s) = start {
                // Only a count that does not return to zero (absurd
                // coordinates) leaves a run open at the last cell.
                let c1 = (c0 + diff.len() as u32).min(w);
                if s < c1 {
                    f(PixelSpan { row, c0: s, c1 });
                }
            }
        });
    }
}

/// The first column whose pixel centre is at or right of `x`, clamped to
/// `0..=w` (`w`: right of the image); a NaN crossing counts as left of it.
#[inline(always)]
pub(crate) fn column(x: f64, w: f64) -> u32 {
    // Clamped first: `⌈x − ½⌉` is 0 at x = 0 and w at x = w, and the
    // clamped value is small enough for `ceil_small`.
    let x = if x > 0.0 { x } else { 0.0 };
    let x = if x < w { x } else { w };
    ceil_small(x - 0.5) as u32
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;

    proptest! {
        /// Every write of layers that fit comes back from its packing.
        #[test]
        fn writes_unpack_to_themselves(
            cell in 0u32..1 << 31,
            delta: i32,
            row in 0u32..1 << 16,
            cols in (0u32..1 << 17, 0u32..1 << 17),
            target: u32,
        ) {
            for w in [Write::Add { cell, delta }, Write::Widen { row, cols }, Write::Target(target)] {
                prop_assert_eq!(Write::unpack(w.pack()), w);
            }
        }

        /// An instance's counts (overlapping spans: counts above one) moved
        /// into layers that hold another's cover their union there, and so
        /// do the logged writes redone on a copy of those layers; the log
        /// holds a widen and two adds a run of covered pixels per row, and
        /// the instance's layers end empty.
        #[test]
        fn moved_counts_cover_the_union_with_two_writes_a_run(
            own in prop::collection::vec((0u32..6, 0u32..20, 0u32..21), 0..12),
            other in prop::collection::vec((0u32..6, 0u32..20, 0u32..21), 0..6),
        ) {
            let (w, h) = (20u32, 6u32);
            let spans = |list: &[(u32, u32, u32)]| -> Vec<PixelSpan> {
                list.iter()
                    .filter(|(_, a, b)| a < b)
                    .map(|&(row, c0, c1)| PixelSpan { row, c0, c1 })
                    .collect()
            };
            let (own, other) = (spans(&own), spans(&other));
            let mut alone = Layers::new(w, h);
            let mut into = Layers::new(w, h);
            for s in &own {
                alone.span(*s);
            }
            for s in &other {
                into.span(*s);
            }
            let mut copy = into.clone();
            let mut log = Vec::new();
            alone.move_into(&mut into, &mut log);
            for &bits in &log {
                copy.redo(Write::unpack(bits));
            }
            // Each pixel a span of `spans` covers.
            let cover = |spans: &[PixelSpan]| {
                let mut out = vec![false; (w * h) as usize];
                for s in spans {
                    for c in s.c0..s.c1 {
                        out[(s.row * w + c) as usize] = true;
                    }
                }
                out
            };
            let pixels = |layers: &Layers| {
                let mut spans = Vec::new();
                layers.covered_spans(|s| spans.push(s));
                cover(&spans)
            };
            // The reference: each pixel covered by either list.
            let covered = cover(&[own.as_slice(), other.as_slice()].concat());
            prop_assert_eq!(&pixels(&into), &covered);
            prop_assert_eq!(&pixels(&copy), &covered);
            prop_assert!(pixels(&alone).iter().all(|&c| !c));
            prop_assert!(alone.diff.iter().all(|&d| d == 0));
            // Runs of the instance's own coverage, row by row.
            let mine = cover(&own);
            let (mut runs, mut rows) = (0, 0);
            for row in mine.chunks(w as usize) {
                let starts = (0..row.len()).filter(|&c| row[c] && (c == 0 || !row[c - 1])).count();
                runs += starts;
                rows += usize::from(starts > 0);
            }
            let widens = log.iter().filter(|&&b| matches!(Write::unpack(b), Write::Widen { .. })).count();
            prop_assert_eq!(widens, rows);
            prop_assert_eq!(log.len() - widens, 2 * runs);
        }
    }
}
