//! Loading experiment files: the built-in one, errors with key and line.

use super::*;

fn load(text: &str) -> Result<Experiment, ExperimentError> {
    Experiment::from_toml(
        text,
        "test.toml",
        Path::new("."),
        "t",
        &LoadOptions::default(),
    )
}

/// The error's (line, key, message).
fn invalid(text: &str) -> (usize, String, String) {
    match load(text).unwrap_err() {
        ExperimentError::Invalid {
            line, key, message, ..
        } => (line, key, message),
        other => panic!("expected an Invalid error, got {other}"),
    }
}

const MINIMAL: &str = r#"
generator = "spaceship"
[score]
form = "normalized"
[volume]
min = [-5.0, -5.0, -2.0]
max = [5.0, 5.0, 18.0]
resolution = [10, 20, 10]
[[volume.targets]]
builtin = "ship"
"#;

#[test]
fn the_builtin_experiment_loads() {
    let e = Experiment::builtin();
    assert_eq!(e.generator(), "spaceship");
    assert_eq!(e.default_method(), Method::DEFAULT);
    assert_eq!(Method::DEFAULT, Method::Tandem);
    assert_eq!(e.optimum(), Some(2.0));
    assert_eq!(e.graph().limits().max_len, Some(100));
    assert!(e.budget(Method::Ga).is_some());
    assert!(e.scene().contains("100×200×100"), "{}", e.scene());
}

#[test]
fn methods_that_regrow_subtrees_are_warned_of_a_missing_max_len() {
    // The spaceship declares no max_len of its own.
    let e = load(MINIMAL).unwrap();
    assert_eq!(e.graph().limits().max_len, None);
    // The method warnings come after the experiment's own.
    let own = e.warnings().len();
    let extra = |e: &Experiment, methods: &[Method]| {
        let w = e.warnings_for(methods);
        assert_eq!(w[..e.warnings().len()], *e.warnings());
        w[e.warnings().len()..].to_vec()
    };
    for m in [Method::Rjmcmc, Method::Hybrid, Method::Tandem] {
        let w = extra(&e, &[m]);
        assert!(w.len() == 1 && w[0].contains("max_len"), "{m}: {w:?}");
    }
    // Once for each distinct method, however often it is named.
    let w = extra(
        &e,
        &[Method::Rjmcmc, Method::Ga, Method::Rjmcmc, Method::Tandem],
    );
    assert_eq!(w.len(), 2, "{w:?}");
    assert!(w[0].contains("rjmcmc") && w[1].contains("tandem"), "{w:?}");
    // The paper's GA and SMC never regrow subtrees; a GA with local search does.
    for m in [Method::Ga, Method::Islands, Method::Smc, Method::Sosmc] {
        assert_eq!(e.warnings_for(&[m]).len(), own, "{m}");
    }
    let ga = "[ga]\npopulation = 20\nelites = 4\ninit_length = 20\nmutation_rate = 0.3\nsplit = { grow = 1.0, cut = 1.0, alter = 1.0 }\nlocal_search = 4\n";
    let local = load(&format!("{MINIMAL}{ga}")).unwrap();
    assert_eq!(extra(&local, &[Method::Ga]).len(), 1);
    // A max_len silences it.
    let limited = load(&format!("{MINIMAL}[limits]\nmax_len = 100\n")).unwrap();
    assert!(extra(&limited, &Method::ALL).is_empty());
}

#[test]
fn a_minimal_file_gets_defaults() {
    let e = load(MINIMAL).unwrap();
    assert_eq!(e.name(), "t");
    assert_eq!(e.seed(), 1);
    assert_eq!(e.budget(Method::Ga), None);
    assert!(matches!(e.method(Method::Sosmc).params, MethodParams::Smc(p) if p.particles == 500));
}

#[test]
fn errors_name_the_key_and_the_line() {
    // A wrong type.
    let (line, key, msg) = invalid(&format!("{MINIMAL}[ga]\npopulation = \"many\"\n"));
    assert_eq!((line, key.as_str()), (12, "ga.population"), "{msg}");
    // An unknown key.
    let (line, key, msg) = invalid(&MINIMAL.replace("builtin = \"ship\"", "biultin = \"ship\""));
    assert_eq!((line, key.as_str()), (10, "volume.targets[0].biultin"));
    assert!(msg.contains("unknown field"), "{msg}");
    // A missing key.
    let (_, key, msg) = invalid(&MINIMAL.replace("form = \"normalized\"\n", ""));
    assert_eq!(key, "score");
    assert!(msg.contains("form"), "{msg}");
    // Unknown generator, method, built-in target.
    let (line, key, _) = invalid(&MINIMAL.replace("spaceship", "spaceshp"));
    assert_eq!((line, key.as_str()), (2, "generator"));
    let (_, key, _) = invalid(&format!("method = \"gaa\"\n{MINIMAL}"));
    assert_eq!(key, "method");
    let (line, key, _) = invalid(&MINIMAL.replace("\"ship\"", "\"boat\""));
    assert_eq!((line, key.as_str()), (10, "volume.targets[0].builtin"));
    // A missing file.
    let (line, key, msg) =
        invalid(&MINIMAL.replace("builtin = \"ship\"", "mesh = \"nowhere.obj\""));
    assert_eq!((line, key.as_str()), (10, "volume.targets[0].mesh"));
    assert!(msg.contains("no such file"), "{msg}");
    // ${data} without a data directory.
    let (_, _, msg) = invalid(&MINIMAL.replace("builtin = \"ship\"", "mesh = \"${data}/x.obj\""));
    assert!(msg.contains("data directory"), "{msg}");
    // Parameters the GA refuses.
    let ga = "[ga]\npopulation = 10\nelites = 10\ninit_length = 5\nmutation_rate = 0.3\nsplit = { grow = 1, cut = 1, alter = 1 }\n";
    let (line, key, msg) = invalid(&format!("{MINIMAL}{ga}"));
    assert_eq!((line, key.as_str()), (11, "ga"));
    assert!(msg.contains("elites"), "{msg}");
    // Parameters RJMCMC and SMC refuse (their own checks, with the table's line).
    let (line, key, msg) = invalid(&format!("{MINIMAL}[rjmcmc]\nchains = 0\ninit_length = 5\n"));
    assert_eq!((line, key.as_str()), (11, "rjmcmc"));
    assert!(msg.contains("chains"), "{msg}");
    let (_, key, msg) = invalid(&format!("{MINIMAL}[sosmc]\nparticles = 0\n"));
    assert_eq!(key, "sosmc");
    assert!(msg.contains("particles"), "{msg}");
    // An empty budget, a bad grid, a syntax error.
    let (_, key, _) = invalid(&format!("{MINIMAL}[budget]\n"));
    assert_eq!(key, "budget");
    let (_, key, _) = invalid(&MINIMAL.replace("[10, 20, 10]", "[0, 20, 10]"));
    assert_eq!(key, "volume");
    let (line, key, _) = invalid(&MINIMAL.replace("[score]", "[score"));
    assert_eq!((line, key.as_str()), (3, ""));
    // An unknown inside rule.
    let (line, key, msg) =
        invalid(&MINIMAL.replace("builtin = \"ship\"", "builtin = \"ship\"\ninside = \"odd\""));
    assert_eq!((line, key.as_str()), (11, "volume.targets[0].inside"));
    assert!(msg.contains("parity") && msg.contains("winding"), "{msg}");
    // Both scenes.
    let image = "[image]\n[[image.targets]]\npng = \"x.png\"\ncamera = { phi = 0.0, theta = 0.0, r = 5.0, look_at = [0.0, 0.0, 0.0] }\n";
    let (_, key, _) = invalid(&format!("{MINIMAL}{image}"));
    assert_eq!(key, "image");
}

#[test]
fn the_error_message_shows_file_line_and_key() {
    let err = load(&format!("{MINIMAL}[ga]\npopulation = \"many\"\n")).unwrap_err();
    let text = err.to_string();
    assert!(
        text.starts_with("test.toml:12:14: `ga.population`: "),
        "{text}"
    );
}

#[test]
fn methods_parse_by_name() {
    assert_eq!("SOSMC".parse::<Method>().unwrap(), Method::Sosmc);
    assert!("annealing".parse::<Method>().is_err());
    assert_eq!(
        Method::ALL.map(Method::name),
        [
            "ga", "smc", "sosmc", "rjmcmc", "islands", "hybrid", "tandem"
        ]
    );
}

/// Every experiment in `experiments/<folder>`, loaded, each with a budget
/// for every method; `None` (the test skips) without the paper's data (or
/// for `user_targets`, the models').
fn load_folder(folder: &str) -> Option<Vec<Experiment>> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("experiments")
        .join(folder);
    let needs: &[&str] = match folder {
        "user_targets" => &["paper", "models"],
        _ => &["paper"],
    };
    for data in needs {
        let data = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../shared/data")
            .join(data);
        if !data.is_dir() {
            eprintln!("skipped: no data at {}", data.display());
            return None;
        }
    }
    let mut experiments = Vec::new();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let e =
            Experiment::load(&path, &LoadOptions::default()).unwrap_or_else(|err| panic!("{err}"));
        for m in Method::ALL {
            assert!(e.budget(m).is_some(), "{}: {m} has a budget", e.name());
        }
        experiments.push(e);
    }
    experiments.sort_by(|a, b| a.name().cmp(b.name()));
    Some(experiments)
}

/// The experiments on targets of `../shared/data/models` (a user's own
/// meshes and renders) load, with an optimum for the curves.
#[test]
fn the_user_target_experiments_load() {
    let Some(experiments) = load_folder("user_targets") else {
        return;
    };
    let names: Vec<&str> = experiments.iter().map(Experiment::name).collect();
    assert_eq!(
        names,
        [
            "city_skyline_teapot",
            "city_volume_cow",
            "spaceship_spot",
            "tree_sketch_bunny"
        ]
    );
    assert!(experiments.iter().all(|e| e.optimum().is_some()));
}

#[test]
fn the_paper_experiments_load() {
    let Some(experiments) = load_folder("paper") else {
        return;
    };
    for e in &experiments {
        assert!(e.optimum().is_some());
    }
    let names: Vec<&str> = experiments.iter().map(Experiment::name).collect();
    // A relative path resolves `${data}` once (the tests run in the package root).
    let relative = Experiment::load(
        Path::new("experiments/paper/spaceship_volume.toml"),
        &LoadOptions::default(),
    );
    assert!(relative.is_ok(), "{}", relative.unwrap_err());
    assert_eq!(
        names,
        [
            "city_skyline_shoe",
            "city_skyline_whale",
            "city_volume_castle",
            "spaceship_volume",
            "tree_avoid",
            "tree_eg_logo",
            "tree_sketch"
        ]
    );
}

#[test]
fn the_other_targets_load() {
    let Some(experiments) = load_folder("other_targets") else {
        return;
    };
    let names: Vec<&str> = experiments.iter().map(Experiment::name).collect();
    assert_eq!(names, ["tree_sketch_eg", "tree_sketch_mickey"]);
}

#[test]
fn a_target_with_holes_may_use_the_winding_number() {
    // A box [-3, 3] × [-3, 3] × [0, 10] without its +x side.
    let dir = std::env::temp_dir().join(format!("shapegen-inside-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let obj = dir.join("open_box.obj");
    let mut text = String::new();
    for z in [0.0, 10.0] {
        for (x, y) in [(-3.0, -3.0), (3.0, -3.0), (3.0, 3.0), (-3.0, 3.0)] {
            text += &format!("v {x} {y} {z}\n");
        }
    }
    // Bottom, top and three sides, facing out.
    for f in [
        [1, 3, 2],
        [1, 4, 3],
        [5, 6, 7],
        [5, 7, 8],
        [1, 2, 6],
        [1, 6, 5],
        [3, 4, 8],
        [3, 8, 7],
        [4, 1, 5],
        [4, 5, 8],
    ] {
        text += &format!("f {} {} {}\n", f[0], f[1], f[2]);
    }
    std::fs::write(&obj, text).unwrap();
    let file = MINIMAL.replace(
        "builtin = \"ship\"",
        &format!("mesh = {:?}", obj.display().to_string()),
    );
    // Parity: every row (along x) crosses the open box once, so it is
    // empty: an error that says why and what to use instead.
    let (line, key, msg) = invalid(&file);
    assert_eq!((line, key.as_str()), (9, "volume.targets[0]"));
    assert!(
        msg.contains("not watertight") && msg.contains("winding"),
        "{msg}"
    );
    let winding = load(&file.replace(
        "[[volume.targets]]\n",
        "[[volume.targets]]\ninside = \"winding\"\n",
    ))
    .unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    // Cells of 1 × 0.5 × 2 over [-5, 5]² × [-2, 18]: the box holds the
    // centres x ∈ {-2.5 .. 2.5} (6), y ∈ {-2.75 .. 2.75} (12), z ∈ {1 .. 9} (5).
    assert!(
        winding.scene().contains("with 360 target cells"),
        "{}",
        winding.scene()
    );
    assert!(
        winding
            .warnings()
            .iter()
            .all(|w| !w.contains("not watertight"))
    );
}

#[test]
fn cells_outside_the_grid_may_be_counted_by_instance_boxes() {
    // Trees (rotated frusta and leaves) in a grid they outgrow: counting
    // the instances' boxes instead of their cells outside the grid can only
    // add to the overlap term, so lower the normalized score.
    let trees = MINIMAL.replace("spaceship", "tree_v2");
    let solid = load(&trees).unwrap();
    let aabb = load(&trees.replace(
        "[[volume.targets]]",
        "outside_count = \"aabb\"\n[[volume.targets]]",
    ))
    .unwrap();
    let mut rng = crate::rng::stream(5, &[]);
    let mut lower = 0;
    for _ in 0..20 {
        let c = crate::ops::random_individual(
            solid.graph(),
            &crate::ops::InitLength::Around { l0: 60 },
            &mut rng,
        )
        .unwrap();
        let (s, a) = (solid.evaluate(&c), aabb.evaluate(&c));
        assert!(a <= s, "{a} > {s}");
        lower += usize::from(a < s);
    }
    assert!(lower > 0, "no tree left the grid");
    // An unknown rule names the key.
    let (_, key, _) = invalid(&trees.replace(
        "[[volume.targets]]",
        "outside_count = \"boxes\"\n[[volume.targets]]",
    ));
    assert_eq!(key, "volume.outside_count");
}

/// A box mesh `[lo, hi]` as OBJ text.
fn box_obj(lo: [f64; 3], hi: [f64; 3]) -> String {
    let mut text = String::new();
    for k in 0..8 {
        let c = |a: usize| if k >> a & 1 == 1 { hi[a] } else { lo[a] };
        text += &format!("v {} {} {}\n", c(0), c(1), c(2));
    }
    // Outward faces of the corners numbered by bits (x, y, z).
    for f in [
        [1, 3, 4, 2],
        [5, 6, 8, 7],
        [1, 2, 6, 5],
        [3, 7, 8, 4],
        [1, 5, 7, 3],
        [2, 4, 8, 6],
    ] {
        text += &format!(
            "f {} {} {}\nf {} {} {}\n",
            f[0], f[1], f[2], f[0], f[2], f[3]
        );
    }
    text
}

#[test]
fn targets_are_placed_by_scale_rotate_translate_and_fit() {
    let dir = std::env::temp_dir().join(format!("shapegen-place-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // A target in other units: 2000 × 1000 × 1000, far from the grid.
    let obj = dir.join("huge.obj");
    std::fs::write(
        &obj,
        box_obj([4000.0, -500.0, -500.0], [6000.0, 500.0, 500.0]),
    )
    .unwrap();
    let file = MINIMAL.replace(
        "builtin = \"ship\"",
        &format!("mesh = {:?}", obj.display().to_string()),
    );
    // As it is: an error that says it lies outside the grid and how to place it.
    let (_, key, msg) = invalid(&file);
    assert_eq!(key, "volume.targets[0]");
    assert!(
        msg.contains("outside the grid") && msg.contains("fit"),
        "{msg}"
    );
    // Fitted into the grid [-5, 5]² × [-2, 18] with its proportions: the
    // scale is 10 / 2000, so it becomes x ∈ [-5, 5], y ∈ [-2.5, 2.5],
    // z ∈ [5.5, 10.5]: 10 × 10 × 2 cell centres of 1 × 0.5 × 2.
    let fitted = load(&file.replace(
        "[[volume.targets]]\n",
        "[[volume.targets]]\nfit = \"grid\"\n",
    ))
    .unwrap();
    assert!(
        fitted.scene().contains("with 200 target cells"),
        "{}",
        fitted.scene()
    );
    // The same by hand: scale, then rotate (90° about z swaps x and y: 5 × 10 × 5), then translate.
    let by_hand = load(&file.replace(
        "[[volume.targets]]\n",
        "[[volume.targets]]\nscale = 0.005\nrotate = [0.0, 0.0, 90.0]\ntranslate = [0.3, -25.0, 8.0]\n",
    ))
    .unwrap();
    // x ∈ [-2.2, 2.8] (5 centres), y ∈ [-5, 5] (20), z ∈ [5.5, 10.5] (2).
    assert!(
        by_hand.scene().contains("with 200 target cells"),
        "{}",
        by_hand.scene()
    );
    // fit into a box, and mistakes.
    let boxed = load(&file.replace(
        "[[volume.targets]]\n",
        "[[volume.targets]]\nfit = { min = [-1.0, -1.0, 0.0], max = [1.0, 1.0, 6.0] }\n",
    ))
    .unwrap();
    // 2 × 1 × 1 → x ∈ [-1, 1] (2 centres), y ∈ [-0.5, 0.5] (2), z ∈ [2.5, 3.5] (1).
    assert!(
        boxed.scene().contains("with 4 target cells"),
        "{}",
        boxed.scene()
    );
    let with = |extra: &str| {
        file.replace(
            "[[volume.targets]]\n",
            &format!("[[volume.targets]]\n{extra}\n"),
        )
    };
    let (_, key, msg) = invalid(&with("fit = \"grid\"\nscale = 2.0"));
    assert_eq!(key, "volume.targets[0].fit");
    assert!(msg.contains("drop `scale`"), "{msg}");
    let (_, key, _) = invalid(&with("fit = \"room\""));
    assert_eq!(key, "volume.targets[0].fit");
    let (_, key, _) = invalid(&with("scale = -1.0"));
    assert_eq!(key, "volume.targets[0].scale");
    let (_, key, _) = invalid(&with(
        "fit = { min = [1.0, 1.0, 1.0], max = [0.0, 2.0, 2.0] }",
    ));
    assert_eq!(key, "volume.targets[0].fit");
    // target.obj shows the target as placed.
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    let c = crate::ops::random_individual(
        fitted.graph(),
        &crate::ops::InitLength::Around { l0: 6 },
        &mut crate::rng::stream(1, &[]),
    )
    .unwrap();
    fitted.write_model(&c, &out).unwrap();
    let target = std::fs::read_to_string(out.join("target.obj")).unwrap();
    let vertices: Vec<[f32; 3]> = target
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| {
            let v: Vec<f32> = l.split(' ').map(|x| x.parse().unwrap()).collect();
            [v[0], v[1], v[2]]
        })
        .collect();
    for (a, (lo, hi)) in [(-5.0, 5.0), (-2.5, 2.5), (5.5, 10.5)]
        .into_iter()
        .enumerate()
    {
        let min = vertices.iter().map(|v| v[a]).fold(f32::MAX, f32::min);
        let max = vertices.iter().map(|v| v[a]).fold(f32::MIN, f32::max);
        assert!(
            (min - lo).abs() < 1e-4 && (max - hi).abs() < 1e-4,
            "axis {a}: {min} {max}"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn image_targets_take_a_mask_and_either_camera() {
    let dir = std::env::temp_dir().join(format!("shapegen-mask-exp-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let png = dir.join("render.png");
    // A grey square on white, 16 × 12.
    image::RgbImage::from_fn(16, 12, |c, r| {
        image::Rgb(if (4..12).contains(&c) && (2..10).contains(&r) {
            [90, 90, 90]
        } else {
            [255; 3]
        })
    })
    .save(&png)
    .unwrap();
    let file = |target: &str| {
        format!(
            "generator = \"tree_v2\"\n[score]\nform = \"normalized\"\n[image]\nwidth = 16\nheight = 12\n[[image.targets]]\npng = {:?}\n{target}\n",
            png.display().to_string()
        )
    };
    let orbit = "camera = { phi = -1.5708, theta = 0.0, r = 9.0, look_at = [0.0, 3.0, 0.0] }";
    let look = "camera = { eye = [0.0, 3.0, 9.0], target = [0.0, 3.0, 0.0] }";
    // The paper's rule finds no red-0 pixel: an error naming the key and the fix.
    let (_, key, msg) = invalid(&file(orbit));
    assert_eq!(key, "image.targets[0].png");
    assert!(
        msg.contains("mask = \\\"dark\\\"") || msg.contains("mask = \"dark\""),
        "{msg}"
    );
    let dark = load(&file(&format!("mask = \"dark\"\n{orbit}"))).unwrap();
    assert!(
        dark.scene().contains("with 64 target pixels"),
        "{}",
        dark.scene()
    );
    let dark = load(&file(&format!("mask = \"dark\"\nthreshold = 0.4\n{look}"))).unwrap();
    assert!(
        dark.scene().contains("with 64 target pixels"),
        "{}",
        dark.scene()
    );
    // A threshold out of range, a threshold for red0, a camera mixing both kinds.
    let (_, key, _) = invalid(&file(&format!("mask = \"dark\"\nthreshold = 1.5\n{orbit}")));
    assert_eq!(key, "image.targets[0].threshold");
    let (_, key, _) = invalid(&file(&format!("threshold = 0.5\n{orbit}")));
    assert_eq!(key, "image.targets[0].threshold");
    let mixed = "camera = { eye = [0.0, 3.0, 9.0], target = [0.0, 3.0, 0.0], r = 2.0 }";
    let (_, key, msg) = invalid(&file(&format!("mask = \"dark\"\n{mixed}")));
    assert_eq!(key, "image.targets[0].camera");
    assert!(msg.contains("not both"), "{msg}");
    let (_, key, _) = invalid(&file("mask = \"dark\"\ncamera = { eye = [0.0, 3.0, 9.0] }"));
    assert_eq!(key, "image.targets[0].camera");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn every_ga_starts_challengers_unless_its_table_says_challenge_0() {
    use crate::optimize::DEFAULT_CHALLENGE;
    let challenges = |e: &Experiment| {
        let MethodParams::Ga(ga) = e.method(Method::Ga).params else {
            panic!("the GA");
        };
        let MethodParams::Islands(islands) = e.method(Method::Islands).params else {
            panic!("the island GA");
        };
        let MethodParams::Hybrid(hybrid) = e.method(Method::Hybrid).params else {
            panic!("the hybrid");
        };
        let MethodParams::Tandem(tandem) = e.method(Method::Tandem).params else {
            panic!("the tandem");
        };
        [
            ga.challenge,
            islands.ga.challenge,
            hybrid.ga.challenge,
            tandem.challenge,
        ]
    };
    let d = DEFAULT_CHALLENGE;
    assert_eq!(challenges(&load(MINIMAL).unwrap()), [d; 4]);
    let ga = "[ga]\npopulation = 120\nelites = 20\ninit_length = 30\nmutation_rate = 0.3\nsplit = { grow = 1.0, cut = 1.0, alter = 1.0 }\n";
    assert_eq!(
        challenges(&load(&format!("{MINIMAL}{ga}")).unwrap()),
        [d; 4]
    );
    // The paper's GA turns its own off; the islands and the hybrid keep theirs.
    let paper = load(&format!("{MINIMAL}{ga}challenge = 0\n")).unwrap();
    assert_eq!(challenges(&paper), [0, d, d, d]);
    let own = "[islands]\nchallenge = 7\n[hybrid]\nchallenge = 0\n[tandem]\nchallenge = 9\n";
    let e = load(&format!("{MINIMAL}{ga}challenge = 5\n{own}")).unwrap();
    assert_eq!(challenges(&e), [5, 7, 0, 9]);
    // Every paper experiment runs the paper's GA.
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments/paper");
    for entry in std::fs::read_dir(dir).unwrap() {
        let text = std::fs::read_to_string(entry.unwrap().path()).unwrap();
        let file: crate::experiment::file::ExperimentFile = toml::from_str(&text).unwrap();
        let ga = file.ga.expect("a [ga] table");
        assert_eq!(ga.get_ref().challenge, Some(0));
    }
}

#[test]
fn the_island_ga_splits_the_experiments_ga() {
    // Without a table: the GA's population in 4 islands, with the GA's budget.
    let ga = "[ga]\npopulation = 120\nelites = 20\ninit_length = 30\nmutation_rate = 0.3\nsplit = { grow = 1.0, cut = 1.0, alter = 1.0 }\nbudget = { generations = 7 }\n";
    let e = load(&format!("{MINIMAL}{ga}")).unwrap();
    let MethodParams::Islands(p) = e.method(Method::Islands).params else {
        panic!("islands run the island GA");
    };
    assert_eq!((p.islands, p.ga.population, p.ga.elites), (4, 30, 5));
    assert_eq!(e.budget(Method::Islands), e.budget(Method::Ga));
    // A table sets the islands and the migration, and may set its own budget.
    let table = "[islands]\nislands = 6\ninterval = 3\nmigrants = 1\ntopology = \"random\"\nbudget = { seconds = 2.0 }\n";
    let e = load(&format!("{MINIMAL}{ga}{table}")).unwrap();
    let MethodParams::Islands(p) = e.method(Method::Islands).params else {
        panic!("islands run the island GA");
    };
    assert_eq!(
        (p.islands, p.ga.population, p.interval, p.migrants),
        (6, 20, 3, 1)
    );
    assert_eq!(p.topology, crate::optimize::Topology::Random);
    assert_ne!(e.budget(Method::Islands), e.budget(Method::Ga));
    // Too many islands for the population, and a misspelled key, are errors.
    let (_, key, msg) = invalid(&format!("{MINIMAL}{ga}[islands]\nislands = 100\n"));
    assert_eq!(key, "islands");
    assert!(msg.contains("fewer than 2"), "{msg}");
    let (_, _, msg) = invalid(&format!("{MINIMAL}{ga}[islands]\nmigrant = 1\n"));
    assert!(msg.contains("migrant"), "{msg}");
}

#[test]
fn the_hybrid_runs_the_experiments_ga_then_its_rjmcmc() {
    let ga = "[ga]\npopulation = 120\nelites = 20\ninit_length = 30\nmutation_rate = 0.3\nsplit = { grow = 1.0, cut = 1.0, alter = 1.0 }\nbudget = { generations = 7 }\n[rjmcmc]\nchains = 9\ninit_length = 10\n";
    let e = load(&format!("{MINIMAL}{ga}")).unwrap();
    let MethodParams::Hybrid(p) = e.method(Method::Hybrid).params else {
        panic!("hybrid runs the hybrid");
    };
    assert_eq!(
        (
            p.ga.population,
            p.rjmcmc.chains,
            p.patience,
            p.patience_share
        ),
        (120, 9, 100, 0.5)
    );
    assert_eq!(e.budget(Method::Hybrid), e.budget(Method::Ga));
    let e = load(&format!("{MINIMAL}{ga}[hybrid]\npatience = 7\n")).unwrap();
    assert!(matches!(e.method(Method::Hybrid).params, MethodParams::Hybrid(p) if p.patience == 7));
    let (_, key, msg) = invalid(&format!("{MINIMAL}{ga}[hybrid]\npatience = 0\n"));
    assert_eq!(key, "hybrid");
    assert!(msg.contains("patience"), "{msg}");
    let e = load(&format!("{MINIMAL}{ga}[hybrid]\npatience_share = 0.0\n")).unwrap();
    assert!(
        matches!(e.method(Method::Hybrid).params, MethodParams::Hybrid(p) if p.patience_share == 0.0)
    );
    let (_, key, msg) = invalid(&format!("{MINIMAL}{ga}[hybrid]\npatience_share = 1.5\n"));
    assert_eq!(key, "hybrid");
    assert!(msg.contains("patience_share"), "{msg}");
}

#[test]
fn the_tandem_runs_the_experiments_ga_beside_its_rjmcmc() {
    let ga = "[ga]\npopulation = 120\nelites = 20\ninit_length = 30\nmutation_rate = 0.3\nsplit = { grow = 1.0, cut = 1.0, alter = 1.0 }\nbudget = { generations = 7 }\n[rjmcmc]\nchains = 9\ninit_length = 10\n";
    let e = load(&format!("{MINIMAL}{ga}")).unwrap();
    let MethodParams::Tandem(p) = e.method(Method::Tandem).params else {
        panic!("tandem runs the tandem");
    };
    // The recommended GA: local search and elite deduplication.
    assert_eq!(
        (
            p.ga.population,
            p.ga.local_search,
            p.ga.elite_dedup,
            p.rjmcmc.chains,
            p.interval,
            p.migrants
        ),
        (120, 30, true, 9, 10, 2)
    );
    // The paper's GA itself is unchanged.
    let MethodParams::Ga(g) = e.method(Method::Ga).params else {
        panic!("ga runs the GA");
    };
    assert_eq!((g.local_search, g.elite_dedup), (0, false));
    assert_eq!(e.budget(Method::Tandem), e.budget(Method::Ga));
    let e = load(&format!(
        "{MINIMAL}{ga}[tandem]\ninterval = 4\nmigrants = 3\nlocal_search = 0\nelite_dedup = false\n"
    ))
    .unwrap();
    assert!(matches!(
        e.method(Method::Tandem).params,
        MethodParams::Tandem(p) if (p.interval, p.migrants, p.ga.local_search, p.ga.elite_dedup) == (4, 3, 0, false)
    ));
    let (_, key, msg) = invalid(&format!("{MINIMAL}{ga}[tandem]\nmigrants = 10\n"));
    assert_eq!(key, "tandem");
    assert!(msg.contains("chains (9)"), "{msg}");
    let (_, key, msg) = invalid(&format!("{MINIMAL}{ga}[tandem]\nlocal_search = 101\n"));
    assert_eq!(key, "tandem");
    assert!(msg.contains("local_search (101)"), "{msg}");
}

#[test]
fn the_gas_local_search_is_read_and_checked() {
    let ga = |n: usize| {
        format!(
            "[ga]\npopulation = 50\nelites = 10\ninit_length = 30\nmutation_rate = 0.3\nsplit = {{ grow = 1.0, cut = 1.0, alter = 1.0 }}\nlocal_search = {n}\n"
        )
    };
    let e = load(&format!("{MINIMAL}{}", ga(12))).unwrap();
    assert!(matches!(e.method(Method::Ga).params, MethodParams::Ga(p) if p.local_search == 12));
    let (_, key, msg) = invalid(&format!("{MINIMAL}{}", ga(41)));
    assert_eq!(key, "ga");
    assert!(msg.contains("local_search (41)"), "{msg}");
}

#[test]
fn the_adaptive_split_is_read_for_the_ga_and_the_tandem() {
    let ga = |adaptive: &str| {
        format!(
            "[ga]\npopulation = 50\nelites = 10\ninit_length = 30\nmutation_rate = 0.3\nsplit = {{ grow = 1.0, cut = 1.0, alter = 1.0 }}\n{adaptive}"
        )
    };
    let e = load(&format!("{MINIMAL}{}", ga(""))).unwrap();
    assert!(matches!(e.method(Method::Ga).params, MethodParams::Ga(p) if !p.adaptive_split));
    assert!(
        matches!(e.method(Method::Tandem).params, MethodParams::Tandem(p) if !p.ga.adaptive_split)
    );
    let e = load(&format!("{MINIMAL}{}", ga("adaptive_split = true\n"))).unwrap();
    assert!(matches!(e.method(Method::Ga).params, MethodParams::Ga(p) if p.adaptive_split));
    // The tandem's own setting wins over the GA's.
    let e = load(&format!(
        "{MINIMAL}{}[tandem]\nadaptive_split = true\n",
        ga("")
    ))
    .unwrap();
    assert!(matches!(e.method(Method::Ga).params, MethodParams::Ga(p) if !p.adaptive_split));
    assert!(
        matches!(e.method(Method::Tandem).params, MethodParams::Tandem(p) if p.ga.adaptive_split)
    );
    let (_, key, msg) = invalid(&format!("{MINIMAL}{}", ga("adaptive_split = 1\n")));
    assert_eq!(key, "ga.adaptive_split", "{msg}");
    assert!(msg.contains("boolean"), "{msg}");
}

/// The tandem's parameters of the minimal experiment with `table` added.
fn tandem_of(table: &str) -> crate::optimize::TandemParams {
    let e = load(&format!("{MINIMAL}{table}")).unwrap();
    let MethodParams::Tandem(p) = e.method(Method::Tandem).params else {
        panic!("a tandem holds its parameters");
    };
    p
}

#[test]
fn the_tandem_balance_is_read() {
    let read = |table: &str| {
        let p = tandem_of(table);
        (p.balance, p.to_chains)
    };
    // The recommended tandem's: balanced, the GA's best kept from the chains.
    assert_eq!(read(""), (true, false));
    assert_eq!(
        read("[tandem]\nbalance = true\nto_chains = true\n"),
        (true, true)
    );
    assert_eq!(
        read("[tandem]\nbalance = false\nto_chains = false\n"),
        (false, false)
    );
    for key in ["balance", "to_chains"] {
        let (_, at, msg) = invalid(&format!("{MINIMAL}[tandem]\n{key} = \"yes\"\n"));
        assert_eq!(at, format!("tandem.{key}"), "{msg}");
    }
}

#[test]
fn the_tandem_challenge_is_read() {
    let read = |table: &str| tandem_of(table).challenge;
    assert_eq!(read(""), crate::optimize::TANDEM_CHALLENGE);
    assert_eq!(read("[tandem]\nchallenge = 0\n"), 0);
    assert_eq!(read("[tandem]\nchallenge = 250\n"), 250);
    let (_, at, msg) = invalid(&format!("{MINIMAL}[tandem]\nchallenge = -1\n"));
    assert_eq!(at, "tandem.challenge", "{msg}");
}

#[test]
fn a_first_phase_takes_the_smc_or_sosmc_settings() {
    let tables = "[ga]\npopulation = 120\nelites = 20\ninit_length = 30\nmutation_rate = 0.3\nsplit = { grow = 1.0, cut = 1.0, alter = 1.0 }\n[smc]\nparticles = 70\n[sosmc]\nparticles = 80\n";
    let first = |toml: &str| {
        let e = load(&format!("{MINIMAL}{tables}{toml}")).unwrap();
        let MethodParams::Hybrid(p) = e.method(Method::Hybrid).params else {
            panic!("hybrid runs the hybrid");
        };
        p.first_phase
    };
    assert_eq!(first(""), None);
    assert_eq!(first("[hybrid]\nfirst_phase = \"none\"\n"), None);
    let smc = first("[hybrid]\nfirst_phase = \"smc\"\n").unwrap();
    assert_eq!(
        (smc.particles, smc.order),
        (70, crate::optimize::SlotOrder::Program)
    );
    let sosmc = first("[hybrid]\nfirst_phase = \"sosmc\"\n").unwrap();
    assert_eq!(
        (sosmc.particles, sosmc.order),
        (80, crate::optimize::SlotOrder::Random)
    );
    // The tandem's, from the same tables.
    let e = load(&format!(
        "{MINIMAL}{tables}[tandem]\nfirst_phase = \"sosmc\"\n"
    ))
    .unwrap();
    assert!(matches!(
        e.method(Method::Tandem).params,
        MethodParams::Tandem(p) if p.first_phase.is_some_and(|f| f.particles == 80)
    ));
    let (_, key, msg) = invalid(&format!(
        "{MINIMAL}{tables}[hybrid]\nfirst_phase = \"ga\"\n"
    ));
    assert_eq!(key, "hybrid.first_phase", "{msg}");
    assert!(msg.contains("sosmc"), "{msg}");
}
