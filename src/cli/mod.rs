//! The `shapegen` command line: `run`, `compare` and `render`.

pub mod args;
mod compare;
mod curve;
mod plot;
mod render;
mod run;

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

use shapegen::experiment::{Experiment, ExperimentError, LoadOptions};

pub use args::{Cli, Command};
pub use compare::compare;
pub use render::render;
pub use run::run;

/// An error for the user.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// From the experiment (loading, running, writing).
    #[error(transparent)]
    Experiment(#[from] ExperimentError),
    /// Anything else, as a sentence.
    #[error("{0}")]
    Message(String),
}

impl CliError {
    /// An error from a message.
    pub fn msg(m: impl Into<String>) -> Self {
        Self::Message(m.into())
    }
}

static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// Makes Ctrl-C stop the run cleanly after the current generation (the
/// results so far are written); a second Ctrl-C exits at once.
pub fn catch_interrupts() {
    let installed = ctrlc::set_handler(|| {
        if INTERRUPTED.swap(true, Ordering::SeqCst) {
            std::process::exit(130);
        }
        eprintln!("\nshapegen: stopping after this generation (Ctrl-C again to quit at once)");
    });
    if let Err(e) = installed {
        eprintln!("shapegen: warning: cannot catch Ctrl-C: {e}");
    }
}

/// Whether Ctrl-C was pressed.
pub fn interrupted() -> bool {
    INTERRUPTED.load(Ordering::SeqCst)
}

/// The experiment file at `path`, or the built-in one.
fn load_experiment(path: Option<&Path>, data: Option<&Path>) -> Result<Experiment, CliError> {
    let mut options = LoadOptions::from_env();
    if let Some(d) = data {
        options.data = Some(d.to_path_buf());
    }
    Ok(match path {
        Some(p) => Experiment::load(p, &options)?,
        None => Experiment::builtin(),
    })
}

/// A `--seconds` value as a duration (finite and > 0).
fn seconds(s: f64) -> Result<std::time::Duration, CliError> {
    if s > 0.0 && s.is_finite() {
        Ok(std::time::Duration::from_secs_f64(s))
    } else {
        Err(CliError::msg(format!("--seconds must be > 0, got {s}")))
    }
}

/// A rayon pool with `threads` workers (default: all cores).
fn thread_pool(threads: Option<usize>) -> Result<rayon::ThreadPool, CliError> {
    if threads == Some(0) {
        return Err(CliError::msg("--threads must be at least 1"));
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build()
        .map_err(|e| CliError::msg(format!("cannot start worker threads: {e}")))
}
