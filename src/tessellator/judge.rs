//! How a triangle of the hierarchy is judged in a view: its bound, and whether nothing of it
//! can show.
//!
//! The bound is the node's kept vectors and remainder (see `kept`) put through the bounds of
//! the `deviation` module: in model units, the longest vector plus the remainder; on screen,
//! the vectors projected one by one at the view rays of the flat triangle's part that can
//! show (`deviation/screen.rs`, which derives it for any vectors whose hull, widened by the
//! remainder, holds the deviation). Its corners' recorded points are the flat triangle that is
//! written out, and the points the bake measured the vectors against.
//!
//! A triangle is hidden when its three corners lie beyond one plane of the view (the near
//! plane, or a side plane) by more than its longest vector plus the remainder plus the
//! rounding of the move into view coordinates: the surface piece is within that of the flat
//! triangle, so all of it lies beyond that plane. It is not written out, and its bound on
//! screen is 0 (nothing of it counts). Its sides that other triangles share lie beyond the same
//! plane: a gap there is out of sight.

use glam::Vec3;

use super::address::ONE;
use super::grid_judge::{FirstLook, GridJudge, KeptQuotient, Seen, Sight};
use super::hierarchy::{Hierarchy, Pending};
use super::select::Tessellator;
use crate::deviation::certificate::{Asked, Lasting};
use crate::deviation::kept::longest_of;
use crate::deviation::lattice::{deviation_vectors, RUN_TIME_POINTS, RUN_TIME_STEPS};
use crate::deviation::vectors::{Deviations, NodeVectors, Quantised};
use crate::deviation::{bound_on_screen, isotropic_bound_on_screen, view_extent, EPS};
use crate::view::{Camera, Projection, View};
use crate::Arithmetic;

/// A triangle's bound in a view's units (pixels or model units), and whether it is hidden.
#[derive(Clone, Copy, Debug)]
pub(super) struct Judged {
    /// The bound; unless judged `exact`, only a value over the tolerance where the bound is.
    pub bound: Bound,
    pub hidden: bool,
    /// Where certificates were asked for (see `reuse`): the largest of the steps asked for
    /// over which this judgement (over the tolerance or not) is certain.
    pub lasting: Option<Lasting>,
}

impl Judged {
    /// A judgement with no certificate.
    pub(super) const fn bare(bound: f32, hidden: bool) -> Judged {
        Judged {
            bound: Bound::Value(bound),
            hidden,
            lasting: None,
        }
    }
}

/// A judgement's bound: a value, or a first look's quotient within the tolerance, divided
/// out only where it is read (see `grid_judge::WithinQuotient`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Bound {
    /// This value.
    Value(f32),
    /// Within the view's tolerance by a first look, with this bound. (Never made where
    /// nothing is kept.)
    #[allow(dead_code)]
    Within(KeptQuotient),
}

impl Bound {
    /// The bound's value.
    pub fn value(self) -> f32 {
        match self {
            Bound::Value(b) => b,
            Bound::Within(q) => q.value(),
        }
    }

    /// Whether it is over `tolerance`, the view's, or not a number.
    pub fn is_over(self, tolerance: f32) -> bool {
        match self {
            Bound::Value(b) => b > tolerance || b.is_nan(),
            Bound::Within(_) => false,
        }
    }
}

/// What a judgement reads of a frame: the hierarchy, the arithmetic of its bounds, which
/// patches the frame culls, and its vertices' points, moved into view coordinates through
/// whatever cache of them it keeps. A tessellator is one; the threads of a step are others
/// (see `step`), each with a cache of its own.
pub(super) trait Frame {
    /// The hierarchy.
    fn tree(&self) -> &Hierarchy<'_>;
    /// How bounds are computed from the kept vectors.
    fn arithmetic(&self) -> Arithmetic;
    /// Whether the frame culls patch `patch` (see `cull`).
    fn is_culled(&self, patch: u32) -> bool;
    /// The point of vertex `v`.
    fn position(&self, v: u32) -> [f32; 3];
    /// Vertex `v`, whose point `p` gives, in `camera`'s view coordinates: the same bits as
    /// `camera.to_view(p())`, from a cache of the frame's where it keeps one.
    fn viewed(&self, v: u32, p: impl FnOnce() -> Vec3, camera: &Camera) -> Vec3;
    /// The frame's move of the bake's points in integers, where it makes one (see
    /// `grid_view`): then corners come from [`viewed_on_grid`](Self::viewed_on_grid).
    fn grid_view(&self) -> Option<&super::grid_view::GridView> {
        None
    }
    /// [`viewed`](Self::viewed), the bake's points moved by `grid`: within its
    /// [`slack`](super::grid_view::GridView::slack) of those bits. (From
    /// [`fixed_on_grid`](Self::fixed_on_grid); a point off the grid, below the bake, is moved
    /// in `f32`.)
    fn viewed_on_grid(
        &self,
        v: u32,
        grid: &super::grid_view::GridView,
        p: impl FnOnce() -> Vec3,
        camera: &Camera,
    ) -> Vec3 {
        match self.fixed_on_grid(v, grid) {
            Some(fixed) => grid.point_of(fixed),
            None => camera.to_view(p()),
        }
    }
    /// The frame's constants for a first look in integers, where it takes one (see
    /// `grid_judge`): then corners come from [`fixed_on_grid`](Self::fixed_on_grid) too.
    fn grid_judge(&self) -> Option<&GridJudge> {
        None
    }
    /// Vertex `v` in `grid`'s fixed point, if it is a grid point.
    fn fixed_on_grid(&self, v: u32, grid: &super::grid_view::GridView) -> Option<[i32; 3]> {
        let _ = (v, grid);
        None
    }
}

impl Frame for Tessellator<'_, '_> {
    fn tree(&self) -> &Hierarchy<'_> {
        &self.tree
    }

    fn arithmetic(&self) -> Arithmetic {
        self.arithmetic
    }

    fn is_culled(&self, patch: u32) -> bool {
        Tessellator::is_culled(self, patch)
    }

    fn position(&self, v: u32) -> [f32; 3] {
        Tessellator::position(self, v)
    }

    fn viewed(&self, v: u32, p: impl FnOnce() -> Vec3, camera: &Camera) -> Vec3 {
        Tessellator::viewed(self, v, p, camera)
    }

    fn grid_view(&self) -> Option<&super::grid_view::GridView> {
        Tessellator::grid_view(self)
    }

    fn grid_judge(&self) -> Option<&GridJudge> {
        Tessellator::grid_judge(self)
    }

    fn fixed_on_grid(&self, v: u32, grid: &super::grid_view::GridView) -> Option<[i32; 3]> {
        Tessellator::fixed_on_grid(self, v, grid)
    }
}

/// Judges `h` in `view`: by its node's kept vectors, or below the bake by its own lattice
/// (see `refine`). Not `exact`, a bound over the tolerance may be given as any value over it
/// that the bound is at least (the directional bound stops as soon as it is over: most
/// triangles judged over are halved, and need no more). With `asked` (camera steps, see
/// `reuse`), the judgement comes with the largest of them it is certain over.
pub(super) fn judge(
    selection: &impl Frame,
    view: &View,
    h: &Pending,
    exact: bool,
    asked: Asked<'_>,
) -> Judged {
    if selection.is_culled(h.tri.patch) {
        // A patch facing away (see `cull`): nothing of it shows.
        return Judged::bare(0.0, true);
    }
    let stop = if exact {
        f32::INFINITY
    } else {
        view.tolerance()
    };
    // The corners' points. (Where the tessellator keeps the frame's last vertices in view
    // coordinates, most judgements read them there only: they are found where needed.)
    let points = || h.corners.map(|v| Vec3::from_array(selection.position(v)));
    let eager = (!super::select::CACHE_VIEWED).then(points);
    let corners = || eager.unwrap_or_else(points);
    let tree = selection.tree();
    let mut baked = None;
    if let Some((node, leaf)) = tree.node_bound(h) {
        // Where the frame takes one, a first look in integers (see `grid_judge`): it finds
        // most triangles within as the `f32` judgement would, and most others in view. (A
        // bound within the tolerance is never asked for in full: `exact` is for one over.)
        let mut seen = Seen::NOTHING;
        let mut over = None;
        if let (View::Screen { .. }, Some(grid), Some(look), None) =
            (view, selection.grid_view(), selection.grid_judge(), eager)
        {
            // (Gathered in place, and lent: on ARMv6-M, arrays of options moved through the
            // stack cost about 100 instructions a judgement.)
            let mut fixed = [[0; 3]; 3];
            let on_grid = h.corners.iter().zip(&mut fixed).all(|(&v, slot)| {
                selection
                    .fixed_on_grid(v, grid)
                    .map(|p| *slot = p)
                    .is_some()
            });
            if on_grid {
                let first = look.look(grid, &fixed, &node, view.tolerance(), exact);
                match first {
                    FirstLook::Within(bound) => {
                        return Judged {
                            bound,
                            hidden: false,
                            lasting: None,
                        }
                    }
                    FirstLook::Over(bound) => over = Some(Judged::bare(bound, false)),
                    FirstLook::Seen(found) => seen = found,
                }
            }
        }
        // (Over by the first look, the judgement is made; a leaf of the bake may still be
        // within by its own lattice, below.)
        let j = match over {
            Some(j) => j,
            None => {
                // In model units, the bake's own bound (the oracles' too); on screen, one from
                // the quantised vectors, and the vectors only when the isotropic bound is not
                // enough.
                let big = match view {
                    View::Object { .. } => node.longest(),
                    View::Screen { .. } => node.longest_quantised(),
                };
                judge_vectors(
                    view,
                    |camera| match eager {
                        Some(corners) => corners.map(|p| camera.to_view(p)),
                        None => viewed(selection, h, camera),
                    },
                    |camera| match selection.arithmetic() {
                        Arithmetic::Integer => {
                            NodeVectors::Integer(Quantised::new(node.vectors, node.scale))
                        }
                        Arithmetic::Float => {
                            NodeVectors::Float(node.kept().map(|v| camera.rotate_to_view(v)))
                        }
                    },
                    big,
                    node.remainder,
                    // (The corners read from a cache may be the integer move's: see
                    // `grid_view`.)
                    match eager {
                        Some(_) => 0.0,
                        None => selection.grid_view().map_or(0.0, |g| g.slack()),
                    },
                    seen,
                    stop,
                    // A certificate bounds the float vectors' bound over a camera step; the
                    // integer one may stand above it by its own roundings, which no certificate
                    // covers: its judgements keep none, and are made again every frame.
                    match selection.arithmetic() {
                        Arithmetic::Float => asked,
                        Arithmetic::Integer => Asked::NONE,
                    },
                )
            }
        };
        // A leaf of the bake keeps one bound, no vector: where it is over, the run time's
        // own lattice (with `refine`) may be within, as it is for a triangle below the bake.
        let over = matches!(j.bound, Bound::Value(b) if b > view.tolerance());
        if !(leaf && cfg!(feature = "refine") && !j.hidden && over) {
            return j;
        }
        baked = Some(j);
    }
    let patch = tree
        .patch_of(h.tri.patch)
        .filter(|_| cfg!(feature = "refine"));
    let Some(patch) = patch else {
        // (A build without refinement makes no triangle below the bake.)
        return baked.unwrap_or(Judged::bare(f32::INFINITY, false));
    };
    let grid = h.tri.corners.map(|p| [p[0] as u32, p[1] as u32]);
    let corners = corners();
    let (vectors, remainder) = deviation_vectors::<RUN_TIME_STEPS, RUN_TIME_POINTS>(
        &patch,
        grid,
        ONE as u32,
        corners.map(|c| c.to_array()),
    );
    let big = longest_of(&vectors);
    if !(big.is_finite() && remainder.is_finite()) {
        return baked.unwrap_or(Judged::bare(f32::INFINITY, false));
    }
    let own = judge_vectors(
        view,
        |camera| corners.map(|p| camera.to_view(p)),
        |camera| vectors.map(|v| camera.rotate_to_view(v)),
        big,
        remainder,
        0.0,
        Seen::NOTHING,
        stop,
        asked,
    );
    // Two bounds of one leaf: the smaller holds. Whether it is hidden stays the bake's
    // bound's say, so that a build without `refine` writes the same triangles.
    match baked {
        Some(b) => Judged {
            bound: {
                let (own, b) = (own.bound.value(), b.bound.value());
                Bound::Value(if own < b { own } else { b })
            },
            hidden: b.hidden,
            // Within while either bound is; over while both are (the baked one is over
            // here: it was asked for the lattice's only then).
            lasting: match (own.lasting, b.lasting) {
                (Some(l @ Lasting { over: false, .. }), _) => Some(l),
                (Some(l), Some(m)) if l.over && m.over && l.class == m.class => Some(Lasting {
                    level: l.level.min(m.level),
                    step: crate::math::min(l.step, m.step),
                    ..l
                }),
                _ => None,
            },
        },
        None => own,
    }
}

/// `h`'s corners in `camera`'s view coordinates, from the tessellator's cache of the frame's
/// last ones where it has them (see `Tessellator::viewed`), their points moved there
/// otherwise.
#[inline(always)]
fn viewed(selection: &impl Frame, h: &Pending, camera: &Camera) -> [Vec3; 3] {
    let point = |v: u32| Vec3::from_array(selection.position(v));
    match selection.grid_view() {
        Some(grid) => h
            .corners
            .map(|v| selection.viewed_on_grid(v, grid, || point(v), camera)),
        None => h.corners.map(|v| selection.viewed(v, || point(v), camera)),
    }
}

/// Judges the flat triangle whose corners `viewed` gives in a camera's view coordinates and
/// whose deviation lies in the hull of zero and the vectors `vectors` gives for a camera
/// (none longer than `big`) widened by `remainder`, the corners within `remainder` and
/// `slack` more of their points' moves into view coordinates (see `deviation/screen.rs`:
/// *Rounding*); a directional bound over `stop` may stop there (see [`judge`]), and with
/// `asked` steps the judgement comes with its certificate. `seen`: what a first look found
/// certain (see `grid_judge`), which the `f32` tests then need not look at.
#[allow(clippy::too_many_arguments)]
fn judge_vectors<D: Deviations>(
    view: &View,
    viewed: impl FnOnce(&Camera) -> [Vec3; 3],
    vectors: impl FnOnce(&Camera) -> D,
    big: f32,
    remainder: f32,
    slack: f32,
    seen: Seen,
    stop: f32,
    asked: Asked<'_>,
) -> Judged {
    match view {
        View::Object { .. } => Judged::bare(big + remainder, false),
        View::Screen { camera, .. } => {
            let viewed = viewed(camera);
            let size = view_extent(&viewed);
            // The corners' own slack (none where they are the float move's: the same bits,
            // and no addition where the build never moves them otherwise).
            // (A test of its bits: where `f32` is software, a comparison is a library call.)
            let widened = |x: f32| if slack.to_bits() != 0 { x + slack } else { x };
            let corners = widened(remainder);
            if seen.sight == Sight::Unknown
                && beyond_one_plane(camera, viewed, size, widened(big + remainder))
            {
                return Judged::bare(0.0, true);
            }
            let tolerance = view.tolerance();
            // Most triangles a frame judges are within the tolerance by the isotropic bound
            // already, which needs no vectors; the others take the directional one.
            let m = big + remainder;
            // (A first look may know it over: then only its being over is read.)
            let isotropic = match seen.isotropic_over {
                true => f32::INFINITY,
                false => isotropic_bound_on_screen(camera, viewed, size, m, corners),
            };
            let asked = if cfg!(feature = "reuse") {
                asked
            } else {
                Asked::NONE
            };
            let certify = |e: &D, over: bool, bound: f32| {
                crate::deviation::certificate::lasting(
                    camera,
                    viewed,
                    e.in_view(camera).as_ref(),
                    big,
                    remainder,
                    corners,
                    tolerance,
                    over,
                    bound,
                    asked,
                )
            };
            if isotropic <= tolerance {
                let mut j = Judged::bare(isotropic, false);
                if !asked.is_empty() {
                    j.lasting = certify(&vectors(camera), false, isotropic);
                }
                return j;
            }
            let e = vectors(camera);
            let inside = seen.sight == Sight::EveryCorner;
            let full = || {
                bound_on_screen(
                    camera, viewed, size, &e, big, remainder, corners, stop, inside,
                )
            };
            if asked.is_empty() {
                return Judged::bare(full(), false);
            }
            // (Where the certificate's own bounds decide the judgement, the bound on screen
            // is not needed: see `judged_with_lasting`.)
            let (bound, lasting) = crate::deviation::certificate::judged_with_lasting(
                camera,
                viewed,
                e.in_view(camera).as_ref(),
                big,
                remainder,
                corners,
                tolerance,
                asked,
                stop == f32::INFINITY,
                full,
            );
            Judged {
                bound: Bound::Value(bound),
                hidden: false,
                lasting,
            }
        }
    }
}

/// Whether leaf `h`, below the bake, is hidden: its corners beyond one plane of `camera`'s
/// view by more than a bound of its deviation that needs no samples, the remainder of
/// linear interpolation from its patch's second derivatives (`½ ρ²`, see `deviation`), with
/// three times the patch's rounding slack (the corners' points may come from the patch across
/// a shared curve, within their own slack); `bounds` are the patch's. The run time's
/// judgement hid it by its lattice's tighter bound; this one, recomputed where the mesh is
/// written out, leaves out no more.
pub(super) fn hidden_below_the_bake(
    selection: &Tessellator<'_, '_>,
    camera: &Camera,
    h: &Pending,
    bounds: &crate::deviation::PatchBounds,
) -> bool {
    let uv = h.tri.corners.map(super::address::unit);
    let margin = bounds.curvature_term(uv) * (1.0 + 1.0 / 1024.0) + 3.0 * bounds.slack;
    let viewed = h
        .corners
        .map(|v| camera.to_view(Vec3::from_array(selection.position(v))));
    margin.is_finite() && beyond_one_plane(camera, viewed, view_extent(&viewed), margin)
}

/// Whether the three points `view` (in `camera`'s view coordinates, `size` their
/// [`view_extent`]) lie beyond one plane of the view by more than `margin` (and the rounding
/// of moving them into view coordinates).
/// Never for an orthographic camera (it has no side planes here).
pub(super) fn beyond_one_plane(camera: &Camera, view: [Vec3; 3], size: f32, margin: f32) -> bool {
    if let Projection::Orthographic { .. } = camera.projection() {
        return false;
    }
    let w = margin + 16.0 * EPS * size;
    if !w.is_finite() {
        return false;
    }
    let ([sx, sy], [nx, ny]) = camera.side_planes();
    let near = camera.near();
    // Each plane's signed distance outside (as `deviation/screen.rs` clips, negated), times
    // the plane's norm (`nx`, `ny` >= 1): no division. The product and the quotient round
    // within a few `ε` of the distance, which the slack in `w` covers, as it covered the
    // quotient's.
    let (wx, wy) = (w * nx, w * ny);
    view.iter().all(|p| near - p.z > w)
        || view.iter().all(|p| -p.x - sx * p.z > wx)
        || view.iter().all(|p| p.x - sx * p.z > wx)
        || view.iter().all(|p| -p.y - sy * p.z > wy)
        || view.iter().all(|p| p.y - sy * p.z > wy)
}
