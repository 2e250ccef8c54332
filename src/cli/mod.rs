//! The `shapegen` command line as a library: `run`, `compare`, `render` and `gallery`
//! for the built-in generators and a program's own (feature `cli`, on by
//! default).
//!
//! A program that declares its own generator gets the whole command line
//! (progress, checkpoint and resume, Ctrl-C, `compare`, `curves.png`) for
//! it in a few lines, and its experiment files can name it:
//!
//! ```no_run
//! use shapegen::cli::Cli;
//! use shapegen::scenes::Spaceship; // stands for the program's own generator
//!
//! fn main() -> std::process::ExitCode {
//!     Cli::new().generator("my_ship", Spaceship).run()
//! }
//! ```
//!
//! `examples/custom_generator.rs` is a complete program.

#[macro_use]
mod say;
pub mod args;
mod compare;
mod design;
mod gallery;
mod guard;
mod plot;
mod progress;
mod render;
mod run;
mod saved;
mod transform;
mod variations;

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Parser;

use crate::experiment::{BUILTIN, Experiment, ExperimentError, LoadOptions};
use crate::express::Generator;
use crate::registry::Registry;
use args::{Args, Command};
use guard::catch_interrupts;

pub use progress::Progress;
pub use saved::SavedRun;

/// An error for the user.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// From the experiment (loading, running, writing).
    #[error(transparent)]
    Experiment(#[from] ExperimentError),
    /// The command line itself (unknown flag, bad value, `--help`).
    #[error("{0}")]
    Args(#[from] clap::Error),
    /// The user stopped the run (Ctrl-C, SIGTERM) before its budget; the
    /// results so far were written. Exit status 130.
    #[error("interrupted before the budget was spent; the results so far are in {}", .0.display())]
    Interrupted(PathBuf),
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

impl From<crate::score::ScoreError> for CliError {
    fn from(e: crate::score::ScoreError) -> Self {
        Self::Experiment(e.into())
    }
}

/// The command line for a set of generators.
#[derive(Debug, Clone)]
pub struct Cli {
    registry: Registry,
    /// Name, TOML text and the folder its relative paths resolve against.
    default_experiment: (String, String, PathBuf),
}

impl Default for Cli {
    fn default() -> Self {
        Self::new()
    }
}

impl Cli {
    /// The built-in generators, with the built-in experiment as the default
    /// (what `shapegen run` uses without an experiment file).
    #[must_use]
    pub fn new() -> Self {
        Self {
            registry: Registry::builtin(),
            default_experiment: ("default".into(), BUILTIN.into(), PathBuf::from(".")),
        }
    }

    /// Adds a generator that experiment files can name `name` (replacing a
    /// built-in of that name).
    #[must_use]
    pub fn generator<G>(mut self, name: &str, generator: G) -> Self
    where
        G: Generator + Send + 'static,
        G::State: crate::transform::Blend,
    {
        self.registry.register(name, generator);
        self
    }

    /// Uses `registry` for the generators instead.
    #[must_use]
    pub fn registry(mut self, registry: Registry) -> Self {
        self.registry = registry;
        self
    }

    /// The experiment used when the command line names none: TOML text
    /// (e.g. `include_str!("my.toml")`) named `name`, whose relative paths
    /// resolve against `base`.
    #[must_use]
    pub fn default_experiment(
        mut self,
        name: &str,
        toml: impl Into<String>,
        base: impl Into<PathBuf>,
    ) -> Self {
        self.default_experiment = (name.into(), toml.into(), base.into());
        self
    }

    /// Runs the command line of this process (`std::env::args_os`): prints
    /// errors with their causes, and returns the exit status (0 success,
    /// 1 error, 2 a usage mistake, 130 a run stopped by Ctrl-C or SIGTERM
    /// before its budget, its results written; `--help` prints and succeeds).
    pub fn run(self) -> ExitCode {
        match self.run_from(std::env::args_os()) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e @ CliError::Interrupted(_)) => {
                errln!("shapegen: {e}");
                ExitCode::from(130)
            }
            Err(CliError::Args(e)) => {
                let _ = e.print();
                ExitCode::from(u8::try_from(e.exit_code()).unwrap_or(2))
            }
            Err(e) => {
                errln!("shapegen: error: {e}");
                let mut source = std::error::Error::source(&e);
                while let Some(s) = source {
                    errln!("  caused by: {s}");
                    source = s.source();
                }
                ExitCode::FAILURE
            }
        }
    }

    /// Runs a command line given as arguments (the first is the program's
    /// name), e.g. `["shapegen", "run", "my.toml", "--generations", "5"]`.
    pub fn run_from<I, T>(&self, args: I) -> Result<(), CliError>
    where
        I: IntoIterator<Item = T>,
        T: Into<OsString> + Clone,
    {
        let args = Args::try_parse_from(args)?;
        catch_interrupts();
        match args.command.unwrap_or_default() {
            Command::Run(a) => run::run(self, &a),
            Command::Compare(a) => compare::compare(self, &a),
            Command::Render(a) => render::render(self, &a),
            Command::Gallery(a) => gallery::gallery(self, &a),
            Command::Design(c) => design::design(self, c),
            Command::Transform(a) => transform::transform(self, &a),
        }
    }

    /// The experiment file at `path`, or the default one.
    fn load_experiment(
        &self,
        path: Option<&Path>,
        data: Option<&Path>,
    ) -> Result<Experiment, CliError> {
        let mut options = LoadOptions::from_env();
        if let Some(d) = data {
            options.data = Some(d.to_path_buf());
        }
        Ok(match path {
            Some(p) => Experiment::load_with(p, &self.registry, &options)?,
            None => {
                let (name, text, base) = &self.default_experiment;
                Experiment::from_toml_with(
                    text,
                    "<built-in>",
                    base,
                    name,
                    &self.registry,
                    &options,
                )?
            }
        })
    }
}

/// The chromosome saved in `path` (a `best.json`, a gallery's
/// `models/NN.json`), of `experiment`'s generator.
fn read_chromosome(
    experiment: &Experiment,
    path: &Path,
) -> Result<crate::genome::Chromosome, CliError> {
    crate::experiment::check_regular_file(path).map_err(CliError::msg)?;
    let text = std::fs::read_to_string(path)
        .map_err(|e| CliError::msg(format!("cannot read {}: {e}", path.display())))?;
    let data: crate::genome::ChromosomeData = serde_json::from_str(&text)
        .map_err(|e| CliError::msg(format!("{}: not a chromosome file: {e}", path.display())))?;
    Ok(experiment.chromosome(&data, path)?)
}

/// A learned generator written by `shapegen design export`.
fn read_learned(path: &Path) -> Result<crate::design::LearnedPdf, CliError> {
    crate::experiment::check_regular_file(path).map_err(CliError::msg)?;
    let text = std::fs::read_to_string(path)
        .map_err(|e| CliError::msg(format!("cannot read {}: {e}", path.display())))?;
    serde_json::from_str(&text).map_err(|e| {
        CliError::msg(format!(
            "{}: not a learned generator written by `shapegen design export`: {e}",
            path.display()
        ))
    })
}

/// A `--seconds` value as a duration (finite, > 0, at most a century).
fn seconds(s: f64) -> Result<std::time::Duration, CliError> {
    crate::optimize::Budget::seconds(s).ok_or_else(|| {
        CliError::msg(format!(
            "--seconds must be > 0 and at most {:.0} (a century), got {s}",
            crate::optimize::Budget::MAX_SECONDS
        ))
    })
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
