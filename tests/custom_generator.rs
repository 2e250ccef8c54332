//! A user's own generator through the whole command line, as a program
//! built with `shapegen::cli::Cli` runs it: the topiary of
//! `examples/custom_generator` through `run`, checkpoint and resume,
//! `compare` and `render`, with its own meshes in what is scored and written.

#[path = "../examples/custom_generator/topiary.rs"]
mod topiary;

use std::path::{Path, PathBuf};

use crate::util::json;
use shapegen::cli::Cli;
use shapegen::experiment::{Experiment, LoadOptions};
use shapegen::registry::Registry;
use topiary::Topiary;

fn experiment_file() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/custom_generator/topiary.toml")
}

fn cli() -> Cli {
    Cli::new().generator("topiary", Topiary)
}

fn run(args: &[&str]) {
    let mut all = vec!["shapegen"];
    all.extend_from_slice(args);
    if let Err(e) = cli().run_from(all) {
        panic!("shapegen {args:?} failed: {e}");
    }
}

fn temp(name: &str) -> PathBuf {
    crate::util::temp("custom", name)
}

/// Faces per object in an OBJ file, by object name prefix (`ball`, `pot`, ...).
fn faces_by_shape(obj: &Path) -> Vec<(String, usize)> {
    let mut out: Vec<(String, usize)> = Vec::new();
    for line in std::fs::read_to_string(obj).unwrap().lines() {
        if let Some(name) = line.strip_prefix("o ") {
            let shape = name.rsplit_once('_').map_or(name, |(s, _)| s);
            out.push((shape.to_string(), 0));
        } else if line.starts_with("f ") {
            out.last_mut().expect("faces after an object").1 += 1;
        }
    }
    out
}

#[test]
fn the_registry_names_the_users_generator_in_experiment_files() {
    let file = experiment_file();
    // Without the registration the file's generator is unknown, and the
    // error lists what is registered.
    let err = Experiment::load(&file, &LoadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("unknown generator `topiary`") && err.contains("tree_v2"),
        "{err}"
    );
    let registry = Registry::builtin().with("topiary", Topiary);
    let e = Experiment::load_with(&file, &registry, &LoadOptions::default()).unwrap();
    assert_eq!(e.generator(), "topiary");
    assert!(e.scene().contains("48×48×48"), "{}", e.scene());
    // Two targets: the crown and the pot.
    let c = shapegen::ops::random_individual(
        e.graph(),
        &shapegen::ops::InitLength::Around { l0: 12 },
        &mut shapegen::rng::stream(1, &[]),
    )
    .unwrap();
    let q = e.quality(&c);
    assert_eq!(q.len(), 2);
    assert!(q.iter().all(|q| (0.0..=1.0).contains(&q.iou)));
}

#[test]
fn run_resume_compare_and_render_work_for_the_users_generator() {
    let dir = temp("cli");
    let file = experiment_file();
    let file = file.to_str().unwrap();
    let (whole, part, resumed) = (dir.join("whole"), dir.join("part"), dir.join("resumed"));
    let cp = dir.join("run.checkpoint");
    let s = |p: &PathBuf| p.to_str().unwrap().to_string();
    run(&[
        "run",
        file,
        "--generations",
        "24",
        "--threads",
        "2",
        "-q",
        "--out",
        &s(&whole),
    ]);
    run(&[
        "run",
        file,
        "--generations",
        "12",
        "--threads",
        "1",
        "-q",
        "--out",
        &s(&part),
        "--checkpoint",
        &s(&cp),
        "--every",
        "12",
    ]);
    run(&[
        "run",
        file,
        "--resume",
        &s(&cp),
        "--generations",
        "24",
        "--threads",
        "1",
        "-q",
        "--out",
        &s(&resumed),
    ]);
    // Resumed on another thread count, the run ends bit-identically.
    assert_eq!(
        std::fs::read(whole.join("best.json")).unwrap(),
        std::fs::read(resumed.join("best.json")).unwrap()
    );
    let (a, b) = (
        json(&whole.join("summary.json")),
        json(&resumed.join("summary.json")),
    );
    assert_eq!(a["best_fitness"], b["best_fitness"]);
    assert_eq!(a["evaluations"], b["evaluations"]);
    assert_eq!(b["resumed"], true);
    assert_eq!(a["generator"], "topiary");
    // Quality per target, beside the fitness.
    let quality = a["quality"].as_array().unwrap();
    assert_eq!(quality.len(), 2);
    for q in quality {
        for k in ["iou", "precision", "recall"] {
            let v = q[k].as_f64().unwrap();
            assert!((0.0..=1.0).contains(&v), "{k} = {v}");
        }
    }
    assert!(quality[0]["iou"].as_f64().unwrap() > 0.2, "{a}");

    // best.obj holds the meshes the model was scored with: the example's
    // 168-triangle ball and 32-triangle pot (no built-in mesh exists for
    // either), and the built-in 8-sided frustum.
    let faces = faces_by_shape(&whole.join("best.obj"));
    assert!(faces.iter().any(|(s, _)| s == "ball"), "{faces:?}");
    for (shape, n) in &faces {
        let expected = match shape.as_str() {
            "ball" => 168,
            "pot" => 32,
            "cube" => 12,
            "frustum" => shapegen::score::Mesh::trunk().triangles.len(),
            other => panic!("unexpected shape {other}"),
        };
        assert_eq!(*n, expected, "{shape}");
    }
    // target.obj holds both targets as placed: the crown lifted to y ≈ 2.7–5.1.
    let target = std::fs::read_to_string(whole.join("target.obj")).unwrap();
    let ys: Vec<f32> = target
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| l.split(' ').nth(1).unwrap().parse().unwrap())
        .collect();
    let top = ys.iter().copied().fold(f32::MIN, f32::max);
    assert!((top - 5.1).abs() < 1e-3, "{top}");

    // render re-expresses the saved chromosome with the same meshes.
    let rendered = dir.join("render");
    run(&[
        "render",
        &s(&whole.join("best.json")),
        "--experiment",
        file,
        "--out",
        &s(&rendered),
    ]);
    assert_eq!(
        std::fs::read(whole.join("best.obj")).unwrap(),
        std::fs::read(rendered.join("best.obj")).unwrap()
    );

    // compare runs every method on it and reports IoU at 10/50/100 %.
    let compared = dir.join("compare");
    run(&[
        "compare",
        file,
        "--methods",
        "ga,rjmcmc",
        "--runs",
        "1",
        "--seconds",
        "0.4",
        "-q",
        "--out",
        &s(&compared),
    ]);
    let summary = json(&compared.join("summary.json"));
    for m in ["ga", "rjmcmc"] {
        let iou = &summary["methods"][m]["iou_at"];
        let last = iou["100%"].as_f64().unwrap();
        assert!((0.0..=1.0).contains(&last), "{m}: {iou}");
        assert!(compared.join(m).join("best.obj").is_file());
    }
    assert!(compared.join("curves.png").is_file());
    assert!(compared.join("best_by_method.png").is_file());
    // A gallery of the user's generator, with its own meshes (pot, ball).
    let gallery = dir.join("gallery");
    run(&[
        "gallery",
        &s(&experiment_file()),
        "--samples",
        "12",
        "--clusters",
        "4",
        "--thumbnail",
        "40",
        "-q",
        "--out",
        &s(&gallery),
    ]);
    let doc = json(&gallery.join("gallery.json"));
    assert_eq!(doc["models"].as_array().unwrap().len(), 13);
    // The centre's OBJ holds the user's pot mesh (the gallery renders what is scored).
    let shapes = faces_by_shape(&gallery.join("models/00.obj"));
    assert!(
        shapes.iter().any(|(name, _)| name.contains("pot")),
        "{shapes:?}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_users_cli_runs_its_own_default_experiment() {
    let dir = temp("default");
    let cli = cli().default_experiment(
        "topiary",
        include_str!("../examples/custom_generator/topiary.toml"),
        Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/custom_generator"),
    );
    let out = dir.join("out");
    cli.run_from([
        "shapegen",
        "run",
        "--generations",
        "3",
        "-q",
        "--out",
        out.to_str().unwrap(),
    ])
    .unwrap();
    assert_eq!(json(&out.join("summary.json"))["experiment"], "topiary");
    // A usage mistake is an error, not an exit.
    assert!(matches!(
        cli.run_from(["shapegen", "run", "--no-such-flag"]),
        Err(shapegen::cli::CliError::Args(_))
    ));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn write_model_writes_the_meshes_it_is_given() {
    use shapegen::express::{CountingSink, Generator};
    use shapegen::scenes::Spaceship;
    use shapegen::score::{Mesh, ShapeMeshes, write_model};
    // The spaceship with its cube replaced by a tetrahedron.
    let tetra = Mesh {
        positions: vec![
            [0.0, 0.0, 0.0].into(),
            [1.0, 0.0, 0.0].into(),
            [0.0, 1.0, 0.0].into(),
            [0.0, 0.0, 1.0].into(),
        ],
        triangles: vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
    };
    let mut shapes = ShapeMeshes::builtin(&Spaceship).unwrap();
    shapes.set("cube", tetra).unwrap();
    let c = shapegen::ops::random_individual(
        Spaceship.graph(),
        &shapegen::ops::InitLength::Around { l0: 20 },
        &mut shapegen::rng::stream(2, &[]),
    )
    .unwrap();
    let mut count = CountingSink::default();
    Spaceship.express(&c, &mut count);
    let dir = temp("write-model");
    let path = dir.join("model.obj");
    write_model(&path, &Spaceship, &c, &shapes).unwrap();
    let faces = faces_by_shape(&path);
    assert_eq!(faces.len() as u64, count.count);
    assert!(
        faces.iter().all(|(s, n)| s == "cube" && *n == 4),
        "{faces:?}"
    );
    // Meshes for another generator's shapes are refused.
    let topiary = ShapeMeshes::new(vec!["ball".into(); 4], vec![Mesh::unit_cube(); 4]).unwrap();
    assert!(write_model(&path, &Spaceship, &c, &topiary).is_err());
    // Written atomically: no temporary file is left beside it.
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, ["model.obj"]);
    std::fs::remove_dir_all(&dir).ok();
}

/// A user's generator with its own state type (`Twig`, blended through its
/// scope) transforms into a paper tree (a plain `Scope`) through the
/// command line; the endpoints are the two designs.
#[test]
fn transforms_into_a_paper_tree() {
    let dir = temp("transform");
    let file = dir.join("t.toml");
    std::fs::write(
        &file,
        "[first]\ngenerator = \"topiary\"\nseed = 4\n\n[second]\ngenerator = \"tree_v2\"\nseed = 9\n\n\
         [matches]\nadd = [[\"Stem\", \"T\"], [\"Branch\", \"b\"], [\"Branch\", \"n\"], [\"Branch\", \"m\"]]\n\n\
         [frames]\ncount = 5\nsize = 64\n",
    )
    .unwrap();
    let out = dir.join("out");
    run(&[
        "transform",
        file.to_str().unwrap(),
        "-q",
        "--out",
        out.to_str().unwrap(),
    ]);
    let facts = json(&out.join("sequence.json"));
    assert_eq!(facts["matches"], 5, "{facts}");
    assert!(out.join("sequence.gif").is_file());

    let registry = Registry::builtin().with("topiary", Topiary);
    let t = shapegen::transform::TransformFile::load(&file, &registry)
        .unwrap()
        .transformation;
    let count = |d: &shapegen::transform::Design| d.express().len();
    assert_eq!(t.at(0.0).len(), count(t.first()));
    assert_eq!(t.at(1.0).len(), count(t.second()));
    std::fs::remove_dir_all(&dir).ok();
}
