//! What can go wrong with an experiment.

use std::ops::Range;
use std::path::{Path, PathBuf};

use crate::genome::GenomeError;
use crate::optimize::OptimizeError;
use crate::score::ScoreError;

/// An experiment that cannot be loaded, run or written out.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ExperimentError {
    /// The file cannot be read.
    #[error("{}: cannot read the experiment: {source}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// A path that is not a regular file (a directory, a pipe, a device).
    #[error("cannot read the experiment: {why}")]
    NotAFile {
        /// The path.
        path: PathBuf,
        /// What it is instead.
        why: String,
    },
    /// A key of the file is missing, unknown or has an unusable value.
    #[error("{file}:{line}:{column}: {}{message}", key_prefix(key))]
    Invalid {
        /// The file (or `<built-in>`).
        file: String,
        /// 1-based line of the offending key or value.
        line: usize,
        /// 1-based column.
        column: usize,
        /// Dotted path of the key (`ga.population`, `volume.targets[0].mesh`), empty for syntax errors.
        key: String,
        /// What is wrong.
        message: String,
    },
    /// A method the experiment cannot run.
    #[error("unknown method `{0}`: use ga, smc, sosmc or rjmcmc")]
    UnknownMethod(String),
    /// The run's budget sets no limit.
    #[error(
        "no budget for method `{0}`: give --seconds, or a [budget] table or a budget in the method's table"
    )]
    NoBudget(String),
    /// A chromosome that does not belong to the experiment's generator.
    #[error("{}: not a chromosome of this experiment's generator: {source}", path.display())]
    Chromosome {
        /// The file.
        path: PathBuf,
        /// Why.
        source: Box<GenomeError>,
    },
    /// Writing an output failed.
    #[error("cannot write {}: {reason}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// Why.
        reason: String,
    },
    /// The optimizer refused to run.
    #[error(transparent)]
    Optimize(#[from] OptimizeError),
    /// Scoring geometry failed.
    #[error(transparent)]
    Score(#[from] ScoreError),
    /// Making a picture or gallery failed.
    #[error(transparent)]
    Gallery(#[from] crate::gallery::GalleryError),
    /// A learned prior (`learned.json`) that cannot be used.
    #[error("{}: cannot use the learned prior: {source}", path.display())]
    Prior {
        /// The file.
        path: PathBuf,
        /// Why.
        source: Box<crate::design::DesignError>,
    },
}

fn key_prefix(key: &str) -> String {
    if key.is_empty() {
        String::new()
    } else {
        format!("`{key}`: ")
    }
}

impl ExperimentError {
    /// An output file could not be written.
    pub fn write(path: &Path, reason: impl std::fmt::Display) -> Self {
        Self::Write {
            path: path.to_path_buf(),
            reason: reason.to_string(),
        }
    }
}

/// The text of an experiment file, to turn byte spans into lines and columns.
pub(super) struct Source<'a> {
    pub name: &'a str,
    pub text: &'a str,
}

impl Source<'_> {
    /// An [`ExperimentError::Invalid`] at `span`.
    pub fn error(
        &self,
        key: &str,
        span: Range<usize>,
        message: impl Into<String>,
    ) -> ExperimentError {
        let at = span.start.min(self.text.len());
        let before = &self.text[..at];
        let line = before.matches('\n').count() + 1;
        let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
        ExperimentError::Invalid {
            file: self.name.to_string(),
            line,
            column,
            key: key.to_string(),
            message: message.into(),
        }
    }
}
