//! Design a pdf for the paper's spaceship from the library: a program plays
//! the user, scoring three batches of models ("exactly two wing pairs 70,
//! one 30, others 0"), learns the preference, exports a learned generator
//! and shows what the generator makes before and after, as two galleries.
//!
//! `cargo run --release --example design_session [OUT_DIR]` writes
//! `OUT_DIR/default/gallery.png`, `OUT_DIR/learned/gallery.png` and
//! `OUT_DIR/learned.json` (default `out/design_session`).

use std::path::PathBuf;

use shapegen::design::session::{Mode, Session};
use shapegen::design::tasks::wing_pairs;
use shapegen::design::{FactorOptions, Learner, StructureOptions};
use shapegen::experiment::Experiment;
use shapegen::gallery::{Gallery, GalleryOptions};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "out/design_session".into()),
    );
    // The built-in experiment: the spaceship with the paper's limits.
    let experiment = Experiment::builtin();
    let graph = experiment.graph();
    let mut session = Session::new("spaceship", graph, 7);
    // Three rounds: default samples first, then the current and the
    // complementary pdf, 24 models each, scored by the program.
    for mode in [Mode::Default, Mode::Current, Mode::Complementary] {
        let batch = session.sample(graph, mode, 24)?;
        for shown in &batch {
            session.score(shown.id, wing_pairs(graph, &shown.model))?;
        }
        let top = session.learn(graph, FactorOptions::default())?.factors[0].top_features(graph, 2);
        println!(
            "after {} scored models ({} batch): most relevant {:?}",
            session.scored_count(),
            mode.name(),
            top
        );
    }
    let mut rng = shapegen::rng::stream(7, &[1]);
    let (pdf, _, acceptance) = session.export(
        graph,
        Learner::Structure,
        1000,
        StructureOptions::default(),
        &mut rng,
    )?;
    println!(
        "learned generator: {} components (rejection acceptance {:.0} %)",
        pdf.components.len(),
        100.0 * acceptance
    );
    std::fs::create_dir_all(&out)?;
    shapegen::output::write_json(&out.join("learned.json"), &pdf)?;

    let options = GalleryOptions {
        samples: 120,
        clusters: 10,
        ..GalleryOptions::default()
    };
    let sampler = pdf.sampler(graph)?;
    let share = |g: &Gallery| {
        let models = &g.models[1..];
        let liked = models
            .iter()
            .filter(|m| {
                m.chromosome
                    .as_ref()
                    .is_some_and(|c| wing_pairs(graph, c) > 0.0)
            })
            .count();
        100.0 * liked as f64 / models.len() as f64
    };
    let default = Gallery::sample(&experiment, &options, &|_| {})?;
    default.write(
        &out.join("default"),
        &experiment,
        "The spaceship's default pdf",
    )?;
    let learned = Gallery::sample_with(&experiment, &options, &|_| {}, &|rng| {
        sampler.sample(rng).map_err(|e| e.to_string())
    })?;
    learned.write(
        &out.join("learned"),
        &experiment,
        "The spaceship after designing its pdf",
    )?;
    println!(
        "one or two wing pairs: {:.0} % of the default pdf's samples, {:.0} % of the learned generator's; wrote {}",
        share(&default),
        share(&learned),
        out.display()
    );
    Ok(())
}
