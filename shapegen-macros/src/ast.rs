//! The macro's own model of a `generator!` declaration.

use proc_macro2::{Span, TokenStream};
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

impl Generator {
    /// Every graph node in id order: (its declaration, its index among the members).
    pub fn members(&self) -> impl Iterator<Item = (&Node, usize)> {
        self.nodes
            .iter()
            .flat_map(|n| (0..n.members.len()).map(move |m| (n, m)))
    }

    /// Number of graph nodes (a family counts once per member).
    pub fn node_count(&self) -> usize {
        self.nodes.iter().map(|n| n.members.len()).sum()
    }
}

#[derive(Default)]
pub struct Limits {
    pub max_depth: Option<Expr>,
    pub min_len: Option<Expr>,
    pub max_len: Option<Expr>,
}

/// One `node` declaration: a single node, or a family of nodes (`node b, n, m`)
/// that share one body and differ only in `each[...]` values.
pub struct Node {
    /// The graph nodes declared (one name for a single node).
    pub members: Vec<Ident>,
    pub emits: bool,
    pub consts: Vec<Const>,
    pub params: Vec<Param>,
    pub slots: Vec<Slot>,
    /// Semantic tags: one shared by every member, or `each[..]` one per member.
    pub tags: Vec<PerMember<Ident>>,
    /// The state binding of the body closure (`|scope|`, `|mut s|`).
    pub binder: Pat,
    /// The body's tokens (a brace-delimited group).
    pub body: TokenStream,
}

impl Node {
    /// The name the declaration goes by in messages and generated items: its first member.
    pub fn name(&self) -> &Ident {
        &self.members[0]
    }

    /// Whether this declares a family of several nodes.
    pub fn is_family(&self) -> bool {
        self.members.len() > 1
    }
}

/// A value that is either the same for every member of a node family or
/// given per member with `each[v0, v1, ...]`.
pub enum PerMember<T> {
    Shared(T),
    Each {
        /// The `each[...]` tokens, for errors.
        span: Span,
        values: Vec<T>,
    },
}

impl<T> PerMember<T> {
    /// The value for member `m` (the last one if `each` has too few; checked separately).
    pub fn get(&self, m: usize) -> &T {
        match self {
            Self::Shared(v) => v,
            Self::Each { values, .. } => &values[m.min(values.len() - 1)],
        }
    }

    /// Every distinct value written.
    pub fn all(&self) -> &[T] {
        match self {
            Self::Shared(v) => std::slice::from_ref(v),
            Self::Each { values, .. } => values,
        }
    }
}

/// A named constant of a node's body: `attach: f32 = 0.38` or `each[...]`.
pub struct Const {
    pub name: Ident,
    pub ty: Type,
    pub value: PerMember<Expr>,
}

pub struct Param {
    pub name: Ident,
    pub kind: Kind,
    pub dist: PerMember<DistCall>,
}

/// A distribution as written: `uniform(0, 1)`.
pub struct DistCall {
    pub dist: Ident,
    pub args: Vec<Expr>,
    /// The call's tokens (`uniform(0, 1)`), for errors spanning it.
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
    /// The keywords of parameter types, as written.
    pub const NAMES: [&'static str; 5] = ["f32", "vec2", "vec3", "int", "choice"];

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
    /// For a slot array `name[N]`: the length `N`, a literal or a constant expression.
    pub count: Option<Expr>,
    pub target: Ident,
    pub p: PerMember<Expr>,
}

impl Slot {
    /// The array length if it is a number literal; `None` for a constant
    /// expression (known only when the generated code compiles).
    pub fn literal_len(&self) -> Option<usize> {
        match &self.count {
            None => Some(1),
            Some(e) => crate::eval::integer(e),
        }
    }
}
