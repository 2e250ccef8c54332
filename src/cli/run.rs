//! `shapegen run`: one optimization with a progress bar, checkpoints and
//! the result files.

use std::ops::ControlFlow;
use std::path::PathBuf;

use super::args::RunArgs;
use super::guard::{self, interrupted};
use super::progress::Progress;
use super::saved::SavedRun;
use super::{Cli, CliError, seconds, thread_pool};
use crate::optimize::{Budget, GenerationStats, Interruptible, StopReason};
use crate::output::{self, Row, Summary};

/// Runs `shapegen run`.
pub(super) fn run(cli: &Cli, args: &RunArgs) -> Result<(), CliError> {
    let mut experiment = cli.load_experiment(
        args.experiment.experiment.as_deref(),
        args.experiment.data.as_deref(),
    )?;
    if let Some(path) = &args.prior {
        experiment.use_prior(&super::read_learned(path)?, path)?;
    }
    if args.generations == Some(0) {
        return Err(CliError::msg(
            "--generations must be at least 1 (generation 0 is the initial population)",
        ));
    }
    let saved: Option<SavedRun> = match &args.resume {
        None => None,
        Some(path) => Some(SavedRun::read(path, &experiment)?),
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
    let _taken = check_outputs(&experiment, args)?;
    for w in experiment.warnings_for(&[method]) {
        errln!("shapegen: warning: {w}");
    }
    if !args.quiet {
        errln!(
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
    // The latest generation's checkpoint, unwritten (with the curve's length
    // then): written when Ctrl-C stops the run in the middle of the next.
    let mut pending: Option<(crate::optimize::Checkpoint, usize)> = None;
    // Computed once: it hashes every target cell and mesh vertex.
    let fingerprint = experiment.fingerprint();
    let seal = |checkpoint, curve: &[Row]| SavedRun {
        experiment: experiment.name().to_string(),
        method: method.name().to_string(),
        budget,
        fingerprint: fingerprint.clone(),
        curve: curve.to_vec(),
        checkpoint,
        integrity: String::new(),
    };
    let observer = |s: &GenerationStats<'_>| {
        curve.push(Row::of(s));
        progress.update(s);
        let stop = interrupted();
        if let Some(path) = &args.checkpoint {
            if stop || s.generation.is_multiple_of(args.every.max(1)) {
                pending = None;
                if let Err(e) = seal(s.checkpoint(), &curve).write(path) {
                    // The last good checkpoint is intact (writes are atomic):
                    // stop here and still write the results.
                    errln!("\nshapegen: error: {e}; stopping and writing the results so far");
                    checkpoint_error = Some((s.generation, e));
                    return ControlFlow::Break(());
                }
            } else {
                pending = Some((s.checkpoint(), curve.len()));
            }
        }
        if stop {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    };
    let mut observer = Interruptible {
        observer,
        flag: guard::interrupt_flag(),
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
    drop(observer);
    // Stopped in the middle of a generation: save the last complete one.
    if let (Some(path), Some((checkpoint, len))) = (&args.checkpoint, pending.take())
        && result.stop == StopReason::Observer
        && checkpoint_error.is_none()
        && let Err(e) = seal(checkpoint, &curve[..len]).write(path)
    {
        checkpoint_error = Some((result.generations, e));
    }
    progress.finish();
    let stopped_by_user = result.stop == StopReason::Observer && checkpoint_error.is_none();
    if stopped_by_user {
        errln!("shapegen: interrupted; writing the results so far");
    }
    let summary = Summary {
        threads,
        resumed: saved.is_some(),
        ..Summary::of(&experiment, method, seed, &result)
    };
    // A model below the graph's minimum length (SMC stopped before any
    // particle was complete) or without a score is no result to write.
    let complete = result.best_fitness.is_finite()
        && crate::genome::Chromosome::from_data(
            experiment.graph(),
            &result.best.to_data(experiment.graph()),
        )
        .is_ok();
    if !complete {
        guard::writing(|| -> Result<(), CliError> {
            output::write_curve(&args.out.join("curve.csv"), &curve)?;
            output::write_json(&args.out.join("summary.json"), &summary)?;
            Ok(())
        })?;
        return Err(CliError::msg(format!(
            "no complete model within the budget ({} generations, {} evaluations): {method} needs more generations (SMC and SOSMC build models gene by gene); wrote {} and {} only",
            result.generations,
            result.evaluations,
            args.out.join("curve.csv").display(),
            args.out.join("summary.json").display()
        )));
    }
    // A second Ctrl-C waits until the result files are complete.
    // The pictures render on the run's threads.
    errln!(
        "shapegen: writing the model, pictures and curve to {}",
        args.out.display()
    );
    let written = guard::writing(|| {
        pool.install(|| output::write_run(&experiment, &result, &curve, &summary, &args.out))
    })?;
    outln!(
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
    outln!("wrote {}", list(&written));
    if let Some((generation, e)) = checkpoint_error {
        return Err(CliError::msg(format!(
            "the checkpoint could not be written at generation {generation} ({e}); the run stopped there and its results are in {}; the last checkpoint written before, if any, is intact",
            args.out.display()
        )));
    }
    if stopped_by_user {
        return Err(CliError::Interrupted(args.out.clone()));
    }
    Ok(())
}

/// Before any work: the output folder takes files and is this run's alone
/// (held until the lock returned is dropped), the checkpoint's folder takes
/// files too, and no output is an input of the run (a checkpoint may replace the
/// one resumed from).
fn check_outputs(
    experiment: &crate::experiment::Experiment,
    args: &RunArgs,
) -> Result<guard::OutputLock, CliError> {
    let taken = guard::take_output_dir(&args.out)?;
    let mut inputs = experiment.inputs().to_vec();
    if let Some(cp) = &args.checkpoint {
        guard::check_output_file(cp)?;
        guard::refuse_overwriting_inputs(std::slice::from_ref(cp), &inputs)?;
    }
    inputs.extend(args.resume.iter().cloned());
    let outputs: Vec<PathBuf> = output::run_files(experiment)
        .iter()
        .map(|n| args.out.join(n))
        .collect();
    if let Some(cp) = &args.checkpoint {
        // The result files must not replace the checkpoint either.
        guard::refuse_overwriting_inputs(&outputs, std::slice::from_ref(cp))?;
    }
    guard::refuse_overwriting_inputs(&outputs, &inputs)?;
    Ok(taken)
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

fn list(paths: &[PathBuf]) -> String {
    paths
        .iter()
        .map(|p| p.display().to_string())
        .collect::<Vec<_>>()
        .join(", ")
}
