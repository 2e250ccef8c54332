//! The paper's generators: uncontrolled generation gives valid chromosomes
//! whose geometry has the expected structure, and the macro-expressed
//! geometry equals the interpreter's.

use shapegen::express::Instances;
use shapegen::glam::Vec3;
use shapegen::prelude::*;
use shapegen::rng::stream;
use shapegen::scenes::Spaceship;

/// Uncontrolled generation: grow following the graph's probabilities until nothing is open.
fn uncontrolled<G: Generator>(generator: &G, seed: u64, max: u32) -> Chromosome {
    let mut rng = stream(seed, &[]);
    random_individual(generator.graph(), &InitLength::Fixed { l0: max }, &mut rng).unwrap()
}

#[test]
fn spaceship_boxes_chain_along_z_and_wings_mirror() {
    let ship = Spaceship;
    let graph = ship.graph();
    assert_eq!(graph.node_count(), 6);
    for seed in 0..20 {
        let c = uncontrolled(&ship, seed, 60);
        c.validate(graph).unwrap();
        let mut model = Instances::default();
        ship.express(&c, &mut model);
        // Every gene but S emits one box; W and w emit two.
        let wings = c
            .genes(graph)
            .filter(|g| ["W", "w"].contains(&graph.node(g.node()).name.as_ref()))
            .count();
        assert_eq!(model.0.len(), c.len() - 1 + wings, "seed {seed}");
        // Nothing rotates in the spaceship except the wing mirror (π about z),
        // so every box is axis-aligned: translation = centre, diagonal = size.
        let boxes: Vec<(Vec3, Vec3)> = model
            .0
            .iter()
            .map(|i| {
                let m = i.transform.matrix3;
                (
                    Vec3::from(i.transform.translation),
                    Vec3::new(m.x_axis.x, m.y_axis.y, m.z_axis.z).abs(),
                )
            })
            .collect();
        // Body boxes (centred on the z axis) chain along +z from z = 0, each abutting the last.
        let mut bodies: Vec<&(Vec3, Vec3)> = boxes
            .iter()
            .filter(|(c, _)| c.x.abs() < 1e-5 && c.y.abs() < 1e-5)
            .collect();
        bodies.sort_by(|a, b| a.0.z.total_cmp(&b.0.z));
        let bodies_in_genes = c
            .genes(graph)
            .filter(|g| graph.node(g.node()).name == "B")
            .count();
        assert_eq!(bodies.len(), bodies_in_genes, "seed {seed}");
        let mut end = 0.0f32;
        for (centre, size) in bodies {
            assert!(
                (centre.z - 0.5 * size.z - end).abs() < 1e-4,
                "seed {seed}: gap in the body chain"
            );
            end = centre.z + 0.5 * size.z;
        }
        // Towers stand on top (y > 0); wing boxes come in mirror pairs (x, y, z) ~ (−x, −y, z).
        for (centre, _) in boxes.iter().filter(|(c, _)| c.x.abs() > 1e-5) {
            let mirrored = Vec3::new(-centre.x, -centre.y, centre.z);
            assert!(
                boxes.iter().any(|(o, _)| (*o - mirrored).length() < 1e-4),
                "seed {seed}: wing box at {centre} has no mirror image"
            );
        }
        assert!(
            boxes.iter().all(|(c, _)| c.x.abs() > 1e-5 || c.y >= -1e-5),
            "seed {seed}: a tower below the body"
        );
    }
}

#[test]
fn macro_and_interpreter_express_the_same_spaceships() {
    let ship = Spaceship;
    let interp = Spaceship::interpreter();
    for seed in 0..50 {
        let c = uncontrolled(&ship, seed, 80);
        let (mut a, mut b) = (Instances::default(), Instances::default());
        ship.express(&c, &mut a);
        interp.express(&c, &mut b);
        assert_eq!(a, b, "seed {seed}");
    }
}

mod trees_and_cities {
    use super::*;
    use shapegen::scenes::{GridCity, SpaceFillingCity, TreeV1, TreeV2, grid_lot};

    fn tree_structure<G: Generator>(tree: &G) {
        let graph = tree.graph();
        for seed in 0..30 {
            let c = uncontrolled(tree, seed, 250);
            c.validate(graph).unwrap();
            let mut model = Instances::default();
            tree.express(&c, &mut model);
            let frustums = model.0.iter().filter(|i| i.shape == 0).count();
            let leaves = model.0.iter().filter(|i| i.shape == 1).count();
            // Every gene but S is one frustum; each branch without child branches carries one leaf.
            assert_eq!(frustums, c.len() - 1, "seed {seed}");
            let final_branches = c
                .genes(graph)
                .filter(|g| ["b", "n", "m"].contains(&graph.node(g.node()).name.as_ref()))
                .filter(|g| g.children().count() == 0)
                .count();
            assert_eq!(leaves, final_branches, "seed {seed}");
            for g in c.genes(graph) {
                assert!(g.children().count() <= 3);
            }
            // Branches shrink: every frustum but the trunk is shorter than the trunk.
            let height = |i: &shapegen::express::Instance| i.transform.matrix3.y_axis.length();
            let trunk = height(&model.0[0]);
            assert!(
                (1.4..=1.8).contains(&trunk),
                "seed {seed}: trunk height {trunk}"
            );
            assert!(
                model.0[1..]
                    .iter()
                    .filter(|i| i.shape == 0)
                    .all(|i| height(i) < trunk)
            );
            // Leaves are emitted at unit size.
            for leaf in model.0.iter().filter(|i| i.shape == 1) {
                assert!((height(leaf) - 1.0).abs() < 1e-4);
            }
        }
    }

    #[test]
    fn trees_have_one_frustum_per_branch_and_leaves_on_final_branches() {
        tree_structure(&TreeV2);
        tree_structure(&TreeV1);
    }

    #[test]
    fn v1_trunks_stand_anywhere_in_the_square_v2_at_the_origin() {
        for seed in 0..20 {
            let mut model = Instances::default();
            TreeV2.express(&uncontrolled(&TreeV2, seed, 20), &mut model);
            let t = model.0[0].transform.translation;
            assert!(t.x.abs() < 1e-6 && t.z.abs() < 1e-6);
            let mut model = Instances::default();
            TreeV1.express(&uncontrolled(&TreeV1, seed, 20), &mut model);
            let t = model.0[0].transform.translation;
            assert!(t.x.abs() <= 2.5 && t.z.abs() <= 2.5);
        }
    }

    #[test]
    fn city_buildings_stand_on_the_lot_lattice() {
        let city = SpaceFillingCity;
        let graph = city.graph();
        let buildings = graph.node_id("Building").unwrap();
        for seed in 0..30 {
            let c = uncontrolled(&city, seed, 300);
            c.validate(graph).unwrap();
            let mut model = Instances::default();
            city.express(&c, &mut model);
            assert_eq!(
                model.0.len(),
                c.genes(graph).filter(|g| g.node() == buildings).count()
            );
            for b in &model.0 {
                let t = b.transform.translation;
                let h = b.transform.matrix3.y_axis.length();
                assert!(
                    (t.y - 0.5 * h).abs() < 1e-4,
                    "seed {seed}: a building does not stand on y = 0"
                );
                for v in [t.x, t.z] {
                    let lots = v / 2.2;
                    assert!(
                        (lots - lots.round()).abs() < 1e-3,
                        "seed {seed}: {v} is not on the lattice"
                    );
                }
            }
            // All four arms are expressed in every city (p = 1), so W's lots can appear.
            let arms = ["N", "E", "S", "W"].map(|a| graph.node_id(a).unwrap());
            for arm in arms {
                assert_eq!(c.genes(graph).filter(|g| g.node() == arm).count(), 1);
            }
        }
    }

    #[test]
    fn grid_city_buildings_sit_on_their_lots() {
        let city = GridCity;
        let graph = city.graph();
        for seed in 0..20 {
            let c = uncontrolled(&city, seed, 101);
            let mut model = Instances::default();
            city.express(&c, &mut model);
            let root = c.root_gene(graph);
            let lots: Vec<usize> = root.children().map(|(slot, _)| slot).collect();
            assert_eq!(model.0.len(), lots.len());
            for (b, lot) in model.0.iter().zip(lots) {
                let t = Vec3::from(b.transform.translation);
                let expected = grid_lot(lot);
                assert!((t.x - expected.x).abs() < 1e-4 && (t.z - expected.z).abs() < 1e-4);
            }
        }
    }

    #[test]
    fn macro_and_interpreter_agree_on_every_scene() {
        fn check<G: Generator>(g: &G, i: &impl Generator<State = G::State>) {
            for seed in 0..40 {
                let c = uncontrolled(g, seed, 150);
                let (mut a, mut b) = (Instances::default(), Instances::default());
                g.express(&c, &mut a);
                i.express(&c, &mut b);
                assert_eq!(a, b, "seed {seed}");
            }
        }
        check(&TreeV2, &TreeV2::interpreter());
        check(&TreeV1, &TreeV1::interpreter());
        check(&SpaceFillingCity, &SpaceFillingCity::interpreter());
        check(&GridCity, &GridCity::interpreter());
    }
}
