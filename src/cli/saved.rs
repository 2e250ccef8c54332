//! Checkpoint files of `shapegen run`: the optimizer's checkpoint plus what
//! the CLI needs to continue the same run, sealed by a content hash and
//! tied to a fingerprint of everything that changes scores.

use std::collections::BTreeMap;
use std::path::Path;

use serde::{Deserialize, Serialize};

use super::CliError;
use crate::experiment::{Experiment, check_regular_file};
use crate::genome::Chromosome;
use crate::optimize::{Budget, Checkpoint, FNV1A_START, SavedIndividual, SavedState, fnv1a};
use crate::output::{Row, write_json_compact};

/// How many individuals of a checkpoint's population (best first: the
/// elites) have their stored fitness recomputed on resume.
const VERIFIED: usize = 64;

/// What a checkpoint file holds.
#[derive(Debug, Serialize, Deserialize)]
pub struct SavedRun {
    /// The experiment's name.
    pub experiment: String,
    /// The method.
    pub method: String,
    /// The budget of the run.
    pub budget: Budget,
    /// What the scores depended on ([`Experiment::fingerprint`]).
    pub fingerprint: BTreeMap<String, String>,
    /// The curve up to the checkpoint.
    pub curve: Vec<Row>,
    /// The optimizer's state.
    pub checkpoint: Checkpoint,
    /// FNV-1a of the file's JSON with this field empty: a file changed by
    /// hand or damaged is refused.
    #[serde(default)]
    pub integrity: String,
}

impl SavedRun {
    /// The hash [`integrity`](Self::integrity) must hold.
    fn seal(&self) -> Result<String, CliError> {
        let mut unsealed = serde_json::to_value(self)
            .map_err(|e| CliError::msg(format!("cannot encode the checkpoint: {e}")))?;
        unsealed["integrity"] = serde_json::Value::String(String::new());
        let text = serde_json::to_string(&unsealed)
            .map_err(|e| CliError::msg(format!("cannot encode the checkpoint: {e}")))?;
        Ok(format!("{:016x}", fnv1a(FNV1A_START, text.as_bytes())))
    }

    /// Writes the checkpoint atomically (the previous one stays intact
    /// until the new one is complete).
    pub fn write(mut self, path: &Path) -> Result<(), CliError> {
        self.integrity = String::new();
        self.integrity = self.seal()?;
        Ok(write_json_compact(path, &self)?)
    }

    /// Reads a checkpoint and checks it against `experiment`: its content
    /// hash, the experiment's name and fingerprint, and the stored fitness
    /// of its best model and elites, recomputed.
    pub fn read(path: &Path, experiment: &Experiment) -> Result<Self, CliError> {
        let bad = |why: String| CliError::msg(format!("{}: {why}", path.display()));
        check_regular_file(path)
            .map_err(|why| CliError::msg(format!("cannot read the checkpoint: {why}")))?;
        let text = std::fs::read_to_string(path).map_err(|e| {
            CliError::msg(format!("cannot read checkpoint {}: {e}", path.display()))
        })?;
        let saved: Self = serde_json::from_str(&text)
            .map_err(|e| bad(format!("not a shapegen checkpoint: {e}")))?;
        if saved.integrity != saved.seal()? {
            return Err(bad(
                "the checkpoint was changed or damaged after it was written (its content hash does not match); refusing to resume from it".into(),
            ));
        }
        if saved.experiment != experiment.name() {
            return Err(bad(format!(
                "the checkpoint belongs to experiment `{}`, not `{}`",
                saved.experiment,
                experiment.name()
            )));
        }
        let now = experiment.fingerprint();
        let changed: Vec<&str> = now
            .iter()
            .filter(|(k, v)| saved.fingerprint.get(*k) != Some(v))
            .map(|(k, _)| k.as_str())
            .collect();
        if !changed.is_empty() {
            return Err(bad(format!(
                "the experiment changed since the checkpoint was written ({}): its scores would not be the ones the run computed; start a new run instead",
                changed.join(", ")
            )));
        }
        saved.verify_fitness(experiment).map_err(bad)?;
        Ok(saved)
    }

    /// Recomputes the fitness of the best model and the first [`VERIFIED`]
    /// individuals of the population or chains.
    fn verify_fitness(&self, experiment: &Experiment) -> Result<(), String> {
        let cp = &self.checkpoint;
        let stored = stored_models(&cp.state)?;
        for (what, s) in std::iter::once(("best model", &cp.best))
            .chain(stored.into_iter().map(|s| ("stored model", s)))
        {
            let c = Chromosome::from_partial_data(experiment.graph(), &s.chromosome)
                .map_err(|e| format!("a {what} is not a chromosome of this generator: {e}"))?;
            let recomputed = experiment.evaluate(&c);
            let stored = f64::from_bits(s.fitness_bits);
            if recomputed.to_bits() != s.fitness_bits && !(recomputed.is_nan() && stored.is_nan()) {
                return Err(format!(
                    "the checkpoint says its {what} has fitness {stored}, but it scores {recomputed}: refusing to resume from it"
                ));
            }
        }
        Ok(())
    }
}

/// The first [`VERIFIED`] models a checkpoint's state stores with their
/// fitness (SMC particles are partial models and are not checked).
fn stored_models(state: &SavedState) -> Result<Vec<&SavedIndividual>, String> {
    Ok(match state {
        SavedState::Population { individuals, .. } => {
            if individuals.is_empty() {
                return Err("the checkpoint's population is empty".into());
            }
            individuals.iter().take(VERIFIED).collect()
        }
        SavedState::Chains { chains, .. } => {
            if chains.is_empty() {
                return Err("the checkpoint has no chains".into());
            }
            chains.iter().take(VERIFIED).collect()
        }
        SavedState::Particles { particles } => {
            if particles.is_empty() {
                return Err("the checkpoint has no particles".into());
            }
            Vec::new()
        }
        SavedState::Islands { islands, .. } => {
            if islands.iter().all(Vec::is_empty) {
                return Err("the checkpoint's islands are empty".into());
            }
            islands.iter().flatten().take(VERIFIED).collect()
        }
        SavedState::Hybrid { state, .. } => stored_models(state)?,
        SavedState::Tandem { ga, .. } => stored_models(ga)?,
    })
}
