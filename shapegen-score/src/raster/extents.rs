//! Which part of each row of an image may hold anything, so that reading
//! and clearing cost what was touched, not the image.

use std::ops::Range;

/// Per row, the part `(start, end)` that may hold non-zero values (empty:
/// `(u32::MAX, 0)`), and the rows that may have a non-empty part. The
/// units are the holder's: cells of [`Layers`](super::Layers), words of
/// [`Coverage`](super::Coverage).
#[derive(Clone, Debug, Default)]
pub(crate) struct RowExtents {
    parts: Vec<(u32, u32)>,
    /// `rows.0..rows.1`; `(height, 0)` when none.
    rows: (u32, u32),
}

impl RowExtents {
    /// No part of any of `height` rows.
    pub(crate) fn new(height: u32) -> Self {
        Self {
            parts: vec![(u32::MAX, 0); height as usize],
            rows: (height, 0),
        }
    }

    /// The rows that may have a non-empty part.
    pub(crate) fn rows(&self) -> Range<u32> {
        self.rows.0..self.rows.1
    }

    /// Row `r`'s part (empty if it has none).
    #[inline]
    pub(crate) fn get(&self, r: u32) -> (u32, u32) {
        self.parts[r as usize]
    }

    /// Widens the parts of rows `rows.0..rows.1` to hold `part`.
    #[inline]
    pub(crate) fn widen(&mut self, rows: (u32, u32), part: (u32, u32)) {
        if rows.0 >= rows.1 {
            return;
        }
        self.rows = (self.rows.0.min(rows.0), self.rows.1.max(rows.1));
        for p in &mut self.parts[rows.0 as usize..rows.1 as usize] {
            *p = (p.0.min(part.0), p.1.max(part.1));
        }
    }

    /// Calls `f` with each row's non-empty part, in order, and leaves
    /// every part empty.
    pub(crate) fn take_each(&mut self, mut f: impl FnMut(u32, (u32, u32))) {
        for r in self.rows() {
            let p = std::mem::replace(&mut self.parts[r as usize], (u32::MAX, 0));
            if p.0 < p.1 {
                f(r, p);
            }
        }
        self.rows = (self.parts.len() as u32, 0);
    }
}
