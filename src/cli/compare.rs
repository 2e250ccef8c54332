//! `shapegen compare`: every method several times with the same wall-clock
//! budget, summarized like the paper's figures 7 and 9.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::ops::ControlFlow;

use serde::Serialize;

use super::args::CompareArgs;
use super::guard::{self, interrupted};
use super::plot::{self, Series};
use super::{Cli, CliError, seconds, thread_pool};
use crate::experiment::{Experiment, Method};
use crate::genome::Chromosome;
use crate::optimize::{Budget, GenerationStats, Interruptible, RunResult, StopReason};
use crate::output::{self, Row, mean_iou, write_json};
use crate::score::write_atomically;

/// Points of the common time grid.
const GRID: usize = 200;
/// Budget fractions reported in the summary.
const FRACTIONS: [f64; 4] = [0.1, 0.25, 0.5, 1.0];
/// Budget fractions at which the best model's IoU is reported.
const IOU_FRACTIONS: [f64; 3] = [0.1, 0.5, 1.0];

/// One finished run.
struct Run {
    seed: u64,
    rows: Vec<Row>,
    result: RunResult,
    /// Mean IoU over targets of the best model so far at [`IOU_FRACTIONS`]
    /// of the budget (`None` while there is no valid model).
    iou_at: Vec<Option<f64>>,
}

/// The best model so far each time it changed: (seconds, fitness, model).
type Improvements = Vec<(f64, f64, Chromosome)>;

/// The IoU of the best model at each of [`IOU_FRACTIONS`] of `seconds`.
fn iou_at(experiment: &Experiment, improvements: &Improvements, seconds: f64) -> Vec<Option<f64>> {
    IOU_FRACTIONS
        .iter()
        .map(|f| {
            improvements
                .iter()
                .take_while(|(t, _, _)| *t <= f * seconds || *f == 1.0)
                .last()
                .map(|(_, _, c)| mean_iou(&experiment.quality(c)))
        })
        .collect()
}

/// Per-method statistics of `summary.json`.
#[derive(Debug, Serialize)]
pub struct MethodSummary {
    /// Runs.
    pub runs: usize,
    /// Mean of the runs' final best fitness.
    pub final_mean: f64,
    /// Their standard deviation.
    pub final_std: f64,
    /// Mean best fitness at 10 %, 25 %, 50 % and 100 % of the budget
    /// (`null` while some run has no valid model yet).
    pub mean_at: BTreeMap<String, Option<f64>>,
    /// Standard deviation at the same fractions.
    pub std_at: BTreeMap<String, Option<f64>>,
    /// Mean IoU (over runs; per run the mean over targets) of the best
    /// model at 10 %, 50 % and 100 % of the budget (`null` while some run
    /// has no valid model yet).
    pub iou_at: BTreeMap<String, Option<f64>>,
    /// Seconds until the mean of this method's runs' best first reaches
    /// each other method's final mean, every run having a valid model
    /// (`null`: not within the budget); exact, from every run's rows.
    pub seconds_to_reach: BTreeMap<String, Option<f64>>,
    /// The same in evaluations (each run's, when the mean reached it).
    pub evaluations_to_reach: BTreeMap<String, Option<u64>>,
    /// With `--goal`: when the mean of the runs' best first reached it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub goal: Option<GoalReached>,
    /// Mean evaluations per run.
    pub evaluations: f64,
    /// Mean generations per run.
    pub generations: f64,
    /// Best fitness over all runs, and the seed of that run.
    pub best: f64,
    /// The seed of the best run (its model is in `<method>/`).
    pub best_seed: u64,
    /// The lowest final best fitness of a run.
    pub worst: f64,
    /// The median of the runs' final best fitness.
    pub median: f64,
    /// Every run, in the order they ran.
    pub each_run: Vec<RunSummary>,
}

/// One run of a method in `summary.json`: how far it got and why it ended.
#[derive(Debug, Serialize)]
pub struct RunSummary {
    /// Its seed.
    pub seed: u64,
    /// Its final best fitness.
    pub best: f64,
    /// Seconds it ran (less than the budget when it stopped early).
    pub seconds: f64,
    /// Evaluations it made.
    pub evaluations: u64,
    /// Generations it ran.
    pub generations: u64,
    /// Why it ended (`wall_time`: the budget; `exhausted`: the method had
    /// nothing left to do, as SMC once every particle is complete).
    pub stop: StopReason,
}

impl RunSummary {
    fn of(run: &Run) -> Self {
        Self {
            seed: run.seed,
            best: run.result.best_fitness,
            seconds: run.result.elapsed.as_secs_f64(),
            evaluations: run.result.evaluations,
            generations: run.result.generations,
            stop: run.result.stop,
        }
    }
}

/// When a method's mean curve first reached the `--goal` fitness: the mean
/// over its runs of each run's best so far, every run having a valid model.
#[derive(Debug, Serialize)]
pub struct GoalReached {
    /// The goal.
    pub fitness: f64,
    /// Seconds into the runs (`null`: not within the budget).
    pub seconds: Option<f64>,
    /// Evaluations each run had made (`null`: not within the budget).
    pub evaluations: Option<u64>,
}

/// `summary.json` of a comparison.
#[derive(Debug, Serialize)]
pub struct CompareSummary {
    /// The experiment.
    pub experiment: String,
    /// Seconds per run.
    pub seconds: f64,
    /// Runs per method.
    pub runs: u64,
    /// Threads.
    pub threads: usize,
    /// The experiment's optimum, if known.
    pub optimum: Option<f64>,
    /// Per method.
    pub methods: BTreeMap<String, MethodSummary>,
}

/// Runs `shapegen compare`.
pub(super) fn compare(cli: &Cli, args: &CompareArgs) -> Result<(), CliError> {
    let experiment = cli.load_experiment(
        args.experiment.experiment.as_deref(),
        args.experiment.data.as_deref(),
    )?;
    if args.runs == 0 || args.methods.is_empty() {
        return Err(CliError::msg("give at least one method and one run"));
    }
    if args.goal.is_some_and(|g| !g.is_finite()) {
        return Err(CliError::msg("--goal must be a finite fitness"));
    }
    let _taken = guard::take_output_dir(&args.out)?;
    let mut outputs: Vec<std::path::PathBuf> =
        ["curves.csv", "runs.csv", "summary.json", "curves.png"]
            .iter()
            .map(|n| args.out.join(n))
            .collect();
    let run_files = output::run_files(&experiment);
    for m in &args.methods {
        outputs.extend(run_files.iter().map(|n| args.out.join(m.name()).join(n)));
    }
    guard::refuse_overwriting_inputs(&outputs, experiment.inputs())?;
    for w in experiment.warnings_for(&args.methods) {
        errln!("shapegen: warning: {w}");
    }
    let pool = thread_pool(args.threads)?;
    let threads = pool.current_num_threads();
    let budget = Budget::wall_time(seconds(args.seconds)?);
    let first_seed = args.seed.unwrap_or(experiment.seed());
    let mut methods: Vec<Method> = Vec::new();
    for m in &args.methods {
        if !methods.contains(m) {
            methods.push(*m);
        }
    }
    errln!(
        "shapegen: comparing {} on `{}` ({}): {} run(s) × {} s each, {threads} thread(s)",
        methods
            .iter()
            .map(|m| m.name())
            .collect::<Vec<_>>()
            .join(", "),
        experiment.name(),
        experiment.scene(),
        args.runs,
        args.seconds
    );
    let mut all: BTreeMap<Method, Vec<Run>> = BTreeMap::new();
    // Runs alternate between methods so slow drifts of the machine hit all alike.
    'runs: for r in 0..args.runs {
        for &method in &methods {
            let seed = first_seed + r;
            let mut rows = Vec::new();
            let mut improvements: Improvements = Vec::new();
            let observer = |s: &GenerationStats<'_>| {
                rows.push(Row::of(s));
                let improved = improvements
                    .last()
                    .is_none_or(|(_, best, _)| s.best_so_far > *best);
                if s.best_so_far.is_finite() && improved {
                    improvements.push((
                        s.elapsed.as_secs_f64(),
                        s.best_so_far,
                        s.best_chromosome.clone(),
                    ));
                }
                if interrupted() {
                    ControlFlow::Break(())
                } else {
                    ControlFlow::Continue(())
                }
            };
            let mut observer = Interruptible {
                observer,
                flag: guard::interrupt_flag(),
            };
            let result =
                pool.install(|| experiment.run(method, &budget, seed, None, &mut observer))?;
            drop(observer);
            if !args.quiet {
                errln!(
                    "  {method:<6} run {} (seed {seed}): best {:.4} after {} generations, {} evaluations, {:.2} s ({})",
                    r + 1,
                    result.best_fitness,
                    result.generations,
                    result.evaluations,
                    result.elapsed.as_secs_f64(),
                    stop_words(result.stop)
                );
            }
            let iou_at = iou_at(&experiment, &improvements, args.seconds);
            all.entry(method).or_default().push(Run {
                seed,
                rows,
                result,
                iou_at,
            });
            if interrupted() {
                errln!("shapegen: interrupted; summarizing the finished runs");
                break 'runs;
            }
        }
    }
    // Written as a set: staged, then moved in with summary.json last.
    let stage = output::Stage::new(&args.out)?;
    let out = stage.path();
    let times: Vec<f64> = (0..=GRID)
        .map(|k| args.seconds * k as f64 / GRID as f64)
        .collect();
    let mut series = Vec::new();
    let mut curves_csv = String::from("method,seconds,mean_best,std_best,runs\n");
    // Per method: the mean curve on the time grid, and the final mean and std.
    let mut curves = BTreeMap::new();
    let mut finals = BTreeMap::new();
    for (&method, runs) in &all {
        // A method's curve ends where its last run ended (SMC, say, can
        // finish long before the budget): the grid up to there, then that
        // moment.
        let end = last_end(runs).min(args.seconds);
        let mut times: Vec<f64> = times.iter().copied().filter(|&t| t < end).collect();
        times.push(end);
        let stats: Vec<(f64, f64, usize)> = times.iter().map(|&t| at(runs, t)).collect();
        for (t, (mean, std, n)) in times.iter().zip(&stats) {
            let _ = writeln!(
                curves_csv,
                "{method},{t:.3},{},{},{n}",
                output::number(*mean),
                output::number(*std)
            );
        }
        finals.insert(method, mean_std(runs.iter().map(|r| r.result.best_fitness)));
        series.push(Series {
            name: method.name().to_string(),
            points: times
                .iter()
                .zip(&stats)
                .filter(|(_, (m, _, n))| m.is_finite() && *n == runs.len())
                .map(|(&t, &(m, s, _))| (t, m, s))
                .collect(),
        });
        curves.insert(method, stats);
    }
    let mut summary = CompareSummary {
        experiment: experiment.name().to_string(),
        seconds: args.seconds,
        runs: args.runs,
        threads,
        optimum: experiment.optimum(),
        methods: BTreeMap::new(),
    };
    // Each method's best model, for best_by_method.png.
    let mut best_pictures = Vec::new();
    for (&method, runs) in &all {
        let full = |t: f64| {
            let (m, s, n) = at(runs, t);
            (n == runs.len()).then_some((m, s))
        };
        let mut mean_at = BTreeMap::new();
        let mut std_at = BTreeMap::new();
        for f in FRACTIONS {
            let key = format!("{:.0}%", f * 100.0);
            let v = if f == 1.0 {
                Some(finals[&method])
            } else {
                full(f * args.seconds)
            };
            mean_at.insert(key.clone(), v.map(|v| v.0));
            std_at.insert(key, v.map(|v| v.1));
        }
        let mut iou = BTreeMap::new();
        for (k, f) in IOU_FRACTIONS.iter().enumerate() {
            let values: Option<Vec<f64>> = runs.iter().map(|r| r.iou_at[k]).collect();
            iou.insert(
                format!("{:.0}%", f * 100.0),
                values.map(|v| v.iter().sum::<f64>() / v.len() as f64),
            );
        }
        let (final_mean, final_std) = finals[&method];
        let (mut seconds_to_reach, mut evaluations_to_reach) = (BTreeMap::new(), BTreeMap::new());
        for (&other, &(goal, _)) in &finals {
            if other != method {
                let name = other.name().to_string();
                seconds_to_reach.insert(name.clone(), first_reaching(runs, goal, |r| r.seconds));
                evaluations_to_reach.insert(name, first_reaching(runs, goal, |r| r.evaluations));
            }
        }
        let best_run = runs
            .iter()
            .max_by(|a, b| a.result.best_fitness.total_cmp(&b.result.best_fitness))
            .expect("at least one run");
        let (worst, median) = worst_median(runs.iter().map(|r| r.result.best_fitness));
        let n = runs.len() as f64;
        summary.methods.insert(
            method.name().to_string(),
            MethodSummary {
                runs: runs.len(),
                final_mean,
                final_std,
                mean_at,
                std_at,
                iou_at: iou,
                seconds_to_reach,
                evaluations_to_reach,
                goal: args.goal.map(|fitness| GoalReached {
                    fitness,
                    seconds: first_reaching(runs, fitness, |row| row.seconds),
                    evaluations: first_reaching(runs, fitness, |row| row.evaluations),
                }),
                evaluations: runs
                    .iter()
                    .map(|r| r.result.evaluations as f64)
                    .sum::<f64>()
                    / n,
                generations: runs
                    .iter()
                    .map(|r| r.result.generations as f64)
                    .sum::<f64>()
                    / n,
                best: best_run.result.best_fitness,
                best_seed: best_run.seed,
                worst,
                median,
                each_run: runs.iter().map(RunSummary::of).collect(),
            },
        );
        let dir = out.join(method.name());
        best_pictures.push((
            format!("{method}: {:.3}", best_run.result.best_fitness),
            crate::gallery::best_view_picture(&experiment, &best_run.result.best, 320)
                .map_err(|e| CliError::msg(e.to_string()))?,
        ));
        experiment.write_model(&best_run.result.best, &dir)?;
        output::write_chromosome(&dir.join("best.json"), &experiment, &best_run.result.best)?;
    }
    if let Some(warning) = plot::labelled_row(&out.join("best_by_method.png"), &best_pictures)? {
        errln!("shapegen: warning: {warning}");
    }
    let mut runs_csv = String::from("method,run,seed,generation,seconds,evaluations,best,mean\n");
    for (method, runs) in &all {
        for (i, run) in runs.iter().enumerate() {
            for r in &run.rows {
                let _ = writeln!(
                    runs_csv,
                    "{method},{i},{},{},{:.6},{},{},{}",
                    run.seed,
                    r.generation,
                    r.seconds,
                    r.evaluations,
                    output::number(r.best),
                    output::number(r.mean)
                );
            }
        }
    }
    write_atomically(&out.join("curves.csv"), curves_csv.as_bytes())?;
    write_atomically(&out.join("runs.csv"), runs_csv.as_bytes())?;
    write_json(&out.join("summary.json"), &summary)?;
    let title = format!(
        "{}: mean best fitness ± std over {} run(s), {threads} thread(s)",
        experiment.name(),
        args.runs
    );
    if let Some(warning) = plot::curves(
        &out.join("curves.png"),
        &title,
        args.seconds,
        experiment.optimum(),
        &series,
    )? {
        errln!("shapegen: warning: {warning}");
    }
    stage.publish()?;
    let out = &args.out;
    outln!(
        "{:<8} {:>12} {:>12} {:>12} {:>8}   {:>6} {:>6} {:>6} {:>12}",
        "method",
        "10%",
        "50%",
        "100%",
        "worst",
        "IoU10%",
        "IoU50%",
        "IoU",
        "evaluations"
    );
    for (name, m) in &summary.methods {
        let cell = |k: &str| match (m.mean_at[k], m.std_at[k]) {
            (Some(a), Some(b)) => format!("{a:.3}±{b:.3}"),
            _ => "-".to_string(),
        };
        let iou = |k: &str| m.iou_at[k].map_or_else(|| "-".to_string(), |v| format!("{v:.3}"));
        outln!(
            "{name:<8} {:>12} {:>12} {:>12} {:>8.3}   {:>6} {:>6} {:>6} {:>12.0}",
            cell("10%"),
            cell("50%"),
            cell("100%"),
            m.worst,
            iou("10%"),
            iou("50%"),
            iou("100%"),
            m.evaluations
        );
    }
    for (name, m) in &summary.methods {
        if let Some(line) = early_stops(&m.each_run, args.seconds) {
            outln!("{name}: {line}");
        }
    }
    for (name, m) in &summary.methods {
        if let Some(g) = &m.goal {
            match (g.seconds, g.evaluations) {
                (Some(s), Some(e)) => outln!(
                    "{name} reaches {} after {s:.2} s, {e} evaluations",
                    g.fitness
                ),
                _ => outln!("{name} does not reach {} within the budget", g.fitness),
            }
        }
    }
    outln!(
        "wrote {0}/curves.csv, {0}/runs.csv, {0}/summary.json, {0}/curves.png, {0}/best_by_method.png and each method's best model in {0}/<method>/",
        out.display()
    );
    Ok(())
}

/// Why a run stopped, in words.
fn stop_words(stop: StopReason) -> &'static str {
    match stop {
        StopReason::Generations => "generation limit",
        StopReason::Evaluations => "evaluation limit",
        StopReason::WallTime => "time budget",
        StopReason::TargetFitness => "reached the target fitness",
        StopReason::Observer => "interrupted",
        StopReason::Exhausted => "finished: nothing left to do",
    }
}

/// A line on the runs that ended before `budget` seconds for another
/// reason than the budget (none if every run used its budget).
fn early_stops(runs: &[RunSummary], budget: f64) -> Option<String> {
    let early: Vec<&RunSummary> = runs
        .iter()
        .filter(|r| r.stop != StopReason::WallTime)
        .collect();
    if early.is_empty() {
        return None;
    }
    let each: Vec<String> = early
        .iter()
        .map(|r| {
            format!(
                "seed {} after {:.2} s ({})",
                r.seed,
                r.seconds,
                stop_words(r.stop)
            )
        })
        .collect();
    Some(format!(
        "{} of {} run(s) ended before the {budget} s budget: {}",
        early.len(),
        runs.len(),
        each.join(", ")
    ))
}

/// When the last of `runs` ended, in seconds.
fn last_end(runs: &[Run]) -> f64 {
    runs.iter()
        .map(|r| r.result.elapsed.as_secs_f64())
        .fold(0.0, f64::max)
}

/// The lowest and the median of `values` (NaN counts as lowest; NaN for none).
fn worst_median(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let mut v: Vec<f64> = values
        .map(|x| if x.is_nan() { f64::NEG_INFINITY } else { x })
        .collect();
    if v.is_empty() {
        return (f64::NAN, f64::NAN);
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    let median = if n % 2 == 1 {
        v[n / 2]
    } else {
        (v[n / 2 - 1] + v[n / 2]) / 2.0
    };
    (v[0], median)
}

/// Mean, standard deviation and count of the runs' best-so-far at time `t`
/// (runs without a valid model by then do not count).
fn at(runs: &[Run], t: f64) -> (f64, f64, usize) {
    let values: Vec<f64> = runs
        .iter()
        .filter_map(|r| {
            r.rows
                .iter()
                .take_while(|row| row.seconds <= t)
                .last()
                .map(|row| row.best)
                .filter(|b| b.is_finite())
        })
        .collect();
    let (m, s) = mean_std(values.iter().copied());
    (m, s, values.len())
}

/// The first value of `key` (a row's seconds or evaluations, which grow
/// along each run) at which the mean of the runs' best so far (each run's
/// last row at or before it) reaches `goal`, every run having a valid
/// model. The mean changes only at rows: one sweep over all runs' rows in
/// the order of `key`. (Of rows with equal keys, checking after each is
/// enough: a best so far only grows, so a mean that reaches the goal
/// before the last of them still does after it.)
fn first_reaching<K: PartialOrd + Copy>(
    runs: &[Run],
    goal: f64,
    key: impl Fn(&Row) -> K,
) -> Option<K> {
    let key = &key;
    let mut rows: Vec<(K, usize, f64)> = (runs.iter().enumerate())
        .flat_map(|(i, r)| r.rows.iter().map(move |row| (key(row), i, row.best)))
        .collect();
    // Stable: a run's rows with equal keys stay in their order.
    rows.sort_by(|a, b| a.0.partial_cmp(&b.0).unwrap_or(std::cmp::Ordering::Equal));
    let mut best = vec![f64::NAN; runs.len()];
    for &(k, i, b) in &rows {
        if b.is_finite() {
            best[i] = b;
        }
        // The mean as `mean_std` takes it (the same sum in the same order),
        // without its copy and its standard deviation at every row.
        if best.iter().all(|b| b.is_finite())
            && best.iter().sum::<f64>() / best.len() as f64 >= goal
        {
            return Some(k);
        }
    }
    None
}

/// Mean and (population) standard deviation; NaN for no values.
fn mean_std(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let v: Vec<f64> = values.filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return (f64::NAN, f64::NAN);
    }
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n;
    (mean, var.sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(seconds: f64, best: f64) -> Row {
        Row {
            generation: 0,
            seconds,
            evaluations: 0,
            best,
            mean: best,
            std: 0.0,
        }
    }

    /// A run with these rows.
    fn run(rows: Vec<Row>) -> Run {
        Run {
            seed: 0,
            rows,
            iou_at: Vec::new(),
            result: RunResult {
                best: Chromosome::root(
                    &crate::demo::blocks_graph(),
                    &mut crate::rng::stream(0, &[]),
                ),
                best_fitness: 0.0,
                evaluations: 0,
                generations: 0,
                elapsed: std::time::Duration::ZERO,
                stop: crate::optimize::StopReason::WallTime,
                population: Vec::new(),
            },
        }
    }

    /// [`first_reaching`] written plainly: every row's key in turn, the
    /// mean of the runs' last rows at or before it, as [`at`] takes them.
    fn first_reaching_reference<K: PartialOrd + Copy>(
        runs: &[Run],
        goal: f64,
        key: impl Fn(&Row) -> K,
    ) -> Option<K> {
        let mut keys: Vec<K> = runs.iter().flat_map(|r| r.rows.iter().map(&key)).collect();
        keys.sort_by(|a, b| a.partial_cmp(b).expect("no NaN keys"));
        keys.into_iter().find(|&k| {
            let bests: Vec<f64> = (runs.iter())
                .filter_map(|r| {
                    (r.rows.iter().take_while(|row| key(row) <= k).last())
                        .map(|row| row.best)
                        .filter(|b| b.is_finite())
                })
                .collect();
            bests.len() == runs.len() && mean_std(bests.into_iter()).0 >= goal
        })
    }

    proptest::proptest! {
        /// Over random runs (rows with equal times or evaluations, runs
        /// without a valid model at first, goals the means hit exactly).
        #[test]
        fn the_goal_is_reached_where_the_plain_search_says(
            runs in proptest::collection::vec(
                proptest::collection::vec((0u8..3, 0u8..3, 0u8..2, 0u8..4), 0..12),
                1..4,
            ),
            goal in 0u8..12,
        ) {
            let runs: Vec<Run> = runs
                .into_iter()
                .map(|steps| {
                    let (mut t, mut e, mut best) = (0.0, 0, f64::NAN);
                    let rows = steps.into_iter().map(|(dt, de, valid, gain)| {
                        t += f64::from(dt) * 0.5;
                        e += u64::from(de) * 100;
                        if valid == 1 || best.is_finite() {
                            best = best.max(0.0) + f64::from(gain);
                        }
                        let mut r = row(t, best);
                        r.evaluations = e;
                        r
                    });
                    run(rows.collect())
                })
                .collect();
            let goal = f64::from(goal) * 0.5;
            proptest::prop_assert_eq!(
                first_reaching(&runs, goal, |r| r.seconds),
                first_reaching_reference(&runs, goal, |r| r.seconds)
            );
            proptest::prop_assert_eq!(
                first_reaching(&runs, goal, |r| r.evaluations),
                first_reaching_reference(&runs, goal, |r| r.evaluations)
            );
        }
    }

    #[test]
    fn the_goal_is_reached_when_every_run_counts() {
        let runs = [
            run(vec![row(0.5, f64::NAN), row(1.0, 1.0), row(2.0, 3.0)]),
            run(vec![row(0.2, 2.0), row(1.5, 5.0)]),
        ];
        // At 0.2 s the one valid run alone has 2.0: not yet.
        assert_eq!(first_reaching(&runs, 1.5, |r| r.seconds), Some(1.0));
        assert_eq!(first_reaching(&runs, 3.0, |r| r.seconds), Some(1.5));
        assert_eq!(first_reaching(&runs, 4.0, |r| r.seconds), Some(2.0));
        assert_eq!(first_reaching(&runs, 4.5, |r| r.seconds), None);
    }

    #[test]
    fn curves_take_the_last_row_at_or_before_t() {
        let runs = [
            run(vec![row(0.5, f64::NAN), row(1.0, 1.0), row(2.0, 3.0)]),
            run(vec![row(0.2, 2.0), row(1.5, 5.0)]),
        ];
        assert_eq!(at(&runs, 0.1).2, 0);
        assert_eq!(at(&runs, 0.6), (2.0, 0.0, 1));
        assert_eq!(at(&runs, 1.0), (1.5, 0.5, 2));
        assert_eq!(at(&runs, 9.0), (4.0, 1.0, 2));
        assert!(mean_std(std::iter::empty()).0.is_nan());
    }

    #[test]
    fn the_worst_and_the_median_of_the_finals() {
        assert_eq!(worst_median([3.0, 1.0, 2.0].into_iter()), (1.0, 2.0));
        assert_eq!(worst_median([4.0, 1.0, 2.0, 3.0].into_iter()), (1.0, 2.5));
        let (worst, median) = worst_median([f64::NAN, 1.0].into_iter());
        assert_eq!((worst, median), (f64::NEG_INFINITY, f64::NEG_INFINITY));
        assert!(worst_median(std::iter::empty()).0.is_nan());
    }

    #[test]
    fn runs_that_end_early_are_named_with_their_reason() {
        let mut early = run(vec![row(0.02, 1.0)]);
        early.result.stop = StopReason::Exhausted;
        early.result.elapsed = std::time::Duration::from_millis(20);
        early.seed = 7;
        let mut full = run(vec![row(10.0, 1.0)]);
        full.result.elapsed = std::time::Duration::from_secs(10);
        let runs = [RunSummary::of(&full), RunSummary::of(&early)];
        assert_eq!(
            early_stops(&runs, 10.0).as_deref(),
            Some(
                "1 of 2 run(s) ended before the 10 s budget: seed 7 after 0.02 s (finished: nothing left to do)"
            )
        );
        assert_eq!(early_stops(&runs[..1], 10.0), None);
        assert_eq!(last_end(&[full, early]), 10.0);
    }
}
