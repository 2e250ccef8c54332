//! Volume targets and counting a model's voxels against them.
//!
//! Targets are voxelized once, with the same centre-sampled routine as the
//! model, and combined into one weight per cell as the paper does:
//! `C(v) = Σ_i (w_i · V_i(v) + w̃_i · (1 − V_i(v)))`. Evaluating a model
//! voxelizes each instance as it is emitted and accumulates the counts the
//! scores need; only the touched cells are reset afterwards, so an
//! evaluation costs what the model covers, not the grid's size.

use std::path::Path;

use glam::Affine3A;

use crate::error::ScoreError;
use crate::grid::Grid;
use crate::mesh::Mesh;
use crate::solid::{Inside, Solid};
use crate::voxelize::{Span, Voxelizer};

/// One volume target: a closed mesh in world coordinates and its weights.
#[derive(Clone, Debug)]
pub struct VolumeTarget {
    /// Name (for messages).
    pub name: String,
    /// The mesh, in world coordinates.
    pub mesh: Mesh,
    /// `w_i`: weight of each target cell the model covers (positive = fill).
    pub fill: f64,
    /// `w̃_i`: weight of each model cell outside the target (negative = avoid).
    pub outside: f64,
    /// How the mesh's inside is decided (ray parity unless told otherwise;
    /// [`Inside::WindingNumber`] for meshes with holes).
    pub inside: Inside,
}

/// How a model's cells outside the grid are counted (`N_out` of the linear
/// score, part of `O` in the normalized one).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum OutsideCount {
    /// Lattice cells outside the grid whose centre lies inside an instance
    /// (each instance counts its own): the paper's definition.
    #[default]
    Solid,
    /// Lattice cells outside the grid whose centre lies inside an
    /// instance's bounding box (the closed world box around its placed
    /// local bounding box): what the authors' code counts, for comparisons
    /// with it.
    Aabb,
}

/// A voxel grid with targets combined into one weight per cell.
#[derive(Clone, Debug)]
pub struct VolumeScene {
    grid: Grid,
    /// `C(v)` per cell.
    weight: Vec<f32>,
    /// Whether each cell is inside some target.
    target: Vec<bool>,
    target_cells: u64,
    /// Per group of targets (only with two or more groups): whether each
    /// cell is inside one of the group's targets.
    members: Vec<Vec<bool>>,
    /// `Σ_i w̃_i`: the weight of a model cell outside the grid (outside every target).
    outside_sum: f64,
    outside_count: OutsideCount,
    warnings: Vec<String>,
}

impl VolumeScene {
    /// Voxelizes `targets` over `grid` and combines them; each target is
    /// reported on its own by [`quality`](Self::quality). A target that
    /// covers no cell centre is an error that says why
    /// ([`ScoreError::EmptyTarget`]).
    pub fn new(grid: Grid, targets: &[VolumeTarget]) -> Result<Self, ScoreError> {
        let singles: Vec<_> = (0..targets.len()).map(|i| i..i + 1).collect();
        Self::new_grouped(grid, targets, &singles)
    }

    /// [`new`](Self::new), with [`quality`](Self::quality) reported per
    /// group of targets (the union of each group's cells): e.g. the parts of
    /// one object given as several meshes. Every target must be in exactly
    /// one group, in order. A group that covers no cell is an error; an
    /// empty part of a group that covers some is a warning.
    pub fn new_grouped(
        grid: Grid,
        targets: &[VolumeTarget],
        groups: &[std::ops::Range<usize>],
    ) -> Result<Self, ScoreError> {
        let tiles = groups.first().is_none_or(|g| g.start == 0)
            && groups
                .windows(2)
                .all(|w| w[0].end == w[1].start && w[0].start < w[0].end)
            && groups
                .last()
                .is_none_or(|g| g.end == targets.len() && g.start < g.end);
        if !tiles || (groups.is_empty() && !targets.is_empty()) {
            return Err(ScoreError::Target(format!(
                "the groups {groups:?} do not split the {} targets in order",
                targets.len()
            )));
        }
        let n = grid.len();
        let mut weight = vec![0.0f64; n];
        let mut target = vec![false; n];
        let mut inside = vec![false; n];
        let mut warnings = Vec::new();
        let mut vox = Voxelizer::new();
        let mut members: Vec<Vec<bool>> = if groups.len() > 1 {
            vec![vec![false; n]; groups.len()]
        } else {
            Vec::new()
        };
        // Per target: why it covers no cell (`None` if it covers some).
        let mut empty: Vec<Option<String>> = Vec::new();
        for (k, t) in targets.iter().enumerate() {
            if !t.fill.is_finite() || !t.outside.is_finite() {
                return Err(ScoreError::Target(format!(
                    "target `{}` has a non-finite weight",
                    t.name
                )));
            }
            let solid = Solid::with_inside(&t.name, &t.mesh, t.inside)?;
            if let Solid::Mesh(m) = &solid
                && m.boundary_edges() > 0
                && t.inside == Inside::Parity
            {
                warnings.push(format!(
                    "target `{}` is not watertight ({} boundary edges): its inside is decided by ray parity and may have holes or streaks (the winding-number rule copes with holes)",
                    t.name,
                    m.boundary_edges()
                ));
            }
            inside.iter_mut().for_each(|c| *c = false);
            vox.spans(&grid, &solid, &Affine3A::IDENTITY, |s| {
                for i in in_grid(&grid, s) {
                    inside[i] = true;
                }
            });
            let cells = inside.iter().filter(|&&c| c).count() as u64;
            if cells == 0 {
                empty.push(Some(empty_target(&grid, t, &solid)));
            } else {
                empty.push(None);
            }
            for ((w, tg), &ins) in weight.iter_mut().zip(target.iter_mut()).zip(&inside) {
                *w += if ins { t.fill } else { t.outside };
                *tg |= ins;
            }
            if let Some(g) = groups.iter().position(|g| g.contains(&k))
                && let Some(member) = members.get_mut(g)
            {
                member.iter_mut().zip(&inside).for_each(|(m, &i)| *m |= i);
            }
        }
        let target_cells = target.iter().filter(|&&t| t).count() as u64;
        // A group that covers no cell is a mistake; one empty part of a
        // group that does (below the grid's resolution) is a warning.
        if let Some(g) = groups
            .iter()
            .find(|g| empty[(*g).clone()].iter().all(Option::is_some))
        {
            let reason = empty[g.start].clone().unwrap_or_default();
            return Err(ScoreError::EmptyTarget {
                target: g.start,
                reason,
            });
        }
        warnings.extend(empty.iter().flatten().cloned());
        Ok(Self {
            grid,
            weight: weight.into_iter().map(|w| w as f32).collect(),
            target,
            target_cells,
            members,
            outside_sum: targets.iter().map(|t| t.outside).sum(),
            outside_count: OutsideCount::Solid,
            warnings,
        })
    }

    /// The same scene counting cells outside the grid by `rule`.
    #[must_use]
    pub fn with_outside_count(mut self, rule: OutsideCount) -> Self {
        self.outside_count = rule;
        self
    }

    /// How cells outside the grid are counted.
    #[must_use]
    pub fn outside_count(&self) -> OutsideCount {
        self.outside_count
    }

    /// The grid.
    #[must_use]
    pub fn grid(&self) -> &Grid {
        &self.grid
    }

    /// `T`: cells inside some target.
    #[must_use]
    pub fn target_cells(&self) -> u64 {
        self.target_cells
    }

    /// The outside weight `Σ w̃_i` a model cell outside the grid contributes.
    #[must_use]
    pub fn outside_sum(&self) -> f64 {
        self.outside_sum
    }

    /// Problems worth telling the user (e.g. a target that is not watertight).
    #[must_use]
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// `C(v)` per cell, indexed like [`Grid::index`].
    #[must_use]
    pub fn weights(&self) -> &[f32] {
        &self.weight
    }

    /// Per target (in the order given to [`new`](Self::new)), or per group
    /// ([`new_grouped`](Self::new_grouped)): how the model in `scratch`
    /// (right after it was counted) covers its cells. Model cells outside
    /// the grid count as model cells outside every target.
    #[must_use]
    pub fn quality(&self, scratch: &VolumeScratch) -> Vec<crate::Quality> {
        let hits = scratch.hits();
        let model = hits.iter().filter(|&&h| h > 0).count() as u64 + scratch.counts().outside;
        let of = |mask: &[bool]| {
            let (mut both, mut target) = (0u64, 0u64);
            for (&h, &m) in hits.iter().zip(mask) {
                target += u64::from(m);
                both += u64::from(m && h > 0);
            }
            crate::Quality::from_counts(both, model, target)
        };
        if self.members.is_empty() {
            vec![of(&self.target)]
        } else {
            self.members.iter().map(|m| of(m)).collect()
        }
    }

    /// Whether cell `i` (linear index) is a target cell.
    #[must_use]
    pub fn is_target(&self, i: usize) -> bool {
        self.target[i]
    }
}

/// Why target `t` covers no cell of `grid`, in words.
fn empty_target(grid: &Grid, t: &VolumeTarget, solid: &Solid) -> String {
    let (lo, hi) = t.mesh.bounds();
    let (glo, ghi) = (grid.min(), grid.max());
    let (lo, hi) = (lo.as_dvec3(), hi.as_dvec3());
    let f = |v: glam::DVec3| format!("[{:.4}, {:.4}, {:.4}]", v.x, v.y, v.z);
    let place = "place it with `fit = \"grid\"` (or scale, rotate, translate)";
    if hi.cmplt(glo).any() || lo.cmpgt(ghi).any() {
        format!(
            "target `{}` lies outside the grid: its bounds are {} to {}, the grid's {} to {}; {place}",
            t.name,
            f(lo),
            f(hi),
            f(glo),
            f(ghi)
        )
    } else if let Solid::Mesh(m) = solid
        && m.boundary_edges() > 0
        && t.inside == Inside::Parity
    {
        format!(
            "target `{}` covers no cell: it is not watertight ({} boundary edges), so ray parity finds no inside; use inside = \"winding\"",
            t.name,
            m.boundary_edges()
        )
    } else {
        format!(
            "target `{}` covers no cell centre of the grid (bounds {} to {}; cells of {}): it is flat, smaller than a cell or not closed; {place}",
            t.name,
            f(lo),
            f(hi),
            f(grid.cell_size())
        )
    }
}

/// The linear indices of a span's cells inside the grid.
fn in_grid(grid: &Grid, s: Span) -> std::ops::Range<usize> {
    let d = grid.dims();
    let row_ok = s.y >= 0 && s.z >= 0 && (s.y as u64) < d.y as u64 && (s.z as u64) < d.z as u64;
    let (x0, x1) = (s.x0.max(0), s.x1.min(d.x as i64));
    if !row_ok || x0 >= x1 {
        return 0..0;
    }
    let base = grid.index(glam::UVec3::new(0, s.y as u32, s.z as u32));
    base + x0 as usize..base + x1 as usize
}

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

impl VolumeScene {
    /// Writes a PNG of the cells of one grid slice: the slice perpendicular
    /// to `axis` (0 = x, 1 = y, 2 = z) at cell `index`, coloured like the
    /// image overlay (target only light blue, model only red, both green,
    /// the rest white; cells hit twice or more darker). `hits` comes from
    /// [`VolumeScratch::hits`]. Each cell becomes `scale × scale` pixels; the
    /// image's up direction is the next axis (y for x and z slices, z for y).
    pub fn write_slice(
        &self,
        path: &Path,
        hits: &[u8],
        axis: usize,
        index: u32,
        scale: u32,
    ) -> Result<(), ScoreError> {
        let d = self.grid.dims();
        let bad = |reason: String| ScoreError::Image {
            path: path.to_path_buf(),
            reason,
        };
        if axis > 2 || index >= d[axis] || hits.len() != self.grid.len() || scale == 0 {
            return Err(bad(format!(
                "no slice {index} along axis {axis} of a {}×{}×{} grid with {} hit counts",
                d.x,
                d.y,
                d.z,
                hits.len()
            )));
        }
        // (horizontal, vertical) axes of the picture.
        let (u, v) = match axis {
            0 => (2, 1),
            1 => (0, 2),
            _ => (0, 1),
        };
        let (w, h) = (d[u] * scale, d[v] * scale);
        let img = image::RgbImage::from_fn(w, h, |px, py| {
            let mut c = glam::UVec3::ZERO;
            c[axis] = index;
            c[u] = px / scale;
            c[v] = d[v] - 1 - py / scale;
            let i = self.grid.index(c);
            let (t, m) = (self.target[i], hits[i]);
            image::Rgb(match (t, m) {
                (true, 0) => [150, 190, 240],
                (true, 1) => [0, 128, 0],
                (true, _) => [0, 70, 0],
                (false, 0) => [255, 255, 255],
                (false, 1) => [220, 40, 40],
                (false, _) => [130, 20, 20],
            })
        });
        crate::files::write_png(path, &img)
    }
}
