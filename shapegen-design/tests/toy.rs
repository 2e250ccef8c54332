//! The thesis's toy grammar (Fig. 4.2): two stacked masses, each with a
//! height, one of three meshes and one of three colours; and its design
//! tasks, played by a program.

use rand::SeedableRng;
use rand_pcg::Pcg64;
use shapegen_core::prelude::*;
use shapegen_design::preference::RELEVANCE;
use shapegen_design::*;

fn toy() -> Graph {
    GraphBuilder::new("toy")
        .start("Stack")
        .node("Stack", |n| {
            n.slot("bottom", "Mass", 1.0).slot("top", "Mass", 1.0)
        })
        .node("Mass", |n| {
            n.emits()
                .param_f32("h", Dist::uniform(1.0, 5.0))
                .param_choice("mesh", vec![1.0, 1.0, 1.0])
                .param_choice("colour", vec![1.0, 1.0, 1.0])
        })
        .build()
        .unwrap()
}

/// (mesh, colour) of the bottom and top masses.
fn masses(g: &Graph, m: &Chromosome) -> [(u32, u32); 2] {
    let root = m.root_gene(g);
    let at = |slot| {
        let gene = m.gene(g, root.child(slot).unwrap());
        (gene.param_choice(1), gene.param_choice(2))
    };
    [at(0), at(1)]
}

/// The thesis's colour task: both masses brown (colour 0) 100, both blue or
/// both turquoise 50, mixed colours 0.
fn same_colour(g: &Graph, m: &Chromosome) -> f64 {
    let [a, b] = masses(g, m);
    match (a.1, b.1) {
        (0, 0) => 100.0,
        (x, y) if x == y => 50.0,
        _ => 0.0,
    }
}

fn sample(g: &Graph, n: usize, seed: u64) -> Vec<Chromosome> {
    let mut rng = Pcg64::seed_from_u64(seed);
    (0..n).map(|_| uncontrolled(g, &mut rng).unwrap()).collect()
}

/// ARD finds the heights irrelevant to the colour task (thesis Fig. 4.5):
/// their weights end near zero, the colour paths' do not, and the predicted
/// score of a two-turquoise stack hardly moves with the heights.
#[test]
fn ard_drops_the_heights() {
    let g = toy();
    let models = sample(&g, 60, 1);
    let scores: Vec<f64> = models.iter().map(|m| same_colour(&g, m)).collect();
    let f = Factor::fit("colour", &g, &models, &scores, FactorOptions::default()).unwrap();
    let keys = f.space.keys();
    let w = f.gp.weights();
    let height: Vec<f64> = keys
        .iter()
        .zip(w)
        .filter(|(k, _)| matches!(k, FeatureKey::Param { .. }))
        .map(|(_, &w)| w)
        .collect();
    eprintln!("heights {height:?}\ntop {:?}", f.top_features(&g, 10));
    assert!(!height.is_empty());
    assert!(
        height.iter().all(|&w| w < RELEVANCE),
        "height weights {height:?}; top {:?}",
        f.top_features(&g, 8)
    );
    let colour_max = keys
        .iter()
        .zip(w)
        .filter(|(k, _)| k.describe(&g).contains("colour"))
        .map(|(_, &w)| w)
        .fold(0.0, f64::max);
    assert!(
        colour_max > 10.0 * RELEVANCE,
        "top {:?}",
        f.top_features(&g, 8)
    );
    // Two turquoise boxes at every height: predictions stay close together.
    let m = models
        .iter()
        .find(|m| masses(&g, m)[0].1 == 2 && masses(&g, m)[1].1 == 2)
        .expect("a turquoise pair among 60 samples");
    let mut data = m.to_data(&g);
    let mut preds = Vec::new();
    for h in [1.0f32, 2.0, 3.0, 4.0, 5.0] {
        // Both heights: the last parameter word before the choices of each mass.
        let root = m.root_gene(&g);
        for slot in 0..2 {
            let pos = root.child(slot).unwrap() as usize;
            data.words[pos + 2] = h.to_bits();
        }
        let c = Chromosome::from_data(&g, &data).unwrap();
        preds.push(f.predict(&g, &c).0);
    }
    let (lo, hi) = preds
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &p| (a.min(p), b.max(p)));
    assert!(hi - lo < 5.0, "predictions over heights {preds:?}");
    assert!(
        (lo - 50.0).abs() < 15.0,
        "two turquoise boxes should score about 50: {preds:?}"
    );
}
