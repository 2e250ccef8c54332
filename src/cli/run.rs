//! `shapegen run`: one optimization with a progress bar, checkpoints and
//! the result files.

use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use serde::{Deserialize, Serialize};
use shapegen::experiment::{Experiment, write_atomically};
use shapegen::optimize::{Budget, Checkpoint, GenerationStats, RunResult, StopReason};

use super::args::RunArgs;
use super::curve::{self, Row};
use super::{CliError, interrupted, load_experiment, seconds, thread_pool};

/// What a checkpoint file holds: the optimizer's checkpoint plus what the
/// CLI needs to continue the same run and its curve.
#[derive(Debug, Serialize, Deserialize)]
pub struct SavedRun {
    /// The experiment's name.
    pub experiment: String,
    /// The method.
    pub method: String,
    /// The budget of the run.
    pub budget: Budget,
    /// The curve up to the checkpoint.
    pub curve: Vec<Row>,
    /// The optimizer's state.
    pub checkpoint: Checkpoint,
}

/// What `summary.json` holds.
#[derive(Debug, Serialize, Deserialize)]
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
    /// Worker threads.
    pub threads: usize,
    /// Whether the run was resumed from a checkpoint.
    pub resumed: bool,
}

/// Runs `shapegen run`.
pub fn run(args: &RunArgs) -> Result<(), CliError> {
    let experiment = load_experiment(
        args.experiment.experiment.as_deref(),
        args.experiment.data.as_deref(),
    )?;
    let saved: Option<SavedRun> = match &args.resume {
        None => None,
        Some(path) => Some(read_saved(path)?),
    };
    let method = match (&saved, args.method) {
        (Some(s), Some(m)) if s.method != m.name() => {
            return Err(CliError::msg(format!(
                "the checkpoint is a `{}` run; --method {m} does not match",
                s.method
            )));
        }
        (Some(s), _) => s.method.parse()?,
        (None, Some(m)) => m,
        (None, None) => experiment.default_method(),
    };
    if let Some(s) = &saved
        && s.experiment != experiment.name()
    {
        return Err(CliError::msg(format!(
            "the checkpoint belongs to experiment `{}`, not `{}`",
            s.experiment,
            experiment.name()
        )));
    }
    let budget = match (&saved, args.seconds, args.generations) {
        (_, Some(s), g) => {
            let b = Budget::wall_time(seconds(s)?);
            g.map_or(b, |g| b.and_generations(g))
        }
        (_, None, Some(g)) => Budget::generations(g),
        (Some(s), None, None) => s.budget,
        (None, None, None) => experiment.budget(method).ok_or_else(|| {
            CliError::msg(format!(
                "the experiment gives no budget for {method}: pass --seconds or --generations"
            ))
        })?,
    };
    let seed = match &saved {
        Some(s) => {
            if args.seed.is_some_and(|seed| seed != s.checkpoint.seed) {
                return Err(CliError::msg(format!(
                    "the checkpoint was written with seed {}; --seed does not match",
                    s.checkpoint.seed
                )));
            }
            s.checkpoint.seed
        }
        None => args.seed.unwrap_or(experiment.seed()),
    };
    let pool = thread_pool(args.threads)?;
    let threads = pool.current_num_threads();
    for w in experiment.warnings() {
        eprintln!("shapegen: warning: {w}");
    }
    if !args.quiet {
        eprintln!(
            "shapegen: {} on `{}` ({}, {}); {} thread(s), seed {seed}{}",
            method,
            experiment.name(),
            experiment.generator(),
            experiment.scene(),
            threads,
            saved
                .as_ref()
                .map(|s| format!(", resuming at generation {}", s.checkpoint.generation))
                .unwrap_or_default()
        );
    }
    let mut curve: Vec<Row> = saved.as_ref().map(|s| s.curve.clone()).unwrap_or_default();
    let mut watcher = Watcher::new(&budget, args.quiet);
    let mut checkpoint_error = None;
    let mut observer = |s: &GenerationStats<'_>| {
        curve.push(Row::of(s));
        watcher.update(s);
        let stop = interrupted();
        if let Some(path) = &args.checkpoint
            && (stop || s.generation.is_multiple_of(args.every.max(1)))
        {
            let saved = SavedRun {
                experiment: experiment.name().to_string(),
                method: method.name().to_string(),
                budget,
                curve: curve.clone(),
                checkpoint: s.checkpoint(),
            };
            if let Err(e) = write_json(path, &saved) {
                checkpoint_error = Some(e);
                return ControlFlow::Break(());
            }
        }
        if stop {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    };
    let result = pool.install(|| {
        experiment.run(
            method,
            &budget,
            seed,
            saved.as_ref().map(|s| &s.checkpoint),
            &mut observer,
        )
    })?;
    watcher.finish();
    if let Some(e) = checkpoint_error {
        return Err(e);
    }
    if result.stop == StopReason::Observer {
        eprintln!("shapegen: interrupted; writing the results so far");
    }
    let summary = Summary {
        experiment: experiment.name().to_string(),
        generator: experiment.generator().to_string(),
        method: method.name().to_string(),
        seed,
        best_fitness: result.best_fitness,
        optimum: experiment.optimum(),
        best_genes: result.best.len(),
        evaluations: result.evaluations,
        generations: result.generations,
        seconds: result.elapsed.as_secs_f64(),
        stop: result.stop,
        threads,
        resumed: saved.is_some(),
    };
    let written = write_run(&experiment, &result, &curve, &summary, &args.out)?;
    println!(
        "best fitness {:.4}{} ({} genes) after {} generations, {} evaluations, {:.1} s",
        result.best_fitness,
        experiment
            .optimum()
            .map(|o| format!(" of {o}"))
            .unwrap_or_default(),
        result.best.len(),
        result.generations,
        result.evaluations,
        result.elapsed.as_secs_f64()
    );
    println!("wrote {}", list(&written));
    Ok(())
}

/// Writes every result file of a run into `dir`; returns their paths.
pub fn write_run(
    experiment: &Experiment,
    result: &RunResult,
    curve: &[Row],
    summary: &Summary,
    dir: &Path,
) -> Result<Vec<PathBuf>, CliError> {
    let mut written = experiment.write_model(&result.best, dir)?;
    let best = dir.join("best.json");
    write_json(&best, &result.best.to_data(experiment.graph()))?;
    let csv = dir.join("curve.csv");
    write_atomically(&csv, curve::to_csv(curve).as_bytes())?;
    let json = dir.join("summary.json");
    write_json(&json, summary)?;
    written.extend([best, csv, json]);
    Ok(written)
}

/// Writes `value` as pretty JSON, atomically.
pub fn write_json(path: &Path, value: &impl Serialize) -> Result<(), CliError> {
    let text = serde_json::to_string_pretty(value)
        .map_err(|e| CliError::msg(format!("cannot encode {}: {e}", path.display())))?;
    Ok(write_atomically(path, text.as_bytes())?)
}

fn read_saved(path: &Path) -> Result<SavedRun, CliError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| CliError::msg(format!("cannot read checkpoint {}: {e}", path.display())))?;
    serde_json::from_str(&text).map_err(|e| {
        CliError::msg(format!(
            "{}: not a shapegen checkpoint: {e}",
            path.display()
        ))
    })
}

fn list(paths: &[PathBuf]) -> String {
    paths
        .iter()
        .map(|p| p.display().to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

/// The progress bar on a terminal, or a line every few seconds otherwise.
pub struct Watcher {
    bar: Option<ProgressBar>,
    budget: Budget,
    quiet: bool,
    last_line: Instant,
    last: Option<(f64, u64)>,
}

impl Watcher {
    /// A watcher for a run with `budget`.
    pub fn new(budget: &Budget, quiet: bool) -> Self {
        let target = ProgressDrawTarget::stderr();
        let bar = (!quiet && !target.is_hidden()).then(|| {
            let bar = ProgressBar::with_draw_target(Some(1000), target);
            bar.set_style(
                ProgressStyle::with_template(
                    "{bar:30.cyan/blue} {percent:>3}% {elapsed_precise} {msg}",
                )
                .expect("a valid template"),
            );
            bar
        });
        Self {
            bar,
            budget: *budget,
            quiet,
            last_line: Instant::now(),
            last: None,
        }
    }

    /// Shows one generation.
    pub fn update(&mut self, s: &GenerationStats<'_>) {
        let secs = s.elapsed.as_secs_f64();
        let rate = match self.last {
            Some((t, e)) if secs > t => (s.evaluations - e) as f64 / (secs - t),
            _ => s.evaluations as f64 / secs.max(1e-9),
        };
        self.last = Some((secs, s.evaluations));
        let message = format!(
            "gen {} | {:.0} eval/s | best {:.4} | mean {:.4}",
            s.generation, rate, s.best_so_far, s.mean
        );
        let b = &self.budget;
        let fraction = [
            b.wall_time.map(|t| secs / t.as_secs_f64()),
            b.generations.map(|g| s.generation as f64 / g.max(1) as f64),
            b.evaluations
                .map(|e| s.evaluations as f64 / e.max(1) as f64),
        ]
        .into_iter()
        .flatten()
        .fold(0.0, f64::max);
        if let Some(bar) = &self.bar {
            bar.set_position((fraction.min(1.0) * 1000.0) as u64);
            bar.set_message(message);
        } else if !self.quiet
            && (self.last_line.elapsed() >= Duration::from_secs(2) || s.generation == 0)
        {
            self.last_line = Instant::now();
            eprintln!(
                "  {:>3.0}% {message} ({secs:.1} s)",
                fraction.min(1.0) * 100.0
            );
        }
    }

    /// Removes the bar.
    pub fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}
