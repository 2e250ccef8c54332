//! Property test: for every paper generator and random chromosomes (random
//! individuals changed by random operators), the geometry expressed by the
//! macro-generated code equals the interpreter's, instance for instance,
//! and stepping one gene at a time (`express_gene`, `express_from`) gives
//! the same instances.

use proptest::prelude::*;
use rand::RngExt;
use shapegen::express::Instances;
use shapegen::prelude::*;
use shapegen::rng::stream;
use shapegen::scenes::{GridCity, SpaceFillingCity, Spaceship, TreeV1, TreeV2};

/// A random chromosome: a random individual, then random grow/cut/alter and crossovers.
fn random_chromosome(graph: &Graph, seed: u64, ops: usize) -> Chromosome {
    let mut rng = stream(seed, &[]);
    let init = InitLength::Between { lo: 1, hi: 120 };
    let mut c = random_individual(graph, &init, &mut rng).unwrap();
    let other = random_individual(graph, &init, &mut rng).unwrap();
    for _ in 0..ops {
        match rng.random_range(0..4) {
            0 => drop(grow(graph, &mut c, &mut rng)),
            1 => drop(cut(graph, &mut c, &mut rng)),
            2 => drop(alter(graph, &mut c, &mut rng)),
            _ => {
                if let Some((a, _)) =
                    crossover(graph, &c, &other, &CrossoverConfig::default(), &mut rng)
                {
                    c = a;
                }
            }
        }
    }
    c
}

fn same<G: Generator>(
    generator: &G,
    interpreter: &impl Generator<State = G::State>,
    seed: u64,
    ops: usize,
) -> Result<(), TestCaseError> {
    let c = random_chromosome(generator.graph(), seed, ops);
    c.validate(generator.graph())
        .map_err(|e| TestCaseError::fail(e.to_string()))?;
    let (mut a, mut b) = (Instances::default(), Instances::default());
    generator.express(&c, &mut a);
    interpreter.express(&c, &mut b);
    prop_assert_eq!(&a, &b);
    prop_assert_eq!(&stepped(generator, &c), &a);
    prop_assert_eq!(&stepped(interpreter, &c), &a);
    let mut from_root = Instances::default();
    let mut pending = shapegen::express::Pending::new();
    generator.express_from(&c, 0, generator.axiom(), &mut from_root, &mut pending);
    prop_assert_eq!(&from_root, &a);
    Ok(())
}

/// The reference of `express_gene`: one step per gene, depth first, children
/// in the order their parent schedules them.
fn stepped<G: Generator>(generator: &G, c: &Chromosome) -> Instances {
    let mut out = Instances::default();
    let mut stack = vec![(0, generator.axiom())];
    let mut children = shapegen::express::Pending::new();
    while let Some((pos, state)) = stack.pop() {
        generator.express_gene(c, pos, state, &mut out, &mut children);
        let scheduled: Vec<_> = children.drain().collect();
        stack.extend(scheduled.into_iter().rev());
    }
    out
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn spaceship(seed in any::<u64>(), ops in 0usize..60) {
        same(&Spaceship, &Spaceship::interpreter(), seed, ops)?;
    }

    #[test]
    fn tree_v2(seed in any::<u64>(), ops in 0usize..60) {
        same(&TreeV2, &TreeV2::interpreter(), seed, ops)?;
    }

    #[test]
    fn tree_v1(seed in any::<u64>(), ops in 0usize..60) {
        same(&TreeV1, &TreeV1::interpreter(), seed, ops)?;
    }

    #[test]
    fn space_filling_city(seed in any::<u64>(), ops in 0usize..60) {
        same(&SpaceFillingCity, &SpaceFillingCity::interpreter(), seed, ops)?;
    }

    #[test]
    fn grid_city(seed in any::<u64>(), ops in 0usize..60) {
        same(&GridCity, &GridCity::interpreter(), seed, ops)?;
    }
}
