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
///
/// A triangle is kept as nine 32-bit words, its grid points' two 16-bit coordinates packed
/// into one: the search takes most triangles off the stack just after it put them there, and
/// a triangle written with 16-bit stores and read back by a copy's wider loads waits for the
/// stores to reach the cache first (a quarter of the samples of the search's halving in
/// `perf annotate`, on an AMD EPYC), where words written and read one by one go straight
/// through.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StackSlot([u32; 9]);

impl StackSlot {
    /// An empty slot.
    pub const EMPTY: StackSlot = StackSlot::of(&Pending::NONE);

    /// The slot holding `h`.
    #[inline(always)]
    pub(super) const fn of(h: &Pending) -> StackSlot {
        let c = &h.tri.corners;
        StackSlot([
            h.node,
            h.tri.patch,
            packed(c[0]),
            packed(c[1]),
            packed(c[2]),
            h.corners[0],
            h.corners[1],
            h.corners[2],
            h.shape.0,
        ])
    }

    /// The triangle this slot holds.
    #[inline(always)]
    pub(super) fn get(&self) -> Pending {
        let w = &self.0;
        let point = |x: u32| [x as u16, (x >> 16) as u16];
        Pending {
            node: w[0],
            tri: super::address::Tri {
                patch: w[1],
                corners: [point(w[2]), point(w[3]), point(w[4])],
            },
            corners: [w[5], w[6], w[7]],
            shape: super::hierarchy::Shape(w[8]),
        }
    }
}

/// Grid point `p` in one word.
#[inline(always)]
const fn packed(p: [u16; 2]) -> u32 {
    p[0] as u32 | (p[1] as u32) << 16
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tessellator::address::Tri;
    use crate::tessellator::hierarchy::Shape;

    /// A slot gives back the triangle it was given, its 16-bit coordinates whole.
    #[test]
    fn a_slot_holds_a_triangle_as_it_was() {
        let h = Pending {
            node: 0x8765_4321,
            tri: Tri {
                patch: 7,
                corners: [[0, 0x8000], [0xffff, 1], [0x1234, 0xfedc]],
            },
            corners: [1, u32::MAX, 3],
            shape: Shape(0x8000_0005),
        };
        assert_eq!(StackSlot::of(&h).get(), h);
        assert_eq!(StackSlot::EMPTY.get(), Pending::NONE);
    }
}
