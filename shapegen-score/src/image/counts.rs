//! Counting one model's silhouettes against image targets.

use glam::Affine3A;
use shapegen_core::express::ShapeId;

use super::ImageTarget;
use crate::instance_cache::InstanceCache;
use crate::raster::{Layers, RasterShape, Rasterizer, View, Write};

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

/// Per-thread working memory: per target, how many triangles of the model
/// cover each pixel centre, and the rasterizer.
///
/// Every instance adds its triangles' edges to per-row differences of the
/// counts (see [`Rasterizer`](crate::Rasterizer)); no instance paints over
/// another. The counts are read once per model, over the part of each row
/// the model touched, and only that part is cleared for the next model, so
/// an evaluation costs what the model's silhouettes cross.
///
/// The writes of every instance added by shape (see
/// [`add_shape`](Self::add_shape)) are remembered, and an instance added
/// again is replayed from them.
#[derive(Clone, Debug)]
pub struct ImageScratch {
    work: Work,
    cache: WriteCache,
}

/// What adding an instance writes: per target its counts, and the views and
/// rasterizer that draw into them; per target, the counts of the instance
/// alone, drawn there first when its writes are to be recorded.
#[derive(Clone, Debug)]
struct Work {
    layers: Vec<Layers>,
    views: Vec<View>,
    rasterizer: Rasterizer,
    alone: Vec<Layers>,
}

/// Per instance, its writes into every target's counts, each target's
/// after a [`Write::Target`] marker, [packed](Write::pack) (see
/// [`InstanceCache`]).
type WriteCache = InstanceCache<u64, ()>;

/// Writes the cache holds at most (8 bytes each: 64 MiB); when full, it
/// starts over. A 250-gene tree with the paper's leaf in the tree-sketch
/// scene writes about 17,000 when none of its instances were seen before:
/// room for two generations of 200 such trees, about what a GA reuses.
const CACHE_WRITES: usize = 1 << 23;

/// Instances the cache holds at most; when full, it starts over.
const CACHE_INSTANCES: usize = 1 << 18;

impl ImageScratch {
    /// Working memory for `targets`.
    #[must_use]
    pub fn new(targets: &[ImageTarget]) -> Self {
        let layers: Vec<Layers> = targets
            .iter()
            .map(|t| Layers::new(t.camera.width, t.camera.height))
            .collect();
        Self {
            work: Work {
                // Made here, not at the first record: evaluations after the
                // first ones allocate nothing.
                alone: layers.clone(),
                layers,
                views: targets.iter().map(|t| View::new(&t.camera)).collect(),
                rasterizer: Rasterizer::new(),
            },
            cache: WriteCache::new(CACHE_WRITES, CACHE_INSTANCES),
        }
    }

    /// Starts a new model.
    pub fn begin(&mut self) {
        self.work.layers.iter_mut().for_each(Layers::clear);
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
    /// makes that one's writes again instead of being drawn, with the same
    /// covered pixels (its record holds only whether each pixel is covered,
    /// not by how many of its triangles: see `Layers::move_into`). An
    /// instance's writes are recorded the second time it is added (the
    /// first, it is drawn as by `add`: most instances of a random
    /// population are never seen again). Only shapes with more than 16
    /// vertices are remembered (boxes and the built-in leaf are drawn
    /// faster than their writes are recorded; the rule is
    /// `RasterShape::worth_replaying`), and only for images less than
    /// 65,536 pixels wide and high.
    pub fn add_shape(
        &mut self,
        targets: &[ImageTarget],
        shape: ShapeId,
        raster: &RasterShape,
        transform: &Affine3A,
    ) {
        self.take_targets(targets);
        let n = targets.len();
        let fits = (self.work.layers.iter().take(n)).all(|l| Write::fits(l.size().0, l.size().1));
        if !(raster.worth_replaying() && fits) {
            self.work.draw(n, raster, transform);
            return;
        }
        self.cache.add_recording_second(
            shape,
            transform,
            &mut self.work,
            |work| work.draw(n, raster, transform),
            |work, writes, ()| {
                // Every record starts with a target marker.
                let mut target = 0;
                for &w in writes {
                    match Write::unpack(w) {
                        Write::Target(i) => target = i as usize,
                        w => work.layers[target].redo(w),
                    }
                }
            },
            |work, writes| {
                let Work {
                    layers,
                    views,
                    rasterizer,
                    alone,
                } = work;
                // Drawn alone, then moved: the rasterizer's inner loops stay
                // as they are, and the record has two writes a run of
                // covered pixels (and a widen a row).
                let seen = layers.iter_mut().zip(views.iter()).zip(alone.iter_mut());
                for (i, ((layers, view), alone)) in seen.take(n).enumerate() {
                    writes.push(Write::Target(i as u32).pack());
                    rasterizer.draw(view, raster, transform, alone);
                    alone.move_into(layers, writes);
                }
            },
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
    /// Reads the counts over the part of each row the model touched; the
    /// weights are summed in a fixed order, so the same model gives the
    /// same sum.
    #[must_use]
    pub fn counts_for(&self, targets: &[ImageTarget]) -> ImageCounts {
        let mut counts = ImageCounts::default();
        for (target, layers) in targets.iter().zip(&self.work.layers) {
            let width = target.camera.width as usize;
            let mut lanes = [0.0f64; 4];
            let (mut good, mut bad) = (0u64, 0u64);
            layers.rows(|row, c0, diff| {
                // The last cell (right of the image) counts for no pixel.
                let diff = &diff[..diff.len().min(width - c0 as usize)];
                let at = row as usize * width + c0 as usize;
                let (l, g, b) = count_row(diff, &target.weights[at..at + diff.len()]);
                for k in 0..4 {
                    lanes[k] += l[k];
                }
                (good, bad) = (good + g, bad + b);
            });
            counts.weight += (lanes[0] + lanes[1]) + (lanes[2] + lanes[3]);
            counts.good += good;
            counts.bad += bad;
        }
        counts
    }

    /// Which pixels of target `i` (row-major, row 0 at the top) the model
    /// added since [`begin`](Self::begin) covers.
    #[must_use]
    pub fn covered(&self, i: usize) -> Vec<bool> {
        let layers = &self.work.layers[i];
        let (w, h) = layers.size();
        let mut out = vec![false; (w * h) as usize];
        layers.covered_spans(|s| {
            out[(s.row * w + s.c0) as usize..(s.row * w + s.c1) as usize].fill(true);
        });
        out
    }
}

impl Work {
    /// Prepares the views of `targets` where they differ from the ones the
    /// scratch has (new cameras); whether any did.
    fn take_views(&mut self, targets: &[ImageTarget]) -> bool {
        let mut changed = false;
        let each = (self.layers.iter_mut().zip(&mut self.alone)).zip(&mut self.views);
        for (target, ((layers, alone), view)) in targets.iter().zip(each) {
            if view.camera() != &target.camera {
                *view = View::new(&target.camera);
                let size = (target.camera.width, target.camera.height);
                if layers.size() != size {
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
}

/// The weight sums (in four lanes), `G` and `B` of the covered pixels of
/// one row part from its count differences and weights. Kept in locals (a
/// closure adding to its caller's sums would go through memory at every
/// pixel), the weights in four independent lanes: one running sum would
/// make every covered pixel wait for the previous addition.
#[inline]
fn count_row(diff: &[i32], weights: &[f32]) -> ([f64; 4], u64, u64) {
    let mut lanes = [0.0f64; 4];
    let (mut good, mut bad) = (0u64, 0u64);
    let mut count = 0;
    let mut diff4 = diff.chunks_exact(4);
    let mut weights4 = weights.chunks_exact(4);
    for (d, wt) in (&mut diff4).zip(&mut weights4) {
        for k in 0..4 {
            count += d[k];
            let m = count > 0;
            lanes[k] += if m { f64::from(wt[k]) } else { 0.0 };
            good += u64::from(m & (wt[k] > 0.0));
            bad += u64::from(m & (wt[k] < 0.0));
        }
    }
    for (d, &wt) in diff4.remainder().iter().zip(weights4.remainder()) {
        count += d;
        let m = count > 0;
        lanes[0] += if m { f64::from(wt) } else { 0.0 };
        good += u64::from(m & (wt > 0.0));
        bad += u64::from(m & (wt < 0.0));
    }
    (lanes, good, bad)
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
