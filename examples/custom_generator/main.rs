//! A user's own generator with the whole `shapegen` command line: the
//! topiary of `topiary.rs` (not one of the paper's), registered under the
//! name its experiment file uses.
//!
//! ```sh
//! cargo run --release --example custom_generator -- run examples/custom_generator/topiary.toml
//! cargo run --release --example custom_generator -- compare examples/custom_generator/topiary.toml --seconds 10
//! cargo run --release --example custom_generator -- render out/best.json --experiment examples/custom_generator/topiary.toml
//! ```
//!
//! Without an experiment file it runs the embedded `topiary.toml` (its
//! meshes are read from this folder of the checkout). `run` writes `out/best.obj` (pot, stem,
//! branches and foliage balls, with the example's own meshes), the target
//! as placed (`target.obj`), slices, `best.json`, `curve.csv` and
//! `summary.json` with IoU, precision and recall per target.

mod topiary;

use shapegen::cli::Cli;
use topiary::Topiary;

fn main() -> std::process::ExitCode {
    Cli::new()
        .generator("topiary", Topiary)
        .default_experiment(
            "topiary",
            include_str!("topiary.toml"),
            concat!(env!("CARGO_MANIFEST_DIR"), "/examples/custom_generator"),
        )
        .run()
}
