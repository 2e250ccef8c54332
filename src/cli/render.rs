//! `shapegen render`: re-express a saved chromosome.

use shapegen::genome::ChromosomeData;

use super::args::RenderArgs;
use super::{CliError, load_experiment};

/// Runs `shapegen render`.
pub fn render(args: &RenderArgs) -> Result<(), CliError> {
    let experiment = load_experiment(args.experiment.as_deref(), args.data.as_deref())?;
    let path = &args.chromosome;
    let text = std::fs::read_to_string(path)
        .map_err(|e| CliError::msg(format!("cannot read {}: {e}", path.display())))?;
    let data: ChromosomeData = serde_json::from_str(&text)
        .map_err(|e| CliError::msg(format!("{}: not a chromosome file: {e}", path.display())))?;
    let chromosome = experiment.chromosome(&data, path)?;
    let written = experiment.write_model(&chromosome, &args.out)?;
    println!(
        "fitness {:.4} ({} genes) on `{}`; wrote {}",
        experiment.evaluate(&chromosome),
        chromosome.len(),
        experiment.name(),
        written
            .iter()
            .map(|p| p.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    Ok(())
}
