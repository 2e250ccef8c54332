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
    assert_eq!(e.default_method(), Method::Ga);
    assert_eq!(e.optimum(), Some(2.0));
    assert_eq!(e.graph().limits().max_len, Some(100));
    assert!(e.budget(Method::Ga).is_some());
    assert!(e.scene().contains("100×200×100"), "{}", e.scene());
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
        ["ga", "smc", "sosmc", "rjmcmc"]
    );
}

#[test]
fn the_paper_experiments_load() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments/paper");
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data/paper");
    if !data.is_dir() {
        eprintln!("skipped: no paper data at {}", data.display());
        return;
    }
    let mut names = Vec::new();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let e =
            Experiment::load(&path, &LoadOptions::default()).unwrap_or_else(|err| panic!("{err}"));
        for m in Method::ALL {
            assert!(e.budget(m).is_some(), "{}: {m} has a budget", e.name());
        }
        assert!(e.optimum().is_some());
        names.push(e.name().to_string());
    }
    names.sort();
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
            "tree_sketch"
        ]
    );
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
