//! Which pixels of an image a model covers, a bit a pixel: the union of
//! its instances' coverage, each instance's added as runs of covered
//! pixels (see [`Layers::take_runs`](super::Layers::take_runs)). A union
//! needs no counts, so a run is a few word ORs into a bitmap small enough
//! for the processor's caches (60 KB for 800 × 600 pixels), and the
//! model's pixels are read 64 at a time.

use super::Layers;
use super::extents::RowExtents;

/// Bits of a word of [`Coverage`].
pub(crate) const WORD: u32 = 64;

/// A bit a pixel, row-major, `words` words a row (bit `c % 64` of word
/// `c / 64` is column `c`); every bit outside the extents is zero.
#[derive(Clone, Debug, Default)]
pub(crate) struct Coverage {
    width: u32,
    height: u32,
    words: usize,
    bits: Vec<u64>,
    /// Per row, the words that may hold set bits.
    extents: RowExtents,
}

impl Coverage {
    /// Nothing covered, for a `width × height` image.
    pub(crate) fn new(width: u32, height: u32) -> Self {
        let words = width.div_ceil(WORD) as usize;
        Self {
            width,
            height,
            words,
            bits: vec![0; words * height as usize],
            extents: RowExtents::new(height),
        }
    }

    /// The image's width and height.
    pub(crate) fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// Words a row.
    pub(crate) fn words(&self) -> usize {
        self.words
    }

    /// Uncovers every pixel, at the cost of the words touched.
    pub(crate) fn clear(&mut self) {
        let Self {
            bits,
            extents,
            words,
            ..
        } = self;
        extents.take_each(|r, (w0, w1)| {
            let base = r as usize * *words;
            bits[base + w0 as usize..base + w1 as usize].fill(0);
        });
    }

    /// Covers the pixels `c0..c1` of row `row` (`c0 < c1 <= width`,
    /// `row < height`).
    #[inline]
    pub(crate) fn add_run(&mut self, row: u32, c0: u32, c1: u32) {
        debug_assert!(c0 < c1 && c1 <= self.width && row < self.height);
        let (w0, w1) = (c0 / WORD, (c1 - 1) / WORD);
        self.extents.widen((row, row + 1), (w0, w1 + 1));
        let base = row as usize * self.words;
        // Bits from c0 on in the first word, to c1 − 1 in the last.
        let first = u64::MAX << (c0 % WORD);
        let last = u64::MAX >> (WORD - 1 - (c1 - 1) % WORD);
        if w0 == w1 {
            self.bits[base + w0 as usize] |= first & last;
        } else {
            let words = &mut self.bits[base + w0 as usize..=base + w1 as usize];
            let n = words.len();
            words[0] |= first;
            // Word by word: most runs cover a word or two, and `fill`
            // called the library's memset for every one, even when empty.
            for w in &mut words[1..n - 1] {
                *w = u64::MAX;
            }
            words[n - 1] |= last;
        }
    }

    /// Calls `f` with every word of pixels covered here or by `layers`
    /// (of the same size: a pixel is covered there if its count is
    /// positive), as `(row, word, bits)`, row by row, left to right, over
    /// the words either may cover (others hold no pixel of either). The
    /// layers' differences are summed cell by cell over their rows' parts,
    /// so an instance drawn into them costs what its box holds, as the
    /// model's other instances in the coverage cost their words.
    #[inline]
    pub(crate) fn with_layers(&self, layers: &Layers, mut f: impl FnMut(u32, u32, u64)) {
        let (mine, theirs) = (self.extents.rows(), layers.row_range());
        // Rows outside either range have empty parts there.
        for r in mine.start.min(theirs.start)..mine.end.max(theirs.end) {
            let (w0, w1) = self.extents.get(r);
            let ((c0, c1), diff) = layers.row(r);
            // The words of pixels the layers' part may cover (the last
            // cell, right of the image, counts for no pixel).
            let c1 = c1.min(self.width);
            let (d0, d1) = if c0 < c1 {
                (c0 / WORD, c1.div_ceil(WORD))
            } else {
                (u32::MAX, 0)
            };
            let (k0, k1) = (w0.min(d0), w1.max(d1));
            let base = r as usize * self.words;
            let mut count = 0;
            for k in k0..k1 {
                let mut bits = if (w0..w1).contains(&k) {
                    self.bits[base + k as usize]
                } else {
                    0
                };
                if (d0..d1).contains(&k) {
                    // The word's cells within the part (the count is zero
                    // before it, and all cells after it are zero).
                    let (a, b) = ((k * WORD).max(c0), ((k + 1) * WORD).min(c1));
                    let mut flags = [0u8; WORD as usize];
                    let at = (a - k * WORD) as usize;
                    for (flag, &d) in flags[at..].iter_mut().zip(&diff[a as usize..b as usize]) {
                        count += d;
                        *flag = u8::from(count > 0);
                    }
                    bits |= pack_flags(&flags);
                }
                f(r, k, bits);
            }
        }
    }
}

/// The 64 flags (0 or 1) as the bits of a word, flag `i` in bit `i`: 8
/// at a time by one multiply, which moves byte `i`'s low bit to bit
/// `56 + i` (the products of other bytes all land elsewhere, without
/// carries). One variable shift a flag would cost more (a shift by a
/// register is three operations on x86-64).
#[inline]
fn pack_flags(flags: &[u8; WORD as usize]) -> u64 {
    let mut bits = 0;
    for (i, eight) in flags.chunks_exact(8).enumerate() {
        let x = u64::from_le_bytes(eight.try_into().expect("8 bytes"));
        bits |= (x.wrapping_mul(0x0102_0408_1020_4080) >> 56) << (8 * i);
    }
    bits
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;
    use crate::raster::PixelSpan;

    proptest! {
        /// Flags pack to the bits a loop sets one by one.
        #[test]
        fn flags_pack_to_their_bits(flags in prop::array::uniform32(0u8..2), more in prop::array::uniform32(0u8..2)) {
            let mut all = [0u8; 64];
            all[..32].copy_from_slice(&flags);
            all[32..].copy_from_slice(&more);
            let expected = all.iter().enumerate().fold(0u64, |b, (i, &f)| b | u64::from(f) << i);
            prop_assert_eq!(pack_flags(&all), expected);
        }

        /// Runs added to the coverage (overlapping, touching, across words,
        /// at the image's edges) and spans drawn into layers (overlapping:
        /// counts above one) are read together as their union, only over
        /// words either touched; cleared, nothing is left.
        #[test]
        fn runs_and_layers_cover_their_union(
            width in prop_oneof![Just(64u32), Just(128), 1u32..200],
            runs in prop::collection::vec((0u32..5, 0.0..1.0f64, 0.0..1.0f64), 0..16),
            spans in prop::collection::vec((0u32..5, 0.0..1.0f64, 0.0..1.0f64), 0..8),
        ) {
            let h = 5;
            let mut coverage = Coverage::new(width, h);
            let mut layers = Layers::new(width, h);
            let mut expected = vec![false; (width * h) as usize];
            let mut touched = vec![false; coverage.words() * h as usize];
            let cols = |a: f64, b: f64| {
                let (a, b) = ((a * f64::from(width)) as u32, (b * f64::from(width + 1)) as u32);
                (a.min(b), a.max(b).min(width))
            };
            for (i, (row, a, b)) in runs.into_iter().chain(spans).enumerate() {
                let (c0, c1) = cols(a, b);
                if c0 >= c1 {
                    continue;
                }
                if i < 16 && i % 2 == 0 {
                    coverage.add_run(row, c0, c1);
                } else {
                    layers.span(PixelSpan { row, c0, c1 });
                }
                expected[(row * width + c0) as usize..(row * width + c1) as usize].fill(true);
                for k in c0 / WORD..c1.div_ceil(WORD) {
                    touched[row as usize * coverage.words() + k as usize] = true;
                }
            }
            let mut got = vec![false; (width * h) as usize];
            let mut read = vec![false; touched.len()];
            coverage.with_layers(&layers, |row, k, bits| {
                read[row as usize * coverage.words() + k as usize] = true;
                for j in 0..WORD {
                    if bits >> j & 1 == 1 {
                        got[(row * width + k * WORD + j) as usize] = true;
                    }
                }
            });
            prop_assert_eq!(got, expected);
            // Every word touched is read (the layers may widen a row by a
            // word or so more, no further).
            prop_assert!(touched.iter().zip(&read).all(|(&t, &r)| r || !t));
            coverage.clear();
            layers.clear();
            prop_assert!(coverage.bits.iter().all(|&b| b == 0));
            let mut any = false;
            coverage.with_layers(&layers, |_, _, bits| any |= bits != 0);
            prop_assert!(!any);
        }
    }
}
