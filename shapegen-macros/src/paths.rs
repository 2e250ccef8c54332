//! Finding a slot scheduled twice on one execution path of a node body.
//!
//! `child!(slot, state)` pushes the child once per call; a second call for
//! the same slot on one path expresses the same gene twice, which is never
//! what the author meant. The analysis follows Rust's control flow through
//! blocks, `if`/`else`, `match`, loops and early exits, and reports a pair of
//! calls only when one of them lies on *every* path through the other's
//! position (so `if c { child!(a, s) } else { child!(a, t) }` is fine, and so
//! is `if c { child!(a, s); return; } child!(a, t);`). Calls with a computed
//! array index (`lots[k]`) are not followed.

use std::collections::BTreeMap;

use proc_macro2::{Span, TokenStream};
use syn::visit::Visit;
use syn::{Block, Expr, Macro, Stmt};

use crate::body::{CallKind, parse_call};
use crate::ctxt::Ctxt;

/// A scheduled slot: its name and constant array index.
type Key = (String, Option<usize>);
/// Scheduled slots, each with where it was scheduled.
type Set = BTreeMap<Key, Span>;

/// What a piece of code schedules.
#[derive(Default, Clone)]
struct Flow {
    /// On some path through it, including paths that leave early.
    may: Set,
    /// On some path that reaches the code after it.
    may_after: Set,
    /// On every path that reaches the code after it.
    must: Set,
    /// No path reaches the code after it.
    diverges: bool,
}

impl Flow {
    fn scheduled(key: Key, span: Span) -> Self {
        let set: Set = [(key, span)].into();
        Self {
            may: set.clone(),
            may_after: set.clone(),
            must: set,
            diverges: false,
        }
    }

    fn diverging() -> Self {
        Self {
            diverges: true,
            ..Self::default()
        }
    }

    /// `self` then `next`, reporting a slot scheduled by both on one path.
    fn then(&mut self, cx: &Ctxt, next: Flow) {
        if self.diverges {
            return;
        }
        for (key, span) in &next.may {
            if self.must.contains_key(key) {
                report(cx, key, *span);
            }
        }
        for (key, span) in &next.must {
            if self.may_after.contains_key(key) && !self.must.contains_key(key) {
                report(cx, key, *span);
            }
        }
        self.may.extend(next.may);
        self.may_after.extend(next.may_after);
        self.must.extend(next.must);
        self.diverges = next.diverges;
    }

    /// One of `branches` runs.
    fn alternatives(branches: Vec<Flow>) -> Self {
        let mut out = Flow {
            diverges: true,
            ..Flow::default()
        };
        let mut must: Option<Set> = None;
        for b in branches {
            out.may.extend(b.may);
            if b.diverges {
                continue;
            }
            out.diverges = false;
            out.may_after.extend(b.may_after);
            must = Some(match must {
                None => b.must,
                Some(m) => m
                    .into_iter()
                    .filter(|(k, _)| b.must.contains_key(k))
                    .collect(),
            });
        }
        out.must = must.unwrap_or_default();
        out
    }

    /// Code that may run any number of times, including none.
    fn repeated(body: Flow) -> Self {
        Flow {
            may: body.may,
            may_after: body.may_after,
            ..Flow::default()
        }
    }
}

fn report(cx: &Ctxt, (slot, index): &Key, span: Span) {
    let slot = match index {
        Some(i) => format!("{slot}[{i}]"),
        None => slot.clone(),
    };
    cx.error(
        span,
        format!(
            "slot `{slot}` is scheduled twice on one path: each `child!` expresses the child \
             once more; schedule it once (alternatives go in `if`/`else` or `match`)"
        ),
    );
}

/// Checks a node body (a brace group); a body that is not a valid block is
/// left to the compiler.
pub fn check(cx: &Ctxt, body: &TokenStream) {
    if let Ok(b) = syn::parse2::<Block>(body.clone()) {
        block(cx, &b);
    }
}

fn block(cx: &Ctxt, b: &Block) -> Flow {
    let mut flow = Flow::default();
    for s in &b.stmts {
        let next = stmt(cx, s);
        flow.then(cx, next);
    }
    flow
}

fn stmt(cx: &Ctxt, s: &Stmt) -> Flow {
    match s {
        Stmt::Local(l) => {
            let Some(init) = &l.init else {
                return Flow::default();
            };
            let mut flow = expr(cx, &init.expr);
            if let Some((_, otherwise)) = &init.diverge {
                flow.then(
                    cx,
                    Flow::alternatives(vec![Flow::default(), expr(cx, otherwise)]),
                );
            }
            flow
        }
        Stmt::Expr(e, _) => expr(cx, e),
        Stmt::Macro(m) => mac(&m.mac),
        Stmt::Item(_) => Flow::default(),
    }
}

fn mac(m: &Macro) -> Flow {
    let Some(name) = m.path.get_ident().map(ToString::to_string) else {
        return Flow::default();
    };
    match name.as_str() {
        "child" => {
            let group =
                proc_macro2::Group::new(proc_macro2::Delimiter::Parenthesis, m.tokens.clone());
            match parse_call(CallKind::Child, &group) {
                Ok(c) if c.index.is_none() || c.literal_index().is_some() => {
                    Flow::scheduled((c.id.to_string(), c.literal_index()), c.id.span())
                }
                _ => Flow::default(),
            }
        }
        "panic" | "unreachable" | "todo" | "unimplemented" => Flow::diverging(),
        _ => Flow::default(),
    }
}

fn expr(cx: &Ctxt, e: &Expr) -> Flow {
    match e {
        Expr::Block(b) => block(cx, &b.block),
        Expr::Unsafe(b) => block(cx, &b.block),
        Expr::Macro(m) => mac(&m.mac),
        Expr::If(i) => {
            let mut flow = expr(cx, &i.cond);
            let then = block(cx, &i.then_branch);
            let otherwise = i
                .else_branch
                .as_ref()
                .map_or_else(Flow::default, |(_, e)| expr(cx, e));
            flow.then(cx, Flow::alternatives(vec![then, otherwise]));
            flow
        }
        Expr::Match(m) => {
            let mut flow = expr(cx, &m.expr);
            let arms = m.arms.iter().map(|a| expr(cx, &a.body)).collect();
            flow.then(cx, Flow::alternatives(arms));
            flow
        }
        Expr::ForLoop(f) => {
            let mut flow = expr(cx, &f.expr);
            flow.then(cx, Flow::repeated(block(cx, &f.body)));
            flow
        }
        Expr::While(w) => {
            let mut flow = expr(cx, &w.cond);
            flow.then(cx, Flow::repeated(block(cx, &w.body)));
            flow
        }
        Expr::Loop(l) => Flow::repeated(block(cx, &l.body)),
        Expr::Closure(c) => {
            // Checked on its own: it may be called any number of times.
            expr(cx, &c.body);
            Flow::default()
        }
        Expr::Return(r) => {
            let mut flow = r.expr.as_ref().map_or_else(Flow::default, |e| expr(cx, e));
            flow.then(cx, Flow::diverging());
            flow
        }
        Expr::Break(b) => {
            let mut flow = b.expr.as_ref().map_or_else(Flow::default, |e| expr(cx, e));
            flow.then(cx, Flow::diverging());
            flow
        }
        Expr::Continue(_) => Flow::diverging(),
        // Anything else evaluates its parts in order.
        _ => {
            let mut parts = Parts::default();
            syn::visit::visit_expr(&mut parts, e);
            let mut flow = Flow::default();
            for p in parts.0 {
                let next = match p {
                    Part::Expr(e) => expr(cx, e),
                    Part::Macro(m) => mac(m),
                };
                flow.then(cx, next);
            }
            flow
        }
    }
}

enum Part<'a> {
    Expr(&'a Expr),
    Macro(&'a Macro),
}

/// The direct sub-expressions (and macro calls) of an expression, in order.
#[derive(Default)]
struct Parts<'a>(Vec<Part<'a>>);

impl<'a> Visit<'a> for Parts<'a> {
    fn visit_expr(&mut self, e: &'a Expr) {
        self.0.push(Part::Expr(e));
    }

    fn visit_macro(&mut self, m: &'a Macro) {
        self.0.push(Part::Macro(m));
    }

    fn visit_item(&mut self, _: &'a syn::Item) {}
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The messages `check` reports for a body.
    fn errors(body: &str) -> Vec<String> {
        let cx = Ctxt::new();
        check(&cx, &body.parse().unwrap());
        match cx.check() {
            Ok(()) => Vec::new(),
            Err(e) => e.into_iter().map(|e| e.to_string()).collect(),
        }
    }

    #[test]
    fn a_slot_twice_in_sequence_is_reported() {
        let e = errors("{ child!(a, s); child!(b, s); child!(a, s); }");
        assert_eq!(e.len(), 1, "{e:?}");
        assert!(e[0].contains("slot `a` is scheduled twice"), "{e:?}");
        assert_eq!(
            errors("{ child!(lots[3], s); child!(lots[3], t); }").len(),
            1
        );
        // Once unconditionally and once in a branch: the branch's path has both.
        assert_eq!(errors("{ child!(a, s); if c { child!(a, s); } }").len(), 1);
        assert_eq!(errors("{ if c { child!(a, s); } child!(a, s); }").len(), 1);
        assert_eq!(
            errors("{ let x = { child!(a, s); 1 }; f(child!(a, s)); }").len(),
            1
        );
    }

    #[test]
    fn alternatives_and_early_exits_are_not_reported() {
        for ok in [
            "{ if c { child!(a, s); } else { child!(a, t); } }",
            "{ match k { 0 => child!(a, s), _ => child!(a, t) } }",
            "{ if c { child!(a, s); return; } child!(a, t); }",
            "{ child!(lots[1], s); child!(lots[2], s); }",
            "{ for k in 0..3 { child!(lots[k], s); } }",
            "{ if c { child!(a, s); } if d { child!(a, t); } }",
            "{ let f = |x| child!(a, x); f(s); }",
            "{ child!(a, s); child!(b, s); if expressed!(a) { child!(c, s); } }",
        ] {
            assert_eq!(errors(ok), Vec::<String>::new(), "{ok}");
        }
    }
}
