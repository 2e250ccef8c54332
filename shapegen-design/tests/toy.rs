//! Learning preferences on small grammars: the thesis's toy grammar
//! (Fig. 4.2) and its colour task, and a chain whose task needs longer paths.

use rand::SeedableRng;
use rand_pcg::Pcg64;
use shapegen_core::prelude::*;
use shapegen_design::preference::RELEVANCE;
use shapegen_design::toy::{graph as toy, masses, same_colour};
use shapegen_design::*;

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
    assert!(!height.is_empty());
    // The largest weights are the colours'; the heights' are below the
    // relevance threshold (a fraction of the largest), so structure
    // learning would not split for them.
    let max = w.iter().copied().fold(0.0, f64::max);
    let colour_max = keys
        .iter()
        .zip(w)
        .filter(|(k, _)| k.describe(&g).contains("colour"))
        .map(|(_, &w)| w)
        .fold(0.0, f64::max);
    assert_eq!(colour_max, max, "top {:?}", f.top_features(&g, 8));
    assert!(
        height.iter().all(|&w| w < RELEVANCE * max),
        "height weights {height:?}; top {:?}",
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

/// `k` grows when paths of effective length 1 cannot tell apart models
/// with very different scores: in a chain of beads, "the second bead is red"
/// needs the path `Root.first>Bead.next>Bead(colour=red)`, of effective
/// length 2 (the first slot is certain).
#[test]
fn path_length_grows_until_the_features_separate_the_scores() {
    let g = GraphBuilder::new("beads")
        .start("Root")
        .limits(Limits {
            max_depth: Some(3),
            min_len: 1,
            max_len: None,
        })
        .node("Root", |n| n.slot("first", "Bead", 1.0))
        .node("Bead", |n| {
            n.param_choice("colour", vec![1.0, 1.0])
                .slot("next", "Bead", 0.8)
        })
        .build()
        .unwrap();
    let models = sample(&g, 80, 4);
    let bead = g.node_id("Bead").unwrap();
    let second_red = |m: &Chromosome| {
        let first = m.gene(&g, m.root_gene(&g).child(0).unwrap());
        first.child(0).is_some_and(|p| {
            let b = m.gene(&g, p);
            b.node() == bead && b.param_choice(0) == 0
        })
    };
    let scores: Vec<f64> = models
        .iter()
        .map(|m| if second_red(m) { 100.0 } else { 0.0 })
        .collect();
    let f = Factor::fit("second", &g, &models, &scores, FactorOptions::default()).unwrap();
    assert!(
        f.space.options().path_length >= 2,
        "k stayed at {}",
        f.space.options().path_length
    );
    // With k fixed at 1 the features cannot separate them; with the grown k the fit can.
    let fixed = FactorOptions {
        max_path_length: 1,
        ..FactorOptions::default()
    };
    let f1 = Factor::fit("second", &g, &models, &scores, fixed).unwrap();
    let err = |f: &Factor| -> f64 {
        models
            .iter()
            .zip(&scores)
            .map(|(m, s)| (f.predict(&g, m).0 - s).abs())
            .sum::<f64>()
            / models.len() as f64
    };
    assert!(
        err(&f) < 0.5 * err(&f1),
        "grown k: {:.1}, k = 1: {:.1}",
        err(&f),
        err(&f1)
    );
}
