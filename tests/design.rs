//! Designing a pdf from the command line as a user does it: sample a batch,
//! fill in scores, learn, look at the current pdf, export, then use the
//! learned generator in a gallery and a run; and the errors a careless user meets.

use std::path::Path;
use std::process::Command;

use shapegen::design::session::{Mode, Session, SessionError};
use shapegen::design::tasks;
use shapegen::graph::Graph;
use shapegen::prelude::*;

use crate::util::{TempDir, json};

fn shapegen(dir: &Path, args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_shapegen"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("the binary runs")
}

fn ok(dir: &Path, args: &[&str]) -> String {
    let o = shapegen(dir, args);
    assert!(
        o.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn fails(dir: &Path, args: &[&str], says: &str) {
    let o = shapegen(dir, args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{args:?} should fail");
    assert!(err.contains(says), "{args:?}: expected `{says}` in: {err}");
    assert!(!err.contains("panicked"), "{err}");
}

/// Fills the batch's scores by the wing-pair task (scored from the session,
/// which holds the batch's models).
fn score_batch(dir: &Path, graph: &Graph) {
    let scores = dir.join("design/batch/scores.json");
    let mut file = json(&scores);
    let session = json(&dir.join("design/session.json"));
    let pending = session["pending"].as_array().unwrap();
    for entry in file["models"].as_array_mut().unwrap() {
        let id = entry["id"].as_u64().unwrap();
        let data = pending
            .iter()
            .find(|p| p["id"].as_u64() == Some(id))
            .unwrap();
        let data: ChromosomeData = serde_json::from_value(data["model"].clone()).unwrap();
        let m = Chromosome::from_data(graph, &data).unwrap();
        entry["score"] = tasks::wing_pairs(graph, &m).into();
    }
    std::fs::write(&scores, serde_json::to_string(&file).unwrap()).unwrap();
}

#[test]
fn a_design_session_from_the_command_line() {
    let dir = TempDir::new("design", "session");
    let experiment = shapegen::experiment::Experiment::builtin();
    let graph = experiment.graph().clone();
    fails(&dir, &["design", "learn"], "no session");
    fails(
        &dir,
        &["design", "sample", "--mode", "current"],
        "needs a learned preference",
    );
    ok(
        &dir,
        &["design", "sample", "--count", "24", "--thumbnail", "64"],
    );
    let batch = json(&dir.join("design/batch/scores.json"));
    let models = batch["models"].as_array().unwrap();
    assert_eq!(models.len(), 24);
    for m in models {
        assert!(m["score"].is_null() && m["predicted"].is_null());
        let png = dir
            .join("design/batch")
            .join(m["thumbnail"].as_str().unwrap());
        assert!(
            std::fs::metadata(&png).unwrap().len() > 200,
            "{}",
            png.display()
        );
    }
    let html = std::fs::read_to_string(dir.join("design/batch/index.html")).unwrap();
    assert_eq!(html.matches("<img").count(), 24);
    // Learning before any score is filled in is a clear error.
    fails(&dir, &["design", "learn"], "no scored models");
    score_batch(&dir, &graph);
    let out = ok(&dir, &["design", "learn"]);
    assert!(out.contains("24 scores added"), "{out}");
    assert!(
        out.contains("W"),
        "the wing features should be named: {out}"
    );
    // A second round from the current pdf: predictions appear, and most
    // models drawn have one or two wing pairs (the default pdf gives 43 %).
    ok(
        &dir,
        &[
            "design",
            "sample",
            "--mode",
            "current",
            "--count",
            "24",
            "--thumbnail",
            "64",
        ],
    );
    let batch = json(&dir.join("design/batch/scores.json"));
    assert!(
        batch["models"]
            .as_array()
            .unwrap()
            .iter()
            .all(|m| m["predicted"].is_f64())
    );
    let session = Session::load(&dir.join("design/session.json"), "spaceship", &graph).unwrap();
    let liked = session
        .pending
        .iter()
        .filter(|p| {
            tasks::wing_pairs(&graph, &Chromosome::from_data(&graph, &p.model).unwrap()) > 0.0
        })
        .count();
    assert!(
        liked >= 16,
        "only {liked} of 24 current-pdf models have one or two wing pairs"
    );
    score_batch(&dir, &graph);
    ok(&dir, &["design", "learn"]);
    // Out-of-range scores are refused and nothing is saved.
    let before = std::fs::read(dir.join("design/session.json")).unwrap();
    ok(
        &dir,
        &["design", "sample", "--count", "4", "--thumbnail", "32"],
    );
    let scores = dir.join("design/batch/scores.json");
    let mut file = json(&scores);
    file["models"][0]["score"] = 140.0.into();
    std::fs::write(&scores, serde_json::to_string(&file).unwrap()).unwrap();
    let mid = std::fs::read(dir.join("design/session.json")).unwrap();
    fails(&dir, &["design", "learn"], "outside 0..=100");
    assert_eq!(std::fs::read(dir.join("design/session.json")).unwrap(), mid);
    assert_ne!(before, mid, "the new batch was saved as pending");
    // Export, then use the learned generator.
    let out = ok(&dir, &["design", "export", "--training", "300"]);
    assert!(out.contains("structure learned generator"), "{out}");
    let learned = json(&dir.join("design/learned.json"));
    assert!(!learned["components"].as_array().unwrap().is_empty());
    ok(
        &dir,
        &[
            "gallery",
            "--prior",
            "design/learned.json",
            "--samples",
            "20",
            "--clusters",
            "4",
            "--thumbnail",
            "32",
            "-q",
            "--out",
            "g",
        ],
    );
    assert!(dir.join("g/gallery.png").exists());
    let doc = json(&dir.join("g/gallery.json"));
    assert_eq!(doc["models"].as_array().unwrap().len(), 21);
    ok(
        &dir,
        &[
            "run",
            "--prior",
            "design/learned.json",
            "--generations",
            "2",
            "-q",
            "--out",
            "r",
        ],
    );
    assert_eq!(
        json(&dir.join("r/summary.json"))["prior"],
        "design/learned.json"
    );
    let best = json(&dir.join("r/best.json"));
    let best: ChromosomeData = serde_json::from_value(best).unwrap();
    Chromosome::from_data(&graph, &best).expect("a prior run's model is the generator's");
    // A session file is not a learned generator.
    fails(
        &dir,
        &[
            "run",
            "--prior",
            "design/session.json",
            "--generations",
            "1",
            "-q",
            "--out",
            "r2",
        ],
        "not a learned generator",
    );
}

#[test]
fn sessions_refuse_bad_scores_unknown_models_and_other_generators() {
    let task = &tasks::scene_tasks()[0];
    let g = &task.graph;
    let mut s = Session::new("spaceship", g, 3);
    assert!(matches!(
        s.sample(g, Mode::Current, 4),
        Err(SessionError::NotLearned("current"))
    ));
    let shown = s.sample(g, Mode::Default, 6).unwrap();
    assert_eq!(s.pending.len(), 6);
    assert!(matches!(
        s.score(shown[0].id, -1.0),
        Err(SessionError::ScoreRange { .. })
    ));
    assert!(matches!(
        s.score(shown[0].id, f64::NAN),
        Err(SessionError::ScoreRange { .. })
    ));
    assert!(matches!(
        s.score(999, 50.0),
        Err(SessionError::UnknownModel(999))
    ));
    s.score(shown[0].id, 80.0).unwrap();
    s.score(shown[0].id, 60.0).unwrap(); // a correction
    assert_eq!(s.factors[0].scored.len(), 1);
    assert_eq!(s.factors[0].scored[0].score, 60.0);
    // A file round trip, and another generator's graph refused.
    let dir = TempDir::new("design", "roundtrip");
    let path = dir.join("s.json");
    s.save(&path).unwrap();
    let back = Session::load(&path, "spaceship", g).unwrap();
    assert_eq!(back.pending.len(), 5);
    let tree = &tasks::scene_tasks()[2].graph;
    assert!(matches!(
        Session::load(&path, "tree_v2", tree),
        Err(SessionError::ForeignGenerator { .. })
    ));
    // Scored mode shows the scored models with their scores, for corrections.
    let again = s.sample(g, Mode::Scored, 10).unwrap();
    assert_eq!(again.len(), 1);
    assert_eq!(again[0].score, Some(60.0));
}

#[test]
fn the_evaluation_command_writes_its_table_and_curves() {
    let dir = TempDir::new("design", "evaluate");
    let out = ok(
        &dir,
        &[
            "design",
            "evaluate",
            "--quick",
            "--tasks",
            "toy-colour",
            "-q",
            "--out",
            "e",
        ],
    );
    assert!(out.contains("| toy-colour |"), "{out}");
    let doc = json(&dir.join("e/evaluation.json"));
    let r = &doc[0];
    // Structure learning beats the default pdf on the toy's colour task.
    assert!(r["js_structure"].as_f64().unwrap() < r["js_default"].as_f64().unwrap());
    let png = image::open(dir.join("e/curves.png")).unwrap().to_rgb8();
    assert!(
        png.width() >= 640 && png.pixels().any(|p| p.0 == [214, 39, 40]),
        "the GPR curve is drawn"
    );
    fails(
        &dir,
        &["design", "evaluate", "--tasks", "nope"],
        "unknown task `nope`",
    );
}

/// A session with a learned preference, from the command line: its folder.
fn learned_session(name: &str) -> TempDir {
    let dir = TempDir::new("design", name);
    let graph = shapegen::experiment::Experiment::builtin().graph().clone();
    ok(
        &dir,
        &["design", "sample", "--count", "12", "--thumbnail", "32"],
    );
    score_batch(&dir, &graph);
    ok(&dir, &["design", "learn"]);
    dir
}

/// #54 finding 3: the server and the command line write one session file;
/// neither replaces a revision it did not read.
#[test]
fn the_server_and_the_command_line_share_a_session() {
    use shapegen::design::server::DesignServer;
    let dir = TempDir::new("design", "shared");
    let graph = shapegen::experiment::Experiment::builtin().graph().clone();
    let path = dir.join("design/session.json");
    ok(
        &dir,
        &["design", "sample", "--count", "8", "--thumbnail", "32"],
    );
    let server = DesignServer::new(shapegen::experiment::Experiment::builtin(), &path, 3).unwrap();
    let state = |s: &DesignServer| -> serde_json::Value {
        serde_json::from_slice(&s.respond("GET", "/api/state", &[]).body).unwrap()
    };
    let before = state(&server)["revision"].as_u64().unwrap();
    // The command line scores the batch while the server holds the session.
    score_batch(&dir, &graph);
    ok(&dir, &["design", "learn"]);
    // The page, still on the old revision, is told to reload; nothing of
    // the command line's is lost.
    let post = |s: &DesignServer, body: String| s.respond("POST", "/api/factor", body.as_bytes());
    let r = post(
        &server,
        format!(r#"{{"name": "colour", "revision": {before}}}"#),
    );
    assert_eq!(r.status, 409, "{}", String::from_utf8_lossy(&r.body));
    let now = state(&server);
    assert_eq!(
        now["scored"], 8,
        "the server shows the command line's scores"
    );
    assert!(now["revision"].as_u64().unwrap() > before);
    // After a reload, the page's change is applied on top of them.
    let rev = now["revision"].as_u64().unwrap();
    let r = post(
        &server,
        format!(r#"{{"name": "colour", "revision": {rev}}}"#),
    );
    assert_eq!(r.status, 200, "{}", String::from_utf8_lossy(&r.body));
    let saved = json(&path);
    assert_eq!(saved["factors"][0]["scored"].as_array().unwrap().len(), 8);
    assert_eq!(saved["factors"][1]["name"], "colour");
    // A copy read before the server's change is refused, not written.
    let mut stale = Session::load(&path, "spaceship", &graph).unwrap();
    let r = post(
        &server,
        format!(r#"{{"name": "size", "revision": {}}}"#, rev + 1),
    );
    assert_eq!(r.status, 200);
    stale.select_factor("other").unwrap();
    let e = stale.save(&path).unwrap_err();
    assert!(matches!(e, SessionError::Changed { .. }), "{e}");
    assert!(e.to_string().contains("changed by another program"), "{e}");
    assert_eq!(
        json(&path)["factors"][2]["name"],
        "size",
        "the server's change stands"
    );
    // So is a new session over one that appeared meanwhile.
    let mut fresh = Session::new("spaceship", &graph, 1);
    assert!(matches!(
        fresh.save(&path),
        Err(SessionError::Changed { .. })
    ));
}

/// #54 finding 7: hand-edited sessions are refused with what is wrong, by
/// every command, never with a panic; model ids never wrap.
#[test]
fn edited_sessions_are_refused_whole() {
    let dir = learned_session("edited");
    let path = dir.join("design/session.json");
    let good = std::fs::read(&path).unwrap();
    let edit = |what: &str, says: &str, f: &dyn Fn(&mut serde_json::Value)| {
        let mut v: serde_json::Value = serde_json::from_slice(&good).unwrap();
        f(&mut v);
        std::fs::write(&path, serde_json::to_vec(&v).unwrap()).unwrap();
        for args in [
            &["design", "sample", "--count", "2", "--thumbnail", "16"][..],
            &["design", "export", "--training", "20"][..],
        ] {
            let o = shapegen(&dir, args);
            let err = String::from_utf8_lossy(&o.stderr);
            assert!(!o.status.success(), "{what}: {args:?} accepted it");
            assert!(!err.contains("panicked"), "{what}: {err}");
            assert!(
                err.contains("not a shapegen design session"),
                "{what}: {err}"
            );
            assert!(err.contains(says), "{what}: expected `{says}` in {err}");
        }
    };
    let factor = "/learned/factors/0";
    edit("an empty scale", "keys and scales", &|v| {
        v.pointer_mut(&format!("{factor}/space/scale"))
            .unwrap()
            .as_array_mut()
            .unwrap()
            .clear();
    });
    edit("a zero scale", "not a positive number", &|v| {
        v.pointer_mut(&format!("{factor}/space/scale/0"))
            .map(|x| *x = 0.0.into())
            .unwrap();
    });
    edit("weights of another length", "disagree in number", &|v| {
        v.pointer_mut(&format!("{factor}/gp/theta"))
            .unwrap()
            .as_array_mut()
            .unwrap()
            .pop();
    });
    edit(
        "a training input of another length",
        "disagree in number",
        &|v| {
            v.pointer_mut(&format!("{factor}/gp/x/0"))
                .unwrap()
                .as_array_mut()
                .unwrap()
                .push(1.0.into());
        },
    );
    edit(
        "a feature of a node that does not exist",
        "names node 999",
        &|v| {
            v.pointer_mut(&format!("{factor}/space/keys/0"))
                .map(|k| *k = serde_json::json!({"count": {"node": 999}}))
                .unwrap();
        },
    );
    edit("a model listed twice", "twice", &|v| {
        let first = v["factors"][0]["scored"][0].clone();
        v["factors"][0]["scored"]
            .as_array_mut()
            .unwrap()
            .push(first);
    });
    edit("an id past the next id", "the next id is 3", &|v| {
        v["next_id"] = 3.into();
    });
    edit("a shown model it does not hold", "model 12345", &|v| {
        v["shown"] = serde_json::json!([12345]);
    });
    // Ids run out with an error, not by wrapping onto an older model.
    let mut v: serde_json::Value = serde_json::from_slice(&good).unwrap();
    v["next_id"] = (u64::MAX - 1).into();
    std::fs::write(&path, serde_json::to_vec(&v).unwrap()).unwrap();
    fails(
        &dir,
        &["design", "sample", "--count", "2", "--thumbnail", "16"],
        "every model id",
    );
    std::fs::write(&path, &good).unwrap();
    // Factor names the server refuses, and a scores file naming a model twice.
    fails(
        &dir,
        &["design", "sample", "--factor", " ", "--thumbnail", "16"],
        "a factor's name must be",
    );
    let long = "x".repeat(81);
    fails(
        &dir,
        &["design", "sample", "--factor", &long, "--thumbnail", "16"],
        "a factor's name must be",
    );
    ok(
        &dir,
        &["design", "sample", "--count", "4", "--thumbnail", "16"],
    );
    let scores = dir.join("design/batch/scores.json");
    let mut file = json(&scores);
    let models = file["models"].as_array_mut().unwrap();
    let twice = models[0].clone();
    models.push(twice);
    for m in models.iter_mut() {
        m["score"] = 50.0.into();
    }
    std::fs::write(&scores, serde_json::to_vec(&file).unwrap()).unwrap();
    let before = std::fs::read(&path).unwrap();
    fails(&dir, &["design", "learn"], "twice");
    assert_eq!(std::fs::read(&path).unwrap(), before, "nothing was saved");
}

/// Every JSON pointer in `v`, containers included.
fn pointers(v: &serde_json::Value, at: String, out: &mut Vec<String>) {
    match v {
        serde_json::Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                pointers(x, format!("{at}/{i}"), out);
            }
        }
        serde_json::Value::Object(o) => {
            for (k, x) in o {
                pointers(
                    x,
                    format!("{at}/{}", k.replace('~', "~0").replace('/', "~1")),
                    out,
                );
            }
        }
        _ => {}
    }
    out.push(at);
}

/// A learned session made through the library, as JSON.
fn learned_session_json(graph: &Graph) -> serde_json::Value {
    let mut s = Session::new("spaceship", graph, 5);
    let shown = s.sample(graph, Mode::Default, 10).unwrap();
    for (i, m) in shown.iter().enumerate() {
        s.score(m.id, (i * 11) as f64).unwrap();
    }
    s.select_factor("second").unwrap();
    s.sample(graph, Mode::Default, 3).unwrap();
    s.learn(graph, shapegen::design::FactorOptions::default())
        .unwrap();
    serde_json::to_value(&s).unwrap()
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(400))]

    /// The session loader over hand-edited files: up to four edits
    /// anywhere (a number, a string, null, an empty list or table, a
    /// removed entry); every file is refused with an error or loads into a
    /// session that predicts, samples, describes and scores without a panic.
    #[test]
    fn edited_session_files_load_or_are_refused(
        edits in proptest::collection::vec((proptest::prelude::any::<usize>(), 0u8..12), 1..5)
    ) {
        use std::sync::OnceLock;
        static BASE: OnceLock<(Graph, serde_json::Value)> = OnceLock::new();
        let (graph, base) = BASE.get_or_init(|| {
            let g = shapegen::experiment::Experiment::builtin().graph().clone();
            let v = learned_session_json(&g);
            (g, v)
        });
        let mut v = base.clone();
        for (at, kind) in edits {
            let mut all = Vec::new();
            pointers(&v, String::new(), &mut all);
            // Models' packed words are most of the leaves: three edits in
            // four go elsewhere.
            if at % 4 != 0 {
                all.retain(|p| !p.contains("/model/"));
            }
            let path = &all[at % all.len()];
            let replacement = match kind {
                0 => serde_json::json!(0),
                1 => serde_json::json!(-1),
                2 => serde_json::json!(1e300),
                3 => serde_json::json!(u64::MAX),
                4 => serde_json::json!("x"),
                5 => serde_json::Value::Null,
                6 => serde_json::json!([]),
                7 => serde_json::json!({}),
                8 => serde_json::json!(1),
                9 => serde_json::json!(0.5),
                _ => {
                    // Remove the entry from its container.
                    let (parent, key) = path.rsplit_once('/').unwrap_or(("", ""));
                    match v.pointer_mut(parent) {
                        Some(serde_json::Value::Array(a)) => {
                            if let Ok(i) = key.parse::<usize>() && i < a.len() { a.remove(i); }
                        }
                        Some(serde_json::Value::Object(o)) => { o.remove(&key.replace("~1", "/").replace("~0", "~")); }
                        _ => {}
                    }
                    continue;
                }
            };
            if let Some(x) = v.pointer_mut(path) {
                *x = replacement;
            }
        }
        let dir = TempDir::new("design", "fuzz");
        let path = dir.join("session.json");
        std::fs::write(&path, serde_json::to_vec(&v).unwrap()).unwrap();
        let loaded = Session::load(&path, "spaceship", graph);
        if let Ok(mut s) = loaded {
            let models = s.sample(graph, Mode::Default, 2);
            if let Some(p) = &s.learned {
                for f in &p.factors {
                    let _ = f.top_features(graph, 5);
                }
                if let Ok(m) = &models {
                    let _ = p.predict(graph, &m[0].model);
                    let _ = p.distance(graph, &m[0].model, &m[1].model);
                }
            }
            let _ = s.sample(graph, Mode::Scored, 4);
            if let Ok(m) = models {
                let _ = s.score(m[0].id, 50.0);
            }
            let _ = s.save(&path);
        }
    }
}
