//! The island GA: several populations evolving apart, exchanging their best.

use std::borrow::Cow;
use std::ops::ControlFlow;

use rand::RngExt;
use serde::{Deserialize, Serialize};

use super::adaptive_split::AdaptiveSplit;
use super::challenger::{Challenged, Lineage};
use super::checkpoint::{Checkpoint, SavedIndividual, SavedState};
use super::driver::{Context, Method, Run, drive};
use super::ga::GaState;
use super::selection::rank_order;
use super::{Fitness, Ga, GaParams, Individual, OptimizeError, Optimizer, RunResult, purpose};
use crate::graph::Graph;
use crate::rng::stream;

/// Where an island's migrants go.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Topology {
    /// Island `k` sends to island `k + 1` (the last to the first).
    #[default]
    Ring,
    /// Each island sends to another island drawn at random at each migration.
    Random,
}

/// Parameters of the [`IslandGa`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct IslandParams {
    /// Each island's GA (its population size is per island).
    pub ga: GaParams,
    /// Number of islands `k`.
    pub islands: usize,
    /// Generations between migrations.
    pub interval: u64,
    /// How many of its best individuals an island sends at each migration;
    /// they replace the receiving island's worst.
    pub migrants: usize,
    /// Where migrants go.
    pub topology: Topology,
}

impl IslandParams {
    /// Four islands of a quarter of `ga`'s population each (elites scaled
    /// alike, at least 1), exchanging their 2 best every 10 generations on a ring.
    #[must_use]
    pub fn split(ga: GaParams) -> Self {
        Self::split_into(ga, 4)
    }

    /// [`split`](Self::split) into `islands` islands (at least 1) of
    /// `ga.population / islands` individuals (at least 2).
    #[must_use]
    pub fn split_into(ga: GaParams, islands: usize) -> Self {
        let islands = islands.max(1);
        let population = (ga.population / islands).max(2);
        Self {
            ga: GaParams {
                population,
                elites: (ga.elites / islands).clamp(1, population - 1),
                ..ga
            },
            islands,
            interval: 10,
            migrants: 2,
            topology: Topology::Ring,
        }
    }

    /// Every problem with these parameters.
    pub fn problems(&self) -> Vec<String> {
        let mut p = self.ga.problems();
        if self.islands == 0 {
            p.push("islands must be at least 1".into());
        }
        if self.interval == 0 {
            p.push("the migration interval must be at least 1 generation".into());
        }
        if self.migrants >= self.ga.population {
            p.push(format!(
                "migrants ({}) must be fewer than an island's population ({})",
                self.migrants, self.ga.population
            ));
        }
        p
    }
}

/// `k` GA populations ([`Ga`], Algorithm 1 each) evolving independently;
/// every `interval` generations each island's `migrants` best replace the
/// worst of the island its [`Topology`] names.
///
/// Island `k` breeds from its own streams (the GA's, extended by `k`), all
/// islands' children are evaluated together, and a migration is decided by
/// generation-level streams, so the result is the same for any number of
/// threads.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IslandGa {
    /// The parameters.
    pub params: IslandParams,
}

impl IslandGa {
    /// An island GA with the given parameters.
    #[must_use]
    pub const fn new(params: IslandParams) -> Self {
        Self { params }
    }

    fn ga(&self) -> Ga {
        Ga::new(self.params.ga)
    }

    /// Where island `k`'s challengers draw their streams.
    fn lineage(&self, k: u64) -> Lineage {
        Lineage {
            home: k,
            stride: self.params.islands as u64,
        }
    }

    /// Island `k`'s population `state`, with no challenger yet.
    fn island(&self, k: u64, state: GaState) -> Challenged {
        Challenged::new(state, Some(k), self.lineage(k))
    }

    /// Each island's population, from one evaluated batch of all of them.
    fn split(&self, mut all: Vec<Individual>) -> Vec<Challenged> {
        let n = self.params.ga.population;
        let mut islands = Vec::with_capacity(self.params.islands);
        while !all.is_empty() {
            let rest = all.split_off(n.min(all.len()));
            islands.push(self.island(islands.len() as u64, GaState::new(all)));
            all = rest;
        }
        islands
    }

    /// Sends each island's best to its destination, replacing the worst
    /// there (the islands' incumbents; challengers neither send nor
    /// receive, so a population that has spread over every island cannot
    /// take them over before they overtake it).
    fn migrate(&self, islands: &mut [Challenged], seed: u64, generation: u64) {
        let k = islands.len();
        let m = self.params.migrants;
        if k < 2 || m == 0 {
            return;
        }
        let migrants: Vec<Vec<Individual>> = islands
            .iter()
            .map(|s| s.incumbent.population[..m].to_vec())
            .collect();
        let mut rng = stream(seed, &[generation, u64::MAX, purpose::MIGRATE]);
        for (from, group) in migrants.into_iter().enumerate() {
            let to = match self.params.topology {
                Topology::Ring => (from + 1) % k,
                Topology::Random => (from + 1 + rng.random_range(0..k - 1)) % k,
            };
            let island = &mut islands[to].incumbent;
            let mut population = std::mem::take(&mut island.population);
            let keep = population.len() - m;
            population.truncate(keep);
            population.extend(group);
            island.replace(population);
        }
    }
}

impl Optimizer for IslandGa {
    fn name(&self) -> &'static str {
        "islands"
    }

    fn run_from<F: Fitness>(&self, run: Run<'_, F>) -> Result<RunResult, OptimizeError> {
        drive(self, run)
    }
}

impl Method for IslandGa {
    type Params = IslandParams;
    type State = Vec<Challenged>;

    fn name(&self) -> &'static str {
        "islands"
    }

    fn params(&self) -> &IslandParams {
        &self.params
    }

    fn problems(&self) -> Vec<String> {
        self.params.problems()
    }

    fn init<F: Fitness>(
        &self,
        cx: &mut Context<'_, '_, F>,
    ) -> Result<Vec<Challenged>, OptimizeError> {
        let mut all = Vec::new();
        for k in 0..self.params.islands as u64 {
            all.extend(self.ga().initial_population(cx.graph, cx.seed, Some(k))?);
        }
        Ok(self.split(cx.evaluate_within_budget(all)))
    }

    fn restore(
        &self,
        graph: &Graph,
        checkpoint: &Checkpoint,
    ) -> Result<Vec<Challenged>, OptimizeError> {
        let SavedState::Islands {
            islands,
            split_bits,
            challenges,
        } = &checkpoint.state
        else {
            return Err(OptimizeError::Checkpoint(
                "it holds no island populations".into(),
            ));
        };
        let (k, n) = (self.params.islands, self.params.ga.population);
        if islands.len() != k || islands.iter().any(|i| i.len() != n) {
            return Err(OptimizeError::Checkpoint(format!(
                "it does not hold {k} islands of {n} individuals"
            )));
        }
        if !split_bits.is_empty() && split_bits.len() != k {
            return Err(OptimizeError::Checkpoint(format!(
                "it holds mutation splits for {} islands, not {k}",
                split_bits.len()
            )));
        }
        if !challenges.is_empty() && challenges.len() != k {
            return Err(OptimizeError::Checkpoint(format!(
                "it holds challenges for {} islands, not {k}",
                challenges.len()
            )));
        }
        islands
            .iter()
            .enumerate()
            .map(|(i, island)| {
                let population = island
                    .iter()
                    .map(|i| i.restore(graph))
                    .collect::<Result<Vec<_>, _>>()?;
                let mut state = GaState::new(population);
                state.split = split_bits.get(i).map(|&b| AdaptiveSplit::from_bits(b));
                let k = i as u64;
                Challenged::restore(
                    &self.ga(),
                    graph,
                    state,
                    Some(k),
                    self.lineage(k),
                    challenges.get(i),
                )
            })
            .collect()
    }

    fn save(&self, graph: &Graph, islands: &Vec<Challenged>) -> SavedState {
        SavedState::Islands {
            islands: islands
                .iter()
                .map(|s| {
                    s.incumbent
                        .population
                        .iter()
                        .map(|i| SavedIndividual::save(graph, i))
                        .collect()
                })
                .collect(),
            split_bits: islands
                .iter()
                .filter_map(|s| s.incumbent.split.map(AdaptiveSplit::to_bits))
                .collect(),
            challenges: if self.params.ga.challenge > 0 {
                islands.iter().map(|s| s.save(&self.ga(), graph)).collect()
            } else {
                Vec::new()
            },
        }
    }

    fn report<'s>(&self, _graph: &Graph, islands: &'s Vec<Challenged>) -> Cow<'s, [Individual]> {
        Cow::Owned(
            islands
                .iter()
                .flat_map(|s| {
                    (s.incumbent.population.iter())
                        .chain(s.challenger_models())
                        .cloned()
                })
                .collect(),
        )
    }

    fn final_population(&self, _graph: &Graph, islands: Vec<Challenged>) -> Vec<Individual> {
        let mut all: Vec<Individual> = islands
            .into_iter()
            .flat_map(Challenged::into_models)
            .collect();
        all.sort_by(|a, b| rank_order(a.fitness, b.fitness));
        all
    }

    fn step<F: Fitness>(
        &self,
        cx: &mut Context<'_, '_, F>,
        islands: &mut Vec<Challenged>,
    ) -> Result<ControlFlow<Vec<Individual>>, OptimizeError> {
        let (graph, seed, g) = (cx.graph, cx.seed, cx.generation());
        let ga = self.ga();
        let mut all = Vec::with_capacity(islands.len() * self.params.ga.population);
        let mut steps = Vec::with_capacity(islands.len());
        for island in islands.iter_mut() {
            let side = island.side();
            let next = island.candidates(&ga, graph, seed, g, side)?;
            steps.push((side, next.len()));
            all.extend(next);
        }
        let Some(evaluated) = cx.evaluate_interruptible(all) else {
            let previous = std::mem::take(islands);
            return Ok(ControlFlow::Break(
                previous
                    .into_iter()
                    .flat_map(Challenged::into_models)
                    .collect(),
            ));
        };
        let mut rest = evaluated;
        for (island, (side, count)) in islands.iter_mut().zip(steps) {
            let tail = rest.split_off(count.min(rest.len()));
            island.settle(side, rest, self.params.ga.challenge);
            rest = tail;
        }
        if g % self.params.interval == 0 {
            self.migrate(islands, seed, g);
        }
        Ok(ControlFlow::Continue(()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optimize::test_support::with_fitness;

    #[test]
    fn a_ring_migration_replaces_each_next_islands_worst_with_the_best() {
        let individual = with_fitness();
        let island = |scores: &[f64]| {
            Ga::alone(GaState::new(
                scores.iter().map(|&f| individual(f)).collect(),
            ))
        };
        let ga = IslandGa::new(IslandParams {
            ga: GaParams {
                population: 4,
                elites: 1,
                ..GaParams::paper_spaceship()
            },
            islands: 3,
            interval: 1,
            migrants: 1,
            topology: Topology::Ring,
        });
        let mut islands = vec![
            island(&[9.0, 8.0, 7.0, 6.0]),
            island(&[5.0, 4.0, 3.0, 2.0]),
            island(&[1.0, 0.5, 0.25, 0.0]),
        ];
        ga.migrate(&mut islands, 1, 1);
        let scores: Vec<Vec<f64>> = islands
            .iter()
            .map(|s| s.incumbent.population.iter().map(|i| i.fitness).collect())
            .collect();
        assert_eq!(
            scores,
            [
                vec![9.0, 8.0, 7.0, 1.0],
                vec![9.0, 5.0, 4.0, 3.0],
                vec![5.0, 1.0, 0.5, 0.25],
            ]
        );
    }
}
