//! [`ModelFitness`]: a generator's models scored against a [`Scene`], the
//! [`Fitness`] the optimizers run.

use glam::Affine3A;
use shapegen_core::express::{Generator, ModelSink, Pending, ShapeId};
use shapegen_core::genome::Chromosome;
use shapegen_core::graph::Limits;
use shapegen_core::optimize::Fitness;

use crate::error::ScoreError;
use crate::image::ImageTargets;
use crate::mesh::Mesh;
use crate::shapes::ShapeMeshes;
use crate::volume::VolumeScene;

/// Quintic smootherstep: `t³(6t² − 15t + 10)` with `t = clamp((x − a)/(b − a), 0, 1)`; 0 when `b <= a`.
#[must_use]
pub fn smootherstep(a: f64, b: f64, x: f64) -> f64 {
    if b <= a {
        return 0.0;
    }
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * t * (t * (6.0 * t - 15.0) + 10.0)
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
    /// Forgets what `scratch` remembers of the models it scored (the
    /// instances it would replay), keeping its memory: the models that
    /// follow are scored as if never seen. A scene that remembers nothing
    /// has nothing to do.
    fn forget(_scratch: &mut Self::Scratch) {}
    /// Adds one instance of `shape`, the fitness's shape number `id` (a
    /// scratch belongs to the fitness that made it, so a scene may remember
    /// what it did for an `id` and transform).
    fn add(
        &self,
        scratch: &mut Self::Scratch,
        id: ShapeId,
        shape: &Self::Shape,
        transform: &Affine3A,
    );
    /// The counts of the model added since [`begin`](Scene::begin).
    fn counts(&self, scratch: &Self::Scratch) -> Self::Counts;
    /// The score of a model with `counts` and `len` genes.
    fn score(&self, score: &Self::Score, counts: &Self::Counts, len: usize, limits: &Limits)
    -> f64;
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

    /// Forgets what `scratch` remembers of the models it scored, keeping
    /// its memory ([`Scene::forget`]): to time models never seen without
    /// timing a new scratch's first use of its memory, or to start over
    /// after the meshes changed.
    pub fn forget(&self, scratch: &mut (S::Scratch, Pending<G::State>)) {
        S::forget(&mut scratch.0);
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
            .add(self.scratch, shape, &self.shapes[shape as usize], transform);
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
