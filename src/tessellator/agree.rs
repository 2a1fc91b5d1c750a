//! Agreement: every edge takes one factor from both its sides, every piece of a non-uniform
//! pattern is bounded on its own, and factors grow until every piece is within its threshold.
//!
//! Each edge takes the larger factor of its two triangles (and any halving asked of it) and
//! each curve the largest of the triangles along it, so both sides of every edge place the same
//! points (see `pattern`). A triangle whose edges then differ from its inside is cut in a
//! pattern whose pieces are not uniform: each piece is bounded on its own, from the lattice of
//! step 1/3 on the piece (7 points besides its corners) and a ninth of the piece's curvature
//! term (the same argument as the bound's, see `refine`; the coarser step 1/2 left most
//! halvings and their neighbours over), first with the whole patch's second derivatives and,
//! where a piece is over, with the triangle's box; where one is still over, the triangle's
//! factor grows and the edges are agreed again. The factors a round raises are applied when
//! the round ends, so every triangle of a round sees the same factors and the result does not
//! depend on the order of the triangles in storage. A round skips a patch whose factors and
//! curve factors have not changed since it was last checked, and a pattern keeps its bound for
//! the frame once computed.

use super::pieces::{factor_for, piece_bound, refined_bound};
use super::refine::{own_threshold, threshold};
use super::{FrameStats, Tessellator};
use crate::deviation::PatchBounds;
use crate::domain::DomainIndex;
use crate::domain::GridPoint;
use crate::math::{self, sqrt};
use crate::model::EdgeLink;
use crate::view::View;

/// Rounds of agreeing edges and checking non-uniform patterns, at most.
const AGREE_ROUNDS: usize = 32;

impl<Ix: DomainIndex> Tessellator<'_, '_, Ix> {
    /// Agrees on edges and bounds the pieces of non-uniform patterns, until nothing changes
    /// (raising factors only while `refine`); the last round leaves every patch's largest
    /// bound over threshold.
    pub(super) fn agree(&mut self, view: &View, tol: f32, refine: bool, stats: &mut FrameStats) {
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
        self.record_patterns();
    }

    /// Records every stated triangle's agreed pattern in its state
    /// ([`TriangleSlot::pattern`](super::storage::TriangleSlot)): the output passes (counting,
    /// writing, streaming) read it rather than agree on each edge again.
    fn record_patterns(&mut self) {
        let baked = self.baked;
        for p in 0..baked.patch_count() {
            let slot = self.storage.patches[p];
            if slot.culled || slot.factor <= 1 {
                continue;
            }
            let Some(sides) = baked.patch_edges(p) else {
                continue;
            };
            for t in 0..slot.state_count as usize {
                let pattern = self.patch_view_with(p, sides).and_then(|view_p| {
                    let (v, n) = view_p.triangle(t)?;
                    let (nf, e) = view_p.pattern_of(t, v, n);
                    Some([nf, e[0], e[1], e[2]])
                });
                if let (Some(pattern), Some(state)) = (pattern, self.state_mut(p, t)) {
                    state.pattern = pattern;
                }
            }
        }
    }

    /// A curve's factor can exceed every triangle's along it in one patch: that patch is
    /// refined too.
    fn spread_curve_factors(&mut self) {
        let baked = self.baked;
        for p in 0..baked.patch_count() {
            if self.storage.patches[p].culled {
                continue;
            }
            if let Some(edges) = baked.patch_edges(p) {
                for link in edges {
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
        let mut changed = false;
        for p in 0..baked.patch_count() {
            if self.storage.patches[p].culled {
                continue;
            }
            let Some(patch) = self.patches.patch(p) else {
                continue;
            };
            // Nothing changed since the patch was last checked: its patterns and bounds stand.
            let Some(sides) = baked.patch_edges(p) else {
                continue;
            };
            let curve_factors = sides.map(|link| match link {
                EdgeLink::Curve { curve, .. } => self.storage.curves[curve as usize].factor,
                EdgeLink::Collapsed => 1,
            });
            let here = &self.storage.patches[p];
            if here.settled && here.checked_curves == curve_factors {
                continue;
            }
            // Without a factor above 1 in the patch or on its curves, every pattern is the
            // triangle itself. A patch cut by its curves alone takes states now (see `states`).
            let curve_factor = curve_factors.into_iter().max().unwrap_or(1);
            // (A patch without states has no factor above 1 and no halved edge.)
            let cut = curve_factor > 1
                || (0..here.state_count as usize).any(|t| {
                    let state = self.state(p, t);
                    state.factor > 1 || state.halves()
                });
            if cut {
                self.give_states(p);
            }
            let stated = self.has_states(p);
            let max = if stated { self.settings.max_factor } else { 1 };
            self.storage.patches[p].settled = true;
            self.storage.patches[p].checked_curves = curve_factors;
            if !cut && !stated {
                // Uncut, and its bound over threshold is what `choose_factors` found.
                continue;
            }
            let slot = self.storage.patches[p];
            let (vo, to, tc) = (
                slot.vertex_offset as usize,
                slot.triangle_offset as usize,
                slot.triangle_capacity as usize,
            );

            let mut worst_ratio = if !stated {
                // What `choose_factors` found (its rounds only add to it).
                slot.error_ratio
            } else if slot.exhausted() {
                0.0
            } else {
                slot.recorded / slot.c
            };
            let mut whole = None;
            for t in 0..tc {
                let Some((v, n)) = self.storage.triangles[to + t].live_parts() else {
                    continue;
                };
                let corners = v.map(|id| self.storage.vertices[vo + id as usize].corner_point());
                let mut state = self.state(p, t);
                let f = state.factor.max(1);
                if !cut {
                    // Uncut: `pieces` and `threshold` are as `choose_factors` left them.
                    if stated {
                        worst_ratio = math::max(worst_ratio, state.pieces / state.threshold);
                    }
                    continue;
                }
                let mut bound = self.bound_entry(p, to + t, corners).cached();
                let edges = self
                    .patch_view_with(p, sides)
                    .map(|view_p| [0, 1, 2].map(|i| view_p.edge_factor(t, v, n, i)));
                let uniform = edges.is_none_or(|e| e == [f; 3]);
                // (For a triangle left uncut by its bound on screen and cut after all.)
                let mut isotropic = None;
                if !uniform {
                    // Its pieces are judged at its own depth, not at its patch's nearest: a
                    // cut triangle by its own bound (which chose its factor), an uncut one by
                    // the threshold it was judged with, or, for a baked prefix triangle, the
                    // one the recorded bound gives at its corners.
                    // One left uncut by its bound on screen and cut after all has its
                    // pieces held to the threshold of its own object-space bound.
                    if f > 1 {
                        let b = self.bound_of(p, to + t, &patch, corners, stats);
                        state.threshold = threshold(view, tol, &b);
                        bound = Some(b);
                    } else if state.on_screen() {
                        // Its own threshold is the one its own bound gives (its margin),
                        // computed again each round: uncut, it keeps the one its bound on
                        // screen implies.
                        let points = self.bound_entry(p, to + t, corners).corner_points(&patch);
                        isotropic = Some(own_threshold(view, tol, points, state.margin));
                    } else if !state.judged() {
                        let points = self.bound_entry(p, to + t, corners).corner_points(&patch);
                        // (Every triangle of a patch without states is within `plain`.)
                        let margin = if stated { slot.recorded } else { slot.plain };
                        let own = own_threshold(view, tol, points, margin);
                        state.threshold = math::max(slot.c, own);
                    }
                }
                let c = isotropic.unwrap_or(state.threshold);
                // Pieces of a non-uniform pattern, each bounded on its own.
                // (A pattern already bounded this frame keeps its bound.)
                let mut pieces = None;
                let mut computed = None;
                // The whole patch's bounds (cached in its slot, prepared once for the
                // patch) where a pattern is new.
                if whole.is_none()
                    && edges.is_some_and(|e| e != [f; 3] && state.pattern != [f, e[0], e[1], e[2]])
                {
                    whole = Some(
                        self.storage.patches[p]
                            .whole
                            .get_or_insert_with(|| PatchBounds::of(&patch))
                            .prepared(),
                    );
                }
                if let (Some(view_p), Some(edges)) = (self.patch_view_with(p, sides), edges) {
                    let key = [f, edges[0], edges[1], edges[2]];
                    if edges != [f; 3] && state.pattern == key {
                        pieces = Some(state.pieces);
                    } else if edges != [f; 3] {
                        computed = Some(key);
                        // Each piece first with the whole patch's remainder, and where that
                        // is over, with the triangle's box (cut once, where first needed).
                        let whole = whole.unwrap_or_else(|| PatchBounds::of(&patch).prepared());
                        let tri = corners.map(GridPoint::to_unit);
                        let mut local = None;
                        let mut worst = 0.0f32;
                        view_p.refine(t, &mut |_| {}, &mut |_, local_uv| {
                            let piece = local_uv
                                .map(|[u, v, d]| (u as f32 / d as f32, v as f32 / d as f32));
                            let b = piece_bound(&patch, &whole, &mut local, tri, piece, c);
                            worst = math::max(worst, b);
                        });
                        pieces = Some(worst);
                    }
                }
                if let Some(key) = computed {
                    state.pattern = key;
                    stats.estimated += 1;
                }
                let piece_bound = match (pieces, bound) {
                    (Some(worst), _) => {
                        if allow_raise && worst > c && f < max {
                            // Pieces shrink about as the factor grows.
                            let grow = libm::ceilf(f as f32 * sqrt(worst / c));
                            let next = if f == 1 && state.halves() {
                                // A halving that was not enough: the uniform cut its own
                                // bound chose.
                                2
                            } else if state.on_screen() {
                                // Left uncut by its bound on screen, over its own threshold:
                                // the uniform cut its own bound chooses (whose pieces are
                                // within it).
                                let b = self.bound_of(p, to + t, &patch, corners, stats);
                                factor_for(&b, c, max).max(2)
                            } else if grow >= max as f32 {
                                max
                            } else {
                                (grow as u8).max(f + 1)
                            };
                            // Applied after the round, so that every triangle of a round
                            // sees the same factors (the outcome does not depend on the
                            // order of the triangles in storage).
                            changed = true;
                            state.pending = next;
                            self.put_state(p, t, state);
                            continue;
                        }
                        worst
                    }
                    // Cut uniformly: by its own bound, which chose the factor.
                    (None, Some(b)) if f > 1 => refined_bound(&b, f),
                    // Uncut: a baked prefix triangle within the recorded bound, or one
                    // judged uncut in `choose_factors` (by whichever bound settled it). (In a
                    // patch without states, `choose_factors` counted it.)
                    (None, _) if !stated => continue,
                    (None, _) => state.pieces,
                };
                state.pieces = piece_bound;
                self.put_state(p, t, state);
                worst_ratio = math::max(worst_ratio, piece_bound / c);
            }
            self.storage.patches[p].error_ratio = worst_ratio;
        }
        if changed {
            for p in 0..baked.patch_count() {
                let slot = self.storage.patches[p];
                if slot.culled {
                    continue;
                }
                for t in 0..slot.triangle_capacity as usize {
                    let Some(state) = self.state_mut(p, t) else {
                        break;
                    };
                    let next = state.pending;
                    if next > 0 {
                        state.pending = 0;
                        self.raise_factor(p, t, next, view, tol, stats);
                    }
                }
            }
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
        let Some(edges) = self.baked.patch_edges(p) else {
            return;
        };
        let slot = self.storage.patches[p];
        let (vo, to) = (slot.vertex_offset as usize, slot.triangle_offset as usize);
        let Some((v, n)) = self.storage.triangles[to + t].live_parts() else {
            return;
        };
        let corners = v.map(|id| self.storage.vertices[vo + id as usize].corner_point());
        let b = self.bound_of(p, to + t, &patch, corners, stats);
        let Some(state) = self.state_mut(p, t) else {
            return;
        };
        state.threshold = threshold(view, tol, &b);
        state.set_on_screen(false);
        // Cut uniformly, its pieces are within this (a round that finds it in a non-uniform
        // pattern bounds that pattern's pieces instead).
        state.pieces = refined_bound(&b, f);
        state.factor = f;
        self.storage.patches[p].settled = false;
        let s = &mut self.storage.patches[p];
        s.factor = s.factor.max(f);
        self.hand_to_curves(&edges, corners, n, f);
    }
}
