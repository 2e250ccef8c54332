//! What to emit after errors: the generator's type with its inherent
//! methods and a `Generator` implementation whose bodies are never run (the
//! crate does not compile), so code using the generator type-checks and
//! only the real mistakes are reported (as thiserror's `fallback.rs`).

use proc_macro2::{TokenStream, TokenTree};
use quote::{format_ident, quote};
use syn::parse::{ParseStream, Parser};
use syn::{Attribute, Ident, Path, Token, Type, Visibility};

use crate::ast::Generator;
use crate::expand::nodes::{Names, body_fn};

/// The fallback for a declaration that parsed: with the node bodies, so
/// that the code they use counts as used and their own type errors show.
pub fn expand(g: &Generator) -> TokenStream {
    let (state_ty, _) = crate::expand::state(g);
    let names = Names::new();
    let mut seen = std::collections::HashSet::new();
    let bodies = g
        .nodes
        .iter()
        .filter(|n| seen.insert(n.name().to_string()))
        .map(|n| {
            let fn_name = format_ident!("__sg_node_{}", n.name());
            body_fn(g, n, &fn_name, &state_ty, &names)
        });
    let bodies = quote!(#(#bodies)*);
    emit(&g.attrs, &g.vis, &g.name, &g.krate, &state_ty, &bodies)
}

/// The fallback for a declaration that did not parse: its header
/// (`pub struct Name;`), `state:` and `crate:` items are read leniently.
/// Without even a header there is nothing to name, so nothing is emitted.
pub fn from_tokens(input: TokenStream) -> TokenStream {
    let header = |s: ParseStream| {
        let attrs = s.call(Attribute::parse_outer)?;
        let vis: Visibility = s.parse()?;
        s.parse::<Token![struct]>()?;
        let name: Ident = s.parse()?;
        Ok((attrs, vis, name))
    };
    let Ok((attrs, vis, name)) = header.parse2(take_header(&input)) else {
        return TokenStream::new();
    };
    let mut krate: Path = syn::parse_quote!(::shapegen);
    let mut state_ty = None;
    let tokens: Vec<TokenTree> = input.into_iter().collect();
    for (i, t) in tokens.iter().enumerate() {
        let TokenTree::Ident(word) = t else { continue };
        let colon = matches!(tokens.get(i + 1), Some(TokenTree::Punct(p)) if p.as_char() == ':');
        if !colon {
            continue;
        }
        let rest: TokenStream = tokens[i + 2..]
            .iter()
            .take_while(
                |t| !matches!(t, TokenTree::Punct(p) if p.as_char() == ';' || p.as_char() == '='),
            )
            .cloned()
            .collect();
        if word == "crate" {
            if let Ok(p) = syn::parse2::<Path>(rest) {
                krate = p;
            }
        } else if word == "state"
            && let Ok(ty) = syn::parse2::<Type>(rest)
        {
            state_ty = Some(quote!(#ty));
        }
    }
    let state_ty = state_ty.unwrap_or_else(|| quote!(#krate::express::Scope));
    emit(&attrs, &vis, &name, &krate, &state_ty, &TokenStream::new())
}

/// The tokens up to the first top-level `;`.
fn take_header(input: &TokenStream) -> TokenStream {
    input
        .clone()
        .into_iter()
        .take_while(|t| !matches!(t, TokenTree::Punct(p) if p.as_char() == ';'))
        .collect()
}

fn emit(
    attrs: &[Attribute],
    vis: &Visibility,
    name: &Ident,
    krate: &Path,
    state_ty: &TokenStream,
    bodies: &TokenStream,
) -> TokenStream {
    // Only doc comments are kept: other attributes may be the mistake.
    let docs = attrs.iter().filter(|a| a.path().is_ident("doc"));
    quote! {
        #(#docs)*
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
        #vis struct #name;

        #[allow(dead_code, unused_variables, unreachable_code)]
        impl #name {
            #vis fn spec() -> &'static #krate::graph::GraphSpec {
                ::core::unreachable!()
            }

            #vis fn try_graph() -> ::core::result::Result<&'static #krate::graph::Graph, &'static #krate::graph::GraphErrors> {
                ::core::unreachable!()
            }

            #vis fn interpreter() -> #krate::express::Interpreter<#state_ty> {
                ::core::unreachable!()
            }

            #bodies
        }

        #[allow(unused_variables)]
        impl #krate::express::Generator for #name {
            type State = #state_ty;

            fn graph(&self) -> &#krate::graph::Graph {
                ::core::unreachable!()
            }

            fn shapes(&self) -> &[::std::borrow::Cow<'static, str>] {
                ::core::unreachable!()
            }

            fn axiom(&self) -> #state_ty {
                ::core::unreachable!()
            }

            fn express_with<__SgSink: #krate::express::ModelSink>(
                &self,
                chromosome: &#krate::genome::Chromosome,
                sink: &mut __SgSink,
                stack: &mut #krate::express::Pending<#state_ty>,
            ) {
                ::core::unreachable!()
            }

            fn express_gene<__SgSink: #krate::express::ModelSink>(
                &self,
                chromosome: &#krate::genome::Chromosome,
                pos: u32,
                state: #state_ty,
                sink: &mut __SgSink,
                children: &mut #krate::express::Pending<#state_ty>,
            ) {
                ::core::unreachable!()
            }
        }
    }
}
