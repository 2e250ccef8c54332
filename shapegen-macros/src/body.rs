//! Rewriting a node body's `emit!(shape, transform)` and `child!(slot, state)`.
//!
//! The body is ordinary Rust; only these two pseudo-macros are replaced, by
//! calls on the node's output (`NodeOut`) with the shape or slot resolved to
//! a constant index. Unknown names are reported with the name's span; every
//! other token keeps its span, so type errors point into the user's body.

use proc_macro2::{Group, Ident, Span, TokenStream, TokenTree};
use quote::quote_spanned;
use syn::parse::{ParseStream, Parser};
use syn::spanned::Spanned;
use syn::{Expr, Path, Token};

use crate::ctxt::Ctxt;

/// What the rewriting needs to know about one node.
pub struct Scope<'a> {
    pub krate: &'a Path,
    pub node: &'a Ident,
    pub shapes: &'a [Ident],
    pub slots: &'a [crate::ast::Slot],
    /// The output variable (hygienic).
    pub out: &'a Ident,
}

/// Whether a body calls `emit!` anywhere.
pub fn emits(body: &TokenStream) -> bool {
    let mut prev_emit = false;
    for tt in body.clone() {
        match &tt {
            TokenTree::Ident(i) => prev_emit = i == "emit",
            TokenTree::Punct(p) if p.as_char() == '!' && prev_emit => return true,
            TokenTree::Group(g) if emits(&g.stream()) => return true,
            _ => prev_emit = false,
        }
    }
    false
}

/// The body with `emit!`/`child!` replaced.
pub fn rewrite(cx: &Ctxt, scope: &Scope<'_>, body: TokenStream) -> TokenStream {
    let tokens: Vec<TokenTree> = body.into_iter().collect();
    let mut out = Vec::with_capacity(tokens.len());
    let mut i = 0;
    while i < tokens.len() {
        if let (TokenTree::Ident(name), Some(TokenTree::Punct(bang)), Some(TokenTree::Group(args))) =
            (&tokens[i], tokens.get(i + 1), tokens.get(i + 2))
            && bang.as_char() == '!'
            && (name == "emit" || name == "child" || name == "expressed")
        {
            out.extend(call(cx, scope, name, args));
            i += 3;
            continue;
        }
        match &tokens[i] {
            TokenTree::Group(g) => {
                let mut ng = Group::new(g.delimiter(), rewrite(cx, scope, g.stream()));
                ng.set_span(g.span());
                out.push(TokenTree::Group(ng));
            }
            t => out.push(t.clone()),
        }
        i += 1;
    }
    out.into_iter().collect()
}

/// `emit!(shape, transform)`, `child!(slot, state)` or `expressed!(slot)`;
/// a slot is `name` or `name[index]` for a slot array.
fn call(cx: &Ctxt, scope: &Scope<'_>, name: &Ident, args: &Group) -> TokenStream {
    let what = match name.to_string().as_str() {
        "emit" => "emit!(shape, transform)",
        "child" => "child!(slot, state)",
        _ => "expressed!(slot)",
    };
    let has_value = name != "expressed";
    let parsed = (|input: ParseStream| {
        let id: Ident = input.parse()?;
        let index = if input.peek(syn::token::Bracket) {
            let inner;
            syn::bracketed!(inner in input);
            Some(inner.parse::<Expr>()?)
        } else {
            None
        };
        let value = if has_value {
            input.parse::<Token![,]>()?;
            Some(input.parse::<Expr>()?)
        } else {
            None
        };
        input.parse::<Option<Token![,]>>()?;
        Ok((id, index, value))
    })
    .parse2(args.stream());
    let (id, index, value) = match parsed {
        Ok(x) => x,
        Err(e) => {
            cx.error(e.span(), format!("expected `{what}`: {e}"));
            return TokenStream::new();
        }
    };
    let krate = scope.krate;
    let out = scope.out;
    let span = args.span();
    let label = id.to_string();
    if name == "emit" {
        let Some(k) = scope.shapes.iter().position(|s| *s == id) else {
            cx.error(
                id.span(),
                format!("unknown shape `{id}`: declare it in `shapes: [...]`"),
            );
            return TokenStream::new();
        };
        if let Some(i) = &index {
            cx.error(i.span(), "shapes are not indexed");
        }
        let k = k as u16;
        return quote_spanned!(span=> #krate::express::NodeOut::emit_shape(#out, #k, #label, #value));
    }
    let Some(j) = scope.slots.iter().position(|s| s.name == id) else {
        cx.error(
            id.span(),
            format!("node `{}` has no slot `{id}`", scope.node),
        );
        return TokenStream::new();
    };
    let base: usize = scope.slots[..j].iter().map(|s| s.len()).sum();
    let slot = &scope.slots[j];
    let slot_ref = match (&slot.count, &index) {
        (None, None) => {
            quote_spanned!(span=> #krate::express::SlotRef { index: #base, name: #label, element: 0 })
        }
        (Some(_), Some(i)) => {
            let n = slot.len();
            let k = hidden("__sg_k");
            let msg = format!("slot index {{}} is out of range for `{label}[{n}]`");
            quote_spanned!(span=> {
                let #k: usize = #i;
                ::core::assert!(#k < #n, #msg, #k);
                #krate::express::SlotRef { index: #base + #k, name: #label, element: #k }
            })
        }
        (None, Some(i)) => {
            cx.error(i.span(), format!("slot `{id}` is not an array"));
            return TokenStream::new();
        }
        (Some(_), None) => {
            cx.error(
                id.span(),
                format!("slot `{id}` is an array: write `{id}[index]`"),
            );
            return TokenStream::new();
        }
    };
    match value {
        Some(v) => {
            quote_spanned!(span=> #krate::express::NodeOut::express_child(#out, #slot_ref, #v))
        }
        None => quote_spanned!(span=> #krate::express::NodeOut::is_expressed(#out, #slot_ref)),
    }
}

/// A hygienic identifier for generated code.
pub fn hidden(name: &str) -> Ident {
    Ident::new(name, Span::mixed_site())
}
