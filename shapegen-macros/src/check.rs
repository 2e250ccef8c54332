//! Checking a declaration's meaning before any code is generated: one
//! `check_*` rule per concern, each saying why it exists. Every problem is
//! recorded in the [`Ctxt`], so all are reported at once.
//!
//! Limits that core enforces on graphs (slots per node, nodes per graph) are
//! not repeated here: the generated code asserts them at compile time
//! against core's own constants (see `expand::spec`).

use std::collections::{HashMap, HashSet};

use syn::Expr;
use syn::spanned::Spanned;

use crate::ast::{DistCall, Generator, Kind, Node, Param, PerMember};
use crate::body::{self, Call, CallKind};
use crate::ctxt::Ctxt;
use crate::eval::{components, integer, number};
use crate::hint::did_you_mean;
use crate::paths;

/// Runs every rule on `g`.
pub fn generator(cx: &Ctxt, g: &Generator) {
    check_unique_names(cx, g);
    check_start(cx, g);
    check_reachable(cx, g);
    check_limits(cx, g);
    for n in &g.nodes {
        check_each_counts(cx, n);
        check_node_names(cx, n);
        check_tags(cx, n);
        for p in &n.params {
            for d in p.dist.all() {
                check_distribution(cx, p, d);
            }
        }
        check_slots(cx, g, n);
        let calls = body::calls(cx, &n.body);
        check_calls(cx, g, n, &calls);
        check_emits(cx, n, &calls);
        check_split(cx, &calls);
        paths::check(cx, &n.body);
    }
}

/// Nodes and shapes are looked up by name: a name declared twice would be ambiguous.
fn check_unique_names(cx: &Ctxt, g: &Generator) {
    let mut nodes = HashSet::new();
    for (n, m) in g.members() {
        let name = &n.members[m];
        if !nodes.insert(name.to_string()) {
            cx.error(name.span(), format!("duplicate node `{name}`"));
        }
    }
    let mut shapes = HashSet::new();
    for s in &g.shapes {
        if !shapes.insert(s.to_string()) {
            cx.error(s.span(), format!("duplicate shape `{s}`"));
        }
    }
    if g.nodes.is_empty() {
        cx.error(g.name.span(), "a generator needs at least one `node`");
    }
}

/// Every derivation tree starts at the start node, so it must exist.
fn check_start(cx: &Ctxt, g: &Generator) {
    match &g.start {
        None => cx.error(g.name.span(), "missing start node: add `start: NodeName;`"),
        Some(s) if !node_names(g).any(|n| n == s) => cx.error(
            s.span(),
            format!(
                "unknown start node `{s}`{}",
                did_you_mean(&s.to_string(), node_strings(g))
            ),
        ),
        Some(_) => {}
    }
}

/// A node no derivation can reach is dead code, and usually a misspelled target.
fn check_reachable(cx: &Ctxt, g: &Generator) {
    let Some(start) = &g.start else { return };
    let members: Vec<(&Node, usize)> = g.members().collect();
    let mut index = HashMap::new();
    for (i, (n, m)) in members.iter().enumerate() {
        index.entry(n.members[*m].to_string()).or_insert(i);
    }
    let Some(&s) = index.get(&start.to_string()) else {
        return;
    };
    let mut reached = vec![false; members.len()];
    let mut stack = vec![s];
    while let Some(i) = stack.pop() {
        if std::mem::replace(&mut reached[i], true) {
            continue;
        }
        stack.extend(
            members[i]
                .0
                .slots
                .iter()
                .filter_map(|sl| index.get(&sl.target.to_string()).copied()),
        );
    }
    for (i, (n, m)) in members.iter().enumerate() {
        let name = &n.members[*m];
        if !reached[i] && index[&name.to_string()] == i {
            cx.error(
                name.span(),
                format!("node `{name}` cannot be reached from the start node `{start}`"),
            );
        }
    }
}

/// Lengths satisfy `min_len <= L < max_len`, and every tree has its root gene.
fn check_limits(cx: &Ctxt, g: &Generator) {
    let l = &g.limits;
    let value = |e: &Option<Expr>| e.as_ref().and_then(number);
    if let Some(e) = &l.min_len
        && number(e) == Some(0.0)
    {
        cx.error(e.span(), "min_len must be at least 1 (the root gene)");
    }
    if let (Some(max), Some(e)) = (value(&l.max_len), &l.max_len) {
        let min = value(&l.min_len).unwrap_or(1.0);
        if max <= min {
            cx.error(
                e.span(),
                format!(
                    "max_len ({max}) must exceed min_len ({min}): lengths satisfy min_len <= L < max_len"
                ),
            );
        }
    }
}

/// `each[..]` gives one value per member: a different count is a value too many
/// or missing, and on a single node it is meaningless.
fn check_each_counts(cx: &Ctxt, n: &Node) {
    let members = n.members.len();
    let check = |span: proc_macro2::Span, count: usize| {
        if !n.is_family() {
            cx.error(
                span,
                format!(
                    "`each[..]` gives one value per member of a node family, but `{}` is a \
                     single node: write the value alone",
                    n.name()
                ),
            );
        } else if count != members {
            let names: Vec<String> = n.members.iter().map(ToString::to_string).collect();
            cx.error(
                span,
                format!(
                    "expected {members} values, one per member ({}), found {count}",
                    names.join(", ")
                ),
            );
        }
    };
    for p in &n.params {
        if let PerMember::Each { span, values } = &p.dist {
            check(*span, values.len());
        }
    }
    for s in &n.slots {
        if let PerMember::Each { span, values } = &s.p {
            check(*span, values.len());
        }
    }
    for c in &n.consts {
        if let PerMember::Each { span, values } = &c.value {
            check(*span, values.len());
        }
    }
    for t in &n.tags {
        if let PerMember::Each { span, values } = t {
            check(*span, values.len());
        }
    }
}

/// Tags name semantic matches between generators (the thesis's §5.4.1): they
/// must read the same in a transformation file (ASCII words, as
/// `graph::check_tag` requires) and a tag given twice to one node is a slip.
fn check_tags(cx: &Ctxt, n: &Node) {
    for t in &n.tags {
        for tag in t.all() {
            let word = tag.to_string();
            let word = word.strip_prefix("r#").unwrap_or(&word);
            let bad = if word.len() > 64 {
                Some("a tag is at most 64 characters long")
            } else if !word.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_') {
                Some("a tag holds only ASCII letters, digits and `_`")
            } else {
                None
            };
            if let Some(reason) = bad {
                cx.error(tag.span(), format!("tag `{word}`: {reason}"));
            }
        }
    }
    for m in 0..n.members.len() {
        let mut seen = HashSet::new();
        for t in &n.tags {
            let tag = t.get(m);
            if !seen.insert(tag.to_string()) {
                let who = if n.is_family() {
                    format!("node `{}`", n.members[m])
                } else {
                    format!("node `{}`", n.name())
                };
                cx.error(tag.span(), format!("{who} has tag `{tag}` twice"));
            }
        }
    }
}

/// Parameters and constants become locals of the body, slots are named in
/// `child!`: each name must mean one thing.
fn check_node_names(cx: &Ctxt, n: &Node) {
    let mut locals = HashSet::new();
    let names = n
        .params
        .iter()
        .map(|p| (&p.name, "parameter"))
        .chain(n.consts.iter().map(|c| (&c.name, "constant")));
    for (name, what) in names {
        if !locals.insert(name.to_string()) {
            cx.error(
                name.span(),
                format!("duplicate {what} `{name}` in node `{}`", n.name()),
            );
        }
    }
    let mut slots = HashSet::new();
    for s in &n.slots {
        if !slots.insert(s.name.to_string()) {
            cx.error(
                s.name.span(),
                format!("duplicate slot `{}` in node `{}`", s.name, n.name()),
            );
        }
    }
}

/// Slots must lead somewhere, with a probability, and arrays need a length.
fn check_slots(cx: &Ctxt, g: &Generator, n: &Node) {
    let nodes = node_strings(g);
    for s in &n.slots {
        if !nodes.iter().any(|x| s.target == x) {
            cx.error(
                s.target.span(),
                format!(
                    "unknown node `{}`{}",
                    s.target,
                    did_you_mean(&s.target.to_string(), &nodes)
                ),
            );
        }
        for p in s.p.all() {
            if let Some(v) = number(p)
                && !(0.0..=1.0).contains(&v)
            {
                cx.syn_error(syn::Error::new_spanned(
                    p,
                    format!("probability {v} is outside [0, 1]"),
                ));
            }
        }
        let Some(len) = &s.count else { continue };
        match (number(len), integer(len)) {
            (_, Some(0)) => cx.error(len.span(), "a slot array needs at least one element"),
            (Some(_), None) => cx.error(
                len.span(),
                "expected the number of elements, e.g. `lots[100]` or `lots[GRID * GRID]`",
            ),
            // A literal, or a constant expression the compiler evaluates.
            _ => {}
        }
    }
}

/// `emit!`/`child!`/`expressed!` must name a declared shape or slot, and
/// arrays are used with an index in range, plain slots without.
fn check_calls(cx: &Ctxt, g: &Generator, n: &Node, calls: &[Call]) {
    let shapes: Vec<String> = g.shapes.iter().map(ToString::to_string).collect();
    let slots: Vec<String> = n.slots.iter().map(|s| s.name.to_string()).collect();
    for c in calls {
        let id = &c.id;
        if c.kind == CallKind::Split {
            continue;
        }
        if c.kind == CallKind::Emit {
            if !g.shapes.iter().any(|s| s == id) {
                cx.error(
                    id.span(),
                    format!(
                        "unknown shape `{id}`{}: declare it in `shapes: [...]`",
                        did_you_mean(&id.to_string(), &shapes)
                    ),
                );
            }
            if let Some(i) = &c.index {
                cx.error(i.span(), "shapes are not indexed");
            }
            continue;
        }
        let Some(slot) = n.slots.iter().find(|s| s.name == *id) else {
            cx.error(
                id.span(),
                format!(
                    "node `{}` has no slot `{id}`{}",
                    n.name(),
                    did_you_mean(&id.to_string(), &slots)
                ),
            );
            continue;
        };
        match (&slot.count, &c.index) {
            (None, Some(i)) => cx.error(i.span(), format!("slot `{id}` is not an array")),
            (Some(_), None) => cx.error(
                id.span(),
                format!("slot `{id}` is an array: write `{id}[index]`"),
            ),
            (Some(_), Some(i)) => {
                if let (Some(k), Some(len)) = (c.literal_index(), slot.literal_len())
                    && k >= len
                {
                    cx.error(
                        i.span(),
                        format!(
                            "slot index {k} is out of range: `{id}` has {len} elements (0..{len})"
                        ),
                    );
                }
            }
            (None, None) => {}
        }
    }
}

/// A split node's children are its split's parts: one `split!` per body,
/// and no `child!` beside it (design transformations read a split node's
/// children as its parts, in order).
fn check_split(cx: &Ctxt, calls: &[Call]) {
    let mut splits = calls.iter().filter(|c| c.kind == CallKind::Split);
    if splits.next().is_none() {
        return;
    }
    for extra in splits {
        cx.error(
            extra.span,
            "a body has at most one `split!`: it is a split node, whose children are the parts \
             of its one split",
        );
    }
    for c in calls.iter().filter(|c| c.kind == CallKind::Child) {
        cx.error(
            c.span,
            "`child!` in a body with `split!`: a split node schedules its children only as \
             parts of its split; give this child its own part, or move the split into a child \
             node",
        );
    }
}

/// SMC ends a step on a node that emits geometry, so the graph must say which do.
fn check_emits(cx: &Ctxt, n: &Node, calls: &[Call]) {
    if !n.emits && body::emits(calls) {
        let name = n.name();
        let members: Vec<String> = n.members.iter().map(ToString::to_string).collect();
        cx.error(
            name.span(),
            format!(
                "node `{name}` emits geometry: declare it `node {} emits {{ ... }}`",
                members.join(", ")
            ),
        );
    }
}

/// The distributions each parameter type accepts, with their arities.
fn signature(kind: Kind, dist: &str) -> Option<usize> {
    match (kind, dist) {
        (Kind::F32 | Kind::Vec2 | Kind::Vec3, "uniform" | "normal") => Some(2),
        (Kind::F32 | Kind::Vec2 | Kind::Vec3, "truncated_normal") => Some(4),
        (Kind::F32 | Kind::Vec2 | Kind::Vec3 | Kind::Int, "constant") => Some(1),
        (Kind::Int, "uniform") => Some(2),
        (Kind::Choice, "choice") => Some(1),
        _ => None,
    }
}

/// A distribution must suit its parameter's type and have a non-empty support
/// (as far as literals show; core checks the rest when the graph is built).
fn check_distribution(cx: &Ctxt, p: &Param, d: &DistCall) {
    let dist = d.dist.to_string();
    let Some(arity) = signature(p.kind, &dist) else {
        let names: &[&str] = match p.kind {
            Kind::F32 | Kind::Vec2 | Kind::Vec3 => {
                &["uniform", "normal", "truncated_normal", "constant"]
            }
            Kind::Int => &["uniform", "constant"],
            Kind::Choice => &["choice"],
        };
        let expected = match p.kind {
            Kind::F32 | Kind::Vec2 | Kind::Vec3 => {
                "`uniform`, `normal`, `truncated_normal` or `constant`"
            }
            Kind::Int => "`uniform` or `constant`",
            Kind::Choice => "`choice([weights...])`",
        };
        let hint = did_you_mean(&dist, names.iter().copied());
        let hint = if hint.is_empty() {
            String::new()
        } else {
            format!(" ({})", &hint[2..])
        };
        cx.error(
            d.dist.span(),
            format!(
                "`{dist}` is not a distribution for this parameter type: expected {expected}{hint}"
            ),
        );
        return;
    };
    if d.args.len() != arity {
        cx.syn_error(syn::Error::new_spanned(
            &d.call,
            format!(
                "`{dist}` takes {arity} argument{}, found {}",
                if arity == 1 { "" } else { "s" },
                d.args.len()
            ),
        ));
        return;
    }
    match p.kind {
        Kind::Choice => check_choice_weights(cx, &d.args[0]),
        Kind::Int => check_int_arguments(cx, d),
        Kind::F32 | Kind::Vec2 | Kind::Vec3 => check_real_arguments(cx, p.kind, d),
    }
}

/// An `int` bound of 0.5 would be truncated silently (`uniform(0.5, 3.5)` would
/// draw 0..=3, 0 included): integer parameters take integer arguments.
fn check_int_arguments(cx: &Ctxt, d: &DistCall) {
    let values: Vec<Option<f64>> = d.args.iter().map(number).collect();
    for (a, v) in d.args.iter().zip(&values) {
        if let Some(v) = v
            && v.fract() != 0.0
        {
            let (floor, ceil) = (v.floor(), v.ceil());
            cx.error(
                a.span(),
                format!(
                    "an `int` parameter takes whole numbers, found {v}: write {floor} or {ceil} \
                     (bounds are inclusive), or make the parameter `f32`"
                ),
            );
            return;
        }
    }
    if d.dist == "uniform"
        && let [Some(lo), Some(hi)] = values.as_slice()
        && lo > hi
    {
        cx.syn_error(syn::Error::new_spanned(
            &d.call,
            format!("inverted range: {lo} > {hi}"),
        ));
    }
}

fn check_real_arguments(cx: &Ctxt, kind: Kind, d: &DistCall) {
    let dist = d.dist.to_string();
    let n = kind.components();
    // Per component: the evaluated arguments (None where not a literal).
    let mut per_component = vec![Vec::new(); n];
    for a in &d.args {
        let comps = if n > 1 {
            match components(a, n) {
                Some(c) if c.len() == n => c,
                Some(c) => {
                    cx.error(
                        a.span(),
                        format!("expected {n} components, found {}", c.len()),
                    );
                    return;
                }
                None => {
                    cx.error(
                        a.span(),
                        format!(
                            "expected an array of {n} numbers (`[a, b{}]`), `[x; {n}]` or a number",
                            if n == 3 { ", c" } else { "" }
                        ),
                    );
                    return;
                }
            }
        } else {
            vec![a.clone()]
        };
        for (i, c) in comps.iter().enumerate() {
            per_component[i].push(number(c));
        }
    }
    for v in per_component {
        let problem = match (dist.as_str(), v.as_slice()) {
            ("uniform", [Some(lo), Some(hi)]) if lo > hi => {
                Some(format!("inverted range: {lo} > {hi}"))
            }
            ("normal", [_, Some(std)]) if *std <= 0.0 => {
                Some(format!("standard deviation {std} must be > 0"))
            }
            ("truncated_normal", [_, Some(std), _, _]) if *std <= 0.0 => {
                Some(format!("standard deviation {std} must be > 0"))
            }
            ("truncated_normal", [_, _, Some(lo), Some(hi)]) if lo > hi => {
                Some(format!("inverted range: {lo} > {hi}"))
            }
            _ => None,
        };
        if let Some(problem) = problem {
            cx.syn_error(syn::Error::new_spanned(&d.call, problem));
            return;
        }
    }
}

/// A choice draws option `i` with probability `w_i / Σ w`: weights must be
/// non-negative and not all zero.
fn check_choice_weights(cx: &Ctxt, e: &Expr) {
    let Expr::Array(a) = e else {
        cx.error(
            e.span(),
            "expected an array of weights: `choice([1.0, 2.0])`",
        );
        return;
    };
    if a.elems.is_empty() {
        cx.error(e.span(), "a choice needs at least one option");
        return;
    }
    let values: Vec<Option<f64>> = a.elems.iter().map(number).collect();
    if let Some(bad) = a
        .elems
        .iter()
        .zip(&values)
        .find(|(_, v)| v.is_some_and(|v| v < 0.0))
    {
        cx.error(bad.0.span(), "choice weights must be >= 0");
    } else if values.iter().all(|v| *v == Some(0.0)) {
        cx.error(e.span(), "choice weights sum to 0");
    }
}

/// Every graph node's name.
fn node_names(g: &Generator) -> impl Iterator<Item = &syn::Ident> {
    g.members().map(|(n, m)| &n.members[m])
}

fn node_strings(g: &Generator) -> Vec<String> {
    node_names(g).map(ToString::to_string).collect()
}
