//! The paper's volume scores, and the volume scene as a [`Scene`].

use glam::Affine3A;
use shapegen_core::express::ShapeId;
use shapegen_core::graph::Limits;

use super::{VolumeCounts, VolumeScene, VolumeScratch};
use crate::error::ScoreError;
use crate::fitness::{Scene, smootherstep};
use crate::mesh::Mesh;
use crate::solid::Solid;

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
    fn forget(scratch: &mut VolumeScratch) {
        scratch.forget();
    }
    fn add(&self, scratch: &mut VolumeScratch, id: ShapeId, shape: &Solid, transform: &Affine3A) {
        scratch.add_shape(self, id, shape, transform);
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
