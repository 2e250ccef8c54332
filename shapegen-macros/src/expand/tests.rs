//! The generated tokens of small declarations.

use super::generator;

fn expand(src: &str) -> String {
    generator(src.parse().unwrap()).to_string()
}

const TOWER: &str = r#"
    /// Docs.
    pub struct Tower;
    shapes: [cube];
    start: Floor;
    node Floor emits {
        params { h: f32 = uniform(1, 2), v: vec3 = uniform([0.5; 3], 1.5) }
        slots { up: Floor = 1 / 4, lots[3]: Floor = 0.5 }
        |s| { emit!(cube, s.instance()); child!(up, s); child!(lots[1], s); }
    }
"#;

#[test]
fn expands_a_graph_and_specialized_code() {
    let out = expand(TOWER);
    assert!(!out.contains("compile_error"), "{out}");
    for needle in [
        "static SPEC",
        "fn __sg_node_Floor",
        "impl :: shapegen :: express :: Generator for Tower",
        // Probabilities made of literals are exact reals: 1 / 4 = 0.25.
        "SlotSpec :: new (\"up\" , \"Floor\" , 0.25f64)",
        // Slot arrays become numbered slots.
        "format ! (\"{}[{}]\" , \"lots\" , i)",
        // Vector ranges are split per component; a scalar is broadcast.
        "Dist :: uniform ((0.5) as f32 , (1.5) as f32)",
        // Core's limits are asserted by the compiler.
        "graph :: MAX_SLOTS",
        "graph :: MAX_NODES",
    ] {
        assert!(out.contains(needle), "missing `{needle}` in {out}");
    }
    // The parameter block starts after 4 slots: h at +4, v at +5..+7.
    assert!(out.contains("HEADER_WORDS + 4usize"), "{out}");
    assert!(out.contains("HEADER_WORDS + 7usize"), "{out}");
}

#[test]
fn a_family_shares_one_body_with_per_member_values() {
    let out = expand(
        r#"
        struct Arms;
        start: S;
        node S { slots { a: N = 1.0, b: E = 1.0 } |s| { child!(a, s); child!(b, s); } }
        node N, E {
            consts { turn: i32 = each[1, 0] }
            params { len: f32 = each[uniform(0, 1), uniform(1, 2)], k: choice([1, 2]) }
            slots { next: N = each[0.5, 0.25] }
            |s| { child!(next, s); }
        }
    "#,
    );
    assert!(!out.contains("compile_error"), "{out}");
    // One body function for the family, one dispatch arm per member.
    assert_eq!(out.matches("fn __sg_node_N").count(), 1, "{out}");
    assert!(!out.contains("fn __sg_node_E"), "{out}");
    assert!(out.contains("1u16 => Self :: __sg_node_N (1 ,"), "{out}");
    assert!(out.contains("2u16 => Self :: __sg_node_N (0 ,"), "{out}");
    assert!(
        out.contains("Dist :: uniform ((1) as f32 , (2) as f32)"),
        "{out}"
    );
    assert!(out.contains("\"next\" , \"N\" , 0.25f64"), "{out}");
    // The short choice form.
    assert!(out.contains("ParamDist :: Choice"), "{out}");
}

#[test]
fn constant_expression_lengths_are_left_to_the_compiler() {
    let out = expand(
        r#"
        struct Grid;
        start: S;
        node S { slots { lots[N * N]: B = 0.5, last: B = 1.0 } params { x: f32 = uniform(0, 1) }
            |s| { child!(lots[2], s); child!(last, s); } }
        node B { |s| {} }
    "#,
    );
    assert!(!out.contains("compile_error"), "{out}");
    // `last` follows the array, `x` both; a constant index is asserted at compile time.
    assert!(
        out.contains("index : 0usize + :: core :: convert :: identity :: < usize > (N * N)"),
        "{out}"
    );
    assert!(
        out.contains("HEADER_WORDS + 1usize + :: core :: convert :: identity :: < usize > (N * N)"),
        "{out}"
    );
    assert!(
        out.contains("const _ : () = :: core :: assert ! (2usize < :: core :: convert :: identity :: < usize > (N * N)"),
        "{out}"
    );
}

#[test]
fn every_error_is_reported_and_the_generator_impl_still_emitted() {
    let out = expand(
        r#"
        struct G;
        shapes: [cube];
        start: Nope;
        node A { slots { x: Missing = 2.0 } |s| { child!(y, s); } }
    "#,
    );
    for needle in [
        "unknown start node `Nope`",
        "unknown node `Missing`",
        "probability 2 is outside",
        "has no slot `y`",
    ] {
        assert!(out.contains(needle), "missing `{needle}` in {out}");
    }
    assert_eq!(out.matches("compile_error").count(), 4, "{out}");
    assert!(
        out.contains("impl :: shapegen :: express :: Generator for G"),
        "{out}"
    );
    // The body is kept, its unresolvable call replaced by `unreachable!()`.
    assert!(out.contains("fn __sg_node_A"), "{out}");
}

#[test]
fn syntax_errors_stop_at_the_first_one_and_keep_the_type() {
    let out = expand("struct G; shapes [cube];");
    assert!(
        out.contains("compile_error") && out.contains("expected `:`"),
        "{out}"
    );
    assert!(
        out.contains("impl :: shapegen :: express :: Generator for G"),
        "{out}"
    );
}
