//! The TOML schema of experiment files, as deserialized (before paths,
//! meshes and images are resolved). Every table refuses unknown keys.

use std::collections::BTreeMap;

use serde::Deserialize;
use toml::Spanned;

/// Three numbers `[x, y, z]`: exactly three (serde's arrays would drop a
/// fourth silently).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Xyz<T>(pub [T; 3]);

impl<'de, T: Deserialize<'de> + Copy> Deserialize<'de> for Xyz<T> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = Vec::<T>::deserialize(d)?;
        match <[T; 3]>::try_from(v.as_slice()) {
            Ok(a) => Ok(Self(a)),
            Err(_) => Err(serde::de::Error::custom(format!(
                "expected 3 numbers [x, y, z], got {}",
                v.len()
            ))),
        }
    }
}

/// A whole experiment file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ExperimentFile {
    pub name: Option<String>,
    pub description: Option<String>,
    pub generator: Spanned<String>,
    pub data: Option<Spanned<String>>,
    pub seed: Option<u64>,
    pub method: Option<Spanned<String>>,
    pub optimum: Option<f64>,
    pub limits: Option<Spanned<LimitsFile>>,
    pub budget: Option<Spanned<BudgetFile>>,
    #[serde(default)]
    pub shapes: BTreeMap<String, ShapeFile>,
    pub score: Spanned<ScoreFile>,
    pub volume: Option<Spanned<VolumeFile>>,
    pub image: Option<Spanned<ImageFile>>,
    pub ga: Option<Spanned<GaFile>>,
    pub smc: Option<Spanned<SmcFile>>,
    pub sosmc: Option<Spanned<SmcFile>>,
    pub rjmcmc: Option<Spanned<RjmcmcFile>>,
    pub islands: Option<Spanned<IslandsFile>>,
    pub hybrid: Option<Spanned<HybridFile>>,
    pub tandem: Option<Spanned<TandemFile>>,
}

/// `[limits]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct LimitsFile {
    pub min_len: Option<u32>,
    pub max_len: Option<u32>,
    pub max_depth: Option<u32>,
}

/// `[budget]` and `budget = {..}` of a method.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct BudgetFile {
    pub seconds: Option<f64>,
    pub evaluations: Option<u64>,
    pub generations: Option<u64>,
}

/// `[shapes.NAME]`: a mesh replacing a generator shape's built-in one.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ShapeFile {
    pub mesh: Spanned<String>,
    #[serde(default)]
    pub normalize: bool,
}

/// `[score]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ScoreFile {
    pub form: ScoreForm,
    pub good: Option<f64>,
    pub bad: Option<f64>,
    pub length: Option<f64>,
    pub overlap: Option<f64>,
    #[serde(rename = "self")]
    pub self_weight: Option<f64>,
}

/// `score.form`.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub(super) enum ScoreForm {
    Normalized,
    Paper,
}

/// `[volume]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct VolumeFile {
    pub min: Xyz<f32>,
    pub max: Xyz<f32>,
    pub resolution: Xyz<u32>,
    pub outside_count: Option<OutsideCountFile>,
    pub targets: Vec<Spanned<VolumeTargetFile>>,
}

/// `volume.outside_count`: how model cells outside the grid are counted.
#[derive(Debug, Deserialize)]
#[serde(rename_all = "snake_case")]
pub(super) enum OutsideCountFile {
    /// Cells inside an instance (the paper).
    Solid,
    /// Cells inside an instance's bounding box (the authors' code).
    Aabb,
}

/// `[[volume.targets]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct VolumeTargetFile {
    pub mesh: Option<Spanned<String>>,
    pub builtin: Option<Spanned<String>>,
    pub fill: Option<f64>,
    pub outside: Option<f64>,
    pub inside: Option<InsideFile>,
    pub scale: Option<Spanned<ScaleFile>>,
    pub rotate: Option<Spanned<Xyz<f32>>>,
    pub translate: Option<Spanned<Xyz<f32>>>,
    pub fit: Option<Spanned<FitFile>>,
}

/// `scale` of a target: one factor, or one per axis.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(untagged)]
pub(super) enum ScaleFile {
    Uniform(f32),
    PerAxis(Xyz<f32>),
}

/// `fit` of a target: `"grid"` or a box.
#[derive(Clone, Debug, Deserialize)]
#[serde(untagged)]
pub(super) enum FitFile {
    Named(String),
    Box { min: Xyz<f32>, max: Xyz<f32> },
}

/// `volume.targets[i].inside`: how a target mesh's inside is decided.
#[derive(Debug, Deserialize)]
#[serde(rename_all = "snake_case")]
pub(super) enum InsideFile {
    /// Ray parity (watertight meshes).
    Parity,
    /// The generalized winding number (meshes with holes).
    Winding,
}

/// `[image]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ImageFile {
    pub width: Option<u32>,
    pub height: Option<u32>,
    pub targets: Vec<Spanned<ImageTargetFile>>,
}

/// `[[image.targets]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ImageTargetFile {
    pub png: Option<Spanned<String>>,
    pub pfm: Option<Spanned<String>>,
    pub mask: Option<MaskFile>,
    pub threshold: Option<Spanned<f32>>,
    pub target: Option<f32>,
    pub background: Option<f32>,
    pub camera: Spanned<CameraFile>,
}

/// `mask` of a PNG target: which pixels are target.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(rename_all = "snake_case")]
pub(super) enum MaskFile {
    Red0,
    Dark,
    Alpha,
    AlphaDark,
}

/// `camera = {..}` of an image target: the paper's orbit camera (`phi`,
/// `theta`, `r`, `look_at`) or a right-handed one (`eye`, `target`, `up`).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct CameraFile {
    pub phi: Option<f64>,
    pub theta: Option<f64>,
    pub r: Option<f64>,
    pub look_at: Option<Xyz<f64>>,
    pub eye: Option<Xyz<f64>>,
    pub target: Option<Xyz<f64>>,
    pub up: Option<Xyz<f64>>,
    pub fov: Option<f64>,
    pub near: Option<f64>,
    pub far: Option<f64>,
}

/// `[ga]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct GaFile {
    pub population: usize,
    pub elites: usize,
    pub init_length: u32,
    pub mutation_rate: f64,
    pub split: SplitFile,
    pub tournament: Option<usize>,
    pub elite_dedup: Option<bool>,
    pub local_search: Option<usize>,
    pub adaptive_split: Option<bool>,
    pub max_retries: Option<u32>,
    pub crossover: Option<EdgeMatchFile>,
    pub challenge: Option<u64>,
    pub budget: Option<Spanned<BudgetFile>>,
}

/// `ga.crossover`: which connections may swap subtrees.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(rename_all = "snake_case")]
pub(super) enum EdgeMatchFile {
    /// The same generator-graph edge (parent node and slot): the paper.
    Strict,
    /// Any connection to the same child node: the authors' code.
    ChildType,
}

/// `split = { grow, cut, alter }` of the GA.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SplitFile {
    pub grow: f64,
    pub cut: f64,
    pub alter: f64,
}

/// `[smc]` and `[sosmc]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SmcFile {
    pub particles: usize,
    pub budget: Option<Spanned<BudgetFile>>,
}

/// `[rjmcmc]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RjmcmcFile {
    pub chains: usize,
    pub init_length: u32,
    pub jump_probability: Option<f64>,
    /// `β` factor per step; 1 turns annealing off.
    pub annealing: Option<f64>,
    pub delayed_rejection: Option<DelayedRejectionFile>,
    pub budget: Option<Spanned<BudgetFile>>,
}

/// `[islands]`: the `[ga]` settings split across islands.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct IslandsFile {
    pub islands: Option<usize>,
    pub interval: Option<u64>,
    pub migrants: Option<usize>,
    pub topology: Option<TopologyFile>,
    pub challenge: Option<u64>,
    pub budget: Option<Spanned<BudgetFile>>,
}

/// `[hybrid]`: the `[ga]` and `[rjmcmc]` settings, and when to switch.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct HybridFile {
    pub patience: Option<u64>,
    pub patience_share: Option<f64>,
    pub first_phase: Option<FirstPhaseFile>,
    pub challenge: Option<u64>,
    pub budget: Option<Spanned<BudgetFile>>,
}

/// `[tandem]`: the `[ga]` and `[rjmcmc]` settings, and how they trade; the
/// GA's `local_search`, `elite_dedup` and `adaptive_split` are the tandem's own.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct TandemFile {
    pub interval: Option<u64>,
    pub migrants: Option<usize>,
    pub local_search: Option<usize>,
    pub elite_dedup: Option<bool>,
    pub adaptive_split: Option<bool>,
    pub first_phase: Option<FirstPhaseFile>,
    pub balance: Option<bool>,
    pub to_chains: Option<bool>,
    pub challenge: Option<u64>,
    pub budget: Option<Spanned<BudgetFile>>,
}

/// `hybrid.first_phase` and `tandem.first_phase`: what builds the GA's first models.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(rename_all = "snake_case")]
pub(super) enum FirstPhaseFile {
    /// Nothing: the GA's random individuals.
    None,
    /// SMC with the `[smc]` settings.
    Smc,
    /// SOSMC with the `[sosmc]` settings.
    Sosmc,
}

/// `islands.topology`.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(rename_all = "snake_case")]
pub(super) enum TopologyFile {
    Ring,
    Random,
}

/// `rjmcmc.delayed_rejection`.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(rename_all = "snake_case")]
pub(super) enum DelayedRejectionFile {
    Off,
    Exact,
    ApproxAlter,
}
