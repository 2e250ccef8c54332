//! `[score]`: the score form and its weights, for a volume or an image scene.

use super::Ctx;
use crate::experiment::ExperimentError;
use crate::experiment::file::{ExperimentFile, ScoreForm};
use crate::score::OverlapCount;
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
    /// The table's weights (finite), with defaults for those left out; keys
    /// the form does not read, and weights that are all 0, are errors.
    pub fn from_file(ctx: &Ctx<'_>, f: &ExperimentFile) -> Result<Self, ExperimentError> {
        let s = f.score.get_ref();
        let err = |m: String| Err(ctx.err("score", &f.score, m));
        let given = [s.good, s.bad, s.length, s.overlap, s.self_weight];
        if let Some(w) = given.iter().flatten().find(|w| !w.is_finite()) {
            return err(format!("weights must be finite, got {w}"));
        }
        // Keys the chosen form does not read would be ignored silently.
        let (form, reads, unused) = match s.form {
            ScoreForm::Normalized => (
                "normalized",
                "good, bad, length and overlap",
                vec![("self", s.self_weight)],
            ),
            ScoreForm::Paper => (
                "paper",
                "self and the targets' own weights (fill and outside; target and background)",
                vec![
                    ("good", s.good),
                    ("bad", s.bad),
                    ("length", s.length),
                    ("overlap", s.overlap),
                ],
            ),
        };
        let unused: Vec<&str> = unused
            .iter()
            .filter(|(_, v)| v.is_some())
            .map(|(k, _)| *k)
            .collect();
        if !unused.is_empty() {
            return err(format!(
                "the {form} form does not use `{}`: it reads {reads}; drop the key or change `form`",
                unused.join("`, `")
            ));
        }
        let weights = Self {
            form: s.form,
            good: s.good.unwrap_or(DEFAULT_GOOD),
            bad: s.bad.unwrap_or(DEFAULT_BAD),
            length: s.length.unwrap_or(DEFAULT_LENGTH),
            overlap: s.overlap,
            self_weight: s.self_weight,
        };
        let all = [
            weights.good,
            weights.bad,
            weights.length,
            weights.overlap.unwrap_or(0.0),
        ];
        if weights.form == ScoreForm::Normalized && all.iter().all(|&w| w == 0.0) {
            return err("every weight is 0: every model would score 0".into());
        }
        Ok(weights)
    }

    /// Warnings about weights that pass but likely say the opposite of what
    /// was meant: a negative weight of the normalized form rewards what it
    /// is named to penalize (or penalizes what it is named to reward).
    pub fn warnings(&self) -> Vec<String> {
        if self.form != ScoreForm::Normalized {
            return Vec::new();
        }
        [
            ("good", Some(self.good)),
            ("bad", Some(self.bad)),
            ("length", Some(self.length)),
            ("overlap", self.overlap),
        ]
        .into_iter()
        .filter_map(|(key, w)| w.filter(|w| *w < 0.0).map(|w| (key, w)))
        .map(|(key, w)| {
            format!(
                "[score] {key} = {w} is negative: the normalized form's weights are magnitudes (a negative `{key}` turns its term around); use {} if that was not meant",
                -w
            )
        })
        .collect()
    }

    /// Whether this is the paper's linear form (which reads the targets'
    /// own weights).
    pub fn is_paper(&self) -> bool {
        self.form == ScoreForm::Paper
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
