//! [`NodeOut`]: where a node body's `emit!`, `child!` and `expressed!` go.

use glam::Affine3A;

use super::Scope;
use super::sink::ShapeId;
use crate::graph::Axis;

/// A child slot as named in a node body: its index in the node, its declared
/// name, and for a slot array (`lots[100]`) the element.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SlotRef<'a> {
    /// Index of the slot among the node's slots.
    pub index: usize,
    /// The declared name (for an array, without the element).
    pub name: &'a str,
    /// The element of a slot array; 0 for a plain slot.
    pub element: usize,
}

/// The output side of one node's operation, as seen by a `generator!` body.
///
/// A body is compiled once, generic over `NodeOut`; the macro's specialized
/// path uses the constant indices, the [`Interpreter`](super::Interpreter)
/// looks shapes and slots up by name. Both receive both.
pub trait NodeOut<St> {
    /// Emits shape `id` (named `name`) placed by `transform`.
    fn emit_shape(&mut self, id: ShapeId, name: &str, transform: Affine3A);

    /// Passes `state` to the child in `slot`, if it is expressed.
    fn express_child(&mut self, slot: SlotRef<'_>, state: St);

    /// Whether the child in `slot` is expressed.
    fn is_expressed(&self, slot: SlotRef<'_>) -> bool;

    /// Announces that the node splits `scope` along `axis`: the children
    /// scheduled next are the parts (`split!` calls it; see
    /// [`ModelSink::split`](super::ModelSink::split)).
    fn split_scope(&mut self, axis: Axis, scope: &Scope);
}
