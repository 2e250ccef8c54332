//! Split rules (CGA's `split`): a scope cut along one axis into parts that
//! partition it, some of fixed length, some stretching, some repeated to fill.

use crate::graph::Axis;

use super::Scope;

/// How long one entry of a split is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SplitSize {
    /// This long (all absolute entries shrink alike when they do not fit,
    /// and grow alike when nothing else can fill the scope).
    Absolute(f32),
    /// Stretches: relative entries and repeated copies share what the
    /// absolute entries leave, in proportion to these nominal lengths.
    Relative(f32),
    /// Copies of about this length, as many as fill the space left (at
    /// least one, at most [`MAX_REPEATS`]); every repeated entry of a split
    /// gets the same number of copies.
    Repeat(f32),
}

/// The most copies one repeated entry makes.
pub const MAX_REPEATS: usize = 1024;

/// One part of a split: the entry it comes from and where it lies along
/// the axis, from the scope's low end.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SplitPart {
    /// Index of the entry in the split's list.
    pub entry: usize,
    /// Distance from the scope's low end.
    pub start: f32,
    /// Length along the axis (positive).
    pub length: f32,
}

/// A length as given: NaN, infinite and negative lengths count as 0.
fn sane(x: f32) -> f32 {
    if x.is_finite() && x > 0.0 { x } else { 0.0 }
}

/// Cuts `extent` into parts, in entry order, appended to `out` (cleared
/// first). The parts partition `[0, extent]`: each starts where the last
/// ended and the last ends at `extent`. Entries that come out with length 0
/// make no part; an extent that is not positive makes none at all.
///
/// The rule, CGA's: absolute entries take their length; what is left is
/// shared by relative entries and repeated copies in proportion to their
/// nominal lengths, the number of copies chosen so that the copies keep
/// about their nominal length. When the absolute entries leave nothing,
/// they shrink alike to fit and the others vanish; when nothing stretches,
/// the absolute entries grow alike to fill.
pub fn split_lengths(extent: f32, sizes: &[SplitSize], out: &mut Vec<SplitPart>) {
    out.clear();
    let extent = sane(extent);
    if extent == 0.0 {
        return;
    }
    let (mut absolute, mut relative, mut repeat) = (0.0f64, 0.0f64, 0.0f64);
    for s in sizes {
        match *s {
            SplitSize::Absolute(x) => absolute += f64::from(sane(x)),
            SplitSize::Relative(x) => relative += f64::from(sane(x)),
            SplitSize::Repeat(x) => repeat += f64::from(sane(x)),
        }
    }
    let extent64 = f64::from(extent);
    let free = extent64 - absolute;
    let stretches = relative + repeat > 0.0;
    // Scale of absolute entries, of stretching ones, and the copies.
    let (scale_abs, scale_rel, copies) = if free > 0.0 && stretches {
        let copies = if repeat > 0.0 {
            let n = ((free - relative) / repeat).round();
            n.clamp(1.0, MAX_REPEATS as f64) as usize
        } else {
            0
        };
        (1.0, free / (relative + copies as f64 * repeat), copies)
    } else if absolute > 0.0 {
        (extent64 / absolute, 0.0, 0)
    } else {
        return;
    };
    let mut at = 0.0f64;
    let mut push = |entry: usize, length: f64, out: &mut Vec<SplitPart>| {
        if length > 0.0 {
            out.push(SplitPart {
                entry,
                start: at as f32,
                length: length as f32,
            });
            at += length;
        }
    };
    for (entry, s) in sizes.iter().enumerate() {
        match *s {
            SplitSize::Absolute(x) => push(entry, f64::from(sane(x)) * scale_abs, out),
            SplitSize::Relative(x) => push(entry, f64::from(sane(x)) * scale_rel, out),
            SplitSize::Repeat(x) => {
                let length = f64::from(sane(x)) * scale_rel;
                for _ in 0..copies {
                    push(entry, length, out);
                }
            }
        }
    }
    // The last part ends at the extent exactly, whatever the rounding.
    if let Some(last) = out.last_mut() {
        last.length = (extent - last.start).max(0.0);
    }
}

impl Scope {
    /// The scope cut along `axis` into the parts of `sizes` (see
    /// [`split_lengths`]), in order from the low end: each part's entry and
    /// its scope (the same frame moved to the part's centre, the same size
    /// but along `axis`).
    #[must_use]
    pub fn split(&self, axis: Axis, sizes: &[SplitSize]) -> Vec<(usize, Scope)> {
        let mut parts = Vec::new();
        let k = axis.index();
        let extent = self.size[k];
        split_lengths(extent, sizes, &mut parts);
        parts
            .iter()
            .map(|p| {
                let mut s = *self;
                let mut offset = glam::Vec3::ZERO;
                offset[k] = -0.5 * extent + p.start + 0.5 * p.length;
                s.translate(offset);
                s.size[k] = p.length;
                (p.entry, s)
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn size() -> impl Strategy<Value = SplitSize> {
        let len = prop_oneof![
            4 => 0.0f32..5.0,
            1 => Just(0.0f32),
            1 => Just(-1.0f32),
            1 => Just(f32::NAN),
            1 => 1e-4f32..1e-2,
        ];
        (0..3u8, len).prop_map(|(k, x)| match k {
            0 => SplitSize::Absolute(x),
            1 => SplitSize::Relative(x),
            _ => SplitSize::Repeat(x),
        })
    }

    proptest! {
        /// The parts partition the extent: no gap, no overlap, in entry order.
        #[test]
        fn parts_partition_the_extent(
            extent in prop_oneof![0.01f32..100.0, Just(0.0), Just(-2.0)],
            sizes in prop::collection::vec(size(), 0..8),
        ) {
            let mut out = Vec::new();
            split_lengths(extent, &sizes, &mut out);
            if out.is_empty() {
                // Nothing to cut, or nothing with a length.
                let any = sizes.iter().any(|s| match *s {
                    SplitSize::Absolute(x) | SplitSize::Relative(x) | SplitSize::Repeat(x) => sane(x) > 0.0,
                });
                prop_assert!(extent <= 0.0 || !any);
                return Ok(());
            }
            let tol = 1e-5 * extent;
            prop_assert!(out[0].start.abs() <= tol);
            for w in out.windows(2) {
                prop_assert!((w[0].start + w[0].length - w[1].start).abs() <= tol, "{w:?}");
                prop_assert!(w[0].entry <= w[1].entry);
            }
            let last = out.last().unwrap();
            prop_assert!((last.start + last.length - extent).abs() <= tol);
            prop_assert!(out.iter().all(|p| p.length >= 0.0 && p.start.is_finite()));
        }
    }

    #[test]
    fn a_facade_of_floors() {
        let mut out = Vec::new();
        // Ground floor 4, floors of about 3 repeated, a 0.5 ledge: 20 high.
        let sizes = [
            SplitSize::Absolute(4.0),
            SplitSize::Repeat(3.0),
            SplitSize::Absolute(0.5),
        ];
        split_lengths(20.0, &sizes, &mut out);
        let entries: Vec<usize> = out.iter().map(|p| p.entry).collect();
        assert_eq!(entries, [0, 1, 1, 1, 1, 1, 2]); // 15.5 / 3 ≈ 5 floors
        assert!((out[1].length - 3.1).abs() < 1e-5);
        assert!((out[6].start - 19.5).abs() < 1e-5);
    }

    #[test]
    fn absolute_parts_shrink_when_they_do_not_fit() {
        let mut out = Vec::new();
        let sizes = [
            SplitSize::Absolute(3.0),
            SplitSize::Relative(1.0),
            SplitSize::Absolute(1.0),
        ];
        split_lengths(2.0, &sizes, &mut out);
        let got: Vec<(usize, f32)> = out.iter().map(|p| (p.entry, p.length)).collect();
        assert_eq!(got, [(0, 1.5), (2, 0.5)]);
    }

    #[test]
    fn scopes_tile_the_parent() {
        let mut parent = Scope::UNIT;
        parent.set_size(glam::Vec3::new(2.0, 6.0, 1.0));
        parent.rotate_y(0.3);
        let parts = parent.split(Axis::Y, &[SplitSize::Repeat(2.0)]);
        assert_eq!(parts.len(), 3);
        for (k, (_, s)) in parts.iter().enumerate() {
            assert!((s.size.y - 2.0).abs() < 1e-6);
            let expected =
                parent
                    .frame
                    .transform_point3(glam::Vec3::new(0.0, -2.0 + 2.0 * k as f32, 0.0));
            assert!(s.origin().abs_diff_eq(expected, 1e-5));
        }
    }
}
