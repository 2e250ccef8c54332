//! Counting one model's cells against a scene: hit counts per cell and the
//! sums the scores need.

use glam::Affine3A;

use super::target::in_grid;
use super::{OutsideCount, VolumeScene};
use crate::grid::Grid;
use crate::solid::Solid;
use crate::voxelize::Voxelizer;

/// Lattice cells outside `grid` whose centres lie in the closed world box
/// around the corners of `solid`'s local bounding box placed by
/// `transform`; none for a transform the voxelizer refuses (singular or not
/// finite).
#[must_use]
pub fn aabb_cells_outside(grid: &Grid, solid: &Solid, transform: &Affine3A) -> u64 {
    let Some((_, wlo, whi)) = crate::voxelize::placed_box(solid, transform) else {
        return 0;
    };
    let (mut all, mut inside) = (1u64, 1u64);
    for axis in 0..3 {
        let cells = grid.clamp_walk(axis, grid.centres_in(axis, wlo[axis], whi[axis]));
        let dim = i64::from(grid.dims()[axis]);
        all = all.saturating_mul((cells.end - cells.start).max(0) as u64);
        inside = inside.saturating_mul((cells.end.min(dim) - cells.start.max(0)).max(0) as u64);
    }
    all - inside
}

/// What one model covers, counted against a [`VolumeScene`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct VolumeCounts {
    /// `Σ C(v)` over the grid cells the model covers (each once).
    pub weight: f64,
    /// `G`: covered target cells.
    pub good: u64,
    /// `B`: covered cells outside every target (in the grid).
    pub bad: u64,
    /// Cells covered by two or more instances.
    pub overlap_cells: u64,
    /// `Σ max(0, h − 1)` over cells with hit count `h`.
    pub overlap_hits: u64,
    /// Lattice cells outside the grid covered by the model (each instance
    /// counts its own; see [`OutsideCount`]).
    pub outside: u64,
}

/// Adds one instance's span to the hit counts and `counts`: branch-free per
/// cell (instances overlap at random, so branches would mispredict), with
/// the sums kept in registers for the span.
#[inline]
fn count_span(hits: &mut [u8], weight: &[f32], target: &[bool], counts: &mut VolumeCounts) {
    let (mut w_sum, mut first, mut good, mut second, mut again) = (0.0f64, 0u64, 0u64, 0u64, 0u64);
    for ((h, &w), &t) in hits.iter_mut().zip(weight).zip(target) {
        let old = *h;
        *h = old.saturating_add(1);
        let is_first = u64::from(old == 0);
        w_sum += if old == 0 { f64::from(w) } else { 0.0 };
        first += is_first;
        good += is_first & u64::from(t);
        second += u64::from(old == 1);
        again += u64::from(old != 0);
    }
    counts.weight += w_sum;
    counts.good += good;
    counts.bad += first - good;
    counts.overlap_cells += second;
    counts.overlap_hits += again;
}

/// Per-thread working memory of volume evaluations: hit counts per cell
/// (all zero between evaluations), the runs to reset, and the voxelizer.
#[derive(Clone, Debug)]
pub struct VolumeScratch {
    hits: Vec<u8>,
    touched: Vec<(u32, u32)>,
    voxelizer: Voxelizer,
    counts: VolumeCounts,
}

impl VolumeScratch {
    /// Working memory for `scene`.
    #[must_use]
    pub fn new(scene: &VolumeScene) -> Self {
        Self {
            hits: vec![0; scene.grid.len()],
            touched: Vec::new(),
            voxelizer: Voxelizer::new(),
            counts: VolumeCounts::default(),
        }
    }

    /// The memory of one scratch over `grid` (bytes): one hit count a cell.
    #[must_use]
    pub fn bytes_needed(grid: &Grid) -> u64 {
        grid.len() as u64
    }

    /// Starts counting a new model.
    pub fn begin(&mut self) {
        for &(start, len) in &self.touched {
            self.hits[start as usize..(start + len) as usize].fill(0);
        }
        self.touched.clear();
        self.counts = VolumeCounts::default();
    }

    /// Adds one instance of `solid`, placed by `transform`.
    pub fn add(&mut self, scene: &VolumeScene, solid: &Solid, transform: &Affine3A) {
        let Self {
            hits,
            touched,
            voxelizer,
            counts,
        } = self;
        let grid = &scene.grid;
        let by_solid = scene.outside_count == OutsideCount::Solid;
        if !by_solid {
            counts.outside += aabb_cells_outside(grid, solid, transform);
        }
        voxelizer.spans(grid, solid, transform, |s| {
            let cells = in_grid(grid, s);
            if by_solid {
                counts.outside += (s.x1 - s.x0) as u64 - cells.len() as u64;
            }
            if cells.is_empty() {
                return;
            }
            let (a, b) = (cells.start, cells.end);
            touched.push((a as u32, (b - a) as u32));
            count_span(
                &mut hits[a..b],
                &scene.weight[a..b],
                &scene.target[a..b],
                counts,
            );
        });
    }

    /// The counts of the model added since [`begin`](Self::begin).
    #[must_use]
    pub fn counts(&self) -> VolumeCounts {
        self.counts
    }

    /// How many instances hit each cell (saturating at 255), indexed like
    /// [`Grid::index`], for the model added since [`begin`](Self::begin).
    #[must_use]
    pub fn hits(&self) -> &[u8] {
        &self.hits
    }
}
