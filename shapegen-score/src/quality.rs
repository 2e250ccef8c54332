//! Quality figures a person can read beside a fitness: intersection over
//! union, precision and recall of a model's cells (or pixels) against one
//! target's.
//!
//! A normalized score saturates near its optimum (0.998 may still be a
//! visibly imperfect fit); these figures do not: an IoU of 0.9 means a
//! tenth of the union is wrong.

/// How well a model covers one target.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Quality {
    /// Cells (pixels) in both, over cells in either: 1 is a perfect fit.
    pub iou: f64,
    /// The share of the model's cells that lie in the target (0 for an
    /// empty model).
    pub precision: f64,
    /// The share of the target's cells the model covers.
    pub recall: f64,
    /// Cells (pixels) the model covers.
    pub model: u64,
}

impl Quality {
    /// From the cells in `both`, the `model`'s cells and the `target`'s
    /// (`both <= model`, `both <= target`). Empty sets give 0, never NaN.
    #[must_use]
    pub fn from_counts(both: u64, model: u64, target: u64) -> Self {
        let ratio = |a: u64, b: u64| if b == 0 { 0.0 } else { a as f64 / b as f64 };
        Self {
            iou: ratio(both, (model + target).saturating_sub(both)),
            precision: ratio(both, model),
            recall: ratio(both, target),
            model,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn figures_of_known_overlaps() {
        // 6 model cells, 8 target cells, 4 in both: union 10.
        let q = Quality::from_counts(4, 6, 8);
        assert_eq!((q.iou, q.precision, q.recall), (0.4, 4.0 / 6.0, 0.5));
        assert_eq!(Quality::from_counts(5, 5, 5).iou, 1.0);
        assert_eq!(Quality::from_counts(0, 0, 5), Quality::default());
        assert_eq!(Quality::from_counts(0, 3, 0).iou, 0.0);
    }
}
