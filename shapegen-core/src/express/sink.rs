//! Where expressed geometry goes.

use glam::Affine3A;

use super::Scope;
use crate::graph::{Axis, NodeId};

/// Index of a shape (mesh) in a generator's [`shapes`](super::Generator::shapes) list.
pub type ShapeId = u16;

/// Receives the instances a generator emits while expressing a chromosome.
///
/// Scoring sinks voxelize or rasterize each instance as it arrives; nothing
/// needs to be stored.
pub trait ModelSink {
    /// One instance of shape `shape`, placed by `transform` (unit mesh to world).
    fn emit(&mut self, shape: ShapeId, transform: &Affine3A);

    /// One instance emitted by a gene of node `node`. Generators call this;
    /// by default it is [`emit`](Self::emit), so only sinks that want to
    /// know the emitting node (e.g. to colour a picture by it) implement it.
    #[inline(always)]
    fn emit_from(&mut self, node: NodeId, shape: ShapeId, transform: &Affine3A) {
        let _ = node;
        self.emit(shape, transform);
    }

    /// A gene of node `node` splits `scope` along `axis` (a split rule,
    /// `split!`): the children it schedules next are the parts, in order.
    /// Ignored by default; design transformations listen, to merge two
    /// split rules as strings.
    #[inline(always)]
    fn split(&mut self, node: NodeId, axis: Axis, scope: &Scope) {
        let _ = (node, axis, scope);
    }
}

/// One emitted instance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Instance {
    /// Which shape.
    pub shape: ShapeId,
    /// The node whose gene emitted it (0 when not emitted by a generator).
    pub node: NodeId,
    /// Unit mesh to world.
    pub transform: Affine3A,
}

impl Instance {
    /// Shape `shape` placed by `transform`, emitted by no particular node.
    #[must_use]
    pub const fn new(shape: ShapeId, transform: Affine3A) -> Self {
        Self {
            shape,
            node: 0,
            transform,
        }
    }
}

/// A sink that keeps every instance, in emission order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Instances(pub Vec<Instance>);

impl ModelSink for Instances {
    #[inline]
    fn emit(&mut self, shape: ShapeId, transform: &Affine3A) {
        self.0.push(Instance::new(shape, *transform));
    }

    #[inline]
    fn emit_from(&mut self, node: NodeId, shape: ShapeId, transform: &Affine3A) {
        self.0.push(Instance {
            shape,
            node,
            transform: *transform,
        });
    }
}

/// A sink that only counts instances (for benchmarks).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CountingSink {
    /// Instances seen.
    pub count: u64,
}

impl ModelSink for CountingSink {
    #[inline]
    fn emit(&mut self, _: ShapeId, _: &Affine3A) {
        self.count += 1;
    }
}

impl<S: ModelSink + ?Sized> ModelSink for &mut S {
    #[inline]
    fn emit(&mut self, shape: ShapeId, transform: &Affine3A) {
        (**self).emit(shape, transform);
    }

    #[inline]
    fn emit_from(&mut self, node: NodeId, shape: ShapeId, transform: &Affine3A) {
        (**self).emit_from(node, shape, transform);
    }
}
