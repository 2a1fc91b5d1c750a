//! Refinement: every triangle of the frame within its own threshold, by a computed bound.
//!
//! A triangle of a patch's baked prefix (one with no vertex that only a neighbour asked for)
//! is within the prefix's recorded bound, so within the patch's threshold `c`: it is left as
//! it is and costs nothing. Every other triangle (next to extra curve points, or anywhere in a
//! patch whose prefix does not reach `c`) is judged against its own threshold `c(T)`, from the
//! flat triangle of its corner points widened by the bound at hand (see [`crate::view`]), so a
//! triangle off the screen or behind the near plane asks for nothing and a near one for the
//! most. The cheapest bound that settles it is used, each one a bound on its own:
//!
//! 1. a bound already at hand: the recorded bound for a prefix triangle, and for any triangle
//!    the curvature term of the whole patch, `½ ρ²` from the patch's second-derivative
//!    bounds, plus the rounding slack (no surface point needed beyond the corners);
//! 2. otherwise its own bound ([`triangle_bound`]: 28 surface points; cached per triangle slot
//!    while the triangle stays), first with the whole patch's second derivatives in the
//!    remainder, kept when it leaves the triangle uncut;
//! 3. and where it must be cut, the same samples with the patch cut to the triangle's box,
//!    whose smaller second derivatives give the tighter `½ ρ² / n²` for the pieces.
//!
//! Second derivatives over the whole patch are at least those over any part of it, so every
//! step's value is a bound, and a triangle that step 2 leaves uncut step 3 would too: the
//! stages save work (on the teapot at 1024x768, 1 px, default bake: a third of the triangles
//! settled at step 1, most of the rest at step 2) without cutting more.
//!
//! Such a triangle is cut uniformly by the smallest factor `n` whose pieces are within `c(T)`:
//! for `n` = 2, 3, 6 the bound's own samples bound the pieces; for any `n`, so does the
//! curvature term `½ ρ² / n²` plus the rounding slack (both in [`TriangleBound`]). Each edge
//! takes the larger factor of its two triangles and each curve the largest of the triangles
//! along it, so both sides of every edge place the same points (see `pattern`). A triangle
//! whose edges then differ from its inside is cut in a pattern whose pieces are not uniform:
//! each piece is bounded on its own, from its corners and edge midpoints and the curvature term
//! of the piece at a quarter (the same argument as the bound's, with a lattice of step 1/2),
//! first with the whole patch's second derivatives and, where a piece is over, with the
//! triangle's box; where one is still over, the triangle's factor grows and the edges are
//! agreed again. A round skips a patch whose factors and curve factors have not changed since
//! it was last checked, and a pattern keeps its bound for the frame once computed.
//!
//! The frame's statistics report the largest bound over threshold of every triangle written,
//! in the view's units: at most the tolerance unless refinement hit
//! [`Settings::max_factor`](super::Settings::max_factor).

use super::select::recorded;
use super::{common_side, FrameStats, Tessellator};
use crate::deviation::{triangle_bound, triangle_bound_staged, PatchBounds, TriangleBound};
use crate::domain::GridPoint;
use crate::math::{length, sqrt};
use crate::model::EdgeLink;
use crate::patch::{BezierPatch, Side};
use crate::view::View;

/// Rounds of agreeing edges and checking non-uniform patterns, at most.
const AGREE_ROUNDS: usize = 32;

/// The side a non-corner boundary point lies on.
fn side_of(p: GridPoint) -> Option<Side> {
    let m = GridPoint::MAX;
    let on_u = p.u == 0 || p.u == m;
    let on_v = p.v == 0 || p.v == m;
    match (on_u, on_v) {
        (true, true) | (false, false) => None,
        (false, true) => Some(if p.v == 0 { Side::V0 } else { Side::V1 }),
        (true, false) => Some(if p.u == 0 { Side::U0 } else { Side::U1 }),
    }
}

/// The bound of the pieces of a uniform refinement by `n`.
pub(super) fn refined_bound(b: &TriangleBound, n: u8) -> f32 {
    let general = b.curvature / (n as f32 * n as f32) + b.slack;
    let sampled = match n {
        1 => b.refined[0],
        2 => b.refined[1],
        3 => b.refined[2],
        6 => b.refined[3],
        _ => f32::INFINITY,
    };
    sampled.min(general)
}

/// The smallest factor up to `max` whose pieces are within `c` (or `max`).
fn factor_for(b: &TriangleBound, c: f32, max: u8) -> u8 {
    (1..=max).find(|&n| refined_bound(b, n) <= c).unwrap_or(max)
}

/// The threshold of a triangle whose surface piece lies within its bound of the flat
/// triangle of `b`'s points.
fn threshold(view: &View, tol: f32, b: &TriangleBound) -> f32 {
    let (scale, culled) = view.triangle_scale(b.points, b.bound());
    if culled {
        f32::INFINITY
    } else {
        tol * scale
    }
}

/// Bound of the piece `uv` of a triangle whose box has the bounds `local`: the piece's
/// corners and edge midpoints sampled, and a quarter of its curvature term.
fn piece_bound(patch: &BezierPatch<'_>, local: &PatchBounds, uv: [(f32, f32); 3]) -> f32 {
    let s = uv.map(|(u, v)| patch.position_direct(u, v));
    let mut worst = 0.0f32;
    for (a, b) in [(0, 1), (1, 2), (2, 0)] {
        let mid = patch.position_direct(0.5 * (uv[a].0 + uv[b].0), 0.5 * (uv[a].1 + uv[b].1));
        worst = worst.max(length(mid - (s[a] + s[b]) * 0.5));
    }
    worst + 0.25 * local.curvature_term(uv) + local.slack
}

impl Tessellator<'_, '_> {
    /// The bound of live triangle `t` of patch `p` with corners `corners`, computed when the
    /// cache does not hold it.
    fn bound_of(
        &mut self,
        patch: &BezierPatch<'_>,
        slot_index: usize,
        corners: [GridPoint; 3],
        stats: &mut FrameStats,
    ) -> TriangleBound {
        let state = &mut self.storage.triangle_states[slot_index];
        if let (Some(b), true) = (state.cached(corners), state.local) {
            return *b;
        }
        let b = triangle_bound(patch, corners);
        state.corners = corners;
        state.bound = b;
        state.known = true;
        state.local = true;
        stats.estimated += 1;
        b
    }

    /// [`bound_of`](Self::bound_of), except that a new bound is first tried with the whole
    /// patch's remainder `whole`, and kept where it is `good_enough` (see
    /// [`triangle_bound_staged`]).
    fn quick_bound_of(
        &mut self,
        patch: &BezierPatch<'_>,
        slot_index: usize,
        corners: [GridPoint; 3],
        stats: &mut FrameStats,
        whole: &PatchBounds,
        good_enough: impl Fn(&TriangleBound) -> bool,
    ) -> TriangleBound {
        let state = &mut self.storage.triangle_states[slot_index];
        if let Some(b) = state.cached(corners) {
            return *b;
        }
        let (b, local) = triangle_bound_staged(patch, corners, whole, good_enough);
        state.corners = corners;
        state.bound = b;
        state.known = true;
        state.local = local;
        stats.estimated += 1;
        b
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
        for p in 0..baked.patch_count() {
            let mut slot = self.storage.patches[p];
            if slot.culled {
                continue;
            }
            let (Some(patch), Some(bp)) = (self.patches.patch(p), baked.patch(p)) else {
                continue;
            };
            let extra: [bool; 4] = core::array::from_fn(|s| slot.sides[s] > slot.requests[s]);
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
            let (vo, to, tc) = (
                slot.vertex_offset as usize,
                slot.triangle_offset as usize,
                slot.triangle_capacity as usize,
            );
            // The whole patch's bounds, computed when first needed.
            let mut whole: Option<PatchBounds> = None;
            for t in 0..tc {
                let Some((v, n)) = self.storage.triangles[to + t].live_parts() else {
                    continue;
                };
                let corners = v.map(|id| {
                    self.storage.vertices[vo + id as usize]
                        .live_point()
                        .unwrap_or_default()
                });
                let near_extra = corners
                    .iter()
                    .any(|&q| side_of(q).is_some_and(|s| extra[s.index()]));
                let state = &mut self.storage.triangle_states[to + t];
                state.threshold = slot.c;
                state.pieces = slot.recorded;
                state.pattern = [0; 4];
                let needs = exhausted || near_extra;
                if let (false, Some(b)) = (needs, state.cached(corners).copied()) {
                    // A prefix triangle with a bound from an earlier frame: both hold.
                    state.threshold = slot.c.max(threshold(view, tol, &b));
                    state.pieces = slot.recorded.min(b.bound());
                }
                // Before computing a bound of its own, a triangle is accepted uncut when a
                // bound at hand is within its own threshold (the flat triangle of its corner
                // points widened by that bound): the recorded bound for a prefix triangle, and
                // the curvature term of the whole patch for any triangle.
                let quick = needs && state.cached(corners).is_none() && {
                    let uv = corners.map(GridPoint::to_unit);
                    let whole = whole.get_or_insert_with(|| PatchBounds::of(&patch));
                    let mut known = whole.curvature_term(uv) + whole.slack;
                    if let (false, Some(r)) = (near_extra, own) {
                        known = known.min(r);
                    }
                    let points = uv.map(|(u, v)| patch.position_direct(u, v).to_array());
                    let (scale, culled) = view.triangle_scale(points, known);
                    let c = if culled { f32::INFINITY } else { tol * scale };
                    let accept = known <= c;
                    if accept {
                        state.threshold = c;
                        state.pieces = known;
                        slot.error_ratio = slot.error_ratio.max(known / c);
                    }
                    accept
                };
                let f = if needs && !quick {
                    let whole = *whole.get_or_insert_with(|| PatchBounds::of(&patch));
                    let mut b = self.quick_bound_of(&patch, to + t, corners, stats, &whole, |b| {
                        refined_bound(b, 1) <= threshold(view, tol, b)
                    });
                    let mut c = threshold(view, tol, &b);
                    let mut f = factor_for(&b, c, max);
                    if f > 1 && !self.storage.triangle_states[to + t].local {
                        // Cut only with the triangle's own remainder.
                        b = self.bound_of(&patch, to + t, corners, stats);
                        c = threshold(view, tol, &b);
                        f = factor_for(&b, c, max);
                    }
                    let state = &mut self.storage.triangle_states[to + t];
                    state.threshold = c;
                    state.pieces = refined_bound(&b, f);
                    slot.error_ratio = slot.error_ratio.max(refined_bound(&b, f) / c);
                    f
                } else {
                    1
                };
                self.storage.triangle_states[to + t].factor = f;
                slot.factor = slot.factor.max(f);
                // Boundary edges hand their factor to the curve.
                for i in 0..3 {
                    if n[i].is_some() {
                        continue;
                    }
                    let (a, b) = (corners[(i + 1) % 3], corners[(i + 2) % 3]);
                    if let Some(side) = common_side(a, b) {
                        if let EdgeLink::Curve { curve, .. } = bp.edges[side.index()] {
                            let cs = &mut self.storage.curves[curve as usize];
                            cs.factor = cs.factor.max(f);
                        }
                    }
                }
            }
            self.storage.patches[p] = slot;
        }
        // Agree on edges and bound the pieces of non-uniform patterns, until nothing changes;
        // the last round leaves every patch's largest bound over threshold.
        let mut settled = false;
        for _ in 0..AGREE_ROUNDS {
            if !self.check_patterns(view, tol, refine, stats) {
                settled = true;
                break;
            }
        }
        if !settled {
            self.check_patterns(view, tol, false, stats);
        }
        self.spread_curve_factors();
    }

    /// A curve's factor can exceed every triangle's along it in one patch: that patch is
    /// refined too.
    fn spread_curve_factors(&mut self) {
        let baked = self.baked;
        for p in 0..baked.patch_count() {
            if self.storage.patches[p].culled {
                continue;
            }
            if let Some(bp) = baked.patch(p) {
                for link in bp.edges {
                    if let EdgeLink::Curve { curve, .. } = link {
                        let f = self.storage.curves[curve as usize].factor;
                        let slot = &mut self.storage.patches[p];
                        slot.factor = slot.factor.max(f);
                    }
                }
            }
        }
    }

    /// One round of agreement: every triangle's bound over threshold for the factors of the
    /// moment; a triangle cut in a non-uniform pattern has each piece bounded, and one with a
    /// piece over its threshold gets a larger factor (and hands it to its curves). Returns
    /// whether any factor changed.
    fn check_patterns(
        &mut self,
        view: &View,
        tol: f32,
        allow_raise: bool,
        stats: &mut FrameStats,
    ) -> bool {
        let baked = self.baked;
        let max = self.settings.max_factor;
        let mut changed = false;
        for p in 0..baked.patch_count() {
            let slot = self.storage.patches[p];
            if slot.culled {
                continue;
            }
            let Some(patch) = self.patches.patch(p) else {
                continue;
            };
            let (vo, to, tc) = (
                slot.vertex_offset as usize,
                slot.triangle_offset as usize,
                slot.triangle_capacity as usize,
            );
            // Nothing changed since the patch was last checked: its patterns and bounds stand.
            let curve_factors = baked.patch(p).map_or([1; 4], |bp| {
                bp.edges.map(|link| match link {
                    EdgeLink::Curve { curve, .. } => self.storage.curves[curve as usize].factor,
                    EdgeLink::Collapsed => 1,
                })
            });
            if slot.settled && slot.checked_curves == curve_factors {
                continue;
            }
            self.storage.patches[p].settled = true;
            self.storage.patches[p].checked_curves = curve_factors;
            let mut worst_ratio = if slot.exhausted() {
                0.0
            } else {
                slot.recorded / slot.c
            };
            // Without a factor above 1 in the patch or on its curves, every pattern is the
            // triangle itself.
            let curve_factor = curve_factors.into_iter().max().unwrap_or(1);
            // The whole patch's bounds, computed when first needed.
            let mut whole: Option<PatchBounds> = None;
            let plain = curve_factor <= 1
                && (0..tc).all(|t| self.storage.triangle_states[to + t].factor <= 1);
            for t in 0..tc {
                let Some((v, _)) = self.storage.triangles[to + t].live_parts() else {
                    continue;
                };
                let corners = v.map(|id| {
                    self.storage.vertices[vo + id as usize]
                        .live_point()
                        .unwrap_or_default()
                });
                let state = &mut self.storage.triangle_states[to + t];
                let f = state.factor.max(1);
                if plain {
                    // Uncut: `pieces` and `threshold` are as `choose_factors` left them.
                    worst_ratio = worst_ratio.max(state.pieces / state.threshold);
                    continue;
                }
                let mut bound = state.cached(corners).copied();
                let n = self.storage.triangles[to + t]
                    .live_parts()
                    .map_or([None; 3], |x| x.1);
                let edges = self
                    .patch_view(p)
                    .map(|view_p| [0, 1, 2].map(|i| view_p.edge_factor(t, v, n, i)));
                let uniform = edges.is_none_or(|e| e == [f; 3]);
                if !uniform && bound.is_none() {
                    // Its pieces are judged at its own depth, not at its patch's nearest.
                    let b = self.bound_of(&patch, to + t, corners, stats);
                    self.storage.triangle_states[to + t].threshold = threshold(view, tol, &b);
                    bound = Some(b);
                }
                let c = self.storage.triangle_states[to + t].threshold;
                // Pieces of a non-uniform pattern, each bounded on its own.
                // (A pattern already bounded this frame keeps its bound.)
                let mut pieces = None;
                let mut computed = None;
                let known = self.storage.triangle_states[to + t];
                if let (Some(view_p), Some(edges)) = (self.patch_view(p), edges) {
                    let key = [f, edges[0], edges[1], edges[2]];
                    if edges != [f; 3] && known.pattern == key {
                        pieces = Some(known.pieces);
                    } else if edges != [f; 3] {
                        computed = Some(key);
                        // First with the whole patch's remainder; cut to the triangle's box
                        // only where that is over the threshold.
                        let whole = *whole.get_or_insert_with(|| PatchBounds::of(&patch));
                        let worst_with = |bounds: &PatchBounds| {
                            let mut worst = 0.0f32;
                            view_p.refine(
                                t,
                                |_| {},
                                |_, local_uv| {
                                    let piece = local_uv.map(|[u, v, d]| {
                                        (u as f32 / d as f32, v as f32 / d as f32)
                                    });
                                    worst = worst.max(piece_bound(&patch, bounds, piece));
                                },
                            );
                            worst
                        };
                        let mut worst = worst_with(&whole);
                        if worst > c {
                            let local =
                                PatchBounds::around(&patch, corners.map(GridPoint::to_unit));
                            worst = worst.min(worst_with(&local));
                        }
                        pieces = Some(worst);
                    }
                }
                if let Some(key) = computed {
                    self.storage.triangle_states[to + t].pattern = key;
                    stats.estimated += 1;
                }
                let piece_bound = match (pieces, bound) {
                    (Some(worst), _) => {
                        if allow_raise && worst > c && f < max {
                            // Pieces shrink about as the factor grows.
                            let grow = libm::ceilf(f as f32 * sqrt(worst / c));
                            let next = if grow >= max as f32 {
                                max
                            } else {
                                (grow as u8).max(f + 1)
                            };
                            changed = true;
                            self.raise_factor(p, t, next, view, tol, stats);
                            continue;
                        }
                        worst
                    }
                    // Uncut, with a bound at hand too: the smaller.
                    (None, Some(b)) if f == 1 => {
                        refined_bound(&b, 1).min(self.storage.triangle_states[to + t].pieces)
                    }
                    (None, Some(b)) => refined_bound(&b, f),
                    // Uncut without a bound of its own: a baked prefix triangle within the
                    // recorded bound, or one accepted by a bound at hand (`choose_factors`).
                    (None, None) => self.storage.triangle_states[to + t].pieces,
                };
                self.storage.triangle_states[to + t].pieces = piece_bound;
                worst_ratio = worst_ratio.max(piece_bound / c);
            }
            self.storage.patches[p].error_ratio = worst_ratio;
        }
        changed
    }

    /// Sets triangle `t` of patch `p` to factor `f` (computing its bound if it has none) and
    /// hands the factor to the curves along it.
    fn raise_factor(
        &mut self,
        p: usize,
        t: usize,
        f: u8,
        view: &View,
        tol: f32,
        stats: &mut FrameStats,
    ) {
        let Some(patch) = self.patches.patch(p) else {
            return;
        };
        let Some(bp) = self.baked.patch(p) else {
            return;
        };
        let slot = self.storage.patches[p];
        let (vo, to) = (slot.vertex_offset as usize, slot.triangle_offset as usize);
        let Some((v, n)) = self.storage.triangles[to + t].live_parts() else {
            return;
        };
        let corners = v.map(|id| {
            self.storage.vertices[vo + id as usize]
                .live_point()
                .unwrap_or_default()
        });
        let b = self.bound_of(&patch, to + t, corners, stats);
        let state = &mut self.storage.triangle_states[to + t];
        state.threshold = threshold(view, tol, &b);
        state.factor = f;
        self.storage.patches[p].settled = false;
        let s = &mut self.storage.patches[p];
        s.factor = s.factor.max(f);
        for i in 0..3 {
            if n[i].is_some() {
                continue;
            }
            let (a, b) = (corners[(i + 1) % 3], corners[(i + 2) % 3]);
            if let Some(side) = common_side(a, b) {
                if let EdgeLink::Curve { curve, .. } = bp.edges[side.index()] {
                    let cs = &mut self.storage.curves[curve as usize];
                    cs.factor = cs.factor.max(f);
                }
            }
        }
    }
}
