//! The macro's own model of a `generator!` declaration.

use proc_macro2::TokenStream;
use syn::{Attribute, Expr, Ident, Pat, Path, Type, Visibility};

/// The whole declaration.
pub struct Generator {
    pub attrs: Vec<Attribute>,
    pub vis: Visibility,
    pub name: Ident,
    /// Path of the crate holding the runtime (`::shapegen` unless `crate: path;`).
    pub krate: Path,
    pub shapes: Vec<Ident>,
    pub start: Option<Ident>,
    pub limits: Limits,
    /// The shape state type and its axiom, if not the default scope.
    pub state: Option<(Type, Expr)>,
    pub nodes: Vec<Node>,
}

#[derive(Default)]
pub struct Limits {
    pub max_depth: Option<Expr>,
    pub min_len: Option<Expr>,
    pub max_len: Option<Expr>,
}

pub struct Node {
    pub name: Ident,
    pub emits: bool,
    pub params: Vec<Param>,
    pub slots: Vec<Slot>,
    /// The state binding of the body closure (`|scope|`, `|mut s|`).
    pub binder: Pat,
    /// The body's tokens (a block).
    pub body: TokenStream,
}

pub struct Param {
    pub name: Ident,
    pub kind: Kind,
    pub dist: Ident,
    pub args: Vec<Expr>,
    /// The distribution call's tokens (`uniform(0, 1)`), for errors spanning it.
    pub call: TokenStream,
}

#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    F32,
    Vec2,
    Vec3,
    Int,
    Choice,
}

impl Kind {
    pub fn from_ident(i: &Ident) -> Option<Self> {
        Some(match i.to_string().as_str() {
            "f32" => Self::F32,
            "vec2" => Self::Vec2,
            "vec3" => Self::Vec3,
            "int" => Self::Int,
            "choice" => Self::Choice,
            _ => return None,
        })
    }

    /// Number of 32-bit words.
    pub fn words(self) -> usize {
        match self {
            Self::F32 | Self::Int | Self::Choice => 1,
            Self::Vec2 => 2,
            Self::Vec3 => 3,
        }
    }

    /// Number of `f32` components (0 for int and choice).
    pub fn components(self) -> usize {
        match self {
            Self::F32 => 1,
            Self::Vec2 => 2,
            Self::Vec3 => 3,
            Self::Int | Self::Choice => 0,
        }
    }
}

pub struct Slot {
    pub name: Ident,
    /// For a slot array `name[N]`: the literal `N`.
    pub count: Option<syn::LitInt>,
    pub target: Ident,
    pub p: Expr,
}

impl Slot {
    /// Number of graph slots this declaration stands for (0 if the count is malformed).
    pub fn len(&self) -> usize {
        match &self.count {
            None => 1,
            Some(n) => n.base10_parse().unwrap_or(0),
        }
    }
}
