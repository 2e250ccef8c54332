//! `shapegen design sample | learn | export`: a pdf design session from the
//! command line (see [`crate::design::session`]); `shapegen design evaluate`:
//! the thesis's evaluation on built-in tasks.

use std::path::Path;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::args::{
    DesignCommand, DesignEvaluateArgs, DesignExportArgs, DesignLearnArgs, DesignSampleArgs,
    DesignServeArgs, SamplerArg, SessionArgs,
};
use super::{Cli, CliError, guard, thread_pool};
use crate::design::session::{Session, Shown};
use crate::design::{FactorOptions, Learner, StructureOptions};
use crate::experiment::Experiment;

/// One model of a batch's scores file.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ScoreEntry {
    /// The model's id in the session.
    pub id: u64,
    /// Its thumbnail, relative to the scores file.
    pub thumbnail: String,
    /// The learned preference's prediction, if any.
    pub predicted: Option<f64>,
    /// Its standard deviation.
    pub std: Option<f64>,
    /// The score to fill in (0-100), or null to skip the model.
    pub score: Option<f64>,
}

/// A batch's scores file (`scores.json`).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ScoresFile {
    /// What to do with it.
    pub instructions: String,
    /// The generator.
    pub generator: String,
    /// The factor the scores are for.
    pub factor: String,
    /// How the batch was drawn.
    pub mode: String,
    /// The models.
    pub models: Vec<ScoreEntry>,
}

/// Runs `shapegen design …`.
pub(super) fn design(cli: &Cli, command: DesignCommand) -> Result<(), CliError> {
    match command {
        DesignCommand::Sample(a) => sample(cli, &a),
        DesignCommand::Learn(a) => learn(cli, &a),
        DesignCommand::Export(a) => export(cli, &a),
        DesignCommand::Evaluate(a) => evaluate(&a),
        DesignCommand::Serve(a) => serve(cli, &a),
    }
}

fn load(cli: &Cli, args: &SessionArgs) -> Result<Experiment, CliError> {
    cli.load_experiment(
        args.experiment.experiment.as_deref(),
        args.experiment.data.as_deref(),
    )
}

fn open_session(experiment: &Experiment, path: &Path) -> Result<Session, CliError> {
    if !path.exists() {
        return Err(CliError::msg(format!(
            "no session at {}: start one with `shapegen design sample --session {}`",
            path.display(),
            path.display()
        )));
    }
    Session::load(path, experiment.generator(), experiment.graph())
        .map_err(|e| CliError::msg(e.to_string()))
}

fn sample(cli: &Cli, args: &DesignSampleArgs) -> Result<(), CliError> {
    let experiment = load(cli, &args.session)?;
    if args.count == 0 || args.count > 1000 {
        return Err(CliError::msg(format!(
            "--count must be 1 to 1000, got {}",
            args.count
        )));
    }
    if !(16..=1024).contains(&args.thumbnail) {
        return Err(CliError::msg(format!(
            "--thumbnail must be 16 to 1024 pixels, got {}",
            args.thumbnail
        )));
    }
    let path = &args.session.session;
    let mut session = if path.exists() {
        open_session(&experiment, path)?
    } else {
        Session::new(
            experiment.generator(),
            experiment.graph(),
            args.seed.unwrap_or(experiment.seed()),
        )
    };
    if let Some(f) = &args.factor {
        session
            .select_factor(f)
            .map_err(|e| CliError::msg(format!("--factor: {e}")))?;
    }
    // Every output checked before anything is drawn.
    guard::check_output_file(path)?;
    let _taken = guard::take_output_dir(&args.out)?;
    let scores_path = args.out.join("scores.json");
    guard::refuse_overwriting_inputs(
        &[
            scores_path.clone(),
            args.out.join("index.html"),
            path.clone(),
        ],
        experiment.inputs(),
    )?;
    let pool = thread_pool(args.threads)?;
    let shown = pool
        .install(|| session.sample(experiment.graph(), args.mode, args.count))
        .map_err(|e| CliError::msg(e.to_string()))?;
    let thumbnails: Vec<image::RgbaImage> = pool.install(|| {
        shown
            .par_iter()
            .map(|s| crate::gallery::best_view_picture(&experiment, &s.model, args.thumbnail))
            .collect::<Result<_, _>>()
            .map_err(|e| CliError::msg(e.to_string()))
    })?;
    let factor = session.factors[session.current].name.clone();
    let entries: Vec<ScoreEntry> = shown
        .iter()
        .map(|s| ScoreEntry {
            id: s.id,
            thumbnail: format!("model_{:06}.png", s.id),
            predicted: s.predicted.map(|p| p.0),
            std: s.predicted.map(|p| p.1),
            score: s.score,
        })
        .collect();
    guard::writing(|| -> Result<(), CliError> {
        for (e, img) in entries.iter().zip(&thumbnails) {
            crate::score::write_png_rgba(&args.out.join(&e.thumbnail), img)?;
        }
        let file = ScoresFile {
            instructions: "Give each model a score from 0 (not wanted) to 100 (most wanted) in its `score` field (leave null to skip), then run `shapegen design learn`.".into(),
            generator: experiment.generator().to_string(),
            factor: factor.clone(),
            mode: args.mode.name().into(),
            models: entries.clone(),
        };
        crate::output::write_json(&scores_path, &file)?;
        let html = page(
            experiment.generator(),
            &factor,
            args.mode.name(),
            &shown,
            &entries,
        );
        crate::score::write_atomically(&args.out.join("index.html"), html.as_bytes())?;
        session.save(path).map_err(|e| CliError::msg(e.to_string()))
    })?;
    outln!(
        "{} models of `{}` ({} pdf) for factor `{factor}`: open {} and fill in the scores in {}, then run `shapegen design learn --session {} --scores {}`",
        shown.len(),
        experiment.generator(),
        args.mode.name(),
        args.out.join("index.html").display(),
        scores_path.display(),
        path.display(),
        scores_path.display()
    );
    Ok(())
}

/// The batch as a page of thumbnails with ids (and predictions once learned).
fn page(
    generator: &str,
    factor: &str,
    mode: &str,
    shown: &[Shown],
    entries: &[ScoreEntry],
) -> String {
    let esc = |s: &str| {
        s.replace('&', "&amp;")
            .replace('<', "&lt;")
            .replace('>', "&gt;")
    };
    let mut cells = String::new();
    for (s, e) in shown.iter().zip(entries) {
        let mut caption = format!("model {}", e.id);
        if let Some((m, sd)) = s.predicted {
            caption += &format!(" · predicted {m:.0} ± {sd:.0}");
        }
        if let Some(score) = s.score {
            caption += &format!(" · scored {score:.0}");
        }
        cells += &format!(
            "<figure><img src=\"{}\" alt=\"model {}\"><figcaption>{}</figcaption></figure>\n",
            esc(&e.thumbnail),
            e.id,
            esc(&caption)
        );
    }
    format!(
        "<!doctype html><html><head><meta charset=\"utf-8\"><title>{g}: score these models</title>\
<style>body{{font-family:sans-serif;margin:1.5em}}main{{display:flex;flex-wrap:wrap;gap:12px}}figure{{margin:0;text-align:center}}img{{border:1px solid #ccc}}figcaption{{font-size:0.9em}}</style>\
</head><body><h1>{g}: factor “{f}”, {m} pdf</h1><p>Score each model from 0 to 100 in <code>scores.json</code> (by its id), then run <code>shapegen design learn</code>.</p><main>\n{cells}</main></body></html>\n",
        g = esc(generator),
        f = esc(factor),
        m = esc(mode),
    )
}

fn learn(cli: &Cli, args: &DesignLearnArgs) -> Result<(), CliError> {
    let experiment = load(cli, &args.session)?;
    let path = &args.session.session;
    let mut session = open_session(&experiment, path)?;
    crate::experiment::check_regular_file(&args.scores).map_err(CliError::msg)?;
    let text = std::fs::read_to_string(&args.scores)
        .map_err(|e| CliError::msg(format!("cannot read {}: {e}", args.scores.display())))?;
    let file: ScoresFile = serde_json::from_str(&text).map_err(|e| {
        CliError::msg(format!(
            "{}: not a scores file written by `design sample`: {e}",
            args.scores.display()
        ))
    })?;
    if file.generator != experiment.generator() {
        return Err(CliError::msg(format!(
            "{} holds models of `{}`, the experiment's generator is `{}`",
            args.scores.display(),
            file.generator,
            experiment.generator()
        )));
    }
    guard::check_output_file(path)?;
    session
        .select_factor(&file.factor)
        .map_err(|e| CliError::msg(format!("{}: {e}; nothing was saved", args.scores.display())))?;
    let mut ids: Vec<u64> = file.models.iter().map(|e| e.id).collect();
    ids.sort_unstable();
    if let Some(w) = ids.windows(2).find(|w| w[0] == w[1]) {
        return Err(CliError::msg(format!(
            "{} lists model {} twice: which score is meant? nothing was saved",
            args.scores.display(),
            w[0]
        )));
    }
    let mut added = 0;
    for e in file.models.iter().filter(|e| e.score.is_some()) {
        let score = e.score.unwrap_or_default();
        session.score(e.id, score).map_err(|err| {
            CliError::msg(format!(
                "{}: {err}; nothing was saved",
                args.scores.display()
            ))
        })?;
        added += 1;
    }
    // Scores are kept even if fitting fails.
    session
        .save(path)
        .map_err(|e| CliError::msg(e.to_string()))?;
    let graph = experiment.graph();
    let preference = session
        .learn(graph, FactorOptions::default())
        .map_err(|e| CliError::msg(e.to_string()))?
        .clone();
    session
        .save(path)
        .map_err(|e| CliError::msg(e.to_string()))?;
    outln!(
        "{added} scores added ({} scored in all); learned {} factor(s):",
        session.scored_count(),
        preference.factors.len()
    );
    for f in &preference.factors {
        outln!(
            "  `{}` from {} models, path length {}; most relevant features:",
            f.name,
            f.gp.len(),
            f.space.options().path_length
        );
        let max = f.gp.weights().iter().copied().fold(0.0, f64::max);
        for (name, w) in f
            .top_features(graph, 6)
            .into_iter()
            .filter(|(_, w)| *w > 0.0 && *w >= 0.05 * max)
        {
            outln!("    {w:8.3}  {name}");
        }
    }
    outln!(
        "next: `shapegen design sample --mode current` to see what it learned, or `shapegen design export`"
    );
    Ok(())
}

fn export(cli: &Cli, args: &DesignExportArgs) -> Result<(), CliError> {
    let experiment = load(cli, &args.session)?;
    let path = &args.session.session;
    let session = open_session(&experiment, path)?;
    if args.training == 0 || args.training > 1_000_000 {
        return Err(CliError::msg(format!(
            "--training must be 1 to 1000000, got {}",
            args.training
        )));
    }
    guard::check_output_file(&args.out)?;
    guard::refuse_overwriting_inputs(
        std::slice::from_ref(&args.out),
        &[experiment.inputs(), std::slice::from_ref(path)].concat(),
    )?;
    let learner = match args.sampler {
        SamplerArg::Structure => Learner::Structure,
        SamplerArg::Parameter => Learner::Parameter,
    };
    let mut rng = session.export_stream(args.seed);
    let (pdf, report, acceptance) = session
        .export(
            experiment.graph(),
            learner,
            args.training,
            StructureOptions::default(),
            &mut rng,
        )
        .map_err(|e| CliError::msg(e.to_string()))?;
    guard::writing(|| crate::output::write_json(&args.out, &pdf))?;
    out!(
        "{} learned generator of `{}`: {} component(s) from {} models drawn by rejection (acceptance {:.1} %)",
        pdf.method,
        experiment.generator(),
        pdf.components.len(),
        args.training,
        100.0 * acceptance
    );
    if let Some(r) = report {
        out!(
            "; split {:?} into {} nodes",
            r.split_nodes,
            r.split_graph_nodes
        );
    }
    outln!(
        "; wrote {} (use it with `shapegen gallery --prior {}` or `shapegen run --prior {}`)",
        args.out.display(),
        args.out.display(),
        args.out.display()
    );
    Ok(())
}

fn evaluate(args: &DesignEvaluateArgs) -> Result<(), CliError> {
    use crate::design::evaluation::{EvalOptions, EvalReport, evaluate};
    use std::fmt::Write as _;
    let all = crate::design::tasks::all();
    if let Some(unknown) = args
        .tasks
        .iter()
        .find(|t| !all.iter().any(|a| &a.name == *t))
    {
        let names: Vec<&str> = all.iter().map(|t| t.name.as_str()).collect();
        return Err(CliError::msg(format!(
            "unknown task `{unknown}`: choose from {}",
            names.join(", ")
        )));
    }
    let tasks: Vec<_> = all
        .into_iter()
        .filter(|t| args.tasks.is_empty() || args.tasks.contains(&t.name))
        .collect();
    let mut options = EvalOptions {
        seed: args.seed,
        ..EvalOptions::default()
    };
    if args.quick {
        options.eval_set = 1000;
        options.training = 500;
        options.fit_models = 96;
        options.scored = vec![12, 24, 48, 96];
    }
    if !args.scored.is_empty() {
        if let Some(&bad) = args.scored.iter().find(|&&n| n == 0 || n > 5000) {
            return Err(CliError::msg(format!(
                "--scored takes 1 to 5000 models, got {bad}"
            )));
        }
        let mut scored = args.scored.clone();
        scored.sort_unstable();
        scored.dedup();
        options.scored = scored;
    }
    let _taken = guard::take_output_dir(&args.out)?;
    let pool = thread_pool(args.threads)?;
    let mut reports: Vec<EvalReport> = Vec::new();
    for task in &tasks {
        let start = std::time::Instant::now();
        let r = pool
            .install(|| evaluate(task, &options))
            .map_err(|e| CliError::msg(format!("task {}: {e}", task.name)))?;
        if !args.quiet {
            errln!(
                "{:10} JS default {:.4}, parameter {:.4}, structure {:.4}; GPR reaches 0.01 after {}, KDE after {}, interactive GPR after {} scored models ({:.0} s)",
                r.task,
                r.js_default,
                r.js_parameter,
                r.js_structure,
                reach(r.gpr_reaches_001),
                reach(r.kde_reaches_001),
                reach(r.active_reaches_001),
                start.elapsed().as_secs_f64()
            );
        }
        reports.push(r);
    }
    let mut table = String::new();
    let _ = writeln!(
        table,
        "| task | preference | default | parameter learning | structure learning | K | split nodes |"
    );
    let _ = writeln!(table, "|---|---|---|---|---|---|---|");
    for r in &reports {
        let _ = writeln!(
            table,
            "| {} | {} | {:.4} | {:.4} | {:.4} | {} | {} |",
            r.task,
            r.description,
            r.js_default,
            r.js_parameter,
            r.js_structure,
            r.components,
            r.structure.split_nodes.join(", ")
        );
    }
    let _ = writeln!(table);
    let _ = writeln!(
        table,
        "| task | GPR reaches JS 0.01 after | KDE (best bandwidth) after | interactive GPR after | GPR / KDE / interactive at the largest n |"
    );
    let _ = writeln!(table, "|---|---|---|---|---|");
    for r in &reports {
        let last = r.curve.last();
        let _ = writeln!(
            table,
            "| {} | {} | {} | {} | {} |",
            r.task,
            reach(r.gpr_reaches_001),
            reach(r.kde_reaches_001),
            reach(r.active_reaches_001),
            last.map_or(String::new(), |p| format!(
                "{:.4} / {:.4} / {} (n = {})",
                p.gpr,
                p.kde,
                r.active
                    .last()
                    .map_or("-".into(), |a| format!("{:.4}", a.1)),
                p.scored
            ))
        );
    }
    let panels: Vec<super::plot::Panel> = reports
        .iter()
        .map(|r| super::plot::Panel {
            title: format!("{} {}", r.task, r.description),
            lines: vec![
                (
                    "GPR".into(),
                    r.curve.iter().map(|p| (p.scored as f64, p.gpr)).collect(),
                ),
                (
                    "weighted KDE (best h)".into(),
                    r.curve.iter().map(|p| (p.scored as f64, p.kde)).collect(),
                ),
                (
                    "GPR, interactive".into(),
                    r.active.iter().map(|p| (p.0 as f64, p.1)).collect(),
                ),
            ],
            levels: vec![
                ("default".into(), r.js_default),
                ("parameter l.".into(), r.js_parameter),
                ("structure l.".into(), r.js_structure),
            ],
        })
        .collect();
    let png = args.out.join("curves.png");
    guard::writing(|| -> Result<(), CliError> {
        crate::output::write_json(&args.out.join("evaluation.json"), &reports)?;
        crate::score::write_atomically(&args.out.join("table.md"), table.as_bytes())?;
        if let Some(w) = super::plot::panels(
            &png,
            "scored models",
            "JS divergence to the target",
            2,
            1e-4,
            &panels,
        )? {
            errln!("shapegen: warning: {w}");
        }
        Ok(())
    })?;
    out!("{table}");
    outln!(
        "wrote evaluation.json, table.md and curves.png to {}",
        args.out.display()
    );
    Ok(())
}

fn reach(n: Option<usize>) -> String {
    n.map_or("not within the curve".into(), |n| n.to_string())
}

fn serve(cli: &Cli, args: &DesignServeArgs) -> Result<(), CliError> {
    let experiment = load(cli, &args.session)?;
    let path = &args.session.session;
    guard::check_output_file(path)?;
    guard::refuse_overwriting_inputs(std::slice::from_ref(path), experiment.inputs())?;
    let seed = args.seed.unwrap_or(experiment.seed());
    let generator = experiment.generator().to_string();
    let server =
        crate::design::server::DesignServer::new(experiment, path, seed).map_err(CliError::msg)?;
    let address = format!("{}:{}", args.host, args.port);
    guard::on_interrupt_say("stopping the server; every change is already saved");
    server
        .serve(&address, |bound| {
            let url = format!("http://{bound}/");
            outln!(
                "designing the pdf of `{generator}` in {}: open {url} (Ctrl-C to stop; every score is saved as it is given)",
                path.display()
            );
            if args.open {
                let opener = if cfg!(target_os = "macos") { "open" } else if cfg!(windows) { "explorer" } else { "xdg-open" };
                if std::process::Command::new(opener).arg(&url).spawn().is_err() {
                    errln!("shapegen: could not open a browser; open {url} yourself");
                }
            }
        }, &guard::interrupted)
        .map_err(CliError::msg)?;
    outln!("stopped; the session is saved in {}", path.display());
    Ok(())
}
