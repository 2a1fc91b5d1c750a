//! The run time's bits, in the caller's `u32`s: per node, whether the frame's mesh halves it
//! (above the bake or, for a leaf of the bake, below it), whether it was judged and whether
//! it is hidden; per vertex, whether the frame's count has seen it; per patch, whether it is
//! culled for facing away. How many words a hierarchy takes, and where each set starts.

use super::hierarchy::Hierarchy;
#[cfg(doc)]
use super::select::Tessellator;

impl Hierarchy<'_> {
    /// `u32` words of [`Tessellator`]'s bit storage for this hierarchy: three bits per node,
    /// one per vertex and one per patch.
    pub fn bit_words(&self) -> usize {
        bit_words_for(self.node_count(), self.vertex_count(), self.patch_count())
    }
}

/// `u32` words of [`Tessellator`]'s bit storage for a hierarchy of `nodes` nodes, `vertices`
/// vertices and `patches` patches (as [`Hierarchy::bit_words`]), for sizing storage at compile time from the lengths
/// of a hierarchy's statics.
///
/// ```
/// use spline_tess::tessellator::bit_words_for;
/// const BITS: usize = bit_words_for(7520, 3900, 32);
/// let bits = [0u32; BITS];
/// assert_eq!(bits.len(), 3 * 235 + 122 + 1);
/// ```
pub const fn bit_words_for(nodes: usize, vertices: usize, patches: usize) -> usize {
    3 * nodes.div_ceil(32) + vertices.div_ceil(32) + patches.div_ceil(32)
}

/// Offsets of the bit sets in [`Tessellator::bits`].
#[derive(Clone, Copy, Debug)]
pub(super) struct Layout {
    /// Per node: halved in the frame's mesh (the bits start at 0).
    pub halved: usize,
    pub judged: usize,
    pub hidden: usize,
    /// Per vertex: seen by the frame's count.
    pub seen: usize,
    /// Per patch: culled as facing away.
    pub culled: usize,
}

impl Layout {
    pub fn of(tree: &Hierarchy<'_>) -> Layout {
        let (v, n) = (
            tree.vertex_count().div_ceil(32),
            tree.node_count().div_ceil(32),
        );
        Layout {
            halved: 0,
            judged: n,
            hidden: 2 * n,
            seen: 3 * n,
            culled: 3 * n + v,
        }
    }
}

/// Whether bit `i` of `bits` is set.
pub(super) fn bit(bits: &[u32], i: u32) -> bool {
    bits.get((i / 32) as usize)
        .is_some_and(|w| w & (1 << (i % 32)) != 0)
}

/// Sets bit `i` of `bits`.
pub(super) fn set(bits: &mut [u32], i: u32) {
    if let Some(w) = bits.get_mut((i / 32) as usize) {
        *w |= 1 << (i % 32);
    }
}

/// Clears bit `i` of `bits`.
pub(super) fn clear(bits: &mut [u32], i: u32) {
    if let Some(w) = bits.get_mut((i / 32) as usize) {
        *w &= !(1 << (i % 32));
    }
}
