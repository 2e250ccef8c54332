//! Experiments: a generator, its targets, a score, limits, methods and a
//! budget, described in a TOML file and ready to run.
//!
//! ```
//! use shapegen::experiment::{Experiment, Method};
//! use shapegen::optimize::{Budget, NoObserver};
//!
//! let experiment = Experiment::builtin();
//! let result = experiment
//!     .run(Method::Ga, &Budget::generations(2), 1, None, &mut NoObserver)
//!     .unwrap();
//! assert!(result.best_fitness <= experiment.optimum().unwrap());
//! ```
//!
//! # The file format
//!
//! ```toml
//! name = "spaceship-volume"             # optional; defaults to the file name
//! description = "Paper Fig. 3 / Fig. 7 left"
//! generator = "spaceship"   # a name in the registry: the built-ins (see `scenes::register`) or a program's own
//! data = "../../../shared/data/paper"   # what ${data} means (relative to this file)
//! seed = 1
//! method = "ga"             # the method `shapegen run` uses without --method
//! optimum = 2.0             # the best reachable score, if known (reported beside results)
//!
//! [limits]                  # genome limits (default: the generator's own)
//! min_len = 4
//! max_len = 100             # exclusive
//! max_depth = 15
//!
//! [budget]                  # whichever comes first; a method's own budget replaces it
//! seconds = 60
//! # evaluations = 20000
//! # generations = 130
//!
//! [shapes.leaf]             # a generator shape's mesh (needed for shapes without a built-in one)
//! mesh = "${data}/leaf.obj"
//! normalize = true          # scale each axis into the unit box, as the paper's shapes
//!
//! [score]
//! form = "normalized"       # or "paper" (the paper's linear s_vol / s_img)
//! good = 2.0                # normalized: w_good, w_bad, w_length
//! bad = 15.0
//! length = 0.1
//! # overlap = 1.0           # normalized volume: a separate overlap term w_overlap
//! # self = 1.0              # paper volume form: w_self per self-overlapping cell
//!
//! [volume]                  # a volume scene ...
//! min = [-5.0, -5.0, -2.0]
//! max = [5.0, 5.0, 18.0]
//! resolution = [100, 200, 100]
//! # outside_count = "aabb"  # model cells outside the grid: "solid" (paper) or instance boxes (authors' code)
//! [[volume.targets]]
//! mesh = "${data}/spaceship_target.obj"   # or builtin = "ship"
//! fill = 1.0                # weight of a covered target cell
//! outside = 0.0             # weight of a model cell outside this target
//! # inside = "winding"      # a mesh with holes: generalized winding number, not ray parity
//! # Placing a target given in other units (applied in this order):
//! # scale = 0.01            # or [sx, sy, sz]
//! # rotate = [-90.0, 0.0, 0.0]  # degrees about x, then y, then z (e.g. a y-up mesh into a z-up grid)
//! # translate = [0.0, 0.0, 8.0]
//! # fit = "grid"            # or { min = [..], max = [..] }: uniform scale and centre into the box
//! #                         # (after `rotate`; not with `scale` or `translate`)
//!
//! # [image]                 # ... or an image scene
//! # width = 800
//! # height = 600
//! # [[image.targets]]
//! # png = "${data}/tree_target_sketch1.png"  # or pfm = "weights.pfm" (signed weights per pixel)
//! # mask = "red0"           # PNG: which pixels are target: "red0" (red channel 0, the paper's
//! #                         # sketches; default), "dark" (luminance < threshold: a drawing or a
//! #                         # shaded render on white), "alpha" (opacity >= threshold: a cut-out
//! #                         # on a transparent background), "alpha_dark" (opaque and dark)
//! # threshold = 0.5         # of dark / alpha / alpha_dark; transparency is always read
//! # target = 1.0            # PNG: weight of target pixels
//! # background = -1.0       # PNG: weight of the others
//! # camera = { phi = -1.5708, theta = 0.0, r = 9.4716, look_at = [-0.681, 3.2558, 0.0],
//! #            fov = 60.0, near = 0.1, far = 100.0 }   # the paper's orbit camera; degrees for fov
//! # camera = { eye = [0.0, 3.0, 9.0], target = [0.0, 3.0, 0.0], up = [0.0, 1.0, 0.0] }
//! #                         # or a right-handed look-at camera (OpenGL/Blender; see score::camera)
//!
//! [ga]
//! population = 150
//! elites = 30
//! init_length = 50          # initial lengths uniform in [L0/2, 3 L0/2]
//! mutation_rate = 0.3
//! split = { grow = 13.5, cut = 13.5, alter = 3.0 }
//! # tournament = 10, elite_dedup = false, max_retries = 3,
//! # local_search = 0        # children a generation that are one chain move from the best distinct models
//! # adaptive_split = false  # true: the grow/cut/alter shares follow how often each one's children beat their parent
//! # crossover = "strict" (same graph edge, the paper) | "child_type" (same child node, the authors' code)
//! budget = { generations = 130 }
//!
//! [smc]                     # and [sosmc]
//! particles = 500
//!
//! [rjmcmc]
//! chains = 70
//! init_length = 50
//! # jump_probability = 0.5, annealing = 1.1 (1 = off), delayed_rejection = "off" | "exact" | "approx_alter"
//!
//! # [islands], [hybrid] and [tandem] build on [ga] and [rjmcmc]; each may set a `budget`:
//! # [islands] islands = 4, interval = 10, migrants = 2, topology = "ring" | "random"
//! # [hybrid]  patience = 100, patience_share = 0.5,
//! #           first_phase = "none" | "smc" | "sosmc"   # which builds the GA's first models ([smc]/[sosmc] settings)
//! # [tandem]  interval = 10, migrants = 2, local_search = 30, elite_dedup = true, adaptive_split = false,
//! #           first_phase = "none" | "smc" | "sosmc"   # as the hybrid's; the chains wait meanwhile
//! #           balance = true, to_chains = false       # share evaluations by progress; send the GA's best to the chains
//! #           challenge = 100                         # GA steps without progress before a challenger population starts (0: never)
//! ```
//!
//! A target that covers no cell (outside the grid, not closed, too small)
//! and a PNG whose mask selects no pixel or every pixel are errors that say
//! why. Relative paths resolve against the file's folder; `${data}` stands for
//! the data directory: [`LoadOptions::data`] (the CLI's `--data` or the
//! `SHAPEGEN_DATA` environment variable) if given, else the file's `data`.
//! A method without a table gets the spaceship presets of the paper. Every
//! mistake is reported with the file, line, column and key.

mod error;
mod file;
mod memory;
pub(crate) mod problem;
mod resolve;
pub(crate) use resolve::toml_key;

use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};
use std::str::FromStr;

pub use error::ExperimentError;

use crate::genome::{Chromosome, ChromosomeData};
use crate::graph::Graph;
pub use crate::optimize::MethodParams;
use crate::optimize::{Budget, Checkpoint, Observer, RunResult};
use crate::registry::Registry;
use crate::score::Quality;
use problem::Problem;

/// The embedded default experiment (`experiments/default.toml`): the
/// spaceship generator toward a ship-shaped volume the project builds itself.
pub const BUILTIN: &str = include_str!("../../experiments/default.toml");

/// An optimization method.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Method {
    /// The genetic algorithm (paper Algorithm 1).
    Ga,
    /// Sequential Monte Carlo, slots in program order.
    Smc,
    /// Stochastically-ordered SMC.
    Sosmc,
    /// Reversible-jump MCMC with parallel tempering.
    Rjmcmc,
    /// The island GA (beyond the paper): the experiment's GA split into islands.
    Islands,
    /// The GA, then RJMCMC from its best models once it stalls (beyond the paper).
    Hybrid,
    /// The GA and RJMCMC side by side, trading their best (beyond the paper).
    Tandem,
}

impl Method {
    /// The method an experiment that names none runs, `run` without
    /// `--method` (unless the experiment names one) and the first of
    /// `compare`'s default set: the tandem, the best across the targets
    /// measured in `reproduction.md`.
    pub const DEFAULT: Method = Method::Tandem;

    /// All methods: the paper's, in its order, then shapegen's.
    pub const ALL: [Method; 7] = [
        Method::Ga,
        Method::Smc,
        Method::Sosmc,
        Method::Rjmcmc,
        Method::Islands,
        Method::Hybrid,
        Method::Tandem,
    ];

    /// The method's name (`ga`, `smc`, `sosmc`, `rjmcmc`, `islands`, `hybrid`, `tandem`).
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Ga => "ga",
            Self::Smc => "smc",
            Self::Sosmc => "sosmc",
            Self::Rjmcmc => "rjmcmc",
            Self::Islands => "islands",
            Self::Hybrid => "hybrid",
            Self::Tandem => "tandem",
        }
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Method {
    type Err = ExperimentError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|m| m.name() == s.trim().to_ascii_lowercase())
            .ok_or_else(|| ExperimentError::UnknownMethod(s.to_string()))
    }
}

/// A method's parameters and its own budget, if the file gives one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MethodConfig {
    /// The parameters.
    pub params: MethodParams,
    /// The method's budget (replaces the experiment's).
    pub budget: Option<Budget>,
}

/// How to load an experiment file.
#[derive(Clone, Debug, Default)]
pub struct LoadOptions {
    /// The data directory `${data}` stands for (overrides the file's `data`).
    pub data: Option<PathBuf>,
}

impl LoadOptions {
    /// Options with the data directory from the `SHAPEGEN_DATA` environment
    /// variable, if set.
    #[must_use]
    pub fn from_env() -> Self {
        Self {
            data: std::env::var_os("SHAPEGEN_DATA").map(PathBuf::from),
        }
    }
}

/// A loaded experiment: its problem (generator + scene + score) is built and
/// its targets are loaded.
pub struct Experiment {
    /// The files the experiment reads (the experiment file first, if any).
    inputs: Vec<PathBuf>,
    name: String,
    description: String,
    generator: String,
    seed: u64,
    default_method: Method,
    optimum: Option<f64>,
    budget: Option<Budget>,
    methods: BTreeMap<Method, MethodConfig>,
    warnings: Vec<String>,
    problem: Box<dyn Problem>,
    /// The learned prior in use ([`Experiment::use_prior`]), if any.
    prior: Option<PathBuf>,
}

impl fmt::Debug for Experiment {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Experiment")
            .field("name", &self.name)
            .field("generator", &self.generator)
            .field("scene", &self.problem.describe())
            .field("methods", &self.methods)
            .finish_non_exhaustive()
    }
}

impl Experiment {
    /// Loads an experiment file (see the [module docs](self) for the format)
    /// naming one of the built-in generators ([`Registry::builtin`]).
    pub fn load(path: &Path, options: &LoadOptions) -> Result<Self, ExperimentError> {
        Self::load_with(path, &Registry::builtin(), options)
    }

    /// Loads an experiment file whose generator is one of `registry`'s
    /// (e.g. the built-ins plus a program's own).
    pub fn load_with(
        path: &Path,
        registry: &Registry,
        options: &LoadOptions,
    ) -> Result<Self, ExperimentError> {
        check_regular_file(path).map_err(|why| ExperimentError::NotAFile {
            path: path.to_path_buf(),
            why,
        })?;
        let text = std::fs::read_to_string(path).map_err(|source| ExperimentError::Read {
            path: path.to_path_buf(),
            source,
        })?;
        let base = path.parent().unwrap_or(Path::new("."));
        let stem = path
            .file_stem()
            .map_or_else(|| "experiment".into(), |s| s.to_string_lossy().into_owned());
        let mut experiment = Self::from_toml_with(
            &text,
            &path.display().to_string(),
            base,
            &stem,
            registry,
            options,
        )?;
        experiment.inputs.insert(0, path.to_path_buf());
        Ok(experiment)
    }

    /// Parses an experiment from TOML `text` naming a built-in generator;
    /// `file` names it in errors, relative paths resolve against `base`,
    /// `default_name` is used when the file has no `name`.
    pub fn from_toml(
        text: &str,
        file: &str,
        base: &Path,
        default_name: &str,
        options: &LoadOptions,
    ) -> Result<Self, ExperimentError> {
        Self::from_toml_with(
            text,
            file,
            base,
            default_name,
            &Registry::builtin(),
            options,
        )
    }

    /// [`from_toml`](Self::from_toml) with the generators of `registry`.
    pub fn from_toml_with(
        text: &str,
        file: &str,
        base: &Path,
        default_name: &str,
        registry: &Registry,
        options: &LoadOptions,
    ) -> Result<Self, ExperimentError> {
        let input = resolve::Input {
            text,
            file,
            base,
            default_name,
        };
        resolve::experiment(&input, registry, options)
    }

    /// The embedded default experiment ([`BUILTIN`]); needs no files.
    #[must_use]
    pub fn builtin() -> Self {
        Self::from_toml(
            BUILTIN,
            "<built-in>",
            Path::new("."),
            "default",
            &LoadOptions::default(),
        )
        .expect("the built-in experiment is valid")
    }

    /// The experiment's name.
    #[must_use]
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Its description (may be empty).
    #[must_use]
    pub fn description(&self) -> &str {
        &self.description
    }

    /// The generator's name in the file and the registry (`spaceship`, `tree_v2`, ...).
    #[must_use]
    pub fn generator(&self) -> &str {
        &self.generator
    }

    /// One line about the scene (grid or images, target size).
    #[must_use]
    pub fn scene(&self) -> String {
        self.problem.describe()
    }

    /// The file's seed.
    #[must_use]
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// The method to use when none is asked for.
    #[must_use]
    pub fn default_method(&self) -> Method {
        self.default_method
    }

    /// The best reachable score, if the file states it.
    #[must_use]
    pub fn optimum(&self) -> Option<f64> {
        self.optimum
    }

    /// Every file the experiment reads: the experiment file (when loaded
    /// from one), target meshes and images, shape meshes. A run must not
    /// write over any of them.
    #[must_use]
    pub fn inputs(&self) -> &[PathBuf] {
        &self.inputs
    }

    /// The names of the files [`write_model`](Self::write_model) writes.
    #[must_use]
    pub fn model_files(&self) -> Vec<String> {
        self.problem.model_files()
    }

    /// What the scores depend on, part by part (generator and limits,
    /// shapes, scene, score): a name and a 16-hex-digit fingerprint each. A
    /// checkpoint stores them so that a resume against a changed target,
    /// grid, camera, weight, mesh or limit is refused.
    #[must_use]
    pub fn fingerprint(&self) -> BTreeMap<String, String> {
        self.problem
            .fingerprint()
            .into_iter()
            .map(|(k, v)| (k.to_string(), format!("{v:016x}")))
            .collect()
    }

    /// Problems worth telling the user (e.g. a target that is not watertight).
    #[must_use]
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// Every warning for running `methods`: the experiment's own
    /// ([`warnings`](Self::warnings)), then one for each distinct method
    /// that regrows subtrees ([`MethodParams::regrows_subtrees`]) on limits
    /// without a `max_len`.
    #[must_use]
    pub fn warnings_for(&self, methods: &[Method]) -> Vec<String> {
        let mut w = self.warnings.clone();
        let mut seen: Vec<Method> = Vec::new();
        for &method in methods {
            if !seen.contains(&method) {
                seen.push(method);
                w.extend(self.method_warning(method));
            }
        }
        w
    }

    /// The warning for `method` on limits without a `max_len`, if it
    /// regrows subtrees.
    fn method_warning(&self, method: Method) -> Option<String> {
        if self.graph().limits().max_len.is_none() && self.method(method).params.regrows_subtrees()
        {
            return Some(format!(
                "no max_len in [limits] (nor in the generator): {method}'s jumps regrow subtrees from \
                 the generator's own distribution, which can propose models of thousands of genes, \
                 slow to score (RJMCMC on a spaceship experiment made 50 times fewer evaluations \
                 without one than with max_len = 100); \
                 set [limits] max_len to a few times the length you expect"
            ));
        }
        None
    }

    /// The generator graph, with the experiment's limits.
    #[must_use]
    pub fn graph(&self) -> &Graph {
        self.problem.graph()
    }

    /// Grows and alters models with the probabilities of a learned pdf
    /// (`shapegen design export`, [`LearnedPdf::prior_graph`](crate::design::LearnedPdf::prior_graph)):
    /// the optimizers' initial individuals and grow moves then follow the
    /// style the user designed, while every model stays one the generator
    /// can derive (the prior keeps the graph's nodes, supports and limits,
    /// so saved chromosomes are the same generator's). The prior file
    /// becomes one of the experiment's [`inputs`](Self::inputs).
    pub fn use_prior(
        &mut self,
        pdf: &crate::design::LearnedPdf,
        path: &Path,
    ) -> Result<(), ExperimentError> {
        let graph = pdf
            .prior_graph(self.graph())
            .map_err(|e| ExperimentError::Prior {
                path: path.to_path_buf(),
                source: Box::new(e),
            })?;
        self.problem.set_graph(graph);
        self.inputs.push(path.to_path_buf());
        self.prior = Some(path.to_path_buf());
        Ok(())
    }

    /// The learned prior file in use, if any.
    #[must_use]
    pub fn prior(&self) -> Option<&Path> {
        self.prior.as_deref()
    }

    /// The configuration of `method` (the paper's spaceship presets if the
    /// file has no table for it).
    #[must_use]
    pub fn method(&self, method: Method) -> MethodConfig {
        self.methods[&method]
    }

    /// The budget of `method`: its own, else the experiment's.
    #[must_use]
    pub fn budget(&self, method: Method) -> Option<Budget> {
        self.methods[&method].budget.or(self.budget)
    }

    /// Runs `method` from the start, or from `resume`, until `budget` is spent.
    pub fn run(
        &self,
        method: Method,
        budget: &Budget,
        seed: u64,
        resume: Option<&Checkpoint>,
        observer: &mut dyn Observer,
    ) -> Result<RunResult, ExperimentError> {
        let config = self.method(method);
        Ok(self
            .problem
            .run(&config.params, budget, seed, resume, observer)?)
    }

    /// The fitness of `chromosome`.
    #[must_use]
    pub fn evaluate(&self, chromosome: &Chromosome) -> f64 {
        self.problem.evaluate(chromosome)
    }

    /// Per target of the file (in its order; the built-in ship is one): IoU,
    /// precision and recall of the model of `chromosome` against it. Unlike
    /// the fitness these do not saturate near a perfect fit.
    #[must_use]
    pub fn quality(&self, chromosome: &Chromosome) -> Vec<Quality> {
        self.problem.quality(chromosome)
    }

    /// Turns stored chromosome data (e.g. a `best.json`) into a chromosome of
    /// this experiment's generator, refusing anything else; `path` names the
    /// file in the error.
    pub fn chromosome(
        &self,
        data: &ChromosomeData,
        path: &Path,
    ) -> Result<Chromosome, ExperimentError> {
        Chromosome::from_data(self.graph(), data).map_err(|source| ExperimentError::Chromosome {
            path: path.to_path_buf(),
            source: Box::new(source),
        })
    }

    /// Writes the model of `chromosome` into `dir`: `best.obj` (with the
    /// meshes it is scored with, replacements included), plus `overlay.png`
    /// (image targets) or `target.obj` and `slice_x/y/z.png` (volume
    /// targets), each atomically. Returns the files written.
    pub fn write_model(
        &self,
        chromosome: &Chromosome,
        dir: &Path,
    ) -> Result<Vec<PathBuf>, ExperimentError> {
        std::fs::create_dir_all(dir).map_err(|e| ExperimentError::write(dir, e))?;
        self.problem.write_model(chromosome, dir)
    }
}

impl crate::gallery::Models for Experiment {
    fn graph(&self) -> &Graph {
        self.problem.graph()
    }
    fn meshes(&self) -> &crate::score::ShapeMeshes {
        self.problem.meshes()
    }
    fn instances(&self, chromosome: &Chromosome) -> Vec<crate::express::Instance> {
        self.problem.instances(chromosome)
    }
}

/// Whether `path` is a regular file that can be read: a directory, a FIFO
/// or a device is refused with words that say so (reading one would fail
/// or block forever).
pub fn check_regular_file(path: &Path) -> Result<(), String> {
    match std::fs::metadata(path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            Err(format!("no such file: {}", path.display()))
        }
        Err(e) => Err(format!("cannot read {}: {e}", path.display())),
        Ok(m) if m.is_dir() => Err(format!("{} is a directory, not a file", path.display())),
        Ok(m) if !m.is_file() => Err(format!(
            "{} is not a regular file (a pipe, socket or device)",
            path.display()
        )),
        Ok(_) => Ok(()),
    }
}

#[cfg(test)]
mod tests;
