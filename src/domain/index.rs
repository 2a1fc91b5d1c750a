//! The integer type a domain mesh stores its slot numbers in.

use core::fmt;

mod sealed {
    pub trait Sealed {}
    impl Sealed for u8 {}
    impl Sealed for u16 {}
}

/// The integer type a [`DomainMesh`](super::DomainMesh) stores its vertex and triangle slot
/// numbers in: `u16` (the default: up to 65,535 slots of each kind, 12-byte triangle slots)
/// or `u8` (up to 255 slots of each kind, 6-byte triangle slots).
///
/// A mesh works on `u16` slot numbers whatever its index type (zero-extended: with `u8`,
/// 255 means "no slot"); `u8` only halves what a triangle slot stores. It suits meshes of at most 130 vertices, such as the run-time meshes
/// of a bake whose patches hold at most that many samples: a
/// [`Tessellator`](crate::Tessellator) whose pool has `u8` slots never inserts more steps in a
/// patch than its stretch of the pool can number, and refines from there.
///
/// ```
/// use spline_tess::{DomainIndex, DomainMesh, GridPoint, MeshTriangle, MeshVertex, Metric};
///
/// assert_eq!(core::mem::size_of::<MeshTriangle<u8>>(), 6);
/// assert_eq!(<u8 as DomainIndex>::MAX_SLOTS, 255);
/// let mut vertices = [MeshVertex::<u8>::default(); 16];
/// let mut triangles = [MeshTriangle::<u8>::default(); DomainMesh::triangles_for(16)];
/// let mut mesh = DomainMesh::indexed(&mut vertices, &mut triangles, Metric::ISOTROPIC)?;
/// mesh.insert(GridPoint::from_unit(0.5, 0.5)).unwrap();
/// assert_eq!(mesh.triangle_count(), 4);
/// # Ok::<(), spline_tess::MeshStorageError>(())
/// ```
pub trait DomainIndex: sealed::Sealed + Copy + Eq + Default + fmt::Debug {
    /// The most slots of each kind a mesh with this index type holds (the largest value
    /// means "no slot").
    const MAX_SLOTS: usize;
    /// "No slot".
    #[doc(hidden)]
    const NONE: Self;
    /// "No slot", widened: the mesh works on `u16` slot numbers, and this one means none.
    #[doc(hidden)]
    const NO_SLOT: u16;
    /// This slot number as a `u16` (a zero extension: "no slot" becomes
    /// [`DomainIndex::NO_SLOT`]).
    #[doc(hidden)]
    fn widen(self) -> u16;
    /// A `u16` slot number (below [`DomainIndex::MAX_SLOTS`], or [`DomainIndex::NO_SLOT`])
    /// in this type.
    #[doc(hidden)]
    fn narrow(wide: u16) -> Self;
}

impl DomainIndex for u16 {
    const MAX_SLOTS: usize = u16::MAX as usize;
    const NONE: u16 = u16::MAX;
    const NO_SLOT: u16 = u16::MAX;

    #[inline(always)]
    fn widen(self) -> u16 {
        self
    }

    #[inline(always)]
    fn narrow(wide: u16) -> u16 {
        wide
    }
}

impl DomainIndex for u8 {
    const MAX_SLOTS: usize = u8::MAX as usize;
    const NONE: u8 = u8::MAX;
    const NO_SLOT: u16 = u8::MAX as u16;

    #[inline(always)]
    fn widen(self) -> u16 {
        u16::from(self)
    }

    #[inline(always)]
    fn narrow(wide: u16) -> u8 {
        // Slot numbers are below 255, and "no slot" is 255.
        wide as u8
    }
}

#[cfg(test)]
mod tests {
    use super::DomainIndex;

    #[test]
    fn narrow_and_widen_keep_slot_numbers_and_none() {
        for k in 0..255u16 {
            assert_eq!(<u8 as DomainIndex>::narrow(k).widen(), k);
        }
        assert_eq!(<u8 as DomainIndex>::narrow(u8::NO_SLOT), u8::NONE);
        assert_eq!(u8::NONE.widen(), u8::NO_SLOT);
        assert_eq!(<u16 as DomainIndex>::narrow(1234).widen(), 1234);
        assert_eq!(u16::NONE.widen(), u16::NO_SLOT);
    }
}
