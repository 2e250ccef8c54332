//! Command-line arguments.

use std::path::PathBuf;

use crate::experiment::Method;
use clap::{Parser, Subcommand};

/// Evolves procedural models toward targets (ShapeGenetics: a genetic
/// algorithm over derivation trees, with SMC, SOSMC and RJMCMC baselines).
///
/// Without a command, runs the built-in experiment (`shapegen run`).
#[derive(Debug, Parser)]
#[command(name = "shapegen", version, about, long_about = None)]
pub struct Args {
    /// What to do.
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// The commands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// One optimization run; writes best.obj, best.json, pictures, curve.csv, summary.json.
    Run(RunArgs),
    /// Every method several times with equal wall-clock budgets; writes curves.csv, curves.png, summary.json.
    Compare(CompareArgs),
    /// Re-expresses a saved chromosome (best.json) and writes its model and pictures.
    Render(RenderArgs),
    /// A thumbnail gallery of what the experiment's generator can make: gallery.png, index.html, gallery.json.
    Gallery(GalleryArgs),
    /// Morphs one design into another (thesis ch. 5): frames/, sequence.gif, contact.png, sequence.json, index.html.
    Transform(TransformArgs),
    /// Design the generator's pdf from preference scores (Dang et al. 2015): sample, score, learn, export.
    #[command(subcommand)]
    Design(DesignCommand),
}

/// `shapegen transform`.
#[derive(Debug, clap::Args)]
pub struct TransformArgs {
    /// The transformation file (TOML: `[first]`, `[second]`, `[blend]`, `[matches]`, `[[timeline]]`, `[frames]`).
    pub file: PathBuf,
    /// Frames in the sequence, both ends included (default: the file's `frames.count`).
    #[arg(long)]
    pub frames: Option<usize>,
    /// One frame only, at this time in [0, 1].
    #[arg(long)]
    pub at: Option<f32>,
    /// Also write each frame's model as OBJ (frames/frame_NNN.obj; variations/NNN.obj).
    #[arg(long)]
    pub obj: bool,
    /// Instead of a sequence, N variations mixing every design of the file
    /// (first, second and each `[[design]]`): pictures, a gallery and variations.json.
    #[arg(long, value_name = "N", conflicts_with_all = ["frames", "at"])]
    pub variations: Option<usize>,
    /// How variations mix the designs: blend (random blend weights) or switch (whole rules only).
    #[arg(long, value_enum, default_value = "blend", requires = "variations")]
    pub mixing: MixingArg,
    /// Seed of the variations: variation i is drawn from seed + i.
    #[arg(long, default_value_t = 1, requires = "variations")]
    pub seed: u64,
    /// Output directory.
    #[arg(long, default_value = "transform")]
    pub out: PathBuf,
    /// No progress bar.
    #[arg(long, short)]
    pub quiet: bool,
}

/// How variations mix their designs (`--mixing`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum MixingArg {
    /// Random blend weights (the thesis's variety).
    Blend,
    /// Weights 0 or 1: whole rules of one design or the other.
    Switch,
}

/// `shapegen design …`: the steps of a design session.
#[derive(Debug, Subcommand)]
pub enum DesignCommand {
    /// Draws a batch of models to score: thumbnails, index.html and scores.json (fill in the scores) in --out.
    Sample(DesignSampleArgs),
    /// Reads the filled-in scores.json into the session and fits the preference.
    Learn(DesignLearnArgs),
    /// Fits a learned generator to the preference and writes it (learned.json) for `gallery --prior` and `run --prior`.
    Export(DesignExportArgs),
    /// The design interface in a browser: a local server with one page (score, sample, sort, factors, export).
    Serve(DesignServeArgs),
    /// The thesis's evaluation (§4.7) on built-in design tasks played by a program: evaluation.json, table.md, curves.png.
    Evaluate(DesignEvaluateArgs),
}

/// `shapegen design serve`.
#[derive(Debug, clap::Args)]
pub struct DesignServeArgs {
    /// Experiment and session.
    #[command(flatten)]
    pub session: SessionArgs,
    /// Port on 127.0.0.1 (0: any free one).
    #[arg(long, default_value_t = 8765)]
    pub port: u16,
    /// Address to listen on (127.0.0.1 keeps the page to this machine).
    #[arg(long, default_value = "127.0.0.1")]
    pub host: String,
    /// Random seed of a new session; default: the experiment's.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Open the page in the default browser.
    #[arg(long)]
    pub open: bool,
}

/// `shapegen design evaluate`.
#[derive(Debug, clap::Args)]
pub struct DesignEvaluateArgs {
    /// Tasks to run, comma-separated (toy-colour, toy-2f, S1, S2, T1, C1); default: all.
    #[arg(long, value_delimiter = ',')]
    pub tasks: Vec<String>,
    /// Smaller sets (1,000 evaluation models, 500 training, up to 96 scored): a quick look, not the reported numbers.
    #[arg(long)]
    pub quick: bool,
    /// The numbers of scored models on the learning curves, comma-separated (default 12,24,48,96,144,192,288,384).
    #[arg(long, value_delimiter = ',')]
    pub scored: Vec<usize>,
    /// Seed of every random stream.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Output directory.
    #[arg(long, default_value = "design/evaluation")]
    pub out: PathBuf,
    /// No progress lines.
    #[arg(long, short)]
    pub quiet: bool,
}

/// The session file of `shapegen design`.
#[derive(Debug, clap::Args)]
pub struct SessionArgs {
    /// The experiment whose generator is designed (its targets are not used).
    #[command(flatten)]
    pub experiment: ExperimentArgs,
    /// The session file: every scored model and score (created by the first `sample`, rewritten atomically).
    #[arg(long, default_value = "design/session.json")]
    pub session: PathBuf,
}

/// `shapegen design sample`.
#[derive(Debug, clap::Args)]
pub struct DesignSampleArgs {
    /// Experiment and session.
    #[command(flatten)]
    pub session: SessionArgs,
    /// Models in the batch.
    #[arg(long, default_value_t = 24)]
    pub count: usize,
    /// How they are chosen: default pdf, current pdf, complementary pdf, most uncertain, or already scored.
    #[arg(long, value_enum, default_value = "default")]
    pub mode: crate::design::session::Mode,
    /// The factor the scores are for (created if new; default: the session's current one).
    #[arg(long)]
    pub factor: Option<String>,
    /// Random seed of a new session; default: the experiment's.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Side of a thumbnail in pixels.
    #[arg(long, default_value_t = 200)]
    pub thumbnail: u32,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Output directory of the batch.
    #[arg(long, default_value = "design/batch")]
    pub out: PathBuf,
}

/// `shapegen design learn`.
#[derive(Debug, clap::Args)]
pub struct DesignLearnArgs {
    /// Experiment and session.
    #[command(flatten)]
    pub session: SessionArgs,
    /// The scores file `sample` wrote, with scores (0-100) filled in; entries left null are skipped.
    #[arg(long, default_value = "design/batch/scores.json")]
    pub scores: PathBuf,
}

/// `shapegen design export`.
#[derive(Debug, clap::Args)]
pub struct DesignExportArgs {
    /// Experiment and session.
    #[command(flatten)]
    pub session: SessionArgs,
    /// structure (split nodes and a mixture; the thesis's default) or parameter (probabilities only).
    #[arg(long, value_enum, default_value = "structure")]
    pub sampler: SamplerArg,
    /// Models drawn from the preference (rejection sampling) to fit it to.
    #[arg(long, default_value_t = 1000)]
    pub training: usize,
    /// Random seed; default: the session's.
    #[arg(long)]
    pub seed: Option<u64>,
    /// The learned generator's file.
    #[arg(long, default_value = "design/learned.json")]
    pub out: PathBuf,
}

/// How `design export` fits the learned generator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum SamplerArg {
    /// Split the relevant nodes by parent and fit a mixture by EM.
    Structure,
    /// Relative frequencies of the slot probabilities and choice weights.
    Parameter,
}

/// `shapegen gallery`.
#[derive(Debug, clap::Args)]
pub struct GalleryArgs {
    /// The experiment whose generator and shapes are shown (its targets are not used).
    #[command(flatten)]
    pub experiment: ExperimentArgs,
    /// Models drawn by uncontrolled generation.
    #[arg(long, default_value_t = 200)]
    pub samples: usize,
    /// Clusters (the default model's and one per representative around it).
    #[arg(long, default_value_t = 14)]
    pub clusters: usize,
    /// Random seed of the samples and the clustering; default: the experiment's.
    #[arg(long)]
    pub seed: Option<u64>,
    /// The model in the middle: a chromosome file (e.g. best.json); default: the generator's default model.
    #[arg(long)]
    pub default_model: Option<PathBuf>,
    /// Draw the samples from a learned generator (`shapegen design export`) instead of the default pdf.
    #[arg(long)]
    pub prior: Option<PathBuf>,
    /// Side of a representative's thumbnail in pixels (the default model's is 3× larger).
    #[arg(long, default_value_t = 160)]
    pub thumbnail: u32,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Output directory.
    #[arg(long, default_value = "gallery")]
    pub out: PathBuf,
    /// No progress bar.
    #[arg(long, short)]
    pub quiet: bool,
}

/// Where the experiment comes from.
#[derive(Debug, clap::Args)]
pub struct ExperimentArgs {
    /// Experiment file (TOML); the built-in experiment if omitted.
    pub experiment: Option<PathBuf>,
    /// Data directory that `${data}` in the experiment stands for [env: SHAPEGEN_DATA].
    #[arg(long)]
    pub data: Option<PathBuf>,
}

/// `shapegen run`.
#[derive(Debug, clap::Args)]
pub struct RunArgs {
    /// The experiment.
    #[command(flatten)]
    pub experiment: ExperimentArgs,
    /// Method (tandem, ga, smc, sosmc, rjmcmc, islands, hybrid); default: the experiment's `method`, else tandem.
    #[arg(long, value_parser = parse_method)]
    pub method: Option<Method>,
    /// Wall-clock budget in seconds (replaces the experiment's budget).
    #[arg(long)]
    pub seconds: Option<f64>,
    /// Budget in generations (replaces the experiment's budget).
    #[arg(long)]
    pub generations: Option<u64>,
    /// Random seed; default: the experiment's. The same seed gives the same result on any number of threads.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Output directory.
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// Write a checkpoint to this file (atomically) every --every generations and on Ctrl-C.
    #[arg(long)]
    pub checkpoint: Option<PathBuf>,
    /// Generations between checkpoints.
    #[arg(long, default_value_t = 10, requires = "checkpoint")]
    pub every: u64,
    /// Resume the run saved in this checkpoint (same experiment; method and seed come from it).
    #[arg(long)]
    pub resume: Option<PathBuf>,
    /// A learned generator (`shapegen design export`): initial models and grow moves follow its probabilities.
    #[arg(long)]
    pub prior: Option<PathBuf>,
    /// No progress bar or progress lines.
    #[arg(long, short)]
    pub quiet: bool,
}

/// `shapegen compare`.
#[derive(Debug, clap::Args)]
pub struct CompareArgs {
    /// The experiment.
    #[command(flatten)]
    pub experiment: ExperimentArgs,
    /// Methods to compare, comma-separated (ga, smc, sosmc, rjmcmc, islands, hybrid, tandem);
    /// default: the default method (tandem) and the paper's four.
    #[arg(long, value_delimiter = ',', value_parser = parse_method, default_value = "tandem,ga,smc,sosmc,rjmcmc")]
    pub methods: Vec<Method>,
    /// Runs per method (seeds seed, seed + 1, ...).
    #[arg(long, default_value_t = 3)]
    pub runs: u64,
    /// Wall-clock budget of every run, in seconds.
    #[arg(long, default_value_t = 30.0)]
    pub seconds: f64,
    /// First seed; default: the experiment's.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Output directory.
    #[arg(long, default_value = "compare")]
    pub out: PathBuf,
    /// A fitness to reach: the summary gives, per method, the seconds and
    /// the evaluations until the mean of its runs' best first reaches it
    /// (e.g. the final mean of a method compared on its own).
    #[arg(long, value_name = "FITNESS", allow_negative_numbers = true)]
    pub goal: Option<f64>,
    /// No progress lines.
    #[arg(long, short)]
    pub quiet: bool,
}

/// `shapegen render`.
#[derive(Debug, clap::Args)]
pub struct RenderArgs {
    /// A chromosome file written by `shapegen run` (best.json).
    pub chromosome: PathBuf,
    /// The experiment it was evolved in (default: the built-in one).
    #[arg(long)]
    pub experiment: Option<PathBuf>,
    /// Data directory that `${data}` in the experiment stands for [env: SHAPEGEN_DATA].
    #[arg(long)]
    pub data: Option<PathBuf>,
    /// Output directory.
    #[arg(long, default_value = "render")]
    pub out: PathBuf,
}

fn parse_method(s: &str) -> Result<Method, String> {
    s.parse()
        .map_err(|e: crate::experiment::ExperimentError| e.to_string())
}

impl Default for Command {
    /// No command: `shapegen run` with its defaults.
    fn default() -> Self {
        Args::parse_from(["shapegen", "run"])
            .command
            .expect("`run` is a command")
    }
}
