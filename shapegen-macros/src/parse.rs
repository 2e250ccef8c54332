//! Parsing a `generator!` declaration into the [`ast`](crate::ast) model.
//!
//! Parsing checks only the shape of the input; the meaning (names, ranges,
//! probabilities) is checked by [`check`](crate::check), which reports every
//! problem at once. A misspelled keyword gets a "did you mean" hint.

use proc_macro2::{Delimiter, TokenStream, TokenTree};
use syn::parse::{Parse, ParseStream};
use syn::punctuated::Punctuated;
use syn::{
    Attribute, Expr, Ident, Pat, Path, Token, Type, Visibility, braced, bracketed, parenthesized,
};

use crate::ast::{Const, DistCall, Generator, Kind, Limits, Node, Param, PerMember, Slot};
use crate::hint::{did_you_mean, message};

mod kw {
    syn::custom_keyword!(shapes);
    syn::custom_keyword!(start);
    syn::custom_keyword!(limits);
    syn::custom_keyword!(state);
    syn::custom_keyword!(node);
    syn::custom_keyword!(emits);
    syn::custom_keyword!(params);
    syn::custom_keyword!(slots);
    syn::custom_keyword!(consts);
    syn::custom_keyword!(tags);
    syn::custom_keyword!(each);
    syn::custom_keyword!(choice);
    syn::custom_keyword!(max_depth);
    syn::custom_keyword!(min_len);
    syn::custom_keyword!(max_len);
}

/// The items a declaration may hold after `struct Name;`.
const ITEMS: [&str; 6] = ["shapes", "start", "limits", "state", "crate", "node"];
/// The sections of a node, before its body.
const SECTIONS: [&str; 4] = ["params", "slots", "consts", "tags"];
/// The keys of `limits: { ... }`.
const LIMIT_KEYS: [&str; 3] = ["max_depth", "min_len", "max_len"];

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
            } else if let Some(word) = peek_word(input) {
                return Err(syn::Error::new(
                    word.span(),
                    message(
                        &format!("unknown item `{word}`"),
                        &word.to_string(),
                        ITEMS,
                        "a generator holds `shapes: [..];`, `start: Node;`, `limits: {..};`, \
                         `state: Type = axiom;`, `crate: path;` and `node`s",
                    ),
                ));
            } else {
                return Err(look.error());
            }
            input.parse::<Token![;]>()?;
        }
        Ok(g)
    }
}

/// The next token if it is an identifier (keywords included), without consuming it.
fn peek_word(input: ParseStream) -> Option<Ident> {
    input.fork().call(syn::ext::IdentExt::parse_any).ok()
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
        } else if let Some(word) = peek_word(&content) {
            return Err(syn::Error::new(
                word.span(),
                message(
                    &format!("unknown limit `{word}`"),
                    &word.to_string(),
                    LIMIT_KEYS,
                    "the limits are `max_depth`, `min_len` and `max_len`",
                ),
            ));
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

/// Parses `node A [, B ...] [emits] { sections |state| { body } }`; its doc
/// comments (`attrs`) document the declaration only.
fn parse_node(input: ParseStream, _attrs: Vec<Attribute>) -> syn::Result<Node> {
    input.parse::<kw::node>()?;
    let mut members = vec![input.parse::<Ident>()?];
    while input.peek(Token![,]) {
        input.parse::<Token![,]>()?;
        members.push(input.parse()?);
    }
    let emits = input.peek(kw::emits);
    if emits {
        input.parse::<kw::emits>()?;
    } else if let Some(word) = peek_word(input) {
        return Err(syn::Error::new(
            word.span(),
            format!(
                "expected `emits` or the node's braces, found `{word}`{}",
                did_you_mean(&word.to_string(), ["emits"])
            ),
        ));
    }
    let content;
    braced!(content in input);
    let (mut consts, mut params, mut slots, mut tags) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
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
        } else if look.peek(kw::consts) {
            content.parse::<kw::consts>()?;
            let inner;
            braced!(inner in content);
            consts.extend(Punctuated::<Const, Token![,]>::parse_terminated(&inner)?);
        } else if look.peek(kw::tags) {
            content.parse::<kw::tags>()?;
            let inner;
            braced!(inner in content);
            while !inner.is_empty() {
                tags.push(per_member(&inner, parse_tag)?);
                if !inner.is_empty() {
                    inner.parse::<Token![,]>()?;
                }
            }
        } else if look.peek(Token![|]) {
            break;
        } else if let Some(word) = peek_word(&content) {
            return Err(syn::Error::new(
                word.span(),
                message(
                    &format!("unknown section `{word}`"),
                    &word.to_string(),
                    SECTIONS,
                    "a node holds `params {..}`, `slots {..}`, `consts {..}` and `tags {..}`, \
                     then its body `|state| { .. }`",
                ),
            ));
        } else {
            return Err(look.error());
        }
    }
    content.parse::<Token![|]>()?;
    let binder = Pat::parse_single(&content)?;
    content.parse::<Token![|]>()?;
    let body = unwrap_invisible(content.parse::<TokenTree>()?);
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
        members,
        emits,
        consts,
        params,
        slots,
        tags,
        binder,
        body: body.into(),
    })
}

/// One tag: a plain word (`branching`), not a string or a path.
fn parse_tag(input: ParseStream) -> syn::Result<Ident> {
    if input.peek(syn::Lit) {
        let lit: syn::Lit = input.parse()?;
        return Err(syn::Error::new(
            lit.span(),
            "a tag is a plain word, not a literal: `tags { branching }`",
        ));
    }
    let tag: Ident = input.call(syn::ext::IdentExt::parse_any)?;
    if input.peek(Token![::]) || input.peek(Token![.]) || input.peek(Token![-]) {
        return Err(syn::Error::new(
            input.span(),
            format!(
                "a tag is one word of letters, digits and `_`: write `{tag}_..` instead of \
                 joining words with punctuation"
            ),
        ));
    }
    Ok(tag)
}

/// A `macro_rules!` fragment (`$body:block`) arrives wrapped in an invisible
/// group; the body is what it holds.
fn unwrap_invisible(mut tt: TokenTree) -> TokenTree {
    while let TokenTree::Group(g) = &tt
        && g.delimiter() == Delimiter::None
    {
        let mut inner = g.stream().into_iter();
        match (inner.next(), inner.next()) {
            (Some(only), None) => tt = only,
            _ => break,
        }
    }
    tt
}

/// `each[v0, v1, ...]` (one value per family member) or a single value.
fn per_member<T>(
    input: ParseStream,
    parse: fn(ParseStream) -> syn::Result<T>,
) -> syn::Result<PerMember<T>> {
    if input.peek(kw::each) && input.peek2(syn::token::Bracket) {
        input.parse::<kw::each>()?;
        let inner;
        let span = bracketed!(inner in input).span.join();
        let mut values = Vec::new();
        while !inner.is_empty() {
            values.push(parse(&inner)?);
            if !inner.is_empty() {
                inner.parse::<Token![,]>()?;
            }
        }
        if values.is_empty() {
            return Err(syn::Error::new(
                span,
                "`each[..]` needs one value per member",
            ));
        }
        return Ok(PerMember::Each { span, values });
    }
    Ok(PerMember::Shared(parse(input)?))
}

impl Parse for Param {
    /// `name: kind = dist(args)`, `name: kind = each[dist(args), ...]` or the
    /// short form `name: choice([weights])`.
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let name: Ident = input.parse()?;
        input.parse::<Token![:]>()?;
        if input.peek(kw::choice) && input.peek2(syn::token::Paren) {
            return Ok(Param {
                name,
                kind: Kind::Choice,
                dist: PerMember::Shared(input.parse()?),
            });
        }
        let kind_ident: Ident = input.call(syn::ext::IdentExt::parse_any)?;
        let Some(kind) = Kind::from_ident(&kind_ident) else {
            let word = kind_ident.to_string();
            let text = if input.peek(syn::token::Paren) {
                format!(
                    "expected the parameter's type before its distribution: \
                     `{name}: f32 = {word}(..)` (only `choice([..])` has a short form)"
                )
            } else {
                let candidates: &[&str] = match word.as_str() {
                    "f64" | "float" | "Float" => &["f32"],
                    "i32" | "u32" | "i64" | "u64" | "usize" | "integer" => &["int"],
                    _ => &Kind::NAMES,
                };
                let head = format!("unknown parameter type `{word}`");
                let tail = "the types are `f32`, `vec2`, `vec3`, `int` and `choice`";
                if candidates.len() == 1 {
                    format!(
                        "{head}: did you mean `{}`? The types are `f32`, `vec2`, `vec3`, `int` and `choice`",
                        candidates[0]
                    )
                } else {
                    message(&head, &word, candidates.iter().copied(), tail)
                }
            };
            return Err(syn::Error::new(kind_ident.span(), text));
        };
        input.parse::<Token![=]>()?;
        let dist = per_member(input, DistCall::parse)?;
        Ok(Param { name, kind, dist })
    }
}

impl Parse for DistCall {
    /// `dist(args)`
    fn parse(input: ParseStream) -> syn::Result<Self> {
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
        Ok(DistCall { dist, args, call })
    }
}

impl Parse for Slot {
    /// `name: Target = probability` or `name[N]: Target = probability`; the
    /// probability may be `each[..]`.
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
        let p = per_member(input, Expr::parse)?;
        Ok(Slot {
            name,
            count,
            target,
            p,
        })
    }
}

impl Parse for Const {
    /// `name: Type = value` or `name: Type = each[..]`
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let name: Ident = input.parse()?;
        input.parse::<Token![:]>()?;
        let ty: Type = input.parse()?;
        input.parse::<Token![=]>()?;
        let value = per_member(input, Expr::parse)?;
        Ok(Const { name, ty, value })
    }
}
