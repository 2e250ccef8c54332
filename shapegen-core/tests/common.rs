//! Shared property-test support: random generator graphs and a naive tree
//! model of chromosomes to check the packed genome against.
#![allow(dead_code)]

use std::collections::BTreeMap;

use proptest::prelude::*;
use shapegen_core::prelude::*;

/// A random parameter distribution (always valid).
fn param_dist() -> impl Strategy<Value = ParamDist> {
    let scalar = prop_oneof![
        (-5.0f32..5.0, 0.0f32..3.0).prop_map(|(lo, w)| Dist::uniform(lo, lo + w)),
        (-5.0f32..5.0).prop_map(Dist::constant),
        (-5.0f32..5.0, 0.1f32..2.0).prop_map(|(m, s)| Dist::normal(m, s)),
        (-2.0f32..2.0, 0.1f32..2.0, 0.0f32..1.0).prop_map(|(m, s, w)| Dist::truncated_normal(
            m,
            s,
            m - w,
            m + w + 0.1
        )),
    ];
    prop_oneof![
        scalar.clone().prop_map(ParamDist::F32),
        [scalar.clone(), scalar.clone()].prop_map(ParamDist::Vec2),
        [scalar.clone(), scalar.clone(), scalar].prop_map(ParamDist::Vec3),
        (-10i32..10, 0i32..5)
            .prop_map(|(lo, w)| ParamDist::Int(IntDist::Uniform { lo, hi: lo + w })),
        proptest::collection::vec(0.0f64..3.0, 1..5).prop_map(|mut w| {
            w[0] += 0.5;
            ParamDist::Choice(w.into())
        }),
    ]
}

/// A slot probability: often exactly 0 or 1, otherwise in (0, 1).
fn probability() -> impl Strategy<Value = f64> {
    prop_oneof![1 => Just(0.0), 2 => Just(1.0), 4 => 0.05f64..0.95]
}

/// A random valid generator graph: 1-7 nodes with random parameters, slots
/// (recursion allowed), probabilities including 0 and 1, and random limits.
pub fn graph() -> impl Strategy<Value = Graph> {
    (1usize..8)
        .prop_flat_map(|n| {
            let node = (
                proptest::collection::vec(param_dist(), 0..4),
                proptest::collection::vec((0..n, probability()), 0..4),
                any::<bool>(),
            );
            (
                proptest::collection::vec(node, n),
                // For node i > 0: the earlier node that gets a slot to it (reachability).
                proptest::collection::vec((any::<prop::sample::Index>(), probability()), n),
                prop_oneof![Just(None), (2u32..12).prop_map(Some)],
                1u32..4,
                prop_oneof![Just(None), (8u32..200).prop_map(Some)],
            )
        })
        .prop_map(|(nodes, links, max_depth, min_len, max_len)| {
            let n = nodes.len();
            let mut b = GraphBuilder::new("random").start("N0").limits(Limits {
                max_depth,
                min_len,
                max_len: max_len.map(|m| m + min_len),
            });
            let mut extra: BTreeMap<usize, Vec<(usize, f64)>> = BTreeMap::new();
            for (i, (idx, p)) in links.iter().enumerate().skip(1) {
                // Keep reachability slots growable so random individuals reach L_min.
                extra.entry(idx.index(i)).or_default().push((i, p.max(0.3)));
            }
            for (i, (params, slots, emits)) in nodes.into_iter().enumerate() {
                let extra = extra.remove(&i).unwrap_or_default();
                b = b.node(format!("N{i}"), |mut nb| {
                    if emits {
                        nb = nb.emits();
                    }
                    for (k, d) in params.into_iter().enumerate() {
                        nb = nb.param(format!("p{k}"), d);
                    }
                    for (k, (t, p)) in slots.into_iter().chain(extra).enumerate() {
                        nb = nb.slot(format!("s{k}"), format!("N{}", t % n), p);
                    }
                    nb
                });
            }
            b.build().expect("generated graphs are valid")
        })
        .prop_filter("the start node must be able to reach L_min", |g| {
            let mut rng = shapegen_core::rng::stream(0, &[]);
            (0..4).all(|_| {
                random_individual(
                    g,
                    &InitLength::Fixed {
                        l0: g.limits().min_len,
                    },
                    &mut rng,
                )
                .is_ok()
            })
        })
}

/// The naive model of a derivation tree: node, parameter words, one optional child per slot.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Tree {
    pub node: u16,
    pub params: Vec<u32>,
    pub children: Vec<Option<Tree>>,
}

impl Tree {
    /// Builds the model by following links from the root.
    pub fn of(graph: &Graph, c: &Chromosome) -> Tree {
        Self::at(graph, c, 0)
    }

    fn at(graph: &Graph, c: &Chromosome, pos: u32) -> Tree {
        let g = c.gene(graph, pos);
        Tree {
            node: g.node(),
            params: g.params().to_vec(),
            children: (0..g.slot_count())
                .map(|j| g.child(j).map(|p| Self::at(graph, c, p)))
                .collect(),
        }
    }

    pub fn len(&self) -> usize {
        1 + self.children.iter().flatten().map(Tree::len).sum::<usize>()
    }

    /// The subtree at `path` (slot indices from the root).
    pub fn get(&self, path: &[usize]) -> &Tree {
        path.iter()
            .fold(self, |t, &j| t.children[j].as_ref().expect("path exists"))
    }

    /// Replaces the optional child at `path` (non-empty) and returns the old one.
    pub fn replace(&mut self, path: &[usize], with: Option<Tree>) -> Option<Tree> {
        let (last, init) = path.split_last().expect("non-root path");
        let mut t = self;
        for &j in init {
            t = t.children[j].as_mut().expect("path exists");
        }
        std::mem::replace(&mut t.children[*last], with)
    }

    /// Multiset of (node, params) over all genes.
    pub fn gene_multiset(&self, into: &mut BTreeMap<(u16, Vec<u32>), usize>) {
        *into.entry((self.node, self.params.clone())).or_default() += 1;
        self.children
            .iter()
            .flatten()
            .for_each(|c| c.gene_multiset(into));
    }
}

/// Slot path from the root to the gene at `pos`.
pub fn path_of(graph: &Graph, c: &Chromosome, pos: u32) -> Vec<usize> {
    let mut path = Vec::new();
    let mut g = c.gene(graph, pos);
    while let Some(p) = g.parent() {
        path.push(g.slot_in_parent() as usize);
        g = c.gene(graph, p);
    }
    path.reverse();
    path
}

/// Runs `optimizer` on the 20-block problem with 25,000 evaluations for
/// each seed: it must come within 5 % of the optimum (1.0) with a valid
/// model and beat random search given its evaluations by 0.3. Returns the
/// results for further checks.
pub fn reaches_the_blocks_optimum<O: Optimizer>(
    optimizer: impl Fn(u64) -> O,
    seeds: &[u64],
) -> Vec<RunResult> {
    use shapegen_core::demo::{BlocksTarget, blocks_graph};
    let graph = blocks_graph();
    let fitness = BlocksTarget {
        graph: &graph,
        blocks: 20,
    };
    let mut results = Vec::new();
    for &seed in seeds {
        let opt = optimizer(seed);
        let r = opt
            .run(
                &graph,
                &fitness,
                &Budget::evaluations(25_000),
                seed,
                &mut NoObserver,
            )
            .unwrap();
        let random = RandomSearch {
            batch: 100,
            init: InitLength::Around { l0: 20 },
        }
        .run(
            &graph,
            &fitness,
            &Budget::evaluations(r.evaluations),
            seed,
            &mut NoObserver,
        )
        .unwrap();
        let name = opt.name();
        assert!(
            r.best_fitness <= 1.0 + 1e-12,
            "{name}: above the optimum: {}",
            r.best_fitness
        );
        assert!(
            r.best_fitness > 0.95,
            "{name}, seed {seed}: reached only {}",
            r.best_fitness
        );
        assert!(
            r.best_fitness > random.best_fitness + 0.3,
            "{name}, seed {seed}: {} vs random search {} with {} evaluations",
            r.best_fitness,
            random.best_fitness,
            random.evaluations
        );
        r.best.validate(&graph).unwrap();
        results.push(r);
    }
    results
}

/// Runs `optimizer` for `generations` on the 30-block problem with seed 7
/// on 1, 2 and 4 threads, asserting the same best, evaluations and final
/// population each time; returns the seed-7 run and a seed-8 run (on one
/// thread), for the caller to check that another seed differs.
pub fn same_result_whatever_the_thread_count<O: Optimizer + Sync>(
    optimizer: &O,
    generations: u64,
) -> (RunResult, RunResult) {
    use shapegen_core::demo::{BlocksTarget, blocks_graph};
    let graph = blocks_graph();
    let fitness = BlocksTarget {
        graph: &graph,
        blocks: 30,
    };
    let run = |threads, seed| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                optimizer
                    .run(
                        &graph,
                        &fitness,
                        &Budget::generations(generations),
                        seed,
                        &mut NoObserver,
                    )
                    .unwrap()
            })
    };
    let one = run(1, 7);
    for threads in [2, 4] {
        let many = run(threads, 7);
        let name = optimizer.name();
        assert_eq!(
            one.best_fitness.to_bits(),
            many.best_fitness.to_bits(),
            "{name}"
        );
        assert_eq!(one.best, many.best, "{name}");
        assert_eq!(one.evaluations, many.evaluations, "{name}");
        assert_eq!(one.population, many.population, "{name}");
    }
    let other = run(1, 8);
    (one, other)
}
