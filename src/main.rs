//! The `shapegen` command line.
//!
//! - `shapegen` / `shapegen run [EXPERIMENT]`: one optimization (the
//!   built-in spaceship experiment without a file), results in `out/`.
//! - `shapegen compare [EXPERIMENT]`: every method, several runs, equal
//!   wall-clock budgets; curves and statistics in `compare/`.
//! - `shapegen render best.json --experiment E`: a saved chromosome's model.

mod cli;

use std::error::Error;

use clap::Parser;
use cli::{Cli, Command};

fn main() {
    let mut args = Cli::parse();
    if args.command.is_none() {
        // No command: `shapegen run` with its defaults.
        args = Cli::parse_from(["shapegen", "run"]);
    }
    cli::catch_interrupts();
    let result = match &args.command {
        None => unreachable!("a command was set above"),
        Some(Command::Run(a)) => cli::run(a),
        Some(Command::Compare(a)) => cli::compare(a),
        Some(Command::Render(a)) => cli::render(a),
    };
    if let Err(e) = result {
        eprintln!("shapegen: error: {e}");
        let mut source = e.source();
        while let Some(s) = source {
            eprintln!("  caused by: {s}");
            source = s.source();
        }
        std::process::exit(1);
    }
}
