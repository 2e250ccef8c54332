//! What each instance added to a scratch, remembered by shape and transform.
//!
//! An optimizer's models share most of their instances with earlier ones (a
//! GA child with its parents, an RJMCMC proposal with the current model):
//! in a GA run on the tree-avoid scene, 99 % of the instances added had been
//! added before, with the same shape and the same transform bits. A scene
//! records what an instance wrote (the volume scene its cell runs, the image
//! scene the runs of pixels it covers) the first time, and replays the
//! record instead of voxelizing or rasterizing it again. A replay gives
//! the same counts (volume scenes) or the same covered pixels (image
//! scenes, which read nothing else of a count) as adding the instance anew.

use std::hash::BuildHasher;

use foldhash::fast::FixedState;
use glam::Affine3A;
use hashbrown::HashTable;
use hashbrown::hash_table::Entry;
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
    /// Per instance, its index in `records`, found by its key's hash: four
    /// bytes and a control byte a slot, so that looking up an instance not
    /// seen before touches a table a fifteenth the size of one holding the
    /// keys (with the keys in the table, the lookups of a fresh spaceship's
    /// instances missed the caches: a sixth of its evaluation).
    slots: HashTable<u32>,
    /// The instances in the order they were first added.
    records: Vec<Record<M>>,
    /// Every recorded instance's items, back to back.
    items: Vec<T>,
    /// Hashes the keys (foldhash: std's SipHash of the 50-byte keys took
    /// about a tenth of a fresh spaceship evaluation).
    hasher: FixedState,
    /// Items held at most: when full, the cache starts over.
    pub(crate) capacity: usize,
    /// Instances held at most: when full, the cache starts over.
    pub(crate) capacity_instances: usize,
}

/// One instance added before: its key, where its items are, and its summary.
#[derive(Clone, Copy, Debug)]
struct Record<M> {
    key: InstanceKey,
    items: (u32, u32),
    summary: M,
}

impl<T, M: Copy> InstanceCache<T, M> {
    /// An empty cache that holds at most `capacity` items and
    /// `capacity_instances` instances before it starts over.
    pub(crate) fn new(capacity: usize, capacity_instances: usize) -> Self {
        // Room for a few hundred models' instances without regrowing.
        let instances = capacity_instances.min(1 << 14);
        Self {
            slots: HashTable::with_capacity(instances),
            records: Vec::with_capacity(instances),
            items: Vec::with_capacity(capacity.min(1 << 16)),
            hasher: FixedState::default(),
            capacity,
            capacity_instances,
        }
    }

    /// How many instances the cache holds.
    #[cfg(test)]
    pub(crate) fn len(&self) -> usize {
        self.records.len()
    }

    /// Forgets every instance.
    pub(crate) fn clear(&mut self) {
        self.slots.clear();
        self.records.clear();
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
        let key = InstanceKey::new(shape, transform);
        let records = &mut self.records;
        match entry(&mut self.slots, records, &self.hasher, key) {
            Entry::Occupied(hit) => {
                let r = records[*hit.get() as usize];
                replay(ctx, slice(&self.items, r.items), r.summary);
            }
            Entry::Vacant(miss) => {
                miss.insert(records.len() as u32);
                let (items, summary) = recorded(&mut self.items, ctx, record);
                records.push(Record {
                    key,
                    items,
                    summary,
                });
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
        let key = InstanceKey::new(shape, transform);
        let records = &mut self.records;
        match entry(&mut self.slots, records, &self.hasher, key) {
            Entry::Occupied(hit) => {
                let r = &mut records[*hit.get() as usize];
                if r.items == SEEN {
                    (r.items, r.summary) = recorded(&mut self.items, ctx, record);
                } else {
                    replay(ctx, slice(&self.items, r.items), r.summary);
                }
            }
            Entry::Vacant(miss) => {
                add(ctx);
                miss.insert(records.len() as u32);
                records.push(Record {
                    key,
                    items: SEEN,
                    summary: M::default(),
                });
            }
        }
    }

    fn start_over_if_full(&mut self) {
        if self.items.len() >= self.capacity || self.records.len() >= self.capacity_instances {
            self.clear();
        }
    }
}

/// The slot of instance `key` in `slots`, whose entries index `records`
/// (growing the table hashes their keys again: rare, and cheaper than
/// keeping each hash).
fn entry<'a, M>(
    slots: &'a mut HashTable<u32>,
    records: &[Record<M>],
    hasher: &FixedState,
    key: InstanceKey,
) -> Entry<'a, u32> {
    slots.entry(
        hasher.hash_one(key),
        |&i| records[i as usize].key == key,
        |&i| hasher.hash_one(records[i as usize].key),
    )
}

/// The items of an instance seen once and not recorded (see
/// [`InstanceCache::add_recording_second`]).
const SEEN: (u32, u32) = (u32::MAX, u32::MAX);

/// A new instance's record: `record` appends its items to `items`; where
/// they are, and the summary it returns.
fn recorded<T, M, C>(
    items: &mut Vec<T>,
    ctx: &mut C,
    record: impl FnOnce(&mut C, &mut Vec<T>) -> M,
) -> ((u32, u32), M) {
    let first = items.len() as u32;
    let summary = record(ctx, items);
    ((first, items.len() as u32), summary)
}

/// The items `range` of a record.
fn slice<T>(items: &[T], range: (u32, u32)) -> &[T] {
    &items[range.0 as usize..range.1 as usize]
}

#[cfg(test)]
mod tests {
    use std::collections::HashMap;

    use proptest::prelude::*;

    use super::*;

    /// An instance of shape `s` translated by `x` along x.
    fn at(x: u8) -> Affine3A {
        Affine3A::from_translation(glam::Vec3::new(f32::from(x), 0.0, 0.0))
    }

    /// What a cache must do, written with a map from instance to its
    /// items: the first time an instance is added it is recorded (its items
    /// are `[x, x + 1, ..]`, `x % 4` of them, with summary `x + s`), later
    /// times replay the record. `record_second`: the first time only adds,
    /// the second records.
    #[derive(Debug, PartialEq)]
    enum Event {
        Added,
        Recorded(Vec<u32>, u32),
        Replayed(Vec<u32>, u32),
    }

    fn items_of(s: ShapeId, x: u8) -> (Vec<u32>, u32) {
        let x = u32::from(x);
        ((x..x + x % 4).collect(), x + u32::from(s))
    }

    proptest! {
        /// Every add, recorded or replayed, as the map says; over as many
        /// instances as make the table grow past its first capacity, and
        /// with capacities small enough that the cache starts over.
        #[test]
        fn replays_what_was_recorded(
            adds in prop::collection::vec((0u16..3, any::<u8>()), 0..1500),
            record_second in any::<bool>(),
            capacity in prop_oneof![Just(usize::MAX), 1usize..200],
        ) {
            let mut cache: InstanceCache<u32, u32> = InstanceCache::new(usize::MAX, capacity);
            let mut seen: HashMap<(ShapeId, u8), usize> = HashMap::new();
            for &(s, x) in &adds {
                if seen.len() >= capacity {
                    seen.clear();
                }
                let times = seen.entry((s, x)).or_default();
                *times += 1;
                let mut event = None;
                let record = |e: &mut Option<Event>, items: &mut Vec<u32>| {
                    let (new, summary) = items_of(s, x);
                    items.extend(&new);
                    *e = Some(Event::Recorded(new, summary));
                    summary
                };
                let replay = |e: &mut Option<Event>, items: &[u32], summary: u32| {
                    *e = Some(Event::Replayed(items.to_vec(), summary));
                };
                let expected = if record_second {
                    cache.add_recording_second(
                        s, &at(x), &mut event, |e| *e = Some(Event::Added), replay, record,
                    );
                    match *times {
                        1 => Event::Added,
                        2 => { let (i, m) = items_of(s, x); Event::Recorded(i, m) }
                        _ => { let (i, m) = items_of(s, x); Event::Replayed(i, m) }
                    }
                } else {
                    cache.add(s, &at(x), &mut event, replay, record);
                    let (i, m) = items_of(s, x);
                    if *times == 1 { Event::Recorded(i, m) } else { Event::Replayed(i, m) }
                };
                prop_assert_eq!(event, Some(expected));
                prop_assert_eq!(cache.len(), seen.len());
            }
        }
    }
}
