//! A visible patch's output triangles: its points (corner nodes, curve points, domain
//! vertices, and the points that refinement adds on edges and inside triangles), their keys,
//! the factors of its edges, and the traversal of every piece its triangles are cut into.
//!
//! # What is off the view is not written
//!
//! In a refined frame ([`update`](super::Tessellator::update)), a patch whose control points'
//! hull is not wholly inside the view has its triangles checked against the view's planes
//! (near, left, right, bottom, top):
//!
//! - **A domain triangle** with corner points `P_0, P_1, P_2` has a bound `m` of its
//!   deviation (the one that judged it, or its prefix's recorded bound): its surface piece lies
//!   within `m` of the flat triangle `P`. Where every corner is farther than `m` beyond one
//!   plane, so is the whole flat triangle (a half-space is convex) and the surface piece: the
//!   triangle is left out with everything it would be cut into.
//! - **A piece** of a cut triangle, with barycentric corners `w_i` (in the triangle), has
//!   surface corners `S(q_i)`, each within `m` of `Σ_k w_ik P_k`, so its flat triangle lies
//!   within `m` of the flat triangle of those combinations, and its surface piece within `m`
//!   of `P` there. Where the combinations are all farther than `m` (plus their rounding,
//!   `8 ε` of the largest coordinate) beyond one plane, the piece is left out. No surface point
//!   is evaluated for the test, so the counting pass and the writing pass agree.
//!
//! A gap left this way has its edges beyond that plane: it is out of sight (the host tests
//! check every edge used once for it). Budget frames, which are not refined, write every
//! triangle, so their count stays the prediction. In the close-up of the teapot at 1024x768
//! (BENCHMARKS.md), this leaves 4% of the written triangles with nothing on screen, from 29%.

use super::pattern::{self, Local};
use super::storage::TriangleSlot;
use super::{along, common_side, Tessellator};
use crate::domain::DomainIndex;
use crate::domain::GridPoint;
use crate::model::EdgeLink;
use crate::patch::Side;
use crate::view::View;

/// Where an output point is and how to compute it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Point {
    /// A corner node.
    Node(u32),
    /// Curve `curve` at parameter `num / den`; `j` is its place along the curve's vertices.
    Curve {
        curve: u32,
        j: u32,
        num: u32,
        den: u32,
    },
    /// An interior domain vertex.
    Vertex { id: u16, p: GridPoint },
    /// Point `r` (from the edge's smaller end) of interior edge `edge` of triangle `slot`.
    Edge {
        slot: u32,
        edge: u8,
        r: u32,
        u: u32,
        v: u32,
        den: u32,
    },
    /// Inner point `k` of the current triangle.
    Face { k: u32, u: u32, v: u32, den: u32 },
}

pub(super) const MAX: u32 = GridPoint::MAX as u32;

/// One visible patch's view for the traversal.
pub(super) struct PatchView<'t, 'm, 's, Ix: DomainIndex = u16> {
    /// The patch.
    p: usize,
    pub(super) vo: usize,
    pub(super) to: usize,
    pub(super) tc: usize,
    edges: [EdgeLink; 4],
    nodes: [u32; 4],
    tess: &'t Tessellator<'m, 's, Ix>,
    /// The view whose hidden pieces [`refine`](Self::refine) leaves out (none: every piece).
    hide: Option<View>,
    /// Whether its triangles' states hold their agreed patterns (output views, made after
    /// agreement: see `agree::record_patterns`).
    recorded: bool,
    /// Where its triangles' states start in the arena and how many there are (0: it has
    /// none; see `states`).
    states: (usize, usize),
    /// The state of every triangle when it has none.
    plain: TriangleSlot,
}

impl<Ix: DomainIndex> PatchView<'_, '_, '_, Ix> {
    pub(super) fn point_of(&self, id: u16) -> GridPoint {
        self.tess.storage.vertices[self.vo + id as usize].corner_point()
    }

    pub(super) fn triangle(&self, t: usize) -> Option<([u16; 3], [Option<u16>; 3])> {
        self.tess.storage.triangles[self.to + t].live_parts()
    }

    /// Triangle `t`'s state this frame.
    pub(super) fn state(&self, t: usize) -> &TriangleSlot {
        let (start, count) = self.states;
        if t < count {
            &self.tess.storage.triangle_states[start + t]
        } else {
            &self.plain
        }
    }

    /// Whether triangle `t` is off the view this frame (not written).
    pub(super) fn hidden(&self, t: usize) -> bool {
        self.state(t).hidden()
    }

    pub(super) fn factor(&self, t: usize) -> u8 {
        self.state(t).factor.max(1)
    }

    /// The node a collapsed side maps to.
    fn side_node(&self, side: Side) -> u32 {
        self.nodes[side.index()]
    }

    /// Curve parameter and place of a boundary point on a curve side.
    fn curve_point(&self, curve: u32, reversed: bool, side: Side, p: GridPoint) -> (u32, u32) {
        let e = along(side, p);
        let t = if reversed { GridPoint::MAX - e } else { e } as u32;
        let cs = self.tess.storage.curves[curve as usize];
        let f = cs.factor.max(1) as u32;
        let j = if t == 0 {
            0
        } else if t == MAX {
            (cs.count as u32 + 1) * f
        } else {
            let off = cs.order_offset as usize;
            let order = &self.tess.storage.curve_order[off..off + cs.count as usize];
            (order.partition_point(|&x| (x as u32) < t) as u32 + 1) * f
        };
        (t, j)
    }

    /// A domain vertex as an output point.
    pub(super) fn vertex(&self, id: u16) -> Point {
        let p = self.point_of(id);
        if id < 4 {
            return Point::Node(self.nodes[id as usize]);
        }
        let side = if p.v == 0 {
            Some(Side::V0)
        } else if p.u == GridPoint::MAX {
            Some(Side::U1)
        } else if p.v == GridPoint::MAX {
            Some(Side::V1)
        } else if p.u == 0 {
            Some(Side::U0)
        } else {
            None
        };
        match side {
            None => Point::Vertex { id, p },
            Some(side) => match self.edges[side.index()] {
                EdgeLink::Collapsed => Point::Node(self.side_node(side)),
                EdgeLink::Curve { curve, reversed } => {
                    let (t, j) = self.curve_point(curve, reversed, side, p);
                    Point::Curve {
                        curve,
                        j,
                        num: t,
                        den: MAX,
                    }
                }
            },
        }
    }

    /// A key that names output point `q` of domain triangle `t` within the frame
    /// ([`TriangleSink::keyed_triangle`]): three tag bits, then what the point's data is a
    /// function of, so equal keys give equal bits. A corner node by its number; a curve point
    /// by its curve and parameter `num / (f * 65535)` (`num < 2^22`, `f <= 64`); an interior
    /// domain vertex by its pool slot; an edge point by its triangle's pool slot, edge and
    /// place (`r < 64`); a face point by its triangle's pool slot and index (`k < 2^11`).
    pub(super) fn key(&self, t: usize, q: Point) -> u64 {
        const TAG: u32 = 61;
        match q {
            Point::Node(n) => n as u64,
            Point::Curve {
                curve, num, den, ..
            } => {
                let f = (den / MAX) as u64;
                (1 << TAG) | (f << 54) | ((num as u64) << 32) | curve as u64
            }
            Point::Vertex { id, .. } => (2 << TAG) | (self.vo + id as usize) as u64,
            Point::Edge { slot, edge, r, .. } => {
                let slot = (self.to + slot as usize) as u64;
                (3 << TAG) | (slot << 8) | ((edge as u64) << 6) | r as u64
            }
            Point::Face { k, .. } => (4 << TAG) | (((self.to + t) as u64) << 11) | k as u64,
        }
    }

    /// Factor of edge `i` (opposite `v[i]`) of triangle `t`.
    pub(super) fn edge_factor(&self, t: usize, v: [u16; 3], n: [Option<u16>; 3], i: usize) -> u8 {
        let own = self.state(t);
        match n[i] {
            Some(nb) => {
                let nb = nb as usize;
                let other = self.state(nb);
                let f = own.factor.max(1).max(other.factor.max(1)).max(own.asked(i));
                if !other.halves() {
                    return f;
                }
                // The neighbour's side of the same edge (looked up only when it asks).
                let back = self.triangle(nb).and_then(|(_, nn)| {
                    (0..3)
                        .find(|&j| nn[j] == Some(t as u16))
                        .map(|j| other.asked(j))
                });
                f.max(back.unwrap_or(0))
            }
            None => {
                let (a, b) = (self.point_of(v[(i + 1) % 3]), self.point_of(v[(i + 2) % 3]));
                match common_side(a, b).map(|s| self.edges[s.index()]) {
                    Some(EdgeLink::Curve { curve, .. }) => {
                        self.tess.storage.curves[curve as usize].factor.max(1)
                    }
                    _ => own.factor.max(1),
                }
            }
        }
    }

    /// The inner factor and ring side factors (`pattern`'s `n` and `e`) domain triangle `t`,
    /// with corners `v` and neighbours `n`, is cut with, as [`refine`](Self::refine) finds
    /// them. (`refine` spells the same lines out: called from there, this function cost the
    /// firmware's render 14k instructions a frame, 2026-11-24.)
    pub(super) fn pattern_of(&self, t: usize, v: [u16; 3], n: [Option<u16>; 3]) -> (u8, [u8; 3]) {
        if self.tess.storage.patches[self.p].factor <= 1 {
            (1, [1; 3])
        } else if let Some(recorded) = self.recorded_pattern(t, v, n) {
            recorded
        } else {
            self.agreed_pattern(t, v, n)
        }
    }

    /// Triangle `t`'s factor and ring side factors, agreed from its and its neighbours'
    /// states now.
    #[inline(always)]
    fn agreed_pattern(&self, t: usize, v: [u16; 3], n: [Option<u16>; 3]) -> (u8, [u8; 3]) {
        // Ring side s is the edge opposite v[s+2].
        let e = [0, 1, 2].map(|s| self.edge_factor(t, v, n, (s + 2) % 3));
        (self.factor(t), e)
    }

    /// Triangle `t`'s pattern as agreement recorded it in its state, in an output view of a
    /// refined patch (none for a triangle without a state: it is agreed again). Debug builds
    /// check it against agreeing again.
    #[inline]
    fn recorded_pattern(
        &self,
        t: usize,
        v: [u16; 3],
        n: [Option<u16>; 3],
    ) -> Option<(u8, [u8; 3])> {
        let (start, count) = self.states;
        if !(self.recorded && t < count) {
            return None;
        }
        let [nf, e0, e1, e2] = self.tess.storage.triangle_states.get(start + t)?.pattern;
        debug_assert_eq!(
            (nf, [e0, e1, e2]),
            self.agreed_pattern(t, v, n),
            "patch {} triangle {t}: recorded pattern",
            self.p
        );
        Some((nf, [e0, e1, e2]))
    }

    /// [`edge_factor`](Self::edge_factor) for output: from the recorded pattern where there
    /// is one (edge `i` is ring side `i + 1`).
    pub(super) fn output_edge_factor(
        &self,
        t: usize,
        v: [u16; 3],
        n: [Option<u16>; 3],
        i: usize,
    ) -> u8 {
        match self.recorded_pattern(t, v, n) {
            Some((_, e)) => e[(i + 1) % 3],
            None => self.edge_factor(t, v, n, i),
        }
    }

    /// Whether [`refine`](Self::refine) writes every piece of every pattern: no piece is left
    /// out for the view, and none is flat. A piece is flat only where two of its points are
    /// one corner node, and the only nodes among a patch's points are its corners and the
    /// points of its collapsed sides: with no collapsed side and four distinct corner nodes,
    /// none is.
    pub(super) fn writes_every_piece(&self) -> bool {
        self.hide.is_none() && !self.may_flatten()
    }

    /// Whether a piece of this patch can be flat (two of its points one corner node): only
    /// with a collapsed side or two corners on one node.
    pub(super) fn may_flatten(&self) -> bool {
        let [a, b, c, d] = self.nodes;
        !(self
            .edges
            .iter()
            .all(|e| matches!(e, EdgeLink::Curve { .. }))
            && a != b
            && a != c
            && a != d
            && b != c
            && b != d
            && c != d)
    }

    /// The inner points and triangles [`refine`](Self::refine) gives domain triangle `t`,
    /// without walking its pattern, for a patch that
    /// [`writes_every_piece`](Self::writes_every_piece).
    pub(super) fn piece_counts(&self, t: usize) -> (u32, u32) {
        match self.triangle(t) {
            Some((v, n)) => {
                let (nf, e) = self.pattern_of(t, v, n);
                (pattern::inner_points(nf, e), pattern::triangle_count(nf, e))
            }
            None => (0, 0),
        }
    }

    /// Every refined triangle of domain triangle `t`, as output points; degenerate ones (two
    /// corners on one collapsed edge) are left out. `faces` receives the inner points first.
    ///
    /// (The callbacks are `dyn`: one copy of the traversal serves the writer, the stream and
    /// the bounds of the pieces. Measured 2026-11-24 on fw_teapot: 7.5 KB less kernel code at
    /// opt-level "s", for 8k more instructions in a frame of 9.7M.)
    pub(super) fn refine(
        &self,
        t: usize,
        faces: &mut dyn FnMut(Point),
        out: &mut dyn FnMut([Point; 3], [[u32; 3]; 3]),
    ) {
        let Some((v, n)) = self.triangle(t) else {
            return;
        };
        // The domain mesh lists every triangle from its smallest point on
        // (`DomainMesh::triangles`): the canonical order the patterns are cut in.
        let pr = v.map(|id| self.point_of(id));
        // Ring side s runs v[s] -> v[s+1]: the edge opposite v[s+2].
        let edge_of = |s: usize| (s + 2) % 3;
        // Nothing refined in or around the patch: every factor is 1 (as `emit`'s fast path).
        let (nf, e) = if self.tess.storage.patches[self.p].factor <= 1 {
            (1, [1; 3])
        } else if let Some(recorded) = self.recorded_pattern(t, v, n) {
            recorded
        } else {
            self.agreed_pattern(t, v, n)
        };
        let corner = v.map(|id| self.vertex(id));
        if nf == 1 && e == [1; 3] {
            // Unrefined: the triangle itself (what the pattern of factor 1 gives).
            let same =
                |x: Point, y: Point| matches!((x, y), (Point::Node(a), Point::Node(b)) if a == b);
            if !(same(corner[0], corner[1])
                || same(corner[1], corner[2])
                || same(corner[2], corner[0]))
            {
                out(corner, pr.map(|p| [p.u as u32, p.v as u32, MAX]));
            }
            return;
        }
        let lattice = |a: u32, b: u32, den_n: u32| {
            let i = den_n - a - b;
            let u = i * pr[0].u as u32 + a * pr[1].u as u32 + b * pr[2].u as u32;
            let w = i * pr[0].v as u32 + a * pr[1].v as u32 + b * pr[2].v as u32;
            (u, w, den_n * MAX)
        };
        let face = |p: Local| -> Point {
            let k = pattern::inner_index(nf, p).unwrap_or(0);
            let (u, w, den) = match p {
                Local::Lattice { a, b } => lattice(a as u32, b as u32, nf as u32),
                _ => lattice(1, 1, 3),
            };
            Point::Face { k, u, v: w, den }
        };
        // Where pieces off the view are left out: the corner points in the rotated order and
        // the margin (a piece's surface and flat triangle lie within it of the flat triangle
        // of its corners' barycentric combinations of `points`).
        let hide = self.hide.and_then(|view| {
            let state = self.state(t);
            let patch = self.tess.patches.patch(self.p)?;
            let points = self
                .tess
                .cached_corner_points(self.p, self.to + t, &patch, pr);
            // (With the rounding of the combinations.)
            let big = points.iter().flatten().fold(0.0f32, |m, &x| m.max(x.abs()));
            Some((view, points, state.margin + 8.0 * f32::EPSILON * big))
        });
        let weights = |l: Local| -> [f32; 3] {
            match l {
                Local::Corner(k) => {
                    let mut w = [0.0; 3];
                    w[k as usize % 3] = 1.0;
                    w
                }
                Local::Side { side, r } => {
                    let s = side as usize % 3;
                    let x = r as f32 / e[s] as f32;
                    let mut w = [0.0; 3];
                    w[s] = 1.0 - x;
                    w[(s + 1) % 3] = x;
                    w
                }
                Local::Lattice { a, b } => {
                    let n = nf as f32;
                    [(nf - a - b) as f32 / n, a as f32 / n, b as f32 / n]
                }
                Local::Centroid => [1.0 / 3.0; 3],
            }
        };
        let inner = pattern::inner_points(nf, e);
        if inner > 0 {
            if pattern::is_uniform(nf, e) || nf >= 3 {
                for b in 1..nf.saturating_sub(1) {
                    for a in 1..nf - b {
                        faces(face(Local::Lattice { a, b }));
                    }
                }
            } else {
                faces(face(Local::Centroid));
            }
        }
        let side_point = |s: u8, r: u8| -> Point {
            let s = s as usize;
            let f = e[s] as u32;
            let (a, b) = (pr[s], pr[(s + 1) % 3]);
            let i = edge_of(s);
            match n[i] {
                Some(_) => {
                    let (lo, hi, r) = if a < b {
                        (a, b, r as u32)
                    } else {
                        (b, a, f - r as u32)
                    };
                    Point::Edge {
                        slot: t as u32,
                        edge: i as u8,
                        r,
                        u: (f - r) * lo.u as u32 + r * hi.u as u32,
                        v: (f - r) * lo.v as u32 + r * hi.v as u32,
                        den: f * MAX,
                    }
                }
                None => {
                    let side = common_side(a, b).unwrap_or(Side::V0);
                    match self.edges[side.index()] {
                        EdgeLink::Collapsed => Point::Node(self.side_node(side)),
                        EdgeLink::Curve { curve, reversed } => {
                            let (ta, ja) = self.curve_point(curve, reversed, side, a);
                            let (tb, jb) = self.curve_point(curve, reversed, side, b);
                            let r = r as u32;
                            let (lo, hi, rl) = if ta < tb {
                                (ta, tb, r)
                            } else {
                                (tb, ta, f - r)
                            };
                            Point::Curve {
                                curve,
                                j: ja.min(jb) + rl,
                                num: (f - rl) * lo + rl * hi,
                                den: f * MAX,
                            }
                        }
                    }
                }
            }
        };
        // The point's own parameters in this patch, as `[u, v, denominator]`.
        let local = |l: Local| -> [u32; 3] {
            match l {
                Local::Corner(k) => [pr[k as usize].u as u32, pr[k as usize].v as u32, MAX],
                Local::Side { side, r } => {
                    let s = side as usize;
                    let (f, r) = (e[s] as u32, r as u32);
                    let (a, b) = (pr[s], pr[(s + 1) % 3]);
                    [
                        (f - r) * a.u as u32 + r * b.u as u32,
                        (f - r) * a.v as u32 + r * b.v as u32,
                        f * MAX,
                    ]
                }
                Local::Lattice { a, b } => {
                    let (u, v, d) = lattice(a as u32, b as u32, nf as u32);
                    [u, v, d]
                }
                Local::Centroid => {
                    let (u, v, d) = lattice(1, 1, 3);
                    [u, v, d]
                }
            }
        };
        pattern::for_each_triangle(nf, e, |tri| {
            if let Some((view, points, margin)) = hide {
                let flat = tri.map(|l| {
                    let w = weights(l);
                    core::array::from_fn(|c| {
                        w[0] * points[0][c] + w[1] * points[1][c] + w[2] * points[2][c]
                    })
                });
                if view.triangle_scale(flat, margin).1 {
                    return;
                }
            }
            let p = tri.map(|l| match l {
                Local::Corner(k) => corner[k as usize],
                Local::Side { side, r } => side_point(side, r),
                other => face(other),
            });
            let same =
                |x: Point, y: Point| matches!((x, y), (Point::Node(a), Point::Node(b)) if a == b);
            if same(p[0], p[1]) || same(p[1], p[2]) || same(p[2], p[0]) {
                return;
            }
            out(p, tri.map(local));
        });
    }
}

impl<'m, 's, Ix: DomainIndex> Tessellator<'m, 's, Ix> {
    pub(super) fn patch_view(&self, p: usize) -> Option<PatchView<'_, 'm, 's, Ix>> {
        self.patch_view_with(p, self.baked.patch_edges(p)?)
    }

    /// [`patch_view`](Self::patch_view) with the patch's sides at hand (read from the bake
    /// once, where a caller takes many views of one patch).
    pub(super) fn patch_view_with(
        &self,
        p: usize,
        edges: [EdgeLink; 4],
    ) -> Option<PatchView<'_, 'm, 's, Ix>> {
        let slot = self.storage.patches.get(p)?;
        if slot.culled {
            return None;
        }
        Some(PatchView {
            p,
            vo: slot.vertex_offset as usize,
            to: slot.triangle_offset as usize,
            tc: slot.triangle_capacity as usize,
            edges,
            nodes: slot.nodes,
            tess: self,
            hide: None,
            recorded: false,
            states: (slot.states as usize, slot.state_count as usize),
            plain: TriangleSlot::plain(slot.plain, slot.c),
        })
    }

    /// [`patch_view`](Self::patch_view) for output: in a refined frame of a patch not wholly
    /// inside the view, its pieces off the view are left out.
    pub(super) fn output_view(&self, p: usize) -> Option<PatchView<'_, 'm, 's, Ix>> {
        let mut view = self.patch_view(p)?;
        if self.refine && !self.storage.patches[p].inside {
            view.hide = self.view;
        }
        view.recorded = true;
        Some(view)
    }
}
