//! The bound cache: what the run time learns about a domain triangle that does not depend on
//! the view (its corners' surface points and its deviation bounds), kept across frames in a
//! caller slice of any length.
//!
//! A frame judges a triangle by the cheapest bound that settles it (see `refine`), and the
//! bounds it computes on the way are worth keeping: the next frame judges mostly the same
//! triangles. Like the vertex cache, it has an entry per pool triangle slot (slot `i` in entry
//! `i` modulo its length), which a triangle keeps while it stays in its slot: a frame walks
//! its triangles in slot order, so it reads the cache in order too (the entries of a cold
//! frame stream from memory rather than each missing the processor's caches; measured
//! 2026-11-24, a tenth of a 1024x768 teapot frame on the host went to those misses when
//! entries were chosen by a hash of the triangle). An entry says which patch and corners it is
//! about, so one taken over by another triangle (a flip, a slot reused, the pool laid out
//! again) is recomputed, never misread. Every value in an entry is a function of its patch
//! and corners alone, so what the cache holds changes a frame's cost, never its outcome: an
//! empty cache is allowed, and recomputes every bound a frame needs.

use crate::deviation::{corner_points, TriangleBound};
use crate::domain::DomainIndex;
use crate::domain::GridPoint;
use crate::math::SIMD_LANES;
use crate::patch::BezierPatch;

use super::Tessellator;

/// One entry of the bound cache: what is known about one domain triangle of one patch that
/// does not depend on the view (its corners' surface points and its bounds), kept across
/// frames (storage slot; contents are private).
///
/// A triangle has the entry of its pool slot, and takes it over from whatever triangle held
/// it. Every value in it is a function of the patch and the corners alone, so a frame's
/// outcome does not depend on what the cache holds, only its cost does (an empty cache
/// recomputes every bound it needs).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BoundSlot {
    /// The patch the entry is about.
    pub(super) patch: u32,
    /// The triangle the entry is about.
    pub(super) corners: [GridPoint; 3],
    /// What is known about it: [`KNOW_POINTS`], [`KNOW_COARSE`], [`KNOW_WHOLE`],
    /// [`KNOW_OWN`] (0: nothing, an empty entry).
    pub(super) known: u8,
    /// The surface at the corners.
    pub(super) points: [[f32; 3]; 3],
    /// Its bound from the lattice of step 1/3 and the whole patch's remainder.
    pub(super) coarse: f32,
    /// Its bound from the full lattice and the whole patch's remainder.
    pub(super) whole: f32,
    /// Its own bound, and its pieces' (the remainder from its box): `refined`, then
    /// `curvature` and `slack` of its [`TriangleBound`] (whose corner points are `points`).
    pub(super) own: [f32; 6],
}

/// [`BoundSlot::points`] holds the corners' surface points.
pub(super) const KNOW_POINTS: u8 = 1;
/// [`BoundSlot::coarse`] holds its bound.
pub(super) const KNOW_COARSE: u8 = 2;
/// [`BoundSlot::whole`] holds its bound.
pub(super) const KNOW_WHOLE: u8 = 4;
/// [`BoundSlot::own`] holds its own bound.
pub(super) const KNOW_OWN: u8 = 8;

impl BoundSlot {
    /// The entry for the triangle in pool triangle slot `slot` in a cache of `cache_len`
    /// entries (none in an empty cache).
    pub(super) fn index(cache_len: usize, slot: usize) -> Option<usize> {
        (cache_len != 0).then(|| slot % cache_len)
    }

    /// Whether the entry is about triangle `corners` of patch `patch`.
    pub(super) fn is_about(&self, patch: usize, corners: [GridPoint; 3]) -> bool {
        self.known != 0 && self.patch == patch as u32 && self.corners == corners
    }

    /// Makes the entry about triangle `corners` of patch `patch` (forgetting what it knew
    /// about another).
    pub(super) fn about(&mut self, patch: usize, corners: [GridPoint; 3]) {
        if !self.is_about(patch, corners) {
            *self = BoundSlot {
                patch: patch as u32,
                corners,
                ..BoundSlot::default()
            };
        }
    }

    /// The triangle's own bound, if the entry holds it.
    pub(super) fn cached(&self) -> Option<TriangleBound> {
        let o = self.own;
        (self.known & KNOW_OWN != 0).then_some(TriangleBound {
            refined: [o[0], o[1], o[2], o[3]],
            curvature: o[4],
            slack: o[5],
            at: GridPoint::default(),
            points: self.points,
        })
    }

    /// The surface at the corners (computed once and kept).
    pub(super) fn corner_points(&mut self, patch: &BezierPatch<'_>) -> [[f32; 3]; 3] {
        if self.known & KNOW_POINTS == 0 {
            self.points = corner_points(patch, self.corners);
            self.known |= KNOW_POINTS;
        }
        self.points
    }

    /// [`corner_points`](Self::corner_points) of the triangle with domain vertices `ids`,
    /// through `memo` (read where it holds all three, and given them).
    pub(super) fn corner_points_memo(
        &mut self,
        patch: &BezierPatch<'_>,
        ids: [u16; 3],
        memo: &mut CornerMemo,
    ) -> [[f32; 3]; 3] {
        if CORNER_MEMO == 0 {
            return self.corner_points(patch);
        }
        if self.known & KNOW_POINTS == 0 {
            if let [Some(a), Some(b), Some(c)] = ids.map(|id| memo.get(id)) {
                self.points = [a, b, c];
                self.known |= KNOW_POINTS;
            }
        }
        let points = self.corner_points(patch);
        for (&id, &point) in ids.iter().zip(&points) {
            memo.put(id, point);
        }
        points
    }

    /// Keeps `b` as the triangle's own bound.
    pub(super) fn keep_own(&mut self, b: &TriangleBound) {
        let r = b.refined;
        self.own = [r[0], r[1], r[2], r[3], b.curvature, b.slack];
        self.points = b.points;
        self.known |= KNOW_OWN | KNOW_POINTS;
    }
}

/// Entries of a [`CornerMemo`]: none where `Vec4` has no SIMD lanes (a microcontroller, whose
/// stack it would take).
const CORNER_MEMO: usize = if SIMD_LANES { 256 } else { 0 };

/// The corner points of one patch's triangles judged in a frame, by domain vertex: a vertex's
/// point is computed once for the triangles around it rather than once for each. The same
/// bits as computing it again (a corner's lattice parameters are a function of its grid point
/// alone). Direct-mapped, on the stack.
pub(super) struct CornerMemo {
    ids: [u16; CORNER_MEMO],
    points: [[f32; 3]; CORNER_MEMO],
}

impl CornerMemo {
    /// A memo holding nothing.
    pub(super) const EMPTY: CornerMemo = CornerMemo {
        ids: [u16::MAX; CORNER_MEMO],
        points: [[0.0; 3]; CORNER_MEMO],
    };

    /// Forgets every point (for another patch).
    pub(super) fn clear(&mut self) {
        self.ids = [u16::MAX; CORNER_MEMO];
    }

    /// The point of domain vertex `id`, if held.
    pub(super) fn get(&self, id: u16) -> Option<[f32; 3]> {
        let k = (id as usize).checked_rem(CORNER_MEMO)?;
        (self.ids[k] == id).then_some(self.points[k])
    }

    /// Holds `point` as domain vertex `id`'s.
    pub(super) fn put(&mut self, id: u16, point: [f32; 3]) {
        if let Some(k) = (id as usize).checked_rem(CORNER_MEMO) {
            self.ids[k] = id;
            self.points[k] = point;
        }
    }
}

impl<Ix: DomainIndex> Tessellator<'_, '_, Ix> {
    /// The cache entry for triangle `corners` of patch `p` in pool triangle slot `slot`, made
    /// about it (the tessellator's spare entry when the caller's cache is empty).
    pub(super) fn bound_entry(
        &mut self,
        p: usize,
        slot: usize,
        corners: [GridPoint; 3],
    ) -> &mut BoundSlot {
        let entry = match BoundSlot::index(self.storage.bounds.len(), slot) {
            Some(i) => &mut self.storage.bounds[i],
            None => &mut self.spare_bound,
        };
        entry.about(p, corners);
        entry
    }

    /// The surface at the corners of triangle `corners` of patch `patch` (index `p`) in pool
    /// triangle slot `slot`, from the cache where it holds them.
    pub(super) fn cached_corner_points(
        &self,
        p: usize,
        slot: usize,
        patch: &BezierPatch<'_>,
        corners: [GridPoint; 3],
    ) -> [[f32; 3]; 3] {
        let entry = match BoundSlot::index(self.storage.bounds.len(), slot) {
            Some(i) => &self.storage.bounds[i],
            None => &self.spare_bound,
        };
        if entry.is_about(p, corners) && entry.known & KNOW_POINTS != 0 {
            entry.points
        } else {
            corner_points(patch, corners)
        }
    }
}
