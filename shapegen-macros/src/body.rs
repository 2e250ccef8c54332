//! A node body's pseudo-macros: `emit!(shape, transform)`,
//! `child!(slot, state)`, `expressed!(slot)` and
//! `split!(state, axis, [slot: size, ..])`.
//!
//! The body is ordinary Rust. [`calls`] finds the pseudo-macros for the
//! checks; after the checks pass, [`rewrite`] replaces each by a call on the
//! node's output (`NodeOut`) with the shape or slot resolved to a constant
//! index. Every other token keeps its span, so type errors point into the
//! user's body.

use proc_macro2::{Group, Ident, Span, TokenStream, TokenTree};
use quote::{quote, quote_spanned};
use syn::parse::{ParseStream, Parser};
use syn::spanned::Spanned;
use syn::{Expr, Path, Token};

use crate::ast::Slot;
use crate::ctxt::Ctxt;
use crate::eval;

/// Which pseudo-macro a call is.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum CallKind {
    Emit,
    Child,
    Expressed,
    /// A `split!`: `id` is its axis, `value` the state split.
    Split,
    /// One named part of a `split!`: checked as a slot, as `child!` is.
    Part,
}

impl CallKind {
    fn from_ident(i: &Ident) -> Option<Self> {
        Some(match i.to_string().as_str() {
            "emit" => Self::Emit,
            "child" => Self::Child,
            "expressed" => Self::Expressed,
            "split" => Self::Split,
            _ => return None,
        })
    }

    fn usage(self) -> &'static str {
        match self {
            Self::Emit => "emit!(shape, transform)",
            Self::Child => "child!(slot, state)",
            Self::Expressed => "expressed!(slot)",
            Self::Split => "split!(state, axis, [slot: size, ..])",
            Self::Part => "slot: size",
        }
    }
}

/// One pseudo-macro call as written.
pub struct Call {
    pub kind: CallKind,
    /// The shape or slot named.
    pub id: Ident,
    /// `[index]` after a slot array's name.
    pub index: Option<Expr>,
    /// The transform (`emit!`) or state (`child!`).
    pub value: Option<Expr>,
    /// The parenthesized arguments' span.
    pub span: Span,
}

impl Call {
    /// The constant array index, if the index is a number literal.
    pub fn literal_index(&self) -> Option<usize> {
        self.index.as_ref().and_then(eval::integer)
    }
}

/// Whether `tokens` at `i` start a pseudo-macro call: `name ! (args)`.
fn call_at(tokens: &[TokenTree], i: usize) -> Option<(CallKind, &Group)> {
    if let (TokenTree::Ident(name), Some(TokenTree::Punct(bang)), Some(TokenTree::Group(args))) =
        (&tokens[i], tokens.get(i + 1), tokens.get(i + 2))
        && bang.as_char() == '!'
    {
        return CallKind::from_ident(name).map(|k| (k, args));
    }
    None
}

/// How long one part of a `split!` is, as written.
pub enum PartSize {
    /// `repeat(len)`.
    Repeat(Expr),
    /// `rel(len)`.
    Relative(Expr),
    /// `abs(len)` or any other expression.
    Absolute(Expr),
}

/// One entry of a `split!`: the slot it schedules (`None` for `_`, a gap).
pub struct Part {
    pub slot: Option<(Ident, Option<Expr>)>,
    pub size: PartSize,
}

/// A parsed `split!(state, axis, [entries])`.
pub struct SplitCall {
    pub state: Expr,
    pub axis: Ident,
    pub parts: Vec<Part>,
}

/// The axes a split may name, as written and as `Axis` variants.
pub const AXES: [(&str, &str); 3] = [("x", "X"), ("y", "Y"), ("z", "Z")];

impl PartSize {
    fn parse(e: Expr) -> Self {
        if let Expr::Call(c) = &e
            && let Expr::Path(p) = &*c.func
            && c.args.len() == 1
            && let Some(f) = p.path.get_ident()
        {
            let arg = c.args[0].clone();
            match f.to_string().as_str() {
                "repeat" => return Self::Repeat(arg),
                "rel" => return Self::Relative(arg),
                "abs" => return Self::Absolute(arg),
                _ => {}
            }
        }
        Self::Absolute(e)
    }
}

/// Parses a `split!`'s arguments.
pub fn parse_split(args: &Group) -> syn::Result<SplitCall> {
    (|input: ParseStream| {
        let state: Expr = input.parse()?;
        input.parse::<Token![,]>()?;
        let axis: Ident = input.parse()?;
        if !AXES.iter().any(|(a, _)| axis == a) {
            return Err(syn::Error::new(
                axis.span(),
                format!("unknown axis `{axis}`: a split cuts along `x`, `y` or `z`"),
            ));
        }
        input.parse::<Token![,]>()?;
        let inner;
        syn::bracketed!(inner in input);
        let mut parts = Vec::new();
        while !inner.is_empty() {
            let slot = if inner.peek(Token![_]) {
                inner.parse::<Token![_]>()?;
                None
            } else {
                let id: Ident = inner.parse()?;
                let index = if inner.peek(syn::token::Bracket) {
                    let i;
                    syn::bracketed!(i in inner);
                    Some(i.parse::<Expr>()?)
                } else {
                    None
                };
                Some((id, index))
            };
            inner.parse::<Token![:]>()?;
            let size = PartSize::parse(inner.parse()?);
            parts.push(Part { slot, size });
            if inner.is_empty() {
                break;
            }
            inner.parse::<Token![,]>()?;
        }
        input.parse::<Option<Token![,]>>()?;
        Ok(SplitCall { state, axis, parts })
    })
    .parse2(args.stream())
    .map_err(|e| {
        syn::Error::new(
            e.span(),
            format!(
                "expected `{}` (sizes: a length, `rel(len)` or `repeat(len)`; `_` for a gap): {e}",
                CallKind::Split.usage()
            ),
        )
    })
}

/// The axis variant (`X`, `Y`, `Z`) of the body's `split!`, if it has one.
pub fn split_axis(body: &TokenStream) -> Option<Ident> {
    let mut found = Vec::new();
    collect(&mut |_| {}, body, &mut found);
    let c = found.iter().find(|c| c.kind == CallKind::Split)?;
    let (_, variant) = AXES.iter().find(|(a, _)| c.id == a)?;
    Some(Ident::new(variant, c.id.span()))
}

/// Parses one call's arguments.
pub fn parse_call(kind: CallKind, args: &Group) -> syn::Result<Call> {
    let has_value = kind != CallKind::Expressed;
    (|input: ParseStream| {
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
        Ok(Call {
            kind,
            id,
            index,
            value,
            span: args.span(),
        })
    })
    .parse2(args.stream())
    .map_err(|e| syn::Error::new(e.span(), format!("expected `{}`: {e}", kind.usage())))
}

/// Every pseudo-macro call in `body`, in token order; a malformed one is
/// reported in `cx` and left out.
pub fn calls(cx: &Ctxt, body: &TokenStream) -> Vec<Call> {
    let mut found = Vec::new();
    collect(&mut |e| cx.syn_error(e), body, &mut found);
    found
}

/// For a body that passed the checks: a compile-time assertion for each
/// constant index into a slot array whose length is a constant expression
/// (module-level, so `cargo check` evaluates it too).
pub fn index_assertions(slots: &[Slot], body: &TokenStream) -> TokenStream {
    let mut found = Vec::new();
    collect(&mut |_| {}, body, &mut found);
    let asserts = found.iter().filter_map(|c| {
        let k = c.literal_index()?;
        let slot = slots.iter().find(|s| s.name == c.id)?;
        let len = slot
            .count
            .as_ref()
            .filter(|_| slot.literal_len().is_none())?;
        let msg = format!(
            "slot index {k} is out of range for the slot array `{}`",
            c.id
        );
        let span = c.index.as_ref().map_or(c.span, Spanned::span);
        Some(quote_spanned!(span=> const _: () = ::core::assert!(#k < ::core::convert::identity::<usize>(#len), #msg);))
    });
    quote!(#(#asserts)*)
}

fn collect(report: &mut dyn FnMut(syn::Error), body: &TokenStream, found: &mut Vec<Call>) {
    let tokens: Vec<TokenTree> = body.clone().into_iter().collect();
    let mut i = 0;
    while i < tokens.len() {
        if let Some((kind, args)) = call_at(&tokens, i) {
            if kind == CallKind::Split {
                match parse_split(args) {
                    Ok(c) => {
                        let state = &c.state;
                        collect(report, &quote!(#state), found);
                        for p in &c.parts {
                            if let Some((id, index)) = &p.slot {
                                found.push(Call {
                                    kind: CallKind::Part,
                                    id: id.clone(),
                                    index: index.clone(),
                                    value: None,
                                    span: id.span(),
                                });
                            }
                        }
                        found.push(Call {
                            kind,
                            id: c.axis,
                            index: None,
                            value: Some(c.state),
                            span: args.span(),
                        });
                    }
                    Err(e) => report(e),
                }
                i += 3;
                continue;
            }
            match parse_call(kind, args) {
                Ok(c) => {
                    // Arguments may hold calls too (`child!(a, f(expressed!(b)))`).
                    if let Some(v) = &c.value {
                        collect(report, &quote!(#v), found);
                    }
                    found.push(c);
                }
                Err(e) => report(e),
            }
            i += 3;
            continue;
        }
        if let TokenTree::Group(g) = &tokens[i] {
            collect(report, &g.stream(), found);
        }
        i += 1;
    }
}

/// What the rewriting needs to know about one node declaration.
pub struct Scope<'a> {
    pub krate: &'a Path,
    pub shapes: &'a [Ident],
    pub slots: &'a [Slot],
    /// The state type (children's values are bound to it, so a mismatch is
    /// reported at the user's expression).
    pub state_ty: &'a TokenStream,
    /// The output variable (hygienic).
    pub out: &'a Ident,
}

/// The body with `emit!`/`child!`/`expressed!` replaced. A call that does
/// not resolve (only after errors, in the [`fallback`](crate::fallback))
/// becomes `unreachable!()`, which has every type, so the rest of the body
/// is still type-checked without follow-on errors.
pub fn rewrite(scope: &Scope<'_>, body: TokenStream) -> TokenStream {
    let tokens: Vec<TokenTree> = body.into_iter().collect();
    let mut out = Vec::with_capacity(tokens.len());
    let mut i = 0;
    while i < tokens.len() {
        if let Some((kind, args)) = call_at(&tokens, i) {
            let call = if kind == CallKind::Split {
                parse_split(args)
                    .ok()
                    .and_then(|c| expand_split(scope, c, args.span()))
            } else {
                parse_call(kind, args)
                    .ok()
                    .and_then(|c| expand_call(scope, c))
            };
            out.extend(call.unwrap_or_else(|| quote!(::core::unreachable!())));
            i += 3;
            continue;
        }
        match &tokens[i] {
            TokenTree::Group(g) => {
                let mut ng = Group::new(g.delimiter(), rewrite(scope, g.stream()));
                ng.set_span(g.span());
                out.push(TokenTree::Group(ng));
            }
            t => out.push(t.clone()),
        }
        i += 1;
    }
    out.into_iter().collect()
}

/// A `split!` as a loop over the scope's parts, each entry's part
/// scheduling its slot as `child!` would (gaps schedule nothing).
fn expand_split(scope: &Scope<'_>, c: SplitCall, span: Span) -> Option<TokenStream> {
    let krate = scope.krate;
    let (_, variant) = AXES.iter().find(|(a, _)| c.axis == a)?;
    let variant = Ident::new(variant, c.axis.span());
    let (entry, part, parent) = (
        hidden("__sg_entry"),
        hidden("__sg_part"),
        hidden("__sg_parent"),
    );
    let mut sizes = Vec::new();
    let mut arms = Vec::new();
    for (k, p) in c.parts.into_iter().enumerate() {
        let (ctor, len) = match p.size {
            PartSize::Repeat(e) => (quote!(Repeat), e),
            PartSize::Relative(e) => (quote!(Relative), e),
            PartSize::Absolute(e) => (quote!(Absolute), e),
        };
        let len = rewrite(scope, quote!(#len));
        let ty = respan(quote!(f32), len.span());
        let var = hidden("__sg_len");
        sizes.push(quote_spanned!(len.span()=> {
            let #var: #ty = #len;
            #krate::express::SplitSize::#ctor(#var)
        }));
        if let Some((id, index)) = p.slot {
            let call = Call {
                kind: CallKind::Child,
                span: id.span(),
                id,
                index,
                value: Some(syn::parse_quote!(#part)),
            };
            let child = expand_call(scope, call)?;
            arms.push(quote!(#k => { #child; }));
        }
    }
    let state = rewrite(scope, {
        let s = &c.state;
        quote!(#s)
    });
    let state_ty = respan(scope.state_ty.clone(), state.span());
    let out = scope.out;
    Some(quote_spanned!(span=> {
        let #parent: #state_ty = #state;
        #krate::express::NodeOut::split_scope(#out, #krate::graph::Axis::#variant, &#parent);
        for (#entry, #part) in #krate::express::Scope::split(
            &#parent,
            #krate::graph::Axis::#variant,
            &[#(#sizes),*],
        ) {
            match #entry {
                #(#arms)*
                _ => {}
            }
        }
    }))
}

fn expand_call(scope: &Scope<'_>, c: Call) -> Option<TokenStream> {
    let (krate, out, span) = (scope.krate, scope.out, c.span);
    let label = c.id.to_string();
    // Values are rewritten too: they may hold `expressed!`.
    let value = c.value.as_ref().map(|v| rewrite(scope, quote!(#v)));
    if c.kind == CallKind::Emit {
        let k = scope.shapes.iter().position(|s| *s == c.id)?;
        let k = k as u16;
        let transform = hidden("__sg_transform");
        let v = value.unwrap_or_default();
        let ty = respan(quote!(#krate::glam::Affine3A), v.span());
        return Some(quote_spanned!(span=> {
            let #transform: #ty = #v;
            #krate::express::NodeOut::emit_shape(#out, #k, #label, #transform)
        }));
    }
    let j = scope.slots.iter().position(|s| s.name == c.id)?;
    let base = slots_len(&scope.slots[..j]);
    let slot = &scope.slots[j];
    let slot_ref = match (&slot.count, &c.index) {
        (None, None) => {
            quote_spanned!(span=> #krate::express::SlotRef { index: #base, name: #label, element: 0 })
        }
        (Some(len), Some(i)) => {
            let len = quote!(#len);
            match (c.literal_index(), slot.literal_len()) {
                // A constant index into an array of literal length: checked by the macro.
                (Some(k), Some(_)) => quote_spanned!(span=>
                    #krate::express::SlotRef { index: #base + #k, name: #label, element: #k }),
                // A constant index into an array of constant length: checked by
                // the compiler (`index_assertions`).
                (Some(k), None) => quote_spanned!(span=>
                    #krate::express::SlotRef { index: #base + #k, name: #label, element: #k }),
                // A computed index: checked at run time.
                (None, _) => {
                    let k = hidden("__sg_k");
                    let msg = format!("slot index {{}} is out of range for `{label}[{{}}]`");
                    quote_spanned!(span=> {
                        let #k: usize = #i;
                        ::core::assert!(#k < (#len), #msg, #k, #len);
                        #krate::express::SlotRef { index: #base + #k, name: #label, element: #k }
                    })
                }
            }
        }
        _ => return None,
    };
    Some(match value {
        Some(v) => {
            let state = hidden("__sg_child");
            let ty = respan(scope.state_ty.clone(), v.span());
            quote_spanned!(span=> {
                let #state: #ty = #v;
                #krate::express::NodeOut::express_child(#out, #slot_ref, #state)
            })
        }
        None => quote_spanned!(span=> #krate::express::NodeOut::is_expressed(#out, #slot_ref)),
    })
}

/// The number of graph slots `slots` stand for, as a constant expression
/// (a literal when every length is one).
pub fn slots_len(slots: &[Slot]) -> TokenStream {
    slots_len_plus(slots, 0)
}

/// [`slots_len`] plus `extra`, folded into one literal where possible.
pub fn slots_len_plus(slots: &[Slot], extra: usize) -> TokenStream {
    let known: usize = extra + slots.iter().filter_map(Slot::literal_len).sum::<usize>();
    let exprs = slots
        .iter()
        .filter(|s| s.literal_len().is_none())
        .filter_map(|s| s.count.as_ref());
    quote!(#known #(+ ::core::convert::identity::<usize>(#exprs))*)
}

/// Whether a body calls `emit!` anywhere.
pub fn emits(calls: &[Call]) -> bool {
    calls.iter().any(|c| c.kind == CallKind::Emit)
}

/// `tokens` with every span set to `span`: a type written for the user's
/// value, so that a mismatch is reported at the value alone.
fn respan(tokens: TokenStream, span: Span) -> TokenStream {
    tokens
        .into_iter()
        .map(|mut t| {
            if let TokenTree::Group(g) = &t {
                let mut ng = Group::new(g.delimiter(), respan(g.stream(), span));
                ng.set_span(span);
                t = TokenTree::Group(ng);
            } else {
                t.set_span(span);
            }
            t
        })
        .collect()
}

/// A hygienic identifier for generated code.
pub fn hidden(name: &str) -> Ident {
    Ident::new(name, Span::mixed_site())
}
