//! Checking a declaration's meaning: names, targets, probabilities, ranges,
//! limits and reachability. Every problem is recorded in the [`Ctxt`].

use std::collections::{HashMap, HashSet};

use syn::Expr;
use syn::spanned::Spanned;

use crate::ast::{Generator, Kind, Param};
use crate::ctxt::Ctxt;
use crate::eval::{components, number};

/// Checks `g`, recording every problem in `cx`.
pub fn generator(cx: &Ctxt, g: &Generator) {
    let mut names = HashSet::new();
    for n in &g.nodes {
        if !names.insert(n.name.to_string()) {
            cx.error(n.name.span(), format!("duplicate node `{}`", n.name));
        }
    }
    let mut shapes = HashSet::new();
    for s in &g.shapes {
        if !shapes.insert(s.to_string()) {
            cx.error(s.span(), format!("duplicate shape `{s}`"));
        }
    }
    match &g.start {
        None => cx.error(g.name.span(), "missing start node: add `start: NodeName;`"),
        Some(s) if !names.contains(&s.to_string()) => {
            cx.error(s.span(), format!("unknown start node `{s}`"))
        }
        Some(_) => {}
    }
    if g.nodes.is_empty() {
        cx.error(g.name.span(), "a generator needs at least one `node`");
    }
    for n in &g.nodes {
        let mut params = HashSet::new();
        for p in &n.params {
            if !params.insert(p.name.to_string()) {
                cx.error(
                    p.name.span(),
                    format!("duplicate parameter `{}` in node `{}`", p.name, n.name),
                );
            }
            param(cx, p);
        }
        let mut slots = HashSet::new();
        for s in &n.slots {
            if !slots.insert(s.name.to_string()) {
                cx.error(
                    s.name.span(),
                    format!("duplicate slot `{}` in node `{}`", s.name, n.name),
                );
            }
            if !names.contains(&s.target.to_string()) {
                cx.error(s.target.span(), format!("unknown node `{}`", s.target));
            }
            if let Some(p) = number(&s.p)
                && !(0.0..=1.0).contains(&p)
            {
                cx.syn_error(syn::Error::new_spanned(
                    &s.p,
                    format!("probability {p} is outside [0, 1]"),
                ));
            }
        }
        for s in &n.slots {
            if let Some(c) = &s.count
                && c.base10_parse::<usize>().is_ok_and(|c| c == 0)
            {
                cx.error(c.span(), "a slot array needs at least one element");
            } else if let Some(c) = &s.count
                && c.base10_parse::<usize>().is_err()
            {
                cx.error(
                    c.span(),
                    "expected the number of elements, e.g. `lots[100]`",
                );
            }
        }
        if n.slots.iter().map(|s| s.len()).sum::<usize>() > 255 {
            cx.error(n.name.span(), "a node may have at most 255 slots");
        }
    }
    limits(cx, g);
    reachability(cx, g);
}

fn limits(cx: &Ctxt, g: &Generator) {
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
            cx.error(e.span(), format!("max_len ({max}) must exceed min_len ({min}): lengths satisfy min_len <= L < max_len"));
        }
    }
}

fn reachability(cx: &Ctxt, g: &Generator) {
    let Some(start) = &g.start else { return };
    let index: HashMap<String, usize> = g
        .nodes
        .iter()
        .enumerate()
        .map(|(i, n)| (n.name.to_string(), i))
        .collect();
    let Some(&s) = index.get(&start.to_string()) else {
        return;
    };
    let mut reached = vec![false; g.nodes.len()];
    let mut stack = vec![s];
    while let Some(i) = stack.pop() {
        if std::mem::replace(&mut reached[i], true) {
            continue;
        }
        stack.extend(
            g.nodes[i]
                .slots
                .iter()
                .filter_map(|sl| index.get(&sl.target.to_string()).copied()),
        );
    }
    for (i, n) in g.nodes.iter().enumerate() {
        if !reached[i] && index[&n.name.to_string()] == i {
            cx.error(
                n.name.span(),
                format!(
                    "node `{}` cannot be reached from the start node `{start}`",
                    n.name
                ),
            );
        }
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

fn param(cx: &Ctxt, p: &Param) {
    let dist = p.dist.to_string();
    let Some(arity) = signature(p.kind, &dist) else {
        let expected = match p.kind {
            Kind::F32 | Kind::Vec2 | Kind::Vec3 => {
                "`uniform`, `normal`, `truncated_normal` or `constant`"
            }
            Kind::Int => "`uniform` or `constant`",
            Kind::Choice => "`choice([weights...])`",
        };
        cx.error(
            p.dist.span(),
            format!("`{dist}` is not a distribution for this parameter type: expected {expected}"),
        );
        return;
    };
    if p.args.len() != arity {
        cx.syn_error(syn::Error::new_spanned(
            &p.call,
            format!(
                "`{dist}` takes {arity} argument{}, found {}",
                if arity == 1 { "" } else { "s" },
                p.args.len()
            ),
        ));
        return;
    }
    if p.kind == Kind::Choice {
        choice_weights(cx, &p.args[0]);
        return;
    }
    let n = p.kind.components().max(1);
    // Per component: the evaluated arguments (None where not a literal).
    let mut per_component = vec![Vec::new(); n];
    for a in &p.args {
        let comps = if p.kind.components() > 1 {
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
            cx.syn_error(syn::Error::new_spanned(&p.call, problem));
            return;
        }
    }
}

fn choice_weights(cx: &Ctxt, e: &Expr) {
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
