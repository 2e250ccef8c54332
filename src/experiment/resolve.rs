//! From a parsed file to a runnable [`Experiment`]: paths, meshes, images,
//! cameras, scores, limits and methods, each checked with its key and line.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Duration;

use toml::Spanned;

use super::error::Source;
use super::file::{
    BudgetFile, DelayedRejectionFile, EdgeMatchFile, ExperimentFile, ImageFile, InsideFile,
    OutsideCountFile, ScoreForm, VolumeFile,
};
use super::problem::{ModelProblem, Problem};
use super::{Experiment, ExperimentError, LoadOptions, Method, MethodConfig, MethodParams};
use crate::demo::spaceship_target;
use crate::express::Generator;
use crate::glam::{DVec3, UVec3, Vec3};
use crate::graph::{Graph, Limits};
use crate::ops::{CrossoverConfig, EdgeMatch, InitLength, MutationSplit};
use crate::optimize::{Budget, DelayedRejection, GaParams, RjmcmcParams, SmcParams};
use crate::scenes::{GridCity, SpaceFillingCity, Spaceship, TreeV1, TreeV2};
use crate::score::Grid;
use crate::score::camera::Camera;
use crate::score::image::ImageTarget;
use crate::score::mesh::Mesh;
use crate::score::obj::ShapeMeshes;
use crate::score::score::{ImageScore, ImageTargets, ModelFitness, OverlapCount, VolumeScore};
use crate::score::solid::Inside;
use crate::score::volume::{OutsideCount, VolumeScene, VolumeTarget};

/// The generators an experiment may name.
const GENERATORS: &str = "spaceship, tree_v1, tree_v2, space_filling_city, grid_city";

/// Everything resolution needs to report errors and find files.
struct Ctx<'a> {
    src: Source<'a>,
    base: &'a Path,
    data: Option<PathBuf>,
}

impl Ctx<'_> {
    fn err<T>(
        &self,
        key: &str,
        spanned: &Spanned<T>,
        message: impl Into<String>,
    ) -> ExperimentError {
        self.src.error(key, spanned.span(), message)
    }

    /// Resolves a path of the file: `${data}` prefix, then relative to the file.
    fn path(&self, key: &str, value: &Spanned<String>) -> Result<PathBuf, ExperimentError> {
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
        if !path.is_file() {
            return Err(self.err(key, value, format!("no such file: {}", path.display())));
        }
        Ok(path)
    }
}

/// Parses and resolves an experiment.
pub(super) fn experiment(
    text: &str,
    file: &str,
    base: &Path,
    default_name: &str,
    options: &LoadOptions,
) -> Result<Experiment, ExperimentError> {
    let src = Source { name: file, text };
    let parsed: ExperimentFile = match toml::de::Deserializer::parse(text) {
        Err(e) => return Err(src.error("", e.span().unwrap_or(0..0), e.message())),
        Ok(de) => serde_path_to_error::deserialize(de).map_err(|e| {
            // `Spanned` values add a private segment to the path.
            let key = e
                .path()
                .to_string()
                .split('.')
                .filter(|k| !k.starts_with("$__") && !k.is_empty())
                .collect::<Vec<_>>()
                .join(".");
            let inner = e.into_inner();
            src.error(&key, inner.span().unwrap_or(0..0), inner.message())
        })?,
    };
    let data = match (&options.data, &parsed.data) {
        (Some(d), _) => Some(d.clone()),
        (None, Some(d)) => Some(base.join(d.get_ref())),
        (None, None) => None,
    };
    let ctx = Ctx { src, base, data };

    let method = match &parsed.method {
        None => Method::Ga,
        Some(m) => m
            .get_ref()
            .parse()
            .map_err(|e: ExperimentError| ctx.err("method", m, e.to_string()))?,
    };
    let budget = parsed
        .budget
        .as_ref()
        .map(|b| budget(&ctx, "budget", b))
        .transpose()?;
    let methods = methods(&ctx, &parsed)?;
    let (problem, warnings) = problem(&ctx, &parsed)?;
    Ok(Experiment {
        name: parsed
            .name
            .clone()
            .unwrap_or_else(|| default_name.to_string()),
        description: parsed.description.clone().unwrap_or_default(),
        generator: parsed.generator.get_ref().clone(),
        seed: parsed.seed.unwrap_or(1),
        default_method: method,
        optimum: parsed.optimum,
        budget,
        methods,
        warnings,
        problem,
    })
}

fn budget(ctx: &Ctx<'_>, key: &str, b: &Spanned<BudgetFile>) -> Result<Budget, ExperimentError> {
    let f = b.get_ref();
    let mut out = Budget::default();
    if let Some(s) = f.seconds {
        if !(s > 0.0 && s.is_finite()) {
            return Err(ctx.err(key, b, format!("seconds must be > 0, got {s}")));
        }
        out.wall_time = Some(Duration::from_secs_f64(s));
    }
    out.evaluations = f.evaluations;
    out.generations = f.generations;
    if out.is_unbounded() {
        return Err(ctx.err(key, b, "give seconds, evaluations or generations"));
    }
    Ok(out)
}

fn methods(
    ctx: &Ctx<'_>,
    f: &ExperimentFile,
) -> Result<BTreeMap<Method, MethodConfig>, ExperimentError> {
    let mut out = BTreeMap::new();
    let ga = match &f.ga {
        None => MethodConfig {
            params: MethodParams::Ga(GaParams::paper_spaceship()),
            budget: None,
        },
        Some(t) => {
            let g = t.get_ref();
            let params = GaParams {
                population: g.population,
                elites: g.elites,
                init: InitLength::Around { l0: g.init_length },
                mutation_rate: g.mutation_rate,
                mutation_split: MutationSplit::new(g.split.grow, g.split.cut, g.split.alter),
                tournament: g.tournament.unwrap_or(10),
                crossover: CrossoverConfig {
                    max_retries: g.max_retries.unwrap_or(3),
                    edge_match: match g.crossover {
                        None | Some(EdgeMatchFile::Strict) => EdgeMatch::Strict,
                        Some(EdgeMatchFile::ChildType) => EdgeMatch::ChildType,
                    },
                },
                elite_dedup: g.elite_dedup.unwrap_or(false),
                ..GaParams::paper_spaceship()
            };
            let problems = params.problems();
            if !problems.is_empty() {
                return Err(ctx.err("ga", t, problems.join("; ")));
            }
            MethodConfig {
                params: MethodParams::Ga(params),
                budget: g
                    .budget
                    .as_ref()
                    .map(|b| budget(ctx, "ga.budget", b))
                    .transpose()?,
            }
        }
    };
    out.insert(Method::Ga, ga);
    for (method, table, preset) in [
        (
            Method::Smc,
            &f.smc,
            SmcParams::paper as fn(usize) -> SmcParams,
        ),
        (Method::Sosmc, &f.sosmc, SmcParams::paper_sosmc),
    ] {
        let config = match table {
            None => MethodConfig {
                params: MethodParams::Smc(preset(500)),
                budget: None,
            },
            Some(t) => {
                let s = t.get_ref();
                let params = preset(s.particles);
                let problems = params.problems();
                if !problems.is_empty() {
                    return Err(ctx.err(method.name(), t, problems.join("; ")));
                }
                let key = format!("{method}.budget");
                MethodConfig {
                    params: MethodParams::Smc(params),
                    budget: s
                        .budget
                        .as_ref()
                        .map(|b| budget(ctx, &key, b))
                        .transpose()?,
                }
            }
        };
        out.insert(method, config);
    }
    let rj = match &f.rjmcmc {
        None => MethodConfig {
            params: MethodParams::Rjmcmc(RjmcmcParams::paper(70, InitLength::Around { l0: 50 })),
            budget: None,
        },
        Some(t) => {
            let r = t.get_ref();
            let mut params =
                RjmcmcParams::paper(r.chains, InitLength::Around { l0: r.init_length });
            if let Some(p) = r.jump_probability {
                params.jump_probability = p;
            }
            if let Some(a) = r.annealing {
                params.annealing = (a != 1.0).then_some(a);
            }
            params.delayed_rejection = match r.delayed_rejection {
                None | Some(DelayedRejectionFile::Off) => DelayedRejection::Off,
                Some(DelayedRejectionFile::Exact) => DelayedRejection::Exact,
                Some(DelayedRejectionFile::ApproxAlter) => DelayedRejection::ApproxAlter,
            };
            let problems = params.problems();
            if !problems.is_empty() {
                return Err(ctx.err("rjmcmc", t, problems.join("; ")));
            }
            MethodConfig {
                params: MethodParams::Rjmcmc(params),
                budget: r
                    .budget
                    .as_ref()
                    .map(|b| budget(ctx, "rjmcmc.budget", b))
                    .transpose()?,
            }
        }
    };
    out.insert(Method::Rjmcmc, rj);
    Ok(out)
}

/// Builds the generator's problem on the file's scene.
fn problem(
    ctx: &Ctx<'_>,
    f: &ExperimentFile,
) -> Result<(Box<dyn Problem>, Vec<String>), ExperimentError> {
    match f.generator.get_ref().as_str() {
        "spaceship" => with_generator(ctx, f, Spaceship),
        "tree_v1" => with_generator(ctx, f, TreeV1),
        "tree_v2" => with_generator(ctx, f, TreeV2),
        "space_filling_city" => with_generator(ctx, f, SpaceFillingCity),
        "grid_city" => with_generator(ctx, f, GridCity),
        other => Err(ctx.err(
            "generator",
            &f.generator,
            format!("unknown generator `{other}`: use one of {GENERATORS}"),
        )),
    }
}

fn with_generator<G>(
    ctx: &Ctx<'_>,
    f: &ExperimentFile,
    generator: G,
) -> Result<(Box<dyn Problem>, Vec<String>), ExperimentError>
where
    G: Generator + Copy + Send + 'static,
    G::State: Send,
{
    let own = *generator.graph().limits();
    let limits = match f.limits.as_ref().map(Spanned::get_ref) {
        None => own,
        Some(l) => Limits {
            min_len: l.min_len.unwrap_or(own.min_len),
            max_len: l.max_len.or(own.max_len),
            max_depth: l.max_depth.or(own.max_depth),
        },
    };
    let graph = Graph::new(generator.graph().spec().clone().with_limits(limits)).map_err(|e| {
        let span = f.limits.as_ref().map_or(0..0, Spanned::span);
        ctx.src.error(
            "limits",
            span,
            format!("the limits do not fit the generator: {e}"),
        )
    })?;
    let shapes = shapes(ctx, f, &generator)?;
    let score = f.score.get_ref();
    let score_err = |m: String| ctx.err("score", &f.score, m);
    check_weights(&[
        score.good,
        score.bad,
        score.length,
        score.overlap,
        score.self_weight,
    ])
    .map_err(score_err)?;
    match (&f.volume, &f.image) {
        (Some(v), None) => {
            let (scene, targets, warnings) = volume_scene(ctx, v)?;
            let score = match score.form {
                ScoreForm::Normalized => VolumeScore::Normalized {
                    w_good: score.good.unwrap_or(1.0),
                    w_bad: score.bad.unwrap_or(1.0),
                    w_length: score.length.unwrap_or(0.0),
                    separate_overlap: score.overlap,
                },
                ScoreForm::Paper => VolumeScore::Linear {
                    w_self: score.self_weight.unwrap_or(0.0),
                    overlap: OverlapCount::Cells,
                },
            };
            let fitness = ModelFitness::new(generator, scene, &shapes, score)
                .map_err(|e| ctx.err("shapes", &f.generator, e.to_string()))?
                .with_limits(limits);
            let names = (0..targets.len())
                .map(|i| format!("target_{i}").into())
                .collect();
            let meshes = targets.into_iter().map(|t| t.mesh).collect();
            let problem = ModelProblem {
                graph,
                generator,
                shapes,
                fitness,
                target_meshes: Some(ShapeMeshes::new(names, meshes)?),
            };
            Ok((Box::new(problem), warnings))
        }
        (None, Some(i)) => {
            let scene = image_scene(ctx, i)?;
            if score.overlap.is_some() || score.self_weight.is_some() {
                return Err(score_err(
                    "`overlap` and `self` apply to volume scenes only".into(),
                ));
            }
            let score = match score.form {
                ScoreForm::Normalized => ImageScore::Normalized {
                    w_good: score.good.unwrap_or(1.0),
                    w_bad: score.bad.unwrap_or(1.0),
                    w_length: score.length.unwrap_or(0.0),
                },
                ScoreForm::Paper => ImageScore::Linear,
            };
            let fitness = ModelFitness::new(generator, scene, &shapes, score)
                .map_err(|e| ctx.err("shapes", &f.generator, e.to_string()))?
                .with_limits(limits);
            let problem = ModelProblem {
                graph,
                generator,
                shapes,
                fitness,
                target_meshes: None,
            };
            Ok((Box::new(problem), Vec::new()))
        }
        (Some(v), Some(_)) => Err(ctx.err(
            "image",
            v,
            "give either a [volume] or an [image] scene, not both",
        )),
        (None, None) => {
            Err(ctx
                .src
                .error("", 0..0, "no scene: add a [volume] or an [image] table"))
        }
    }
}

fn check_weights(weights: &[Option<f64>]) -> Result<(), String> {
    match weights.iter().flatten().find(|w| !w.is_finite()) {
        Some(w) => Err(format!("weights must be finite, got {w}")),
        None => Ok(()),
    }
}

/// The built-in meshes of the generator's shapes, with the file's replacements.
fn shapes<G: Generator>(
    ctx: &Ctx<'_>,
    f: &ExperimentFile,
    generator: &G,
) -> Result<ShapeMeshes, ExperimentError> {
    let mut shapes = ShapeMeshes::builtin(generator)?;
    for (name, s) in &f.shapes {
        let key = format!("shapes.{name}.mesh");
        if !generator.shapes().iter().any(|n| n == name) {
            let known: Vec<&str> = generator.shapes().iter().map(|s| s.as_ref()).collect();
            return Err(ctx.err(
                &format!("shapes.{name}"),
                &s.mesh,
                format!(
                    "the generator has no shape `{name}` (its shapes: {})",
                    known.join(", ")
                ),
            ));
        }
        let path = ctx.path(&key, &s.mesh)?;
        let mesh = Mesh::load_obj(&path).map_err(|e| ctx.err(&key, &s.mesh, e.to_string()))?;
        let mesh = if s.normalize { mesh.normalized() } else { mesh };
        shapes
            .set(name, mesh)
            .map_err(|e| ctx.err(&key, &s.mesh, e.to_string()))?;
    }
    Ok(shapes)
}

fn volume_scene(
    ctx: &Ctx<'_>,
    v: &Spanned<VolumeFile>,
) -> Result<(VolumeScene, Vec<VolumeTarget>, Vec<String>), ExperimentError> {
    let vf = v.get_ref();
    let grid = Grid::new(
        Vec3::from_array(vf.min),
        Vec3::from_array(vf.max),
        UVec3::from_array(vf.resolution),
    )
    .map_err(|e| ctx.err("volume", v, e.to_string()))?;
    if vf.targets.is_empty() {
        return Err(ctx.err("volume.targets", v, "give at least one [[volume.targets]]"));
    }
    let mut targets = Vec::new();
    for (i, t) in vf.targets.iter().enumerate() {
        let key = format!("volume.targets[{i}]");
        let tf = t.get_ref();
        let fill = tf.fill.unwrap_or(1.0);
        let outside = tf.outside.unwrap_or(0.0);
        let inside = match tf.inside {
            None | Some(InsideFile::Parity) => Inside::Parity,
            Some(InsideFile::Winding) => Inside::WindingNumber,
        };
        if !(fill.is_finite() && outside.is_finite()) {
            return Err(ctx.err(&key, t, "fill and outside must be finite"));
        }
        match (&tf.mesh, &tf.builtin) {
            (Some(mesh), None) => {
                let key = format!("{key}.mesh");
                let path = ctx.path(&key, mesh)?;
                let m = Mesh::load_obj(&path).map_err(|e| ctx.err(&key, mesh, e.to_string()))?;
                targets.push(VolumeTarget {
                    name: path.display().to_string(),
                    mesh: m,
                    fill,
                    outside,
                    inside,
                });
            }
            (None, Some(b)) if b.get_ref() == "ship" => {
                targets.extend(spaceship_target().into_iter().map(|t| VolumeTarget {
                    fill,
                    outside,
                    inside,
                    ..t
                }));
            }
            (None, Some(b)) => {
                return Err(ctx.err(
                    &format!("{key}.builtin"),
                    b,
                    format!(
                        "unknown built-in target `{}`: the only one is `ship`",
                        b.get_ref()
                    ),
                ));
            }
            _ => return Err(ctx.err(&key, t, "give exactly one of `mesh` and `builtin`")),
        }
    }
    let scene = VolumeScene::new(grid, &targets)
        .map_err(|e| ctx.err("volume.targets", v, e.to_string()))?
        .with_outside_count(match vf.outside_count {
            None | Some(OutsideCountFile::Solid) => OutsideCount::Solid,
            Some(OutsideCountFile::Aabb) => OutsideCount::Aabb,
        });
    let warnings = scene.warnings().to_vec();
    Ok((scene, targets, warnings))
}

fn image_scene(ctx: &Ctx<'_>, i: &Spanned<ImageFile>) -> Result<ImageTargets, ExperimentError> {
    let f = i.get_ref();
    let size = (f.width.unwrap_or(800), f.height.unwrap_or(600));
    if f.targets.is_empty() {
        return Err(ctx.err("image.targets", i, "give at least one [[image.targets]]"));
    }
    let mut targets = Vec::new();
    for (k, t) in f.targets.iter().enumerate() {
        let key = format!("image.targets[{k}]");
        let tf = t.get_ref();
        let c = tf.camera.get_ref();
        let camera = Camera::orbit(
            c.phi,
            c.theta,
            c.r,
            DVec3::from_array(c.look_at),
            c.fov.unwrap_or(60.0).to_radians(),
            c.near.unwrap_or(0.1),
            c.far.unwrap_or(100.0),
            size,
        )
        .map_err(|e| ctx.err(&format!("{key}.camera"), &tf.camera, e.to_string()))?;
        let target = match (&tf.png, &tf.pfm) {
            (Some(png), None) => {
                let key = format!("{key}.png");
                let path = ctx.path(&key, png)?;
                let (w_t, w_b) = (tf.target.unwrap_or(1.0), tf.background.unwrap_or(-1.0));
                if !(w_t.is_finite() && w_b.is_finite()) {
                    return Err(ctx.err(&key, t, "target and background must be finite"));
                }
                ImageTarget::from_png(&path, camera, w_t, w_b)
                    .map_err(|e| ctx.err(&key, png, e.to_string()))?
            }
            (None, Some(pfm)) => {
                let key = format!("{key}.pfm");
                if tf.target.is_some() || tf.background.is_some() {
                    return Err(ctx.err(
                        &key,
                        pfm,
                        "a float image holds its own weights: drop `target` and `background`",
                    ));
                }
                let path = ctx.path(&key, pfm)?;
                ImageTarget::from_pfm(&path, camera)
                    .map_err(|e| ctx.err(&key, pfm, e.to_string()))?
            }
            _ => return Err(ctx.err(&key, t, "give exactly one of `png` and `pfm`")),
        };
        targets.push(target);
    }
    ImageTargets::new(targets).map_err(|e| ctx.err("image.targets", i, e.to_string()))
}
