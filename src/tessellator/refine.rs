//! Refinement: every triangle of the frame within its own threshold, by a computed bound.
//!
//! A triangle of a patch's baked prefix (one with no vertex that only a neighbour asked for)
//! is within the prefix's recorded bound, so within the patch's threshold `c`: it is left as
//! it is and costs nothing. Every other triangle (next to extra curve points, or anywhere in a
//! patch whose prefix does not reach `c`) is judged against its own threshold `c(T)`, from the
//! flat triangle of its corner points widened by the bound at hand (see [`crate::view`]), so a
//! triangle off the screen or behind the near plane asks for nothing and a near one for the
//! most. The cheapest bound that settles it is used, each one a bound on its own, tried in
//! this order:
//!
//! 1. a bound already at hand: the recorded bound for a prefix triangle (where the recorded
//!    value is the prefix's own, see `bake::interior`), and for any triangle the curvature
//!    term of the whole patch, `½ ρ²` from the patch's second-derivative bounds, plus the
//!    rounding slack (no surface point needed beyond the corners);
//! 2. the lattice of step 1/3 (10 points) with the whole patch's second derivatives in the
//!    remainder `½ ρ² / 9`;
//! 3. the full lattice ([`triangle_bound`]'s 28 points) with the whole patch's remainder;
//! 4. its own bound: the same samples with the patch cut to the triangle's box, whose smaller
//!    second derivatives give the tighter `½ ρ² / n²` for the pieces. Only this one chooses a
//!    factor above 1.
//!
//! 5. its bound on screen ([`crate::deviation`]'s `screen`: the same samples' deviation
//!    vectors projected at the view rays of the part of the triangle that can show), tried
//!    where step 4 asks for a factor of 2: a deviation along the line of sight moves no pixel,
//!    so a triangle facing the eye is often within the tolerance on screen while its
//!    object-space bound is not. It leaves the triangle uncut where that bound is within the
//!    tolerance; its threshold is then the one that puts its own bound at the same ratio (so
//!    the frame's statistics report the bound on screen). On the teapot at 1024x768 it
//!    leaves a third to four fifths of the factors of 2 uncut, about one in thirty of the
//!    factors of 3 and none above (measured 2026-11-24), so larger factors do not try it.
//!    Where a neighbour's factor cuts such a triangle after all (a non-uniform pattern), its
//!    pieces are held to the threshold of its own object-space bound, and where they are
//!    over, it takes the factor that bound chooses (see `agree`).
//!
//! Steps 1 to 3 leave a triangle uncut where their bound is within the threshold it implies.
//! Each step's value depends on the triangle alone, and the values computed are cached per
//! triangle slot while the triangle stays; the steps are always tried in the same order, so
//! the outcome is the same whether a value came from the cache or not (a frame does not
//! depend on earlier frames). On the teapot at 1024x768, 1 px, default bake, about a third of
//! the triangles that need a bound are settled at step 1 and most of the rest at steps 2 and
//! 3.
//!
//! A triangle whose own bound asks for a factor of 2 is halved instead, across the inner edge
//! whose halves have the smallest bound (below), where that is within its threshold, or else
//! has two inner edges halved (three pieces), where those fit: a cut into four can leave its
//! pieces far below the threshold. Each piece's bound samples the piece's lattice of step 1/3,
//! whose points, a third of a half, are points of the triangle's own lattice of step 1/6: the
//! halvings tried cost no surface point beyond the triangle's own bound. The neighbour across
//! a halved edge gets a pattern with that edge halved (two triangles; see `pattern`).
//!
//! Otherwise a triangle is cut uniformly by the smallest factor `n` whose pieces are within
//! `c(T)`: for `n` = 2, 3, 6 the bound's own samples bound the pieces; for any `n`, so does the
//! curvature term `½ ρ² / n²` plus the rounding slack (both in [`TriangleBound`]). Then the
//! edges agree on their factors, and the pieces of non-uniform patterns are bounded on their
//! own (see `agree`). The pieces' bounds, uniform and halved, are computed in `pieces`.
//!
//! A triangle whose threshold is infinite (its region, within the bound that judged it, is off
//! the view) is marked hidden and not written; in a patch not wholly inside the view, so is
//! a baked prefix triangle beyond one of the view's planes by more than the recorded bound
//! (see `emit`).
//!
//! The frame's statistics report the largest bound over threshold of every triangle written,
//! in the view's units: at most the tolerance unless refinement hit
//! [`Settings::max_factor`](super::Settings::max_factor).

use super::bound_cache::{CornerMemo, KNOW_COARSE, KNOW_WHOLE};
use super::pieces::{factor_for, halving, refined_bound};
use super::select::recorded;
use super::storage::TriangleSlot;
use super::{common_side, FrameStats, Tessellator};
use crate::deviation::{triangle_bound, Lattice, PatchBounds, PreparedBounds, TriangleBound};
use crate::domain::DomainIndex;
use crate::domain::GridPoint;
use crate::math;
use crate::model::EdgeLink;
use crate::patch::{BezierPatch, Side};
use crate::view::View;

/// The side a non-corner boundary point lies on.
pub(super) fn side_of(p: GridPoint) -> Option<Side> {
    let m = GridPoint::MAX;
    let on_u = p.u == 0 || p.u == m;
    let on_v = p.v == 0 || p.v == m;
    match (on_u, on_v) {
        (true, true) | (false, false) => None,
        (false, true) => Some(if p.v == 0 { Side::V0 } else { Side::V1 }),
        (true, false) => Some(if p.u == 0 { Side::U0 } else { Side::U1 }),
    }
}

/// The threshold of a triangle whose surface piece lies within `bound` of the flat triangle
/// of `points`.
pub(super) fn own_threshold(view: &View, tol: f32, points: [[f32; 3]; 3], bound: f32) -> f32 {
    let (scale, culled) = view.triangle_scale(points, bound);
    if culled {
        f32::INFINITY
    } else {
        tol * scale
    }
}

/// [`own_threshold`] with a triangle's own bound.
pub(super) fn threshold(view: &View, tol: f32, b: &TriangleBound) -> f32 {
    own_threshold(view, tol, b.points, b.bound())
}

/// What judging a triangle found.
struct Judged {
    /// Its factor.
    factor: u8,
    /// The bound of its pieces (object units).
    pieces: f32,
    /// The threshold it was judged against (infinite: off the view, with its surface piece).
    threshold: f32,
    /// Its own bound where used, with the bounds of the patch cut to its box where they were
    /// computed.
    own: Option<(TriangleBound, Option<PreparedBounds>)>,
    /// Left uncut by its bound on screen: `threshold` is the one that bound implies.
    on_screen: bool,
}

impl Judged {
    /// Uncut by a bound `bound` within threshold `c`.
    fn uncut(bound: f32, c: f32) -> Judged {
        Judged {
            factor: 1,
            pieces: bound,
            threshold: c,
            own: None,
            on_screen: false,
        }
    }
}

impl<Ix: DomainIndex> Tessellator<'_, '_, Ix> {
    /// The own bound of triangle `corners` of patch `patch` (index `p`), computed when the
    /// cache does not hold it.
    pub(super) fn bound_of(
        &mut self,
        p: usize,
        slot: usize,
        patch: &BezierPatch<'_>,
        corners: [GridPoint; 3],
        stats: &mut FrameStats,
    ) -> TriangleBound {
        let entry = self.bound_entry(p, slot, corners);
        if let Some(b) = entry.cached() {
            return b;
        }
        let b = triangle_bound(patch, corners);
        entry.keep_own(&b);
        stats.estimated += 1;
        b
    }

    /// Judges a triangle (in pool triangle slot `slot`) that needs a bound, by the cheapest bound that settles it (see the
    /// module docs): `at_hand` (step 1), then the coarse lattice and the full lattice with
    /// the whole patch's remainder `whole` (`curvature`: its curvature term on the triangle,
    /// computed once for the three steps), each leaving it uncut where it is within the
    /// threshold it implies, then its own bound, which chooses its factor. The steps and their
    /// values depend on the triangle and the view alone (computed values are cached, never
    /// replaced by others), so the outcome does not depend on what earlier frames cached.
    /// Returns the factor, the pieces' bound, the threshold, and the own bound where used
    /// (with the bounds of the patch cut to the triangle's box where they were computed).
    /// The samples are taken in `lattice` (of this patch: holding those of another triangle or
    /// none), for the caller to use again.
    #[allow(clippy::too_many_arguments)]
    fn judge(
        &mut self,
        p: usize,
        slot: usize,
        patch: &BezierPatch<'_>,
        lattice: &mut Lattice,
        corners: [GridPoint; 3],
        ids: [u16; 3],
        memo: &mut CornerMemo,
        whole: &PreparedBounds,
        curvature: f32,
        at_hand: f32,
        view: &View,
        tol: f32,
        max: u8,
        stats: &mut FrameStats,
    ) -> Judged {
        let uv = corners.map(GridPoint::to_unit);
        let state = self.bound_entry(p, slot, corners);
        let points = state.corner_points_memo(patch, ids, memo);
        // (In view coordinates once, for the thresholds of every step.)
        let viewed = view.view_triangle(points);
        let own_threshold = |bound: f32| {
            let (scale, culled) = view.viewed_triangle_scale(&viewed, bound);
            if culled {
                f32::INFINITY
            } else {
                tol * scale
            }
        };
        // 1. A bound at hand.
        let c = own_threshold(at_hand);
        if at_hand <= c {
            return Judged::uncut(at_hand, c);
        }
        // 2. The coarse lattice. One lattice, sampled in place once (and completed) where a
        // step needs it: steps 3 and 4 build on the samples of step 2.
        if state.known & KNOW_COARSE == 0 {
            lattice.sample_coarse_once(patch, corners, points);
            state.coarse = lattice.coarse_bound(curvature, whole.slack).bound();
            state.known |= KNOW_COARSE;
            stats.estimated += 1;
        }
        let c = own_threshold(state.coarse);
        if state.coarse <= c {
            return Judged::uncut(state.coarse, c);
        }
        // 3. The full lattice, with the whole patch's remainder.
        if state.known & KNOW_WHOLE == 0 {
            lattice.sample_coarse_once(patch, corners, points);
            lattice.complete(patch);
            state.whole = lattice.bound(curvature, whole.slack, false).bound();
            state.known |= KNOW_WHOLE;
        }
        let c = own_threshold(state.whole);
        if state.whole <= c {
            return Judged::uncut(state.whole, c);
        }
        // 4. Its own bound: the factor.
        let (b, local) = match state.cached() {
            Some(b) => (b, None),
            None => {
                lattice.sample_coarse_once(patch, corners, points);
                lattice.complete(patch);
                lattice.pieces();
                let local = PatchBounds::around(patch, uv).prepared();
                let b = lattice.bound(local.curvature_term(uv), local.slack, true);
                state.keep_own(&b);
                (b, Some(local))
            }
        };
        // (`b.points` are `points`: the same threshold as `threshold(view, tol, &b)`.)
        let c = own_threshold(b.bound());
        let f = factor_for(&b, c, max);
        // 5. Its bound on screen, from the same samples (see the module docs).
        if let (2, View::Screen { camera, .. }) = (f, view) {
            lattice.sample_coarse_once(patch, corners, points);
            lattice.complete(patch);
            let on_screen = lattice.screen_bound(camera, b.curvature, b.slack);
            if on_screen <= view.tolerance() {
                // The threshold that puts the bound at its ratio to the tolerance.
                // (Finite: an infinite threshold says the triangle is off the view.)
                let implied = if on_screen > 0.0 {
                    math::min(b.bound() * (view.tolerance() / on_screen), f32::MAX)
                } else {
                    f32::MAX
                };
                return Judged {
                    factor: 1,
                    pieces: b.bound(),
                    threshold: implied,
                    own: Some((b, local)),
                    on_screen: true,
                };
            }
        }
        Judged {
            factor: f,
            pieces: refined_bound(&b, f),
            threshold: c,
            own: Some((b, local)),
            on_screen: false,
        }
    }

    /// Chooses every triangle's and curve's refinement factor for `view` (factors 1 when
    /// `refine` is off), and the frame's largest bound over threshold per patch.
    pub(super) fn choose_factors(
        &mut self,
        view: &View,
        tol: f32,
        refine: bool,
        stats: &mut FrameStats,
    ) {
        let baked = self.baked;
        let max = if refine { self.settings.max_factor } else { 1 };
        for c in self.storage.curves[..baked.curve_count()].iter_mut() {
            c.factor = 1;
        }
        // States for the triangles judged on their own or hidden (see `states`); a patch
        // without them leaves every triangle uncut.
        self.clear_states();
        self.share_states(refine);
        // The samples of the last triangle judged, of the patch at hand.
        let mut lattice = Lattice::UNSAMPLED;
        // The corner points of the patch at hand's judged triangles.
        let mut memo = CornerMemo::EMPTY;
        for p in 0..baked.patch_count() {
            let mut slot = self.storage.patches[p];
            if slot.culled {
                continue;
            }
            let (Some(patch), Some(bp)) = (self.patches.patch(p), baked.patch(p)) else {
                continue;
            };
            let extra: [bool; 4] = core::array::from_fn(|s| slot.sides[s] > slot.requests[s]);
            let stated = self.has_states(p);
            let max = if stated { max } else { 1 };
            let exhausted = slot.exhausted();
            // The recorded list is a running minimum: a prefix's value is its own bound only
            // where it fell at its last step (the shortest prefix with that value), as it does
            // for every prefix chosen by a threshold, but not always for the whole list or a
            // capped prefix.
            let steps = slot.steps as usize;
            let own = (steps == 0 || recorded(&bp, steps) < recorded(&bp, steps - 1))
                .then(|| recorded(&bp, steps));
            slot.factor = 1;
            slot.settled = false;
            // The baked prefix's triangles are within its recorded bound.
            slot.error_ratio = if exhausted {
                0.0
            } else {
                slot.recorded / slot.c
            };
            // Without states, and with nothing to judge, every triangle is its prefix's, uncut.
            let (vo, tc) = (slot.vertex_offset as usize, slot.triangle_capacity as usize);
            // (The lattice knows the triangle it holds by its corners alone.)
            lattice.forget();
            memo.clear();
            // The whole patch's bounds, prepared once for its triangles.
            let mut whole = None;
            let tc = if stated || exhausted || extra.contains(&true) {
                tc
            } else {
                0
            };
            for t in 0..tc {
                let Some((v, n)) =
                    self.storage.triangles[slot.triangle_offset as usize + t].live_parts()
                else {
                    continue;
                };
                let corners = v.map(|id| self.storage.vertices[vo + id as usize].corner_point());
                let near_extra = corners
                    .iter()
                    .any(|&q| side_of(q).is_some_and(|s| extra[s.index()]));
                let mut state = TriangleSlot::plain(slot.recorded, slot.c);
                let needs = exhausted || near_extra;
                state.set_judged(needs);
                // Off the view (with its surface piece): not written in a refined frame.
                let hide = refine && !slot.inside && stated;
                if hide && !needs {
                    let points = self
                        .bound_entry(p, slot.triangle_offset as usize + t, corners)
                        .corner_points(&patch);
                    state.set_hidden(view.triangle_scale(points, slot.recorded).1);
                }
                let f = if needs {
                    // A bound at hand: the whole patch's curvature term, and the recorded
                    // bound for a prefix triangle.
                    let whole = *whole.get_or_insert_with(|| {
                        slot.whole
                            .get_or_insert_with(|| PatchBounds::of(&patch))
                            .prepared()
                    });
                    let uv = corners.map(GridPoint::to_unit);
                    let curvature = whole.curvature_term(uv);
                    let mut at_hand = curvature + whole.slack;
                    if let (false, Some(r)) = (near_extra, own) {
                        at_hand = math::min(at_hand, r);
                    }
                    let judged = self.judge(
                        p,
                        slot.triangle_offset as usize + t,
                        &patch,
                        &mut lattice,
                        corners,
                        v,
                        &mut memo,
                        &whole,
                        curvature,
                        at_hand,
                        view,
                        tol,
                        max,
                        stats,
                    );
                    let (f, pieces, c, own_bound) =
                        (judged.factor, judged.pieces, judged.threshold, judged.own);
                    state.set_on_screen(judged.on_screen);
                    state.threshold = c;
                    state.pieces = pieces;
                    // (An infinite threshold: the triangle, within the bound that judged
                    // it, is off the view.)
                    state.set_hidden(hide && c == f32::INFINITY);
                    state.margin = own_bound.map_or(pieces, |(b, _)| b.bound());
                    slot.error_ratio = math::max(slot.error_ratio, pieces / c);
                    // Cut in four, the pieces may sit far below the threshold: a halving is
                    // tried first (checked here, so one that would not do is not tried, and
                    // undone, in the rounds below). A neighbour across a halved edge gets a
                    // pattern with that edge halved, bounded in the rounds.
                    let cheaper = match own_bound {
                        Some((b, local)) if f == 2 => {
                            let local =
                                local.unwrap_or_else(|| PatchBounds::around(&patch, uv).prepared());
                            let inner = n.map(|x| x.is_some());
                            halving(&patch, &mut lattice, corners, b.points, &local, inner, c)
                        }
                        _ => None,
                    };
                    match cheaper {
                        Some(split) => {
                            state.set_split(split);
                            // (The patch is refined: no fast path for it.)
                            slot.factor = slot.factor.max(2);
                            1
                        }
                        None => f,
                    }
                } else {
                    1
                };
                state.factor = f;
                slot.factor = slot.factor.max(f);
                slot.put_state(self.storage.triangle_states, t, state);
                self.hand_to_curves(&bp.edges, corners, n, f);
            }
            self.storage.patches[p] = slot;
        }
        self.agree(view, tol, refine, stats);
        stats.triangle_states_needed = self.states_wanted;
        stats.patches_without_states = self.storage.patches[..baked.patch_count()]
            .iter()
            .filter(|slot| slot.short)
            .count();
    }

    /// Hands factor `f` of a triangle (corner points `corners`, neighbours `n`) to the curves
    /// along its boundary edges, for a patch whose sides are `edges`.
    pub(super) fn hand_to_curves(
        &mut self,
        edges: &[EdgeLink; 4],
        corners: [GridPoint; 3],
        n: [Option<u16>; 3],
        f: u8,
    ) {
        for i in 0..3 {
            if n[i].is_some() {
                continue;
            }
            let (a, b) = (corners[(i + 1) % 3], corners[(i + 2) % 3]);
            if let Some(side) = common_side(a, b) {
                if let EdgeLink::Curve { curve, .. } = edges[side.index()] {
                    let cs = &mut self.storage.curves[curve as usize];
                    cs.factor = cs.factor.max(f);
                }
            }
        }
    }
}
