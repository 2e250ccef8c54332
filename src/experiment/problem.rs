//! One generator scored against one scene, behind an object-safe trait so an
//! experiment can pick both at run time (the [`Registry`](crate::registry::Registry)
//! builds them).

use std::path::{Path, PathBuf};

use super::{ExperimentError, MethodParams};
use crate::express::{Generator, Instance, ShapeId};
use crate::gallery::Terminals;
use crate::genome::Chromosome;
use crate::glam::Affine3A;
use crate::graph::Graph;
use crate::optimize::{
    Budget, Checkpoint, FNV1A_START, Fitness, Observer, OptimizeError, Optimizer, Run, RunResult,
    fnv1a,
};
use crate::score::VolumeScene;
use crate::score::write_atomically;
use crate::score::write_obj;
use crate::score::{
    ImageScore, ImageTargets, ModelFitness, Quality, Scene, ShapeMeshes, VolumeScore,
};
use crate::score::{RenderMeshes, Renderer, Style, write_png_rgba};

/// A scene resolved from an experiment file, before a generator is chosen.
pub(crate) enum SceneSetup {
    /// A voxel scene; `targets` are the target meshes written as `target.obj`.
    Volume {
        scene: Box<VolumeScene>,
        score: VolumeScore,
        targets: ShapeMeshes,
    },
    /// Image targets.
    Image {
        scene: ImageTargets,
        score: ImageScore,
    },
}

/// A generator and a scored scene, ready to optimize.
pub(crate) trait Problem: Send + Sync {
    /// The generator graph with the experiment's limits.
    fn graph(&self) -> &Graph;
    /// Replaces the graph by one with the same nodes (fingerprint) and
    /// limits but other probabilities (a learned prior).
    fn set_graph(&mut self, graph: Graph);
    /// Runs `method` (from the start, or from `resume`).
    fn run(
        &self,
        method: &MethodParams,
        budget: &Budget,
        seed: u64,
        resume: Option<&Checkpoint>,
        observer: &mut dyn Observer,
    ) -> Result<RunResult, OptimizeError>;
    /// The fitness of one chromosome.
    fn evaluate(&self, chromosome: &Chromosome) -> f64;
    /// Per target: IoU, precision and recall of the model of `chromosome`.
    fn quality(&self, chromosome: &Chromosome) -> Vec<Quality>;
    /// Writes `best.obj` and the scene's pictures of `chromosome` into `dir`.
    fn write_model(
        &self,
        chromosome: &Chromosome,
        dir: &Path,
    ) -> Result<Vec<PathBuf>, ExperimentError>;
    /// One line about the scene.
    fn describe(&self) -> String;
    /// The names of the files `write_model` writes.
    fn model_files(&self) -> Vec<String>;
    /// What the scores depend on, part by part.
    fn fingerprint(&self) -> Vec<(&'static str, u64)>;
    /// The meshes the shapes are scored with.
    fn meshes(&self) -> &ShapeMeshes;
    /// The instances the model of `chromosome` emits.
    fn instances(&self, chromosome: &Chromosome) -> Vec<Instance>;
}

/// [`Problem`] for a generator `G` on a scene `S`.
pub(crate) struct ModelProblem<G, S: Scene> {
    pub graph: Graph,
    pub fitness: ModelFitness<G, S>,
    /// Target meshes written as `target.obj` (volume scenes).
    pub target_meshes: Option<ShapeMeshes>,
}

/// What a scene reports besides the score.
pub(crate) trait SceneOutputs: Scene {
    /// Pictures of the model held in `scratch` (right after it was counted).
    fn write_pictures(
        &self,
        scratch: &Self::Scratch,
        dir: &Path,
    ) -> Result<Vec<PathBuf>, ExperimentError>;
    /// Per target: how the model held in `scratch` covers it.
    fn quality_of(&self, scratch: &Self::Scratch) -> Vec<Quality>;
    /// One line about the scene.
    fn describe(&self) -> String;
    /// The names of the pictures `write_pictures` writes.
    fn picture_files(&self) -> Vec<String>;
    /// A fingerprint of everything in the scene that changes scores.
    fn fingerprint(&self) -> u64;
    /// Shaded pictures of the model (`instances` of `meshes`) as the scene
    /// sees it (an image target's camera); none by default.
    fn write_views(
        &self,
        meshes: &RenderMeshes,
        instances: &[Instance],
        dir: &Path,
    ) -> Result<Vec<PathBuf>, ExperimentError> {
        let _ = (meshes, instances, dir);
        Ok(Vec::new())
    }
    /// The names of the pictures `write_views` writes.
    fn view_files(&self) -> Vec<String> {
        Vec::new()
    }
}

impl SceneOutputs for VolumeScene {
    fn write_pictures(
        &self,
        scratch: &Self::Scratch,
        dir: &Path,
    ) -> Result<Vec<PathBuf>, ExperimentError> {
        let d = self.grid().dims();
        let mut written = Vec::new();
        for (axis, name) in ["x", "y", "z"].iter().enumerate() {
            // Enlarge small slices to about 400 pixels across.
            let across = (0..3)
                .filter(|&a| a != axis)
                .map(|a| d[a])
                .max()
                .unwrap_or(1);
            let scale = (400 / across.max(1)).clamp(1, 8);
            let path = dir.join(format!("slice_{name}.png"));
            self.write_slice(&path, &scratch.hits(), axis, d[axis] / 2, scale)?;
            written.push(path);
        }
        Ok(written)
    }

    fn quality_of(&self, scratch: &Self::Scratch) -> Vec<Quality> {
        self.quality(scratch)
    }

    fn picture_files(&self) -> Vec<String> {
        ["x", "y", "z"].map(|a| format!("slice_{a}.png")).to_vec()
    }

    fn fingerprint(&self) -> u64 {
        let mut h = fnv1a(
            FNV1A_START,
            format!("{:?} {:?}", self.grid(), self.outside_count()).as_bytes(),
        );
        for w in self.weights() {
            h = fnv1a(h, &w.to_bits().to_le_bytes());
        }
        for i in 0..self.grid().len() {
            h = fnv1a(h, &[u8::from(self.is_target(i))]);
        }
        h
    }

    fn describe(&self) -> String {
        let d = self.grid().dims();
        format!(
            "volume grid {}×{}×{} with {} target cells",
            d.x,
            d.y,
            d.z,
            self.target_cells()
        )
    }
}

/// One picture per image target: `stem.png`, or `stem_0.png`, `stem_1.png`, ...
fn per_target(stem: &str, targets: usize) -> Vec<String> {
    match targets {
        1 => vec![format!("{stem}.png")],
        n => (0..n).map(|i| format!("{stem}_{i}.png")).collect(),
    }
}

impl SceneOutputs for ImageTargets {
    fn write_pictures(
        &self,
        scratch: &Self::Scratch,
        dir: &Path,
    ) -> Result<Vec<PathBuf>, ExperimentError> {
        let mut written = Vec::new();
        for (i, (target, name)) in self.targets().iter().zip(self.picture_files()).enumerate() {
            let path = dir.join(name);
            target.write_overlay(&path, &scratch.covered(i))?;
            written.push(path);
        }
        Ok(written)
    }

    fn quality_of(&self, scratch: &Self::Scratch) -> Vec<Quality> {
        self.quality(scratch)
    }

    fn picture_files(&self) -> Vec<String> {
        per_target("overlay", self.targets().len())
    }

    fn write_views(
        &self,
        meshes: &RenderMeshes,
        instances: &[Instance],
        dir: &Path,
    ) -> Result<Vec<PathBuf>, ExperimentError> {
        let mut renderer = Renderer::new();
        let mut written = Vec::new();
        for (target, name) in self.targets().iter().zip(self.view_files()) {
            let mut picture =
                renderer.picture(meshes, instances, target.camera(), &Style::default());
            target.draw_outline(&mut picture);
            let path = dir.join(name);
            write_png_rgba(&path, &picture)?;
            written.push(path);
        }
        Ok(written)
    }

    fn view_files(&self) -> Vec<String> {
        per_target("view", self.targets().len())
    }

    fn fingerprint(&self) -> u64 {
        let mut h = FNV1A_START;
        for t in self.targets() {
            h = fnv1a(h, format!("{:?}", t.camera()).as_bytes());
            for w in t.weights() {
                h = fnv1a(h, &w.to_bits().to_le_bytes());
            }
        }
        h
    }

    fn describe(&self) -> String {
        let t = &self.targets()[0].camera();
        format!(
            "{} image target(s) of {}×{} with {} target pixels",
            self.targets().len(),
            t.width,
            t.height,
            self.target_pixels()
        )
    }
}

impl<G, S> Problem for ModelProblem<G, S>
where
    G: Generator + Send,
    G::State: Send,
    S: SceneOutputs + Send + Sync,
    S::Shape: Send + Sync,
    S::Score: Send + Sync,
{
    fn graph(&self) -> &Graph {
        &self.graph
    }

    fn set_graph(&mut self, graph: Graph) {
        debug_assert_eq!(graph.fingerprint(), self.graph.fingerprint());
        self.graph = graph;
    }

    fn run(
        &self,
        method: &MethodParams,
        budget: &Budget,
        seed: u64,
        resume: Option<&Checkpoint>,
        observer: &mut dyn Observer,
    ) -> Result<RunResult, OptimizeError> {
        method.run_from(Run {
            graph: &self.graph,
            fitness: &self.fitness,
            budget: *budget,
            seed,
            start: resume,
            observer,
        })
    }

    fn evaluate(&self, chromosome: &Chromosome) -> f64 {
        self.fitness
            .evaluate(chromosome, &mut self.fitness.scratch())
    }

    fn quality(&self, chromosome: &Chromosome) -> Vec<Quality> {
        let mut scratch = self.fitness.scratch();
        self.fitness.counts(chromosome, &mut scratch);
        self.fitness.scene().quality_of(&scratch.0)
    }

    fn write_model(
        &self,
        chromosome: &Chromosome,
        dir: &Path,
    ) -> Result<Vec<PathBuf>, ExperimentError> {
        let obj = dir.join("best.obj");
        let mut text = Vec::new();
        self.fitness
            .write_obj(&mut text, chromosome)
            .map_err(|e| ExperimentError::write(&obj, e))?;
        write_atomically(&obj, &text)?;
        let mut written = vec![obj];
        if let Some(targets) = &self.target_meshes {
            let instances: Vec<Instance> = (0..targets.len())
                .map(|i| Instance::new(i as ShapeId, Affine3A::IDENTITY))
                .collect();
            let path = dir.join("target.obj");
            let mut text = Vec::new();
            write_obj(&mut text, &instances, targets)
                .map_err(|e| ExperimentError::write(&path, e))?;
            write_atomically(&path, &text)?;
            written.push(path);
        }
        let mut scratch = self.fitness.scratch();
        self.fitness.counts(chromosome, &mut scratch);
        written.extend(self.fitness.scene().write_pictures(&scratch.0, dir)?);
        let meshes = crate::gallery::render_meshes(&self.fitness, Terminals::Auto)?;
        let instances = crate::gallery::Models::instances(&self.fitness, chromosome);
        let png = dir.join("best.png");
        write_png_rgba(
            &png,
            &crate::gallery::best_view_picture_of(&meshes, &instances, 600)?,
        )?;
        written.push(png);
        written.extend(self.fitness.scene().write_views(&meshes, &instances, dir)?);
        Ok(written)
    }

    fn describe(&self) -> String {
        self.fitness.scene().describe()
    }

    fn model_files(&self) -> Vec<String> {
        let mut files = vec!["best.obj".to_string()];
        if self.target_meshes.is_some() {
            files.push("target.obj".into());
        }
        files.extend(self.fitness.scene().picture_files());
        files.push("best.png".into());
        files.extend(self.fitness.scene().view_files());
        files
    }

    fn meshes(&self) -> &ShapeMeshes {
        self.fitness.meshes()
    }

    fn instances(&self, chromosome: &Chromosome) -> Vec<Instance> {
        crate::gallery::Models::instances(&self.fitness, chromosome)
    }

    fn fingerprint(&self) -> Vec<(&'static str, u64)> {
        let meshes = self.fitness.meshes();
        let mut shapes = FNV1A_START;
        for i in 0..meshes.len() {
            let m = meshes.mesh(i as u16);
            shapes = fnv1a(shapes, meshes.name(i as u16).as_bytes());
            for p in &m.positions {
                for c in p.to_array() {
                    shapes = fnv1a(shapes, &c.to_bits().to_le_bytes());
                }
            }
            for t in &m.triangles {
                for v in t {
                    shapes = fnv1a(shapes, &v.to_le_bytes());
                }
            }
        }
        let score = format!("{:?} {:?}", self.fitness.score(), self.fitness.limits());
        vec![
            (
                "generator and limits",
                fnv1a(FNV1A_START, format!("{:?}", self.graph.spec()).as_bytes()),
            ),
            ("shape meshes", shapes),
            (
                "targets, grid and cameras",
                self.fitness.scene().fingerprint(),
            ),
            ("score and weights", fnv1a(FNV1A_START, score.as_bytes())),
        ]
    }
}
