//! What each instance added to a scratch, remembered by shape and transform.
//!
//! An optimizer's models share most of their instances with earlier ones (a
//! GA child with its parents, an RJMCMC proposal with the current model):
//! in a GA run on the tree-avoid scene, 99 % of the instances added had been
//! added before, with the same shape and the same transform bits. A scene
//! records what an instance wrote (the volume scene its cell runs, the image
//! scene its count differences) the first time, and replays the record
//! instead of voxelizing or rasterizing it again. A record is the same
//! numbers the instance wrote, so a replay gives the same counts.

use std::collections::HashMap;
use std::collections::hash_map::Entry;

use foldhash::fast::FixedState;
use glam::Affine3A;
use shapegen_core::express::ShapeId;

/// An instance: its shape and its transform's bits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
struct InstanceKey {
    shape: ShapeId,
    transform: [u32; 12],
}

impl InstanceKey {
    fn new(shape: ShapeId, transform: &Affine3A) -> Self {
        Self {
            shape,
            transform: transform.to_cols_array().map(f32::to_bits),
        }
    }
}

/// The records of instances added before: per instance, items of type `T`
/// (kept back to back) and a summary `M`.
#[derive(Clone, Debug)]
pub(crate) struct InstanceCache<T, M> {
    /// Hashed with foldhash: std's SipHash of the 50-byte keys took about a
    /// tenth of a fresh spaceship evaluation.
    instances: HashMap<InstanceKey, Cached<M>, FixedState>,
    /// Every cached instance's items, back to back.
    items: Vec<T>,
    /// Items held at most: when full, the cache starts over.
    pub(crate) capacity: usize,
    /// Instances held at most: when full, the cache starts over.
    pub(crate) capacity_instances: usize,
}

/// One cached instance: where its items are, and its summary.
#[derive(Clone, Copy, Debug)]
struct Cached<M> {
    items: (u32, u32),
    summary: M,
}

impl<T, M: Copy> InstanceCache<T, M> {
    /// An empty cache that holds at most `capacity` items and
    /// `capacity_instances` instances before it starts over.
    pub(crate) fn new(capacity: usize, capacity_instances: usize) -> Self {
        Self {
            // Room for a few hundred models' instances without regrowing.
            instances: HashMap::with_capacity_and_hasher(
                capacity_instances.min(1 << 14),
                FixedState::default(),
            ),
            items: Vec::with_capacity(capacity.min(1 << 16)),
            capacity,
            capacity_instances,
        }
    }

    /// How many instances the cache holds.
    #[cfg(test)]
    pub(crate) fn len(&self) -> usize {
        self.instances.len()
    }

    /// Forgets every instance.
    pub(crate) fn clear(&mut self) {
        self.instances.clear();
        self.items.clear();
    }

    /// Adds instance `(shape, transform)` with one hash, hit or miss: if it
    /// was recorded before, `replay(ctx, items, summary)`; else
    /// `record(ctx, items)`, which appends the instance's items and returns
    /// its summary, and the record is kept.
    pub(crate) fn add<C>(
        &mut self,
        shape: ShapeId,
        transform: &Affine3A,
        ctx: &mut C,
        replay: impl FnOnce(&mut C, &[T], M),
        record: impl FnOnce(&mut C, &mut Vec<T>) -> M,
    ) {
        self.start_over_if_full();
        match self.instances.entry(InstanceKey::new(shape, transform)) {
            Entry::Occupied(hit) => {
                let Cached { items, summary } = *hit.get();
                replay(ctx, slice(&self.items, items), summary);
            }
            Entry::Vacant(miss) => {
                miss.insert(recorded(&mut self.items, ctx, record));
            }
        }
    }

    /// [`add`](Self::add) for records that cost more than adding the
    /// instance without one: the first time an instance is seen, only
    /// `add(ctx)` and a note that it was seen; the second time, `record`;
    /// from then on, `replay`. Instances seen once (most of a random
    /// population's) cost no record.
    pub(crate) fn add_recording_second<C>(
        &mut self,
        shape: ShapeId,
        transform: &Affine3A,
        ctx: &mut C,
        add: impl FnOnce(&mut C),
        replay: impl FnOnce(&mut C, &[T], M),
        record: impl FnOnce(&mut C, &mut Vec<T>) -> M,
    ) where
        M: Default,
    {
        self.start_over_if_full();
        match self.instances.entry(InstanceKey::new(shape, transform)) {
            Entry::Occupied(mut hit) => {
                let Cached { items, summary } = *hit.get();
                if items == SEEN {
                    *hit.get_mut() = recorded(&mut self.items, ctx, record);
                } else {
                    replay(ctx, slice(&self.items, items), summary);
                }
            }
            Entry::Vacant(miss) => {
                add(ctx);
                miss.insert(Cached {
                    items: SEEN,
                    summary: M::default(),
                });
            }
        }
    }

    fn start_over_if_full(&mut self) {
        if self.items.len() >= self.capacity || self.instances.len() >= self.capacity_instances {
            self.clear();
        }
    }
}

/// The items of an instance seen once and not recorded (see
/// [`InstanceCache::add_recording_second`]).
const SEEN: (u32, u32) = (u32::MAX, u32::MAX);

/// A new instance's record: `record` appends its items to `items`.
fn recorded<T, M, C>(
    items: &mut Vec<T>,
    ctx: &mut C,
    record: impl FnOnce(&mut C, &mut Vec<T>) -> M,
) -> Cached<M> {
    let first = items.len() as u32;
    let summary = record(ctx, items);
    Cached {
        items: (first, items.len() as u32),
        summary,
    }
}

/// The items `range` of a record.
fn slice<T>(items: &[T], range: (u32, u32)) -> &[T] {
    &items[range.0 as usize..range.1 as usize]
}
