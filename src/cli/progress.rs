//! Progress of a run on the terminal: an indicatif bar, or a line every few
//! seconds when standard error is not a terminal.

use std::ops::ControlFlow;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use crate::experiment::Experiment;
use crate::optimize::{Budget, GenerationStats, Observer};
use crate::output::mean_iou;

/// A bar counting `len` items of `unit` (`models`, `frames`, ...) with
/// `message` before it, elapsed time and an estimate of what is left: the
/// bar of every command that works through a known number of items.
pub(super) fn counting_bar(
    len: usize,
    unit: &str,
    message: impl Into<std::borrow::Cow<'static, str>>,
) -> ProgressBar {
    let bar = ProgressBar::new(len as u64);
    bar.set_style(
        ProgressStyle::with_template(&format!(
            "{{msg}} [{{bar:30}}] {{pos}}/{{len}} {unit}, {{elapsed}} (eta {{eta}})"
        ))
        .expect("valid template")
        .progress_chars("=> "),
    );
    bar.set_message(message);
    bar
}

/// How often the IoU of the best model is recomputed for the display (it
/// costs one extra scoring of that model).
const IOU_EVERY: Duration = Duration::from_millis(500);

/// Shows a run's progress: generation, evaluations per second, best and
/// mean fitness, and (with [`with_quality`](Self::with_quality)) the IoU of
/// the best model so far. An [`Observer`] by itself, or called from another
/// observer with [`update`](Self::update).
///
/// ```no_run
/// use shapegen::cli::Progress;
/// use shapegen::experiment::{Experiment, Method};
/// use shapegen::optimize::Budget;
///
/// let experiment = Experiment::builtin();
/// let budget = Budget::generations(50);
/// let mut progress = Progress::new(&budget, false).with_quality(&experiment);
/// let result = experiment.run(Method::Ga, &budget, 1, None, &mut progress)?;
/// progress.finish();
/// # Ok::<(), shapegen::experiment::ExperimentError>(())
/// ```
pub struct Progress<'a> {
    bar: Option<ProgressBar>,
    budget: Budget,
    quiet: bool,
    last_line: Instant,
    last: Option<(f64, u64)>,
    experiment: Option<&'a Experiment>,
    /// The best fitness whose IoU is shown, the IoU, and when it was computed.
    iou: Option<(f64, f64, Instant)>,
}

impl<'a> Progress<'a> {
    /// A display for a run with `budget`; `quiet` shows nothing.
    #[must_use]
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
            experiment: None,
            iou: None,
        }
    }

    /// Also shows the IoU of the best model so far with `experiment`'s
    /// targets (mean over targets).
    #[must_use]
    pub fn with_quality(mut self, experiment: &'a Experiment) -> Self {
        self.experiment = Some(experiment);
        self
    }

    /// Shows one generation.
    pub fn update(&mut self, s: &GenerationStats<'_>) {
        if self.quiet {
            return;
        }
        let secs = s.elapsed.as_secs_f64();
        let rate = match self.last {
            Some((t, e)) if secs > t => (s.evaluations - e) as f64 / (secs - t),
            _ => s.evaluations as f64 / secs.max(1e-9),
        };
        self.last = Some((secs, s.evaluations));
        let iou = self.iou(s);
        let message = format!(
            "gen {} | {:.0} eval/s | best {:.4}{} | mean {:.4}",
            s.generation,
            rate,
            s.best_so_far,
            iou.map(|i| format!(" (IoU {i:.3})")).unwrap_or_default(),
            s.mean
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
        } else if self.last_line.elapsed() >= Duration::from_secs(2) || s.generation == 0 {
            self.last_line = Instant::now();
            errln!(
                "  {:>3.0}% {message} ({secs:.1} s)",
                fraction.min(1.0) * 100.0
            );
        }
    }

    /// The IoU of the best model so far, recomputed when the best changed
    /// and [`IOU_EVERY`] has passed.
    fn iou(&mut self, s: &GenerationStats<'_>) -> Option<f64> {
        let experiment = self.experiment?;
        if !s.best_so_far.is_finite() {
            return None;
        }
        let stale = match self.iou {
            None => true,
            Some((fitness, _, at)) => fitness != s.best_so_far && at.elapsed() >= IOU_EVERY,
        };
        if stale {
            let iou = mean_iou(&experiment.quality(s.best_chromosome));
            self.iou = Some((s.best_so_far, iou, Instant::now()));
        }
        self.iou.map(|(_, iou, _)| iou)
    }

    /// Removes the bar.
    pub fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

impl Observer for Progress<'_> {
    fn generation(&mut self, stats: &GenerationStats<'_>) -> ControlFlow<()> {
        self.update(stats);
        ControlFlow::Continue(())
    }
}
