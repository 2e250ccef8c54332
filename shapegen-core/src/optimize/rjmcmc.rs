//! Reversible-jump MCMC (Talton et al. 2011) in the paper's framework (§7).
//!
//! Each chain holds one chromosome. Per generation every chain proposes a
//! *jump* (probability `jump_probability`) or a *diffusion*:
//!
//! - diffusion: a gene with parameters, chosen by level-biased selection,
//!   gets all its parameters redrawn from the prior; accepted with
//!   `min{1, exp(β(ℓ' − ℓ))}`;
//! - jump: a non-root gene whose node has slots, chosen by level-biased
//!   selection, keeps its own parameters while everything below it is
//!   regrown from the graph (each open slot expressed with its `p`, depth
//!   first, up to `max_depth`). The new genes copy the parameters of the
//!   removed ones of the same node, in pre-order (first removed `A` to first
//!   new `A`, ...), and draw the rest from the prior.
//!
//! **Detailed balance.** The copy pairing is symmetric (the reverse jump
//! pairs the same genes), so copies are an involution with unit Jacobian;
//! the regrown structure is proposed with its prior probability and fresh
//! parameters with their prior density. Prior and proposal therefore cancel,
//! leaving `α = min{1, exp(β(ℓ' − ℓ)) · q_{x'}(v) / q_x(v)}` with `q` the
//! level-biased selection probability `1/|levels| · 1/n(depth(v))`. This
//! holds exactly when regrowth is limited by `max_depth` only (a length cap
//! `L_max` truncates proposals, as the reference code did), at `β = 1`
//! without annealing: the chain then samples `prior(x) · L(x)`.
//!
//! Proposals outside the graph's length limits are rejected outright (the
//! target is zero there). Chains run at inverse temperatures from a ladder
//! (parallel tempering); once per generation one random adjacent pair
//! proposes to swap states.

use std::borrow::Cow;
use std::ops::ControlFlow;

use rand::{Rng, RngExt};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::checkpoint::{Checkpoint, SavedIndividual, SavedState};
use super::driver::{Context, Method, Run, drive};
use super::evaluation::Candidate;
use super::fitness::is_valid_score;
use super::{Fitness, Individual, OptimizeError, Optimizer, RunResult, purpose};
use crate::genome::{Chromosome, word};
use crate::graph::Graph;
use crate::ops::{InitLength, cut_unchecked, grow_unchecked, random_individual};
use crate::rng::stream;

/// Inverse temperatures of the chains.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Ladder {
    /// Every chain at `β = 1` (plain MCMC, no swaps).
    Flat,
    /// Geometric temperatures `T_i = T_max^{i/(P−1)}`; the paper's rule (70 %
    /// acceptance in the hottest chain for 1 % in the coldest) gives
    /// `T_max = ln 0.01 / ln 0.7 ≈ 12.91` ([`Ladder::paper`]).
    Geometric {
        /// The hottest temperature.
        t_max: f64,
    },
    /// The reference code's `β_i = (i + 1)^−1.03`.
    Reference,
}

impl Ladder {
    /// The paper's geometric ladder.
    #[must_use]
    pub fn paper() -> Self {
        Self::Geometric {
            t_max: 0.01f64.ln() / 0.7f64.ln(),
        }
    }

    pub(crate) fn betas(&self, chains: usize) -> Vec<f64> {
        (0..chains)
            .map(|i| match *self {
                Self::Flat => 1.0,
                Self::Geometric { t_max } if chains > 1 => {
                    1.0 / t_max.powf(i as f64 / (chains - 1) as f64)
                }
                Self::Geometric { .. } => 1.0,
                Self::Reference => (i as f64 + 1.0).powf(-1.03),
            })
            .collect()
    }
}

/// How fitness becomes a log-likelihood `ℓ`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum LogLikelihood {
    /// `ℓ = f / τ`.
    FitnessIsLogLik {
        /// Temperature `τ`.
        tau: f64,
    },
    /// `ℓ = ln f`; when either compared fitness is `<= 0`, both are shifted by
    /// `−min + 0.01` first (the reference code; `ℓ` then depends on the pair).
    LogShiftedFitness,
}

impl LogLikelihood {
    /// `ℓ(to) − ℓ(from)`.
    fn difference(&self, from: f64, to: f64) -> f64 {
        match *self {
            Self::FitnessIsLogLik { tau } => (to - from) / tau,
            Self::LogShiftedFitness => {
                let shift = if from <= 0.0 || to <= 0.0 {
                    -from.min(to) + 0.01
                } else {
                    0.0
                };
                (to + shift).ln() - (from + shift).ln()
            }
        }
    }
}

/// Parameters of [`Rjmcmc`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct RjmcmcParams {
    /// Number of chains.
    pub chains: usize,
    /// Initial states (the GA's random individuals).
    pub init: InitLength,
    /// Probability that a proposal is a jump.
    pub jump_probability: f64,
    /// Inverse temperatures.
    pub ladder: Ladder,
    /// Multiply every `β` by this after each step (the paper: 1.1); `None` = off.
    pub annealing: Option<f64>,
    /// Fitness to log-likelihood.
    pub log_likelihood: LogLikelihood,
    /// A second proposal after a rejected jump.
    pub delayed_rejection: DelayedRejection,
}

/// Delayed rejection: what a chain tries after its jump is rejected.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DelayedRejection {
    /// No second stage.
    #[default]
    Off,
    /// Regrow again at the same gene, accepted with the Tierney–Mira rule
    /// `α2 = min{1, e^{β(ℓ_y2 − ℓ_x)} · q_{y2}(v)/q_x(v) · (1 − α1(y2, y1)) / (1 − α1(x, y1))}`.
    /// Keeps detailed balance; jumps then draw all new parameters afresh
    /// (with copies the reverse first stage would be impossible).
    Exact,
    /// Redraw the parameters of one gene of the rejected jump's regrown part
    /// and accept with the plain jump ratio against the current state: the
    /// paper's "additional alter mutations". Approximate (no detailed balance).
    ApproxAlter,
}

impl RjmcmcParams {
    /// The paper presets' conventions: jump probability 0.5, the geometric
    /// ladder, annealing ×1.1 per step, log of shifted fitness.
    #[must_use]
    pub fn paper(chains: usize, init: InitLength) -> Self {
        Self {
            chains,
            init,
            jump_probability: 0.5,
            ladder: Ladder::paper(),
            annealing: Some(1.1),
            log_likelihood: LogLikelihood::LogShiftedFitness,
            delayed_rejection: DelayedRejection::Off,
        }
    }

    /// Every problem with these parameters.
    pub fn problems(&self) -> Vec<String> {
        let mut p = Vec::new();
        if self.chains == 0 {
            p.push("chains must be at least 1".to_string());
        }
        if !(0.0..=1.0).contains(&self.jump_probability) {
            p.push(format!(
                "jump_probability must be in [0, 1], got {}",
                self.jump_probability
            ));
        }
        if let Some(a) = self.annealing
            && !(a > 0.0 && a.is_finite())
        {
            p.push(format!("annealing factor must be finite and > 0, got {a}"));
        }
        if let LogLikelihood::FitnessIsLogLik { tau } = self.log_likelihood
            && !(tau > 0.0 && tau.is_finite())
        {
            p.push(format!(
                "log-likelihood temperature must be finite and > 0, got {tau}"
            ));
        }
        p
    }
}

/// RJMCMC with parallel tempering.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rjmcmc {
    /// The parameters.
    pub params: RjmcmcParams,
}

/// Genes a jump may start from: non-root genes whose node has slots.
fn jump_point(graph: &Graph) -> impl Fn(u32, u16) -> bool + '_ {
    move |pos, node| pos != 0 && graph.layout(node).slots > 0
}

/// Genes a diffusion may alter: genes with parameters.
fn has_params(graph: &Graph) -> impl Fn(u32, u16) -> bool + '_ {
    move |_, node| graph.layout(node).param_words > 0
}

/// Level-biased selection among the genes accepted by `eligible(pos, node)`:
/// a depth uniformly among the depths holding one, then a gene uniformly.
/// Returns the chosen gene and its selection probability.
fn select<R: Rng + ?Sized>(
    graph: &Graph,
    c: &Chromosome,
    eligible: impl Fn(u32, u16) -> bool,
    rng: &mut R,
) -> Option<(u32, f64)> {
    let by_level = levels(graph, c, &eligible);
    if by_level.is_empty() {
        return None;
    }
    let level = &by_level[rng.random_range(0..by_level.len())];
    let v = level[rng.random_range(0..level.len())];
    Some((v, 1.0 / (by_level.len() as f64 * level.len() as f64)))
}

/// Selection probability of `v` in `c` under [`select`] (0 if not eligible).
fn selection_probability(
    graph: &Graph,
    c: &Chromosome,
    v: u32,
    eligible: impl Fn(u32, u16) -> bool,
) -> f64 {
    let by_level = levels(graph, c, &eligible);
    by_level
        .iter()
        .find(|l| l.contains(&v))
        .map_or(0.0, |l| 1.0 / (by_level.len() as f64 * l.len() as f64))
}

/// Eligible gene positions grouped by depth (non-empty levels only).
fn levels(graph: &Graph, c: &Chromosome, eligible: &impl Fn(u32, u16) -> bool) -> Vec<Vec<u32>> {
    let mut depth_at = vec![0u32; c.words().len()];
    let mut out: Vec<Vec<u32>> = Vec::new();
    for g in c.genes(graph) {
        let d = g.parent().map_or(0, |p| depth_at[p as usize] + 1);
        depth_at[g.pos() as usize] = d;
        if eligible(g.pos(), g.node()) {
            let d = d as usize;
            if out.len() <= d {
                out.resize(d + 1, Vec::new());
            }
            out[d].push(g.pos());
        }
    }
    out.retain(|l| !l.is_empty());
    out
}

/// Jump at `v`: remove everything below it and regrow from the graph; with
/// `copy`, new genes take the parameters of removed genes of the same node in
/// pre-order. The regrown genes are the last ones of the chromosome.
fn jump<R: Rng + ?Sized>(graph: &Graph, c: &mut Chromosome, v: u32, copy: bool, rng: &mut R) {
    // Parameters of the removed genes, per node, in pre-order.
    let mut removed: Vec<std::collections::VecDeque<Vec<u32>>> =
        vec![Default::default(); graph.node_count()];
    let children: Vec<u32> = c.gene(graph, v).children().map(|(_, p)| p).collect();
    for &child in &children {
        for g in c.subtree(graph, child) {
            removed[g.node() as usize].push_back(g.params().to_vec());
        }
    }
    // Cut the child subtrees (v precedes them and never moves).
    loop {
        let Some((_, child)) = c.gene(graph, v).children().next() else {
            break;
        };
        cut_unchecked(graph, c, child);
    }
    // Regrow depth first from v's slots.
    let depth_v = c.depth(v);
    let limits = *graph.limits();
    let mut open: Vec<(u32, u32, u32)> = Vec::new();
    let push_slots = |open: &mut Vec<(u32, u32, u32)>, c: &Chromosome, pos: u32, depth: u32| {
        if limits.allows_depth(depth + 1) {
            let node = word::node(c.words[pos as usize]);
            for j in (0..graph.layout(node).slots).rev() {
                open.push((pos, j, depth));
            }
        }
    };
    push_slots(&mut open, c, v, depth_v);
    let mut added = 0;
    while let Some((pos, slot, depth)) = open.pop() {
        let node = word::node(c.words[pos as usize]);
        let edge = *graph.edge(node, slot);
        let room = limits.max_len.is_none_or(|m| c.len() as u32 + 1 < m)
            && added < super::smc::MAX_STEP_GENES;
        if room && rng.random_bool(edge.p) {
            let child = grow_unchecked(graph, c, pos, slot, rng).child;
            added += 1;
            if let Some(params) = removed[edge.to as usize].pop_front().filter(|_| copy) {
                let layout = graph.layout(edge.to);
                let at = child as usize + word::SLOTS + layout.slots as usize;
                c.words[at..at + params.len()].copy_from_slice(&params);
            }
            push_slots(&mut open, c, child, depth + 1);
        }
    }
}

/// What the delayed-rejection stage needs from the first.
#[derive(Clone, Copy)]
struct SecondStage<'a> {
    proposals: &'a [(Proposal, f64)],
    rejected: &'a [(usize, f64)],
    betas: &'a [f64],
    seed: u64,
}

/// A chain's proposal and what its acceptance needs.
pub(crate) struct Proposal {
    /// The proposed state.
    pub state: Chromosome,
    /// `q_{x'}(v) / q_x(v)` (1 for diffusion).
    selection_ratio: f64,
    /// Whether `state` differs from the chain's (a no-op proposal is not evaluated).
    pub changed: bool,
    /// For a jump: the gene `v`, `q_x(v)`, and how many genes `x` keeps before regrowth.
    jump: Option<(u32, f64, usize)>,
}

impl Rjmcmc {
    /// An RJMCMC optimizer.
    #[must_use]
    pub const fn new(params: RjmcmcParams) -> Self {
        Self { params }
    }

    fn propose<R: Rng + ?Sized>(&self, graph: &Graph, x: &Chromosome, rng: &mut R) -> Proposal {
        let copy = self.params.delayed_rejection != DelayedRejection::Exact;
        propose(graph, x, self.params.jump_probability, copy, rng)
    }
}

/// One proposal of the chains' kernel from `x`: a jump at a level-biased
/// gene with probability `jump_probability` (copying the removed genes'
/// parameters if `copy`), else a diffusion of one gene's parameters. A jump
/// outside the graph's length limits, or with no gene to move, leaves `x`
/// unchanged (`changed` false).
pub(crate) fn propose<R: Rng + ?Sized>(
    graph: &Graph,
    x: &Chromosome,
    jump_probability: f64,
    copy: bool,
    rng: &mut R,
) -> Proposal {
    let mut y = x.clone();
    let unchanged = |y| Proposal {
        state: y,
        selection_ratio: 1.0,
        changed: false,
        jump: None,
    };
    if rng.random_bool(jump_probability) {
        let Some((v, q)) = select(graph, x, jump_point(graph), rng) else {
            return unchanged(y);
        };
        jump(graph, &mut y, v, copy, rng);
        if !graph.limits().allows_len(y.len() as u32) {
            // Outside the target's support (length limits): rejected outright.
            return unchanged(x.clone());
        }
        let kept = x.len() - x.subtree_len(graph, v) + 1;
        let q_back = selection_probability(graph, &y, v, jump_point(graph));
        Proposal {
            state: y,
            selection_ratio: q_back / q,
            changed: true,
            jump: Some((v, q, kept)),
        }
    } else {
        let Some((v, _)) = select(graph, x, has_params(graph), rng) else {
            return unchanged(y);
        };
        y.redraw_params(graph, v, rng);
        Proposal {
            state: y,
            selection_ratio: 1.0,
            changed: true,
            jump: None,
        }
    }
}

impl Rjmcmc {
    /// The second-stage proposal after the jump `first` from `x` was rejected.
    fn second_stage<R: Rng + ?Sized>(
        &self,
        graph: &Graph,
        x: &Chromosome,
        first: &Proposal,
        rng: &mut R,
    ) -> Option<Chromosome> {
        let (v, _, kept) = first.jump?;
        match self.params.delayed_rejection {
            DelayedRejection::Off => None,
            DelayedRejection::Exact => {
                let mut y = x.clone();
                jump(graph, &mut y, v, false, rng);
                graph.limits().allows_len(y.len() as u32).then_some(y)
            }
            DelayedRejection::ApproxAlter => {
                // Genes of the regrown part are those after the `kept` surviving genes.
                let regrown = &first.state.positions()[kept.min(first.state.len())..];
                let with_params: Vec<u32> = regrown
                    .iter()
                    .copied()
                    .filter(|&p| graph.layout(first.state.gene(graph, p).node()).param_words > 0)
                    .collect();
                let mut y = first.state.clone();
                if !with_params.is_empty() {
                    y.redraw_params(
                        graph,
                        with_params[rng.random_range(0..with_params.len())],
                        rng,
                    );
                }
                Some(y)
            }
        }
    }
}

impl Rjmcmc {
    /// The second stage for every chain whose jump was rejected.
    fn delayed_rejection<F: Fitness>(
        &self,
        cx: &mut Context<'_, '_, F>,
        chains: &mut [super::Individual],
        stage: &SecondStage<'_>,
    ) {
        let graph = cx.graph;
        let SecondStage {
            proposals,
            rejected,
            betas,
            seed,
        } = *stage;
        let g = cx.generation();
        let second: Vec<(usize, Chromosome, f64)> = rejected
            .par_iter()
            .filter_map(|&(i, _)| {
                let mut rng = stream(seed, &[g, i as u64, purpose::BREED, 2]);
                let y2 =
                    self.second_stage(graph, &chains[i].chromosome, &proposals[i].0, &mut rng)?;
                Some((i, y2, rng.random::<f64>()))
            })
            .collect();
        let candidates = second
            .iter()
            .map(|(_, y, _)| Candidate::new(y.clone()))
            .collect();
        // Not interrupted: the first stage already changed the chains.
        let evaluated = cx.evaluate(candidates);
        let ll = self.params.log_likelihood;
        for ((i, _, u), y2) in second.iter().zip(evaluated) {
            let (i, beta) = (*i, betas[*i]);
            if !is_valid_score(y2.fitness) {
                continue;
            }
            let (p1, _) = &proposals[i];
            let (v, q_x, _) = p1.jump.expect("only rejected jumps reach the second stage");
            let x = &chains[i];
            let q_y2 = selection_probability(graph, &y2.chromosome, v, jump_point(graph));
            let log_alpha = match self.params.delayed_rejection {
                DelayedRejection::Exact => {
                    let f_y1 = rejected.iter().find(|r| r.0 == i).map_or(f64::NAN, |r| r.1);
                    let q_y1 = q_x * p1.selection_ratio;
                    // α1(a, b) = min{1, e^{β(ℓ_b − ℓ_a)} q_b / q_a}
                    let alpha1 = |fa: f64, qa: f64, fb: f64, qb: f64| {
                        (beta * ll.difference(fa, fb) + (qb / qa).ln())
                            .exp()
                            .min(1.0)
                    };
                    let back = 1.0
                        - if is_valid_score(f_y1) {
                            alpha1(y2.fitness, q_y2, f_y1, q_y1)
                        } else {
                            0.0
                        };
                    let forth = 1.0
                        - if is_valid_score(f_y1) {
                            alpha1(x.fitness, q_x, f_y1, q_y1)
                        } else {
                            0.0
                        };
                    if forth <= 0.0 {
                        continue;
                    }
                    beta * ll.difference(x.fitness, y2.fitness)
                        + (q_y2 / q_x).ln()
                        + (back / forth).ln()
                }
                _ => beta * ll.difference(x.fitness, y2.fitness) + (q_y2 / q_x).ln(),
            };
            if u.ln() < log_alpha {
                chains[i] = y2;
            }
        }
    }
}

impl Optimizer for Rjmcmc {
    fn name(&self) -> &'static str {
        "rjmcmc"
    }

    fn run_from<F: Fitness>(&self, run: Run<'_, F>) -> Result<RunResult, OptimizeError> {
        drive(self, run)
    }
}

/// The chains (one per temperature) and their inverse temperatures.
pub(crate) struct Chains {
    pub chains: Vec<Individual>,
    pub betas: Vec<f64>,
}

impl Rjmcmc {
    /// The state saved in `saved`.
    pub(crate) fn restore_state(
        &self,
        graph: &Graph,
        saved: &SavedState,
    ) -> Result<Chains, OptimizeError> {
        let SavedState::Chains { chains, betas_bits } = saved else {
            return Err(OptimizeError::Checkpoint(
                "it holds no RJMCMC chains".into(),
            ));
        };
        if chains.len() != self.params.chains || betas_bits.len() != chains.len() {
            return Err(OptimizeError::Checkpoint(format!(
                "it holds {} chains, not {}",
                chains.len(),
                self.params.chains
            )));
        }
        Ok(Chains {
            chains: chains
                .iter()
                .map(|c| c.restore(graph))
                .collect::<Result<Vec<_>, _>>()?,
            betas: betas_bits.iter().map(|&b| f64::from_bits(b)).collect(),
        })
    }

    /// The state a checkpoint saves.
    pub(crate) fn save_state(&self, graph: &Graph, state: &Chains) -> SavedState {
        SavedState::Chains {
            chains: state
                .chains
                .iter()
                .map(|c| SavedIndividual::save(graph, c))
                .collect(),
            betas_bits: state.betas.iter().map(|b| b.to_bits()).collect(),
        }
    }
}

impl Method for Rjmcmc {
    type Params = RjmcmcParams;
    type State = Chains;

    fn name(&self) -> &'static str {
        "rjmcmc"
    }

    fn params(&self) -> &RjmcmcParams {
        &self.params
    }

    fn problems(&self) -> Vec<String> {
        self.params.problems()
    }

    fn init<F: Fitness>(&self, cx: &mut Context<'_, '_, F>) -> Result<Chains, OptimizeError> {
        let (graph, seed) = (cx.graph, cx.seed);
        let init: Vec<Candidate> = (0..self.params.chains as u64)
            .into_par_iter()
            .map(|i| {
                Ok(Candidate::new(random_individual(
                    graph,
                    &self.params.init,
                    &mut stream(seed, &[0, i, purpose::INIT]),
                )?))
            })
            .collect::<Result<_, OptimizeError>>()?;
        // Stopped by Ctrl-C or the clock like the GA's generation 0: chains
        // slower to score than the budget end it with the models evaluated
        // by then; the others start NaN and take their first valid proposal.
        Ok(Chains {
            chains: cx.evaluate_within_budget(init),
            betas: self.params.ladder.betas(self.params.chains),
        })
    }

    fn restore(&self, graph: &Graph, checkpoint: &Checkpoint) -> Result<Chains, OptimizeError> {
        self.restore_state(graph, &checkpoint.state)
    }

    fn save(&self, graph: &Graph, state: &Chains) -> SavedState {
        self.save_state(graph, state)
    }

    fn report<'s>(&self, _graph: &Graph, state: &'s Chains) -> Cow<'s, [Individual]> {
        Cow::Borrowed(&state.chains)
    }

    fn final_population(&self, _graph: &Graph, state: Chains) -> Vec<Individual> {
        state.chains
    }

    fn step<F: Fitness>(
        &self,
        cx: &mut Context<'_, '_, F>,
        state: &mut Chains,
    ) -> Result<ControlFlow<Vec<Individual>>, OptimizeError> {
        let (proposals, candidates) = self.proposals(cx.graph, cx.seed, cx.generation(), state);
        let Some(evaluated) = cx.evaluate_interruptible(candidates) else {
            return Ok(ControlFlow::Break(std::mem::take(&mut state.chains)));
        };
        self.accept(cx, state, evaluated, &proposals);
        Ok(ControlFlow::Continue(()))
    }
}

/// One proposal per chain, with the uniform number its acceptance draws.
pub(crate) type Proposals = Vec<(Proposal, f64)>;

impl Rjmcmc {
    /// Every chain's proposal of generation `g`, and the candidates to
    /// evaluate (an unchanged proposal keeps its chain's fitness).
    pub(crate) fn proposals(
        &self,
        graph: &Graph,
        seed: u64,
        g: u64,
        state: &Chains,
    ) -> (Proposals, Vec<Candidate>) {
        let chains = &state.chains;
        let proposals: Proposals = chains
            .par_iter()
            .enumerate()
            .map(|(i, x)| {
                let mut rng = stream(seed, &[g, i as u64, purpose::BREED]);
                let p = self.propose(graph, &x.chromosome, &mut rng);
                (p, rng.random::<f64>())
            })
            .collect();
        let candidates = proposals
            .iter()
            .zip(chains.iter())
            .map(|((p, _), x)| Candidate {
                chromosome: p.state.clone(),
                fitness: (!p.changed).then_some(x.fitness),
            })
            .collect();
        (proposals, candidates)
    }

    /// The rest of a generation once the proposals are `evaluated`: the
    /// first stage's acceptance, delayed rejection, a tempering swap and
    /// annealing.
    pub(crate) fn accept<F: Fitness>(
        &self,
        cx: &mut Context<'_, '_, F>,
        state: &mut Chains,
        evaluated: Vec<Individual>,
        proposals: &Proposals,
    ) {
        let (seed, g) = (cx.seed, cx.generation());
        let Chains { chains, betas } = state;
        let ll = self.params.log_likelihood;
        // First stage; remember rejected jumps (with y1's fitness) for delayed rejection.
        let mut rejected: Vec<(usize, f64)> = Vec::new();
        let stage = chains
            .iter_mut()
            .zip(evaluated)
            .zip(proposals)
            .zip(betas.iter())
            .enumerate();
        for (i, (((x, y), (p, u)), beta)) in stage {
            if !p.changed {
                continue;
            }
            let accept = if !is_valid_score(y.fitness) {
                false
            } else if !is_valid_score(x.fitness) {
                true
            } else {
                let log_alpha = beta * ll.difference(x.fitness, y.fitness) + p.selection_ratio.ln();
                u.ln() < log_alpha
            };
            if accept {
                *x = y;
            } else if p.jump.is_some() && is_valid_score(x.fitness) {
                rejected.push((i, y.fitness));
            }
        }
        if self.params.delayed_rejection != DelayedRejection::Off && !rejected.is_empty() {
            let stage = SecondStage {
                proposals,
                rejected: &rejected,
                betas,
                seed,
            };
            self.delayed_rejection(cx, chains, &stage);
        }
        // Parallel tempering: one adjacent pair proposes to swap states.
        if chains.len() > 1 && !matches!(self.params.ladder, Ladder::Flat) {
            let mut rng = stream(seed, &[g, u64::MAX, purpose::BREED]);
            let i = rng.random_range(0..chains.len() - 1);
            let (a, b) = (&chains[i], &chains[i + 1]);
            if is_valid_score(a.fitness) && is_valid_score(b.fitness) {
                let log_alpha = (betas[i] - betas[i + 1]) * ll.difference(a.fitness, b.fitness);
                if rng.random::<f64>().ln() < log_alpha {
                    chains.swap(i, i + 1);
                }
            }
        }
        if let Some(factor) = self.params.annealing {
            betas.iter_mut().for_each(|b| *b *= factor);
        }
    }
}
