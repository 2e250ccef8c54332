//! `[score]`: the score form and its weights, for a volume or an image scene.

use super::Ctx;
use crate::experiment::ExperimentError;
use crate::experiment::file::{ExperimentFile, ScoreForm};
use crate::score::score::OverlapCount;
use crate::score::{ImageScore, VolumeScore};

/// `w_good`, `w_bad` and `w_length` when the file leaves them out.
const DEFAULT_GOOD: f64 = 1.0;
const DEFAULT_BAD: f64 = 1.0;
const DEFAULT_LENGTH: f64 = 0.0;

/// The checked `[score]` table.
pub(super) struct Weights {
    form: ScoreForm,
    good: f64,
    bad: f64,
    length: f64,
    overlap: Option<f64>,
    self_weight: Option<f64>,
}

impl Weights {
    /// The table's weights (finite), with defaults for those left out.
    pub fn from_file(ctx: &Ctx<'_>, f: &ExperimentFile) -> Result<Self, ExperimentError> {
        let s = f.score.get_ref();
        let given = [s.good, s.bad, s.length, s.overlap, s.self_weight];
        if let Some(w) = given.iter().flatten().find(|w| !w.is_finite()) {
            return Err(ctx.err(
                "score",
                &f.score,
                format!("weights must be finite, got {w}"),
            ));
        }
        Ok(Self {
            form: s.form,
            good: s.good.unwrap_or(DEFAULT_GOOD),
            bad: s.bad.unwrap_or(DEFAULT_BAD),
            length: s.length.unwrap_or(DEFAULT_LENGTH),
            overlap: s.overlap,
            self_weight: s.self_weight,
        })
    }

    /// The volume score.
    pub fn volume(&self) -> VolumeScore {
        match self.form {
            ScoreForm::Normalized => VolumeScore::Normalized {
                w_good: self.good,
                w_bad: self.bad,
                w_length: self.length,
                separate_overlap: self.overlap,
            },
            ScoreForm::Paper => VolumeScore::Linear {
                w_self: self.self_weight.unwrap_or(0.0),
                overlap: OverlapCount::Cells,
            },
        }
    }

    /// The image score; `overlap` and `self` are refused.
    pub fn image(&self, ctx: &Ctx<'_>, f: &ExperimentFile) -> Result<ImageScore, ExperimentError> {
        if self.overlap.is_some() || self.self_weight.is_some() {
            return Err(ctx.err(
                "score",
                &f.score,
                "`overlap` and `self` apply to volume scenes only",
            ));
        }
        Ok(match self.form {
            ScoreForm::Normalized => ImageScore::Normalized {
                w_good: self.good,
                w_bad: self.bad,
                w_length: self.length,
            },
            ScoreForm::Paper => ImageScore::Linear,
        })
    }
}
