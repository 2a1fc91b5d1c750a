//! The pool: one stretch of vertex and triangle slots, sized by the caller, shared by every
//! patch's domain mesh and laid out each frame in proportion to what the view needs.
//!
//! # Demand
//!
//! A patch whose target prefix has `n` interior points and whose sides carry `s` curve
//! samples has `b = 4 + s` boundary vertices, so its mesh holds `n + b` vertices and
//! `2n + b - 2` triangles (see [`crate::domain`]). Deletions come first in a frame, so a mesh
//! never holds more than the larger of what it held and what its target holds. The frame's
//! demand is the sum over the visible patches, plus the meshes kept for culled patches.
//!
//! # When the pool is short
//!
//! 1. The culled patches' meshes are let go (each goes back to its two triangles, and is
//!    rebuilt when it comes back into view).
//! 2. If the visible patches need more than the pool holds beside the culled patches' meshes
//!    let go (whatever those hold now, so that the frame depends on the view alone, not on
//!    the frames before), every patch's prefix is chosen for its
//!    threshold times one common factor `k > 1`: the smallest factor (found by doubling, then
//!    bisection on its logarithm) whose prefixes fit. `k` large enough empties every prefix, and
//!    the pool always holds that ([`StorageSize::minimum`](super::StorageSize::minimum)).
//!
//! A shorter prefix is one the refinement takes over from, as it does when the samples run
//! out: its recorded bound is above the patch's threshold, so every triangle is judged on its
//! own bound and cut until its pieces are within the tolerance (see `refine`). The error
//! bound holds; the frame spends more triangles, and
//! [`FrameStats::prefix_scale`](super::FrameStats::prefix_scale) reports `k`.
//!
//! # Layout
//!
//! Each patch owns a contiguous stretch of vertex slots and one of triangle slots (with their
//! [`TriangleSlot`](super::TriangleSlot)s, which hold the current frame's state alone: a frame
//! writes them after the layout, so they are not moved). When a visible patch's target needs more than its
//! stretch, the pool is laid out again: every mesh is compacted (its live slots moved to the
//! front, see [`DomainMesh`]), each patch gets its demand plus a share of what is left over
//! in proportion to its demand (at most what it could ever hold), and the stretches are moved
//! to their new places: first, in increasing order, those that move down, then, in
//! decreasing order, those that move up, so no move overwrites live slots that have not moved
//! yet. The work is linear in the pool, and only frames whose demand outgrows the layout pay
//! it.

use super::storage::PatchSlot;
#[cfg(doc)]
use super::storage::TriangleSlot;
use super::Tessellator;
use crate::domain::DomainIndex;
use crate::domain::DomainMesh;
#[cfg(doc)]
use crate::domain::{MeshTriangle, MeshVertex};

/// Vertex and triangle slots of the pool.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PoolSize {
    /// [`MeshVertex`] slots.
    pub vertices: usize,
    /// [`MeshTriangle`] slots (each with a [`TriangleSlot`]).
    pub triangles: usize,
}

impl PoolSize {
    /// True when both counts are within `other`'s.
    pub fn fits_in(&self, other: &PoolSize) -> bool {
        self.vertices <= other.vertices && self.triangles <= other.triangles
    }

    fn plus(self, other: PoolSize) -> PoolSize {
        PoolSize {
            vertices: self.vertices + other.vertices,
            triangles: self.triangles + other.triangles,
        }
    }

    /// What is left of `self` after `other` (none where `other` is more).
    fn less(self, other: PoolSize) -> PoolSize {
        PoolSize {
            vertices: self.vertices.saturating_sub(other.vertices),
            triangles: self.triangles.saturating_sub(other.triangles),
        }
    }
}

/// How a frame's prefixes fit the pool.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct PoolFit {
    /// What the visible patches' full prefixes need.
    pub(super) needed: PoolSize,
    /// The factor the thresholds were multiplied by to choose the prefixes (1 when they fit).
    pub(super) scale: f32,
    /// Whether the culled patches' meshes are let go.
    pub(super) release: bool,
}

/// Bisection steps on `log2 k` once a fitting power of two is found.
const BISECTIONS: usize = 10;

impl<Ix: DomainIndex> Tessellator<'_, '_, Ix> {
    /// The pool the caller's storage gives.
    pub fn pool_size(&self) -> PoolSize {
        PoolSize {
            vertices: self.storage.vertices.len(),
            triangles: self.storage.triangles.len(),
        }
    }

    /// Slots the culled patches' meshes hold: as they are, or let go.
    fn culled_slots(&self, release: bool) -> PoolSize {
        let mut held = PoolSize::default();
        for slot in &self.storage.patches[..self.baked.patch_count()] {
            if slot.culled {
                let (v, t) = if release {
                    (4, 2)
                } else {
                    (
                        usize::from(slot.mesh.vertex_count()),
                        slot.mesh.triangle_count(),
                    )
                };
                held.vertices += v;
                held.triangles += t;
            }
        }
        held
    }

    /// Chooses the frame's prefixes (every visible patch's target) so that the meshes fit
    /// the pool: see the module docs.
    pub(super) fn fit_pool(&mut self) -> PoolFit {
        let pool = self.pool_size();
        let needed = self.set_targets(1.0);
        // The room is what the pool holds beside the culled patches' meshes let go, whatever
        // they hold now: the prefixes then depend on the view alone, not on the frames before.
        let room = pool.less(self.culled_slots(true));
        let mut fit = PoolFit {
            needed,
            scale: 1.0,
            release: !needed.plus(self.culled_slots(false)).fits_in(&pool),
        };
        if needed.fits_in(&room) {
            return fit;
        }
        fit.release = true;
        // `lo` does not fit; find a power of two `hi` that does.
        let (mut lo, mut hi) = (1.0f32, 2.0f32);
        while !self.set_targets(hi).fits_in(&room) {
            lo = hi;
            hi = if hi < 1e30 { hi * 2.0 } else { f32::INFINITY };
            if hi == f32::INFINITY {
                break;
            }
        }
        if hi.is_finite() {
            for _ in 0..BISECTIONS {
                let mid = crate::math::sqrt(lo) * crate::math::sqrt(hi);
                if self.set_targets(mid).fits_in(&room) {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
        }
        self.set_targets(hi);
        fit.scale = hi;
        fit
    }

    /// Lets the culled patches' meshes go back to their two triangles.
    pub(super) fn release_culled(&mut self) {
        for p in 0..self.baked.patch_count() {
            let slot = self.storage.patches[p];
            if !slot.culled || (slot.steps == 0 && slot.sides == [0; 4]) {
                continue;
            }
            let Ok(mesh) = DomainMesh::indexed(
                &mut self.storage.vertices[slot.vertex_range()],
                &mut self.storage.triangles[slot.triangle_range()],
                slot.mesh.metric(),
            ) else {
                continue;
            };
            let s = &mut self.storage.patches[p];
            s.mesh = mesh.header();
            s.steps = 0;
            s.requests = [0; 4];
            s.sides = [0; 4];
        }
    }

    /// Lays the pool out again if a visible patch's target needs more than its stretch (see
    /// the module docs). Called between the frame's deletions and its insertions.
    pub(super) fn lay_out_pool(&mut self) {
        let count = self.baked.patch_count();
        let outgrown = (0..count).any(|p| {
            let slot = &self.storage.patches[p];
            let (v, t) = self.target_slots(p);
            !slot.culled
                && (v > slot.vertex_capacity as usize || t > slot.triangle_capacity as usize)
        });
        if !outgrown {
            return;
        }
        // Every mesh compacted; its demand. (The triangles' states are not moved with them: a
        // frame writes them afresh after the layout, and the bound cache is keyed by corners,
        // not slots.)
        let mut demand = PoolSize::default();
        for p in 0..count {
            let slot = self.storage.patches[p];
            let mut mesh = DomainMesh::resume(
                &mut self.storage.vertices[slot.vertex_range()],
                &mut self.storage.triangles[slot.triangle_range()],
                slot.mesh,
            );
            mesh.compact(|_, _| {});
            self.storage.patches[p].mesh = mesh.header();
            let (v, t) = self.wanted_slots(p);
            demand.vertices += v;
            demand.triangles += t;
        }
        // New stretches: the demand, plus a share of the rest. (The demand fits unless a
        // deletion failed, which exact predicates rule out; then the insertions report it.)
        let pool = self.pool_size();
        if !demand.fits_in(&pool) {
            return;
        }
        let spare = pool.less(demand);
        for p in 0..count {
            let (v, t) = self.wanted_slots(p);
            let slot = &mut self.storage.patches[p];
            let share = |need: usize, spare: usize, total: usize, limit: u16| -> usize {
                let extra = (spare as u64 * need as u64 / total.max(1) as u64) as usize;
                (need + extra).min((limit as usize).max(need))
            };
            let (nv, nt) = if slot.culled {
                (v, t)
            } else {
                (
                    share(v, spare.vertices, demand.vertices, slot.vertex_limit),
                    share(t, spare.triangles, demand.triangles, slot.triangle_limit),
                )
            };
            slot.vertex_capacity = nv as u32;
            slot.triangle_capacity = nt as u32;
        }
        self.move_stretches();
    }

    /// Slots patch `p` keeps through the layout: its live slots, or its target's if more.
    fn wanted_slots(&self, p: usize) -> (usize, usize) {
        let slot = &self.storage.patches[p];
        let live = (
            usize::from(slot.mesh.vertex_count()),
            slot.mesh.triangle_count(),
        );
        if slot.culled {
            return live;
        }
        let (v, t) = self.target_slots(p);
        (v.max(live.0), t.max(live.1))
    }

    /// Moves every patch's live slots to the new stretches (their capacities are set, their
    /// offsets follow from them) and resumes its mesh there.
    fn move_stretches(&mut self) {
        let count = self.baked.patch_count();
        let storage = &mut self.storage;
        let total = |f: fn(&PatchSlot) -> u32| -> usize {
            storage.patches[..count].iter().map(|s| f(s) as usize).sum()
        };
        let (mut end_v, mut end_t) = (total(|s| s.vertex_capacity), total(|s| s.triangle_capacity));
        // Down first, in increasing order.
        let (mut vo, mut to) = (0usize, 0usize);
        for p in 0..count {
            let slot = storage.patches[p];
            if vo < slot.vertex_offset as usize {
                let n = usize::from(slot.mesh.vertex_count());
                move_slots(storage.vertices, slot.vertex_offset as usize, vo, n);
                storage.patches[p].vertex_offset = vo as u32;
            }
            if to < slot.triangle_offset as usize {
                let (from, n) = (slot.triangle_offset as usize, slot.mesh.triangle_count());
                move_slots(storage.triangles, from, to, n);
                storage.patches[p].triangle_offset = to as u32;
            }
            vo += slot.vertex_capacity as usize;
            to += slot.triangle_capacity as usize;
        }
        // Then up, in decreasing order.
        for p in (0..count).rev() {
            let slot = storage.patches[p];
            end_v -= slot.vertex_capacity as usize;
            end_t -= slot.triangle_capacity as usize;
            if end_v > slot.vertex_offset as usize {
                let n = usize::from(slot.mesh.vertex_count());
                move_slots(storage.vertices, slot.vertex_offset as usize, end_v, n);
                storage.patches[p].vertex_offset = end_v as u32;
            }
            if end_t > slot.triangle_offset as usize {
                let (from, n) = (slot.triangle_offset as usize, slot.mesh.triangle_count());
                move_slots(storage.triangles, from, end_t, n);
                storage.patches[p].triangle_offset = end_t as u32;
            }
        }
        for p in 0..count {
            let slot = storage.patches[p];
            let mesh = DomainMesh::resume_compacted(
                &mut storage.vertices[slot.vertex_range()],
                &mut storage.triangles[slot.triangle_range()],
                slot.mesh,
            );
            storage.patches[p].mesh = mesh.header();
        }
    }
}

/// Moves `n` slots from `from` to `to` (the ranges may overlap).
fn move_slots<T: Copy>(slots: &mut [T], from: usize, to: usize, n: usize) {
    if from != to && n > 0 {
        slots.copy_within(from..from + n, to);
    }
}
