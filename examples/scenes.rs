//! Express a random model of each of the paper's generators and write it as
//! an OBJ file you can open in Blender or MeshLab.
//!
//! `cargo run --release --example scenes [SEED]` writes
//! `out/spaceship.obj`, `out/tree_v2.obj`, `out/tree_v1.obj`,
//! `out/space_filling_city.obj` and `out/grid_city.obj`.

use std::error::Error;
use std::path::Path;

use shapegen::express::{CountingSink, Generator};
use shapegen::prelude::*;
use shapegen::rng::stream;
use shapegen::scenes::{GridCity, SpaceFillingCity, Spaceship, TreeV1, TreeV2};
use shapegen::score::ShapeMeshes;
use shapegen::score::write_model;

/// A random individual of about `genes` genes, written to `out/<name>.obj`.
fn write<G: Generator>(
    generator: &G,
    name: &str,
    genes: u32,
    seed: u64,
) -> Result<(), Box<dyn Error>> {
    let mut rng = stream(seed, &[]);
    let chromosome = random_individual(
        generator.graph(),
        &InitLength::Around { l0: genes },
        &mut rng,
    )?;
    let mut count = CountingSink::default();
    generator.express(&chromosome, &mut count);
    let path = Path::new("out").join(format!("{name}.obj"));
    write_model(
        &path,
        generator,
        &chromosome,
        &ShapeMeshes::builtin(generator)?,
    )?;
    println!(
        "{:<28} {:>4} genes, {:>4} instances",
        path.display(),
        chromosome.len(),
        count.count
    );
    Ok(())
}

fn main() -> Result<(), Box<dyn Error>> {
    let seed = match std::env::args().nth(1) {
        Some(s) => s
            .parse()
            .map_err(|e| format!("SEED must be a number: {e}"))?,
        None => 1,
    };
    std::fs::create_dir_all("out")?;
    write(&Spaceship, "spaceship", 50, seed)?;
    write(&TreeV2, "tree_v2", 250, seed)?;
    write(&TreeV1, "tree_v1", 100, seed)?;
    write(&SpaceFillingCity, "space_filling_city", 50, seed)?;
    write(&GridCity, "grid_city", 40, seed)?;
    Ok(())
}
