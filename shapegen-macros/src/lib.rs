//! The `generator!` procedural macro of [shapegen](https://crates.io/crates/shapegen).
//!
//! This crate is a thin shim: the macro parses its input into the model of
//! [`ast`] ([`parse`]), checks it ([`check`], every problem reported at once
//! through [`ctxt`]), and generates code ([`expand`], [`body`]). Use it
//! through `shapegen::generator!`, whose documentation describes the syntax.

mod ast;
mod body;
mod check;
mod ctxt;
mod eval;
mod expand;
mod parse;

/// Declares a procedural generator. See `shapegen::generator!` for the syntax.
#[proc_macro]
pub fn generator(input: proc_macro::TokenStream) -> proc_macro::TokenStream {
    expand::generator(input.into()).into()
}
