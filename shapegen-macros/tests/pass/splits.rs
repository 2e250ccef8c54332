// Split rules: `split!(state, axis, [slot: size, ..])` with absolute,
// relative and repeated parts, `_` gaps and array elements; the parts
// partition the scope, a repeated slot's subtree is expressed once per
// copy, and the interpreter splits as the specialized code does.
use shapegen::express::Instances;
use shapegen::prelude::*;

const N: usize = 2;

shapegen::generator! {
    pub struct Row;
    shapes: [cube];
    start: S;

    node S {
        params { width: f32 = uniform(9.0, 9.0) }
        slots { end: Box = 1.0, bay: Box = 1.0, mid[N]: Box = 1.0 }
        |mut scope| {
            scope.size.x = width;
            split!(scope, x, [end: 1.0, _: rel(1.0), bay: repeat(2.0), mid[1]: abs(0.5 * 2.0), end: 1.0,]);
        }
    }

    node Box emits {
        |scope| { emit!(cube, scope.instance()); }
    }
}

pub fn main() {
    let c = default_model(Row.graph()).unwrap();
    let (mut a, mut b) = (Instances::default(), Instances::default());
    Row.express(&c, &mut a);
    Row::interpreter().express(&c, &mut b);
    assert_eq!(a, b);
    // 9 = 1 + gap + bays + 1 + 1: the gap (nominal 1) and the bays (about
    // 2 each) share 6, so round(5 / 2) = 3 bays: six boxes.
    assert_eq!(a.0.len(), 6);
    let xs: Vec<(f32, f32)> = a
        .0
        .iter()
        .map(|i| (i.transform.translation.x, i.transform.matrix3.x_axis.x))
        .collect();
    // Boxes tile [-4.5, 4.5] apart from the gap.
    let covered: f32 = xs.iter().map(|(_, w)| w).sum();
    let first = xs[0].0 - 0.5 * xs[0].1;
    let last = xs[xs.len() - 1].0 + 0.5 * xs[xs.len() - 1].1;
    assert!((first + 4.5).abs() < 1e-5 && (last - 4.5).abs() < 1e-5, "{xs:?}");
    assert!(covered < 9.0, "the gap covers nothing: {xs:?}");
    assert_eq!(Row::spec().nodes[0].split, Some(shapegen::graph::Axis::X));
    assert_eq!(Row::spec().nodes[1].split, None);
}
