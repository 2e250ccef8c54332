//! A transformation sequence: frames at evenly spaced times, their
//! pictures from one fixed camera, and what changes from frame to frame.

use std::borrow::Cow;

use serde::Serialize;

use super::{Placed, Transformation};
use crate::express::Instance;
use crate::glam::{UVec3, Vec3};
use crate::score::{
    BoundingSphere, Grid, Mesh, RenderMeshes, Renderer, ShapeMeshes, Solid, Style, Viewpoint,
    Voxelizer,
};

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

/// The built-in mesh of each of `t`'s shapes (a unit cube for a name without one).
pub fn meshes(t: &Transformation) -> Result<ShapeMeshes, crate::score::ScoreError> {
    named_meshes(t.shapes())
}

/// The built-in mesh of each shape of `names` (a unit cube for a name without one).
pub fn named_meshes(names: &[Cow<'static, str>]) -> Result<ShapeMeshes, crate::score::ScoreError> {
    let names = names.to_vec();
    let meshes: Vec<Mesh> = names
        .iter()
        .map(|n| Mesh::builtin(n).unwrap_or_else(Mesh::unit_cube))
        .collect();
    ShapeMeshes::new(names, meshes)
}

/// Frames as sets of voxels of one grid fitted to both designs, to measure
/// how much a sequence changes from one frame to the next.
#[derive(Clone)]
pub struct Occupancy {
    grid: Grid,
    solids: Vec<Solid>,
    voxelizer: Voxelizer,
    dims: UVec3,
}

impl Occupancy {
    /// A grid of `side`³ cells around both designs of `t` (their bounding
    /// box, with a margin of 2 %).
    pub fn new(t: &Transformation, side: u32) -> Result<Self, crate::score::ScoreError> {
        let ends = [t.at(0.0), t.at(1.0)];
        Self::around(t.shapes(), ends.iter().flatten(), side)
    }

    /// A grid of `side`³ cells around `shapes` (of the shapes named
    /// `names`), with a margin of 2 %.
    pub fn around<'a>(
        names: &[Cow<'static, str>],
        shapes: impl IntoIterator<Item = &'a Placed>,
        side: u32,
    ) -> Result<Self, crate::score::ScoreError> {
        let meshes = named_meshes(names)?;
        let solids = (0..meshes.len() as u16)
            .map(|i| Solid::new(meshes.name(i), meshes.mesh(i)))
            .collect::<Result<Vec<_>, _>>()?;
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for p in shapes {
            for c in super::pairing::corners(&p.transform) {
                lo = lo.min(c);
                hi = hi.max(c);
            }
        }
        if !lo.is_finite() || !hi.is_finite() {
            (lo, hi) = (Vec3::splat(-1.0), Vec3::splat(1.0));
        }
        let margin = 0.02 * (hi - lo).max_element().max(1e-3);
        let dims = UVec3::splat(side.max(2));
        let grid = Grid::new(lo - margin, hi + margin, dims)?;
        Ok(Self {
            grid,
            solids,
            voxelizer: Voxelizer::new(),
            dims,
        })
    }

    /// The cells `shapes` fill, as a bit set. A shape thinner than a cell
    /// and a half along one of its axes is thickened to that along it, so
    /// that thin branches are measured as they move instead of flickering
    /// in and out of cell centres; shapes of size zero fill nothing.
    pub fn cells(&mut self, shapes: &[Placed]) -> Vec<u64> {
        let d = self.dims;
        let n = (d.x * d.y * d.z) as usize;
        let mut bits = vec![0u64; n.div_ceil(64)];
        let thinnest = 1.5 * self.grid.cell_size().min_element() as f32;
        for p in shapes {
            let solid = &self.solids[p.shape as usize];
            let mut t = p.transform;
            let m = &mut t.matrix3;
            let axes = [&mut m.x_axis, &mut m.y_axis, &mut m.z_axis];
            if axes.iter().any(|a| a.length() == 0.0) {
                continue;
            }
            for a in axes {
                let l = a.length();
                if l < thinnest {
                    *a *= thinnest / l;
                }
            }
            self.voxelizer.spans(&self.grid, solid, &t, |s| {
                if s.y < 0 || s.z < 0 || s.y >= i64::from(d.y) || s.z >= i64::from(d.z) {
                    return;
                }
                let row = (s.z as usize * d.y as usize + s.y as usize) * d.x as usize;
                for x in s.x0.max(0)..s.x1.min(i64::from(d.x)) {
                    let i = row + x as usize;
                    bits[i / 64] |= 1 << (i % 64);
                }
            });
        }
        bits
    }
}

/// `1 − IoU` of two cell sets (0 for two empty sets).
#[must_use]
pub fn change(a: &[u64], b: &[u64]) -> f64 {
    let (mut both, mut either) = (0u64, 0u64);
    for (x, y) in a.iter().zip(b) {
        both += u64::from((x & y).count_ones());
        either += u64::from((x | y).count_ones());
    }
    if either == 0 {
        0.0
    } else {
        1.0 - both as f64 / either as f64
    }
}

/// How smooth a sequence is: the largest and the 95th percentile of the
/// change between consecutive frames, and the number of times the count of
/// instances changes (discrete events).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Smoothness {
    /// Largest `1 − IoU` between consecutive frames.
    pub largest_change: f64,
    /// Its 95th percentile.
    pub p95_change: f64,
    /// Consecutive frames whose instance counts differ.
    pub count_changes: usize,
}

impl Smoothness {
    /// From each frame's facts (the first frame's change is not counted).
    #[must_use]
    pub fn of(frames: &[FrameFacts]) -> Self {
        let mut changes: Vec<f64> = frames.iter().skip(1).map(|f| f.change).collect();
        changes.sort_by(f64::total_cmp);
        let p95 = if changes.is_empty() {
            0.0
        } else {
            changes[((changes.len() - 1) as f64 * 0.95).round() as usize]
        };
        Self {
            largest_change: changes.last().copied().unwrap_or(0.0),
            p95_change: p95,
            count_changes: frames
                .windows(2)
                .filter(|w| w[0].instances != w[1].instances)
                .count(),
        }
    }
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
    /// `1 − IoU` of this frame's cells and the previous frame's (0 for the first).
    pub change: f64,
}

/// Renders transformation frames from one camera fitted to both designs.
#[derive(Clone)]
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
        let mut both = t.at(0.0);
        both.extend(t.at(1.0));
        Self::framing(t.shapes(), &both, viewpoint, size)
    }

    /// A painter for shapes named `names`, its camera at `viewpoint`
    /// fitted to `framing` (e.g. every variation of a variety).
    pub fn framing(
        names: &[Cow<'static, str>],
        framing: &[Placed],
        viewpoint: Viewpoint,
        size: u32,
    ) -> Result<Self, crate::score::ScoreError> {
        let meshes = RenderMeshes::new(&named_meshes(names)?)?;
        let sphere = meshes
            .bounding_sphere(&instances(framing))
            .unwrap_or(BoundingSphere {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::express::Generator;
    use crate::scenes::{TreeV1, TreeV2};
    use crate::transform::{Design, Mode, Settings};

    #[test]
    fn change_is_one_minus_iou() {
        assert_eq!(change(&[0b1111], &[0b1111]), 0.0);
        assert_eq!(change(&[0b0011], &[0b1100]), 1.0);
        assert!((change(&[0b0111], &[0b1110]) - 0.5).abs() < 1e-12);
        assert_eq!(change(&[0], &[0]), 0.0);
    }

    fn facts(changes: &[f64], counts: &[usize]) -> Vec<FrameFacts> {
        changes
            .iter()
            .zip(counts)
            .enumerate()
            .map(|(k, (&change, &instances))| FrameFacts {
                t: k as f32,
                instances,
                visible: instances,
                derive_ms: 0.0,
                change,
            })
            .collect()
    }

    #[test]
    fn smoothness_skips_the_first_frame() {
        let s = Smoothness::of(&facts(&[0.9, 0.1, 0.3, 0.2], &[1, 1, 2, 2]));
        assert_eq!(s.largest_change, 0.3);
        assert_eq!(s.count_changes, 1);
    }

    /// The measure sees the thesis's pops: unpaired branches of trees v1
    /// and v2 appear at the threshold in one frame; grown, they do not.
    #[test]
    fn grown_shapes_change_less_per_frame_than_popped_ones() {
        let largest = |mode| {
            let mut rng = crate::rng::stream(11, &[]);
            let a = crate::ops::uncontrolled(TreeV1.graph(), &mut rng).unwrap();
            let b = crate::ops::uncontrolled(TreeV2.graph(), &mut rng).unwrap();
            let (a, b) = (
                Design::new(TreeV1, a).unwrap(),
                Design::new(TreeV2, b).unwrap(),
            );
            let t = crate::transform::Transformation::new(a, b).with_settings(Settings {
                mode,
                ..Settings::default()
            });
            let mut occupancy = Occupancy::new(&t, 48).unwrap();
            let cells: Vec<_> = frame_times(41)
                .iter()
                .map(|&x| occupancy.cells(&t.at(x)))
                .collect();
            cells
                .windows(2)
                .map(|w| change(&w[0], &w[1]))
                .fold(0.0, f64::max)
        };
        let (grow, thesis) = (largest(Mode::Grow), largest(Mode::Thesis));
        assert!(grow < 0.5 * thesis, "grow {grow}, thesis {thesis}");
    }
}
