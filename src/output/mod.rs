//! A run's result files, as the command line writes them, for programs that
//! run experiments themselves:
//!
//! | file | what | written by |
//! |---|---|---|
//! | `best.obj` | the best model, with the meshes it was scored with | [`Experiment::write_model`] |
//! | `target.obj` | the volume targets as placed | [`Experiment::write_model`] |
//! | `slice_x/y/z.png` | middle voxel slices (volume scenes) | [`Experiment::write_model`] |
//! | `overlay.png` | silhouette over the target (image scenes) | [`Experiment::write_model`] |
//! | `best.png` | the best model shaded, from its best view | [`Experiment::write_model`] |
//! | `view.png` | the best model shaded from the target camera, the target's outline over it (image scenes) | [`Experiment::write_model`] |
//! | `population.png` | the final population clustered around the best model, like a gallery | [`write_population`] |
//! | `best.json` | the best chromosome in the validated exchange form | [`write_chromosome`] |
//! | `curve.csv` | per generation: seconds, evaluations, best, mean, std | [`write_curve`] |
//! | `summary.json` | the run's figures, IoU/precision/recall per target | [`Summary`] |
//!
//! [`write_run`] writes them all, as a set: `summary.json` is renamed into
//! place last, so a folder with a `summary.json` holds one run's files, and
//! a run that cannot write them all (a full disk) leaves the previous set
//! as it was. Every other file is written atomically too (a temporary file
//! beside it, then a rename).
//!
//! ```
//! use shapegen::experiment::{Experiment, Method};
//! use shapegen::optimize::{Budget, NoObserver};
//! use shapegen::output::{self, Summary};
//!
//! let experiment = Experiment::builtin();
//! let result = experiment.run(Method::Ga, &Budget::generations(2), 1, None, &mut NoObserver)?;
//! let summary = Summary::of(&experiment, Method::Ga, 1, &result);
//! assert!(summary.quality[0].iou >= 0.0 && summary.quality[0].iou <= 1.0);
//! let dir = std::env::temp_dir().join("shapegen-doc-output");
//! let written = output::write_run(&experiment, &result, &[], &summary, &dir)?;
//! assert!(written.iter().any(|p| p.ends_with("best.obj")));
//! # std::fs::remove_dir_all(&dir).ok();
//! # Ok::<(), shapegen::experiment::ExperimentError>(())
//! ```

mod curve;

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

pub use curve::{Row, number, to_csv};

use crate::experiment::{Experiment, ExperimentError, Method};
use crate::genome::Chromosome;
use crate::optimize::{RunResult, StopReason};
use crate::score::Quality;
use crate::score::write_atomically;

/// How the best model covers one target (see [`Quality`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct TargetQuality {
    /// Intersection over union of model and target cells (pixels).
    pub iou: f64,
    /// The share of the model's cells in the target.
    pub precision: f64,
    /// The share of the target's cells the model covers.
    pub recall: f64,
}

impl From<Quality> for TargetQuality {
    fn from(q: Quality) -> Self {
        Self {
            iou: q.iou,
            precision: q.precision,
            recall: q.recall,
        }
    }
}

/// What `summary.json` holds.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Summary {
    /// The experiment's name.
    pub experiment: String,
    /// The generator.
    pub generator: String,
    /// The method.
    pub method: String,
    /// The seed.
    pub seed: u64,
    /// Best fitness found.
    pub best_fitness: f64,
    /// The experiment's optimum, if known.
    pub optimum: Option<f64>,
    /// Per target, how the best model covers it.
    pub quality: Vec<TargetQuality>,
    /// Genes of the best chromosome.
    pub best_genes: usize,
    /// Fitness evaluations.
    pub evaluations: u64,
    /// Generations after the initial one.
    pub generations: u64,
    /// Wall-clock seconds (including time before a resumed checkpoint).
    pub seconds: f64,
    /// Why the run stopped.
    pub stop: StopReason,
    /// Worker threads (0 if unknown).
    pub threads: usize,
    /// Whether the run was resumed from a checkpoint.
    pub resumed: bool,
    /// The learned prior the run grew models with (`run --prior`), if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub prior: Option<String>,
}

impl Summary {
    /// The summary of `result`, a run of `method` with `seed` on
    /// `experiment` (`threads` 0, not resumed: set them if known).
    #[must_use]
    pub fn of(experiment: &Experiment, method: Method, seed: u64, result: &RunResult) -> Self {
        Self {
            experiment: experiment.name().to_string(),
            generator: experiment.generator().to_string(),
            method: method.name().to_string(),
            seed,
            best_fitness: result.best_fitness,
            optimum: experiment.optimum(),
            quality: experiment
                .quality(&result.best)
                .into_iter()
                .map(TargetQuality::from)
                .collect(),
            best_genes: result.best.len(),
            evaluations: result.evaluations,
            generations: result.generations,
            seconds: result.elapsed.as_secs_f64(),
            stop: result.stop,
            threads: 0,
            resumed: false,
            prior: experiment.prior().map(|p| p.display().to_string()),
        }
    }
}

/// The names of the files [`write_run`] writes.
#[must_use]
pub fn run_files(experiment: &Experiment) -> Vec<String> {
    let mut files = experiment.model_files();
    files.extend(["population.png", "best.json", "curve.csv", "summary.json"].map(String::from));
    files
}

/// Most models of a final population [`write_population`] clusters (each
/// is rendered once for its view attributes: enough for 14 clusters, and
/// seconds, not a minute, for large trees).
pub const POPULATION_SHOWN: usize = 120;

/// Writes `population.png`: the final population (its first
/// [`POPULATION_SHOWN`] distinct models) clustered like a gallery around the
/// best model, each from the best model's best view, so one sees what the
/// optimizer kept.
pub fn write_population(
    experiment: &Experiment,
    result: &RunResult,
    seed: u64,
    path: &Path,
) -> Result<(), ExperimentError> {
    let mut others: Vec<Chromosome> = Vec::new();
    for ind in &result.population {
        if others.len() >= POPULATION_SHOWN {
            break;
        }
        if ind.chromosome != result.best && !others.contains(&ind.chromosome) {
            others.push(ind.chromosome.clone());
        }
    }
    let picture = if others.is_empty() {
        crate::gallery::best_view_picture(experiment, &result.best, 480)?
    } else {
        let options = crate::gallery::GalleryOptions {
            clusters: (others.len() + 1).clamp(2, 14),
            thumbnail: 120,
            seed,
            ..crate::gallery::GalleryOptions::default()
        };
        crate::gallery::Gallery::of(
            "best model",
            experiment,
            result.best.clone(),
            others,
            &options,
            &|_| {},
        )?
        .picture()
    };
    Ok(crate::score::write_png_rgba(path, &picture)?)
}

/// Writes every result file of a run into `dir` (created if missing):
/// the model and pictures, `best.json`, `curve.csv` and `summary.json`.
/// Returns their paths.
///
/// The files are written as a set: first into a hidden folder in `dir`,
/// then renamed into place with `summary.json` removed first and put back
/// last, so `dir` never holds a `summary.json` beside files of another
/// run. If any file cannot be written (a full disk), the hidden folder is
/// removed and `dir` keeps the previous set untouched.
pub fn write_run(
    experiment: &Experiment,
    result: &RunResult,
    curve: &[Row],
    summary: &Summary,
    dir: &Path,
) -> Result<Vec<PathBuf>, ExperimentError> {
    let stage = Stage::new(dir)?;
    let staging = stage.path();
    experiment.write_model(&result.best, staging)?;
    write_population(
        experiment,
        result,
        summary.seed,
        &staging.join("population.png"),
    )?;
    write_chromosome(&staging.join("best.json"), experiment, &result.best)?;
    write_curve(&staging.join("curve.csv"), curve)?;
    write_json(&staging.join("summary.json"), summary)?;
    stage.publish()
}

/// A set of result files written into a hidden folder inside their
/// output folder, then renamed into place by [`publish`](Self::publish)
/// with `summary.json` (the set's seal) taken away first and put back
/// last. Dropped unpublished (an error while writing), it removes the
/// hidden folder and the output folder keeps its previous set.
pub struct Stage {
    dir: PathBuf,
    staging: PathBuf,
}

impl Stage {
    /// A stage for `dir` (created if missing).
    pub fn new(dir: &Path) -> Result<Self, ExperimentError> {
        std::fs::create_dir_all(dir).map_err(|e| ExperimentError::write(dir, e))?;
        let staging = dir.join(format!(".shapegen-staging-{}", std::process::id()));
        std::fs::remove_dir_all(&staging).ok();
        std::fs::create_dir(&staging).map_err(|e| ExperimentError::write(&staging, e))?;
        Ok(Self {
            dir: dir.to_path_buf(),
            staging,
        })
    }

    /// The hidden folder to write the set into (subfolders allowed).
    #[must_use]
    pub fn path(&self) -> &Path {
        &self.staging
    }

    /// Moves the set into the output folder, `summary.json` last; returns
    /// the published files' paths, by name with `summary.json` last.
    pub fn publish(self) -> Result<Vec<PathBuf>, ExperimentError> {
        let mut files = Vec::new();
        staged_files(&self.staging, &mut files)
            .map_err(|e| ExperimentError::write(&self.staging, e))?;
        let seal = self.dir.join("summary.json");
        match std::fs::remove_file(&seal) {
            Ok(()) => {}
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
            Err(e) => return Err(ExperimentError::write(&seal, e)),
        }
        let (seals, rest): (Vec<PathBuf>, Vec<PathBuf>) = files
            .into_iter()
            .partition(|p| *p == self.staging.join("summary.json"));
        let mut published = Vec::new();
        for from in rest.into_iter().chain(seals) {
            let to = self
                .dir
                .join(from.strip_prefix(&self.staging).unwrap_or(&from));
            if let Some(parent) = to.parent() {
                std::fs::create_dir_all(parent).map_err(|e| ExperimentError::write(parent, e))?;
            }
            std::fs::rename(&from, &to).map_err(|e| ExperimentError::write(&to, e))?;
            published.push(to);
        }
        Ok(published)
    }
}

impl Drop for Stage {
    fn drop(&mut self) {
        std::fs::remove_dir_all(&self.staging).ok();
    }
}

/// Every file below `dir`, sorted by name within each folder.
fn staged_files(dir: &Path, out: &mut Vec<PathBuf>) -> std::io::Result<()> {
    let mut entries: Vec<_> = std::fs::read_dir(dir)?.collect::<Result<_, _>>()?;
    entries.sort_by_key(std::fs::DirEntry::file_name);
    for e in entries {
        if e.file_type()?.is_dir() {
            staged_files(&e.path(), out)?;
        } else {
            out.push(e.path());
        }
    }
    Ok(())
}

/// Writes `chromosome` of `experiment`'s generator as JSON (`best.json`),
/// in the form [`Experiment::chromosome`] reads back.
pub fn write_chromosome(
    path: &Path,
    experiment: &Experiment,
    chromosome: &Chromosome,
) -> Result<(), ExperimentError> {
    write_json(path, &chromosome.to_data(experiment.graph()))
}

/// Writes the rows as CSV (`curve.csv`, see [`to_csv`]).
pub fn write_curve(path: &Path, rows: &[Row]) -> Result<(), ExperimentError> {
    Ok(write_atomically(path, to_csv(rows).as_bytes())?)
}

/// Writes `value` as pretty JSON, atomically.
pub fn write_json(path: &Path, value: &impl Serialize) -> Result<(), ExperimentError> {
    let text = serde_json::to_string_pretty(value).map_err(|e| ExperimentError::write(path, e))?;
    Ok(write_atomically(path, text.as_bytes())?)
}

/// Writes `value` as compact JSON, atomically: for files that programs read
/// (checkpoints), where the pretty form of a large population, a number a
/// line, is several times the size and the time.
pub fn write_json_compact(path: &Path, value: &impl Serialize) -> Result<(), ExperimentError> {
    let text = serde_json::to_string(value).map_err(|e| ExperimentError::write(path, e))?;
    Ok(write_atomically(path, text.as_bytes())?)
}

/// Mean IoU over targets, for one-number displays.
#[must_use]
pub fn mean_iou(quality: &[Quality]) -> f64 {
    if quality.is_empty() {
        return 0.0;
    }
    quality.iter().map(|q| q.iou).sum::<f64>() / quality.len() as f64
}
