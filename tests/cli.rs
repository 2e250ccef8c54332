//! The `shapegen` command line as a user runs it: `run` on the built-in and
//! on a paper experiment, `compare`, `render`, checkpoint and resume, and
//! clear errors for bad input.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

use crate::util::json;

fn shapegen(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_shapegen"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn ok(args: &[&str]) -> String {
    let out = shapegen(args);
    assert!(
        out.status.success(),
        "shapegen {args:?} failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn failure(args: &[&str]) -> String {
    let out = shapegen(args);
    assert!(!out.status.success(), "shapegen {args:?} should fail");
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!err.contains("panicked"), "{err}");
    err
}

/// A fresh temporary directory for one test of this module.
fn temp(name: &str) -> PathBuf {
    crate::util::temp("cli", name)
}

/// `curve.csv` rows as numbers (empty fields are NaN).
fn curve(path: &Path) -> Vec<Vec<f64>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| {
            l.split(',')
                .map(|x| x.parse().unwrap_or(f64::NAN))
                .collect()
        })
        .collect()
}

/// The summary agrees with the curve: generations, evaluations, best so far.
fn check_consistent(dir: &Path) -> Value {
    let summary = json(&dir.join("summary.json"));
    let rows = curve(&dir.join("curve.csv"));
    let last = rows.last().unwrap();
    assert_eq!(last[0], summary["generations"].as_f64().unwrap());
    assert_eq!(last[2], summary["evaluations"].as_f64().unwrap());
    assert_eq!(last[3], summary["best_fitness"].as_f64().unwrap());
    // Best so far never decreases; time and evaluations never go back.
    for w in rows.windows(2) {
        assert!(w[1][1] >= w[0][1] && w[1][2] >= w[0][2]);
        assert!(
            w[0][3].is_nan() || w[1][3] >= w[0][3],
            "best so far decreased: {w:?}"
        );
    }
    summary
}

#[test]
fn run_on_the_builtin_experiment_writes_consistent_results() {
    let out = temp("run");
    let o = out.to_str().unwrap();
    ok(&[
        "run",
        "--generations",
        "15",
        "--seed",
        "3",
        "--out",
        o,
        "-q",
    ]);
    for f in [
        "best.obj",
        "target.obj",
        "best.json",
        "curve.csv",
        "summary.json",
        "slice_x.png",
        "slice_y.png",
        "slice_z.png",
        "best.png",
        "population.png",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    // The pictures show a model: many pixels that are not background.
    for f in ["best.png", "population.png"] {
        let img = image::open(out.join(f)).unwrap().to_rgb8();
        let drawn = img.pixels().filter(|p| p.0 != [255, 255, 255]).count();
        assert!(drawn * 50 > img.len() / 3, "{f}: only {drawn} pixels drawn");
    }
    let summary = check_consistent(&out);
    assert_eq!(summary["generations"], 15);
    assert_eq!(summary["seed"], 3);
    assert_eq!(summary["method"], "tandem");
    let best = summary["best_fitness"].as_f64().unwrap();
    assert!(best > 0.0 && best <= 2.0, "{best}");
    assert_eq!(curve(&out.join("curve.csv")).len(), 16);

    // render re-expresses best.json to the same fitness.
    let rendered = out.join("render");
    let text = ok(&[
        "render",
        out.join("best.json").to_str().unwrap(),
        "--out",
        rendered.to_str().unwrap(),
    ]);
    assert!(text.contains(&format!("fitness {best:.4}")), "{text}");
    assert_eq!(
        std::fs::read(rendered.join("best.obj")).unwrap(),
        std::fs::read(out.join("best.obj")).unwrap()
    );
    std::fs::remove_dir_all(&out).ok();
}

#[test]
fn a_resumed_run_ends_like_the_uninterrupted_one() {
    let dir = temp("resume");
    let (whole, part, resumed) = (dir.join("whole"), dir.join("part"), dir.join("resumed"));
    let cp = dir.join("run.checkpoint");
    for method in ["ga", "sosmc", "rjmcmc"] {
        let args = ["run", "--method", method, "--seed", "5", "-q", "--threads"];
        ok(&[
            &args[..],
            &["2", "--generations", "12", "--out", whole.to_str().unwrap()],
        ]
        .concat());
        // Stop at generation 6 with a checkpoint, then resume to 12 on one thread.
        ok(&[
            &args[..],
            &["2", "--generations", "6", "--out", part.to_str().unwrap()],
            &["--checkpoint", cp.to_str().unwrap(), "--every", "3"],
        ]
        .concat());
        ok(&[
            "run",
            "--resume",
            cp.to_str().unwrap(),
            "--generations",
            "12",
            "--threads",
            "1",
            "-q",
            "--out",
            resumed.to_str().unwrap(),
        ]);
        let (a, b) = (check_consistent(&whole), check_consistent(&resumed));
        for key in [
            "best_fitness",
            "evaluations",
            "generations",
            "best_genes",
            "seed",
        ] {
            assert_eq!(a[key], b[key], "{method}: {key}");
        }
        assert_eq!(b["resumed"], true);
        assert_eq!(
            std::fs::read(whole.join("best.json")).unwrap(),
            std::fs::read(resumed.join("best.json")).unwrap(),
            "{method}"
        );
        let (ca, cb) = (
            curve(&whole.join("curve.csv")),
            curve(&resumed.join("curve.csv")),
        );
        assert_eq!(ca.len(), cb.len());
        for (x, y) in ca.iter().zip(&cb) {
            // Same generation, evaluations and fitness (times differ).
            assert_eq!((x[0], x[2]), (y[0], y[2]));
            assert_eq!(x[3].to_bits(), y[3].to_bits());
        }
    }
    // A checkpoint refuses another method.
    let err = failure(&["run", "--resume", cp.to_str().unwrap(), "--method", "ga"]);
    assert!(err.contains("does not match"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn compare_writes_curves_and_a_summary() {
    let out = temp("compare");
    let text = ok(&[
        "compare",
        "--methods",
        "ga,rjmcmc",
        "--runs",
        "2",
        "--seconds",
        "0.6",
        "--out",
        out.to_str().unwrap(),
        "-q",
    ]);
    assert!(text.contains("ga") && text.contains("rjmcmc"), "{text}");
    for f in [
        "curves.csv",
        "runs.csv",
        "summary.json",
        "curves.png",
        "best_by_method.png",
        "ga/best.obj",
        "rjmcmc/best.json",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let summary = json(&out.join("summary.json"));
    for m in ["ga", "rjmcmc"] {
        let s = &summary["methods"][m];
        assert_eq!(s["runs"], 2);
        // The final mean is the mean of the runs' final best in runs.csv.
        let runs = std::fs::read_to_string(out.join("runs.csv")).unwrap();
        let mut last = [f64::NAN; 2];
        for line in runs
            .lines()
            .skip(1)
            .filter(|l| l.starts_with(&format!("{m},")))
        {
            let f: Vec<&str> = line.split(',').collect();
            last[f[1].parse::<usize>().unwrap()] = f[6].parse().unwrap_or(f64::NAN);
        }
        let mean = (last[0] + last[1]) / 2.0;
        assert!(
            (s["final_mean"].as_f64().unwrap() - mean).abs() < 1e-12,
            "{m}"
        );
        assert!(
            s["mean_at"]["100%"].as_f64().unwrap()
                >= s["mean_at"]["50%"].as_f64().unwrap_or(f64::MIN)
        );
    }
    // The method with the higher final mean reaches the other's: at the
    // seconds and evaluations it gives, the mean of its runs' best so far
    // (their last rows in runs.csv at or before that point) is at least
    // the other's final mean.
    let final_mean = |m: &str| summary["methods"][m]["final_mean"].as_f64().unwrap();
    let (lead, other) = if final_mean("ga") >= final_mean("rjmcmc") {
        ("ga", "rjmcmc")
    } else {
        ("rjmcmc", "ga")
    };
    let runs = std::fs::read_to_string(out.join("runs.csv")).unwrap();
    let rows: Vec<Vec<&str>> = (runs.lines().skip(1))
        .map(|l| l.split(',').collect::<Vec<_>>())
        .filter(|f| f[0] == lead)
        .collect();
    // runs.csv rounds seconds to microseconds.
    let mean_at = |column: usize, at: f64| {
        let mut best = [f64::NAN; 2];
        for f in rows
            .iter()
            .filter(|f| f[column].parse::<f64>().unwrap() <= at + 1e-6)
        {
            best[f[1].parse::<usize>().unwrap()] = f[6].parse().unwrap_or(f64::NAN);
        }
        (best[0] + best[1]) / 2.0
    };
    let s = &summary["methods"][lead];
    let seconds = s["seconds_to_reach"][other].as_f64().expect("reached");
    let evaluations = s["evaluations_to_reach"][other].as_f64().expect("reached");
    assert!(mean_at(4, seconds) >= final_mean(other), "{s}");
    assert!(mean_at(5, evaluations) >= final_mean(other), "{s}");
    std::fs::remove_dir_all(&out).ok();
}

#[test]
fn a_paper_experiment_runs_with_a_short_budget() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let data = root.join("../shared/data/paper");
    if !data.is_dir() {
        eprintln!("skipped: no paper data at {}", data.display());
        return;
    }
    let out = temp("paper");
    // As a user types it from the checkout: a relative path, the file's own data folder.
    let file = Path::new("experiments/paper/city_skyline_whale.toml");
    let run = Command::new(env!("CARGO_BIN_EXE_shapegen"))
        .current_dir(root)
        .args([
            "run",
            file.to_str().unwrap(),
            "--generations",
            "3",
            "-q",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    for f in ["overlay.png", "view.png", "best.png", "population.png"] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let summary = check_consistent(&out);
    assert_eq!(summary["experiment"], "city_skyline_whale");
    assert_eq!(summary["generator"], "space_filling_city");
    // A chromosome of another generator is refused by render.
    let builtin = temp("paper-builtin");
    ok(&[
        "run",
        "--generations",
        "1",
        "-q",
        "--out",
        builtin.to_str().unwrap(),
    ]);
    let err = failure(&[
        "render",
        builtin.join("best.json").to_str().unwrap(),
        "--experiment",
        root.join(file).to_str().unwrap(),
        "--data",
        data.to_str().unwrap(),
    ]);
    assert!(
        err.contains("not a chromosome of this experiment's generator"),
        "{err}"
    );
    std::fs::remove_dir_all(&out).ok();
    std::fs::remove_dir_all(&builtin).ok();
}

#[test]
fn bad_input_gets_a_clear_error() {
    let dir = temp("bad");
    let bad = dir.join("bad.toml");
    std::fs::write(
        &bad,
        "generator = \"spaceship\"\n[score]\nform = \"normalised\"\n",
    )
    .unwrap();
    let err = failure(&["run", bad.to_str().unwrap()]);
    assert!(err.contains("bad.toml:3:8: `score.form`"), "{err}");
    let err = failure(&["run", dir.join("missing.toml").to_str().unwrap()]);
    assert!(err.contains("cannot read the experiment"), "{err}");
    let err = failure(&["run", "--generations", "many"]);
    assert!(err.contains("invalid value"), "{err}");
    let err = failure(&["run", "--method", "annealing"]);
    assert!(err.contains("unknown method"), "{err}");
    let garbage = dir.join("garbage.json");
    std::fs::write(&garbage, "{\"words\": [1, 2").unwrap();
    let err = failure(&["render", garbage.to_str().unwrap()]);
    assert!(err.contains("not a chromosome file"), "{err}");
    let err = failure(&["run", "--resume", garbage.to_str().unwrap()]);
    assert!(err.contains("not a shapegen checkpoint"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

/// Ctrl-C (SIGINT) stops a run after the current generation and still
/// writes every result file, with a checkpoint to resume from.
#[cfg(unix)]
#[test]
fn ctrl_c_writes_the_results_so_far() {
    let dir = temp("sigint");
    let out = dir.join("out");
    let cp = dir.join("run.checkpoint");
    let child = Command::new(env!("CARGO_BIN_EXE_shapegen"))
        .args(["run", "--generations", "1000000", "-q", "--out"])
        .arg(&out)
        .arg("--checkpoint")
        .arg(&cp)
        .arg("--every")
        .arg("1000000")
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Let it get going, then interrupt it as a terminal would.
    std::thread::sleep(std::time::Duration::from_millis(1500));
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    // Stopped before the budget: status 130, the results written.
    assert_eq!(output.status.code(), Some(130), "{stderr}");
    assert!(stderr.contains("interrupted"), "{stderr}");
    let summary = check_consistent(&out);
    assert_eq!(summary["stop"], "observer");
    assert!(out.join("best.obj").is_file());
    // The checkpoint written on Ctrl-C resumes where the run stopped.
    let generations = summary["generations"].as_u64().unwrap();
    let resumed = dir.join("resumed");
    ok(&[
        "run",
        "--resume",
        cp.to_str().unwrap(),
        "--generations",
        &(generations + 2).to_string(),
        "-q",
        "--out",
        resumed.to_str().unwrap(),
    ]);
    assert_eq!(
        json(&resumed.join("summary.json"))["generations"],
        generations + 2
    );
    std::fs::remove_dir_all(&dir).ok();
}
