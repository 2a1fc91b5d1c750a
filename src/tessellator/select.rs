//! Selection and update: each patch's threshold and prefix of baked steps, each curve's
//! samples, and the domain meshes brought to them in place.
//!
//! A patch's threshold `c` comes from the view (the convex hull of its control points, see
//! [`crate::view`]); its
//! prefix is the steps recorded with a bound above `c`. The steps of the prefix that request
//! curve samples say how many samples of each side's curve the patch needs; a curve carries
//! the largest request of the visible patches that share it, so both patches along it place
//! the same points. Each frame deletes first (so a mesh never needs more than its capacity),
//! then inserts, and touches only what changed.

use crate::domain::DomainIndex;
use glam::Vec3;

use super::{FrameStats, Tessellator, TessellatorStorage};
use crate::bake::{boundary_point, BakedPatch, InteriorSample};
use crate::bound::BoundingSphere;
use crate::domain::{DomainMesh, InsertError};
use crate::model::EdgeLink;
use crate::patch::Side;
use crate::view::{HullFit, View};

use super::pool::{PoolFit, PoolSize};
use super::storage::PatchSlot;

/// A patch's threshold and visibility in one view.
pub(super) struct PatchFit {
    /// Threshold, object units.
    pub(super) c: f32,
    /// Off the view, or facing away.
    pub(super) culled: bool,
    /// Culled for facing away.
    pub(super) back_facing: bool,
    /// Its control points' hull wholly inside the view.
    pub(super) inside: bool,
}

/// Count of steps recorded with a bound above `c` in a non-increasing list whose value before
/// the first step is `initial`.
pub(super) fn prefix(initial: f32, len: usize, bound: impl Fn(usize) -> f32, c: f32) -> usize {
    // NaN thresholds and bounds count as "not above".
    if initial.partial_cmp(&c) != Some(core::cmp::Ordering::Greater) || len == 0 {
        return 0;
    }
    // Smallest n in 1..=len with bound(n - 1) <= c, or len.
    if bound(len - 1) > c {
        return len;
    }
    let (mut lo, mut hi) = (1usize, len);
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        if bound(mid - 1) <= c {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    lo
}

/// The recorded bound of a prefix of `n` steps.
pub(super) fn recorded(bp: &BakedPatch<'_>, n: usize) -> f32 {
    match n {
        0 => bp.initial_deviation,
        _ => bp.samples.bound(n - 1).unwrap_or(0.0),
    }
}

/// The side a step requests a curve sample of.
fn request(step: Option<InteriorSample>) -> Option<Side> {
    step.and_then(|s| s.requested_side())
}

/// Moves a patch's request counts from a prefix of `from` steps to one of `to`.
pub(super) fn move_requests(bp: &BakedPatch<'_>, requests: &mut [u16; 4], from: usize, to: usize) {
    if to > from {
        for k in from..to {
            if let Some(side) = request(bp.samples.get(k)) {
                requests[side.index()] += 1;
            }
        }
    } else {
        for k in to..from {
            if let Some(side) = request(bp.samples.get(k)) {
                requests[side.index()] -= 1;
            }
        }
    }
}

impl<'m, 's, Ix: DomainIndex> Tessellator<'m, 's, Ix> {
    /// The patch's sphere.
    pub(super) fn sphere(slot: &PatchSlot) -> BoundingSphere {
        BoundingSphere {
            center: Vec3::from_array(slot.center),
            radius: slot.radius,
        }
    }

    /// Patch `p`'s threshold for `view` (object units), whether it is culled (off the view, or
    /// facing away from the eye: see `back`) and whether it lies wholly inside the view: the
    /// patch, and every triangle between its points, lies in its control points' convex hull
    /// (the weights are positive).
    pub(super) fn patch_threshold(&self, p: usize, view: &View, tol: f32) -> PatchFit {
        let fit = match self.patches.patch(p) {
            Some(patch) => view.hull_scale(patch.points()),
            None => {
                let (scale, culled) = view.scale(&Self::sphere(&self.storage.patches[p]));
                HullFit {
                    scale,
                    culled,
                    inside: false,
                }
            }
        };
        let back_facing = !fit.culled && self.faces_away(p, view);
        PatchFit {
            c: tol * fit.scale,
            culled: fit.culled || back_facing,
            back_facing,
            inside: fit.inside,
        }
    }

    /// Thresholds, culling, prefixes (cut to what the pool holds, see `pool`), requests, and
    /// the curves' counts (sorted parameters kept up to date). Returns the pool's fit.
    pub(super) fn select(&mut self, view: &View, tol: f32) -> PoolFit {
        let baked = self.baked;
        for p in 0..baked.patch_count() {
            let fit = self.patch_threshold(p, view, tol);
            let slot = &mut self.storage.patches[p];
            slot.c = fit.c;
            slot.culled = fit.culled;
            slot.back_facing = fit.back_facing;
            slot.inside = fit.inside;
        }
        let fit = self.fit_pool();
        for k in 0..baked.curve_count() {
            let cs = self.storage.curves[k];
            let Some(curve) = baked.curve(k) else {
                continue;
            };
            let target = if cs.used { cs.predict } else { cs.count };
            let samples = curve.samples;
            let off = cs.order_offset as usize;
            let order = &mut self.storage.curve_order[off..off + samples.len()];
            let mut n = cs.count as usize;
            while n < target as usize {
                let t = samples.get(n).map_or(0, |s| s.t);
                let at = order[..n].partition_point(|&x| x < t);
                order.copy_within(at..n, at + 1);
                order[at] = t;
                n += 1;
            }
            while n > target as usize {
                n -= 1;
                let t = samples.get(n).map_or(0, |s| s.t);
                let at = order[..=n].partition_point(|&x| x < t);
                order.copy_within(at + 1..=n, at);
            }
            self.storage.curves[k].count = target;
        }
        fit
    }

    /// Sets every visible patch's target prefix for its threshold times `scale` (its
    /// [`PatchSlot::target`], `target_interior` and `recorded`) and the curves' predicted
    /// counts, and returns the slots the visible patches' meshes then hold.
    pub(super) fn set_targets(&mut self, scale: f32) -> PoolSize {
        let baked = self.baked;
        for c in self.storage.curves[..baked.curve_count()].iter_mut() {
            c.used = false;
            c.predict = 0;
        }
        for p in 0..baked.patch_count() {
            let Some(bp) = baked.patch(p) else { continue };
            let slot = &mut self.storage.patches[p];
            if slot.culled {
                continue;
            }
            let steps = bp.samples;
            let n = prefix(
                bp.initial_deviation,
                steps.len(),
                |i| steps.bound(i).unwrap_or(0.0),
                slot.c * scale,
            )
            .min(slot.step_cap as usize);
            slot.target = n as u16;
            slot.recorded = recorded(&bp, n);
            // `requests` follows `steps`, the prefix in the mesh; the target's requests are
            // worked out from it.
            let mut want = slot.requests;
            move_requests(&bp, &mut want, slot.steps as usize, n);
            slot.target_interior = (n - want.iter().map(|&r| r as usize).sum::<usize>()) as u16;
            for (s, link) in bp.edges.into_iter().enumerate() {
                if let EdgeLink::Curve { curve, .. } = link {
                    let cs = &mut self.storage.curves[curve as usize];
                    cs.used = true;
                    cs.predict = cs.predict.max(want[s]);
                }
            }
        }
        let mut need = PoolSize::default();
        for p in 0..baked.patch_count() {
            let slot = self.storage.patches[p];
            if !slot.culled {
                let (v, t) = self.target_slots(p);
                need.vertices += v;
                need.triangles += t;
            }
        }
        need
    }

    /// Vertex and triangle slots patch `p`'s mesh holds at its target (set by
    /// [`set_targets`](Self::set_targets)): `n` interior and `b` boundary vertices make
    /// `2n + b - 2` triangles.
    pub(super) fn target_slots(&self, p: usize) -> (usize, usize) {
        let slot = &self.storage.patches[p];
        let mut boundary = 4usize;
        if let Some(bp) = self.baked.patch(p) {
            for link in bp.edges {
                if let EdgeLink::Curve { curve, .. } = link {
                    boundary += usize::from(self.storage.curves[curve as usize].predict);
                }
            }
        }
        let interior = usize::from(slot.target_interior);
        (interior + boundary, 2 * interior + boundary - 2)
    }

    /// The mesh of patch `p`, over its storage.
    pub(super) fn mesh<'b>(
        storage: &'b mut TessellatorStorage<'s, Ix>,
        slot: &PatchSlot,
    ) -> DomainMesh<'b, Ix> {
        DomainMesh::resume(
            &mut storage.vertices[slot.vertex_range()],
            &mut storage.triangles[slot.triangle_range()],
            slot.mesh,
        )
    }

    /// The curve sample counts patch `p`'s sides are to hold this frame.
    fn curve_targets(&self, p: usize) -> [u16; 4] {
        self.baked.patch(p).map_or([0; 4], |bp| {
            bp.edges.map(|link| match link {
                EdgeLink::Curve { curve, .. } => self.storage.curves[curve as usize].count,
                EdgeLink::Collapsed => 0,
            })
        })
    }

    /// Deletes the points of patch `p` past its target prefix and its curves' counts (so its
    /// mesh then needs at most the slots of its target).
    pub(super) fn shrink_patch(&mut self, p: usize, stats: &mut FrameStats) {
        let baked = self.baked;
        let Some(bp) = baked.patch(p) else {
            return;
        };
        let mut slot = self.storage.patches[p];
        let steps = bp.samples;
        let curve_targets = self.curve_targets(p);
        if slot.steps <= slot.target && (0..4).all(|s| slot.sides[s] <= curve_targets[s]) {
            return;
        }
        let mut mesh = Self::mesh(&mut self.storage, &slot);
        while slot.steps > slot.target {
            slot.steps -= 1;
            if let Some(s) = steps.get(slot.steps as usize) {
                if let Some(side) = s.requested_side() {
                    slot.requests[side.index()] -= 1;
                } else if let Some(id) = mesh.find(s.point) {
                    if mesh.remove(id).is_ok() {
                        stats.deleted += 1;
                    }
                }
            }
        }
        for (s, link) in bp.edges.into_iter().enumerate() {
            let EdgeLink::Curve { curve, reversed } = link else {
                continue;
            };
            let Some(bc) = baked.curve(curve as usize) else {
                continue;
            };
            while slot.sides[s] > curve_targets[s] {
                slot.sides[s] -= 1;
                if let Some(cs) = bc.samples.get(slot.sides[s] as usize) {
                    let point = boundary_point(Side::ALL[s], cs.t, reversed);
                    if let Some(id) = mesh.find(point) {
                        if mesh.remove(id).is_ok() {
                            stats.deleted += 1;
                        }
                    }
                }
            }
        }
        slot.mesh = mesh.header();
        self.storage.patches[p] = slot;
    }

    /// Inserts the points of patch `p` up to its target prefix and its curves' counts (after
    /// [`shrink_patch`](Self::shrink_patch), in storage laid out for the target).
    pub(super) fn grow_patch(
        &mut self,
        p: usize,
        stats: &mut FrameStats,
    ) -> Result<(), InsertError> {
        let baked = self.baked;
        let Some(bp) = baked.patch(p) else {
            return Ok(());
        };
        let mut slot = self.storage.patches[p];
        let steps = bp.samples;
        let curve_targets = self.curve_targets(p);
        if slot.target == slot.steps && curve_targets == slot.sides {
            return Ok(());
        }
        let mut mesh = Self::mesh(&mut self.storage, &slot);
        let mut result = Ok(());
        'insert: {
            for (s, link) in bp.edges.into_iter().enumerate() {
                let EdgeLink::Curve { curve, reversed } = link else {
                    continue;
                };
                let Some(bc) = baked.curve(curve as usize) else {
                    continue;
                };
                while slot.sides[s] < curve_targets[s] {
                    if let Some(cs) = bc.samples.get(slot.sides[s] as usize) {
                        let point = boundary_point(Side::ALL[s], cs.t, reversed);
                        if let Err(e) = mesh.insert(point) {
                            result = Err(e);
                            break 'insert;
                        }
                        stats.inserted += 1;
                    }
                    slot.sides[s] += 1;
                }
            }
            while slot.steps < slot.target {
                if let Some(s) = steps.get(slot.steps as usize) {
                    if let Some(side) = s.requested_side() {
                        slot.requests[side.index()] += 1;
                    } else {
                        if let Err(e) = mesh.insert(s.point) {
                            result = Err(e);
                            break 'insert;
                        }
                        stats.inserted += 1;
                    }
                }
                slot.steps += 1;
            }
        }
        slot.mesh = mesh.header();
        self.storage.patches[p] = slot;
        result
    }
}
