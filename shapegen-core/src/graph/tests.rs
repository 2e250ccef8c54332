use super::*;

static SHIP_PARAMS: [ParamSpec; 1] = [ParamSpec::new(
    "scale",
    ParamDist::uniform_vec3([0.6; 3], [1.5; 3]),
)];
static SHIP_SLOTS: [SlotSpec; 2] = [
    SlotSpec::new("next", "Body", 1.0 / 3.0),
    SlotSpec::new("wing", "Wing", 1.0 / 3.0),
];
static START_SLOTS: [SlotSpec; 1] = [SlotSpec::new("body", "Body", 1.0)];
static NODES: [NodeSpec; 3] = [
    NodeSpec::new("Start", &[], &START_SLOTS, false),
    NodeSpec::new("Body", &SHIP_PARAMS, &SHIP_SLOTS, true),
    NodeSpec::new("Wing", &[], &[], true),
];
static SPEC: GraphSpec = GraphSpec::new("static-ship", &NODES, "Start", Limits::NONE);

#[test]
fn a_static_spec_compiles() {
    let g = Graph::new(SPEC.clone()).unwrap();
    assert_eq!(g.node_count(), 3);
    assert_eq!(g.start(), 0);
    let body = g.node_id("Body").unwrap();
    assert_eq!(g.layout(body).gene_words, 2 + 2 + 3);
    assert_eq!(g.edge(body, 1).to, g.node_id("Wing").unwrap());
    assert_eq!(g.edges().len(), 3);
}

#[test]
fn builder_and_static_agree_on_fingerprint() {
    let built = GraphBuilder::new("static-ship")
        .start("Start")
        .node("Start", |n| n.slot("body", "Body", 1.0))
        .node("Body", |n| {
            n.emits()
                .param("scale", ParamDist::uniform_vec3([0.6; 3], [1.5; 3]))
                .slot("next", "Body", 1.0 / 3.0)
                .slot("wing", "Wing", 1.0 / 3.0)
        })
        .node("Wing", |n| n.emits())
        .build()
        .unwrap();
    assert_eq!(built.spec(), &SPEC);
    assert_eq!(
        built.fingerprint(),
        Graph::new(SPEC.clone()).unwrap().fingerprint()
    );
}

#[test]
fn every_problem_is_reported_at_once() {
    let err = GraphBuilder::new("bad")
        .start("Nope")
        .limits(Limits {
            max_depth: None,
            min_len: 5,
            max_len: Some(5),
        })
        .node("A", |n| {
            n.param_f32("x", Dist::uniform(1.0, 0.0))
                .param_f32("x", Dist::constant(1.0))
                .slot("s", "Missing", 0.5)
                .slot("s", "A", 1.5)
        })
        .node("A", |n| n)
        .build()
        .unwrap_err();
    let e = err.errors();
    let has = |f: &dyn Fn(&GraphError) -> bool| e.iter().any(f);
    assert!(has(
        &|e| matches!(e, GraphError::DuplicateNode { node } if node == "A")
    ));
    assert!(has(
        &|e| matches!(e, GraphError::DuplicateParam { param, .. } if param == "x")
    ));
    assert!(has(
        &|e| matches!(e, GraphError::EmptySupport { param, .. } if param == "x")
    ));
    assert!(has(
        &|e| matches!(e, GraphError::DuplicateSlot { slot, .. } if slot == "s")
    ));
    assert!(has(
        &|e| matches!(e, GraphError::UnknownTarget { target, .. } if target == "Missing")
    ));
    assert!(has(
        &|e| matches!(e, GraphError::BadProbability { p, .. } if *p == 1.5)
    ));
    assert!(has(
        &|e| matches!(e, GraphError::UnknownStart { start } if start == "Nope")
    ));
    assert!(has(&|e| matches!(e, GraphError::BadLimits { .. })));
    assert_eq!(e.len(), 8, "{err}");
    let text = err.to_string();
    assert!(
        text.contains("8 problems") && text.contains("Missing"),
        "{text}"
    );
}

#[test]
fn unreachable_and_missing_start_are_reported() {
    let err = GraphBuilder::new("g").node("A", |n| n).build().unwrap_err();
    assert_eq!(err.errors(), &[GraphError::NoStart]);
    let err = GraphBuilder::new("g")
        .start("A")
        .node("A", |n| n.slot("b", "B", 0.5))
        .node("B", |n| n)
        .node("C", |n| n.slot("a", "A", 0.5))
        .build()
        .unwrap_err();
    assert_eq!(
        err.errors(),
        &[GraphError::Unreachable { node: "C".into() }]
    );
    let err = GraphBuilder::new("g").start("A").build().unwrap_err();
    assert!(err.errors().contains(&GraphError::NoNodes));
}

#[test]
fn spec_serde_round_trips() {
    let spec = SPEC.clone();
    let json = serde_json::to_string(&spec).unwrap();
    let back: GraphSpec = serde_json::from_str(&json).unwrap();
    assert_eq!(back, spec);
}

#[test]
fn builder_tags_are_checked_and_leave_the_fingerprint_alone() {
    use super::{GraphBuilder, GraphError};
    let graph = |tags: &[&str]| {
        let tags: Vec<String> = tags.iter().map(ToString::to_string).collect();
        GraphBuilder::new("g")
            .start("S")
            .node("S", move |mut n| {
                for t in tags {
                    n = n.tag(t);
                }
                n
            })
            .build()
    };
    let tagged = graph(&["trunk", "mass_lvl0"]).unwrap();
    let id = tagged.node_id("S").unwrap();
    assert_eq!(tagged.node(id).tags.as_ref(), ["trunk", "mass_lvl0"]);
    assert_eq!(tagged.fingerprint(), graph(&[]).unwrap().fingerprint());
    let errors = graph(&["", "a b", "9lives", "ok", "ok"]).unwrap_err();
    let kinds: Vec<_> = errors
        .errors()
        .iter()
        .map(|e| match e {
            GraphError::BadTag { tag, .. } => format!("bad {tag}"),
            GraphError::DuplicateTag { tag, .. } => format!("twice {tag}"),
            other => format!("{other}"),
        })
        .collect();
    assert_eq!(kinds, ["bad ", "bad a b", "bad 9lives", "twice ok"]);
}
