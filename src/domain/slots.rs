//! The slots a [`DomainMesh`] keeps its vertices and triangles in, in caller storage: their
//! layout, packed by the index type ([`DomainIndex`]).

#[cfg(doc)]
use super::DomainMesh;
use super::{DomainIndex, GridPoint};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
/// One vertex slot of a [`DomainMesh`] (6 bytes with `u16` slot numbers, 5 with `u8`: see
/// [`DomainIndex`]).
#[repr(C, packed)]
pub struct MeshVertex<Ix: DomainIndex = u16> {
    /// Its point's `u` (packed, so that a `u8`-indexed slot takes 5 bytes); for a free slot,
    /// the next free slot.
    pub(super) u: u16,
    /// Its point's `v`.
    pub(super) v: u16,
    /// An incident triangle; "none" marks a free slot (a live vertex always has one).
    pub(super) link: Ix,
}

impl<Ix: DomainIndex> MeshVertex<Ix> {
    /// A slot holding `point`, linked to triangle `link`.
    #[inline(always)]
    pub(super) fn new(point: GridPoint, link: u16) -> Self {
        MeshVertex {
            u: point.u,
            v: point.v,
            link: Ix::narrow(link),
        }
    }

    /// A free slot, chained to free slot `next` (`Ix::NO_SLOT`: the last).
    pub(super) fn free(next: u16) -> Self {
        MeshVertex {
            u: next,
            v: 0,
            link: Ix::NONE,
        }
    }

    /// Whether the slot holds a vertex.
    pub(super) fn is_live(&self) -> bool {
        let link = self.link;
        link != Ix::NONE
    }

    /// The point the slot holds (for a free slot, the next free slot as `u`).
    #[inline(always)]
    pub(super) fn point(&self) -> GridPoint {
        // Copies (a packed field is read by value, never by reference).
        let (u, v) = (self.u, self.v);
        GridPoint { u, v }
    }

    /// The point of a live slot.
    pub(crate) fn live_point(&self) -> Option<GridPoint> {
        self.is_live().then(|| self.point())
    }

    /// The point of a slot known to be live (a corner of a live triangle); meaningless for a
    /// free slot.
    pub(crate) fn corner_point(&self) -> GridPoint {
        self.point()
    }
}

// By hand: the derive would take references to the packed fields.
#[cfg(feature = "defmt")]
impl<Ix: DomainIndex> defmt::Format for MeshVertex<Ix> {
    fn format(&self, f: defmt::Formatter<'_>) {
        let link = self.link;
        defmt::write!(
            f,
            "MeshVertex {{ point: {}, link: {} }}",
            self.point(),
            link.widen()
        )
    }
}

impl<Ix: DomainIndex> Default for MeshVertex<Ix> {
    fn default() -> Self {
        MeshVertex::free(Ix::NO_SLOT)
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
/// One triangle slot of a [`DomainMesh`] (12 bytes with `u16` indices, 6 with `u8`: see
/// [`DomainIndex`]).
pub struct MeshTriangle<Ix: DomainIndex = u16> {
    /// Vertices, counter-clockwise; "none" in a free slot (a vertex slot number is always
    /// below it).
    pub(super) v: [Ix; 3],
    /// `n[i]`: the triangle across the edge opposite `v[i]`; for a free slot `n[0]` is the
    /// next free slot.
    pub(super) n: [Ix; 3],
}

impl<Ix: DomainIndex> MeshTriangle<Ix> {
    /// A free slot, chained to free slot `next` (`Ix::NO_SLOT`: the last).
    pub(super) fn free(next: u16) -> Self {
        MeshTriangle {
            v: [Ix::NONE; 3],
            n: [Ix::narrow(next), Ix::NONE, Ix::NONE],
        }
    }

    /// Whether the slot holds a triangle.
    pub(super) fn is_live(&self) -> bool {
        self.v[0] != Ix::NONE
    }

    /// The slot with `u16` slot numbers, as the mesh works on it.
    #[inline(always)]
    pub(super) fn widen(self) -> MeshTriangle {
        MeshTriangle {
            v: self.v.map(Ix::widen),
            n: self.n.map(Ix::widen),
        }
    }

    /// The slot `wide` (slot numbers below [`DomainIndex::MAX_SLOTS`], or `Ix::NO_SLOT`) in this
    /// index type.
    #[inline(always)]
    pub(super) fn narrow(wide: MeshTriangle) -> Self {
        MeshTriangle {
            v: wide.v.map(Ix::narrow),
            n: wide.n.map(Ix::narrow),
        }
    }

    /// Vertices (counter-clockwise) and neighbours (`n[i]` across the edge opposite `v[i]`,
    /// `None` on the square's boundary) of a live slot.
    pub(crate) fn live_parts(&self) -> Option<([u16; 3], [Option<u16>; 3])> {
        self.is_live().then(|| {
            let w = self.widen();
            (w.v, w.n.map(|n| (n != Ix::NO_SLOT).then_some(n)))
        })
    }
}

impl<Ix: DomainIndex> Default for MeshTriangle<Ix> {
    fn default() -> Self {
        MeshTriangle::free(Ix::NO_SLOT)
    }
}
