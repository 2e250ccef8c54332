//! A run's progress curve: one row per generation, and `curve.csv`.

use std::fmt::Write as _;

use crate::optimize::GenerationStats;
use serde::{Deserialize, Serialize};

/// One generation of a run.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Row {
    /// Generation (0 = the initial population).
    pub generation: u64,
    /// Seconds since the run started.
    pub seconds: f64,
    /// Evaluations so far.
    pub evaluations: u64,
    /// Best fitness so far (NaN until a valid model exists).
    #[serde(with = "nan_as_null")]
    pub best: f64,
    /// Mean fitness of the generation.
    #[serde(with = "nan_as_null")]
    pub mean: f64,
    /// Standard deviation of the generation's fitness.
    #[serde(with = "nan_as_null")]
    pub std: f64,
}

impl Row {
    /// The row of one generation.
    pub fn of(s: &GenerationStats<'_>) -> Self {
        Self {
            generation: s.generation,
            seconds: s.elapsed.as_secs_f64(),
            evaluations: s.evaluations,
            best: s.best_so_far,
            mean: s.mean,
            std: s.std,
        }
    }
}

/// The rows as CSV (`generation,seconds,evaluations,best,mean,std`; empty
/// fields for undefined values).
pub fn to_csv(rows: &[Row]) -> String {
    let mut out = String::from("generation,seconds,evaluations,best,mean,std\n");
    for r in rows {
        let _ = writeln!(
            out,
            "{},{:.6},{},{},{},{}",
            r.generation,
            r.seconds,
            r.evaluations,
            number(r.best),
            number(r.mean),
            number(r.std)
        );
    }
    out
}

/// A finite number, or an empty field.
pub fn number(x: f64) -> String {
    if x.is_finite() {
        x.to_string()
    } else {
        String::new()
    }
}

/// JSON has no NaN: store non-finite values as `null`.
mod nan_as_null {
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
        if x.is_finite() {
            s.serialize_f64(*x)
        } else {
            s.serialize_none()
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
    }
}
