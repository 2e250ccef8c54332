//! Code generation, after the checks: the pipeline's entry point and the
//! pieces it assembles.
//!
//! - [`spec`]: the graph declaration (the `GraphSpec`, the shapes) and
//!   compile-time assertions of core's limits;
//! - [`nodes`]: one monomorphic function per node declaration, the
//!   specialized dispatch arms and the interpreter's rules;
//! - [`generator_impl`]: the type, its inherent methods and its
//!   `Generator` implementation.

mod generator_impl;
pub(crate) mod nodes;
mod spec;

use proc_macro2::TokenStream;
use quote::quote;

use crate::ast::Generator;
use crate::check;
use crate::ctxt::Ctxt;
use crate::fallback;

/// Expands a `generator!` invocation: parse, check every rule, and only
/// then generate. After errors the `compile_error!`s come with the
/// [`fallback`], so the user sees the real mistakes and not follow-ups.
pub fn generator(input: TokenStream) -> TokenStream {
    let g: Generator = match syn::parse2(input.clone()) {
        Ok(g) => g,
        Err(e) => {
            let errors = e.to_compile_error();
            let fallback = fallback::from_tokens(input);
            return quote!(#errors #fallback);
        }
    };
    let cx = Ctxt::new();
    check::generator(&cx, &g);
    match cx.check() {
        Ok(()) => expand(&g),
        Err(e) => {
            let errors = e.to_compile_error();
            let fallback = fallback::expand(&g);
            quote!(#errors #fallback)
        }
    }
}

/// The state type's tokens and the axiom's.
pub fn state(g: &Generator) -> (TokenStream, TokenStream) {
    let krate = &g.krate;
    match &g.state {
        Some((ty, axiom)) => (quote!(#ty), quote!(#axiom)),
        None => (
            quote!(#krate::express::Scope),
            quote!(#krate::express::Scope::UNIT),
        ),
    }
}

/// Generates the code of a checked declaration.
fn expand(g: &Generator) -> TokenStream {
    let declaration = spec::declaration(g);
    let nodes = nodes::expand(g);
    generator_impl::expand(g, &declaration, &nodes)
}

#[cfg(test)]
mod tests;
