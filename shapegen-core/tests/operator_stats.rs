//! Statistical tests: grow's and cut's choice frequencies follow the paper's
//! formulas (chi-square with fixed seeds), and p = 0 slots are never grown.

use shapegen_core::prelude::*;
use shapegen_core::rng::{ShapeRng, stream};

/// Chi-square critical values at significance 0.001, by degrees of freedom.
const CHI2_999: [f64; 11] = [
    0.0, 10.83, 13.82, 16.27, 18.47, 20.52, 22.46, 24.32, 26.12, 27.88, 29.59,
];

fn chi_square(observed: &[u64], expected_weights: &[f64]) -> f64 {
    let n: u64 = observed.iter().sum();
    let total: f64 = expected_weights.iter().sum();
    observed
        .iter()
        .zip(expected_weights)
        .map(|(&o, &w)| {
            let e = n as f64 * w / total;
            (o as f64 - e).powi(2) / e
        })
        .sum()
}

/// A spaceship-like graph with probabilities 1, 1/3, 0.9 and 0.
fn graph() -> Graph {
    GraphBuilder::new("stats")
        .start("S")
        .node("S", |n| n.slot("body", "B", 1.0))
        .node("B", |n| {
            n.emits()
                .param_vec3("scale", [Dist::uniform(0.6, 1.5); 3])
                .slot("next", "B", 1.0 / 3.0)
                .slot("wing", "W", 1.0 / 3.0)
                .slot("top", "T", 1.0 / 3.0)
                .slot("never", "W", 0.0)
        })
        .node("T", |n| n.emits().slot("seg", "T", 1.0))
        .node("W", |n| {
            n.emits()
                .param_f32("move", Dist::uniform(-0.5, 0.5))
                .slot("seg", "W", 0.9)
        })
        .build()
        .unwrap()
}

/// S → B1 → {B2, T1 → T2}; B2 → W1 → W2.
fn fixture(graph: &Graph) -> (Chromosome, [u32; 7]) {
    let mut rng = stream(1, &[]);
    let mut c = Chromosome::root(graph, &mut rng);
    let b1 = grow_at(graph, &mut c, 0, 0, &mut rng).unwrap().child;
    let b2 = grow_at(graph, &mut c, b1, 0, &mut rng).unwrap().child;
    let t1 = grow_at(graph, &mut c, b1, 2, &mut rng).unwrap().child;
    let t2 = grow_at(graph, &mut c, t1, 0, &mut rng).unwrap().child;
    let w1 = grow_at(graph, &mut c, b2, 1, &mut rng).unwrap().child;
    let w2 = grow_at(graph, &mut c, w1, 0, &mut rng).unwrap().child;
    (c, [0, b1, b2, t1, t2, w1, w2])
}

/// Grows the fixture 60,000 times with `grow_once` and checks that the
/// chosen (gene, slot) frequencies are `p / Σ p` and that p = 0 slots never appear.
fn check_grow_frequencies(
    seed: u64,
    mut grow_once: impl FnMut(&Graph, &mut Chromosome, &mut ShapeRng) -> Grown,
) {
    let graph = graph();
    let (c, [_, b1, b2, _, t2, _, w2]) = fixture(&graph);
    // Open slots with p > 0: B1.wing (1/3), B2.next, B2.top (1/3 each),
    // T2.seg (1), W2.seg (0.9). The two "never" slots (p = 0) must not appear.
    let cases = [(b1, 1), (b2, 0), (b2, 2), (t2, 0), (w2, 0)];
    let weights = [1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0, 1.0, 0.9];
    let mut counts = [0u64; 5];
    let mut rng = stream(seed, &[]);
    for _ in 0..60_000 {
        let mut x = c.clone();
        let g = grow_once(&graph, &mut x, &mut rng);
        let k = cases.iter().position(|&s| s == (g.parent, g.slot));
        let k = k
            .unwrap_or_else(|| panic!("grew an unexpected slot {:?} (p = 0?)", (g.parent, g.slot)));
        counts[k] += 1;
    }
    assert_fits(&counts, &weights);
}

fn assert_fits(counts: &[u64], weights: &[f64]) {
    let chi2 = chi_square(counts, weights);
    assert!(
        chi2 < CHI2_999[counts.len() - 1],
        "chi2 = {chi2}, counts {counts:?}"
    );
}

#[test]
fn grow_frequencies_match_p_over_sum_p() {
    check_grow_frequencies(42, |graph, c, rng| {
        grow(graph, c, rng).expect("open slots exist")
    });
}

#[test]
fn grower_frequencies_match_p_over_sum_p() {
    let mut grower = Grower::new();
    check_grow_frequencies(43, |graph, c, rng| {
        grower.reset(graph, c);
        grower.grow(graph, c, rng).expect("open slots exist")
    });
}

#[test]
fn cut_frequencies_match_one_minus_p() {
    let graph = graph();
    let (c, [_, b1, b2, t1, t2, w1, w2]) = fixture(&graph);
    // Candidates and 1 − p: B1 (p = 1: never), B2 2/3, T1 2/3, T2 (p = 1: never), W1 2/3, W2 0.1.
    let victims = [b2, t1, w1, w2];
    let weights = [2.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0, 0.1];
    let mut counts = [0u64; 4];
    let mut rng = stream(44, &[]);
    for _ in 0..60_000 {
        let mut x = c.clone();
        let cut = cut(&graph, &mut x, &mut rng).expect("cuttable genes exist");
        // Identify the victim by the emptied (parent, slot).
        let victim = c.gene(&graph, cut.parent).child(cut.slot as usize).unwrap();
        assert!(victim != b1 && victim != t2, "a p = 1 child was cut");
        counts[victims.iter().position(|&v| v == victim).unwrap()] += 1;
    }
    assert_fits(&counts, &weights);
}

#[test]
fn nothing_to_grow_or_cut_is_a_no_op() {
    let graph = GraphBuilder::new("fixed")
        .start("S")
        .node("S", |n| n.slot("a", "A", 1.0).slot("z", "A", 0.0))
        .node("A", |n| n.param_f32("x", Dist::uniform(0.0, 1.0)))
        .build()
        .unwrap();
    let mut rng = stream(5, &[]);
    let mut c = Chromosome::root(&graph, &mut rng);
    assert!(grow(&graph, &mut c, &mut rng).is_some());
    let full = c.clone();
    // The only open slot has p = 0 and the only child has p = 1.
    for _ in 0..100 {
        assert!(grow(&graph, &mut c, &mut rng).is_none());
        assert!(cut(&graph, &mut c, &mut rng).is_none());
    }
    assert_eq!(c, full);
}

#[test]
fn tournament_and_split_draw_shapes() {
    // The mutation split's conditional frequencies: 13.5 / 13.5 / 3.
    let split = MutationSplit::new(13.5, 13.5, 3.0);
    let mut rng = stream(6, &[]);
    let mut counts = [0u64; 3];
    for _ in 0..30_000 {
        counts[split.draw(&mut rng) as usize] += 1;
    }
    assert_fits(&counts, &[13.5, 13.5, 3.0]);
}
