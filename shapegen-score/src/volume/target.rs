//! Volume targets voxelized and combined into one weight per cell.

use glam::Affine3A;

use crate::error::ScoreError;
use crate::grid::Grid;
use crate::mesh::Mesh;
use crate::solid::{Inside, Solid};
use crate::voxelize::{Span, Voxelizer};

use super::VolumeScratch;

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
    pub(super) grid: Grid,
    /// `C(v)` per cell.
    pub(super) weight: Vec<f32>,
    /// Whether each cell is inside some target.
    pub(super) target: Vec<bool>,
    pub(super) target_cells: u64,
    /// Per group of targets (only with two or more groups): whether each
    /// cell is inside one of the group's targets.
    pub(super) members: Vec<Vec<bool>>,
    /// `Σ_i w̃_i`: the weight of a model cell outside the grid (outside every target).
    pub(super) outside_sum: f64,
    /// `(C of target cells, C of other cells)` when the weight depends on
    /// target membership alone (one target, say): counting then reads no
    /// weights.
    pub(super) uniform: Option<(f32, f32)>,
    pub(super) outside_count: OutsideCount,
    pub(super) warnings: Vec<String>,
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
        let mut warnings = Vec::new();
        let mut vox = Voxelizer::new();
        // Per target: its cells in the grid, as runs of linear indices in
        // increasing order (each within one row), and why it covers no
        // cell (`None` if it covers some).
        let mut runs: Vec<Vec<std::ops::Range<usize>>> = Vec::with_capacity(targets.len());
        let mut empty: Vec<Option<String>> = Vec::new();
        for t in targets {
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
            // One target's spans never overlap (each row's crossings in pairs).
            let mut own = Vec::new();
            vox.spans(&grid, &solid, &Affine3A::IDENTITY, |s| {
                let span = in_grid(&grid, s);
                if !span.is_empty() {
                    own.push(span);
                }
            });
            own.sort_unstable_by_key(|r| r.start);
            empty.push(own.is_empty().then(|| empty_target(&grid, t, &solid)));
            runs.push(own);
        }
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
        let (weight, target, members) = combine(&grid, targets, groups, &runs);
        let target_cells = target.iter().filter(|&&t| t).count() as u64;
        let uniform = uniform_weights(&weight, &target);
        Ok(Self {
            grid,
            uniform,
            weight,
            target,
            target_cells,
            members,
            outside_sum: targets.iter().map(|t| t.outside).sum(),
            outside_count: OutsideCount::Solid,
            warnings,
        })
    }

    /// The memory a scene over `grid` with `groups` groups of targets
    /// keeps (bytes: the `f32` weights, target and per-group flags), for
    /// checks before a large grid is allocated. Building it takes little
    /// more: the targets' runs of cells, summed one row at a time.
    #[must_use]
    pub fn bytes_needed(grid: &Grid, groups: usize) -> u64 {
        let per_cell = 4 + 1 + if groups > 1 { groups as u64 } else { 0 };
        grid.len() as u64 * per_cell
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

/// The weight `C` of every cell (summed over `targets` in order, in
/// `f64`, then rounded to `f32`), whether it is inside some target, and,
/// for two or more `groups`, whether it is inside one of each group's
/// targets: from each target's `runs` of cells (see
/// [`VolumeScene::new_grouped`]), one row of the grid at a time, so that
/// only the kept arrays span the grid.
fn combine(
    grid: &Grid,
    targets: &[VolumeTarget],
    groups: &[std::ops::Range<usize>],
    runs: &[Vec<std::ops::Range<usize>>],
) -> (Vec<f32>, Vec<bool>, Vec<Vec<bool>>) {
    let (n, row) = (grid.len(), grid.dims().x as usize);
    let mut weight = Vec::with_capacity(n);
    let mut target = Vec::with_capacity(n);
    // (Not `vec![Vec::with_capacity(n); k]`: a clone of an empty vector
    // keeps none of its capacity.)
    let groups_kept = if groups.len() > 1 { groups.len() } else { 0 };
    let mut members: Vec<Vec<bool>> = (0..groups_kept).map(|_| Vec::with_capacity(n)).collect();
    let group_of: Vec<Option<usize>> = (0..targets.len())
        .map(|k| groups.iter().position(|g| g.contains(&k)))
        .collect();
    let (mut sum, mut inside, mut any) = (vec![0.0f64; row], vec![false; row], vec![false; row]);
    let mut member = vec![vec![false; row]; members.len()];
    let mut next = vec![0; runs.len()];
    for start in (0..n).step_by(row.max(1)) {
        let end = start + row;
        sum.fill(0.0);
        any.fill(false);
        member.iter_mut().for_each(|m| m.fill(false));
        for (k, t) in targets.iter().enumerate() {
            inside.fill(false);
            while let Some(r) = runs[k].get(next[k]).filter(|r| r.start < end) {
                inside[r.start - start..r.end - start].fill(true);
                next[k] += 1;
            }
            for ((w, a), &i) in sum.iter_mut().zip(any.iter_mut()).zip(&inside) {
                *w += if i { t.fill } else { t.outside };
                *a |= i;
            }
            if let Some(m) = group_of[k].and_then(|g| member.get_mut(g)) {
                m.iter_mut().zip(&inside).for_each(|(m, &i)| *m |= i);
            }
        }
        weight.extend(sum.iter().map(|&w| w as f32));
        target.extend_from_slice(&any);
        for (all, m) in members.iter_mut().zip(&member) {
            all.extend_from_slice(m);
        }
    }
    (weight, target, members)
}

/// `(w_target, w_other)` if every target cell has weight `w_target` and
/// every other cell `w_other` (bit for bit).
fn uniform_weights(weight: &[f32], target: &[bool]) -> Option<(f32, f32)> {
    // One pass: the first weight of each kind, and whether any differs.
    let mut first: [Option<u32>; 2] = [None, None];
    let mut same = true;
    for (w, &t) in weight.iter().zip(target) {
        let bits = w.to_bits();
        same &= *first[usize::from(t)].get_or_insert(bits) == bits;
    }
    same.then(|| {
        let w = |k: usize| f32::from_bits(first[k].unwrap_or(0));
        (w(1), w(0))
    })
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
pub(super) fn in_grid(grid: &Grid, s: Span) -> std::ops::Range<usize> {
    let d = grid.dims();
    let row_ok = s.y >= 0 && s.z >= 0 && (s.y as u64) < d.y as u64 && (s.z as u64) < d.z as u64;
    let (x0, x1) = (s.x0.max(0), s.x1.min(d.x as i64));
    if !row_ok || x0 >= x1 {
        return 0..0;
    }
    let base = grid.index(glam::UVec3::new(0, s.y as u32, s.z as u32));
    base + x0 as usize..base + x1 as usize
}
