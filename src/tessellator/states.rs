//! The frame's triangle states: an arena of [`TriangleSlot`]s that only some patches use.
//!
//! A patch whose baked prefix is within its threshold, and whose triangles are all baked
//! prefix triangles, judges none of them on its own and cuts none: every one of its triangles
//! has factor 1 and the prefix's recorded bound. Such a patch needs no state per triangle, and
//! in a frame that needs no refinement (most frames of a small display) that is every patch.
//!
//! Each frame starts with an empty arena. A patch takes a stretch of it, one state per live
//! triangle of its mesh (compacted to its first slots), when its triangles are to be judged on
//! their own (its prefix is exhausted, some of its sides hold curve samples beyond its own
//! requests, or its triangles off the view are to be hidden) or cut (a curve along it is
//! refined by a neighbour). A patch without states has, for every triangle,
//! [`TriangleSlot::plain`] of its slot's `plain` bound.
//!
//! Why the bound stays a bound without states: every triangle of such a patch is written
//! uncut, at factor 1, in the pattern its curves give it. Its `plain` bound starts at the
//! prefix's recorded bound (which covers every baked prefix triangle) and takes the maximum of
//! every bound computed for one of its triangles (a judged triangle's own bound at factor 1,
//! and each piece's bound of a non-uniform pattern), so it covers each triangle it is written
//! with. Its largest bound over threshold is the maximum of the same bounds, each over the
//! threshold it was judged against.
//!
//! A patch that finds the arena full is left uncut: every bound computed for one of its
//! triangles this frame (at factor 1, with the non-uniform pattern its curves give it) raises
//! its `plain` bound and its largest bound over threshold, so the frame reports it in
//! [`FrameStats::max_predicted_error`](super::FrameStats::max_predicted_error), like a budget
//! fit, and every triangle's reported bound still covers it.

use super::storage::TriangleSlot;
use super::Tessellator;
use crate::domain::DomainIndex;
use crate::domain::DomainMesh;

impl TriangleSlot {
    /// The state of every triangle of a patch without states: factor 1, uncut, not judged on
    /// its own, within `bound` against threshold `c`.
    pub(super) fn plain(bound: f32, c: f32) -> TriangleSlot {
        let mut state = TriangleSlot::default();
        state.factor = 1;
        state.pieces = bound;
        state.threshold = c;
        state.margin = bound;
        state
    }
}

impl<Ix: DomainIndex> Tessellator<'_, '_, Ix> {
    /// Empties the arena for a new frame: no patch has states.
    pub(super) fn clear_states(&mut self) {
        self.states_taken = 0;
        self.states_wanted = 0;
        let count = self.baked.patch_count();
        for slot in self.storage.patches[..count].iter_mut() {
            slot.states = 0;
            slot.state_count = 0;
            slot.plain = slot.recorded;
            slot.short = false;
        }
    }

    /// Whether patch `p`'s triangles are to be judged on their own or hidden this frame:
    /// its prefix is exhausted, some side holds curve samples beyond its requests, or, in a
    /// refined frame, it is not wholly inside the view.
    pub(super) fn wants_states(&self, p: usize, refine: bool) -> bool {
        let slot = &self.storage.patches[p];
        let extra = (0..4).any(|s| slot.sides[s] > slot.requests[s]);
        !slot.culled && (slot.exhausted() || extra || (refine && !slot.inside))
    }

    /// Gives states to every patch that wants them ([`wants_states`](Self::wants_states)),
    /// if the arena holds them all; otherwise to the patches farthest over their thresholds
    /// first (recorded bound over threshold), each that still fits.
    pub(super) fn share_states(&mut self, refine: bool) {
        let count = self.baked.patch_count();
        let wanted: usize = (0..count)
            .filter(|&p| self.wants_states(p, refine))
            .map(|p| self.storage.patches[p].mesh.triangle_count())
            .sum();
        if wanted <= self.storage.triangle_states.len() {
            for p in 0..count {
                if self.wants_states(p, refine) {
                    self.give_states(p);
                }
            }
            return;
        }
        // (Quadratic in the patches, in frames short of states only.)
        loop {
            let mut best: Option<(f32, usize)> = None;
            for p in 0..count {
                if self.has_states(p)
                    || self.storage.patches[p].short
                    || !self.wants_states(p, refine)
                {
                    continue;
                }
                let slot = &self.storage.patches[p];
                let over = slot.recorded / slot.c;
                // (NaN, from a zero threshold and bound, counts as nothing over.)
                let over = if over.is_nan() { 0.0 } else { over };
                if best.is_none_or(|(b, _)| over > b) {
                    best = Some((over, p));
                }
            }
            let Some((_, p)) = best else {
                return;
            };
            self.give_states(p);
        }
    }

    /// Whether patch `p` has states this frame.
    pub(super) fn has_states(&self, p: usize) -> bool {
        self.storage.patches[p].state_count > 0
    }

    /// Gives patch `p` a state per live triangle, each [`TriangleSlot::plain`] of its bound,
    /// unless it has them already; its mesh is compacted first, so that its live triangles
    /// take its first triangle slots. False when the arena has no room for them.
    ///
    /// (A live count, unlike the slots a mesh's history leaves its triangles in, depends on
    /// the frame alone: so do which patches find room, and the frame's triangles.)
    pub(super) fn give_states(&mut self, p: usize) -> bool {
        if self.has_states(p) {
            return true;
        }
        let slot = self.storage.patches[p];
        let (start, count) = (self.states_taken, slot.mesh.triangle_count());
        if !slot.short {
            self.states_wanted += count;
        }
        if start + count > self.storage.triangle_states.len() {
            self.storage.patches[p].short = true;
            return false;
        }
        let mut mesh = DomainMesh::resume(
            &mut self.storage.vertices[slot.vertex_range()],
            &mut self.storage.triangles[slot.triangle_range()],
            slot.mesh,
        );
        mesh.compact(|_, _| {});
        let header = mesh.header();
        self.storage.triangle_states[start..start + count]
            .fill(TriangleSlot::plain(slot.plain, slot.c));
        let slot = &mut self.storage.patches[p];
        slot.mesh = header;
        slot.states = start as u32;
        // (A mesh's live triangles: at most `DomainIndex::MAX_SLOTS`.)
        slot.state_count = count as u16;
        self.states_taken = start + count;
        true
    }

    /// Triangle `t`'s state in patch `p` (its patch's plain one when it has none).
    pub(super) fn state(&self, p: usize, t: usize) -> TriangleSlot {
        let slot = &self.storage.patches[p];
        match slot
            .state_index(t)
            .and_then(|i| self.storage.triangle_states.get(i))
        {
            Some(&state) => state,
            None => TriangleSlot::plain(slot.plain, slot.c),
        }
    }

    /// Triangle `t`'s state in patch `p`, to change, if the patch has states.
    pub(super) fn state_mut(&mut self, p: usize, t: usize) -> Option<&mut TriangleSlot> {
        let i = self.storage.patches[p].state_index(t)?;
        self.storage.triangle_states.get_mut(i)
    }

    /// Writes triangle `t`'s state in patch `p` ([`PatchSlot::put_state`]).
    pub(super) fn put_state(&mut self, p: usize, t: usize, state: TriangleSlot) {
        self.storage.patches[p].put_state(self.storage.triangle_states, t, state);
    }
}
