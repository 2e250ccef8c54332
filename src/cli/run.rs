//! `shapegen run`: one optimization with a progress bar, checkpoints and
//! the result files.

use std::ops::ControlFlow;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::args::RunArgs;
use super::progress::Progress;
use super::{Cli, CliError, interrupted, seconds, thread_pool};
use crate::optimize::{Budget, Checkpoint, GenerationStats, StopReason};
use crate::output::{self, Row, Summary, write_json};

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

/// Runs `shapegen run`.
pub(super) fn run(cli: &Cli, args: &RunArgs) -> Result<(), CliError> {
    let experiment = cli.load_experiment(
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
    let mut progress = Progress::new(&budget, args.quiet).with_quality(&experiment);
    let mut checkpoint_error = None;
    let mut observer = |s: &GenerationStats<'_>| {
        curve.push(Row::of(s));
        progress.update(s);
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
                checkpoint_error = Some(CliError::from(e));
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
    progress.finish();
    if let Some(e) = checkpoint_error {
        return Err(e);
    }
    if result.stop == StopReason::Observer {
        eprintln!("shapegen: interrupted; writing the results so far");
    }
    let summary = Summary {
        threads,
        resumed: saved.is_some(),
        ..Summary::of(&experiment, method, seed, &result)
    };
    let written = output::write_run(&experiment, &result, &curve, &summary, &args.out)?;
    println!(
        "best fitness {:.4}{}, {} ({} genes) after {} generations, {} evaluations, {:.1} s",
        result.best_fitness,
        experiment
            .optimum()
            .map(|o| format!(" of {o}"))
            .unwrap_or_default(),
        quality_line(&summary),
        result.best.len(),
        result.generations,
        result.evaluations,
        result.elapsed.as_secs_f64()
    );
    println!("wrote {}", list(&written));
    Ok(())
}

/// IoU, precision and recall per target, as one phrase.
fn quality_line(summary: &Summary) -> String {
    summary
        .quality
        .iter()
        .enumerate()
        .map(|(i, q)| {
            let which = if summary.quality.len() > 1 {
                format!("target {i}: ")
            } else {
                String::new()
            };
            format!(
                "{which}IoU {:.3}, precision {:.3}, recall {:.3}",
                q.iou, q.precision, q.recall
            )
        })
        .collect::<Vec<_>>()
        .join("; ")
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
