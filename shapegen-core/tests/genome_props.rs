//! Property tests of the packed genome and its operators over random
//! generator graphs and long random operation sequences.

use std::collections::BTreeMap;

use crate::common::{Tree, path_of};
use proptest::prelude::*;
use rand::RngExt;
use shapegen_core::ops::UNBOUNDED_CAP;
use shapegen_core::prelude::*;
use shapegen_core::rng::{ShapeRng, stream};

const OPS_PER_CASE: usize = 1500;

fn multiset(graph: &Graph, cs: &[&Chromosome]) -> BTreeMap<(u16, Vec<u32>), usize> {
    let mut m = BTreeMap::new();
    for c in cs {
        Tree::of(graph, c).gene_multiset(&mut m);
    }
    m
}

fn check_valid(graph: &Graph, c: &Chromosome, what: &str) -> Result<(), TestCaseError> {
    c.validate(graph)
        .map_err(|e| TestCaseError::fail(format!("{what} produced an invalid chromosome: {e}")))?;
    prop_assert_eq!(c.len(), Tree::of(graph, c).len());
    Ok(())
}

/// One random operation on a random member of `pop`, with its specific property checked.
fn random_op(
    graph: &Graph,
    pop: &mut [Chromosome],
    rng: &mut ShapeRng,
) -> Result<(), TestCaseError> {
    let i = rng.random_range(0..pop.len());
    let before = pop[i].clone();
    let before_tree = Tree::of(graph, &before);
    match rng.random_range(0..6u32) {
        0 | 1 => {
            let c = &mut pop[i];
            if let Some(g) = grow(graph, c, rng) {
                check_valid(graph, c, "grow")?;
                prop_assert_eq!(c.len(), before.len() + 1, "grow adds exactly one gene");
                prop_assert!(
                    graph.edge(c.gene(graph, g.parent).node(), g.slot).p > 0.0,
                    "p = 0 slot grown"
                );
                // The model: the old tree with one new leaf at the grown slot.
                let mut expected = before_tree;
                let path: Vec<usize> = path_of(graph, c, g.child);
                let leaf = Tree::of(graph, c).get(&path).clone();
                prop_assert!(leaf.children.iter().all(Option::is_none));
                prop_assert_eq!(expected.replace(&path, Some(leaf)), None);
                prop_assert_eq!(Tree::of(graph, c), expected);
            } else {
                prop_assert_eq!(
                    &pop[i],
                    &before,
                    "a grow that did nothing changed the chromosome"
                );
            }
        }
        2 => {
            // Choose the victim ourselves through the public API to know the path.
            let c = &mut pop[i];
            let victims: Vec<u32> = c.genes(graph).skip(1).map(|g| g.pos()).collect();
            let removed_path = if victims.is_empty() {
                None
            } else {
                let v = victims[rng.random_range(0..victims.len())];
                Some((path_of(graph, c, v), v))
            };
            match removed_path {
                Some((path, v)) => match cut_at(graph, c, v) {
                    Ok(cut) => {
                        check_valid(graph, c, "cut_at")?;
                        let mut expected = before_tree;
                        let gone = expected.replace(&path, None).expect("victim existed");
                        prop_assert_eq!(cut.removed, gone.len());
                        prop_assert_eq!(
                            Tree::of(graph, c),
                            expected,
                            "cut removes exactly the subtree"
                        );
                    }
                    Err(OpError::Limits) => {
                        prop_assert!(
                            before.len() - before.subtree_len(graph, v)
                                < graph.limits().min_len as usize
                        );
                        prop_assert_eq!(&pop[i], &before);
                    }
                    Err(e) => return Err(TestCaseError::fail(format!("cut_at failed: {e}"))),
                },
                None => prop_assert_eq!(cut_at(graph, c, 0), Err(OpError::Root)),
            }
        }
        3 => {
            let c = &mut pop[i];
            match cut(graph, c, rng) {
                Some(cut) => {
                    check_valid(graph, c, "cut")?;
                    let p = graph.edge(c.gene(graph, cut.parent).node(), cut.slot).p;
                    prop_assert!(p < 1.0, "a p = 1 child was cut");
                    prop_assert_eq!(c.len() + cut.removed, before.len());
                }
                None => prop_assert_eq!(&pop[i], &before),
            }
        }
        4 => {
            let c = &mut pop[i];
            if let Some(pos) = alter(graph, c, rng) {
                check_valid(graph, c, "alter")?;
                prop_assert!(graph.layout(c.gene(graph, pos).node()).param_words > 0);
                // Structure is unchanged; only that gene's parameters may differ.
                let (a, b) = (before.gene(graph, pos), c.gene(graph, pos));
                prop_assert_eq!(
                    &a.words()[..2 + a.slot_count()],
                    &b.words()[..2 + b.slot_count()]
                );
                let changed = before
                    .words()
                    .iter()
                    .zip(c.words())
                    .enumerate()
                    .filter(|(_, (x, y))| x != y)
                    .all(|(k, _)| k >= pos as usize && k < pos as usize + a.words().len());
                prop_assert!(changed, "alter touched another gene");
            } else {
                prop_assert_eq!(&pop[i], &before);
            }
        }
        _ => {
            let j = rng.random_range(0..pop.len());
            let (a, b) = (pop[i].clone(), pop[j].clone());
            let edge_match = if rng.random_bool(0.8) {
                EdgeMatch::Strict
            } else {
                EdgeMatch::ChildType
            };
            let cfg = CrossoverConfig {
                max_retries: 3,
                edge_match,
            };
            if let Some((c1, c2)) = crossover(graph, &a, &b, &cfg, rng) {
                check_valid(graph, &c1, "crossover")?;
                check_valid(graph, &c2, "crossover")?;
                prop_assert_eq!(
                    multiset(graph, &[&a, &b]),
                    multiset(graph, &[&c1, &c2]),
                    "crossover conserves genes"
                );
                prop_assert_eq!(c1.len() + c2.len(), a.len() + b.len());
                pop[i] = c1;
                pop[j] = c2;
            }
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    /// Thousands of random operations on random graphs: every chromosome
    /// validates after every operation, and each operation does exactly what
    /// it says (checked against the naive tree model).
    #[test]
    fn operator_sequences_keep_chromosomes_valid(graph in crate::common::graph(), seed in any::<u64>()) {
        let mut rng = stream(seed, &[]);
        let init = InitLength::Between { lo: 1, hi: 40 };
        let mut pop: Vec<Chromosome> = (0..4)
            .map(|_| random_individual(&graph, &init, &mut rng).expect("graph reaches L_min"))
            .collect();
        for c in &pop {
            check_valid(&graph, c, "random_individual")?;
        }
        for step in 0..OPS_PER_CASE {
            random_op(&graph, &mut pop, &mut rng)?;
            if step.is_multiple_of(97) {
                // Occasionally replace an individual by a fresh one.
                let k = rng.random_range(0..pop.len());
                if let Ok(c) = random_individual(&graph, &init, &mut rng) {
                    check_valid(&graph, &c, "random_individual")?;
                    pop[k] = c;
                }
            }
        }
    }

    /// The default model and uncontrolled generation always give valid
    /// chromosomes within the limits. The default model has every parameter
    /// at its central value, and, when it did not have to grow to `L_min`
    /// or stop at `L_max`, every slot with `p >= ½` (and only those)
    /// expressed wherever the depth limit allows.
    #[test]
    fn default_and_uncontrolled_models_are_valid(graph in crate::common::graph(), seed in any::<u64>()) {
        let limits = *graph.limits();
        // Unbounded chains reach UNBOUNDED_CAP genes deep: too deep for the
        // recursive naive tree, so only `validate` checks those.
        let valid = |c: &Chromosome, what: &str| {
            if c.max_depth(&graph) < 200 {
                check_valid(&graph, c, what)
            } else {
                c.validate(&graph).map_err(|e| TestCaseError::fail(format!("{what}: {e}")))
            }
        };
        let d = default_model(&graph).expect("graph reaches L_min");
        valid(&d, "default_model")?;
        prop_assert!(limits.allows_len(d.len() as u32) || limits.max_len.is_none());
        prop_assert!(d.len() as u32 <= limits.max_len.map_or(UNBOUNDED_CAP, |m| m - 1));
        let capped = d.len() as u32 + 1 >= limits.max_len.unwrap_or(UNBOUNDED_CAP + 1);
        let grown = d.len() as u32 == limits.min_len;
        for g in d.genes(&graph) {
            let node = graph.node(g.node());
            for (k, p) in node.params.iter().enumerate() {
                let mut central = vec![0; p.dist.kind().words()];
                p.dist.central_into(&mut central);
                prop_assert!(p.dist.contains(&central));
                prop_assert_eq!(g.param(k), &central[..]);
            }
            if capped || grown {
                continue;
            }
            let room = limits.allows_depth(d.depth(g.pos()) + 1);
            for (j, slot) in node.slots.iter().enumerate() {
                prop_assert_eq!(g.child(j).is_some(), room && slot.p >= 0.5, "slot {} of {}", j, node.name);
            }
        }
        let mut rng = stream(seed, &[]);
        for _ in 0..8 {
            let c = uncontrolled(&graph, &mut rng).expect("graph reaches L_min");
            valid(&c, "uncontrolled")?;
            prop_assert!(c.len() as u32 >= limits.min_len);
            prop_assert!(c.len() as u32 <= limits.max_len.map_or(UNBOUNDED_CAP, |m| m - 1));
        }
    }

    /// Serialization round-trips and re-validates.
    #[test]
    fn serde_round_trips(graph in crate::common::graph(), seed in any::<u64>()) {
        let mut rng = stream(seed, &[]);
        let c = random_individual(&graph, &InitLength::Between { lo: 1, hi: 60 }, &mut rng).unwrap();
        let json = serde_json::to_string(&c.to_data(&graph)).unwrap();
        let data: ChromosomeData = serde_json::from_str(&json).unwrap();
        prop_assert_eq!(Chromosome::from_data(&graph, &data).unwrap(), c);
    }

    /// Corrupting any word of a chromosome is either still a valid derivation
    /// (e.g. another parameter value in the support) or rejected: never a panic.
    #[test]
    fn corrupted_data_is_rejected_not_panicking(graph in crate::common::graph(), seed in any::<u64>(), flips in proptest::collection::vec((any::<prop::sample::Index>(), any::<u32>()), 1..4)) {
        let mut rng = stream(seed, &[]);
        let c = random_individual(&graph, &InitLength::Between { lo: 1, hi: 30 }, &mut rng).unwrap();
        let mut data = c.to_data(&graph);
        for (idx, value) in flips {
            let k = idx.index(data.words.len());
            data.words[k] = value;
        }
        if let Ok(back) = Chromosome::from_data(&graph, &data) {
            back.validate(&graph).unwrap();
            prop_assert_eq!(Tree::of(&graph, &back).len(), back.len());
        }
        data.words.truncate(data.words.len() / 2);
        let _ = Chromosome::from_data(&graph, &data);
    }
}
