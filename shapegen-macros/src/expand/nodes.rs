//! One monomorphic function per node declaration (a family shares one,
//! taking its members' constants as arguments), the specialized dispatch arm
//! of each graph node, and the interpreter's rule for each.

use proc_macro2::{Ident, TokenStream};
use quote::{format_ident, quote};
use syn::Path;

use crate::ast::{Generator, Kind, Node};
use crate::body::{self, hidden};

/// The hygienic names generated code shares.
pub struct Names {
    /// The node's output (`NodeOut`).
    pub out: Ident,
    /// The incoming state.
    pub state: Ident,
    /// The chromosome's words.
    pub words: Ident,
    /// The position of the gene being expressed.
    pub pos: Ident,
    /// The interpreter's parameter lookup.
    pub input: Ident,
}

impl Names {
    pub fn new() -> Self {
        Self {
            out: hidden("__sg_out"),
            state: hidden("__sg_state"),
            words: hidden("__sg_words"),
            pos: hidden("__sg_pos"),
            input: hidden("__sg_input"),
        }
    }
}

/// The generated pieces, for [`generator_impl`](super::generator_impl).
pub struct Nodes {
    pub names: Names,
    /// The body functions (inherent associated functions of the type).
    pub bodies: Vec<TokenStream>,
    /// `id => Self::body(params read at constant offsets, ...)`, one per graph node.
    pub direct_arms: Vec<TokenStream>,
    /// `.rule("name", |input, state, out| ...)`, one per graph node.
    pub rules: Vec<TokenStream>,
}

pub fn expand(g: &Generator) -> Nodes {
    let names = Names::new();
    let (state_ty, _) = super::state(g);
    let mut nodes = Nodes {
        bodies: Vec::new(),
        direct_arms: Vec::new(),
        rules: Vec::new(),
        names,
    };
    let mut id: u16 = 0;
    for n in &g.nodes {
        let fn_name = format_ident!("__sg_node_{}", n.name());
        nodes
            .bodies
            .push(body_fn(g, n, &fn_name, &state_ty, &nodes.names));
        for m in 0..n.members.len() {
            let consts: Vec<TokenStream> = n
                .consts
                .iter()
                .map(|c| {
                    let v = c.value.get(m);
                    quote!(#v)
                })
                .collect();
            nodes
                .direct_arms
                .push(direct_arm(&g.krate, n, id, &fn_name, &consts, &nodes.names));
            nodes
                .rules
                .push(rule(n, m, &fn_name, &consts, &nodes.names));
            id += 1;
        }
    }
    nodes
}

/// The node's body as a function generic over its output: constants, then
/// parameters, then the state. A name declared twice (an error already
/// reported) is passed once.
pub fn body_fn(
    g: &Generator,
    n: &Node,
    fn_name: &Ident,
    state_ty: &TokenStream,
    names: &Names,
) -> TokenStream {
    let krate = &g.krate;
    let Names { out, state, .. } = names;
    let scope = body::Scope {
        krate,
        shapes: &g.shapes,
        slots: &n.slots,
        state_ty,
        out,
    };
    let user_body = body::rewrite(&scope, n.body.clone());
    let binder = &n.binder;
    let mut seen = std::collections::HashSet::new();
    let consts: Vec<_> = n
        .consts
        .iter()
        .filter(|c| seen.insert(c.name.to_string()))
        .collect();
    let params: Vec<_> = n
        .params
        .iter()
        .filter(|p| seen.insert(p.name.to_string()))
        .collect();
    let const_names = consts.iter().map(|c| &c.name);
    let const_types = consts.iter().map(|c| &c.ty);
    let param_names = params.iter().map(|p| &p.name);
    let param_types = params.iter().map(|p| rust_type(krate, p.kind));
    quote! {
        #[inline(always)]
        #[allow(unused_variables, unused_mut, non_snake_case, clippy::all)]
        fn #fn_name<__SgOut: #krate::express::NodeOut<#state_ty>>(
            #(#const_names: #const_types,)*
            #(#param_names: #param_types,)*
            #state: #state_ty,
            #out: &mut __SgOut,
        ) {
            let #binder: #state_ty = #state;
            #user_body
        }
    }
}

/// The specialized path: parameters read at offsets fixed at compile time.
fn direct_arm(
    krate: &Path,
    n: &Node,
    id: u16,
    fn_name: &Ident,
    consts: &[TokenStream],
    names: &Names,
) -> TokenStream {
    let Names {
        out,
        state,
        words,
        pos,
        ..
    } = names;
    let mut offset = 0;
    let reads = n.params.iter().map(|p| {
        let at = offset;
        offset += p.kind.words();
        read_param(krate, n, p.kind, words, pos, at)
    });
    quote!(#id => Self::#fn_name(#(#consts,)* #(#reads,)* #state, &mut #out),)
}

/// The interpreter's rule for member `m`: parameters looked up by name.
fn rule(n: &Node, m: usize, fn_name: &Ident, consts: &[TokenStream], names: &Names) -> TokenStream {
    let Names {
        out, state, input, ..
    } = names;
    let lookups = n.params.iter().map(|p| {
        let pn = p.name.to_string();
        let method = match p.kind {
            Kind::F32 => quote!(f32),
            Kind::Vec2 => quote!(vec2),
            Kind::Vec3 => quote!(vec3),
            Kind::Int => quote!(int),
            Kind::Choice => quote!(choice),
        };
        quote!(#input.#method(#pn))
    });
    let name = n.members[m].to_string();
    quote!(.rule(#name, |#input, #state, #out| Self::#fn_name(#(#consts,)* #(#lookups,)* #state, #out)))
}

/// `words[pos + HEADER + slots + at ..]` read as the parameter's Rust type.
fn read_param(
    krate: &Path,
    n: &Node,
    kind: Kind,
    words: &Ident,
    pos: &Ident,
    at: usize,
) -> TokenStream {
    let w = |k: usize| {
        let at = body::slots_len_plus(&n.slots, at + k);
        quote!(#words[#pos + #krate::__private::HEADER_WORDS + #at])
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

/// The Rust type of a parameter in the body.
fn rust_type(krate: &Path, kind: Kind) -> TokenStream {
    match kind {
        Kind::F32 => quote!(f32),
        Kind::Vec2 => quote!(#krate::glam::Vec2),
        Kind::Vec3 => quote!(#krate::glam::Vec3),
        Kind::Int => quote!(i32),
        Kind::Choice => quote!(u32),
    }
}
