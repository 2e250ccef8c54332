//! From a parsed file to a runnable [`Experiment`], one table at a time (as
//! ripgrep turns its low-level arguments into high-level ones): each
//! submodule resolves one part and reports mistakes with their key and line.
//!
//! - [`methods`]: `[ga]`, `[smc]`, `[sosmc]`, `[rjmcmc]` and budgets;
//! - [`shapes`]: the generator's shape meshes and `[shapes.*]` replacements;
//! - [`score`]: `[score]` as a volume or image score;
//! - [`volume`] and [`image`]: the scene and its targets.

mod image;
mod methods;
mod score;
mod shapes;
mod volume;

use std::path::{Path, PathBuf};

use toml::Spanned;

use super::error::Source;
use super::file::ExperimentFile;
use super::problem::{Problem, SceneSetup};
use super::{Experiment, ExperimentError, LoadOptions, Method};
use crate::graph::{Graph, Limits};
use crate::registry::{Registered, Registry};

/// Everything resolution needs to report errors and find files.
pub(super) struct Ctx<'a> {
    src: Source<'a>,
    base: &'a Path,
    data: Option<PathBuf>,
    /// Every file the experiment reads, as resolved.
    inputs: std::cell::RefCell<Vec<PathBuf>>,
}

impl Ctx<'_> {
    /// An error at `spanned`'s place in the file.
    pub fn err<T>(
        &self,
        key: &str,
        spanned: &Spanned<T>,
        message: impl Into<String>,
    ) -> ExperimentError {
        self.src.error(key, spanned.span(), message)
    }

    /// Resolves a path of the file: `${data}` prefix, then relative to the file.
    pub fn path(&self, key: &str, value: &Spanned<String>) -> Result<PathBuf, ExperimentError> {
        let raw = value.get_ref();
        let path = if let Some(rest) = raw.strip_prefix("${data}") {
            let Some(data) = &self.data else {
                return Err(self.err(
                    key,
                    value,
                    "`${data}` is used but no data directory is set: add `data = \"...\"` to the file, pass --data or set SHAPEGEN_DATA",
                ));
            };
            // The data directory is already resolved (against the file or the cwd).
            data.join(rest.trim_start_matches(['/', '\\']))
        } else if Path::new(raw).is_relative() {
            self.base.join(raw)
        } else {
            PathBuf::from(raw)
        };
        if let Err(why) = super::check_regular_file(&path) {
            return Err(self.err(key, value, why));
        }
        self.inputs.borrow_mut().push(path.clone());
        Ok(path)
    }
}

/// What [`experiment`] reads besides the text.
pub(super) struct Input<'a> {
    /// The text of the file.
    pub text: &'a str,
    /// The file's name in errors.
    pub file: &'a str,
    /// The folder relative paths resolve against.
    pub base: &'a Path,
    /// The name when the file gives none.
    pub default_name: &'a str,
}

/// Parses and resolves an experiment; its generator comes from `registry`.
pub(super) fn experiment(
    input: &Input<'_>,
    registry: &Registry,
    options: &LoadOptions,
) -> Result<Experiment, ExperimentError> {
    let src = Source {
        name: input.file,
        text: input.text,
    };
    let parsed = parse(&src)?;
    let data = match (&options.data, &parsed.data) {
        (Some(d), _) => Some(d.clone()),
        (None, Some(d)) => Some(input.base.join(d.get_ref())),
        (None, None) => None,
    };
    let ctx = Ctx {
        src,
        base: input.base,
        data,
        inputs: std::cell::RefCell::new(Vec::new()),
    };
    let default_method = match &parsed.method {
        None => Method::DEFAULT,
        Some(m) => m
            .get_ref()
            .parse()
            .map_err(|e: ExperimentError| ctx.err("method", m, e.to_string()))?,
    };
    let budget = parsed
        .budget
        .as_ref()
        .map(|b| methods::budget(&ctx, "budget", b))
        .transpose()?;
    if let Some(o) = parsed.optimum
        && !o.is_finite()
    {
        return Err(ctx
            .src
            .error("optimum", 0..0, format!("must be a finite number, got {o}")));
    }
    let methods = methods::from_file(&ctx, &parsed)?;
    let generator = generator(&ctx, &parsed, registry)?;
    let (problem, warnings) = problem(&ctx, &parsed, generator)?;
    let inputs = ctx.inputs.take();
    let mut experiment = Experiment {
        inputs,
        name: parsed
            .name
            .clone()
            .unwrap_or_else(|| input.default_name.to_string()),
        description: parsed.description.clone().unwrap_or_default(),
        generator: parsed.generator.get_ref().clone(),
        seed: parsed.seed.unwrap_or(1),
        default_method,
        optimum: parsed.optimum,
        budget,
        methods,
        warnings,
        problem,
        prior: None,
    };
    if let Some(w) = unseen(&experiment) {
        experiment.warnings.push(w);
    }
    Ok(experiment)
}

/// Random models of the generator this many: if none is seen (covers a
/// cell of the grid, a pixel of a camera), the scene is likely misplaced.
const PROBES: u64 = 16;

/// A warning if none of [`PROBES`] random models (the GA's initial lengths,
/// a fixed seed) is seen by the scene: every model would score alike.
fn unseen(e: &Experiment) -> Option<String> {
    let crate::experiment::MethodParams::Ga(ga) = e.method(Method::Ga).params else {
        return None;
    };
    for k in 0..PROBES {
        let mut rng = crate::rng::stream(k, &[u64::from(u32::MAX)]);
        let c = crate::ops::random_individual(e.graph(), &ga.init, &mut rng).ok()?;
        if e.quality(&c).iter().any(|q| q.model > 0) {
            return None;
        }
    }
    Some(format!(
        "none of {PROBES} random models of `{}` is seen by the scene ({}): check that the grid or the cameras look at where the generator builds (it starts at the origin)",
        e.generator(),
        e.scene()
    ))
}

/// The dotted key of a TOML deserialization error's path (`ga.population`),
/// without the private segments `Spanned` values add.
pub(crate) fn toml_key(path: &serde_path_to_error::Path) -> String {
    path.to_string()
        .split('.')
        .filter(|k| !k.starts_with("$__") && !k.is_empty())
        .collect::<Vec<_>>()
        .join(".")
}

/// The TOML text as the file schema, with the key and line of any mistake.
fn parse(src: &Source<'_>) -> Result<ExperimentFile, ExperimentError> {
    match toml::de::Deserializer::parse(src.text) {
        Err(e) => Err(src.error("", e.span().unwrap_or(0..0), e.message())),
        Ok(de) => serde_path_to_error::deserialize(de).map_err(|e| {
            let key = toml_key(e.path());
            let inner = e.into_inner();
            src.error(&key, inner.span().unwrap_or(0..0), inner.message())
        }),
    }
}

/// The registered generator the file names.
fn generator<'r>(
    ctx: &Ctx<'_>,
    f: &ExperimentFile,
    registry: &'r Registry,
) -> Result<&'r dyn Registered, ExperimentError> {
    let name = f.generator.get_ref();
    registry.get(name).ok_or_else(|| {
        ctx.err(
            "generator",
            &f.generator,
            format!("unknown generator `{name}`: use one of {}", registry.list()),
        )
    })
}

/// The generator's graph with the file's `[limits]`.
fn graph(
    ctx: &Ctx<'_>,
    f: &ExperimentFile,
    generator: &dyn Registered,
) -> Result<Graph, ExperimentError> {
    let own = *generator.graph().limits();
    let limits = match f.limits.as_ref().map(Spanned::get_ref) {
        None => own,
        Some(l) => Limits {
            min_len: l.min_len.unwrap_or(own.min_len),
            max_len: l.max_len.or(own.max_len),
            max_depth: l.max_depth.or(own.max_depth),
        },
    };
    Graph::new(generator.graph().spec().clone().with_limits(limits)).map_err(|e| {
        let span = f.limits.as_ref().map_or(0..0, Spanned::span);
        ctx.src.error(
            "limits",
            span,
            format!("the limits do not fit the generator: {e}"),
        )
    })
}

/// The generator scored on the file's scene, and the scene's warnings.
fn problem(
    ctx: &Ctx<'_>,
    f: &ExperimentFile,
    generator: &dyn Registered,
) -> Result<(Box<dyn Problem>, Vec<String>), ExperimentError> {
    let graph = graph(ctx, f, generator)?;
    let shapes = shapes::from_file(ctx, f, generator.shapes())?;
    let weights = score::Weights::from_file(ctx, f)?;
    let (scene, warnings) = match (&f.volume, &f.image) {
        (Some(v), None) => {
            let (scene, targets, warnings) = volume::from_file(ctx, v, weights.is_paper())?;
            let score = weights.volume();
            (
                SceneSetup::Volume {
                    scene: Box::new(scene),
                    score,
                    targets,
                },
                warnings,
            )
        }
        (None, Some(i)) => {
            let scene = image::from_file(ctx, i, weights.is_paper())?;
            let score = weights.image(ctx, f)?;
            (SceneSetup::Image { scene, score }, Vec::new())
        }
        (Some(v), Some(_)) => {
            return Err(ctx.err(
                "image",
                v,
                "give either a [volume] or an [image] scene, not both",
            ));
        }
        (None, None) => {
            return Err(ctx
                .src
                .error("", 0..0, "no scene: add a [volume] or an [image] table"));
        }
    };
    let warnings: Vec<String> = weights.warnings().into_iter().chain(warnings).collect();
    let problem = generator
        .problem(graph, shapes, scene)
        .map_err(|e| ctx.err("shapes", &f.generator, e.to_string()))?;
    Ok((problem, warnings))
}
