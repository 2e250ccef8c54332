//! `shapegen render`: re-express a saved chromosome.

use super::args::RenderArgs;
use super::{Cli, CliError, guard};
use crate::genome::ChromosomeData;
use crate::output::mean_iou;

/// Runs `shapegen render`.
pub(super) fn render(cli: &Cli, args: &RenderArgs) -> Result<(), CliError> {
    let experiment = cli.load_experiment(args.experiment.as_deref(), args.data.as_deref())?;
    let path = &args.chromosome;
    crate::experiment::check_regular_file(path).map_err(CliError::msg)?;
    guard::check_output_dir(&args.out)?;
    let outputs: Vec<_> = experiment
        .model_files()
        .iter()
        .map(|n| args.out.join(n))
        .collect();
    let mut inputs = experiment.inputs().to_vec();
    inputs.push(path.clone());
    guard::refuse_overwriting_inputs(&outputs, &inputs)?;
    let text = std::fs::read_to_string(path)
        .map_err(|e| CliError::msg(format!("cannot read {}: {e}", path.display())))?;
    let data: ChromosomeData = serde_json::from_str(&text)
        .map_err(|e| CliError::msg(format!("{}: not a chromosome file: {e}", path.display())))?;
    let chromosome = experiment.chromosome(&data, path)?;
    let written = experiment.write_model(&chromosome, &args.out)?;
    println!(
        "fitness {:.4}, IoU {:.3} ({} genes) on `{}`; wrote {}",
        experiment.evaluate(&chromosome),
        mean_iou(&experiment.quality(&chromosome)),
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
