//! The `shapegen` command line.
//!
//! With no arguments it evolves the paper's spaceship generator toward a
//! built-in ship-shaped target volume and writes the results to `out/`.

use std::error::Error;
use std::fs;
use std::io::Write;
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};

use clap::Parser;
use serde::Serialize;
use shapegen::demo::spaceship_target;
use shapegen::express::{Instance, ShapeId};
use shapegen::glam::{Affine3A, UVec3, Vec3};
use shapegen::prelude::*;
use shapegen::scenes::Spaceship;
use shapegen::score::Grid;
use shapegen::score::obj::{ShapeMeshes, write_model, write_obj};
use shapegen::score::score::{VolumeFitness, VolumeScore};
use shapegen::score::volume::VolumeScene;
use shapegen::score::volume::VolumeTarget;

/// Evolves procedural models toward a target with a genetic algorithm.
#[derive(Debug, Parser)]
#[command(version, about)]
struct Args {
    /// Random seed (the same seed gives the same result on any number of threads).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Generations to run.
    #[arg(long, default_value_t = 400)]
    generations: u64,
    /// Optimization method: the paper's GA or one of its baselines.
    #[arg(long, value_enum, default_value_t = Method::Ga)]
    method: Method,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Directory for the results.
    #[arg(long, default_value = "out")]
    out: PathBuf,
}

/// The optimization methods of the paper (§6–7), with its spaceship settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum Method {
    /// Genetic algorithm (P 150, E 30, 30 % mutation).
    Ga,
    /// Sequential Monte Carlo (500 particles).
    Smc,
    /// Stochastically-ordered SMC (500 particles).
    Sosmc,
    /// Reversible-jump MCMC with parallel tempering and annealing (70 chains).
    Rjmcmc,
}

impl Method {
    fn name(self) -> &'static str {
        match self {
            Self::Ga => "ga",
            Self::Smc => "smc",
            Self::Sosmc => "sosmc",
            Self::Rjmcmc => "rjmcmc",
        }
    }
}

/// What `summary.json` holds.
#[derive(Serialize)]
struct Summary<'a> {
    generator: &'a str,
    target: &'a str,
    method: &'a str,
    seed: u64,
    optimum: f64,
    best_fitness: f64,
    best_genes: usize,
    target_cells: u64,
    covered_target_cells: u64,
    covered_other_cells: u64,
    evaluations: u64,
    generations: u64,
    seconds: f64,
    stop: StopReason,
}

fn main() {
    if let Err(e) = run(Args::parse()) {
        eprintln!("shapegen: error: {e}");
        let mut source = e.source();
        while let Some(s) = source {
            eprintln!("  caused by: {s}");
            source = s.source();
        }
        std::process::exit(1);
    }
}

fn run(args: Args) -> Result<(), Box<dyn Error>> {
    if let Some(threads) = args.threads {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build_global()?;
    }
    // The paper's spaceship scene setup (normalized score 2 / 15 / 0.1,
    // lengths 4 <= L < 100), on the paper's 100×200×100 grid.
    let limits = Limits {
        max_depth: Some(15),
        min_len: 4,
        max_len: Some(100),
    };
    let graph = Graph::new(Spaceship::spec().clone().with_limits(limits))?;
    let grid = Grid::new(
        Vec3::new(-5.0, -5.0, -2.0),
        Vec3::new(5.0, 5.0, 18.0),
        UVec3::new(100, 200, 100),
    )?;
    let targets = spaceship_target();
    let scene = VolumeScene::new(grid, &targets)?;
    let score = VolumeScore::Normalized {
        w_good: 2.0,
        w_bad: 15.0,
        w_length: 0.1,
        separate_overlap: None,
    };
    let fitness = VolumeFitness::new(Spaceship, scene, &ShapeMeshes::builtin(&Spaceship)?, score)?
        .with_limits(limits);
    println!(
        "shapegen: {} on spaceships (paper Fig. 4a) toward a built-in ship-shaped volume of {} cells; optimum 2.0, seed {}",
        args.method.name(),
        fitness.scene().target_cells(),
        args.seed
    );
    let mut curve = String::from("generation,seconds,evaluations,best,mean,std\n");
    let mut observer = |s: &GenerationStats<'_>| {
        curve.push_str(&format!(
            "{},{:.6},{},{},{},{}\n",
            s.generation,
            s.elapsed.as_secs_f64(),
            s.evaluations,
            s.best,
            s.mean,
            s.std
        ));
        if s.generation.is_multiple_of(25) {
            println!(
                "  generation {:>4}  evaluations {:>7}  best {:>8.4}  mean {:>8.4}  ({:.1} s)",
                s.generation,
                s.evaluations,
                s.best,
                s.mean,
                s.elapsed.as_secs_f64()
            );
        }
        ControlFlow::Continue(())
    };
    let budget = Budget::generations(args.generations);
    let init = InitLength::Around { l0: 50 };
    let result = match args.method {
        Method::Ga => Ga::new(GaParams::paper_spaceship()).run(
            &graph,
            &fitness,
            &budget,
            args.seed,
            &mut observer,
        )?,
        Method::Smc => Smc::new(SmcParams::paper(500)).run(
            &graph,
            &fitness,
            &budget,
            args.seed,
            &mut observer,
        )?,
        Method::Sosmc => Smc::new(SmcParams::paper_sosmc(500)).run(
            &graph,
            &fitness,
            &budget,
            args.seed,
            &mut observer,
        )?,
        Method::Rjmcmc => Rjmcmc::new(RjmcmcParams::paper(70, init)).run(
            &graph,
            &fitness,
            &budget,
            args.seed,
            &mut observer,
        )?,
    };
    let counts = fitness.counts(&result.best, &mut fitness.scratch());
    println!(
        "done: best fitness {:.4} ({} genes; {} of {} target cells covered, {} outside) after {} generations, {} evaluations, {:.1} s",
        result.best_fitness,
        result.best.len(),
        counts.good,
        fitness.scene().target_cells(),
        counts.bad + counts.outside,
        result.generations,
        result.evaluations,
        result.elapsed.as_secs_f64()
    );
    fs::create_dir_all(&args.out)
        .map_err(|e| format!("cannot create output directory {}: {e}", args.out.display()))?;
    write_model(&args.out.join("best.obj"), &Spaceship, &result.best)?;
    write_target(&args.out.join("target.obj"), &targets)?;
    let summary = Summary {
        generator: graph.name(),
        target: "built-in ship-shaped volume (shapegen::demo::spaceship_target)",
        method: args.method.name(),
        seed: args.seed,
        optimum: 2.0,
        best_fitness: result.best_fitness,
        best_genes: result.best.len(),
        target_cells: fitness.scene().target_cells(),
        covered_target_cells: counts.good,
        covered_other_cells: counts.bad + counts.outside,
        evaluations: result.evaluations,
        generations: result.generations,
        seconds: result.elapsed.as_secs_f64(),
        stop: result.stop,
    };
    let files = [
        ("curve.csv", curve),
        (
            "best.json",
            serde_json::to_string_pretty(&result.best.to_data(&graph))?,
        ),
        ("summary.json", serde_json::to_string_pretty(&summary)?),
    ];
    for (name, text) in files {
        write_atomically(&args.out.join(name), &text)?;
    }
    println!(
        "wrote {0}/best.obj, {0}/target.obj, {0}/best.json, {0}/curve.csv, {0}/summary.json",
        args.out.display()
    );
    Ok(())
}

/// The target meshes as one OBJ (one object each), to open beside `best.obj`.
fn write_target(path: &Path, targets: &[VolumeTarget]) -> Result<(), Box<dyn Error>> {
    let names = targets
        .iter()
        .map(|t| t.name.replace(' ', "_").into())
        .collect();
    let shapes = ShapeMeshes::new(names, targets.iter().map(|t| t.mesh.clone()).collect())?;
    let instances: Vec<Instance> = (0..targets.len())
        .map(|i| Instance {
            shape: i as ShapeId,
            transform: Affine3A::IDENTITY,
        })
        .collect();
    let mut text = Vec::new();
    write_obj(&mut text, &instances, &shapes)?;
    write_atomically(path, std::str::from_utf8(&text)?)
}

/// Writes a file atomically (temporary file, then rename), so an interrupted
/// run never leaves a truncated result behind.
fn write_atomically(path: &Path, text: &str) -> Result<(), Box<dyn Error>> {
    let tmp = path.with_extension("tmp");
    let write = || -> std::io::Result<()> {
        let mut f = fs::File::create(&tmp)?;
        f.write_all(text.as_bytes())?;
        f.sync_all()?;
        fs::rename(&tmp, path)
    };
    write().map_err(|e| format!("cannot write {}: {e}", path.display()).into())
}
