//! The genetic algorithm (paper Algorithm 1).

use std::borrow::Cow;
use std::collections::HashSet;
use std::ops::ControlFlow;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::adaptive_split::{AdaptiveSplit, Origin};
use super::challenger::{Challenged, Lineage};
use super::checkpoint::{Checkpoint, SavedIndividual, SavedState};
use super::driver::{Context, Method, Run, drive};
use super::evaluation::Candidate;
use super::fitness::is_valid_score;
use super::rjmcmc::propose;
use super::selection::{
    Roulette, RouletteShift, best_distinct, best_distinct_repeated, rank_order, tournament,
};
use super::{Fitness, Individual, OptimizeError, Optimizer, RunResult, purpose};
use crate::graph::Graph;
use crate::ops::{
    CrossoverConfig, InitLength, MutationSplit, crossover, mutate, random_individual,
};
use crate::rng::{ShapeRng, stream};

/// The stream `(seed, base..., island)`; a lone GA (`island = None`) draws
/// from `(seed, base...)`, the streams it always had.
fn island_stream(seed: u64, base: [u64; 3], island: Option<u64>) -> ShapeRng {
    match island {
        None => stream(seed, &base),
        Some(k) => stream(seed, &[base[0], base[1], base[2], k]),
    }
}

/// Parameters of the [`Ga`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct GaParams {
    /// Population size `P`.
    pub population: usize,
    /// Number of elites `E` copied unchanged to the next generation.
    pub elites: usize,
    /// Length of the random initial individuals.
    pub init: InitLength,
    /// Probability that a pair of children is made by mutation rather than crossover.
    pub mutation_rate: f64,
    /// Relative weights of grow, cut and alter among mutations.
    pub mutation_split: MutationSplit,
    /// Tournament size `k`.
    pub tournament: usize,
    /// Crossover settings.
    pub crossover: CrossoverConfig,
    /// Roulette weights for negative fitness.
    pub roulette: RouletteShift,
    /// Count identical chromosomes once when choosing elites (against sample impoverishment).
    pub elite_dedup: bool,
    /// Local search on elites: how many children of each generation are one
    /// move of the RJMCMC chains' kernel (a jump regrowing below a gene with
    /// the removed genes' parameters copied, or a diffusion of one gene's
    /// parameters, each with probability 1/2) from the best distinct
    /// individuals, in turn. 0 (the paper): none.
    #[serde(default)]
    pub local_search: usize,
    /// An adaptive mutation split: the shares of grow, cut and alter start
    /// from `mutation_split` and then follow how often each one's children
    /// beat their parent ([`AdaptiveSplit`]); `mutation_rate` stays fixed.
    /// `false` (the paper): the fixed split.
    #[serde(default)]
    pub adaptive_split: bool,
    /// Steps without progress (the best rising by
    /// [`PROGRESS_SHARE`](super::PROGRESS_SHARE) of its gain since the first
    /// generation) after which a *challenger* starts: a second population
    /// from random models that steps in turn with the GA, takes its place
    /// if its best overtakes the GA's, and is dropped if it stalls as long
    /// below it (see [`TandemParams::challenge`](super::TandemParams::challenge),
    /// which the tandem uses instead of this). `0` (the paper, the presets
    /// and saved parameters without the field): never; experiment files
    /// default to [`DEFAULT_CHALLENGE`](super::DEFAULT_CHALLENGE).
    #[serde(default)]
    pub challenge: u64,
}

impl Default for GaParams {
    /// The paper's spaceship settings ([`GaParams::paper_spaceship`]).
    fn default() -> Self {
        Self::paper_spaceship()
    }
}

impl GaParams {
    /// Spaceship volume (paper Fig. 7 left): P 150, E 30, `L0` 50, 30 % mutation as 13.5 / 13.5 / 3.
    #[must_use]
    pub const fn paper_spaceship() -> Self {
        Self {
            population: 150,
            elites: 30,
            init: InitLength::Around { l0: 50 },
            mutation_rate: 0.3,
            mutation_split: MutationSplit::new(13.5, 13.5, 3.0),
            tournament: 10,
            crossover: CrossoverConfig {
                max_retries: 3,
                edge_match: crate::ops::EdgeMatch::Strict,
            },
            roulette: RouletteShift::IfNegative,
            elite_dedup: false,
            local_search: 0,
            adaptive_split: false,
            challenge: 0,
        }
    }

    /// Tree sketch (paper Fig. 7 right): P 200, E 30, `L0` 250, 30 % mutation as 10.5 / 10.5 / 9.
    #[must_use]
    pub const fn paper_tree_sketch() -> Self {
        Self {
            population: 200,
            elites: 30,
            init: InitLength::Around { l0: 250 },
            mutation_split: MutationSplit::new(10.5, 10.5, 9.0),
            ..Self::paper_spaceship()
        }
    }

    /// City skyline, shoe (paper Fig. 9b): P 180, E 40, `L0` 50, 40 % mutation as 10 / 12 / 18.
    #[must_use]
    pub const fn paper_city_shoe() -> Self {
        Self {
            population: 180,
            elites: 40,
            mutation_rate: 0.4,
            mutation_split: MutationSplit::new(10.0, 12.0, 18.0),
            ..Self::paper_spaceship()
        }
    }

    /// The children bred each generation: the places not taken by elites.
    #[must_use]
    pub const fn children(&self) -> usize {
        self.population.saturating_sub(self.elites)
    }

    /// Every problem with these parameters.
    pub fn problems(&self) -> Vec<String> {
        let mut p = Vec::new();
        if self.population < 2 {
            p.push(format!(
                "population must be at least 2, got {}",
                self.population
            ));
        }
        if self.elites >= self.population {
            p.push(format!(
                "elites ({}) must be fewer than the population ({})",
                self.elites, self.population
            ));
        }
        if !(0.0..=1.0).contains(&self.mutation_rate) {
            p.push(format!(
                "mutation_rate must be in [0, 1], got {}",
                self.mutation_rate
            ));
        }
        if let Some(e) = self.mutation_split.problem() {
            p.push(e.to_string());
        }
        if self.tournament == 0 {
            p.push("tournament size must be at least 1".into());
        }
        if self.crossover.max_retries == 0 && self.mutation_rate < 1.0 {
            p.push("crossover.max_retries must be at least 1".into());
        }
        if self.local_search > self.children() {
            p.push(format!(
                "local_search ({}) must not exceed the children of a generation (population - elites = {})",
                self.local_search,
                self.children()
            ));
        }
        p
    }
}

/// The paper's genetic algorithm (Algorithm 1).
///
/// Each generation: evaluate the new individuals (copies keep their cached
/// fitness), sort best first (stable; failed evaluations last), keep the `E`
/// best, then fill the population with pairs of children. For each pair one
/// parent is drawn by k-tournament and one by roulette; with probability
/// `mutation_rate` each parent's clone gets one mutation (grow, cut or alter
/// by the split), otherwise the pair is the crossover of the parents (or
/// their copies when no compatible connection is found). Operators respect
/// the graph's limits, so every child satisfies `L_min <= L < L_max`.
///
/// Pair `i` of generation `g` draws from its own stream `(seed, g, i)`, so
/// breeding and evaluation run in parallel and the result is the same for any
/// number of threads.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Ga {
    /// The parameters.
    pub params: GaParams,
}

impl Ga {
    /// A GA with the given parameters.
    #[must_use]
    pub const fn new(params: GaParams) -> Self {
        Self { params }
    }

    /// The random initial population; individual `i` draws from the stream
    /// `(seed, 0, i, INIT[, island])`.
    pub(crate) fn initial_population(
        &self,
        graph: &Graph,
        seed: u64,
        island: Option<u64>,
    ) -> Result<Vec<Candidate>, OptimizeError> {
        (0..self.params.population as u64)
            .into_par_iter()
            .map(|i| {
                let mut rng = island_stream(seed, [0, i, purpose::INIT], island);
                Ok(Candidate::new(random_individual(
                    graph,
                    &self.params.init,
                    &mut rng,
                )?))
            })
            .collect()
    }

    /// The candidates of generation `generation` bred from `state` (sorted
    /// best first): the elites, then pairs of children, pair `i` drawn from
    /// the stream `(seed, generation, i, BREED[, island])`.
    pub(crate) fn next_generation(
        &self,
        graph: &Graph,
        state: &mut GaState,
        seed: u64,
        generation: u64,
        island: Option<u64>,
    ) -> Vec<Candidate> {
        let GaState {
            population,
            wheel,
            scores,
            split,
            origins,
        } = state;
        let split = if self.params.adaptive_split {
            split
                .get_or_insert_with(|| AdaptiveSplit::new(&self.params.mutation_split))
                .split()
        } else {
            self.params.mutation_split
        };
        let mut next = self.elites(graph, population);
        scores.clear();
        scores.extend(population.iter().map(|i| i.fitness));
        wheel.rebuild(scores, self.params.roulette);
        let local = self.local_moves(graph, population, seed, generation, island);
        let missing = self.params.population - next.len() - local.len();
        let children: Vec<(Candidate, Origin)> = (0..missing.div_ceil(2) as u64)
            .into_par_iter()
            .flat_map_iter(|i| {
                let mut rng = island_stream(seed, [generation, i, purpose::BREED], island);
                self.breed_pair(graph, population, wheel, &split, &mut rng)
            })
            .collect();
        origins.clear();
        if self.params.adaptive_split {
            origins.resize(next.len(), None);
            origins.extend(children.iter().take(missing).map(|(_, o)| *o));
            origins.resize(origins.len() + local.len(), None);
        }
        // With one place left, only the pair's first child is kept.
        next.extend(children.into_iter().take(missing).map(|(c, _)| c));
        next.extend(local);
        next
    }

    /// A first population from `models` (complete models of an earlier
    /// phase): their best distinct valid ones, repeated in turn to fill the
    /// population; the random initial population (of `island`'s streams),
    /// evaluated, if none is valid.
    pub(crate) fn population_from<F: Fitness>(
        &self,
        cx: &mut Context<'_, '_, F>,
        models: &[Individual],
        island: Option<u64>,
    ) -> Result<GaState, OptimizeError> {
        let mut sorted: Vec<&Individual> = models.iter().collect();
        sorted.sort_by(|a, b| rank_order(a.fitness, b.fitness));
        let population =
            best_distinct_repeated(cx.graph, sorted.into_iter(), self.params.population);
        if population.is_empty() {
            let initial = self.initial_population(cx.graph, cx.seed, island)?;
            return Ok(GaState::new(cx.evaluate_within_budget(initial)));
        }
        Ok(GaState::new(population))
    }

    /// The local-search children: move `i` (from the stream `(seed,
    /// generation, i, LOCAL[, island])`) starts from the `i mod d`-th of the
    /// `d` best distinct valid individuals. A move that changes nothing
    /// (no gene to move, or a jump outside the length limits) is a copy.
    fn local_moves(
        &self,
        graph: &Graph,
        sorted: &[Individual],
        seed: u64,
        generation: u64,
        island: Option<u64>,
    ) -> Vec<Candidate> {
        let n = self.params.local_search;
        if n == 0 {
            return Vec::new();
        }
        let starts = best_distinct(graph, sorted.iter(), n);
        if starts.is_empty() {
            return Vec::new();
        }
        (0..n as u64)
            .into_par_iter()
            .map(|i| {
                let x = starts[i as usize % starts.len()];
                let mut rng = island_stream(seed, [generation, i, purpose::LOCAL], island);
                let moved = propose(graph, &x.chromosome, 0.5, true, &mut rng);
                if moved.changed {
                    Candidate::new(moved.state)
                } else {
                    Candidate {
                        chromosome: x.chromosome.clone(),
                        fitness: Some(x.fitness),
                    }
                }
            })
            .collect()
    }

    /// The elites: the `E` best valid individuals, each structure once if `elite_dedup`.
    fn elites(&self, graph: &Graph, sorted: &[Individual]) -> Vec<Candidate> {
        let mut seen = HashSet::new();
        sorted
            .iter()
            .filter(|i| is_valid_score(i.fitness))
            .filter(|i| {
                !self.params.elite_dedup || seen.insert(i.chromosome.structural_hash(graph))
            })
            .take(self.params.elites)
            .map(|i| Candidate {
                chromosome: i.chromosome.clone(),
                fitness: Some(i.fitness),
            })
            .collect()
    }

    /// A pair of children, each with the mutation that made it and its
    /// parent's fitness (none for crossovers); `split` is this generation's
    /// mutation split (the parameters' own, or the adaptive one).
    fn breed_pair(
        &self,
        graph: &Graph,
        sorted: &[Individual],
        wheel: &Roulette,
        split: &MutationSplit,
        rng: &mut ShapeRng,
    ) -> [(Candidate, Origin); 2] {
        let p = &self.params;
        let a = &sorted[tournament(sorted.len(), p.tournament, rng)];
        let b = &sorted[wheel.pick(rng)];
        let copy = |i: &Individual| Candidate {
            chromosome: i.chromosome.clone(),
            fitness: Some(i.fitness),
        };
        if rand::RngExt::random_bool(rng, p.mutation_rate) {
            [a, b].map(|parent| {
                let mut child = copy(parent);
                let (kind, changed) = mutate(graph, &mut child.chromosome, split, rng);
                if changed {
                    child.fitness = None;
                }
                (child, Some((kind, parent.fitness)))
            })
        } else {
            match crossover(graph, &a.chromosome, &b.chromosome, &p.crossover, rng) {
                Some((c1, c2)) => [(Candidate::new(c1), None), (Candidate::new(c2), None)],
                None => [(copy(a), None), (copy(b), None)],
            }
        }
    }
}

impl Optimizer for Ga {
    fn name(&self) -> &'static str {
        "ga"
    }

    fn run_from<F: Fitness>(&self, run: Run<'_, F>) -> Result<RunResult, OptimizeError> {
        drive(self, run)
    }
}

/// The GA's state: the population, the roulette and score buffers reused
/// across generations, and with an adaptive split, the split and where each
/// candidate of the generation being evaluated came from.
pub(crate) struct GaState {
    pub population: Vec<Individual>,
    wheel: Roulette,
    scores: Vec<f64>,
    /// The adaptive split (made by the first generation that uses it).
    pub split: Option<AdaptiveSplit>,
    /// The origin of each candidate `next_generation` returned last.
    origins: Vec<Origin>,
}

impl GaState {
    /// The state of `population`, sorted best first (stable; failed
    /// evaluations last) as selection and the elites expect.
    pub fn new(population: Vec<Individual>) -> Self {
        let mut state = Self {
            scores: Vec::with_capacity(population.len()),
            population: Vec::new(),
            wheel: Roulette::default(),
            split: None,
            origins: Vec::new(),
        };
        state.replace(population);
        state
    }

    /// Makes `evaluated`, the candidates of the last `next_generation` in
    /// their order, the current population; an adaptive split learns from it.
    pub fn settle(&mut self, evaluated: Vec<Individual>) {
        if let Some(split) = &mut self.split
            && self.origins.len() == evaluated.len()
        {
            split.learn(&self.origins, &evaluated);
        }
        self.origins.clear();
        self.replace(evaluated);
    }

    /// Makes `population` the current one, sorted best first.
    pub fn replace(&mut self, mut population: Vec<Individual>) {
        population.sort_by(|a, b| rank_order(a.fitness, b.fitness));
        self.population = population;
    }
}

impl Ga {
    /// The state saved in `saved`.
    pub(crate) fn restore_state(
        &self,
        graph: &Graph,
        saved: &SavedState,
    ) -> Result<GaState, OptimizeError> {
        let SavedState::Population {
            individuals,
            split_bits,
            ..
        } = saved
        else {
            return Err(OptimizeError::Checkpoint(
                "it holds no GA population".into(),
            ));
        };
        if individuals.len() != self.params.population {
            return Err(OptimizeError::Checkpoint(format!(
                "it holds {} individuals for a population of {}",
                individuals.len(),
                self.params.population
            )));
        }
        let population = individuals
            .iter()
            .map(|i| i.restore(graph))
            .collect::<Result<Vec<_>, _>>()?;
        let mut state = GaState::new(population);
        state.split = split_bits.map(AdaptiveSplit::from_bits);
        Ok(state)
    }

    /// The state a checkpoint saves.
    pub(crate) fn save_state(&self, graph: &Graph, state: &GaState) -> SavedState {
        SavedState::Population {
            individuals: state
                .population
                .iter()
                .map(|i| SavedIndividual::save(graph, i))
                .collect(),
            split_bits: state.split.map(AdaptiveSplit::to_bits),
            challenge: None,
        }
    }
}

impl Ga {
    /// A lone GA's population `state` with no challenger yet.
    pub(crate) fn alone(state: GaState) -> Challenged {
        Challenged::new(state, None, Lineage::ALONE)
    }

    /// The population and challenger saved in `saved` (a
    /// [`SavedState::Population`]).
    pub(crate) fn restore_challenged(
        &self,
        graph: &Graph,
        saved: &SavedState,
    ) -> Result<Challenged, OptimizeError> {
        let incumbent = self.restore_state(graph, saved)?;
        let challenge = match saved {
            SavedState::Population { challenge, .. } => challenge.as_deref(),
            _ => None,
        };
        Challenged::restore(self, graph, incumbent, None, Lineage::ALONE, challenge)
    }

    /// What [`restore_challenged`](Self::restore_challenged) restores.
    pub(crate) fn save_challenged(&self, graph: &Graph, state: &Challenged) -> SavedState {
        let mut saved = self.save_state(graph, &state.incumbent);
        if let SavedState::Population { challenge, .. } = &mut saved
            && self.params.challenge > 0
        {
            *challenge = Some(Box::new(state.save(self, graph)));
        }
        saved
    }
}

impl Method for Ga {
    type Params = GaParams;
    type State = Challenged;

    fn name(&self) -> &'static str {
        "ga"
    }

    fn params(&self) -> &GaParams {
        &self.params
    }

    fn problems(&self) -> Vec<String> {
        self.params.problems()
    }

    fn init<F: Fitness>(&self, cx: &mut Context<'_, '_, F>) -> Result<Challenged, OptimizeError> {
        // Stopped by Ctrl-C or the clock like any generation: a generation 0
        // slower than the budget ends at the budget, with the models
        // evaluated by then (the rest are NaN).
        let initial = self.initial_population(cx.graph, cx.seed, None)?;
        Ok(Self::alone(GaState::new(
            cx.evaluate_within_budget(initial),
        )))
    }

    fn restore(&self, graph: &Graph, checkpoint: &Checkpoint) -> Result<Challenged, OptimizeError> {
        self.restore_challenged(graph, &checkpoint.state)
    }

    fn save(&self, graph: &Graph, state: &Challenged) -> SavedState {
        self.save_challenged(graph, state)
    }

    fn report<'s>(&self, _graph: &Graph, state: &'s Challenged) -> Cow<'s, [Individual]> {
        if state.challenger_models().is_empty() {
            Cow::Borrowed(&state.incumbent.population)
        } else {
            Cow::Owned(state.models_best_first())
        }
    }

    fn final_population(&self, _graph: &Graph, state: Challenged) -> Vec<Individual> {
        state.into_models()
    }

    fn step<F: Fitness>(
        &self,
        cx: &mut Context<'_, '_, F>,
        state: &mut Challenged,
    ) -> Result<ControlFlow<Vec<Individual>>, OptimizeError> {
        let side = state.side();
        let next = state.candidates(self, cx.graph, cx.seed, cx.generation(), side)?;
        match cx.evaluate_interruptible(next) {
            Some(evaluated) => {
                state.settle(side, evaluated, self.params.challenge);
                Ok(ControlFlow::Continue(()))
            }
            None => Ok(ControlFlow::Break(state.take_models())),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::genome::Chromosome;
    use crate::graph::{Dist, GraphBuilder};
    use crate::optimize::{Budget, FnFitness, NoObserver};

    fn graph() -> Graph {
        GraphBuilder::new("t")
            .start("S")
            .node("S", |n| n.slot("a", "A", 1.0))
            .node("A", |n| {
                n.param_f32("x", Dist::uniform(0.0, 1.0))
                    .slot("l", "A", 0.5)
                    .slot("r", "A", 0.5)
            })
            .build()
            .unwrap()
    }

    #[test]
    fn bad_params_and_budget_are_errors() {
        let g = graph();
        let f = FnFitness(|c: &Chromosome| c.len() as f64);
        let ga = Ga::new(GaParams {
            population: 10,
            elites: 10,
            tournament: 0,
            ..GaParams::default()
        });
        let err = ga
            .run(&g, &f, &Budget::generations(1), 0, &mut NoObserver)
            .unwrap_err();
        let OptimizeError::Params(text) = err else {
            panic!("{err:?}")
        };
        assert!(
            text.contains("elites") && text.contains("tournament"),
            "{text}"
        );
        let ga = Ga::new(GaParams {
            population: 10,
            elites: 2,
            ..GaParams::default()
        });
        assert_eq!(
            ga.run(&g, &f, &Budget::default(), 0, &mut NoObserver)
                .unwrap_err(),
            OptimizeError::UnboundedBudget
        );
    }

    #[test]
    fn nan_fitness_ranks_last_and_never_wins() {
        let g = graph();
        // Odd lengths fail to evaluate.
        let f = FnFitness(|c: &Chromosome| {
            if c.len() % 2 == 1 {
                f64::NAN
            } else {
                c.len() as f64
            }
        });
        let ga = Ga::new(GaParams {
            population: 30,
            elites: 5,
            init: InitLength::Between { lo: 2, hi: 20 },
            ..GaParams::default()
        });
        let r = ga
            .run(&g, &f, &Budget::generations(15), 3, &mut NoObserver)
            .unwrap();
        assert!(r.best_fitness.is_finite() && r.best.len() % 2 == 0);
        let firsts: Vec<f64> = r.population.iter().map(|i| i.fitness).collect();
        let first_nan = firsts
            .iter()
            .position(|f| f.is_nan())
            .unwrap_or(firsts.len());
        assert!(
            firsts[first_nan..].iter().all(|f| f.is_nan()),
            "NaN sorted last: {firsts:?}"
        );
    }

    /// A generation 0 slower than the wall-clock budget ends at the budget
    /// with the models evaluated by then (the paper's huge shapes can make
    /// one evaluation take seconds): 40 models of 20 ms each on one thread
    /// would take 0.8 s; the budget is 0.1 s.
    #[test]
    fn a_slow_initial_population_stops_at_the_budget() {
        let g = graph();
        let f = FnFitness(|c: &Chromosome| {
            std::thread::sleep(std::time::Duration::from_millis(20));
            c.len() as f64
        });
        let ga = Ga::new(GaParams {
            population: 40,
            elites: 5,
            init: InitLength::Between { lo: 2, hi: 20 },
            ..GaParams::default()
        });
        let budget = Budget {
            wall_time: Some(std::time::Duration::from_millis(100)),
            ..Budget::default()
        };
        let r = ga.run(&g, &f, &budget, 1, &mut NoObserver).unwrap();
        assert_eq!(r.generations, 0);
        assert!(
            r.evaluations >= 1 && r.evaluations < 40,
            "{} evaluations",
            r.evaluations
        );
        assert!(r.best_fitness.is_finite());
        let valid = r
            .population
            .iter()
            .filter(|i| i.fitness.is_finite())
            .count() as u64;
        assert_eq!(valid, r.evaluations, "the skipped models are NaN");
    }

    #[test]
    fn cached_fitness_matches_evaluation_and_counts_are_consistent() {
        let g = graph();
        let f = FnFitness(|c: &Chromosome| -(c.len() as f64 - 12.0).abs());
        let ga = Ga::new(GaParams {
            population: 20,
            elites: 4,
            init: InitLength::Between { lo: 1, hi: 30 },
            ..GaParams::default()
        });
        let mut gens = 0;
        let mut last_evals = 0;
        let mut observer = |s: &super::super::GenerationStats<'_>| {
            assert_eq!(s.generation, gens);
            assert!(s.evaluations >= last_evals);
            // New evaluations per generation: at most P − E (elites are cached).
            if gens > 0 {
                assert!(s.evaluations - last_evals <= 16);
            }
            gens += 1;
            last_evals = s.evaluations;
            std::ops::ControlFlow::Continue(())
        };
        let r = ga
            .run(&g, &f, &Budget::generations(10), 1, &mut observer)
            .unwrap();
        assert_eq!(r.generations, 10);
        assert_eq!(r.evaluations, last_evals);
        for i in &r.population {
            assert_eq!(i.fitness, (f.0)(&i.chromosome));
            i.chromosome.validate(&g).unwrap();
        }
    }
}
