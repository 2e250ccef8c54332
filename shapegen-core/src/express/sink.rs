//! Where expressed geometry goes.

use glam::Affine3A;

/// Index of a shape (mesh) in a generator's [`shapes`](super::Generator::shapes) list.
pub type ShapeId = u16;

/// Receives the instances a generator emits while expressing a chromosome.
///
/// Scoring sinks voxelize or rasterize each instance as it arrives; nothing
/// needs to be stored.
pub trait ModelSink {
    /// One instance of shape `shape`, placed by `transform` (unit mesh to world).
    fn emit(&mut self, shape: ShapeId, transform: &Affine3A);
}

/// One emitted instance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Instance {
    /// Which shape.
    pub shape: ShapeId,
    /// Unit mesh to world.
    pub transform: Affine3A,
}

/// A sink that keeps every instance, in emission order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Instances(pub Vec<Instance>);

impl ModelSink for Instances {
    #[inline]
    fn emit(&mut self, shape: ShapeId, transform: &Affine3A) {
        self.0.push(Instance {
            shape,
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
}
