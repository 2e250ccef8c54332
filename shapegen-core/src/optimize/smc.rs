//! Sequential Monte Carlo (SMC) and stochastically-ordered SMC (SOSMC),
//! the baselines of Ritchie et al. 2015 in the paper's framework (§7).
//!
//! Particles are chromosomes that start as a root gene. One step grows open
//! child slots until a gene that emits geometry is added: the next open slot
//! is taken (SMC: in depth-first program order; SOSMC: uniformly at random),
//! closed, and expressed with its graph probability `p`; a slot not
//! expressed stays closed for good. After each step every particle is scored
//! on its partial model and the population is resampled. Finished particles
//! (no open slot left) stay in the population.
//!
//! A step also ends after [`MAX_STEP_GENES`] genes without an emitting one,
//! so a graph whose non-emitting nodes recurse without limits cannot make a
//! step run forever (set `max_depth` or `L_max` to bound particles for real).

/// The most genes one step may add before it ends without an emitting gene.
pub const MAX_STEP_GENES: usize = 10_000;

use std::borrow::Cow;
use std::ops::ControlFlow;

use rand::{Rng, RngExt};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::checkpoint::{Checkpoint, SavedIndividual, SavedParticle, SavedState};
use super::driver::{Context, Method, Run, drive};
use super::evaluation::Candidate;
use super::fitness::is_valid_score;
use super::{Fitness, Individual, OptimizeError, Optimizer, RunResult, purpose};
use crate::genome::{Chromosome, word};
use crate::graph::Graph;
use crate::ops::grow_unchecked;
use crate::rng::stream;

/// Which open slot a step takes next.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SlotOrder {
    /// Depth-first program order (SMC).
    #[default]
    Program,
    /// Uniformly among the open slots (SOSMC).
    Random,
}

/// How particle weights are made from fitness.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum SmcWeights {
    /// `w ∝ exp((f_t − f_{t−1}) / τ)`: the statistically correct SMC weight.
    IncrementalExp {
        /// Temperature `τ`.
        tau: f64,
    },
    /// `w ∝ f − min(0, f_min)`, as the authors' code (paper presets).
    AbsoluteShifted,
    /// `w ∝ exp(f / τ)`, as Ritchie et al.'s original code.
    AbsoluteExp {
        /// Temperature `τ`.
        tau: f64,
    },
}

/// How the population is resampled after each step.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Resampling {
    /// Systematic resampling (one uniform draw; lowest variance).
    #[default]
    Systematic,
    /// Independent draws in proportion to the weights (the authors' code).
    Multinomial,
}

/// Parameters of [`Smc`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SmcParams {
    /// Number of particles.
    pub particles: usize,
    /// SMC (program order) or SOSMC (random order).
    pub order: SlotOrder,
    /// Weights.
    pub weights: SmcWeights,
    /// Resampling scheme.
    pub resampling: Resampling,
}

impl SmcParams {
    /// SMC with the paper presets' conventions (absolute shifted weights, systematic resampling).
    #[must_use]
    pub const fn paper(particles: usize) -> Self {
        Self {
            particles,
            order: SlotOrder::Program,
            weights: SmcWeights::AbsoluteShifted,
            resampling: Resampling::Systematic,
        }
    }

    /// SOSMC with the paper presets' conventions.
    #[must_use]
    pub const fn paper_sosmc(particles: usize) -> Self {
        Self {
            order: SlotOrder::Random,
            ..Self::paper(particles)
        }
    }

    /// Every problem with these parameters.
    pub fn problems(&self) -> Vec<String> {
        let mut p = Vec::new();
        if self.particles == 0 {
            p.push("particles must be at least 1".to_string());
        }
        if let SmcWeights::IncrementalExp { tau } | SmcWeights::AbsoluteExp { tau } = self.weights
            && !(tau > 0.0 && tau.is_finite())
        {
            p.push(format!(
                "the weight temperature must be finite and > 0, got {tau}"
            ));
        }
        p
    }
}

/// SMC or SOSMC over the chromosomes of a generator graph.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Smc {
    /// The parameters.
    pub params: SmcParams,
}

/// One particle: a chromosome and its still-open slots (its "stochastic futures").
#[derive(Clone, Debug)]
struct Particle {
    chromosome: Chromosome,
    /// (gene position, slot, depth of that gene); the next slot is the last (program order).
    open: Vec<(u32, u32, u32)>,
    /// Fitness after the previous step (for incremental weights).
    previous: f64,
    fitness: f64,
}

impl Particle {
    fn new<R: Rng + ?Sized>(graph: &Graph, rng: &mut R) -> Self {
        let chromosome = Chromosome::root(graph, rng);
        let mut p = Self {
            chromosome,
            open: Vec::new(),
            previous: 0.0,
            fitness: f64::NAN,
        };
        p.open_slots(graph, 0, 0);
        p
    }

    fn save(&self, graph: &Graph) -> SavedParticle {
        SavedParticle {
            individual: SavedIndividual::new(graph, &self.chromosome, self.fitness),
            open: self.open.clone(),
            previous_bits: self.previous.to_bits(),
        }
    }

    fn restore(graph: &Graph, saved: &SavedParticle) -> Result<Self, OptimizeError> {
        let Individual {
            chromosome,
            fitness,
        } = saved.individual.restore_partial(graph)?;
        // Every open slot must be an empty slot of a gene of the chromosome.
        for &(pos, slot, _) in &saved.open {
            let gene = chromosome
                .positions()
                .binary_search(&pos)
                .ok()
                .map(|_| chromosome.gene(graph, pos));
            if !gene
                .is_some_and(|g| slot < g.slot_count() as u32 && g.child(slot as usize).is_none())
            {
                return Err(OptimizeError::Checkpoint(format!(
                    "a particle's open slot {slot} of gene {pos} is not an empty slot"
                )));
            }
        }
        Ok(Self {
            chromosome,
            open: saved.open.clone(),
            previous: f64::from_bits(saved.previous_bits),
            fitness,
        })
    }

    fn finished(&self) -> bool {
        self.open.is_empty()
    }

    /// Opens the slots of the gene at `pos` (at `depth`) whose children the limits allow,
    /// in reverse order so that program order takes slot 0 first.
    fn open_slots(&mut self, graph: &Graph, pos: u32, depth: u32) {
        if !graph.limits().allows_depth(depth + 1) {
            return;
        }
        let node = word::node(self.chromosome.words[pos as usize]);
        for j in (0..graph.layout(node).slots).rev() {
            self.open.push((pos, j, depth));
        }
    }

    /// One step: expand open slots until a geometry-emitting gene is added.
    /// Returns whether the chromosome changed.
    fn step<R: Rng + ?Sized>(&mut self, graph: &Graph, order: SlotOrder, rng: &mut R) -> bool {
        let mut changed = false;
        for _ in 0..MAX_STEP_GENES {
            let next = match order {
                SlotOrder::Program => self.open.pop(),
                SlotOrder::Random if self.open.is_empty() => None,
                SlotOrder::Random => {
                    let i = rng.random_range(0..self.open.len());
                    Some(self.open.swap_remove(i))
                }
            };
            let Some((pos, slot, depth)) = next else {
                return changed;
            };
            let node = word::node(self.chromosome.words[pos as usize]);
            let p = graph.edge(node, slot).p;
            let room = graph
                .limits()
                .max_len
                .is_none_or(|m| self.chromosome.len() as u32 + 1 < m);
            if room && rng.random_bool(p) {
                let child = grow_unchecked(graph, &mut self.chromosome, pos, slot, rng).child;
                changed = true;
                self.open_slots(graph, child, depth + 1);
                if graph.emits(graph.edge(node, slot).to) {
                    return changed;
                }
            }
        }
        changed
    }
}

/// Systematic or multinomial resampling: `n` indices drawn in proportion to `weights`.
fn resample<R: Rng + ?Sized>(
    weights: &[f64],
    scheme: Resampling,
    rng: &mut R,
    out: &mut Vec<usize>,
) {
    let n = weights.len();
    out.clear();
    let total: f64 = weights.iter().sum();
    if !(total > 0.0 && total.is_finite()) {
        out.extend(0..n); // no information: keep everyone
        return;
    }
    let mut cumulative = Vec::with_capacity(n);
    let mut acc = 0.0;
    for w in weights {
        acc += w / total;
        cumulative.push(acc);
    }
    let pick = |u: f64| cumulative.partition_point(|&c| c <= u).min(n - 1);
    match scheme {
        Resampling::Systematic => {
            let u0: f64 = rng.random::<f64>() / n as f64;
            out.extend((0..n).map(|k| pick(u0 + k as f64 / n as f64)));
        }
        Resampling::Multinomial => out.extend((0..n).map(|_| pick(rng.random::<f64>()))),
    }
}

impl Smc {
    /// An SMC/SOSMC optimizer.
    #[must_use]
    pub const fn new(params: SmcParams) -> Self {
        Self { params }
    }

    fn weights(&self, particles: &[Particle], out: &mut Vec<f64>) {
        out.clear();
        let valid = |f: f64| is_valid_score(f);
        match self.params.weights {
            SmcWeights::IncrementalExp { tau } => {
                let incr: Vec<f64> = particles
                    .iter()
                    .map(|p| {
                        if valid(p.fitness) && valid(p.previous) {
                            (p.fitness - p.previous) / tau
                        } else {
                            f64::NAN
                        }
                    })
                    .collect();
                let max = incr
                    .iter()
                    .copied()
                    .filter(|x| x.is_finite())
                    .fold(f64::NEG_INFINITY, f64::max);
                out.extend(
                    incr.iter()
                        .map(|&x| if x.is_finite() { (x - max).exp() } else { 0.0 }),
                );
            }
            SmcWeights::AbsoluteShifted => {
                let min = particles
                    .iter()
                    .map(|p| p.fitness)
                    .filter(|f| valid(*f))
                    .fold(f64::INFINITY, f64::min);
                let shift = if min < 0.0 { min } else { 0.0 };
                out.extend(particles.iter().map(|p| {
                    if valid(p.fitness) {
                        p.fitness - shift
                    } else {
                        0.0
                    }
                }));
            }
            SmcWeights::AbsoluteExp { tau } => {
                let max = particles
                    .iter()
                    .map(|p| p.fitness)
                    .filter(|f| valid(*f))
                    .fold(f64::NEG_INFINITY, f64::max);
                out.extend(particles.iter().map(|p| {
                    if valid(p.fitness) {
                        ((p.fitness - max) / tau).exp()
                    } else {
                        0.0
                    }
                }));
            }
        }
    }
}

impl Optimizer for Smc {
    fn name(&self) -> &'static str {
        Method::name(self)
    }

    fn run_from<F: Fitness>(&self, run: Run<'_, F>) -> Result<RunResult, OptimizeError> {
        drive(self, run)
    }
}

/// SMC's state: the particles, and the weight and pick buffers reused across generations.
pub(crate) struct Particles {
    particles: Vec<Particle>,
    weights: Vec<f64>,
    picks: Vec<usize>,
}

impl Particles {
    fn new(particles: Vec<Particle>) -> Self {
        Self {
            particles,
            weights: Vec::new(),
            picks: Vec::new(),
        }
    }
}

impl Smc {
    /// The particles saved in `saved`.
    pub(crate) fn restore_state(
        &self,
        graph: &Graph,
        saved: &SavedState,
    ) -> Result<Particles, OptimizeError> {
        let SavedState::Particles { particles } = saved else {
            return Err(OptimizeError::Checkpoint(
                "it holds no SMC particles".into(),
            ));
        };
        if particles.len() != self.params.particles {
            return Err(OptimizeError::Checkpoint(format!(
                "it holds {} particles, not {}",
                particles.len(),
                self.params.particles
            )));
        }
        let particles = particles
            .iter()
            .map(|p| Particle::restore(graph, p))
            .collect::<Result<_, _>>()?;
        Ok(Particles::new(particles))
    }
}

impl Method for Smc {
    type Params = SmcParams;
    type State = Particles;

    fn name(&self) -> &'static str {
        match self.params.order {
            SlotOrder::Program => "smc",
            SlotOrder::Random => "sosmc",
        }
    }

    fn params(&self) -> &SmcParams {
        &self.params
    }

    fn problems(&self) -> Vec<String> {
        self.params.problems()
    }

    fn init<F: Fitness>(&self, cx: &mut Context<'_, '_, F>) -> Result<Particles, OptimizeError> {
        let (graph, seed) = (cx.graph, cx.seed);
        let mut particles: Vec<Particle> = (0..self.params.particles as u64)
            .into_par_iter()
            .map(|i| Particle::new(graph, &mut stream(seed, &[0, i, purpose::INIT])))
            .collect();
        // Score the starting models (root genes) so incremental weights start from them.
        let roots = particles
            .iter()
            .map(|p| Candidate::new(p.chromosome.clone()))
            .collect();
        for (p, e) in particles.iter_mut().zip(cx.evaluate(roots)) {
            p.fitness = e.fitness;
        }
        Ok(Particles::new(particles))
    }

    fn restore(&self, graph: &Graph, checkpoint: &Checkpoint) -> Result<Particles, OptimizeError> {
        self.restore_state(graph, &checkpoint.state)
    }

    fn save(&self, graph: &Graph, state: &Particles) -> SavedState {
        SavedState::Particles {
            particles: state.particles.iter().map(|p| p.save(graph)).collect(),
        }
    }

    fn report<'s>(&self, graph: &Graph, state: &'s Particles) -> Cow<'s, [Individual]> {
        Cow::Owned(report_particles(
            &state.particles,
            graph.limits().min_len as usize,
        ))
    }

    /// Generation 0 holds only root genes; the first reported generation is the first step.
    fn reports_initial(&self) -> bool {
        false
    }

    fn exhausted(&self, state: &Particles) -> bool {
        state.particles.iter().all(Particle::finished)
    }

    fn final_population(&self, graph: &Graph, state: Particles) -> Vec<Individual> {
        report_particles(&state.particles, graph.limits().min_len as usize)
    }

    fn step<F: Fitness>(
        &self,
        cx: &mut Context<'_, '_, F>,
        state: &mut Particles,
    ) -> Result<ControlFlow<Vec<Individual>>, OptimizeError> {
        let (graph, seed, g) = (cx.graph, cx.seed, cx.generation());
        let Particles {
            particles,
            weights,
            picks,
        } = state;
        if g > 1 {
            // Resample after the previous generation, from its own stream.
            self.weights(particles, weights);
            resample(
                weights,
                self.params.resampling,
                &mut stream(seed, &[g - 1, u64::MAX, purpose::BREED]),
                picks,
            );
            *particles = picks.iter().map(|&k| particles[k].clone()).collect();
        }
        // Step every unfinished particle; evaluate the ones that changed.
        let order = self.params.order;
        let changed: Vec<bool> = particles
            .par_iter_mut()
            .enumerate()
            .map(|(i, p)| {
                !p.finished()
                    && p.step(
                        graph,
                        order,
                        &mut stream(seed, &[g, i as u64, purpose::BREED]),
                    )
            })
            .collect();
        let candidates: Vec<Candidate> = particles
            .iter()
            .zip(&changed)
            .map(|(p, &c)| Candidate {
                chromosome: p.chromosome.clone(),
                fitness: (!c && p.fitness.is_finite()).then_some(p.fitness),
            })
            .collect();
        // Not interrupted: particles and fitness stay in step.
        for (p, e) in particles.iter_mut().zip(cx.evaluate(candidates)) {
            p.previous = p.fitness;
            p.fitness = e.fitness;
        }
        Ok(ControlFlow::Continue(()))
    }
}

/// The population an observer sees: particles too short to be valid models
/// count as failed evaluations.
fn report(evaluated: Vec<Individual>, min_len: usize) -> Vec<Individual> {
    evaluated
        .into_iter()
        .map(|i| {
            if i.chromosome.len() >= min_len {
                i
            } else {
                Individual {
                    fitness: f64::NAN,
                    ..i
                }
            }
        })
        .collect()
}

/// [`report`] of the particles themselves.
fn report_particles(particles: &[Particle], min_len: usize) -> Vec<Individual> {
    let individuals = particles
        .iter()
        .map(|p| Individual {
            chromosome: p.chromosome.clone(),
            fitness: p.fitness,
        })
        .collect();
    report(individuals, min_len)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resampling_is_proportional() {
        let mut rng = stream(1, &[]);
        let mut out = Vec::new();
        let weights = [1.0, 0.0, 3.0, 4.0];
        let mut counts = [0usize; 4];
        for _ in 0..2000 {
            resample(&weights, Resampling::Systematic, &mut rng, &mut out);
            for &k in &out {
                counts[k] += 1;
            }
        }
        assert_eq!(counts[1], 0);
        // Systematic resampling keeps each share within one particle of n · w.
        let total = counts.iter().sum::<usize>() as f64;
        assert!((counts[2] as f64 / total - 3.0 / 8.0).abs() < 0.01);
        resample(&[0.0; 3], Resampling::Multinomial, &mut rng, &mut out);
        assert_eq!(out, [0, 1, 2]);
    }
}
