//! A transformation sequence: frames at evenly spaced times, their
//! pictures from one fixed camera, and what changes from frame to frame.

use std::borrow::Cow;

use serde::Serialize;

use super::{Placed, Transformation};
use crate::express::Instance;
use crate::score::{BoundingSphere, Mesh, RenderMeshes, Renderer, ShapeMeshes, Style, Viewpoint};

/// The times of `count` frames from 0 to 1, both included.
#[must_use]
pub fn frame_times(count: usize) -> Vec<f32> {
    let last = count.max(2) - 1;
    (0..=last).map(|k| k as f32 / last as f32).collect()
}

/// Placed shapes as instances a renderer or writer takes.
#[must_use]
pub fn instances(shapes: &[Placed]) -> Vec<Instance> {
    shapes
        .iter()
        .map(|p| Instance::new(p.shape, p.transform))
        .collect()
}

/// Instances whose box has an extent above `1e-3` of `scale`: what a viewer
/// sees (an unpaired shape grown from nothing is there but invisible at first).
#[must_use]
pub fn visible(shapes: &[Placed], scale: f32) -> usize {
    shapes
        .iter()
        .filter(|p| {
            let m = p.transform.matrix3;
            m.x_axis
                .length()
                .max(m.y_axis.length())
                .max(m.z_axis.length())
                > 1e-3 * scale
        })
        .count()
}

/// One frame's facts, for `sequence.json`.
#[derive(Clone, Debug, Serialize)]
pub struct FrameFacts {
    /// The frame's time.
    pub t: f32,
    /// Instances placed.
    pub instances: usize,
    /// Instances large enough to see (see [`visible`]).
    pub visible: usize,
    /// Milliseconds to co-derive the frame.
    pub derive_ms: f64,
}

/// Renders transformation frames from one camera fitted to both designs.
pub struct Painter {
    meshes: RenderMeshes,
    camera: crate::score::Camera,
    renderer: Renderer,
    scale: f32,
}

impl Painter {
    /// A painter for `t` with built-in meshes for its shapes, at `viewpoint`
    /// (angles in radians), `size` pixels square.
    pub fn new(
        t: &Transformation,
        viewpoint: Viewpoint,
        size: u32,
    ) -> Result<Self, crate::score::ScoreError> {
        let names: Vec<Cow<'static, str>> = t.shapes().to_vec();
        let meshes: Vec<Mesh> = names
            .iter()
            .map(|n| Mesh::builtin(n).unwrap_or_else(Mesh::unit_cube))
            .collect();
        let meshes = RenderMeshes::new(&ShapeMeshes::new(names, meshes)?)?;
        let mut both = instances(&t.at(0.0));
        both.extend(instances(&t.at(1.0)));
        let sphere = meshes.bounding_sphere(&both).unwrap_or(BoundingSphere {
            center: crate::glam::DVec3::ZERO,
            radius: 1.0,
        });
        let camera = viewpoint.camera(&sphere, 40f64.to_radians(), (size, size))?;
        Ok(Self {
            meshes,
            camera,
            renderer: Renderer::new(),
            scale: (2.0 * sphere.radius) as f32,
        })
    }

    /// The size of the scene (its bounding sphere's diameter).
    #[must_use]
    pub fn scale(&self) -> f32 {
        self.scale
    }

    /// The shaded picture of `shapes`.
    pub fn paint(&mut self, shapes: &[Placed]) -> image::RgbaImage {
        self.renderer.picture(
            &self.meshes,
            &instances(shapes),
            &self.camera,
            &Style::default(),
        )
    }
}

/// Frames side by side, `columns` to a row, each shrunk to `side` pixels.
#[must_use]
pub fn contact_sheet(frames: &[image::RgbaImage], columns: u32, side: u32) -> image::RgbaImage {
    let columns = columns.max(1);
    let rows = (frames.len() as u32).div_ceil(columns).max(1);
    let mut sheet =
        image::RgbaImage::from_pixel(columns * side, rows * side, image::Rgba([255; 4]));
    for (k, f) in frames.iter().enumerate() {
        let small = image::imageops::resize(f, side, side, image::imageops::FilterType::Triangle);
        let (x, y) = (k as u32 % columns, k as u32 / columns);
        image::imageops::overlay(&mut sheet, &small, i64::from(x * side), i64::from(y * side));
    }
    sheet
}
