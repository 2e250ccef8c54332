//! How many triangles cover each pixel centre of an image, kept as
//! differences along each row: a crossing of a row by an edge adds its
//! winding contribution at the first column right of it, and a running sum
//! along the row gives every centre's count. Counts add over instances, so
//! a whole model is filled without ever sorting crossings or painting a
//! span, and read once: a pixel is covered iff its count is positive.

use super::extents::RowExtents;
use super::{PixelSpan, ceil_small};

/// Cells [`Layers::take_runs`] tests at once.
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
    /// Per row, the cells that may be non-zero.
    extents: RowExtents,
}

impl Layers {
    /// All-zero counts for a `width × height` image.
    pub(crate) fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            diff: vec![0; (width as usize + 1) * height as usize],
            extents: RowExtents::new(height),
        }
    }

    /// The image's width and height.
    pub(crate) fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// Sets every count back to zero, at the cost of what was touched.
    pub(crate) fn clear(&mut self) {
        let stride = self.width as usize + 1;
        let Self { diff, extents, .. } = self;
        extents.take_each(|r, (c0, c1)| {
            let base = r as usize * stride;
            diff[base + c0 as usize..base + c1 as usize].fill(0);
        });
    }

    /// Widens the part that may hold non-zero differences to the cells
    /// `cols.0..cols.1` of the rows `rows.0..rows.1` (`cols.1 <= width + 1`).
    pub(crate) fn widen(&mut self, rows: (u32, u32), cols: (u32, u32)) {
        self.extents.widen(rows, cols);
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

    /// Calls `f` with the runs of covered pixels (positive count) as
    /// `(row, c0, c1)`, row by row, left to right, each maximal and none
    /// empty, and sets every count back to zero: the same runs as
    /// [`covered_spans`](Self::covered_spans), found by testing blocks of
    /// the differences at once (most of an instance's box holds none).
    pub(crate) fn take_runs(&mut self, mut f: impl FnMut(u32, u32, u32)) {
        let (width, stride) = (self.width, self.width as usize + 1);
        let Self { diff, extents, .. } = self;
        extents.take_each(|r, (c0, c1)| {
            let base = r as usize * stride;
            let cells = &mut diff[base + c0 as usize..base + c1 as usize];
            let (mut count, mut start) = (0i32, None);
            let mut col = c0;
            // A block of zeros changes neither the count nor the coverage;
            // the test of a block at once vectorizes.
            for block in cells.chunks_mut(BLOCK) {
                if block.iter().fold(0, |any, &d| any | d) != 0 {
                    for (j, d) in block.iter_mut().enumerate() {
                        count += std::mem::take(d);
                        let c = (col + j as u32).min(width);
                        match (count > 0, start) {
                            (true, None) => start = Some(c),
                            (false, Some(s)) => {
                                if s < c {
                                    f(r, s, c);
                                }
                                start = None;
                            }
                            _ => {}
                        }
                    }
                }
                col += BLOCK as u32;
            }
            if let Some(s) = start {
                // Only a count that does not return to zero (absurd
                // coordinates) leaves a run open at the last cell.
                let end = c1.min(width);
                if s < end {
                    f(r, s, end);
                }
            }
        });
    }

    /// Calls `f` with each row that may hold covered pixels, its first
    /// column, and the differences from there (to one past the last cell
    /// that may be non-zero; the count is zero left of them).
    pub(crate) fn rows(&self, mut f: impl FnMut(u32, u32, &[i32])) {
        let stride = self.width as usize + 1;
        for r in self.extents.rows() {
            let (c0, c1) = self.extents.get(r);
            if c0 < c1 {
                let base = r as usize * stride;
                f(r, c0, &self.diff[base + c0 as usize..base + c1 as usize]);
            }
        }
    }

    /// The rows that may hold non-zero differences.
    pub(crate) fn row_range(&self) -> std::ops::Range<u32> {
        self.extents.rows()
    }

    /// Row `r`'s cells that may be non-zero, `c0..c1` (empty if none), and
    /// all of its `width + 1` differences.
    #[inline]
    pub(crate) fn row(&self, r: u32) -> ((u32, u32), &[i32]) {
        let stride = self.width as usize + 1;
        let base = r as usize * stride;
        (self.extents.get(r), &self.diff[base..base + stride])
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
        /// An instance's counts (overlapping spans: counts above one) give
        /// the same runs taken as read by `covered_spans`, which cover the
        /// spans' union, and end all zero.
        #[test]
        fn taken_runs_are_the_covered_spans(
            own in prop::collection::vec((0u32..6, 0u32..20, 0u32..21), 0..12),
        ) {
            let (w, h) = (20u32, 6u32);
            let mut layers = Layers::new(w, h);
            let mut covered = vec![false; (w * h) as usize];
            for &(row, c0, c1) in own.iter().filter(|(_, a, b)| a < b) {
                layers.span(PixelSpan { row, c0, c1 });
                covered[(row * w + c0) as usize..(row * w + c1) as usize].fill(true);
            }
            let mut read = Vec::new();
            layers.covered_spans(|s| read.push(s));
            let mut taken = Vec::new();
            layers.take_runs(|row, c0, c1| taken.push(PixelSpan { row, c0, c1 }));
            prop_assert_eq!(&taken, &read);
            let mut union = vec![false; (w * h) as usize];
            for s in &taken {
                union[(s.row * w + s.c0) as usize..(s.row * w + s.c1) as usize].fill(true);
            }
            prop_assert_eq!(union, covered);
            prop_assert!(layers.diff.iter().all(|&d| d == 0));
            let mut left = 0;
            layers.covered_spans(|_| left += 1);
            prop_assert_eq!(left, 0);
        }
    }
}
