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
