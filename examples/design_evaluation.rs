//! The thesis's evaluation of pdf design (§4.7, Table 4.3, Fig. 4.13) on the
//! toy grammar and the paper's generators: a program plays the user of each
//! task in `shapegen::design::tasks`, and the Jensen–Shannon divergences of
//! the default pdf, parameter learning and structure learning to the target
//! pdf are measured, with learning curves of GPR against the weighted KDE.
//!
//! `cargo run --release --example design_evaluation -- [OUT_DIR] [TASK…]`
//! prints the tables and writes `OUT_DIR/design_evaluation.json` (default
//! `out/design`).

use std::error::Error;
use std::path::PathBuf;
use std::time::Instant;

use shapegen::design::evaluation::{EvalOptions, evaluate};
use shapegen::design::tasks;

fn main() -> Result<(), Box<dyn Error>> {
    let mut args = std::env::args().skip(1);
    let out = PathBuf::from(args.next().unwrap_or_else(|| "out/design".into()));
    let only: Vec<String> = args.collect();
    let options = EvalOptions::default();
    let mut reports = Vec::new();
    for task in tasks::all() {
        if !only.is_empty() && !only.contains(&task.name) {
            continue;
        }
        let start = Instant::now();
        let r = evaluate(&task, &options)?;
        println!(
            "{:10} default {:.4}  parameter {:.4}  structure {:.4}  (K = {}, split {:?}, positive {:.3}, {:.1} s)",
            r.task,
            r.js_default,
            r.js_parameter,
            r.js_structure,
            r.components,
            r.structure.split_nodes,
            r.positive_fraction,
            start.elapsed().as_secs_f64()
        );
        for p in &r.curve {
            println!(
                "    n = {:4}: GPR {:.4}  KDE {:.4} (h = {})",
                p.scored, p.gpr, p.kde, p.kde_bandwidth
            );
        }
        for (n, js) in &r.active {
            println!("    interactive n = {n:4}: GPR {js:.4}");
        }
        println!(
            "    JS <= 0.01: GPR after {:?}, KDE after {:?}, interactive GPR after {:?}",
            r.gpr_reaches_001, r.kde_reaches_001, r.active_reaches_001
        );
        reports.push(r);
    }
    std::fs::create_dir_all(&out)?;
    let path = out.join("design_evaluation.json");
    let tmp = path.with_extension("json.tmp");
    std::fs::write(&tmp, serde_json::to_string_pretty(&reports)?)?;
    std::fs::rename(&tmp, &path)?;
    println!("wrote {}", path.display());
    Ok(())
}
