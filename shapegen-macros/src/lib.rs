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
/// that an uncontrolled generation produces them. Nodes that differ only in
/// numbers form a *family* sharing one body.
///
/// ```
/// use shapegen::prelude::*;
/// use shapegen::express::Instances;
///
/// /// Floors per tower side.
/// const SIDES: usize = 2;
///
/// generator! {
///     /// Towers of stacked floors, some with balconies and wings.
///     pub struct Towers;
///     shapes: [cube];                 // meshes the bodies may emit
///     start: Lot;                     // the root of every derivation tree
///     limits: { max_depth: 30, min_len: 2, max_len: 200 };   // optional
///
///     node Lot {
///         params {
///             width: f32 = uniform(1.0, 3.0),     // f32
///             storeys: int = uniform(1, 3),       // int: bounds inclusive
///             style: choice([3, 1]),              // choice: option i with weight w_i
///         }
///         slots { ground: Floor = 1.0, wings[SIDES]: East = 0.25 }
///         |mut scope| {
///             let _ = (storeys, style);
///             scope.set_size([width, 1.0, width].into());
///             child!(ground, scope);
///             for k in 0..SIDES {
///                 child!(wings[k], scope.translated([0.0, 0.0, k as f32].into()));
///             }
///         }
///     }
///
///     node Floor emits {
///         params {
///             height: f32 = normal(1.0, 0.2),
///             shrink: vec2 = uniform([0.8, 0.8], [1.0, 1.0]),              // vec2
///             tilt: vec3 = truncated_normal(0.0, 1.0, -2.0, [2.0, 0.0, 2.0]), // vec3
///             turn: f32 = constant(15),                                     // degrees
///         }
///         slots { up: Floor = 0.8, balcony: Floor = 1 / 4 }
///         |scope| {
///             let mut s = scope;
///             s.resize([shrink.x, 1.0, shrink.y].into());
///             s.size.y = height.abs();
///             s.move_y(0.5 * s.size.y);
///             emit!(cube, s.instance());
///             s.move_y(0.5 * s.size.y);
///             if !expressed!(balcony) {
///                 s.rotate_y((turn + tilt.y).to_radians());
///             }
///             child!(up, s);
///             child!(balcony, s.translated([0.5 * s.size.x, -0.5 * height, 0.0].into()));
///         }
///     }
///
///     /// A family: two wings with one body; `each[..]` gives a value per member.
///     node East, West emits {
///         consts { side: f32 = each[1.0, -1.0] }
///         params { depth: f32 = each[uniform(0.5, 1.0), uniform(0.2, 0.4)] }
///         slots { other: West = each[0.5, 0.0] }
///         |scope| {
///             let s = scope.translated([side * depth, 0.0, 0.0].into());
///             emit!(cube, s.instance());
///             child!(other, s);
///         }
///     }
/// }
///
/// let graph = Towers.graph();
/// assert_eq!(graph.spec().nodes.len(), 4); // Lot, Floor, East, West
/// let mut rng = shapegen::rng::stream(7, &[]);
/// let c = random_individual(graph, &InitLength::Around { l0: 12 }, &mut rng)?;
/// let mut model = Instances::default();
/// Towers.express(&c, &mut model);
/// assert_eq!(model.0.len(), c.len() - 1); // every gene but the lot emits one box
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
/// - `node Name [emits] { consts {..} params {..} slots {..} tags {..} |state| { body } }`,
///   sections optional and in any order. `emits` marks nodes that emit
///   geometry (required if the body uses `emit!`).
///   - parameters, locals of the body:
///
///     | type | Rust type | distributions |
///     |---|---|---|
///     | `f32` | `f32` | `uniform(lo, hi)`, `normal(mean, std)`, `truncated_normal(mean, std, lo, hi)`, `constant(v)` |
///     | `vec2`, `vec3` | `Vec2`, `Vec3` | the same, per component: `[a, b, c]`, `[x; 3]` or one number for all |
///     | `int` | `i32` | `uniform(lo, hi)` (inclusive, whole numbers), `constant(v)` |
///     | `choice` | `u32` | `choice([w0, w1, ..])`: option `i` with probability `w_i / Σ w` |
///
///     written `name: type = distribution`; a choice also as `name: choice([w0, w1])`.
///   - slots: `name: Target = p`, or `name[N]: Target = p` for `N` slots
///     `name[0]..name[N-1]`; `N` is a literal or a constant expression
///     (`lots[GRID * GRID]`). A probability made of number literals is
///     evaluated as a real number (`1 / 3` is one third).
///   - constants: `name: Type = value`, locals of the body like parameters
///     but not part of the genome.
///   - tags: `tags { branching, segment }`, words naming what the node makes;
///     nodes of two generators that share a tag correspond in a design
///     transformation (`shapegen::transform`). Not part of the genome.
///   - the body is ordinary Rust with the incoming state bound by the closure
///     pattern, plus `emit!(shape, transform)` (an `Affine3A` placing the unit
///     mesh), `child!(slot, state)` (schedules the child if it is expressed;
///     `child!(name[i], state)` for arrays) and `expressed!(slot)` (whether the
///     child exists).
///   - a split rule (CGA's `split`, for a `Scope` state):
///     `split!(scope, y, [ground: 4.0, floor: repeat(3.5), _: rel(1.0), ledge: 0.5])`
///     cuts the scope along `x`, `y` or `z` into parts that partition it, in
///     order: a length is absolute (`abs(len)` also), `rel(len)` stretches
///     to share what absolute parts leave, `repeat(len)` makes as many copies
///     of about `len` as fill it (see `Scope::split`). Each part schedules its
///     slot as `child!` would, so a repeated part expresses one subtree once
///     per copy; `_` leaves a gap. A body has at most one `split!` and then
///     no `child!`: the node is a *split node* (`NodeSpec::split`), whose
///     parts design transformations merge as strings.
/// - `node A, B, C [emits] { .. }`: a *family*, one graph node per member (ids
///   in the order written) sharing the sections and the body. Any parameter
///   distribution, slot probability, constant or tag may be given per member as
///   `each[for_a, for_b, for_c]`.
///
/// A declaration can be produced by `macro_rules!`, passing bodies as `block`
/// fragments or token trees.
///
/// # What it generates
///
/// The type; its `GraphSpec` (`Name::spec()`, built once) and checked `Graph`
/// (`Name::try_graph()`, `Generator::graph`); one monomorphic function per
/// node declaration (a family's members call it with their constants), whose
/// parameters are read at offsets fixed at compile time; the `Generator`
/// implementation dispatching on node ids; and `Name::interpreter()`, the
/// same bodies run by the run-time interpreter (parameters and slots looked
/// up by name), for comparison.
///
/// # Errors
///
/// Every mistake the macro can see is reported at once, each with a span
/// on the offending tokens, and a misspelled keyword, type, distribution or
/// name gets a "did you mean" hint: unknown or unreachable nodes, duplicate
/// node, parameter, constant, slot or shape names, probabilities outside
/// [0, 1], inverted or empty ranges and weights, `int` bounds that are not
/// whole numbers, a missing or unknown start node, unknown shapes or slots in
/// `emit!`/`child!`, a constant slot index out of range, a slot scheduled
/// twice on one path of a body, wrong distributions for a parameter type,
/// `each[..]` with a value count other than the family's size, a `split!`
/// along an unknown axis, a second `split!` or a `child!` beside one. After an
/// error the type and its `Generator` implementation are still emitted, so
/// code using the generator reports nothing more. Type errors in a body,
/// including a `child!` state or `emit!` transform of the wrong type, point
/// into the body; core's limits (`graph::MAX_SLOTS` per node,
/// `graph::MAX_NODES`) are checked by the compiler.
#[proc_macro]
pub fn generator(input: proc_macro::TokenStream) -> proc_macro::TokenStream {
    expand::generator(input.into()).into()
}
