//! `[image]`: image targets (PNG with a mask rule, or signed PFM weights),
//! each with the paper's orbit camera or a right-handed look-at camera.

use toml::Spanned;

use super::Ctx;
use crate::experiment::ExperimentError;
use crate::experiment::file::{CameraFile, ImageFile, ImageTargetFile, MaskFile};
use crate::glam::DVec3;
use crate::score::Camera;
use crate::score::ImageTargets;
use crate::score::{ImageTarget, PngMask};

/// The image size when `[image]` gives none (the paper's).
const DEFAULT_SIZE: (u32, u32) = (800, 600);
/// The luminance or opacity threshold of a mask when none is given.
const DEFAULT_THRESHOLD: f32 = 0.5;

/// The scene's targets.
pub(super) fn from_file(
    ctx: &Ctx<'_>,
    i: &Spanned<ImageFile>,
    paper: bool,
) -> Result<ImageTargets, ExperimentError> {
    let f = i.get_ref();
    let size = (
        f.width.unwrap_or(DEFAULT_SIZE.0),
        f.height.unwrap_or(DEFAULT_SIZE.1),
    );
    if f.targets.is_empty() {
        return Err(ctx.err("image.targets", i, "give at least one [[image.targets]]"));
    }
    if paper
        && f.targets.iter().all(|t| {
            let t = t.get_ref();
            t.png.is_some() && t.target == Some(0.0) && t.background == Some(0.0)
        })
    {
        return Err(ctx.err(
            "image.targets",
            i,
            "every pixel weight (target, background) is 0: every model would score 0",
        ));
    }
    let targets = f
        .targets
        .iter()
        .enumerate()
        .map(|(k, t)| target(ctx, &format!("image.targets[{k}]"), t, size))
        .collect::<Result<_, _>>()?;
    ImageTargets::new(targets).map_err(|e| ctx.err("image.targets", i, e.to_string()))
}

fn target(
    ctx: &Ctx<'_>,
    key: &str,
    t: &Spanned<ImageTargetFile>,
    size: (u32, u32),
) -> Result<ImageTarget, ExperimentError> {
    let tf = t.get_ref();
    let camera = camera(ctx, &format!("{key}.camera"), &tf.camera, size)?;
    match (&tf.png, &tf.pfm) {
        (Some(png), None) => {
            let key = format!("{key}.png");
            let path = ctx.path(&key, png)?;
            let (w_t, w_b) = (tf.target.unwrap_or(1.0), tf.background.unwrap_or(-1.0));
            if !(w_t.is_finite() && w_b.is_finite()) {
                return Err(ctx.err(&key, t, "target and background must be finite"));
            }
            let mask = mask(ctx, key.trim_end_matches(".png"), tf)?;
            ImageTarget::from_png_masked(&path, camera, mask, w_t, w_b)
                .map_err(|e| ctx.err(&key, png, e.to_string()))
        }
        (None, Some(pfm)) => {
            let key = format!("{key}.pfm");
            if tf.target.is_some() || tf.background.is_some() || tf.mask.is_some() {
                return Err(ctx.err(
                    &key,
                    pfm,
                    "a float image holds its own weights: drop `target`, `background` and `mask`",
                ));
            }
            let path = ctx.path(&key, pfm)?;
            ImageTarget::from_pfm(&path, camera).map_err(|e| ctx.err(&key, pfm, e.to_string()))
        }
        _ => Err(ctx.err(key, t, "give exactly one of `png` and `pfm`")),
    }
}

/// The orbit camera (`phi`, `theta`, `r`, `look_at`) or, with `eye`, the
/// right-handed look-at camera (`eye`, `target`, `up`).
fn camera(
    ctx: &Ctx<'_>,
    key: &str,
    spanned: &Spanned<CameraFile>,
    size: (u32, u32),
) -> Result<Camera, ExperimentError> {
    let c = spanned.get_ref();
    let err = |m: String| ctx.err(key, spanned, m);
    let fov = c.fov.unwrap_or(60.0).to_radians();
    let (near, far) = (c.near.unwrap_or(0.1), c.far.unwrap_or(100.0));
    let camera = match (c.eye, c.target) {
        (Some(eye), Some(target)) => {
            if c.phi.is_some() || c.theta.is_some() || c.r.is_some() || c.look_at.is_some() {
                return Err(err(
                    "give either the orbit camera (phi, theta, r, look_at) or eye and target, not both".into(),
                ));
            }
            let up = c.up.map_or([0.0, 1.0, 0.0], |u| u.0);
            Camera::look_at(
                DVec3::from_array(eye.0),
                DVec3::from_array(target.0),
                DVec3::from_array(up),
                fov,
                near,
                far,
                size,
            )
        }
        (Some(_), None) | (None, Some(_)) => {
            return Err(err("a look-at camera needs both `eye` and `target`".into()));
        }
        (None, None) => {
            if c.up.is_some() {
                return Err(err("`up` belongs to a look-at camera (eye, target, up); the orbit camera's up follows from theta".into()));
            }
            let (Some(phi), Some(theta), Some(r), Some(look_at)) = (c.phi, c.theta, c.r, c.look_at)
            else {
                return Err(err(
                    "give the orbit camera's phi, theta, r and look_at (or eye and target for a look-at camera)".into(),
                ));
            };
            Camera::orbit(
                phi,
                theta,
                r,
                DVec3::from_array(look_at.0),
                fov,
                near,
                far,
                size,
            )
        }
    };
    camera.map_err(|e| err(e.to_string()))
}

/// The entry's `mask` and `threshold` (default: the paper's `red0`).
fn mask(ctx: &Ctx<'_>, key: &str, tf: &ImageTargetFile) -> Result<PngMask, ExperimentError> {
    let threshold = match &tf.threshold {
        None => DEFAULT_THRESHOLD,
        Some(t) => {
            let v = *t.get_ref();
            if !(0.0..=1.0).contains(&v) {
                return Err(ctx.err(
                    &format!("{key}.threshold"),
                    t,
                    format!("must be in [0, 1], got {v}"),
                ));
            }
            if matches!(tf.mask, None | Some(MaskFile::Red0)) {
                return Err(ctx.err(
                    &format!("{key}.threshold"),
                    t,
                    "the `red0` mask has no threshold: use mask = \"dark\", \"alpha\" or \"alpha_dark\"",
                ));
            }
            v
        }
    };
    Ok(match tf.mask {
        None | Some(MaskFile::Red0) => PngMask::Red0,
        Some(MaskFile::Dark) => PngMask::Dark { threshold },
        Some(MaskFile::Alpha) => PngMask::Alpha { threshold },
        Some(MaskFile::AlphaDark) => PngMask::AlphaDark { threshold },
    })
}
