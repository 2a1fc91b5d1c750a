//! A tessellator's storage: the bits of its hierarchy, a stack of triangles waiting to be
//! judged, and a pool of vertices below the bake. Sized at compile time in a
//! [`TessellatorStorage`] (firmware: a `static` or a local, `const fn new`), or in the
//! caller's slices ([`Tessellator::from_slices`](super::Tessellator::from_slices): sizes
//! chosen at run time on a host).
//!
//! How much of each:
//!
//! - bits: [`bit_words_for`](super::bit_words_for) of the hierarchy's node, vertex and patch counts
//!   ([`Hierarchy::bit_words`](super::Hierarchy::bit_words)), a few hundred words for a model
//!   of thousands of triangles;
//! - stack: at least [`Tessellator::MIN_STACK`](super::Tessellator::MIN_STACK). A frame
//!   never needs more than a few hundred; a shorter stack costs walks of the patches it had
//!   no room for ([`FrameStats::sweeps`](super::FrameStats::sweeps)), never the mesh;
//! - pool: as many vertices as views finer than the bake should make (none: such a view
//!   leaves its triangles whole, within the bound the frame reports). A frame that fills it
//!   says so ([`FrameStats::pool_full`](super::FrameStats::pool_full)).

use super::hierarchy::Pending;
use super::refine::PoolSlot;

/// One entry of a tessellator's stack of triangles waiting to be judged: opaque, the caller
/// only provides room for them.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StackSlot(pub(super) Pending);

impl StackSlot {
    /// An empty slot.
    pub const EMPTY: StackSlot = StackSlot(Pending::NONE);
}

/// A tessellator's storage sized at compile time: `BITS` words of bits (at least
/// [`bit_words_for`](super::bit_words_for) of the hierarchy's node, vertex and patch counts), a
/// stack of `STACK` triangles (at least [`Tessellator::MIN_STACK`](super::Tessellator)) and a
/// pool of `POOL` vertices below the bake (any number, 0 included).
///
/// ```
/// use core::mem::size_of;
/// use spline_tess::tessellator::{bit_words_for, StackSlot, TessellatorStorage};
///
/// // For a hierarchy of 7,520 nodes and 1,977 vertices, with no pool: the bits and the
/// // stack, and no more (but alignment).
/// type Storage = TessellatorStorage<{ bit_words_for(7520, 1977, 32) }, 64, 0>;
/// static STORAGE: Storage = Storage::new();
/// let bytes = 4 * bit_words_for(7520, 1977, 32) + 64 * size_of::<StackSlot>();
/// assert!(size_of::<Storage>() - bytes < 8);
/// ```
#[derive(Clone, Debug)]
pub struct TessellatorStorage<const BITS: usize, const STACK: usize, const POOL: usize> {
    pub(super) bits: [u32; BITS],
    pub(super) stack: [StackSlot; STACK],
    pub(super) pool: [PoolSlot; POOL],
}

impl<const BITS: usize, const STACK: usize, const POOL: usize>
    TessellatorStorage<BITS, STACK, POOL>
{
    /// Empty storage (it can be a `static`).
    pub const fn new() -> Self {
        TessellatorStorage {
            bits: [0; BITS],
            stack: [StackSlot::EMPTY; STACK],
            pool: [PoolSlot::EMPTY; POOL],
        }
    }
}

impl<const BITS: usize, const STACK: usize, const POOL: usize> Default
    for TessellatorStorage<BITS, STACK, POOL>
{
    fn default() -> Self {
        Self::new()
    }
}
