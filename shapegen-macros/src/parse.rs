//! Parsing a `generator!` declaration into the [`ast`](crate::ast) model.
//!
//! Parsing checks only the shape of the input; the meaning (names, ranges,
//! probabilities) is checked by [`check`](crate::check), which reports every
//! problem at once.

use proc_macro2::{Delimiter, TokenStream, TokenTree};
use syn::parse::{Parse, ParseStream};
use syn::punctuated::Punctuated;
use syn::{
    Attribute, Expr, Ident, Pat, Path, Token, Type, Visibility, braced, bracketed, parenthesized,
};

use crate::ast::{Generator, Kind, Limits, Node, Param, Slot};

mod kw {
    syn::custom_keyword!(shapes);
    syn::custom_keyword!(start);
    syn::custom_keyword!(limits);
    syn::custom_keyword!(state);
    syn::custom_keyword!(node);
    syn::custom_keyword!(emits);
    syn::custom_keyword!(params);
    syn::custom_keyword!(slots);
    syn::custom_keyword!(max_depth);
    syn::custom_keyword!(min_len);
    syn::custom_keyword!(max_len);
}

impl Parse for Generator {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let attrs = input.call(Attribute::parse_outer)?;
        let vis: Visibility = input.parse()?;
        input.parse::<Token![struct]>()?;
        let name: Ident = input.parse()?;
        input.parse::<Token![;]>()?;
        let mut g = Generator {
            attrs,
            vis,
            name,
            krate: syn::parse_quote!(::shapegen),
            shapes: Vec::new(),
            start: None,
            limits: Limits::default(),
            state: None,
            nodes: Vec::new(),
        };
        while !input.is_empty() {
            let item_attrs = input.call(Attribute::parse_outer)?;
            let look = input.lookahead1();
            if look.peek(kw::node) {
                g.nodes.push(parse_node(input, item_attrs)?);
                continue;
            }
            if let Some(a) = item_attrs.first() {
                return Err(syn::Error::new_spanned(
                    a,
                    "attributes are only allowed on the generator and its nodes",
                ));
            }
            if look.peek(Token![crate]) {
                input.parse::<Token![crate]>()?;
                input.parse::<Token![:]>()?;
                g.krate = input.parse::<Path>()?;
            } else if look.peek(kw::shapes) {
                input.parse::<kw::shapes>()?;
                input.parse::<Token![:]>()?;
                let content;
                bracketed!(content in input);
                g.shapes = Punctuated::<Ident, Token![,]>::parse_terminated(&content)?
                    .into_iter()
                    .collect();
            } else if look.peek(kw::start) {
                input.parse::<kw::start>()?;
                input.parse::<Token![:]>()?;
                g.start = Some(input.parse()?);
            } else if look.peek(kw::limits) {
                input.parse::<kw::limits>()?;
                input.parse::<Token![:]>()?;
                g.limits = parse_limits(input)?;
            } else if look.peek(kw::state) {
                input.parse::<kw::state>()?;
                input.parse::<Token![:]>()?;
                let ty: Type = input.parse()?;
                input.parse::<Token![=]>()?;
                g.state = Some((ty, input.parse()?));
            } else {
                return Err(look.error());
            }
            input.parse::<Token![;]>()?;
        }
        Ok(g)
    }
}

fn parse_limits(input: ParseStream) -> syn::Result<Limits> {
    let content;
    braced!(content in input);
    let mut limits = Limits::default();
    while !content.is_empty() {
        let look = content.lookahead1();
        let slot = if look.peek(kw::max_depth) {
            content.parse::<kw::max_depth>()?;
            &mut limits.max_depth
        } else if look.peek(kw::min_len) {
            content.parse::<kw::min_len>()?;
            &mut limits.min_len
        } else if look.peek(kw::max_len) {
            content.parse::<kw::max_len>()?;
            &mut limits.max_len
        } else {
            return Err(look.error());
        };
        content.parse::<Token![:]>()?;
        *slot = Some(content.parse()?);
        if !content.is_empty() {
            content.parse::<Token![,]>()?;
        }
    }
    Ok(limits)
}

/// Parses a node; its doc comments (`attrs`) document the declaration only.
fn parse_node(input: ParseStream, _attrs: Vec<Attribute>) -> syn::Result<Node> {
    input.parse::<kw::node>()?;
    let name: Ident = input.parse()?;
    let emits = input.peek(kw::emits);
    if emits {
        input.parse::<kw::emits>()?;
    }
    let content;
    braced!(content in input);
    let mut params = Vec::new();
    let mut slots = Vec::new();
    loop {
        let look = content.lookahead1();
        if look.peek(kw::params) {
            content.parse::<kw::params>()?;
            let inner;
            braced!(inner in content);
            params.extend(Punctuated::<Param, Token![,]>::parse_terminated(&inner)?);
        } else if look.peek(kw::slots) {
            content.parse::<kw::slots>()?;
            let inner;
            braced!(inner in content);
            slots.extend(Punctuated::<Slot, Token![,]>::parse_terminated(&inner)?);
        } else if look.peek(Token![|]) {
            break;
        } else {
            return Err(look.error());
        }
    }
    content.parse::<Token![|]>()?;
    let binder = Pat::parse_single(&content)?;
    content.parse::<Token![|]>()?;
    let body: TokenTree = content.parse()?;
    if !matches!(&body, TokenTree::Group(g) if g.delimiter() == Delimiter::Brace) {
        return Err(syn::Error::new(
            body.span(),
            "expected the node's body in braces: `|scope| { ... }`",
        ));
    }
    if !content.is_empty() {
        return Err(content.error("unexpected tokens after the node's body"));
    }
    Ok(Node {
        name,
        emits,
        params,
        slots,
        binder,
        body: body.into(),
    })
}

impl Parse for Param {
    /// `name: kind = dist(args)`
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let name: Ident = input.parse()?;
        input.parse::<Token![:]>()?;
        let kind_ident: Ident = input.call(syn::ext::IdentExt::parse_any)?;
        let kind = Kind::from_ident(&kind_ident).ok_or_else(|| {
            syn::Error::new(
                kind_ident.span(),
                format!("unknown parameter type `{kind_ident}`: expected `f32`, `vec2`, `vec3`, `int` or `choice`"),
            )
        })?;
        input.parse::<Token![=]>()?;
        let fork = input.fork();
        let dist: Ident = input.parse()?;
        let args;
        parenthesized!(args in input);
        let args = Punctuated::<Expr, Token![,]>::parse_terminated(&args)?
            .into_iter()
            .collect();
        // The call's tokens, kept to point errors at the whole call.
        let mut call = TokenStream::new();
        let mut cursor = fork.cursor();
        while let Some((tt, next)) = cursor.token_tree() {
            call.extend([tt]);
            if next == input.cursor() {
                break;
            }
            cursor = next;
        }
        Ok(Param {
            name,
            kind,
            dist,
            args,
            call,
        })
    }
}

impl Parse for Slot {
    /// `name: Target = probability` or `name[N]: Target = probability`
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let name: Ident = input.parse()?;
        let count = if input.peek(syn::token::Bracket) {
            let inner;
            bracketed!(inner in input);
            Some(inner.parse()?)
        } else {
            None
        };
        input.parse::<Token![:]>()?;
        let target: Ident = input.parse()?;
        input.parse::<Token![=]>()?;
        let p: Expr = input.parse()?;
        Ok(Slot {
            name,
            count,
            target,
            p,
        })
    }
}
