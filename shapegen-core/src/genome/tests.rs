use super::*;
use crate::graph::{Dist, Graph, GraphBuilder, Limits};
use crate::ops::grow_at;
use crate::rng::stream;

fn graph(limits: Limits) -> Graph {
    GraphBuilder::new("g")
        .start("S")
        .limits(limits)
        .node("S", |n| n.slot("a", "A", 1.0).slot("b", "B", 0.5))
        .node("A", |n| {
            n.param_f32("x", Dist::uniform(0.0, 1.0))
                .slot("next", "A", 0.5)
        })
        .node("B", |n| n.param_vec3("v", [Dist::uniform(-1.0, 1.0); 3]))
        .build()
        .unwrap()
}

/// S → A1 → A2, S → B.
fn sample(g: &Graph) -> (Chromosome, u32, u32, u32) {
    let mut rng = stream(3, &[]);
    let mut c = Chromosome::root(g, &mut rng);
    let a1 = grow_at(g, &mut c, 0, 0, &mut rng).unwrap().child;
    let a2 = grow_at(g, &mut c, a1, 0, &mut rng).unwrap().child;
    let b = grow_at(g, &mut c, 0, 1, &mut rng).unwrap().child;
    (c, a1, a2, b)
}

fn corrupt(c: &Chromosome, at: usize, value: u32) -> Chromosome {
    let mut bad = c.clone();
    bad.words[at] = value;
    bad
}

#[test]
fn views_read_the_tree() {
    let g = graph(Limits::NONE);
    let (c, a1, a2, b) = sample(&g);
    c.validate(&g).unwrap();
    assert_eq!(c.len(), 4);
    // Gene sizes: S = 2 + 2 slots, A = 2 + 1 slot + 1 word, B = 2 + 3 words.
    assert_eq!(c.positions(), &[0, 4, 8, 12]);
    let root = c.root_gene(&g);
    assert_eq!(root.children().collect::<Vec<_>>(), vec![(0, a1), (1, b)]);
    assert_eq!(c.gene(&g, a2).parent(), Some(a1));
    assert_eq!(c.depth(a2), 2);
    assert_eq!(c.max_depth(&g), 2);
    let pre: Vec<u32> = c.subtree(&g, 0).map(|g| g.pos()).collect();
    assert_eq!(pre, vec![0, a1, a2, b]);
    assert_eq!(c.subtree_len(&g, a1), 2);
    let x = c.gene(&g, a1).param_f32(0);
    assert!((0.0..=1.0).contains(&x));
    let v = c.gene(&g, b).param_vec3(0);
    assert!(v.iter().all(|c| (-1.0..=1.0).contains(c)));
}

#[test]
fn every_broken_invariant_is_reported() {
    let g = graph(Limits::NONE);
    let (c, a1, a2, b) = sample(&g);
    let (a1, a2, b) = (a1 as usize, a2 as usize, b as usize);
    let check = |bad: Chromosome| bad.validate(&g).unwrap_err();
    assert!(matches!(
        check(corrupt(&c, a1, 77)),
        GenomeError::UnknownNode { node: 77, .. }
    ));
    assert!(matches!(
        check(corrupt(&c, a1, c.words[a1] | 1 << 24)),
        GenomeError::Flags { .. }
    ));
    // The root must be S.
    assert!(matches!(
        check(corrupt(&c, 0, 1)),
        GenomeError::BadRoot { .. } | GenomeError::Truncated { .. }
    ));
    // A parent link pointing forward, or into the middle of a gene (the
    // parent, checked first, already sees that the child's link disagrees).
    for link in [3, (-2i32) as u32] {
        let err = check(corrupt(&c, a2 + 1, link));
        assert!(
            matches!(
                err,
                GenomeError::BadParent { .. } | GenomeError::BrokenLink { .. }
            ),
            "{err}"
        );
    }
    // The parent's slot no longer points back.
    assert!(matches!(
        check(corrupt(&c, a1 + 2, 0)),
        GenomeError::BrokenLink { .. }
    ));
    // A child of the wrong node: B's header claims node A (same slot count as B? no: sizes differ).
    let mut wrong = c.clone();
    wrong.words[b] = word::header(g.node_id("B").unwrap(), 0); // B hanging from S's slot 0 (which takes A)
    assert!(matches!(
        check(wrong),
        GenomeError::BrokenLink { .. } | GenomeError::WrongChild { .. }
    ));
    // A parameter outside its support, and a NaN.
    assert!(matches!(
        check(corrupt(&c, a1 + 3, 2.0f32.to_bits())),
        GenomeError::ParamOutOfSupport { .. }
    ));
    assert!(matches!(
        check(corrupt(&c, b + 2, f32::NAN.to_bits())),
        GenomeError::ParamOutOfSupport { .. }
    ));
    // A truncated buffer.
    let mut short = c.clone();
    short.words.pop();
    assert!(matches!(check(short), GenomeError::Truncated { .. }));
    let empty = Chromosome::empty();
    assert_eq!(empty.validate(&g), Err(GenomeError::Empty));
}

#[test]
fn limits_are_checked() {
    let (c, ..) = sample(&graph(Limits::NONE));
    let deep = graph(Limits {
        max_depth: Some(1),
        ..Limits::NONE
    });
    assert!(matches!(
        c.validate(&deep),
        Err(GenomeError::Depth {
            depth: 2,
            max: 1,
            ..
        })
    ));
    let short = graph(Limits {
        max_depth: None,
        min_len: 1,
        max_len: Some(4),
    });
    assert!(matches!(
        c.validate(&short),
        Err(GenomeError::Length { len: 4, .. })
    ));
    let long = graph(Limits {
        max_depth: None,
        min_len: 5,
        max_len: None,
    });
    assert!(matches!(
        c.validate(&long),
        Err(GenomeError::Length { len: 4, .. })
    ));
}

#[test]
fn data_from_another_graph_or_version_is_refused() {
    let g = graph(Limits::NONE);
    let (c, ..) = sample(&g);
    let other = GraphBuilder::new("other")
        .start("S")
        .node("S", |n| n)
        .build()
        .unwrap();
    let err = Chromosome::from_data(&other, &c.to_data(&g)).unwrap_err();
    assert!(matches!(err, GenomeError::ForeignGraph { .. }));
    assert!(err.to_string().contains("`g`"), "{err}");
    let mut data = c.to_data(&g);
    data.version = 99;
    assert_eq!(
        Chromosome::from_data(&g, &data),
        Err(GenomeError::Version(99))
    );
    let mut data = c.to_data(&g);
    data.genes = 3;
    assert!(matches!(
        Chromosome::from_data(&g, &data),
        Err(GenomeError::Count { .. })
    ));
    // JSON round trip.
    let json = serde_json::to_string(&c.to_data(&g)).unwrap();
    let back: ChromosomeData = serde_json::from_str(&json).unwrap();
    assert_eq!(Chromosome::from_data(&g, &back).unwrap(), c);
}

#[test]
fn structural_hash_ignores_layout_but_not_content() {
    let g = graph(Limits::NONE);
    let mut rng = stream(9, &[]);
    // Same tree grown in two orders: different buffers, same structure.
    let mut x = Chromosome::root(&g, &mut rng);
    let mut y = x.clone();
    let a = grow_at(&g, &mut x, 0, 0, &mut rng).unwrap().child;
    let b = grow_at(&g, &mut x, 0, 1, &mut rng).unwrap().child;
    let b2 = grow_at(&g, &mut y, 0, 1, &mut rng).unwrap().child;
    let a2 = grow_at(&g, &mut y, 0, 0, &mut rng).unwrap().child;
    // Copy parameters so the content matches.
    let (ap, bp) = (
        x.gene(&g, a).params().to_vec(),
        x.gene(&g, b).params().to_vec(),
    );
    y.words[a2 as usize + 3..a2 as usize + 4].copy_from_slice(&ap);
    y.words[b2 as usize + 2..b2 as usize + 5].copy_from_slice(&bp);
    y.validate(&g).unwrap();
    assert_ne!(x, y);
    assert_eq!(x.structural_hash(&g), y.structural_hash(&g));
    let z = corrupt(&y, a2 as usize + 3, 0.25f32.to_bits());
    assert_ne!(x.structural_hash(&g), z.structural_hash(&g));
}
