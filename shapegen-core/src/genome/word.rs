//! The word-level encoding of a gene (paper Fig. 5).
//!
//! | word | content |
//! |---|---|
//! | 0 | node id (bits 0-15), slot index in the parent (bits 16-23), flags (bits 24-31) |
//! | 1 | parent link: `i32` offset in words to the parent's word 0; 0 for the root |
//! | 2 .. 2+S | one child link per slot: `i32` offset to the child's word 0, 0 = empty |
//! | 2+S .. | parameters, `f32`/`i32`/`u32` bit patterns |

use crate::graph::NodeId;

/// Word index of the parent link within a gene.
pub(crate) const PARENT: usize = 1;
/// Word index of the first child link within a gene.
pub(crate) const SLOTS: usize = 2;
/// Flag set on genes that a cut is removing (never present in a valid chromosome).
pub(crate) const DEAD: u32 = 1 << 24;
/// Mask of the flags byte (zero in a valid chromosome).
pub(crate) const FLAGS: u32 = 0xff << 24;

#[inline]
pub(crate) const fn header(node: NodeId, slot: u32) -> u32 {
    node as u32 | (slot << 16)
}

#[inline]
pub(crate) const fn node(w0: u32) -> NodeId {
    (w0 & 0xffff) as NodeId
}

#[inline]
pub(crate) const fn slot(w0: u32) -> u32 {
    (w0 >> 16) & 0xff
}

/// Absolute position `pos + offset` (offset stored as `i32` bits).
#[inline]
pub(crate) const fn follow(pos: usize, link: u32) -> usize {
    (pos as i64 + link as i32 as i64) as usize
}

/// The link stored at `from` that points to `to`.
#[inline]
pub(crate) const fn link(from: usize, to: usize) -> u32 {
    (to as i64 - from as i64) as i32 as u32
}
