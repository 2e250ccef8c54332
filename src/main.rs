//! The `shapegen` command line for the built-in generators (see
//! [`shapegen::cli`] for a program's own).
//!
//! - `shapegen` / `shapegen run [EXPERIMENT]`: one optimization (the
//!   built-in spaceship experiment without a file), results in `out/`.
//! - `shapegen compare [EXPERIMENT]`: every method, several runs, equal
//!   wall-clock budgets; curves and statistics in `compare/`.
//! - `shapegen render best.json --experiment E`: a saved chromosome's model.

fn main() -> std::process::ExitCode {
    shapegen::cli::Cli::new().run()
}
