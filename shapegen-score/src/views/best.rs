//! Best-view selection (thesis §3.4.1): render a model from viewpoints on
//! rings above the ground plane, score each by a weighted sum of its
//! normalized view attributes, keep the best.

use serde::{Deserialize, Serialize};
use shapegen_core::express::Instance;

use super::attributes::{AttributeWeights, ViewAttributes, normalize_columns};
use crate::camera::Camera;
use crate::error::ScoreError;
use crate::render::{BoundingSphere, RenderMeshes, Renderer, Style, fit_camera};

/// A direction to look at a model from: `azimuth` about the up axis (+y,
/// from +x toward +z) and `elevation` above the ground plane, in radians.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Viewpoint {
    /// Angle about +y, from +x toward +z.
    pub azimuth: f64,
    /// Angle above the ground plane.
    pub elevation: f64,
}

impl Viewpoint {
    /// The camera at this viewpoint fitted to `sphere`.
    pub fn camera(
        &self,
        sphere: &BoundingSphere,
        fov_y: f64,
        size: (u32, u32),
    ) -> Result<Camera, ScoreError> {
        fit_camera(
            sphere,
            BoundingSphere::direction(self.azimuth, self.elevation),
            fov_y,
            size,
        )
    }
}

/// Where best-view selection looks from and how it renders.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ViewSampling {
    /// Viewpoints per ring.
    pub azimuths: u32,
    /// The rings' elevations in radians (the thesis: between 0° and 45°).
    pub elevations: Vec<f64>,
    /// Vertical field of view in radians.
    pub fov_y: f64,
    /// Side of the square renders the attributes are computed on.
    pub size: u32,
}

impl Default for ViewSampling {
    /// 32 viewpoints: 8 around each of the rings at 0°, 15°, 30° and 45°;
    /// a 40° field of view; 256² renders.
    fn default() -> Self {
        Self {
            azimuths: 8,
            elevations: [0.0f64, 15.0, 30.0, 45.0].map(f64::to_radians).to_vec(),
            fov_y: 40f64.to_radians(),
            size: 256,
        }
    }
}

impl ViewSampling {
    /// The largest side of the renders attributes are computed on.
    pub const MAX_SIZE: u32 = 2048;

    /// Every viewpoint, ring by ring (azimuths offset by half a step on
    /// every other ring, so the rings interleave).
    #[must_use]
    pub fn viewpoints(&self) -> Vec<Viewpoint> {
        let step = std::f64::consts::TAU / f64::from(self.azimuths.max(1));
        self.elevations
            .iter()
            .enumerate()
            .flat_map(|(ring, &elevation)| {
                let offset = if ring % 2 == 1 { 0.5 * step } else { 0.0 };
                (0..self.azimuths).map(move |k| Viewpoint {
                    azimuth: offset + step * f64::from(k),
                    elevation,
                })
            })
            .collect()
    }

    /// Why this sampling is unusable, if it is.
    #[must_use]
    pub fn problem(&self) -> Option<String> {
        if self.azimuths == 0 || self.elevations.is_empty() {
            return Some("best views need at least one viewpoint".into());
        }
        if self
            .elevations
            .iter()
            .any(|e| !e.is_finite() || e.abs() >= std::f64::consts::FRAC_PI_2)
        {
            return Some("view elevations must lie strictly between −90° and 90°".into());
        }
        if !(self.fov_y > 0.0 && self.fov_y < std::f64::consts::PI) {
            return Some("the field of view must lie in (0°, 180°)".into());
        }
        if !(8..=Self::MAX_SIZE).contains(&self.size) {
            return Some(format!(
                "view renders must be 8 to {} pixels across, got {}",
                Self::MAX_SIZE,
                self.size
            ));
        }
        None
    }
}

/// The outcome of best-view selection.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BestView {
    /// The chosen viewpoint.
    pub viewpoint: Viewpoint,
    /// Its index in `viewpoints`.
    pub index: usize,
    /// Every viewpoint tried.
    pub viewpoints: Vec<Viewpoint>,
    /// Their raw attributes.
    pub attributes: Vec<ViewAttributes>,
    /// Their scores: the weighted sum of the attributes normalized over the
    /// viewpoints.
    pub scores: Vec<f64>,
}

/// Renders `instances` from every viewpoint of `sampling`, each camera
/// fitted to the model's bounding sphere, and picks the one whose
/// normalized attributes score highest under `weights` (the first of
/// equals). Fails on a model with nothing to render or unusable settings.
pub fn best_view(
    renderer: &mut Renderer,
    meshes: &RenderMeshes,
    instances: &[Instance],
    sampling: &ViewSampling,
    weights: &AttributeWeights,
    style: &Style,
) -> Result<BestView, ScoreError> {
    let sphere = meshes
        .bounding_sphere(instances)
        .ok_or_else(|| ScoreError::Camera("the model has no finite geometry to look at".into()))?;
    best_view_around(
        renderer, meshes, instances, &sphere, sampling, weights, style,
    )
}

/// [`best_view`] with the model's bounding sphere already known (the
/// cameras are fitted to `sphere`), for callers that need the sphere too.
pub fn best_view_around(
    renderer: &mut Renderer,
    meshes: &RenderMeshes,
    instances: &[Instance],
    sphere: &BoundingSphere,
    sampling: &ViewSampling,
    weights: &AttributeWeights,
    style: &Style,
) -> Result<BestView, ScoreError> {
    if let Some(p) = sampling.problem() {
        return Err(ScoreError::Camera(p));
    }
    if let Some(p) = weights.problem() {
        return Err(ScoreError::Camera(p.into()));
    }
    let viewpoints = sampling.viewpoints();
    let mut attributes = Vec::with_capacity(viewpoints.len());
    for v in &viewpoints {
        let camera = v.camera(sphere, sampling.fov_y, (sampling.size, sampling.size))?;
        let g = renderer.render(meshes, instances, &camera);
        attributes.push(ViewAttributes::of(g, meshes, style));
    }
    let rows: Vec<[f64; 8]> = attributes
        .iter()
        .map(ViewAttributes::for_best_view)
        .collect();
    let scores: Vec<f64> = normalize_columns(&rows)
        .iter()
        .map(|r| weights.dot(r))
        .collect();
    let mut index = 0;
    for (i, s) in scores.iter().enumerate() {
        if *s > scores[index] {
            index = i;
        }
    }
    Ok(BestView {
        viewpoint: viewpoints[index],
        index,
        viewpoints,
        attributes,
        scores,
    })
}
