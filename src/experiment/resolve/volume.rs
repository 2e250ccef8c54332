//! `[volume]`: the grid and its targets (meshes or the built-in ship),
//! each placed by its `scale`, `rotate`, `translate` and `fit`.

use toml::Spanned;

use super::Ctx;
use crate::demo::spaceship_target;
use crate::experiment::ExperimentError;
use crate::experiment::file::{
    FitFile, InsideFile, OutsideCountFile, ScaleFile, VolumeFile, VolumeTargetFile,
};
use crate::glam::{UVec3, Vec3};
use crate::score::Inside;
use crate::score::{Grid, Mesh, Placement, ScoreError, ShapeMeshes};
use crate::score::{OutsideCount, VolumeScene, VolumeScratch, VolumeTarget};

/// The scene, its target meshes (as placed, for `target.obj`) and warnings.
/// `paper`: the score is the paper's linear form, which reads each target's
/// `fill` and `outside` (the normalized form counts target cells and would
/// ignore them: giving them is an error).
pub(super) fn from_file(
    ctx: &Ctx<'_>,
    v: &Spanned<VolumeFile>,
    paper: bool,
) -> Result<(VolumeScene, ShapeMeshes, Vec<String>), ExperimentError> {
    let vf = v.get_ref();
    let grid = Grid::new(
        Vec3::from_array(vf.min.0),
        Vec3::from_array(vf.max.0),
        UVec3::from_array(vf.resolution.0),
    )
    .map_err(|e| ctx.err("volume", v, e.to_string()))?;
    if vf.targets.is_empty() {
        return Err(ctx.err("volume.targets", v, "give at least one [[volume.targets]]"));
    }
    for (i, t) in vf.targets.iter().enumerate() {
        let tf = t.get_ref();
        if !paper && (tf.fill.is_some() || tf.outside.is_some()) {
            return Err(ctx.err(
                &format!("volume.targets[{i}]"),
                t,
                "`fill` and `outside` weigh cells in the paper form only; the normalized form counts target cells (weights `good`, `bad` in [score]): drop them or use form = \"paper\"",
            ));
        }
    }
    if paper
        && vf
            .targets
            .iter()
            .all(|t| t.get_ref().fill == Some(0.0) && t.get_ref().outside.unwrap_or(0.0) == 0.0)
    {
        return Err(ctx.err(
            "volume.targets",
            v,
            "every target weight (fill, outside) is 0: every model would score 0",
        ));
    }
    let mut targets = Vec::new();
    // Which scene targets each entry became (the built-in ship is several).
    let mut entries = Vec::new();
    for (i, t) in vf.targets.iter().enumerate() {
        let start = targets.len();
        targets.extend(target(ctx, &format!("volume.targets[{i}]"), t, &grid)?);
        entries.push(start..targets.len());
    }
    // The scene and one scratch per worker thread, before they are allocated.
    let threads = rayon::current_num_threads();
    let bytes = VolumeScene::bytes_needed(&grid, entries.len())
        + threads as u64 * VolumeScratch::bytes_needed(&grid);
    let d = grid.dims();
    crate::experiment::memory::check(
        &format!(
            "the {} × {} × {} grid (with {threads} worker threads)",
            d.x, d.y, d.z
        ),
        bytes,
        crate::experiment::memory::available(),
    )
    .map_err(|e| ctx.err("volume.resolution", v, format!("{e}: lower the resolution")))?;
    let scene = VolumeScene::new_grouped(grid, &targets, &entries)
        .map_err(|e| match e {
            ScoreError::EmptyTarget { target, reason } => {
                let i = entries
                    .iter()
                    .position(|p| p.contains(&target))
                    .unwrap_or(0);
                ctx.err(&format!("volume.targets[{i}]"), &vf.targets[i], reason)
            }
            e => ctx.err("volume.targets", v, e.to_string()),
        })?
        .with_outside_count(match vf.outside_count {
            None | Some(OutsideCountFile::Solid) => OutsideCount::Solid,
            Some(OutsideCountFile::Aabb) => OutsideCount::Aabb,
        });
    let warnings = scene.warnings().to_vec();
    let names = (0..targets.len())
        .map(|i| format!("target_{i}").into())
        .collect();
    let meshes = targets.into_iter().map(|t| t.mesh).collect();
    Ok((scene, ShapeMeshes::new(names, meshes)?, warnings))
}

/// One `[[volume.targets]]` entry (the built-in ship is several targets).
fn target(
    ctx: &Ctx<'_>,
    key: &str,
    t: &Spanned<VolumeTargetFile>,
    grid: &Grid,
) -> Result<Vec<VolumeTarget>, ExperimentError> {
    let tf = t.get_ref();
    let fill = tf.fill.unwrap_or(1.0);
    let outside = tf.outside.unwrap_or(0.0);
    let inside = match tf.inside {
        None | Some(InsideFile::Parity) => Inside::Parity,
        Some(InsideFile::Winding) => Inside::WindingNumber,
    };
    if !(fill.is_finite() && outside.is_finite()) {
        return Err(ctx.err(key, t, "fill and outside must be finite"));
    }
    let placement = placement(ctx, key, tf, grid)?;
    let targets = match (&tf.mesh, &tf.builtin) {
        (Some(mesh), None) => {
            let key = format!("{key}.mesh");
            let path = ctx.path(&key, mesh)?;
            let m = Mesh::load_obj(&path).map_err(|e| ctx.err(&key, mesh, e.to_string()))?;
            vec![VolumeTarget {
                name: path.display().to_string(),
                mesh: m,
                fill,
                outside,
                inside,
            }]
        }
        (None, Some(b)) if b.get_ref() == "ship" => spaceship_target()
            .into_iter()
            .map(|t| VolumeTarget {
                fill,
                outside,
                inside,
                ..t
            })
            .collect(),
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
        _ => return Err(ctx.err(key, t, "give exactly one of `mesh` and `builtin`")),
    };
    Ok(match placement {
        None => targets,
        Some(p) => place_together(targets, &p),
    })
}

/// Places the entry's meshes as one (the built-in ship's parts keep their
/// arrangement).
fn place_together(targets: Vec<VolumeTarget>, p: &Placement) -> Vec<VolumeTarget> {
    let placed = p.place_all(targets.iter().map(|t| &t.mesh));
    targets
        .into_iter()
        .zip(placed)
        .map(|(t, mesh)| VolumeTarget { mesh, ..t })
        .collect()
}

/// The entry's `scale`, `rotate`, `translate` and `fit`, if any is given.
fn placement(
    ctx: &Ctx<'_>,
    key: &str,
    tf: &VolumeTargetFile,
    grid: &Grid,
) -> Result<Option<Placement>, ExperimentError> {
    let mut p = Placement::default();
    let finite = |v: Vec3, name: &str, span: std::ops::Range<usize>| {
        if v.is_finite() {
            Ok(v)
        } else {
            Err(ctx
                .src
                .error(&format!("{key}.{name}"), span, "must be finite"))
        }
    };
    if let Some(s) = &tf.scale {
        let v = match *s.get_ref() {
            ScaleFile::Uniform(k) => Vec3::splat(k),
            ScaleFile::PerAxis(a) => Vec3::from_array(a.0),
        };
        p.scale = finite(v, "scale", s.span())?;
        if p.scale.cmple(Vec3::ZERO).any() {
            return Err(ctx.err(
                &format!("{key}.scale"),
                s,
                format!("every factor must be > 0, got {}", p.scale),
            ));
        }
    }
    if let Some(r) = &tf.rotate {
        p.rotate_degrees = finite(Vec3::from_array(r.get_ref().0), "rotate", r.span())?;
    }
    if let Some(t) = &tf.translate {
        p.translate = finite(Vec3::from_array(t.get_ref().0), "translate", t.span())?;
    }
    if let Some(fit) = &tf.fit {
        let fkey = format!("{key}.fit");
        if tf.scale.is_some() || tf.translate.is_some() {
            return Err(ctx.err(
                &fkey,
                fit,
                "`fit` sets the scale and position itself: drop `scale` and `translate` (`rotate` applies before fitting)",
            ));
        }
        let (min, max) = match fit.get_ref() {
            FitFile::Named(n) if n == "grid" => (grid.min().as_vec3(), grid.max().as_vec3()),
            FitFile::Named(n) => {
                return Err(ctx.err(
                    &fkey,
                    fit,
                    format!("unknown box `{n}`: use \"grid\" or {{ min = [..], max = [..] }}"),
                ));
            }
            FitFile::Box { min, max } => (Vec3::from_array(min.0), Vec3::from_array(max.0)),
        };
        if !(min.is_finite() && max.is_finite() && min.cmplt(max).all()) {
            return Err(ctx.err(
                &fkey,
                fit,
                format!("need finite min < max on every axis, got {min} and {max}"),
            ));
        }
        p.fit = Some((min, max));
    }
    Ok((p != Placement::default()).then_some(p))
}
