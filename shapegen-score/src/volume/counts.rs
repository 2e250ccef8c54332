//! Counting one model's cells against a scene: hit counts per cell and the
//! sums the scores need.

use glam::Affine3A;
use shapegen_core::express::ShapeId;
use wide::u8x16;

use super::target::in_grid;
use super::{OutsideCount, VolumeScene};
use crate::grid::Grid;
use crate::instance_cache::InstanceCache;
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

/// A scratch cell: the hit count in the low 7 bits (saturating at 127),
/// whether the cell is a target cell in the top bit (copied from the scene,
/// so that counting reads one byte a cell).
const TARGET: u8 = 0x80;
const HITS: u8 = 0x7f;

/// Adds one instance's span to the hit counts and `counts`: branch-free per
/// cell (instances overlap at random, so branches would mispredict), with
/// the sums kept in registers for the span. `weight` is the scene's weight
/// per cell, or `None` when it depends on target membership alone (the sum
/// is then `good · w_target + bad · w_other`, added by the caller).
#[inline]
fn count_span(cells: &mut [u8], weight: Option<&[f32]>, counts: &mut VolumeCounts) {
    let (mut first, mut good, mut second) = (0u64, 0u64, 0u64);
    match weight {
        None => {
            for chunk in cells.chunks_mut(CHUNK) {
                let (f, g, s) = count_chunk(chunk);
                first += u64::from(f);
                good += u64::from(g);
                second += u64::from(s);
            }
        }
        Some(weight) => {
            let mut w_sum = 0.0f64;
            for (c, &w) in cells.iter_mut().zip(weight) {
                let (f, g, s) = count_cell(c);
                first += u64::from(f);
                good += u64::from(g);
                second += u64::from(s);
                w_sum += if f == 1 { f64::from(w) } else { 0.0 };
            }
            counts.weight += w_sum;
        }
    }
    counts.good += good;
    counts.bad += first - good;
    counts.overlap_cells += second;
    // Every cell hit before this instance is hit again.
    counts.overlap_hits += cells.len() as u64 - first;
}

/// Cells a [`count_chunk`] takes at most: its byte sums cannot overflow.
const CHUNK: usize = 240;

/// [`count_cell`] over at most [`CHUNK`] cells, with the sums in bytes so
/// that the loop vectorizes sixteen or more cells an instruction (sums in
/// `u64` would widen every byte first).
#[inline(always)]
fn count_chunk(cells: &mut [u8]) -> (u8, u8, u8) {
    debug_assert!(cells.len() <= CHUNK);
    let (mut first, mut good, mut second) = (0u8, 0u8, 0u8);
    for c in cells {
        let (f, g, s) = count_cell(c);
        first = first.wrapping_add(f);
        good = good.wrapping_add(g);
        second = second.wrapping_add(s);
    }
    (first, good, second)
}

/// One more hit on cell `c` (saturating): whether it is the cell's first,
/// the first on a target cell, and its second, as 0 or 1.
#[inline(always)]
fn count_cell(c: &mut u8) -> (u8, u8, u8) {
    let old = *c;
    let h = old & HITS;
    *c = old + u8::from(h < HITS);
    let first = u8::from(h == 0);
    (first, first & (old >> 7), u8::from(h == 1))
}

impl Work {
    /// Voxelizes one instance into the counts (and its runs into `record`,
    /// when it is being cached).
    fn voxelize(
        &mut self,
        record: Option<&mut Vec<(u32, u32)>>,
        scene: &VolumeScene,
        solid: &Solid,
        transform: &Affine3A,
    ) {
        let Self {
            cells: scratch,
            touched,
            voxelizer,
            counts,
        } = self;
        let grid = &scene.grid;
        let by_solid = scene.outside_count == OutsideCount::Solid;
        if !by_solid {
            counts.outside += aabb_cells_outside(grid, solid, transform);
        }
        // The runs are kept to reset, then counted all at once.
        let from = touched.len();
        voxelizer.spans(grid, solid, transform, |s| {
            let cells = in_grid(grid, s);
            if by_solid {
                counts.outside += (s.x1 - s.x0) as u64 - cells.len() as u64;
            }
            if !cells.is_empty() {
                touched.push((cells.start as u32, cells.len() as u32));
            }
        });
        let runs = &touched[from..];
        if let Some(record) = record {
            record.extend_from_slice(runs);
        }
        count_runs(scratch, counts, scene, runs);
    }
}

/// Counts the in-grid runs `(first cell, length)` of an instance (which the
/// caller keeps to reset): the one step that voxelizing and replaying
/// share, so both give the same counts. `cells` holds [`PAD`] bytes past
/// the grid's.
fn count_runs(
    cells: &mut [u8],
    counts: &mut VolumeCounts,
    scene: &VolumeScene,
    runs: &[(u32, u32)],
) {
    // Weights that depend on target membership alone are added by the
    // caller (`add_weight`); others are summed cell by cell.
    match scene.uniform {
        Some(_) => count_runs_unweighted(cells, counts, runs),
        None => {
            for &(start, len) in runs {
                let range = start as usize..(start + len) as usize;
                count_span(
                    &mut cells[range.clone()],
                    Some(&scene.weight[range]),
                    counts,
                );
            }
        }
    }
}

/// [`count_span`] without weights of each of `runs`: those at most a
/// [`WORD`] long a word at a time ([`count_word`]), their sums kept per
/// lane in bytes over up to 255 runs (a lane gains at most one a run, so
/// a byte cannot overflow), then added up.
fn count_runs_unweighted(cells: &mut [u8], counts: &mut VolumeCounts, runs: &[(u32, u32)]) {
    let (mut first, mut good, mut second, mut words) = (0, 0, 0, 0);
    for runs in runs.chunks(usize::from(u8::MAX)) {
        let mut lanes = [u8x16::ZERO; 3];
        for &(start, len) in runs {
            let (start, len) = (start as usize, len as usize);
            if len <= WORD {
                // Lanes are 0xff where true: subtracting one adds 1 a lane.
                let hit = count_word(cells, start, len);
                lanes = [lanes[0] - hit[0], lanes[1] - hit[1], lanes[2] - hit[2]];
                words += len as u64;
            } else {
                count_span(&mut cells[start..start + len], None, counts);
            }
        }
        first += lane_sum(lanes[0]);
        good += lane_sum(lanes[1]);
        second += lane_sum(lanes[2]);
    }
    counts.good += good;
    counts.bad += first - good;
    counts.overlap_cells += second;
    counts.overlap_hits += words - first;
}

/// Runs at most this long are counted (and reset) as one 16-byte word.
const WORD: usize = 16;

/// Bytes the scratch holds past the grid's cells: a run's word may reach
/// that far past its end (those bytes are read and written back unchanged).
const PAD: usize = WORD;

/// Per lane, `0xff` in the first `len` lanes of `RUNS[len]`, else `0`.
const RUNS: [[u8; WORD]; WORD + 1] = {
    let mut runs = [[0; WORD]; WORD + 1];
    let mut len = 0;
    while len <= WORD {
        let mut i = 0;
        while i < len {
            runs[len][i] = 0xff;
            i += 1;
        }
        len += 1;
    }
    runs
};

/// The lanes of a run of `len` cells, `0 <= len <=` [`WORD`] (see [`RUNS`]).
#[inline(always)]
fn run_lanes(len: usize) -> u8x16 {
    u8x16::new(RUNS[len])
}

/// One more hit on each of the `len` cells from `start` of `cells`
/// (`1 <= len <=` [`WORD`]; `cells` reaches at least [`WORD`] bytes past
/// `start`), as [`count_cell`] adds one, the 16 bytes from `start` worked
/// at once and the lanes beyond the run left as they were: the lanes whose
/// hit was the cell's first, the first on a target cell, and its second
/// (`0xff` where true).
#[inline(always)]
fn count_word(cells: &mut [u8], start: usize, len: usize) -> [u8x16; 3] {
    debug_assert!((1..=WORD).contains(&len));
    let bytes: &mut [u8; WORD] = (&mut cells[start..start + WORD])
        .try_into()
        .expect("a word is 16 bytes");
    let old = u8x16::new(*bytes);
    let run = run_lanes(len);
    let h = old & u8x16::splat(HITS);
    let first = h.cmp_eq(u8x16::ZERO) & run;
    let target = (old | u8x16::splat(TARGET)).cmp_eq(old);
    // One more hit in each lane of the run below saturation.
    let below = h.cmp_eq(u8x16::splat(HITS)) ^ u8x16::splat(0xff);
    *bytes = (old + (below & run & u8x16::splat(1))).to_array();
    [first, first & target, h.cmp_eq(u8x16::splat(1)) & run]
}

/// The sum of the lanes of `v`: bytes added in pairs, then the four
/// 16-bit sums of each half by one multiply.
#[inline]
fn lane_sum(v: u8x16) -> u64 {
    let v = u128::from_le_bytes(v.to_array());
    let half = |x: u64| {
        let pairs = (x & 0x00ff_00ff_00ff_00ff) + ((x >> 8) & 0x00ff_00ff_00ff_00ff);
        pairs.wrapping_mul(0x0001_0001_0001_0001) >> 48
    };
    half(v as u64) + half((v >> 64) as u64)
}

/// Clears the hit counts of the run `(start, len)` of `cells` (see
/// [`count_runs`]), keeping the target flags.
#[inline]
fn reset_run(cells: &mut [u8], (start, len): (u32, u32)) {
    let (start, len) = (start as usize, len as usize);
    if (1..=WORD).contains(&len) {
        let bytes: &mut [u8; WORD] = (&mut cells[start..start + WORD])
            .try_into()
            .expect("a word is 16 bytes");
        let keep = (run_lanes(len) & u8x16::splat(HITS)) ^ u8x16::splat(0xff);
        *bytes = (u8x16::new(*bytes) & keep).to_array();
    } else {
        for c in &mut cells[start..start + len] {
            *c &= TARGET;
        }
    }
}

/// Per-thread working memory of volume evaluations: per cell its hit count
/// (all zero between evaluations) and target flag, the runs to reset, the
/// voxelizer, and the cell runs of the instances voxelized so far (see
/// [`add_shape`](Self::add_shape)).
#[derive(Clone, Debug)]
pub struct VolumeScratch {
    work: Work,
    cache: RunCache,
}

/// What adding an instance writes: per cell its hit count and target flag,
/// the runs to reset, the voxelizer and the counts.
#[derive(Clone, Debug)]
struct Work {
    cells: Vec<u8>,
    touched: Vec<(u32, u32)>,
    voxelizer: Voxelizer,
    counts: VolumeCounts,
}

/// The cell runs `(first cell, length)` of instances added before, and
/// their cells outside the grid (see [`InstanceCache`]).
type RunCache = InstanceCache<(u32, u32), u64>;

/// Runs the cache holds at most (8 bytes each); when full, it starts over.
const CACHE_RUNS: usize = 1 << 21;

/// Instances the cache holds at most (about 80 bytes each; instances
/// outside the grid have no runs); when full, it starts over.
const CACHE_INSTANCES: usize = 1 << 18;

impl VolumeScratch {
    /// Working memory for `scene`.
    #[must_use]
    pub fn new(scene: &VolumeScene) -> Self {
        Self {
            work: Work {
                cells: scene
                    .target
                    .iter()
                    .map(|&t| if t { TARGET } else { 0 })
                    .chain([0; PAD])
                    .collect(),
                touched: Vec::new(),
                voxelizer: Voxelizer::new(),
                counts: VolumeCounts::default(),
            },
            cache: RunCache::new(CACHE_RUNS, CACHE_INSTANCES),
        }
    }

    /// The memory of one scratch over `grid` (bytes): one byte a cell.
    #[must_use]
    pub fn bytes_needed(grid: &Grid) -> u64 {
        grid.len() as u64 + PAD as u64
    }

    /// Starts counting a new model.
    pub fn begin(&mut self) {
        for &run in &self.work.touched {
            reset_run(&mut self.work.cells, run);
        }
        self.work.touched.clear();
        self.work.counts = VolumeCounts::default();
    }

    /// Forgets the instances remembered for [`add_shape`](Self::add_shape),
    /// keeping the memory: the instances that follow are voxelized as if
    /// never seen.
    pub fn forget(&mut self) {
        self.cache.clear();
    }

    /// Adds one instance of `solid`, placed by `transform`.
    pub fn add(&mut self, scene: &VolumeScene, solid: &Solid, transform: &Affine3A) {
        let (good, bad) = (self.work.counts.good, self.work.counts.bad);
        self.work.voxelize(None, scene, solid, transform);
        self.add_weight(scene, good, bad);
    }

    /// [`add`](Self::add) for shape `shape` of the fitness that made this
    /// scratch: an instance of the same shape with the same transform as
    /// one added before (in this or an earlier model) replays that one's
    /// cell runs instead of voxelizing again, with the same counts.
    pub fn add_shape(
        &mut self,
        scene: &VolumeScene,
        shape: ShapeId,
        solid: &Solid,
        transform: &Affine3A,
    ) {
        let (good, bad) = (self.work.counts.good, self.work.counts.bad);
        self.cache.add(
            shape,
            transform,
            &mut self.work,
            |work, runs, outside| {
                work.counts.outside += outside;
                work.touched.extend_from_slice(runs);
                count_runs(&mut work.cells, &mut work.counts, scene, runs);
            },
            |work, runs| {
                let outside = work.counts.outside;
                work.voxelize(Some(runs), scene, solid, transform);
                work.counts.outside - outside
            },
        );
        self.add_weight(scene, good, bad);
    }

    /// Adds the weight of the cells newly covered since the counts were
    /// `good` and `bad`, when the scene's weights depend on target
    /// membership alone.
    fn add_weight(&mut self, scene: &VolumeScene, good: u64, bad: u64) {
        if let Some((w_target, w_other)) = scene.uniform {
            // This instance's newly covered cells, of each kind.
            let (good, bad) = (self.work.counts.good - good, self.work.counts.bad - bad);
            self.work.counts.weight +=
                good as f64 * f64::from(w_target) + bad as f64 * f64::from(w_other);
        }
    }

    /// The counts of the model added since [`begin`](Self::begin).
    #[must_use]
    pub fn counts(&self) -> VolumeCounts {
        self.work.counts
    }

    /// How many instances hit each cell (saturating at 127), indexed like
    /// [`Grid::index`], for the model added since [`begin`](Self::begin).
    #[must_use]
    pub fn hits(&self) -> Vec<u8> {
        let grid = &self.work.cells[..self.work.cells.len() - PAD];
        grid.iter().map(|c| c & HITS).collect()
    }

    /// How many instances hit cell `i` (linear index), saturating at 127.
    #[must_use]
    pub fn hits_at(&self, i: usize) -> u8 {
        self.work.cells[i] & HITS
    }
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;

    /// The counting rules written out cell by cell, as the docs of
    /// [`VolumeCounts`] state them.
    fn reference(cells: &mut [u8], weight: Option<&[f32]>, counts: &mut VolumeCounts) {
        for (i, c) in cells.iter_mut().enumerate() {
            let (target, h) = (*c & TARGET != 0, *c & HITS);
            if h == 0 {
                counts.weight += weight.map_or(0.0, |w| f64::from(w[i]));
                if target {
                    counts.good += 1;
                } else {
                    counts.bad += 1;
                }
            }
            if h == 1 {
                counts.overlap_cells += 1;
            }
            counts.overlap_hits += u64::from(h > 0);
            if h < HITS {
                *c += 1;
            }
        }
    }

    /// Cells with every flag and hit count, the saturated 127 among them.
    fn cell() -> impl Strategy<Value = u8> {
        prop_oneof![0u8..4, Just(HITS - 1), Just(HITS), Just(TARGET | HITS)]
            .prop_flat_map(|h| prop_oneof![Just(h), Just(h | TARGET)])
    }

    /// A cache that fills up starts over and still counts right: a tiny
    /// capacity, instances repeated across models, against fresh scratches.
    #[test]
    fn a_full_cache_starts_over() {
        use glam::{Quat, Vec3};
        let grid = Grid::new(Vec3::splat(-2.0), Vec3::splat(2.0), glam::UVec3::splat(16)).unwrap();
        let scene = VolumeScene::new(grid, &[]).unwrap();
        let solid = Solid::new("cube", &crate::mesh::Mesh::unit_cube()).unwrap();
        let at = |x: f32| {
            Affine3A::from_scale_rotation_translation(
                Vec3::splat(1.3),
                Quat::from_rotation_y(x),
                Vec3::new(x, 0.0, 0.0),
            )
        };
        let mut cached = VolumeScratch::new(&scene);
        cached.cache.capacity = 20;
        let mut by_count = VolumeScratch::new(&scene);
        by_count.cache.capacity_instances = 2;
        for model in [[0.1, 0.5, 0.1], [0.5, 0.9, 0.1], [0.9, 0.9, 0.5]] {
            cached.begin();
            by_count.begin();
            let mut fresh = VolumeScratch::new(&scene);
            for x in model {
                cached.add_shape(&scene, 0, &solid, &at(x));
                by_count.add_shape(&scene, 0, &solid, &at(x));
                fresh.add(&scene, &solid, &at(x));
            }
            assert_eq!(cached.counts(), fresh.counts());
            assert_eq!(cached.hits(), fresh.hits());
            assert_eq!(by_count.counts(), fresh.counts());
        }
        // Three distinct instances were added: a cache that never started
        // over would hold them all.
        assert!(cached.cache.len() < 3, "the cache never filled up");
    }

    /// A scratch that forgets remembers no instance and counts the next
    /// model as a fresh scratch does.
    #[test]
    fn a_scratch_that_forgets_voxelizes_again() {
        use glam::Vec3;
        let grid = Grid::new(Vec3::splat(-2.0), Vec3::splat(2.0), glam::UVec3::splat(16)).unwrap();
        let scene = VolumeScene::new(grid, &[]).unwrap();
        let solid = Solid::new("cube", &crate::mesh::Mesh::unit_cube()).unwrap();
        let at = Affine3A::from_scale(Vec3::splat(1.7));
        let mut scratch = VolumeScratch::new(&scene);
        scratch.begin();
        scratch.add_shape(&scene, 0, &solid, &at);
        assert_eq!(scratch.cache.len(), 1);
        scratch.forget();
        assert_eq!(scratch.cache.len(), 0);
        scratch.begin();
        scratch.add_shape(&scene, 0, &solid, &at);
        let mut fresh = VolumeScratch::new(&scene);
        fresh.add(&scene, &solid, &at);
        assert_eq!(scratch.counts(), fresh.counts());
        assert_eq!(scratch.hits(), fresh.hits());
        assert_eq!(scratch.cache.len(), 1);
    }

    proptest! {
        /// A run of at most a word, counted and reset word-wise, equals the
        /// reference, at any place of the cells and up to their padded
        /// end; the bytes around it are left as they were.
        #[test]
        fn count_word_matches_the_reference(
            cells in proptest::collection::vec(cell(), 1..40),
            at in any::<proptest::sample::Index>(),
            len in 1..=WORD,
        ) {
            let start = at.index(cells.len());
            let len = len.min(cells.len() - start);
            let mut padded = cells.clone();
            padded.extend([0; PAD]);
            let (mut fast, mut slow) = (padded.clone(), padded);
            let (mut a, mut b) = (VolumeCounts::default(), VolumeCounts::default());
            count_runs_unweighted(&mut fast, &mut a, &[(start as u32, len as u32)]);
            reference(&mut slow[start..start + len], None, &mut b);
            prop_assert_eq!(&fast, &slow);
            prop_assert_eq!(a, b);
            reset_run(&mut fast, (start as u32, len as u32));
            for (i, (c, orig)) in fast.iter().zip(cells.iter().chain(&[0; PAD])).enumerate() {
                let want = if (start..start + len).contains(&i) { orig & TARGET } else { *orig };
                prop_assert_eq!(*c, want, "cell {}", i);
            }
        }

        /// [`lane_sum`] adds the lanes of any vector.
        #[test]
        fn lane_sum_adds_every_lane(v in any::<[u8; WORD]>()) {
            let sum: u64 = v.iter().map(|&b| u64::from(b)).sum();
            prop_assert_eq!(lane_sum(u8x16::new(v)), sum);
        }

        /// Many runs, counted at once, equal the reference run by run, on
        /// cells hit up to saturation: runs of at most a word (more than
        /// a byte's worth, so a lane may take more first hits than a byte
        /// holds and the sums must be taken on the way) and longer ones.
        #[test]
        fn runs_counted_at_once_match_the_reference(
            cells in proptest::collection::vec(
                prop_oneof![3 => prop_oneof![Just(0), Just(TARGET)], 1 => cell()],
                1..6000,
            ),
            runs in proptest::collection::vec(
                (
                    any::<proptest::sample::Index>(),
                    prop_oneof![6 => 1..=4usize, 3 => 1..=WORD, 1 => 1..100usize],
                ),
                0..1500,
            ),
        ) {
            let mut padded = cells.clone();
            padded.extend([0; PAD]);
            let (mut fast, mut slow) = (padded.clone(), padded);
            let (mut a, mut b) = (VolumeCounts::default(), VolumeCounts::default());
            let runs: Vec<(u32, u32)> = runs
                .into_iter()
                .map(|(at, len)| {
                    let start = at.index(cells.len());
                    (start as u32, len.min(cells.len() - start) as u32)
                })
                .collect();
            for &(start, len) in &runs {
                let (start, len) = (start as usize, len as usize);
                reference(&mut slow[start..start + len], None, &mut b);
            }
            count_runs_unweighted(&mut fast, &mut a, &runs);
            prop_assert_eq!(fast, slow);
            prop_assert_eq!(a, b);
        }

        /// The chunked count equals the reference on spans across several
        /// chunks, with and without per-cell weights.
        #[test]
        fn count_span_matches_the_reference(
            cells in proptest::collection::vec(cell(), 0..3 * CHUNK + 7),
            weighted in any::<bool>(),
        ) {
            let weight: Vec<f32> = (0..cells.len()).map(|i| (i % 7) as f32 * 0.25).collect();
            let weight = weighted.then_some(weight.as_slice());
            let (mut fast, mut slow) = (cells.clone(), cells);
            let (mut a, mut b) = (VolumeCounts::default(), VolumeCounts::default());
            count_span(&mut fast, weight, &mut a);
            reference(&mut slow, weight, &mut b);
            prop_assert_eq!(fast, slow);
            prop_assert_eq!(a, b);
        }
    }
}
