//! The `shapegen` binary against careless and hostile input: every case
//! ends within a bounded time with the exact outcome (an error that names
//! the key, line or file, or the right result), no input is modified and
//! no temporary file is left behind.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;

/// How long any case may take.
const LIMIT: Duration = Duration::from_secs(60);

/// A small, fast experiment: the built-in ship on a coarse grid.
const SMALL: &str = r#"name = "small"
generator = "spaceship"
seed = 1
method = "ga"
[budget]
generations = 3
[score]
form = "normalized"
good = 2.0
bad = 15.0
[volume]
min = [-5.0, -5.0, -2.0]
max = [5.0, 5.0, 18.0]
resolution = [20, 40, 20]
[[volume.targets]]
builtin = "ship"
[ga]
population = 20
elites = 4
init_length = 20
mutation_rate = 0.3
split = { grow = 13.5, cut = 13.5, alter = 3.0 }
"#;

/// One case's folder and the inputs written into it.
struct Case {
    dir: PathBuf,
    inputs: std::cell::RefCell<Vec<PathBuf>>,
    before: BTreeMap<PathBuf, Vec<u8>>,
}

/// What a run gave.
struct Outcome {
    code: Option<i32>,
    stdout: String,
    stderr: String,
}

impl Case {
    fn new(name: &str) -> Self {
        let dir =
            std::env::temp_dir().join(format!("shapegen-robust-{name}-{}", std::process::id()));
        std::fs::remove_dir_all(&dir).ok();
        std::fs::create_dir_all(&dir).unwrap();
        Self {
            dir,
            inputs: std::cell::RefCell::new(Vec::new()),
            before: BTreeMap::new(),
        }
    }

    /// Writes an input file of the case.
    fn file(&self, name: &str, bytes: impl AsRef<[u8]>) -> PathBuf {
        let path = self.dir.join(name);
        if let Some(p) = path.parent() {
            std::fs::create_dir_all(p).unwrap();
        }
        std::fs::write(&path, bytes).unwrap();
        self.inputs.borrow_mut().push(path.clone());
        path
    }

    /// Remembers the inputs' contents.
    fn snapshot(&mut self) {
        self.before = self
            .inputs
            .borrow()
            .iter()
            .filter_map(|p| std::fs::read(p).ok().map(|b| (p.clone(), b)))
            .collect();
    }

    /// Runs the binary in the case's folder.
    fn run(&mut self, args: &[&str]) -> Outcome {
        self.snapshot();
        run_in(&self.dir, args)
    }

    /// The run fails cleanly (exit 1 or 2, no panic) and its error says
    /// every one of `words`; inputs and folder are as the checks want.
    fn fails(&mut self, args: &[&str], words: &[&str]) -> String {
        let out = self.run(args);
        assert!(
            matches!(out.code, Some(1 | 2)),
            "shapegen {args:?} should fail with 1 or 2, got {:?}:\n{}",
            out.code,
            out.stderr
        );
        for w in words {
            assert!(
                out.stderr.contains(w),
                "shapegen {args:?}: `{w}` missing from:\n{}",
                out.stderr
            );
        }
        self.checks(args, &out);
        out.stderr
    }

    /// The run succeeds.
    fn succeeds(&mut self, args: &[&str]) -> Outcome {
        let out = self.run(args);
        assert_eq!(
            out.code,
            Some(0),
            "shapegen {args:?} failed:\n{}",
            out.stderr
        );
        self.checks(args, &out);
        out
    }

    /// No panic, inputs unchanged, no temporary file anywhere.
    fn checks(&self, args: &[&str], out: &Outcome) {
        assert!(
            !out.stderr.contains("panicked"),
            "shapegen {args:?} panicked:\n{}",
            out.stderr
        );
        let now = files(&self.dir);
        for (path, bytes) in &self.before {
            assert!(
                now.get(path) == Some(bytes),
                "shapegen {args:?} changed the input {}",
                path.display()
            );
        }
        for path in now.keys() {
            let name = path.file_name().unwrap().to_string_lossy();
            assert!(
                !name.ends_with(".tmp")
                    && !name.starts_with(".shapegen-probe")
                    && !name.starts_with(".shapegen-staging")
                    && name != ".shapegen.lock",
                "shapegen {args:?} left {}",
                path.display()
            );
        }
    }
}

impl Drop for Case {
    fn drop(&mut self) {
        std::fs::remove_dir_all(&self.dir).ok();
    }
}

/// Every regular file below `dir` with its contents.
fn files(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut out = BTreeMap::new();
    let Ok(entries) = std::fs::read_dir(dir) else {
        return out;
    };
    for e in entries.flatten() {
        let p = e.path();
        let Ok(t) = e.file_type() else { continue };
        if t.is_dir() {
            out.extend(files(&p));
        } else if t.is_file() {
            out.insert(p.clone(), std::fs::read(&p).unwrap_or_default());
        }
    }
    out
}

/// Runs the binary in `dir` and waits at most [`LIMIT`].
fn run_in(dir: &Path, args: &[&str]) -> Outcome {
    let mut child = Command::new(env!("CARGO_BIN_EXE_shapegen"))
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    let start = Instant::now();
    loop {
        if child.try_wait().unwrap().is_some() {
            break;
        }
        if start.elapsed() > LIMIT {
            child.kill().ok();
            panic!("shapegen {args:?} did not end within {LIMIT:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let out = child.wait_with_output().unwrap();
    Outcome {
        code: out.status.code(),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}

fn json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// A box `[lo, hi]` as OBJ text.
fn box_obj(lo: [f64; 3], hi: [f64; 3]) -> String {
    let mut text = String::new();
    for k in 0..8 {
        let c = |a: usize| if k >> a & 1 == 1 { hi[a] } else { lo[a] };
        text += &format!("v {} {} {}\n", c(0), c(1), c(2));
    }
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

/// [`SMALL`] with its target replaced by the mesh `mesh` (a path or name).
fn with_mesh(mesh: &str) -> String {
    SMALL.replace("builtin = \"ship\"", &format!("mesh = {mesh:?}"))
}

/// Ends with a `[[image.targets]]` scene of `png` (16 × 12) and `extra` keys.
fn image_experiment(png: &str, extra: &str) -> String {
    format!(
        "name = \"img\"\ngenerator = \"tree_v2\"\n[budget]\ngenerations = 2\n[score]\nform = \"normalized\"\n[image]\nwidth = 16\nheight = 12\n[[image.targets]]\npng = {png:?}\n{extra}\ncamera = {{ phi = -1.5708, theta = 0.0, r = 9.0, look_at = [0.0, 3.0, 0.0] }}\n[ga]\npopulation = 10\nelites = 2\ninit_length = 20\nmutation_rate = 0.3\nsplit = {{ grow = 1.0, cut = 1.0, alter = 1.0 }}\n"
    )
}

/// A 16 × 12 RGBA PNG from a pixel function.
fn png(case: &Case, name: &str, f: impl Fn(u32, u32) -> [u8; 4]) -> PathBuf {
    let path = case.dir.join(name);
    image::RgbaImage::from_fn(16, 12, |c, r| image::Rgba(f(c, r)))
        .save(&path)
        .unwrap();
    case.inputs.borrow_mut().push(path.clone());
    path
}

/// A PNG whose header claims `w × h` pixels, with no image data.
fn png_header(w: u32, h: u32) -> Vec<u8> {
    fn crc(bytes: &[u8]) -> u32 {
        let mut c = 0xffff_ffffu32;
        for &b in bytes {
            c ^= u32::from(b);
            for _ in 0..8 {
                c = if c & 1 == 1 {
                    0xedb8_8320 ^ (c >> 1)
                } else {
                    c >> 1
                };
            }
        }
        !c
    }
    let chunk = |kind: &[u8], data: &[u8]| {
        let mut out = (data.len() as u32).to_be_bytes().to_vec();
        let mut body = kind.to_vec();
        body.extend_from_slice(data);
        out.extend_from_slice(&body);
        out.extend_from_slice(&crc(&body).to_be_bytes());
        out
    };
    let mut ihdr = w.to_be_bytes().to_vec();
    ihdr.extend_from_slice(&h.to_be_bytes());
    ihdr.extend_from_slice(&[8, 6, 0, 0, 0]);
    let mut out = b"\x89PNG\r\n\x1a\n".to_vec();
    out.extend(chunk(b"IHDR", &ihdr));
    // A first data chunk (an empty zlib stream): decoders read the header up to it.
    out.extend(chunk(
        b"IDAT",
        &[0x78, 0x9c, 0x03, 0x00, 0x00, 0x00, 0x00, 0x01],
    ));
    out.extend(chunk(b"IEND", &[]));
    out
}

/// An experiment file, each key mistake reported with its key.
#[test]
fn experiment_files_with_values_that_would_be_ignored_or_misread() {
    let cases: &[(&str, &str, &[&str])] = &[
        (
            "min4",
            "[-5.0, -5.0, -2.0]",
            &["volume.min", "expected 3 numbers [x, y, z], got 4"],
        ),
        ("res4", "[20, 40, 20]", &["volume.resolution", "got 4"]),
    ];
    for (name, find, words) in cases {
        let mut case = Case::new(name);
        let replace = match *name {
            "min4" => "[-5.0, -5.0, -2.0, 1.0]",
            _ => "[20, 40, 20, 5]",
        };
        case.file("e.toml", SMALL.replacen(find, replace, 1));
        case.fails(&["run", "e.toml", "-q"], words);
    }
    let table: &[(&str, String, &[&str])] = &[
        (
            "fill-normalized",
            SMALL.replace("builtin = \"ship\"", "builtin = \"ship\"\nfill = 2.0"),
            &["volume.targets[0]", "fill", "paper form only"],
        ),
        (
            "good-paper",
            SMALL.replace("form = \"normalized\"", "form = \"paper\""),
            &["score", "does not use `good`, `bad`"],
        ),
        (
            "self-normalized",
            SMALL.replace("bad = 15.0", "bad = 15.0\nself = 1.0"),
            &["score", "does not use `self`"],
        ),
        (
            "optimum-nan",
            format!("optimum = nan\n{SMALL}"),
            &["optimum", "finite"],
        ),
        (
            "tournament",
            SMALL.replace("elites = 4", "elites = 4\ntournament = 50"),
            &["ga", "tournament (50) must not exceed the population (20)"],
        ),
        (
            "ga-init0",
            SMALL.replace("init_length = 20", "init_length = 0"),
            &["ga", "init_length must be at least 1"],
        ),
        (
            "rj-init0",
            format!("{SMALL}[rjmcmc]\nchains = 4\ninit_length = 0\n"),
            &["rjmcmc", "init_length"],
        ),
        (
            "zero-weights",
            SMALL.replace("good = 2.0\nbad = 15.0", "good = 0.0\nbad = 0.0"),
            &["score", "every weight is 0"],
        ),
        (
            "zero-paper",
            SMALL
                .replace(
                    "form = \"normalized\"\ngood = 2.0\nbad = 15.0",
                    "form = \"paper\"",
                )
                .replace("builtin = \"ship\"", "builtin = \"ship\"\nfill = 0.0"),
            &["volume.targets", "every target weight"],
        ),
        (
            "population",
            SMALL.replace("population = 20", "population = 100000000"),
            &["ga", "population must be at most 1000000"],
        ),
        (
            "grid-huge",
            SMALL.replace("[20, 40, 20]", "[2048, 2048, 512]"),
            &["volume", "at most 2^27"],
        ),
        (
            "seconds-huge",
            SMALL.replace("generations = 3", "seconds = 1e30"),
            &["budget", "a century"],
        ),
        (
            "generations-0",
            SMALL.replace("generations = 3", "generations = 0"),
            &["budget", "generations must be at least 1"],
        ),
        (
            "form-typo",
            SMALL.replace("\"normalized\"", "\"normalised\""),
            &["e.toml:8:8", "score.form", "unknown variant"],
        ),
        (
            "generator-typo",
            SMALL.replace("\"spaceship\"", "\"spaceshp\""),
            &["generator", "unknown generator `spaceshp`", "tree_v2"],
        ),
        (
            "unknown-key",
            SMALL.replace("seed = 1", "sed = 1"),
            &["unknown field `sed`"],
        ),
        (
            "bad-syntax",
            SMALL.replace("[score]", "[score"),
            &["e.toml:"],
        ),
        (
            "image-huge",
            image_experiment("x.png", "").replace("width = 16", "width = 100000"),
            &["camera", "at most 16384"],
        ),
    ];
    for (name, text, words) in table {
        let mut case = Case::new(name);
        case.file("e.toml", text);
        case.fails(&["run", "e.toml", "-q"], words);
    }
}

/// Target meshes that cover nothing or cannot be read as they are.
#[test]
fn target_meshes_that_cover_nothing_or_lose_faces() {
    let faces = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2\nf 1 3 4\n";
    let table: &[(&str, String, &[&str])] = &[
        (
            "outside",
            box_obj([100.0, 100.0, 100.0], [101.0, 101.0, 101.0]),
            &["volume.targets[0]", "outside the grid", "fit"],
        ),
        (
            "flat",
            "v 1 1 1\nv 1 1 1\nv 1 1 1\nf 1 2 3\n".to_string(),
            &["volume.targets[0]", "covers no cell"],
        ),
        (
            "two-corners",
            faces.to_string(),
            &["line 6", "a face with 2 vertices"],
        ),
        (
            "one-corner",
            faces.replace("f 1 2\n", "f 1\n"),
            &["line 6", "a face with 1 vertices"],
        ),
        (
            "nul",
            format!("{}\0garbage\nf 1 2 3\n", box_obj([0.0; 3], [1.0; 3])),
            &["NUL"],
        ),
        ("no-faces", "v 0 0 0\n".to_string(), &["no faces"]),
        (
            "nan-vertex",
            "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n".to_string(),
            &["not finite"],
        ),
        (
            "index-out",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n".to_string(),
            &["t.obj"],
        ),
    ];
    for (name, obj, words) in table {
        let mut case = Case::new(name);
        case.file("t.obj", obj);
        case.file("e.toml", with_mesh("t.obj"));
        case.fails(&["run", "e.toml", "-q"], words);
    }
    // Geometry far outside or huge costs no more than the grid it touches.
    let far: &[(&str, String, String)] = &[
        (
            "stray-vertex",
            format!(
                "{}v 1e20 0 0\nf 1 2 9\n",
                box_obj([-1.0, -1.0, 0.0], [1.0, 1.0, 4.0])
            ),
            with_mesh("t.obj"),
        ),
        (
            "huge-target",
            box_obj([-5000.0, -5000.0, -2000.0], [5000.0, 5000.0, 18000.0]),
            with_mesh("t.obj"),
        ),
        (
            "huge-shape",
            box_obj([-50.0, -50.0, -50.0], [50.0, 50.0, 50.0]),
            format!("{SMALL}[shapes.cube]\nmesh = \"t.obj\"\n"),
        ),
        (
            "tiny-grid",
            box_obj([-1.0, -1.0, 0.0], [1.0, 1.0, 4.0]),
            with_mesh("t.obj").replace(
                "max = [5.0, 5.0, 18.0]",
                "max = [-4.9999, -4.9999, -1.9999]",
            ),
        ),
    ];
    for (name, obj, experiment) in far {
        let mut case = Case::new(name);
        case.file("t.obj", obj);
        case.file("e.toml", experiment);
        let out = case.run(&["run", "e.toml", "--generations", "3", "-q", "--out", "out"]);
        assert!(
            matches!(out.code, Some(0 | 1)),
            "{name}: {:?} {}",
            out.code,
            out.stderr
        );
        case.checks(&[name], &out);
    }
    // Shapes 100 times the grid on a large grid (200×400×200): every
    // instance covers every cell, so one model takes a good part of a
    // second and generation 0 alone (20 models) would outlast a 1 s budget:
    // the run ends at the budget with the models evaluated by then.
    // The same for the chains' first states (RJMCMC, 100 chains by default)
    // and the tandem's (chains and GA).
    for method in ["ga", "rjmcmc", "tandem"] {
        let mut case = Case::new(&format!("huge-shape-slow-generation-{method}"));
        case.file("t.obj", box_obj([-50.0, -50.0, -50.0], [50.0, 50.0, 50.0]));
        case.file(
            "e.toml",
            format!("{SMALL}[shapes.cube]\nmesh = \"t.obj\"\n")
                .replace("[20, 40, 20]", "[200, 400, 200]"),
        );
        let out = case.succeeds(&[
            "run",
            "e.toml",
            "--method",
            method,
            "--seconds",
            "1",
            "--out",
            "out",
        ]);
        let summary = json(&case.dir.join("out/summary.json"));
        let evaluations = summary["evaluations"].as_u64().unwrap();
        assert!(
            (1..20).contains(&evaluations),
            "{method}: {evaluations} evaluations: {}",
            out.stderr
        );
        // A 1-s budget that must not run away; the bound is loose because
        // a busy two-core machine (a build beside the tests) stretched it
        // past 5 s twice while the run itself was fine.
        assert!(
            summary["seconds"].as_f64().unwrap() < 15.0,
            "{method}: {summary}"
        );
    }
    // A grid far from where the generator builds, around its target.
    let mut case = Case::new("far-grid");
    case.file(
        "t.obj",
        box_obj([100.0, 100.0, 100.0], [104.0, 104.0, 104.0]),
    );
    case.file(
        "e.toml",
        with_mesh("t.obj")
            .replace("min = [-5.0, -5.0, -2.0]", "min = [95.0, 95.0, 95.0]")
            .replace("max = [5.0, 5.0, 18.0]", "max = [110.0, 110.0, 110.0]"),
    );
    let out = case.succeeds(&["run", "e.toml", "--out", "out"]);
    assert!(
        out.stderr
            .contains("none of 16 random models of `spaceship` is seen"),
        "{}",
        out.stderr
    );
    // A grid of 1e-30 units inside the ship's hull: the parts outside it are
    // said at once, and the run ends (every model is 10^30 cells across).
    let mut case = Case::new("nano-grid");
    case.file(
        "e.toml",
        SMALL
            .replace("min = [-5.0, -5.0, -2.0]", "min = [0.0, 0.0, 0.0]")
            .replace("max = [5.0, 5.0, 18.0]", "max = [1e-30, 1e-30, 1e-30]"),
    );
    let out = case.succeeds(&["run", "e.toml", "-q", "--out", "out"]);
    assert!(
        out.stderr.contains("lies outside the grid"),
        "{}",
        out.stderr
    );

    // 1000× too large and far away: fitted into the grid it is fine.
    let mut case = Case::new("fit");
    case.file(
        "t.obj",
        box_obj([4000.0, -500.0, -500.0], [6000.0, 500.0, 500.0]),
    );
    case.file(
        "e.toml",
        with_mesh("t.obj").replace(
            "[[volume.targets]]\n",
            "[[volume.targets]]\nfit = \"grid\"\n",
        ),
    );
    let out = case.succeeds(&["run", "e.toml", "--out", "out"]);
    assert!(out.stderr.contains("target cells"), "{}", out.stderr);
    assert!(
        out.stdout.contains("best fitness") && out.stdout.contains("IoU"),
        "{}",
        out.stdout
    );
}

/// What is not a regular file is refused with the right words, at once.
#[cfg(unix)]
#[test]
fn directories_pipes_and_devices_are_refused() {
    let mut case = Case::new("special");
    std::fs::create_dir_all(case.dir.join("adir")).unwrap();
    let fifo = case.dir.join("fifo");
    assert!(
        Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap()
            .success()
    );
    case.fails(&["run", "adir", "-q"], &["adir is a directory"]);
    case.fails(&["run", "fifo", "-q"], &["not a regular file"]);
    case.fails(&["run", "/dev/zero", "-q"], &["not a regular file"]);
    case.fails(&["run", "missing.toml", "-q"], &["no such file"]);
    case.file("e.toml", with_mesh("adir"));
    case.fails(
        &["run", "e.toml", "-q"],
        &["volume.targets[0].mesh", "adir is a directory"],
    );
    case.file("e.toml", with_mesh("fifo"));
    case.fails(
        &["run", "e.toml", "-q"],
        &["volume.targets[0].mesh", "not a regular file"],
    );
    case.fails(&["render", "fifo"], &["not a regular file"]);
    case.fails(&["render", "adir"], &["is a directory"]);
    case.fails(&["run", "--resume", "fifo", "-q"], &["not a regular file"]);
    case.fails(&["run", "--resume", "adir", "-q"], &["is a directory"]);
}

/// Image targets: transparency, shading, sizes, decompression bombs.
#[test]
fn image_targets_are_never_silently_wrong() {
    let mut case = Case::new("images");
    // All white: no target pixel, an error naming the key and the masks.
    png(&case, "white.png", |_, _| [255; 4]);
    case.file("e.toml", image_experiment("white.png", ""));
    case.fails(
        &["run", "e.toml", "-q"],
        &["image.targets[0].png", "no pixel", "dark"],
    );
    // A transparent black background with black strokes: only the strokes.
    png(&case, "cut.png", |c, _| {
        if c < 4 { [0, 0, 0, 255] } else { [0, 0, 0, 0] }
    });
    case.file("e.toml", image_experiment("cut.png", ""));
    let out = case.succeeds(&["run", "e.toml", "--out", "out"]);
    assert!(
        out.stderr.contains("with 48 target pixels"),
        "{}",
        out.stderr
    );
    // A shaded render on white needs the dark mask.
    png(&case, "render.png", |c, r| {
        if (4..12).contains(&c) && r < 6 {
            [120, 120, 130, 255]
        } else {
            [255; 4]
        }
    });
    case.file("e.toml", image_experiment("render.png", ""));
    case.fails(&["run", "e.toml", "-q"], &["red0", "no pixel"]);
    case.file("e.toml", image_experiment("render.png", "mask = \"dark\""));
    let out = case.succeeds(&["run", "e.toml", "--out", "out"]);
    assert!(
        out.stderr.contains("with 48 target pixels"),
        "{}",
        out.stderr
    );
    // Every pixel target is as useless as none.
    case.file("e.toml", image_experiment("render.png", "mask = \"alpha\""));
    case.fails(&["run", "e.toml", "-q"], &["every pixel"]);
    // Another size: both sizes named.
    case.file(
        "e.toml",
        image_experiment("render.png", "mask = \"dark\"").replace("width = 16", "width = 32"),
    );
    case.fails(&["run", "e.toml", "-q"], &["16×12", "32×12"]);
    // A 15000 × 15000 image header: refused from the header, not decoded.
    case.file("bomb.png", png_header(15000, 15000));
    case.file("e.toml", image_experiment("bomb.png", ""));
    let start = Instant::now();
    case.fails(&["run", "e.toml", "-q"], &["15000×15000", "16×12"]);
    assert!(start.elapsed() < Duration::from_secs(10));
    // A truncated PNG of the right size.
    let mut bytes = std::fs::read(case.dir.join("render.png")).unwrap();
    bytes.truncate(bytes.len() / 2);
    case.file("half.png", bytes);
    case.file("e.toml", image_experiment("half.png", "mask = \"dark\""));
    case.fails(&["run", "e.toml", "-q"], &["half.png"]);
    // A camera looking away from where the trees grow: said before the run.
    case.file(
        "e.toml",
        image_experiment("render.png", "mask = \"dark\"").replace(
            "camera = { phi = -1.5708, theta = 0.0, r = 9.0, look_at = [0.0, 3.0, 0.0] }",
            "camera = { eye = [0.0, 3.0, 9.0], target = [0.0, 3.0, 20.0] }",
        ),
    );
    let out = case.succeeds(&["run", "e.toml", "--out", "out"]);
    assert!(
        out.stderr
            .contains("none of 16 random models of `tree_v2` is seen"),
        "{}",
        out.stderr
    );
    // Mask options.
    case.file(
        "e.toml",
        image_experiment("render.png", "mask = \"dark\"\nthreshold = 2.0"),
    );
    case.fails(
        &["run", "e.toml", "-q"],
        &["image.targets[0].threshold", "[0, 1]"],
    );
    case.file("e.toml", image_experiment("render.png", "mask = \"glow\""));
    case.fails(
        &["run", "e.toml", "-q"],
        &["image.targets[0].mask", "unknown variant"],
    );
}

/// Flags that would panic, hang or run the wrong amount.
#[test]
fn flags_out_of_range() {
    let mut case = Case::new("flags");
    case.file("e.toml", SMALL);
    let cases: &[(&[&str], &[&str])] = &[
        (
            &["run", "e.toml", "--seconds", "1e30"],
            &["--seconds", "a century"],
        ),
        (
            &["run", "e.toml", "--seconds=-1"],
            &["--seconds must be > 0"],
        ),
        (&["run", "e.toml", "--seconds", "NaN"], &["--seconds"]),
        (
            &["run", "e.toml", "--generations", "0"],
            &["--generations must be at least 1"],
        ),
        (&["run", "e.toml", "--generations=-3"], &["--generations"]),
        (
            &["run", "e.toml", "--threads", "0"],
            &["--threads must be at least 1"],
        ),
        (
            &["run", "e.toml", "--method", "annealing"],
            &["unknown method"],
        ),
        (
            &["compare", "e.toml", "--runs", "0"],
            &["at least one method and one run"],
        ),
        (&["compare", "e.toml", "--seconds", "1e30"], &["a century"]),
        (&["run", "e.toml", "--every", "5"], &["--checkpoint"]),
        (&["nonsense"], &["unrecognized subcommand"]),
    ];
    for (args, words) in cases {
        case.fails(args, words);
    }
}

/// Outputs never replace inputs, and an unwritable output is found before
/// the run, not after it.
#[test]
fn outputs_never_replace_inputs_and_are_checked_first() {
    let mut case = Case::new("outputs");
    // A target mesh named like an output, in the output folder.
    case.file(
        "out/target.obj",
        box_obj([-1.0, -1.0, 0.0], [1.0, 1.0, 4.0]),
    );
    case.file("e.toml", with_mesh("out/target.obj"));
    case.fails(
        &["run", "e.toml", "--out", "out", "-q"],
        &["over its input", "target.obj"],
    );
    // An image target named overlay.png there.
    png(&case, "out/overlay.png", |c, _| {
        if c < 4 { [0, 0, 0, 255] } else { [255; 4] }
    });
    case.file("i.toml", image_experiment("out/overlay.png", ""));
    case.fails(
        &["run", "i.toml", "--out", "out", "-q"],
        &["over its input", "overlay.png"],
    );
    // The checkpoint over the experiment file.
    case.file("e.toml", SMALL);
    case.fails(
        &[
            "run",
            "e.toml",
            "--checkpoint",
            "e.toml",
            "-q",
            "--out",
            "o2",
        ],
        &["over its input", "e.toml"],
    );
    // Where nothing can be written: found before the run.
    case.file("afile", "x");
    let start = Instant::now();
    case.fails(
        &["run", "e.toml", "--out", "afile", "-q"],
        &[
            "cannot write results to afile",
            "not a directory",
            "nothing was run",
        ],
    );
    case.fails(
        &["run", "e.toml", "--out", "afile/sub", "-q"],
        &["cannot write results", "nothing was run"],
    );
    case.fails(
        &[
            "run",
            "e.toml",
            "--checkpoint",
            "afile/cp.json",
            "-q",
            "--out",
            "o3",
        ],
        &["cannot write results", "afile"],
    );
    case.fails(
        &[
            "compare",
            "e.toml",
            "--out",
            "afile",
            "-q",
            "--seconds",
            "5",
        ],
        &["nothing was run"],
    );
    case.fails(
        &["render", "e.toml", "--out", "afile"],
        &["nothing was run"],
    );
    assert!(
        start.elapsed() < Duration::from_secs(20),
        "the checks ran the optimizer first"
    );
    // A checkpoint may replace the one resumed from.
    case.succeeds(&[
        "run",
        "e.toml",
        "--checkpoint",
        "cp.json",
        "--every",
        "1",
        "-q",
        "--out",
        "o4",
    ]);
    case.succeeds(&[
        "run",
        "e.toml",
        "--resume",
        "cp.json",
        "--checkpoint",
        "cp.json",
        "--generations",
        "5",
        "-q",
        "--out",
        "o4",
    ]);
}

/// Runs a checkpointed run in `case` and returns the checkpoint's JSON.
fn checkpointed(case: &mut Case) -> Value {
    case.file("e.toml", SMALL);
    case.succeeds(&[
        "run",
        "e.toml",
        "--checkpoint",
        "cp.json",
        "--every",
        "1",
        "-q",
        "--out",
        "out",
    ]);
    json(&case.dir.join("cp.json"))
}

/// Seals a changed checkpoint as shapegen does (FNV-1a of the JSON with an
/// empty `integrity`), so that the deeper checks are reached.
fn reseal(mut v: Value) -> String {
    v["integrity"] = Value::String(String::new());
    let text = serde_json::to_string(&v).unwrap();
    let hash = shapegen::optimize::fnv1a(shapegen::optimize::FNV1A_START, text.as_bytes());
    v["integrity"] = Value::String(format!("{hash:016x}"));
    serde_json::to_string_pretty(&v).unwrap()
}

/// A checkpoint resumes only the run it was written by.
#[test]
fn resuming_against_anything_else_is_refused() {
    let mut case = Case::new("resume");
    let cp = checkpointed(&mut case);
    let resume = |case: &mut Case, words: &[&str]| {
        case.fails(
            &[
                "run",
                "e.toml",
                "--resume",
                "cp.json",
                "--generations",
                "6",
                "-q",
                "--out",
                "r",
            ],
            words,
        );
    };
    // The experiment changed under it: the grid, the weights, the target.
    case.file("e.toml", SMALL.replace("[20, 40, 20]", "[20, 40, 21]"));
    resume(
        &mut case,
        &["experiment changed", "targets, grid and cameras"],
    );
    case.file("e.toml", SMALL.replace("bad = 15.0", "bad = 14.0"));
    resume(&mut case, &["experiment changed", "score and weights"]);
    case.file("t.obj", box_obj([-1.0, -1.0, 0.0], [1.0, 1.0, 4.0]));
    case.file("e.toml", with_mesh("t.obj"));
    resume(&mut case, &["experiment changed", "targets"]);
    case.file("e.toml", format!("{SMALL}\n[limits]\nmax_len = 90\n"));
    resume(&mut case, &["experiment changed", "generator and limits"]);
    // The target mesh's contents changed, same file name.
    case.file("e.toml", with_mesh("t.obj"));
    case.succeeds(&[
        "run",
        "e.toml",
        "--checkpoint",
        "cp2.json",
        "--every",
        "1",
        "-q",
        "--out",
        "o",
    ]);
    case.file("t.obj", box_obj([-1.0, -1.0, 0.0], [1.0, 1.0, 5.0]));
    case.fails(
        &["run", "e.toml", "--resume", "cp2.json", "-q", "--out", "o"],
        &["experiment changed", "targets"],
    );
    // Another experiment's checkpoint.
    case.file(
        "e.toml",
        SMALL.replace("name = \"small\"", "name = \"other\""),
    );
    resume(&mut case, &["belongs to experiment `small`, not `other`"]);
    case.file("e.toml", SMALL);
    // Edited by hand: the content hash tells.
    let mut forged = cp.clone();
    forged["checkpoint"]["best"]["fitness_bits"] = Value::from(10.0f64.to_bits());
    case.file("cp.json", serde_json::to_string_pretty(&forged).unwrap());
    resume(&mut case, &["changed or damaged"]);
    let mut forged = cp.clone();
    forged["checkpoint"]["generation"] = Value::from(1220);
    case.file("cp.json", serde_json::to_string_pretty(&forged).unwrap());
    resume(&mut case, &["changed or damaged"]);
    // Edited and resealed: the stored fitness is recomputed.
    let mut forged = cp.clone();
    forged["checkpoint"]["best"]["fitness_bits"] = Value::from(10.0f64.to_bits());
    case.file("cp.json", reseal(forged));
    resume(&mut case, &["has fitness 10", "refusing"]);
    let mut forged = cp.clone();
    forged["checkpoint"]["state"]["individuals"] = Value::Array(Vec::new());
    case.file("cp.json", reseal(forged));
    resume(&mut case, &["population is empty"]);
    let mut forged = cp.clone();
    forged["checkpoint"]["state"]["individuals"]
        .as_array_mut()
        .unwrap()
        .truncate(5);
    case.file("cp.json", reseal(forged));
    resume(&mut case, &["5 individuals for a population of 20"]);
    // Truncated, or not a checkpoint at all.
    let text = serde_json::to_string_pretty(&cp).unwrap();
    case.file("cp.json", &text[..text.len() / 2]);
    resume(&mut case, &["not a shapegen checkpoint"]);
    case.file("cp.json", "{\"words\": 1}");
    resume(&mut case, &["not a shapegen checkpoint"]);
    // The untouched checkpoint still resumes, bit-identically.
    case.file("cp.json", serde_json::to_string_pretty(&cp).unwrap());
    case.succeeds(&[
        "run",
        "e.toml",
        "--resume",
        "cp.json",
        "--generations",
        "6",
        "-q",
        "--out",
        "r",
    ]);
}

/// SMC with a budget too short for a complete model says so.
#[test]
fn a_budget_too_short_for_any_model_is_an_error() {
    let mut case = Case::new("smc");
    case.file("e.toml", format!("{SMALL}[limits]\nmin_len = 4\n"));
    case.fails(
        &[
            "run",
            "e.toml",
            "--method",
            "smc",
            "--generations",
            "1",
            "--out",
            "out",
            "-q",
        ],
        &["no complete model", "more generations"],
    );
    assert!(case.dir.join("out/summary.json").is_file());
    assert!(!case.dir.join("out/best.json").exists());
}

/// SIGTERM stops like Ctrl-C: results written, exit status 130.
#[cfg(unix)]
#[test]
fn sigterm_stops_cleanly_with_status_130() {
    let case = Case::new("sigterm");
    case.file("e.toml", SMALL);
    let child = Command::new(env!("CARGO_BIN_EXE_shapegen"))
        .args([
            "run",
            "e.toml",
            "--generations",
            "100000000",
            "-q",
            "--out",
            "out",
        ])
        .current_dir(&case.dir)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(1500));
    assert!(
        Command::new("kill")
            .args(["-TERM", &child.id().to_string()])
            .status()
            .unwrap()
            .success()
    );
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "{stderr}");
    assert!(stderr.contains("interrupted"), "{stderr}");
    let summary = json(&case.dir.join("out/summary.json"));
    assert_eq!(summary["stop"], "observer");
    assert!(case.dir.join("out/best.json").is_file());
}

/// A full disk while checkpointing: the last good checkpoint stays, the
/// failure is reported, and the results still land in a healthy --out.
/// Needs a small tmpfs (Linux, as root); says so and skips elsewhere.
#[cfg(target_os = "linux")]
#[test]
fn a_full_disk_while_checkpointing_keeps_the_results() {
    let mut case = Case::new("full");
    let small = case.dir.join("small");
    std::fs::create_dir_all(&small).unwrap();
    let mounted = Command::new("mount")
        .args(["-t", "tmpfs", "-o", "size=256k", "tmpfs"])
        .arg(&small)
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if !mounted {
        eprintln!("skipped: cannot mount a small tmpfs here (needs Linux and root)");
        return;
    }
    // Checkpoints grow with the curve they carry: the first ones fit.
    case.file("e.toml", SMALL);
    let out = case.run(&[
        "run",
        "e.toml",
        "--generations",
        "100000000",
        "--checkpoint",
        "small/cp.json",
        "--every",
        "1",
        "-q",
        "--out",
        "out",
    ]);
    let unmount = || Command::new("umount").arg(&small).status().ok();
    let left: Vec<_> = std::fs::read_dir(&small)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    let good = std::fs::read(small.join("cp.json"));
    unmount();
    assert_eq!(out.code, Some(1), "{}", out.stderr);
    assert!(
        out.stderr.contains("checkpoint could not be written"),
        "{}",
        out.stderr
    );
    assert!(
        case.dir.join("out/summary.json").is_file() && case.dir.join("out/best.json").is_file()
    );
    // No temporary file on the full disk; the last good checkpoint resumes.
    assert!(
        left.iter().all(|n| !n.to_string_lossy().ends_with(".tmp")),
        "{left:?}"
    );
    let good = good.expect("an early checkpoint fits");
    let stopped = json(&case.dir.join("out/summary.json"))["generations"]
        .as_u64()
        .unwrap();
    case.file("cp.json", &good);
    assert_eq!(
        json(&case.dir.join("cp.json"))["checkpoint"]["generation"].as_u64(),
        Some(stopped - 1)
    );
    case.succeeds(&[
        "run",
        "e.toml",
        "--resume",
        "cp.json",
        "--generations",
        &(stopped + 3).to_string(),
        "-q",
        "--out",
        "resumed",
    ]);
}

/// Ctrl-C in the middle of a long generation stops the run within about a
/// second (the generation in progress is dropped), writes the results and
/// a checkpoint of the last complete generation, which resumes.
#[cfg(unix)]
#[test]
fn ctrl_c_stops_a_slow_generation_within_a_second() {
    /// Kills the run if the test fails before it ends.
    struct Reaper(std::process::Child);
    impl Drop for Reaper {
        fn drop(&mut self) {
            self.0.kill().ok();
            self.0.wait().ok();
        }
    }
    use std::io::Read;
    let mut case = Case::new("slow");
    // The paper's 100 × 200 × 100 grid and 20,000 ships a generation: a
    // second or more each on this machine.
    case.file(
        "e.toml",
        SMALL
            .replace("[20, 40, 20]", "[100, 200, 100]")
            .replace("population = 20", "population = 20000")
            .replace("elites = 4", "elites = 100"),
    );
    let args = ["run", "e.toml", "--generations", "1000", "--out", "out"];
    let mut child = Reaper(
        Command::new(env!("CARGO_BIN_EXE_shapegen"))
            .args(args)
            .args(["--checkpoint", "cp.json", "--every", "1000"])
            .current_dir(&case.dir)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap(),
    );
    // Wait for a progress line after generation 0's, then interrupt.
    let mut stderr = child.0.stderr.take().unwrap();
    let mut seen = Vec::new();
    let started = Instant::now();
    let mut buf = [0u8; 256];
    while String::from_utf8_lossy(&seen).matches("eval/s").count() < 2 {
        let n = stderr.read(&mut buf).unwrap();
        let text = String::from_utf8_lossy(&seen);
        assert!(n > 0 && started.elapsed() < LIMIT, "{text}");
        seen.extend_from_slice(&buf[..n]);
    }
    std::thread::sleep(Duration::from_millis(300));
    let signalled = Instant::now();
    let pid = child.0.id().to_string();
    assert!(
        Command::new("kill")
            .args(["-INT", &pid])
            .status()
            .unwrap()
            .success()
    );
    let mut rest = String::new();
    stderr.read_to_string(&mut rest).unwrap();
    let status = child.0.wait().unwrap();
    let stopped_after = signalled.elapsed();
    assert_eq!(status.code(), Some(130), "{rest}");
    // The results take a moment to write; the run itself stops at once.
    assert!(
        stopped_after < Duration::from_secs(3),
        "{stopped_after:?}\n{rest}"
    );
    let summary = json(&case.dir.join("out/summary.json"));
    assert_eq!(summary["stop"], "observer", "{rest}");
    let generations = summary["generations"].as_u64().unwrap();
    let cp = json(&case.dir.join("cp.json"));
    assert_eq!(
        cp["checkpoint"]["generation"].as_u64(),
        Some(generations),
        "{rest}"
    );
    let more = (generations + 1).to_string();
    case.succeeds(&[
        "run",
        "e.toml",
        "--resume",
        "cp.json",
        "--generations",
        &more,
        "-q",
        "--out",
        "resumed",
    ]);
}

/// Runs the binary with its stdout (and, if `both`, stderr) a pipe nobody
/// reads: closed at once, as when `head` or a pager quits.
fn run_with_closed_streams(dir: &Path, args: &[&str], both: bool) -> Option<i32> {
    let mut child = Command::new(env!("CARGO_BIN_EXE_shapegen"))
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(if both { Stdio::piped() } else { Stdio::null() })
        .spawn()
        .expect("the binary runs");
    drop(child.stdout.take());
    drop(child.stderr.take());
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            return status.code();
        }
        assert!(start.elapsed() < LIMIT, "shapegen {args:?} did not end");
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// #54 finding 4: `shapegen run ... 2>&1 | head -1` and the same for
/// `compare` finish and write every result; a closed stream is no error.
#[test]
fn closed_output_streams_never_cost_the_results() {
    let case = Case::new("closed");
    case.file("e.toml", SMALL);
    for both in [true, false] {
        let out = format!("run-{both}");
        let code = run_with_closed_streams(
            &case.dir,
            &[
                "run",
                "e.toml",
                "--out",
                &out,
                "--checkpoint",
                &format!("{out}.cp"),
            ],
            both,
        );
        assert_eq!(code, Some(0), "run, stderr closed too: {both}");
        for f in ["best.json", "best.obj", "summary.json", "curve.csv"] {
            assert!(case.dir.join(&out).join(f).is_file(), "{out}/{f}");
        }
        assert!(case.dir.join(format!("{out}.cp")).is_file());
        let out = format!("compare-{both}");
        let code = run_with_closed_streams(
            &case.dir,
            &[
                "compare",
                "e.toml",
                "--seconds",
                "0.3",
                "--runs",
                "1",
                "--methods",
                "ga",
                "--out",
                &out,
            ],
            both,
        );
        assert_eq!(code, Some(0), "compare, stderr closed too: {both}");
        for f in ["summary.json", "runs.csv", "curves.csv"] {
            assert!(case.dir.join(&out).join(f).is_file(), "{out}/{f}");
        }
    }
}

/// #54 finding 6: one output folder, one run. A second run on a folder in
/// use is refused before it starts, naming the first; the first's files
/// are its own.
#[test]
fn a_second_run_on_a_folder_in_use_is_refused() {
    let mut case = Case::new("shared-out");
    case.file(
        "slow.toml",
        SMALL.replace("generations = 3", "generations = 100000"),
    );
    case.file("e.toml", SMALL.replace("seed = 1", "seed = 2"));
    let mut first = Command::new(env!("CARGO_BIN_EXE_shapegen"))
        .args(["run", "slow.toml", "--seconds", "3", "-q", "--out", "out"])
        .current_dir(&case.dir)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let lock = case.dir.join("out/.shapegen.lock");
    let start = Instant::now();
    while !std::fs::read_to_string(&lock).is_ok_and(|s| s.contains("slow.toml")) {
        assert!(
            start.elapsed() < LIMIT,
            "the first run never took the folder"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    for command in [
        &["run", "e.toml", "--out", "out"][..],
        &[
            "compare",
            "e.toml",
            "--seconds",
            "0.2",
            "--runs",
            "1",
            "--out",
            "out",
        ][..],
        &["gallery", "e.toml", "--out", "out"][..],
    ] {
        // Not `case.fails`: the first run's lock is meant to be there.
        let out = case.run(command);
        assert_eq!(out.code, Some(1), "{command:?}: {}", out.stderr);
        for says in [
            "another shapegen is writing to out",
            "slow.toml",
            "nothing was run",
        ] {
            assert!(out.stderr.contains(says), "{command:?}: {}", out.stderr);
        }
    }
    assert_eq!(first.wait().unwrap().code(), Some(0));
    let summary = json(&case.dir.join("out/summary.json"));
    assert_eq!(summary["seed"], 1);
    assert!(!lock.exists(), "the lock is gone with its run");
    // Free again: the next run takes it.
    case.succeeds(&["run", "e.toml", "-q", "--out", "out"]);
    assert_eq!(json(&case.dir.join("out/summary.json"))["seed"], 2);
}

/// #54 finding 8: a disk that fills while a run writes its results leaves
/// the previous run's set as it was, not a mix of old and new files.
#[test]
fn a_full_disk_while_writing_results_keeps_the_previous_set() {
    let mut case = Case::new("full-results");
    let small = case.dir.join("small");
    std::fs::create_dir_all(&small).unwrap();
    case.file("e.toml", SMALL);
    // One set of results, to size the disk: room for it and a half.
    case.succeeds(&["run", "e.toml", "-q", "--out", "sizing"]);
    let size: usize = files(&case.dir.join("sizing")).values().map(Vec::len).sum();
    let mounted = Command::new("mount")
        .args([
            "-t",
            "tmpfs",
            "-o",
            &format!("size={}", size * 3 / 2 + 16384),
            "tmpfs",
        ])
        .arg(&small)
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if !mounted {
        eprintln!("skipped: cannot mount a small tmpfs here (needs Linux and root)");
        return;
    }
    let unmount = || Command::new("umount").arg(&small).status().ok();
    let first = case.run(&["run", "e.toml", "-q", "--out", "small/out"]);
    let before = files(&small.join("out"));
    let second = case.run(&["run", "e.toml", "--seed", "9", "-q", "--out", "small/out"]);
    let after = files(&small.join("out"));
    let left: Vec<_> = std::fs::read_dir(small.join("out"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    unmount();
    assert_eq!(first.code, Some(0), "{}", first.stderr);
    assert_eq!(
        second.code,
        Some(1),
        "the second set does not fit: {}",
        second.stderr
    );
    assert!(second.stderr.contains("small/out"), "{}", second.stderr);
    assert_eq!(before, after, "the first run's set is as it was");
    assert!(
        left.iter()
            .all(|n| !n.starts_with(".shapegen") && !n.ends_with(".tmp")),
        "{left:?}"
    );
}

/// #54 finding 8: cameras that can never show the model are refused with
/// the key that sets them.
#[test]
fn degenerate_cameras_are_refused() {
    let mut case = Case::new("cameras");
    png(&case, "cut.png", |c, _| {
        if c < 4 { [0, 0, 0, 255] } else { [0, 0, 0, 0] }
    });
    let good = "camera = { phi = -1.5708, theta = 0.0, r = 9.0, look_at = [0.0, 3.0, 0.0] }";
    for (camera, says) in [
        ("r = 0.0", "r (its distance from look_at) is 0"),
        ("r = -9.0", "is -9"),
        ("r = 1e400", "r"),
        ("phi = nan", "camera"),
    ] {
        let (key, value) = camera.split_once(" = ").unwrap();
        let bad = good.replace(
            &format!("{key} = {}", if key == "r" { "9.0" } else { "-1.5708" }),
            &format!("{key} = {value}"),
        );
        case.file(
            "e.toml",
            image_experiment("cut.png", "").replace(good, &bad),
        );
        case.fails(&["run", "e.toml", "-q"], &[says]);
    }
    for camera in [
        "camera = { eye = [0.0, 3.0, 9.0], target = [0.0, 3.0, 9.0] }",
        "camera = { eye = [0.0, 3.0, 9.0], target = [0.0, 3.0, 0.0], up = [0.0, 0.0, 1.0] }",
    ] {
        case.file(
            "e.toml",
            image_experiment("cut.png", "").replace(good, camera),
        );
        case.fails(&["run", "e.toml", "-q"], &["eye ≠ target"]);
    }
}

/// #54 finding 9: the minor points. An OBJ saved with a byte-order mark
/// reads as without one; negative score weights pass with a warning; the
/// design server's Ctrl-C speaks of the server.
#[test]
fn the_minor_points_of_the_sweep() {
    let mut case = Case::new("minor");
    let mesh = box_obj([-2.0, -2.0, 0.0], [2.0, 2.0, 12.0]);
    case.file("plain.obj", &mesh);
    case.file("bom.obj", format!("\u{feff}{mesh}"));
    case.file("plain.toml", with_mesh("plain.obj"));
    case.file("bom.toml", with_mesh("bom.obj"));
    case.succeeds(&["run", "plain.toml", "-q", "--out", "plain"]);
    case.succeeds(&["run", "bom.toml", "-q", "--out", "bom"]);
    let fitness =
        |dir: &str| json(&case.dir.join(dir).join("summary.json"))["best_fitness"].clone();
    assert_eq!(fitness("plain"), fitness("bom"));
    case.file("neg.toml", SMALL.replace("bad = 15.0", "bad = -15.0"));
    let out = case.succeeds(&["run", "neg.toml", "--out", "neg"]);
    assert!(
        out.stderr.contains("bad = -15 is negative") && out.stderr.contains("use 15"),
        "{}",
        out.stderr
    );
    let out = case.succeeds(&["run", "plain.toml", "--out", "plain"]);
    assert!(!out.stderr.contains("negative"), "{}", out.stderr);
}

#[cfg(unix)]
#[test]
fn ctrl_c_stops_the_design_server_saying_so() {
    use std::io::{BufRead, BufReader, Read};
    let case = Case::new("serve-stop");
    let mut child = Command::new(env!("CARGO_BIN_EXE_shapegen"))
        .args(["design", "serve", "--port", "0"])
        .current_dir(&case.dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdout = BufReader::new(child.stdout.take().unwrap());
    let mut line = String::new();
    stdout.read_line(&mut line).unwrap();
    assert!(line.contains("open http://127.0.0.1:"), "{line}");
    let pid = child.id().to_string();
    assert!(
        Command::new("kill")
            .args(["-INT", &pid])
            .status()
            .unwrap()
            .success()
    );
    let start = Instant::now();
    let status = child.wait().unwrap();
    assert!(
        start.elapsed() < Duration::from_secs(2),
        "{:?}",
        start.elapsed()
    );
    let mut err = String::new();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut err)
        .unwrap();
    assert!(err.contains("stopping the server"), "{err}");
    assert!(!err.contains("generation"), "{err}");
    assert_eq!(status.code(), Some(0), "{err}");
}
