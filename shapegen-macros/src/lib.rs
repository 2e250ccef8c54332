//! The `generator!` procedural macro of [shapegen](https://crates.io/crates/shapegen).
//!
//! This crate is a thin shim over a pipeline, one module per stage: `parse`
//! reads the input into the macro's own model (`ast`), `check` runs one
//! named rule per concern (`body` and `paths` look into node bodies; every
//! problem is collected in `ctxt` and reported at once), and only a clean
//! declaration reaches `expand`; after errors, `fallback` still emits the
//! type and its `Generator` impl so that only the real mistakes show. Use
//! the macro through `shapegen::generator!`, whose documentation describes
//! the syntax.

#![forbid(unsafe_code)]

mod ast;
mod body;
mod check;
mod ctxt;
mod eval;
mod expand;
mod fallback;
mod hint;
mod parse;
mod paths;

/// Declares a procedural generator: its graph, the state passed along its
/// edges, and the Rust code of each node's operation.
///
/// A declaration reads like the paper's generator graphs (Fig. 4a, 8): nodes
/// with typed, distributed parameters and child slots with the probability
/// that an uncontrolled generation produces them.
///
/// ```
/// use shapegen::prelude::*;
/// use shapegen::express::Instances;
///
/// generator! {
///     /// Towers of stacked floors, some with a balcony.
///     pub struct Towers;
///     shapes: [cube];                 // meshes the bodies may emit
///     start: Lot;                     // the root of every derivation tree
///     limits: { max_depth: 30, min_len: 2, max_len: 200 };   // optional
///
///     node Lot {
///         params { width: f32 = uniform(1.0, 3.0) }
///         slots { ground: Floor = 1.0 }
///         |mut scope| {
///             scope.set_size([width, 1.0, width].into());
///             child!(ground, scope);
///         }
///     }
///
///     node Floor emits {
///         params {
///             height: f32 = uniform(0.5, 1.5),
///             shrink: vec2 = uniform([0.8, 0.8], [1.0, 1.0]),
///             turn: f32 = uniform(0, 45),        // degrees
///         }
///         slots { up: Floor = 0.8, balcony: Floor = 1 / 4 }
///         |scope| {
///             let mut s = scope;
///             s.resize([shrink.x, 1.0, shrink.y].into());
///             s.size.y = height;
///             s.move_y(0.5 * height);
///             emit!(cube, s.instance());
///             s.move_y(0.5 * height);
///             if !expressed!(balcony) {
///                 s.rotate_y(turn.to_radians());
///             }
///             child!(up, s);
///             child!(balcony, s.translated([0.5 * s.size.x, -0.5 * height, 0.0].into()));
///         }
///     }
/// }
///
/// let graph = Towers.graph();
/// let mut rng = shapegen::rng::stream(7, &[]);
/// let c = random_individual(graph, &InitLength::Around { l0: 12 }, &mut rng)?;
/// let mut model = Instances::default();
/// Towers.express(&c, &mut model);
/// assert_eq!(model.0.len(), c.len() - 1); // every Floor gene emits one box
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Syntax
///
/// - `pub struct Name;`: the generator's type (a unit struct implementing
///   `Generator`), with any doc comments and visibility.
/// - `shapes: [a, b];`: the shapes bodies emit; shape `i` has id `i`.
/// - `start: Node;`: the start node.
/// - `limits: { max_depth: N, min_len: N, max_len: N };` (optional, each
///   key optional): bounds on derivation trees; lengths satisfy `min_len <= L < max_len`.
/// - `state: Type = axiom;` (optional): the state passed along edges; by
///   default `Scope` (an oriented box) starting as `Scope::UNIT`.
/// - `crate: path;` (optional): where the runtime lives (default `::shapegen`;
///   `::shapegen_core` when only the core crate is a dependency).
/// - `node Name [emits] { params { ... } slots { ... } |state| { body } }`:
///   `emits` marks nodes that emit geometry (required if the body uses `emit!`).
///   - parameters: `name: f32 | vec2 | vec3 | int | choice = distribution`, with
///     `uniform(lo, hi)`, `normal(mean, std)`, `truncated_normal(mean, std, lo, hi)`,
///     `constant(v)` for floats (vector bounds as `[a, b, c]`, `[x; 3]` or one
///     number for every component), `uniform(lo, hi)` (inclusive) or `constant(v)`
///     for `int`, and `choice([w0, w1, ...])` (weights) for `choice`. In the
///     body they are locals of type `f32`, `Vec2`, `Vec3`, `i32`, `u32`.
///   - slots: `name: Target = p`, or `name[N]: Target = p` for `N` slots
///     `name[0]..name[N-1]`. A probability made of number literals is
///     evaluated as a real number (`1 / 3` is one third).
///   - the body is ordinary Rust with the incoming state bound by the closure
///     pattern, plus `emit!(shape, transform)` (an `Affine3A` placing the unit
///     mesh), `child!(slot, state)` (schedules the child if it is expressed;
///     `child!(name[i], state)` for arrays) and `expressed!(slot)` (whether the
///     child exists).
///
/// # What it generates
///
/// The type; a `static` `GraphSpec` (`Name::spec()`) and its checked `Graph`
/// (`Name::try_graph()`, `Generator::graph`); one monomorphic function per
/// node, whose parameters are read at offsets fixed at compile time; the
/// `Generator` implementation dispatching on node ids; and
/// `Name::interpreter()`, the same bodies run by the run-time interpreter
/// (parameters and slots looked up by name), for comparison.
///
/// # Errors
///
/// Every mistake the macro can see is reported at once, each with a span
/// on the offending tokens: unknown or unreachable nodes, duplicate node,
/// parameter, slot or shape names, probabilities outside [0, 1], inverted or
/// empty ranges and weights, missing or unknown start node, unknown shapes or
/// slots in `emit!`/`child!`, wrong distributions for a parameter type.
/// Type errors in a body point into the body.
#[proc_macro]
pub fn generator(input: proc_macro::TokenStream) -> proc_macro::TokenStream {
    expand::generator(input.into()).into()
}
