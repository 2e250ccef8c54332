//! The paper's scores, as fitness functions.

use shapegen_core::express::{Generator, Pending};
use shapegen_core::genome::Chromosome;
use shapegen_core::graph::Limits;
use shapegen_core::optimize::Fitness;

use crate::error::ScoreError;
use crate::image::{ImageCounts, ImageScratch, ImageSink, ImageTarget};
use crate::obj::ShapeMeshes;
use crate::raster::RasterShape;
use crate::solid::Solid;
use crate::volume::{VolumeCounts, VolumeScene, VolumeScratch, VolumeSink};

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

/// Scores models of a generator against a [`VolumeScene`].
#[derive(Clone, Debug)]
pub struct VolumeFitness<G> {
    generator: G,
    scene: VolumeScene,
    solids: Vec<Solid>,
    score: VolumeScore,
    limits: Limits,
}

impl<G: Generator> VolumeFitness<G> {
    /// A fitness for `generator`'s models on `scene`, with one mesh per shape.
    pub fn new(
        generator: G,
        scene: VolumeScene,
        shapes: &ShapeMeshes,
        score: VolumeScore,
    ) -> Result<Self, ScoreError> {
        let solids = (0..generator.shapes().len())
            .map(|i| Solid::new(shapes.name(i as u16), shapes.mesh(i as u16)))
            .collect::<Result<_, _>>()?;
        let limits = *generator.graph().limits();
        Ok(Self {
            generator,
            scene,
            solids,
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
    pub fn scene(&self) -> &VolumeScene {
        &self.scene
    }

    /// The counts of `chromosome`'s model (for reports and tests).
    pub fn counts(
        &self,
        chromosome: &Chromosome,
        scratch: &mut (VolumeScratch, Pending<G::State>),
    ) -> VolumeCounts {
        let (volume, pending) = scratch;
        volume.begin();
        let mut sink = VolumeSink {
            scene: &self.scene,
            solids: &self.solids,
            scratch: volume,
        };
        self.generator.express_with(chromosome, &mut sink, pending);
        volume.counts()
    }
}

impl<G> Fitness for VolumeFitness<G>
where
    G: Generator,
    G::State: Send,
{
    type Scratch = (VolumeScratch, Pending<G::State>);

    fn scratch(&self) -> Self::Scratch {
        (VolumeScratch::new(&self.scene), Pending::new())
    }

    fn evaluate(&self, chromosome: &Chromosome, scratch: &mut Self::Scratch) -> f64 {
        let counts = self.counts(chromosome, scratch);
        self.score.score(
            &counts,
            &self.scene,
            chromosome.len(),
            self.generator.graph().limits(),
        )
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

/// Scores models of a generator against image targets.
#[derive(Clone, Debug)]
pub struct ImageFitness<G> {
    generator: G,
    targets: Vec<ImageTarget>,
    shapes: Vec<RasterShape>,
    score: ImageScore,
    limits: Limits,
    target_pixels: u64,
}

impl<G: Generator> ImageFitness<G> {
    /// A fitness for `generator`'s models against `targets`, with one mesh per shape.
    pub fn new(
        generator: G,
        targets: Vec<ImageTarget>,
        shapes: &ShapeMeshes,
        score: ImageScore,
    ) -> Result<Self, ScoreError> {
        if targets.is_empty() {
            return Err(ScoreError::Target(
                "an image fitness needs at least one target".into(),
            ));
        }
        let raster = (0..generator.shapes().len())
            .map(|i| RasterShape::new(shapes.name(i as u16), shapes.mesh(i as u16)))
            .collect::<Result<_, _>>()?;
        let limits = *generator.graph().limits();
        let target_pixels = targets.iter().map(ImageTarget::target_pixels).sum();
        Ok(Self {
            generator,
            targets,
            shapes: raster,
            score,
            limits,
            target_pixels,
        })
    }

    /// Uses `limits` for the length term instead of the generator graph's own.
    #[must_use]
    pub fn with_limits(mut self, limits: Limits) -> Self {
        self.limits = limits;
        self
    }

    /// The targets.
    #[must_use]
    pub fn targets(&self) -> &[ImageTarget] {
        &self.targets
    }

    /// Renders `chromosome`'s silhouettes into `scratch` and returns the counts
    /// (the masks stay readable through [`ImageScratch::covered`]).
    pub fn counts(
        &self,
        chromosome: &Chromosome,
        scratch: &mut (ImageScratch, Pending<G::State>),
    ) -> ImageCounts {
        let (image, pending) = scratch;
        image.begin();
        let mut sink = ImageSink {
            targets: &self.targets,
            shapes: &self.shapes,
            scratch: image,
        };
        self.generator.express_with(chromosome, &mut sink, pending);
        image.counts()
    }
}

impl<G> Fitness for ImageFitness<G>
where
    G: Generator,
    G::State: Send,
{
    type Scratch = (ImageScratch, Pending<G::State>);

    fn scratch(&self) -> Self::Scratch {
        (ImageScratch::new(&self.targets), Pending::new())
    }

    fn evaluate(&self, chromosome: &Chromosome, scratch: &mut Self::Scratch) -> f64 {
        let counts = self.counts(chromosome, scratch);
        self.score
            .score(&counts, self.target_pixels, chromosome.len(), &self.limits)
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
