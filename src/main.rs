//! The `shapegen` command line.
//!
//! With no arguments it runs the built-in demo: the genetic algorithm evolves
//! a tree of blocks toward a known optimum and writes its results to `out/`.

use std::error::Error;
use std::fs;
use std::io::Write;
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};

use clap::Parser;
use serde::Serialize;
use shapegen::demo::{BlocksTarget, blocks_graph};
use shapegen::prelude::*;

/// Evolves procedural models toward a target with a genetic algorithm.
#[derive(Debug, Parser)]
#[command(version, about)]
struct Args {
    /// Random seed (the same seed gives the same result on any number of threads).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Generations to run.
    #[arg(long, default_value_t = 1000)]
    generations: u64,
    /// Number of blocks the demo target asks for.
    #[arg(long, default_value_t = 40)]
    blocks: usize,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Directory for the results.
    #[arg(long, default_value = "out")]
    out: PathBuf,
}

/// What `summary.json` holds.
#[derive(Serialize)]
struct Summary<'a> {
    generator: &'a str,
    method: &'a str,
    seed: u64,
    optimum: f64,
    best_fitness: f64,
    best_genes: usize,
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
    if args.blocks == 0 {
        return Err("--blocks must be at least 1".into());
    }
    if let Some(threads) = args.threads {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build_global()?;
    }
    let graph = blocks_graph();
    let fitness = BlocksTarget {
        graph: &graph,
        blocks: args.blocks,
    };
    let params = GaParams {
        population: 150,
        elites: 30,
        init: InitLength::Around {
            l0: args.blocks as u32,
        },
        ..GaParams::paper_spaceship()
    };
    let budget = Budget::generations(args.generations).and_target_fitness(1.0);
    println!(
        "shapegen demo: evolving a tree of {} blocks with x = 0.5 (optimum fitness 1.0), seed {}",
        args.blocks, args.seed
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
                "  generation {:>4}  evaluations {:>7}  best {:>8.4}  mean {:>8.4}",
                s.generation, s.evaluations, s.best, s.mean
            );
        }
        ControlFlow::Continue(())
    };
    let result = Ga::new(params).run(&graph, &fitness, &budget, args.seed, &mut observer)?;
    println!(
        "done: best fitness {:.4} ({} genes) after {} generations, {} evaluations, {:.2} s ({:?})",
        result.best_fitness,
        result.best.len(),
        result.generations,
        result.evaluations,
        result.elapsed.as_secs_f64(),
        result.stop
    );
    let summary = Summary {
        generator: graph.name(),
        method: "ga",
        seed: args.seed,
        optimum: 1.0,
        best_fitness: result.best_fitness,
        best_genes: result.best.len(),
        evaluations: result.evaluations,
        generations: result.generations,
        seconds: result.elapsed.as_secs_f64(),
        stop: result.stop,
    };
    write_results(
        &args.out,
        &curve,
        &serde_json::to_string_pretty(&result.best.to_data(&graph))?,
        &serde_json::to_string_pretty(&summary)?,
    )?;
    println!(
        "wrote {}/best.json, curve.csv, summary.json",
        args.out.display()
    );
    Ok(())
}

/// Writes each file atomically (temporary file, then rename), so an
/// interrupted run never leaves a truncated result behind.
fn write_results(dir: &Path, curve: &str, best: &str, summary: &str) -> Result<(), Box<dyn Error>> {
    fs::create_dir_all(dir)
        .map_err(|e| format!("cannot create output directory {}: {e}", dir.display()))?;
    for (name, text) in [
        ("curve.csv", curve),
        ("best.json", best),
        ("summary.json", summary),
    ] {
        let path = dir.join(name);
        let tmp = dir.join(format!(".{name}.tmp"));
        let write = || -> std::io::Result<()> {
            let mut f = fs::File::create(&tmp)?;
            f.write_all(text.as_bytes())?;
            f.sync_all()?;
            fs::rename(&tmp, &path)
        };
        write().map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    }
    Ok(())
}
