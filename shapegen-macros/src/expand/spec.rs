//! The graph declaration: the `GraphSpec` (built once, on first use), the
//! shape names, and compile-time assertions that the graph fits the limits
//! core sets (`graph::MAX_NODES`, `graph::MAX_SLOTS`).

use proc_macro2::{Ident, TokenStream};
use quote::{quote, quote_spanned};
use syn::{Expr, Path};

use crate::ast::{DistCall, Generator, Kind, Node, Param, Slot};
use crate::body::slots_len;
use crate::eval::{components, number};

/// The declaration's data, for [`generator_impl`](super::generator_impl).
pub struct Declaration {
    /// Compile-time assertions (items).
    pub asserts: TokenStream,
    /// An expression building the `GraphSpec`.
    pub spec: TokenStream,
    /// An expression of type `[Cow<'static, str>; shape_count]`.
    pub shapes: TokenStream,
    pub shape_count: usize,
}

/// The graph declaration. Everything is built inside the generated items
/// (no helper module), so constants local to a function that declares a
/// generator are in scope.
pub fn declaration(g: &Generator) -> Declaration {
    let krate = &g.krate;
    let graph_name = g.name.to_string();
    let start = g.start.as_ref().map(|s| s.to_string()).unwrap_or_default();
    let nodes: Vec<TokenStream> = g.members().map(|(n, m)| node_spec(krate, n, m)).collect();
    let limits = limits(krate, g);
    let shapes: Vec<String> = g.shapes.iter().map(ToString::to_string).collect();
    Declaration {
        asserts: limit_assertions(g),
        spec: quote! {{
            use ::std::borrow::Cow;
            #krate::graph::GraphSpec {
                name: Cow::Borrowed(#graph_name),
                nodes: Cow::Owned(::std::vec![#(#nodes),*]),
                start: Cow::Borrowed(#start),
                limits: #limits,
            }
        }},
        shapes: quote!([#(::std::borrow::Cow::Borrowed(#shapes)),*]),
        shape_count: shapes.len(),
    }
}

/// Core's limits and constant indices into arrays of constant-expression
/// length, asserted where the compiler knows every length (the macro cannot
/// evaluate `lots[GRID * GRID]`).
fn limit_assertions(g: &Generator) -> TokenStream {
    let krate = &g.krate;
    let count = g.node_count();
    let nodes = quote_spanned!(g.name.span()=>
        const _: () = ::core::assert!(
            #count <= #krate::graph::MAX_NODES,
            "too many nodes: a generator graph holds at most `graph::MAX_NODES`"
        );
    );
    let slots = g.nodes.iter().map(|n| {
        let len = slots_len(&n.slots);
        let msg = format!(
            "node `{}` has too many slots: a node holds at most `graph::MAX_SLOTS`",
            n.name()
        );
        quote_spanned!(n.name().span()=>
            const _: () = ::core::assert!(#len <= #krate::graph::MAX_SLOTS, #msg);
        )
    });
    let indices = g
        .nodes
        .iter()
        .map(|n| crate::body::index_assertions(&n.slots, &n.body));
    quote!(#nodes #(#slots)* #(#indices)*)
}

/// The `NodeSpec` of member `m` of `n`.
fn node_spec(krate: &Path, n: &Node, m: usize) -> TokenStream {
    let name = n.members[m].to_string();
    let params = n.params.iter().map(|p| param_spec(krate, p, p.dist.get(m)));
    let slots = n.slots.iter().map(|s| slot_specs(krate, s, m));
    let emits = n.emits;
    let split = match crate::body::split_axis(&n.body) {
        Some(axis) => quote!(::core::option::Option::Some(#krate::graph::Axis::#axis)),
        None => quote!(::core::option::Option::None),
    };
    let tags = n.tags.iter().map(|t| {
        let word = t.get(m).to_string();
        let word = word.strip_prefix("r#").unwrap_or(&word).to_string();
        quote!(Cow::Borrowed(#word))
    });
    quote! {
        #krate::graph::NodeSpec {
            name: Cow::Borrowed(#name),
            params: Cow::Owned(::std::vec![#(#params),*]),
            slots: Cow::Owned({
                let mut slots = ::std::vec::Vec::new();
                #(#slots)*
                slots
            }),
            emits: #emits,
            tags: Cow::Owned(::std::vec![#(#tags),*]),
            split: #split,
        }
    }
}

/// Pushes a slot's `SlotSpec`s (`name[0]..name[N-1]` for an array) onto `slots`.
fn slot_specs(krate: &Path, s: &Slot, m: usize) -> TokenStream {
    let (name, target) = (s.name.to_string(), s.target.to_string());
    let p = probability(s.p.get(m));
    match &s.count {
        None => quote!(slots.push(#krate::graph::SlotSpec::new(#name, #target, #p));),
        Some(len) => quote! {
            slots.extend((0..(#len) as usize).map(|i| #krate::graph::SlotSpec {
                name: Cow::Owned(::std::format!("{}[{}]", #name, i)),
                target: Cow::Borrowed(#target),
                p: #p,
            }));
        },
    }
}

/// A probability: the exact value when it is made of literals (so `1 / 3` is a third), else the expression.
fn probability(e: &Expr) -> TokenStream {
    match number(e) {
        Some(v) => quote!(#v),
        None => quote!((#e) as f64),
    }
}

fn param_spec(krate: &Path, p: &Param, d: &DistCall) -> TokenStream {
    let name = p.name.to_string();
    let dist = match p.kind {
        Kind::Choice => {
            let weights = match &d.args[0] {
                Expr::Array(a) => a.elems.iter().map(|w| quote!((#w) as f64)).collect(),
                other => vec![quote!((#other) as f64)],
            };
            quote!(#krate::graph::ParamDist::Choice(Cow::Borrowed(&[#(#weights),*])))
        }
        Kind::Int => {
            let a = &d.args;
            let d = if d.dist == "constant" {
                let v = &a[0];
                quote!(#krate::graph::IntDist::Constant { value: (#v) as i32 })
            } else {
                let (lo, hi) = (&a[0], &a[1]);
                quote!(#krate::graph::IntDist::Uniform { lo: (#lo) as i32, hi: (#hi) as i32 })
            };
            quote!(#krate::graph::ParamDist::Int(#d))
        }
        Kind::F32 | Kind::Vec2 | Kind::Vec3 => {
            let n = p.kind.components();
            let args: Vec<Vec<Expr>> = d
                .args
                .iter()
                .map(|a| {
                    if n == 1 {
                        vec![a.clone()]
                    } else {
                        components(a, n).unwrap_or_default()
                    }
                })
                .collect();
            let f = Ident::new(&d.dist.to_string(), proc_macro2::Span::call_site());
            let comps: Vec<TokenStream> = (0..n)
                .map(|i| {
                    let xs = args.iter().map(|a| {
                        a.get(i)
                            .map_or_else(|| quote!(0.0), |x| quote!((#x) as f32))
                    });
                    quote!(#krate::graph::Dist::#f(#(#xs),*))
                })
                .collect();
            match p.kind {
                Kind::F32 => quote!(#krate::graph::ParamDist::F32(#(#comps)*)),
                Kind::Vec2 => quote!(#krate::graph::ParamDist::Vec2([#(#comps),*])),
                _ => quote!(#krate::graph::ParamDist::Vec3([#(#comps),*])),
            }
        }
    };
    quote!(#krate::graph::ParamSpec::new(#name, #dist))
}

fn limits(krate: &Path, g: &Generator) -> TokenStream {
    let opt = |e: &Option<Expr>| match e {
        Some(e) => quote!(::core::option::Option::Some((#e) as u32)),
        None => quote!(::core::option::Option::None),
    };
    let max_depth = opt(&g.limits.max_depth);
    let max_len = opt(&g.limits.max_len);
    let min_len = match &g.limits.min_len {
        Some(e) => quote!((#e) as u32),
        None => quote!(1),
    };
    quote!(#krate::graph::Limits { max_depth: #max_depth, min_len: #min_len, max_len: #max_len })
}
