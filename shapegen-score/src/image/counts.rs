//! Counting one model's silhouettes against image targets.

use glam::Affine3A;
use shapegen_core::express::ShapeId;

use super::ImageTarget;
use super::target::{CLASSES, WeightClasses};
use crate::instance_cache::InstanceCache;
use crate::raster::{Coverage, Layers, RasterShape, Rasterizer, View, WORD};

/// What one model's silhouettes cover, summed over the targets.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ImageCounts {
    /// `Σ I(p)` over covered pixels (the paper's `s_img`).
    pub weight: f64,
    /// `G`: covered pixels with positive weight.
    pub good: u64,
    /// `B`: covered pixels with negative weight.
    pub bad: u64,
}

/// Per-thread working memory: per target, which pixels the model covers,
/// in two parts, and the rasterizer.
///
/// A pixel is covered by the model iff some instance covers it. An
/// instance drawn (see [`Rasterizer`]) adds its
/// triangles' edges to per-row differences of the model's triangle counts
/// (a pixel is covered there iff its count is positive); an instance
/// replayed (see [`add_shape`](Self::add_shape)) adds its runs of covered
/// pixels to a bitmap of the model's coverage, a few word ORs a run. No
/// instance paints over another. The two are read together once per
/// model, the counts cell by cell over the part of each row that drawn
/// instances touched and the bitmap 64 pixels at a time, and only those
/// parts are cleared for the next model.
#[derive(Clone, Debug)]
pub struct ImageScratch {
    work: Work,
    cache: RunCache,
}

/// What adding an instance writes: per target the model's coverage by
/// replayed instances and its counts of drawn ones, the views and
/// rasterizer that draw, and per target the counts of an instance drawn
/// alone to record its runs.
#[derive(Clone, Debug)]
struct Work {
    coverage: Vec<Coverage>,
    layers: Vec<Layers>,
    views: Vec<View>,
    rasterizer: Rasterizer,
    alone: Vec<Layers>,
}

/// Per instance, its runs of covered pixels in every target, each
/// target's after a [`Record::Target`] marker, [packed](Record::pack)
/// (see [`InstanceCache`]).
type RunCache = InstanceCache<u64, ()>;

/// Runs the cache holds at most (8 bytes each: 64 MiB); when full, it
/// starts over. A 250-gene tree with the paper's leaf in the tree-sketch
/// scene has about 6,000 when none of its instances were seen before:
/// room for several generations of 200 such trees, more than a GA reuses.
const CACHE_RUNS: usize = 1 << 23;

/// Instances the cache holds at most; when full, it starts over.
const CACHE_INSTANCES: usize = 1 << 18;

/// One entry of an instance's record in the cache.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Record {
    /// Pixels `c0..c1` of row `row` are covered.
    Run { row: u32, c0: u32, c1: u32 },
    /// The runs that follow are in target `i` of the scratch's.
    Target(u32),
}

/// The top bit of a packed [`Record::Target`].
const TARGET: u64 = 1 << 63;

/// The largest width or height of images whose runs are recorded
/// ([`Record::pack`] keeps rows and columns in 17 bits).
const RECORDED_SIDE: u32 = (1 << 17) - 1;

impl Record {
    /// The entry in 8 bytes: a run as its row and columns in 17 bits each,
    /// a marker as its target under the top bit.
    fn pack(self) -> u64 {
        match self {
            Self::Run { row, c0, c1 } => u64::from(row) << 34 | u64::from(c0) << 17 | u64::from(c1),
            Self::Target(i) => TARGET | u64::from(i),
        }
    }

    /// The entry `bits` [packs](Self::pack).
    #[inline]
    fn unpack(bits: u64) -> Self {
        const SIDE: u64 = RECORDED_SIDE as u64;
        if bits & TARGET != 0 {
            Self::Target(bits as u32)
        } else {
            Self::Run {
                row: (bits >> 34) as u32,
                c0: (bits >> 17 & SIDE) as u32,
                c1: (bits & SIDE) as u32,
            }
        }
    }
}

impl ImageScratch {
    /// Working memory for `targets`.
    #[must_use]
    pub fn new(targets: &[ImageTarget]) -> Self {
        let size = |t: &ImageTarget| (t.camera().width, t.camera().height);
        Self {
            work: Work {
                coverage: targets
                    .iter()
                    .map(|t| Coverage::new(size(t).0, size(t).1))
                    .collect(),
                layers: targets
                    .iter()
                    .map(|t| Layers::new(size(t).0, size(t).1))
                    .collect(),
                views: targets.iter().map(|t| View::new(t.camera())).collect(),
                rasterizer: Rasterizer::new(),
                alone: targets
                    .iter()
                    .map(|t| Layers::new(size(t).0, size(t).1))
                    .collect(),
            },
            cache: RunCache::new(CACHE_RUNS, CACHE_INSTANCES),
        }
    }

    /// Starts a new model.
    pub fn begin(&mut self) {
        self.work.coverage.iter_mut().for_each(Coverage::clear);
        self.work.layers.iter_mut().for_each(Layers::clear);
    }

    /// Forgets the instances remembered for [`add_shape`](Self::add_shape),
    /// keeping the memory: the instances that follow are drawn as if never
    /// seen.
    pub fn forget(&mut self) {
        self.cache.clear();
    }

    /// Adds one instance, seen by each of `targets` (those the scratch was
    /// made for; others are taken in, at the cost of preparing them).
    pub fn add(&mut self, targets: &[ImageTarget], shape: &RasterShape, transform: &Affine3A) {
        self.take_targets(targets);
        self.work.draw(targets.len(), shape, transform);
    }

    /// [`add`](Self::add) for shape `shape` of the fitness that made this
    /// scratch: an instance of the same shape with the same transform as
    /// one added before (in this or an earlier model, with the same targets)
    /// adds that one's runs of covered pixels again instead of being drawn.
    /// An instance's runs are recorded the second time it is added (the
    /// first, it is drawn as by `add`: most instances of a random
    /// population are never seen again). Only shapes with more than 16
    /// vertices are remembered (boxes and the built-in leaf are drawn
    /// about as fast as their runs are replayed; the rule is
    /// `RasterShape::worth_replaying`), and only for images at most
    /// 131,071 pixels wide and high.
    pub fn add_shape(
        &mut self,
        targets: &[ImageTarget],
        shape: ShapeId,
        raster: &RasterShape,
        transform: &Affine3A,
    ) {
        self.take_targets(targets);
        let n = targets.len();
        let fits = (self.work.coverage.iter().take(n)).all(|c| {
            let (w, h) = c.size();
            w <= RECORDED_SIDE && h <= RECORDED_SIDE
        });
        if !(raster.worth_replaying() && fits) {
            self.work.draw(n, raster, transform);
            return;
        }
        self.cache.add_recording_second(
            shape,
            transform,
            &mut self.work,
            |work| work.draw(n, raster, transform),
            |work, runs, ()| {
                // Every record starts with a target marker.
                let mut coverage = &mut work.coverage[0];
                for &bits in runs {
                    match Record::unpack(bits) {
                        Record::Target(i) => coverage = &mut work.coverage[i as usize],
                        Record::Run { row, c0, c1 } => coverage.add_run(row, c0, c1),
                    }
                }
            },
            |work, runs| work.record(n, raster, transform, runs),
        );
    }

    /// Prepares the views of `targets` where they differ from the ones the
    /// scratch has, and forgets the instances drawn for the old ones.
    fn take_targets(&mut self, targets: &[ImageTarget]) {
        if self.work.take_views(targets) {
            self.cache.clear();
        }
    }

    /// The counts of the model added since [`begin`](Self::begin), over
    /// all targets (each covered pixel counted once per target).
    ///
    /// Reads the coverage over the part of each row the model touched. A
    /// target whose weights take at most four non-zero values (a PNG
    /// target's two) is counted by value, 64 pixels at a time, its weight
    /// summed as each value times its covered pixels; another has its
    /// covered pixels' weights summed in row-major order. Either way the
    /// same model gives the same sum.
    #[must_use]
    pub fn counts_for(&self, targets: &[ImageTarget]) -> ImageCounts {
        let mut counts = ImageCounts::default();
        let each = self.work.coverage.iter().zip(&self.work.layers);
        for (target, (coverage, layers)) in targets.iter().zip(each) {
            let c = match target.classes() {
                Some(classes) => count_by_class(coverage, layers, classes),
                None => count_by_pixel(coverage, layers, target.weights()),
            };
            counts.weight += c.weight;
            counts.good += c.good;
            counts.bad += c.bad;
        }
        counts
    }

    /// Which pixels of target `i` (row-major, row 0 at the top) the model
    /// added since [`begin`](Self::begin) covers.
    #[must_use]
    pub fn covered(&self, i: usize) -> Vec<bool> {
        let coverage = &self.work.coverage[i];
        let (w, h) = coverage.size();
        let mut out = vec![false; (w * h) as usize];
        coverage.with_layers(&self.work.layers[i], |row, k, mut bits| {
            while bits != 0 {
                let c = k * WORD + bits.trailing_zeros();
                out[(row * w + c) as usize] = true;
                bits &= bits - 1;
            }
        });
        out
    }
}

impl Work {
    /// Prepares the views of `targets` where they differ from the ones the
    /// scratch has (new cameras); whether any did.
    fn take_views(&mut self, targets: &[ImageTarget]) -> bool {
        let mut changed = false;
        let each = (self.coverage.iter_mut().zip(&mut self.layers)).zip(&mut self.alone);
        for (target, (((coverage, layers), alone), view)) in
            targets.iter().zip(each.zip(&mut self.views))
        {
            let camera = target.camera();
            if view.camera() != camera {
                *view = View::new(camera);
                let size = (camera.width, camera.height);
                if coverage.size() != size {
                    *coverage = Coverage::new(size.0, size.1);
                    *layers = Layers::new(size.0, size.1);
                    *alone = Layers::new(size.0, size.1);
                }
                changed = true;
            }
        }
        changed
    }

    /// Draws one instance into the counts of the first `targets` targets.
    fn draw(&mut self, targets: usize, shape: &RasterShape, transform: &Affine3A) {
        for (layers, view) in self.layers.iter_mut().zip(&self.views).take(targets) {
            self.rasterizer.draw(view, shape, transform, layers);
        }
    }

    /// Draws one instance alone in each of the first `targets` targets,
    /// adds its runs of covered pixels to their coverage, and appends them
    /// to `record`, each target's after its marker.
    fn record(
        &mut self,
        targets: usize,
        shape: &RasterShape,
        transform: &Affine3A,
        record: &mut Vec<u64>,
    ) {
        let each = (self.coverage.iter_mut().zip(&self.views)).zip(&mut self.alone);
        for (i, ((coverage, view), alone)) in each.take(targets).enumerate() {
            record.push(Record::Target(i as u32).pack());
            self.rasterizer.draw(view, shape, transform, alone);
            alone.take_runs(|row, c0, c1| {
                coverage.add_run(row, c0, c1);
                record.push(Record::Run { row, c0, c1 }.pack());
            });
        }
    }
}

/// [`ImageCounts`] of the pixels `coverage` or `layers` cover against
/// weights in `classes`: per class, its covered pixels counted a word at a
/// time; the weight is each class's weight times that count, summed in
/// class order.
fn count_by_class(coverage: &Coverage, layers: &Layers, classes: &WeightClasses) -> ImageCounts {
    let words = coverage.words();
    let mut n = [0u64; CLASSES];
    coverage.with_layers(layers, |row, k, bits| {
        let masks = &classes.masks[row as usize * words + k as usize];
        for (n, mask) in n.iter_mut().zip(masks) {
            *n += u64::from((bits & mask).count_ones());
        }
    });
    let mut counts = ImageCounts::default();
    for (&v, &n) in classes.values.iter().zip(&n) {
        counts.weight += f64::from(v) * n as f64;
        counts.good += if v > 0.0 { n } else { 0 };
        counts.bad += if v < 0.0 { n } else { 0 };
    }
    counts
}

/// [`ImageCounts`] of the pixels `coverage` or `layers` cover against
/// `weights` (row-major), pixel by pixel in row-major order.
fn count_by_pixel(coverage: &Coverage, layers: &Layers, weights: &[f32]) -> ImageCounts {
    let width = coverage.size().0;
    let mut counts = ImageCounts::default();
    coverage.with_layers(layers, |row, k, mut bits| {
        while bits != 0 {
            let c = k * WORD + bits.trailing_zeros();
            let w = weights[(row * width + c) as usize];
            counts.weight += f64::from(w);
            counts.good += u64::from(w > 0.0);
            counts.bad += u64::from(w < 0.0);
            bits &= bits - 1;
        }
    });
    counts
}

#[cfg(test)]
mod tests {
    use glam::{DVec3, Quat, Vec3};

    use super::*;
    use crate::camera::Camera;
    use crate::mesh::Mesh;

    /// A cache that fills up starts over and still counts right (a tiny
    /// capacity of writes, or of instances, against fresh scratches), and
    /// one whose targets change forgets what it drew for the old ones.
    #[test]
    fn a_full_cache_starts_over_and_new_targets_clear_it() {
        let camera = |phi: f64| {
            Camera::orbit(phi, 0.3, 6.0, DVec3::ZERO, 1.0, 0.1, 100.0, (48, 36)).unwrap()
        };
        let target = |phi| vec![ImageTarget::new(camera(phi), vec![1.0; 48 * 36]).unwrap()];
        let (targets, turned) = (target(-1.2), target(0.4));
        // A shape worth replaying.
        let leaf = RasterShape::new("trunk", &Mesh::trunk()).unwrap();
        assert!(leaf.worth_replaying());
        let at = |x: f32| {
            Affine3A::from_scale_rotation_translation(
                Vec3::splat(1.3),
                Quat::from_rotation_y(x),
                Vec3::new(x, 0.0, 0.0),
            )
        };
        let mut by_writes = ImageScratch::new(&targets);
        by_writes.cache.capacity = 20;
        let mut by_count = ImageScratch::new(&targets);
        by_count.cache.capacity_instances = 2;
        let mut switching = ImageScratch::new(&targets);
        let models = [
            [0.1, 0.5, 0.1],
            [0.5, 0.9, 0.1],
            [0.9, 0.9, 0.5],
            [0.9, 0.5, 0.9],
            [0.5, 0.5, 0.5],
        ];
        for (round, model) in models.into_iter().enumerate() {
            let now = if round == 1 { &turned } else { &targets };
            for scratch in [&mut by_writes, &mut by_count, &mut switching] {
                scratch.begin();
            }
            let mut fresh = ImageScratch::new(&targets);
            let mut fresh_now = ImageScratch::new(now);
            for x in model {
                by_writes.add_shape(&targets, 0, &leaf, &at(x));
                by_count.add_shape(&targets, 0, &leaf, &at(x));
                switching.add_shape(now, 0, &leaf, &at(x));
                fresh.add(&targets, &leaf, &at(x));
                fresh_now.add(now, &leaf, &at(x));
            }
            let expected = fresh.counts_for(&targets);
            assert!(expected.good > 0);
            assert_eq!(by_writes.counts_for(&targets), expected);
            assert_eq!(by_count.counts_for(&targets), expected);
            assert_eq!(switching.covered(0), fresh_now.covered(0));
        }
        // Three distinct instances were added: a cache that never started
        // over would hold them all.
        assert!(by_writes.cache.len() < 3, "the cache never filled up");
        assert!(by_count.cache.len() < 3, "the cache never filled up");
    }
}
