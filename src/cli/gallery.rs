//! `shapegen gallery`: a thumbnail gallery of an experiment's generator.

use std::time::Instant;

use super::args::GalleryArgs;
use super::{Cli, CliError, guard, read_chromosome, thread_pool};
use crate::gallery::{GALLERY_FILES, Gallery, GalleryOptions};

/// Runs `shapegen gallery`.
pub(super) fn gallery(cli: &Cli, args: &GalleryArgs) -> Result<(), CliError> {
    let experiment = cli.load_experiment(
        args.experiment.experiment.as_deref(),
        args.experiment.data.as_deref(),
    )?;
    let default_model = match &args.default_model {
        None => None,
        Some(path) => Some(read_chromosome(&experiment, path)?),
    };
    let options = GalleryOptions {
        samples: args.samples,
        clusters: args.clusters,
        seed: args.seed.unwrap_or(experiment.seed()),
        thumbnail: args.thumbnail,
        default_model,
        ..GalleryOptions::default()
    };
    let pool = thread_pool(args.threads)?;
    let _taken = guard::take_output_dir(&args.out)?;
    let mut outputs: Vec<_> = GALLERY_FILES.iter().map(|f| args.out.join(f)).collect();
    outputs.push(args.out.join("models"));
    let mut inputs = experiment.inputs().to_vec();
    inputs.extend(args.default_model.iter().cloned());
    inputs.extend(args.prior.iter().cloned());
    let learned = match &args.prior {
        None => None,
        Some(path) => Some(
            super::read_learned(path)?
                .sampler(experiment.graph())
                .map_err(|e| CliError::msg(format!("{}: {e}", path.display())))?,
        ),
    };
    guard::refuse_overwriting_inputs(&outputs, &inputs)?;
    // A model file of the experiment inside `out/models` would be replaced.
    let models_dir = std::fs::canonicalize(args.out.join("models")).ok();
    if let Some((dir, input)) = models_dir.as_ref().and_then(|dir| {
        inputs
            .iter()
            .find(|i| std::fs::canonicalize(i).is_ok_and(|c| c.starts_with(dir)))
            .map(|i| (dir, i))
    }) {
        return Err(CliError::msg(format!(
            "the gallery would write into {} which holds its input {}: choose another --out; nothing was run",
            dir.display(),
            input.display()
        )));
    }
    let total = options.samples + 1;
    let bar = (!args.quiet).then(|| {
        super::progress::counting_bar(
            total,
            "models",
            format!("gallery of `{}`", experiment.generator()),
        )
    });
    let start = Instant::now();
    let progress = |done: usize| {
        if let Some(bar) = &bar {
            bar.set_position(done as u64);
        }
    };
    let gallery = pool
        .install(|| match &learned {
            None => Gallery::sample(&experiment, &options, &progress),
            Some(sampler) => Gallery::sample_with(&experiment, &options, &progress, &|rng| {
                sampler.sample(rng).map_err(|e| e.to_string())
            }),
        })
        .map_err(|e| CliError::msg(e.to_string()))?;
    if let Some(bar) = &bar {
        bar.finish_and_clear();
    }
    for note in &gallery.notes {
        errln!("shapegen: note: {note}");
    }
    let title = match &args.prior {
        None => format!("What `{}` can make", experiment.generator()),
        Some(p) => format!(
            "What `{}` makes under {}",
            experiment.generator(),
            p.display()
        ),
    };
    let written = guard::writing(|| gallery.write(&args.out, &experiment, &title))
        .map_err(|e| CliError::msg(e.to_string()))?;
    let v = gallery.best_view.viewpoint;
    outln!(
        "gallery of `{}`: {} models in {} clusters, best view at azimuth {:.0}°, elevation {:.0}°, in {:.1} s; wrote {} files to {} (open {})",
        experiment.generator(),
        gallery.models.len(),
        gallery.clusters.len(),
        v.azimuth.to_degrees(),
        v.elevation.to_degrees(),
        start.elapsed().as_secs_f64(),
        written.len(),
        args.out.display(),
        args.out.join("index.html").display()
    );
    Ok(())
}
