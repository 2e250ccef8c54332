//! The generator's type, its inherent methods (`spec`, `try_graph`,
//! `interpreter` and the node bodies) and its `Generator` implementation.

use proc_macro2::TokenStream;
use quote::quote;

use super::nodes::{Names, Nodes};
use super::spec::Declaration;
use crate::ast::Generator;
use crate::body::hidden;

pub fn expand(g: &Generator, declaration: &Declaration, nodes: &Nodes) -> TokenStream {
    let krate = &g.krate;
    let (name, vis, attrs) = (&g.name, &g.vis, &g.attrs);
    let (state_ty, axiom) = super::state(g);
    let Names {
        out,
        state,
        words,
        pos,
        ..
    } = &nodes.names;
    let (bodies, direct_arms, rules) = (&nodes.bodies, &nodes.direct_arms, &nodes.rules);
    let summary = summary(g);
    let stack = hidden("__sg_stack");
    let sink = hidden("__sg_sink");
    let start_len = hidden("__sg_start");
    let Declaration {
        asserts,
        spec,
        shapes,
        shape_count,
    } = declaration;
    quote! {
        #asserts

        #(#attrs)*
        #[doc = ""]
        #[doc = #summary]
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
        #vis struct #name;

        impl #name {
            /// The generator graph as declared.
            #vis fn spec() -> &'static #krate::graph::GraphSpec {
                static SPEC: ::std::sync::LazyLock<#krate::graph::GraphSpec> =
                    ::std::sync::LazyLock::new(|| #spec);
                &SPEC
            }

            /// The checked generator graph, or every problem the macro could
            /// not see at compile time (values given by non-literal expressions).
            #vis fn try_graph() -> ::core::result::Result<&'static #krate::graph::Graph, &'static #krate::graph::GraphErrors> {
                static GRAPH: ::std::sync::LazyLock<::core::result::Result<#krate::graph::Graph, #krate::graph::GraphErrors>> =
                    ::std::sync::LazyLock::new(|| #krate::graph::Graph::new(#name::spec().clone()));
                GRAPH.as_ref()
            }

            /// The same generator run by the run-time `Interpreter`:
            /// identical geometry, with parameters and slots looked up by name.
            ///
            /// # Panics
            /// If the graph is invalid (see [`try_graph`](Self::try_graph)).
            #vis fn interpreter() -> #krate::express::Interpreter<#state_ty> {
                let graph = <Self as #krate::express::Generator>::graph(&Self).clone();
                let shapes = <Self as #krate::express::Generator>::shapes(&Self);
                #krate::express::Interpreter::new(graph, shapes.iter().cloned(), #axiom)
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
                match #name::try_graph() {
                    ::core::result::Result::Ok(g) => g,
                    ::core::result::Result::Err(e) => ::core::panic!("{}", e),
                }
            }

            fn shapes(&self) -> &[::std::borrow::Cow<'static, str>] {
                static SHAPES: [::std::borrow::Cow<'static, str>; #shape_count] = #shapes;
                &SHAPES
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
                while let ::core::option::Option::Some(#state) = #stack.pop_state() {
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

            fn express_gene<__SgSink: #krate::express::ModelSink>(
                &self,
                chromosome: &#krate::genome::Chromosome,
                #pos: u32,
                #state: #state_ty,
                #sink: &mut __SgSink,
                #stack: &mut #krate::express::Pending<#state_ty>,
            ) {
                let #words = chromosome.words();
                let #pos = #pos as usize;
                let mut #out = #krate::__private::Direct { words: #words, pos: #pos, sink: &mut *#sink, stack: &mut *#stack };
                match #krate::__private::node_of(#words[#pos]) {
                    #(#direct_arms)*
                    _ => {}
                }
            }
        }
    }
}

/// A line for the generated type's docs: nodes and their slots.
fn summary(g: &Generator) -> String {
    let nodes: Vec<String> = g
        .members()
        .map(|(n, m)| {
            let slots: Vec<String> = n
                .slots
                .iter()
                .map(|s| format!("{} → {}", s.name, s.target))
                .collect();
            let name = &n.members[m];
            if slots.is_empty() {
                format!("`{name}`")
            } else {
                format!("`{name}` ({})", slots.join(", "))
            }
        })
        .collect();
    format!("Generator graph: {}.", nodes.join("; "))
}
