//! The paper's scores, as fitness functions.

use glam::Affine3A;
use shapegen_core::express::{Generator, ModelSink, Pending, ShapeId};
use shapegen_core::genome::Chromosome;
use shapegen_core::graph::Limits;
use shapegen_core::optimize::Fitness;

use crate::error::ScoreError;
use crate::image::{ImageCounts, ImageScratch, ImageTarget};
use crate::mesh::Mesh;
use crate::obj::ShapeMeshes;
use crate::raster::RasterShape;
use crate::solid::Solid;
use crate::volume::{VolumeCounts, VolumeScene, VolumeScratch};

/// Quintic smootherstep: `t³(6t² − 15t + 10)` with `t = clamp((x − a)/(b − a), 0, 1)`; 0 when `b <= a`.
#[must_use]
pub fn smootherstep(a: f64, b: f64, x: f64) -> f64 {
    if b <= a {
        return 0.0;
    }
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * t * (t * (6.0 * t - 15.0) + 10.0)
}

/// How self-overlap is counted by the linear score.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum OverlapCount {
    /// Cells hit two or more times (default).
    #[default]
    Cells,
    /// `Σ max(0, h − 1)` over cells with hit count `h`.
    Hits,
}

/// Which volume score, with its weights.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum VolumeScore {
    /// The paper's linear score: `Σ_{covered v} C(v) + N_out · Σ w̃ − w_self · N_self`.
    Linear {
        /// Penalty per self-overlap.
        w_self: f64,
        /// What counts as one self-overlap.
        overlap: OverlapCount,
    },
    /// The normalized form of the authors' code (needed for the paper's optima):
    /// `w_g·S(0,T,G) − w_b·S(0,2T,B+O) − w_l·S(L_min,L_max,L)`, or with
    /// `separate_overlap = Some(w_o)`:
    /// `w_g·S(0,T,G) − w_b·S(0,3T,B) − w_o·S(0,G+B,O) − w_l·S(L_min,L_max,L)`.
    /// `O` counts cells hit twice or more plus cells outside the grid.
    Normalized {
        /// `w_good`.
        w_good: f64,
        /// `w_bad`.
        w_bad: f64,
        /// `w_length` (parsimony).
        w_length: f64,
        /// `w_overlap` of the separate-overlap variant.
        separate_overlap: Option<f64>,
    },
}

impl VolumeScore {
    /// The score of a model with `counts` and `len` genes.
    #[must_use]
    pub fn score(
        &self,
        counts: &VolumeCounts,
        scene: &VolumeScene,
        len: usize,
        limits: &Limits,
    ) -> f64 {
        match *self {
            Self::Linear { w_self, overlap } => {
                let n_self = match overlap {
                    OverlapCount::Cells => counts.overlap_cells,
                    OverlapCount::Hits => counts.overlap_hits,
                };
                counts.weight + counts.outside as f64 * scene.outside_sum() - w_self * n_self as f64
            }
            Self::Normalized {
                w_good,
                w_bad,
                w_length,
                separate_overlap,
            } => {
                let t = scene.target_cells() as f64;
                let (g, b) = (counts.good as f64, counts.bad as f64);
                let o = (counts.overlap_cells + counts.outside) as f64;
                let length = match limits.max_len {
                    Some(max) => {
                        smootherstep(f64::from(limits.min_len), f64::from(max), len as f64)
                    }
                    None => 0.0,
                };
                let body = match separate_overlap {
                    None => {
                        w_good * smootherstep(0.0, t, g) - w_bad * smootherstep(0.0, 2.0 * t, b + o)
                    }
                    Some(w_o) => {
                        w_good * smootherstep(0.0, t, g)
                            - w_bad * smootherstep(0.0, 3.0 * t, b)
                            - w_o * smootherstep(0.0, g + b, o)
                    }
                };
                body - w_length * length
            }
        }
    }
}

/// Which image score, with its weights.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ImageScore {
    /// The paper's linear score `s_img = Σ_i Σ_p covered_i(p) · I_i(p)`.
    Linear,
    /// The normalized form: `w_g·S(0,T,G) − w_b·S(0,T,B) − w_l·S(L_min,L_max,L)`.
    Normalized {
        /// `w_good`.
        w_good: f64,
        /// `w_bad`.
        w_bad: f64,
        /// `w_length`.
        w_length: f64,
    },
}

impl ImageScore {
    /// The score of a model with `counts`, `len` genes, and `t` target pixels.
    #[must_use]
    pub fn score(&self, counts: &ImageCounts, t: u64, len: usize, limits: &Limits) -> f64 {
        match *self {
            Self::Linear => counts.weight,
            Self::Normalized {
                w_good,
                w_bad,
                w_length,
            } => {
                let t = t as f64;
                let length = limits.max_len.map_or(0.0, |m| {
                    smootherstep(f64::from(limits.min_len), f64::from(m), len as f64)
                });
                w_good * smootherstep(0.0, t, counts.good as f64)
                    - w_bad * smootherstep(0.0, t, counts.bad as f64)
                    - w_length * length
            }
        }
    }
}

/// What a [`ModelFitness`] scores models against: a volume or image scene.
///
/// A scene prepares one shape per mesh, owns nothing per evaluation (the
/// working memory is a [`Scene::Scratch`]), adds each emitted instance to the
/// scratch, and turns the resulting counts into a score.
pub trait Scene: Sync {
    /// A mesh prepared for this scene.
    type Shape: Sync;
    /// Per-thread working memory.
    type Scratch: Send;
    /// What one model covers.
    type Counts: Copy;
    /// The score form and its weights.
    type Score: Copy + Sync + std::fmt::Debug;

    /// Prepares `mesh` (named `name` in errors).
    fn prepare(&self, name: &str, mesh: &Mesh) -> Result<Self::Shape, ScoreError>;
    /// Fresh working memory.
    fn scratch(&self) -> Self::Scratch;
    /// Clears the working memory for a new model.
    fn begin(scratch: &mut Self::Scratch);
    /// Adds one instance of `shape`.
    fn add(&self, scratch: &mut Self::Scratch, shape: &Self::Shape, transform: &Affine3A);
    /// The counts of the model added since [`begin`](Scene::begin).
    fn counts(&self, scratch: &Self::Scratch) -> Self::Counts;
    /// The score of a model with `counts` and `len` genes.
    fn score(&self, score: &Self::Score, counts: &Self::Counts, len: usize, limits: &Limits)
    -> f64;
}

impl Scene for VolumeScene {
    type Shape = Solid;
    type Scratch = VolumeScratch;
    type Counts = VolumeCounts;
    type Score = VolumeScore;

    fn prepare(&self, name: &str, mesh: &Mesh) -> Result<Solid, ScoreError> {
        Solid::new(name, mesh)
    }
    fn scratch(&self) -> VolumeScratch {
        VolumeScratch::new(self)
    }
    fn begin(scratch: &mut VolumeScratch) {
        scratch.begin();
    }
    fn add(&self, scratch: &mut VolumeScratch, shape: &Solid, transform: &Affine3A) {
        scratch.add(self, shape, transform);
    }
    fn counts(&self, scratch: &VolumeScratch) -> VolumeCounts {
        scratch.counts()
    }
    fn score(
        &self,
        score: &VolumeScore,
        counts: &VolumeCounts,
        len: usize,
        limits: &Limits,
    ) -> f64 {
        score.score(counts, self, len, limits)
    }
}

/// One or more image targets (each an image with its camera).
#[derive(Clone, Debug)]
pub struct ImageTargets {
    targets: Vec<ImageTarget>,
    target_pixels: u64,
}

impl ImageTargets {
    /// The targets; fails if there are none.
    pub fn new(targets: Vec<ImageTarget>) -> Result<Self, ScoreError> {
        if targets.is_empty() {
            return Err(ScoreError::Target(
                "an image scene needs at least one target".into(),
            ));
        }
        let target_pixels = targets.iter().map(ImageTarget::target_pixels).sum();
        Ok(Self {
            targets,
            target_pixels,
        })
    }

    /// The targets.
    #[must_use]
    pub fn targets(&self) -> &[ImageTarget] {
        &self.targets
    }

    /// `T`: pixels with positive weight, over all targets.
    #[must_use]
    pub fn target_pixels(&self) -> u64 {
        self.target_pixels
    }

    /// Per target: how the model in `scratch` (right after it was counted)
    /// covers its pixels of positive weight.
    #[must_use]
    pub fn quality(&self, scratch: &ImageScratch) -> Vec<crate::Quality> {
        self.targets
            .iter()
            .enumerate()
            .map(|(i, t)| {
                let covered = scratch.covered(i);
                let (mut both, mut model) = (0u64, 0u64);
                for (&c, &w) in covered.iter().zip(&t.weights) {
                    model += u64::from(c);
                    both += u64::from(c && w > 0.0);
                }
                crate::Quality::from_counts(both, model, t.target_pixels())
            })
            .collect()
    }
}

impl Scene for ImageTargets {
    type Shape = RasterShape;
    type Scratch = ImageScratch;
    type Counts = ImageCounts;
    type Score = ImageScore;

    fn prepare(&self, name: &str, mesh: &Mesh) -> Result<RasterShape, ScoreError> {
        RasterShape::new(name, mesh)
    }
    fn scratch(&self) -> ImageScratch {
        ImageScratch::new(&self.targets)
    }
    fn begin(scratch: &mut ImageScratch) {
        scratch.begin();
    }
    fn add(&self, scratch: &mut ImageScratch, shape: &RasterShape, transform: &Affine3A) {
        scratch.add(&self.targets, shape, transform);
    }
    fn counts(&self, scratch: &ImageScratch) -> ImageCounts {
        scratch.counts_for(&self.targets)
    }
    fn score(&self, score: &ImageScore, counts: &ImageCounts, len: usize, limits: &Limits) -> f64 {
        score.score(counts, self.target_pixels, len, limits)
    }
}

/// Scores models of a generator against a [`Scene`]: expresses each
/// chromosome, adding every emitted instance to the scene's scratch, and
/// scores the counts. A [`Fitness`] for the optimizers.
#[derive(Clone, Debug)]
pub struct ModelFitness<G, S: Scene> {
    generator: G,
    scene: S,
    /// The meshes the shapes were prepared from (what a written model shows).
    meshes: ShapeMeshes,
    shapes: Vec<S::Shape>,
    score: S::Score,
    limits: Limits,
}

/// Volume scoring ([`VolumeScene`]) of a generator's models.
pub type VolumeFitness<G> = ModelFitness<G, VolumeScene>;

/// Image scoring ([`ImageTargets`]) of a generator's models.
pub type ImageFitness<G> = ModelFitness<G, ImageTargets>;

impl<G: Generator, S: Scene> ModelFitness<G, S> {
    /// A fitness for `generator`'s models on `scene`, with one mesh per shape
    /// (`shapes` must name the generator's shapes, in its order).
    pub fn new(
        generator: G,
        scene: S,
        shapes: &ShapeMeshes,
        score: S::Score,
    ) -> Result<Self, ScoreError> {
        shapes.check_for(generator.shapes())?;
        let prepared = (0..generator.shapes().len())
            .map(|i| scene.prepare(shapes.name(i as u16), shapes.mesh(i as u16)))
            .collect::<Result<_, _>>()?;
        let limits = *generator.graph().limits();
        Ok(Self {
            generator,
            scene,
            meshes: shapes.clone(),
            shapes: prepared,
            score,
            limits,
        })
    }

    /// Uses `limits` (`L_min`, `L_max`) for the length term instead of the
    /// generator graph's own (an experiment may set its own limits).
    #[must_use]
    pub fn with_limits(mut self, limits: Limits) -> Self {
        self.limits = limits;
        self
    }

    /// The scene.
    #[must_use]
    pub fn scene(&self) -> &S {
        &self.scene
    }

    /// The generator.
    #[must_use]
    pub fn generator(&self) -> &G {
        &self.generator
    }

    /// The meshes the shapes are scored with (the built-in ones or their
    /// replacements): what [`write_obj`](Self::write_obj) writes.
    #[must_use]
    pub fn meshes(&self) -> &ShapeMeshes {
        &self.meshes
    }

    /// The score form and its weights.
    #[must_use]
    pub fn score(&self) -> &S::Score {
        &self.score
    }

    /// The limits of the length term.
    #[must_use]
    pub fn limits(&self) -> &Limits {
        &self.limits
    }

    /// Writes the model of `chromosome` as OBJ with the meshes it is scored
    /// with, so the file shows exactly the scored model.
    pub fn write_obj<W: std::io::Write>(
        &self,
        out: W,
        chromosome: &Chromosome,
    ) -> std::io::Result<()> {
        let mut model = shapegen_core::express::Instances::default();
        self.generator.express(chromosome, &mut model);
        crate::obj::write_obj(out, &model.0, &self.meshes)
    }

    /// Expresses `chromosome` into `scratch` and returns its counts (the
    /// scratch keeps the coverage for reports, e.g. an image overlay).
    pub fn counts(
        &self,
        chromosome: &Chromosome,
        scratch: &mut (S::Scratch, Pending<G::State>),
    ) -> S::Counts {
        let (inner, pending) = scratch;
        S::begin(inner);
        let mut sink = SceneSink {
            scene: &self.scene,
            shapes: &self.shapes,
            scratch: inner,
        };
        self.generator.express_with(chromosome, &mut sink, pending);
        self.scene.counts(inner)
    }
}

impl<G, S> Fitness for ModelFitness<G, S>
where
    G: Generator,
    G::State: Send,
    S: Scene,
{
    type Scratch = (S::Scratch, Pending<G::State>);

    fn scratch(&self) -> Self::Scratch {
        (self.scene.scratch(), Pending::new())
    }

    fn evaluate(&self, chromosome: &Chromosome, scratch: &mut Self::Scratch) -> f64 {
        let counts = self.counts(chromosome, scratch);
        self.scene
            .score(&self.score, &counts, chromosome.len(), &self.limits)
    }
}

/// A [`ModelSink`] adding every emitted instance to a scene's scratch.
struct SceneSink<'a, S: Scene> {
    scene: &'a S,
    shapes: &'a [S::Shape],
    scratch: &'a mut S::Scratch,
}

impl<S: Scene> ModelSink for SceneSink<'_, S> {
    fn emit(&mut self, shape: ShapeId, transform: &Affine3A) {
        self.scene
            .add(self.scratch, &self.shapes[shape as usize], transform);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smootherstep_shape() {
        assert_eq!(smootherstep(0.0, 1.0, -1.0), 0.0);
        assert_eq!(smootherstep(0.0, 1.0, 2.0), 1.0);
        assert_eq!(smootherstep(0.0, 1.0, 0.5), 0.5);
        assert_eq!(smootherstep(0.0, 0.0, 3.0), 0.0);
        assert!(smootherstep(0.0, 10.0, 1.0) < 0.1);
    }
}
