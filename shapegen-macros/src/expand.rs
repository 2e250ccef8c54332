//! Code generation: a `static` graph declaration, one monomorphic body
//! function per node, the `Generator` implementation and an interpreter
//! running the same bodies through dynamic lookups.

use proc_macro2::{Span, TokenStream};
use quote::{format_ident, quote};
use syn::{Expr, Ident};

use crate::ast::{Generator, Kind, Node, Param};
use crate::body::{self, hidden};
use crate::check;
use crate::ctxt::Ctxt;
use crate::eval::{components, number};

/// Expands a `generator!` invocation; errors become `compile_error!`s plus a
/// placeholder type, so the user sees the real mistakes and not follow-ups.
pub fn generator(input: TokenStream) -> TokenStream {
    let g: Generator = match syn::parse2(input) {
        Ok(g) => g,
        Err(e) => return e.to_compile_error(),
    };
    let cx = Ctxt::new();
    check::generator(&cx, &g);
    let expanded = expand(&cx, &g);
    match cx.check() {
        Ok(()) => expanded,
        Err(e) => {
            let errors = e.to_compile_error();
            let fallback = fallback(&g);
            quote!(#errors #fallback)
        }
    }
}

/// After errors: the generator's type alone, so other code naming it still compiles.
fn fallback(g: &Generator) -> TokenStream {
    let (vis, name) = (&g.vis, &g.name);
    quote!(#vis struct #name;)
}

fn expand(cx: &Ctxt, g: &Generator) -> TokenStream {
    let krate = &g.krate;
    let name = &g.name;
    let vis = &g.vis;
    let attrs = &g.attrs;
    let module = format_ident!("__shapegen_{}", name);
    let (state_ty, axiom) = match &g.state {
        Some((ty, axiom)) => (quote!(#ty), quote!(#axiom)),
        None => (
            quote!(#krate::express::Scope),
            quote!(#krate::express::Scope::UNIT),
        ),
    };
    let graph_name = name.to_string();
    let start = g.start.as_ref().map(|s| s.to_string()).unwrap_or_default();

    // The static declaration.
    let mut statics = Vec::new();
    let mut node_specs = Vec::new();
    for n in &g.nodes {
        let params_id = format_ident!("PARAMS_{}", n.name);
        let slots_id = format_ident!("SLOTS_{}", n.name);
        let params: Vec<TokenStream> = n.params.iter().map(|p| param_spec(krate, p)).collect();
        let slots: Vec<TokenStream> = n
            .slots
            .iter()
            .flat_map(|s| {
                let tn = s.target.to_string();
                let p = probability(&s.p);
                let names: Vec<String> = match &s.count {
                    None => vec![s.name.to_string()],
                    Some(_) => (0..s.len()).map(|i| format!("{}[{i}]", s.name)).collect(),
                };
                names
                    .into_iter()
                    .map(move |sn| quote!(#krate::graph::SlotSpec::new(#sn, #tn, #p)))
            })
            .collect();
        let (np, ns) = (params.len(), slots.len());
        statics.push(quote! {
            pub static #params_id: [#krate::graph::ParamSpec; #np] = [#(#params),*];
            pub static #slots_id: [#krate::graph::SlotSpec; #ns] = [#(#slots),*];
        });
        let (nn, emits) = (n.name.to_string(), n.emits);
        node_specs.push(quote!(#krate::graph::NodeSpec::new(#nn, &#params_id, &#slots_id, #emits)));
        if !n.emits && body::emits(&n.body) {
            cx.error(
                n.name.span(),
                format!(
                    "node `{}` emits geometry: declare it `node {} emits {{ ... }}`",
                    n.name, n.name
                ),
            );
        }
    }
    let node_count = g.nodes.len();
    let limits = limits(krate, g);
    let shapes: Vec<String> = g.shapes.iter().map(ToString::to_string).collect();
    let shape_count = shapes.len();

    // One body function per node, generic over the output.
    let out = hidden("__sg_out");
    let state_arg = hidden("__sg_state");
    let mut bodies = Vec::new();
    let mut direct_arms = Vec::new();
    let mut rules = Vec::new();
    let words = hidden("__sg_words");
    let pos = hidden("__sg_pos");
    let input_var = hidden("__sg_input");
    for (id, n) in g.nodes.iter().enumerate() {
        let fn_name = format_ident!("__sg_node_{}", n.name);
        let scope = body::Scope {
            krate,
            node: &n.name,
            shapes: &g.shapes,
            slots: &n.slots,
            out: &out,
        };
        let user_body = body::rewrite(cx, &scope, n.body.clone());
        let binder = &n.binder;
        let param_names: Vec<&Ident> = n.params.iter().map(|p| &p.name).collect();
        let param_types: Vec<TokenStream> =
            n.params.iter().map(|p| rust_type(krate, p.kind)).collect();
        bodies.push(quote! {
            #[inline(always)]
            #[allow(unused_variables, unused_mut, non_snake_case, clippy::all)]
            fn #fn_name<__SgOut: #krate::express::NodeOut<#state_ty>>(
                #(#param_names: #param_types,)*
                #state_arg: #state_ty,
                #out: &mut __SgOut,
            ) {
                let #binder: #state_ty = #state_arg;
                #user_body
            }
        });
        // The specialized path: parameters read at constant offsets.
        let id = id as u16;
        let mut offset: usize = n.slots.iter().map(|s| s.len()).sum();
        let reads: Vec<TokenStream> = n
            .params
            .iter()
            .map(|p| {
                let at = offset;
                offset += p.kind.words();
                read_param(krate, p.kind, &words, &pos, at)
            })
            .collect();
        direct_arms.push(quote!(#id => Self::#fn_name(#(#reads,)* #state_arg, &mut #out),));
        // The interpreter: parameters looked up by name.
        let lookups: Vec<TokenStream> = n
            .params
            .iter()
            .map(|p| {
                let pn = p.name.to_string();
                let method = match p.kind {
                    Kind::F32 => quote!(f32),
                    Kind::Vec2 => quote!(vec2),
                    Kind::Vec3 => quote!(vec3),
                    Kind::Int => quote!(int),
                    Kind::Choice => quote!(choice),
                };
                quote!(#input_var.#method(#pn))
            })
            .collect();
        let nn = n.name.to_string();
        rules.push(quote!(.rule(#nn, |#input_var, #state_arg, #out| Self::#fn_name(#(#lookups,)* #state_arg, #out))));
    }
    let summary = summary(g);
    let stack = hidden("__sg_stack");
    let sink = hidden("__sg_sink");
    let start_len = hidden("__sg_start");
    quote! {
        #(#attrs)*
        #[doc = ""]
        #[doc = #summary]
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
        #vis struct #name;

        #[doc(hidden)]
        #[allow(non_upper_case_globals, non_snake_case)]
        mod #module {
            #[allow(unused_imports)]
            use super::*;
            #(#statics)*
            pub static NODES: [#krate::graph::NodeSpec; #node_count] = [#(#node_specs),*];
            pub static SPEC: #krate::graph::GraphSpec = #krate::graph::GraphSpec::new(#graph_name, &NODES, #start, #limits);
            pub static SHAPES: [::std::borrow::Cow<'static, str>; #shape_count] = [#(::std::borrow::Cow::Borrowed(#shapes)),*];
            pub static GRAPH: ::std::sync::LazyLock<::core::result::Result<#krate::graph::Graph, #krate::graph::GraphErrors>> =
                ::std::sync::LazyLock::new(|| #krate::graph::Graph::new(SPEC.clone()));
        }

        impl #name {
            /// The generator graph as declared.
            #vis fn spec() -> &'static #krate::graph::GraphSpec {
                &#module::SPEC
            }

            /// The checked generator graph, or every problem the macro could
            /// not see at compile time (values given by non-literal expressions).
            #vis fn try_graph() -> ::core::result::Result<&'static #krate::graph::Graph, &'static #krate::graph::GraphErrors> {
                #module::GRAPH.as_ref()
            }

            /// The same generator run by the run-time [`Interpreter`](#krate::express::Interpreter):
            /// identical geometry, with parameters and slots looked up by name.
            ///
            /// # Panics
            /// If the graph is invalid (see [`try_graph`](Self::try_graph)).
            #vis fn interpreter() -> #krate::express::Interpreter<#state_ty> {
                let graph = <Self as #krate::express::Generator>::graph(&Self).clone();
                #krate::express::Interpreter::new(graph, #module::SHAPES.iter().cloned(), #axiom)
                    #(#rules)*
                    .build()
                    .expect("every node has exactly one rule")
            }

            #(#bodies)*
        }

        impl #krate::express::Generator for #name {
            type State = #state_ty;

            /// # Panics
            /// If the graph is invalid (see [`try_graph`](Self::try_graph)).
            fn graph(&self) -> &#krate::graph::Graph {
                match #module::GRAPH.as_ref() {
                    ::core::result::Result::Ok(g) => g,
                    ::core::result::Result::Err(e) => ::core::panic!("{}", e),
                }
            }

            fn shapes(&self) -> &[::std::borrow::Cow<'static, str>] {
                &#module::SHAPES
            }

            fn axiom(&self) -> #state_ty {
                #axiom
            }

            fn express_with<__SgSink: #krate::express::ModelSink>(
                &self,
                chromosome: &#krate::genome::Chromosome,
                #sink: &mut __SgSink,
                #stack: &mut #krate::express::Pending<#state_ty>,
            ) {
                let #words = chromosome.words();
                #stack.clear();
                #stack.push(0, #axiom);
                while let ::core::option::Option::Some(#state_arg) = #stack.pop_state() {
                    let #pos = #stack.pop_position() as usize;
                    let #start_len = #stack.len();
                    let mut #out = #krate::__private::Direct { words: #words, pos: #pos, sink: &mut *#sink, stack: &mut *#stack };
                    match #krate::__private::node_of(#words[#pos]) {
                        #(#direct_arms)*
                        _ => {}
                    }
                    #stack.reverse_from(#start_len);
                }
            }
        }
    }
}

/// `words[pos + HEADER + at ..]` read as the parameter's Rust type.
fn read_param(krate: &syn::Path, kind: Kind, words: &Ident, pos: &Ident, at: usize) -> TokenStream {
    let w = |k: usize| {
        let k = at + k;
        quote!(#words[#pos + #krate::__private::HEADER_WORDS + #k])
    };
    let (w0, w1, w2) = (w(0), w(1), w(2));
    match kind {
        Kind::F32 => quote!(f32::from_bits(#w0)),
        Kind::Vec2 => quote!(#krate::glam::Vec2::new(f32::from_bits(#w0), f32::from_bits(#w1))),
        Kind::Vec3 => {
            quote!(#krate::glam::Vec3::new(f32::from_bits(#w0), f32::from_bits(#w1), f32::from_bits(#w2)))
        }
        Kind::Int => quote!(#w0 as i32),
        Kind::Choice => quote!(#w0),
    }
}

fn rust_type(krate: &syn::Path, kind: Kind) -> TokenStream {
    match kind {
        Kind::F32 => quote!(f32),
        Kind::Vec2 => quote!(#krate::glam::Vec2),
        Kind::Vec3 => quote!(#krate::glam::Vec3),
        Kind::Int => quote!(i32),
        Kind::Choice => quote!(u32),
    }
}

/// A probability: the exact value when it is made of literals (so `1 / 3` is a third), else the expression.
fn probability(e: &Expr) -> TokenStream {
    match number(e) {
        Some(v) => quote!(#v),
        None => quote!((#e) as f64),
    }
}

fn param_spec(krate: &syn::Path, p: &Param) -> TokenStream {
    let name = p.name.to_string();
    let dist = match p.kind {
        Kind::Choice => {
            let weights = match &p.args[0] {
                Expr::Array(a) => a.elems.iter().map(|w| quote!((#w) as f64)).collect(),
                other => vec![quote!((#other) as f64)],
            };
            quote!(#krate::graph::ParamDist::Choice(::std::borrow::Cow::Borrowed(&[#(#weights),*])))
        }
        Kind::Int => {
            let a = &p.args;
            let d = if p.dist == "constant" {
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
            let args: Vec<Vec<Expr>> = p
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
            let comps: Vec<TokenStream> = (0..n)
                .map(|i| {
                    let xs: Vec<TokenStream> = args
                        .iter()
                        .map(|a| {
                            a.get(i)
                                .map_or_else(|| quote!(0.0), |x| quote!((#x) as f32))
                        })
                        .collect();
                    let f = Ident::new(&p.dist.to_string(), Span::call_site());
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

fn limits(krate: &syn::Path, g: &Generator) -> TokenStream {
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

/// A line for the generated type's docs: nodes and their slots.
fn summary(g: &Generator) -> String {
    let nodes: Vec<String> = g
        .nodes
        .iter()
        .map(|n: &Node| {
            let slots: Vec<String> = n
                .slots
                .iter()
                .map(|s| format!("{} → {}", s.name, s.target))
                .collect();
            if slots.is_empty() {
                format!("`{}`", n.name)
            } else {
                format!("`{}` ({})", n.name, slots.join(", "))
            }
        })
        .collect();
    format!("Generator graph: {}.", nodes.join("; "))
}

#[cfg(test)]
mod tests {
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
    fn expands_a_static_graph_and_specialized_code() {
        let out = expand(TOWER);
        assert!(!out.contains("compile_error"), "{out}");
        for needle in [
            "pub static SPEC",
            "fn __sg_node_Floor",
            "impl :: shapegen :: express :: Generator for Tower",
            // Probabilities made of literals are exact reals: 1 / 4 = 0.25.
            "SlotSpec :: new (\"up\" , \"Floor\" , 0.25f64)",
            // Slot arrays become numbered slots.
            "\"lots[2]\"",
            // Vector ranges are split per component; a scalar is broadcast.
            "Dist :: uniform ((0.5) as f32 , (1.5) as f32)",
        ] {
            assert!(out.contains(needle), "missing `{needle}` in {out}");
        }
        // The parameter block starts after 4 slots: h at +4, v at +5..+7.
        assert!(out.contains("HEADER_WORDS + 4usize"), "{out}");
        assert!(out.contains("HEADER_WORDS + 7usize"), "{out}");
    }

    #[test]
    fn every_error_is_reported_and_a_placeholder_type_is_emitted() {
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
        assert!(out.ends_with("struct G ;"), "{out}");
    }

    #[test]
    fn syntax_errors_stop_at_the_first_one() {
        let out = expand("struct G; shapes [cube];");
        assert!(
            out.contains("compile_error") && out.contains("expected `:`"),
            "{out}"
        );
    }
}
