//! `shapegen render`: re-express a saved chromosome.

use super::args::RenderArgs;
use super::{Cli, CliError, guard, read_chromosome};
use crate::output::mean_iou;

/// Runs `shapegen render`.
pub(super) fn render(cli: &Cli, args: &RenderArgs) -> Result<(), CliError> {
    let experiment = cli.load_experiment(args.experiment.as_deref(), args.data.as_deref())?;
    let path = &args.chromosome;
    crate::experiment::check_regular_file(path).map_err(CliError::msg)?;
    let _taken = guard::take_output_dir(&args.out)?;
    let outputs: Vec<_> = experiment
        .model_files()
        .iter()
        .map(|n| args.out.join(n))
        .collect();
    let mut inputs = experiment.inputs().to_vec();
    inputs.push(path.clone());
    guard::refuse_overwriting_inputs(&outputs, &inputs)?;
    let chromosome = read_chromosome(&experiment, path)?;
    let written = experiment.write_model(&chromosome, &args.out)?;
    outln!(
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
