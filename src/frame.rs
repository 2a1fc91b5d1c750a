//! From homogeneous derivatives to a Euclidean point, partials and unit normal.
//!
//! The normal is `S_u x S_v` except where a partial vanishes. At an edge collapsed to a point
//! (the poles of the teapot's lid and bottom) one partial is zero along the whole edge, so the
//! cross product there is zero and near it is dominated by rounding. The limit is taken
//! analytically instead: if `S_u` vanishes along `v = v0`, then `S_u(u, v) ~ (v - v0) S_uv(u, v0)`
//! and the normal tends to `sign(v - v0) * (S_uv x S_v)`; symmetrically in u.

use glam::{Vec3, Vec4};

use crate::basis::TensorEval;
use crate::math::{length, normalize};
use crate::patch::Side;

/// Below this ratio of partial lengths a partial is treated as vanished and the analytic limit
/// is used. It only has to catch rounding: along a collapsed row of a polynomial patch the
/// partial is exactly zero (see [`crate::math::lerp4`]), and for a rational one it is `f32`
/// noise of order `1e-7` relative. Genuine surfaces come much closer than `1e-3` (Gumbo has
/// a fold where `|S_u| / |S_v| = 6e-4`), so the ratio must stay far below that.
const DEGENERATE_RATIO: f32 = 1.0e-5;

/// Position, first partial derivatives and unit normal of a surface at one parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// The point on the surface.
    pub position: Vec3,
    /// Partial derivative with respect to u.
    pub partial_u: Vec3,
    /// Partial derivative with respect to v.
    pub partial_v: Vec3,
    /// Unit normal, oriented as `partial_u x partial_v`; at collapsed edges, its limit.
    /// Always finite and of unit length.
    pub normal: Vec3,
}

impl SurfacePoint {}

/// Euclidean position, partials and (when it is defined at this point) the normal.
pub(crate) struct Frame {
    pub(crate) position: Vec3,
    pub(crate) partial_u: Vec3,
    pub(crate) partial_v: Vec3,
    pub(crate) normal: Option<Vec3>,
}

#[inline]
fn xyz(v: Vec4) -> Vec3 {
    Vec3::new(v.x, v.y, v.z)
}

/// Converts homogeneous derivatives to Euclidean ones. `s` and `t` are the parameters scaled to
/// `[0, 1]` over the surface, used only to pick the nearer edge of a vanishing partial;
/// `collapsed(side)` tells whether that edge of the surface is collapsed to a point, and
/// `twist()` gives the homogeneous `a_uv` when the limit needs it (a polynomial patch computes
/// it only then; `ev.a_uv` is not read).
///
/// The analytic limit is taken only at a collapsed edge. A partial can also be tiny for a
/// genuine reason (a rational patch whose weights span six orders of magnitude has
/// `|S_u| / |S_v|` down to `1e-6` in places), and there the direct normal is the right one.
pub(crate) fn frame(
    ev: &TensorEval,
    s: f32,
    t: f32,
    collapsed: impl Fn(Side) -> bool,
    twist: impl FnOnce() -> Vec4,
) -> Frame {
    let w = ev.a.w;
    let position = xyz(ev.a) / w;
    let partial_u = (xyz(ev.a_u) - position * ev.a_u.w) / w;
    let partial_v = (xyz(ev.a_v) - position * ev.a_v.w) / w;
    // Max-norms, and the partials scaled by them: their components are at most 1 and the
    // largest is ±1, so their squared lengths lie in [1, 3] and nothing underflows near a pole.
    let mu = partial_u.abs().max_element();
    let mv = partial_v.abs().max_element();
    let finite = |m: f32| m > 0.0 && m.is_finite();
    // The normal when the partials are not parallel: the sine of their angle,
    // |su x sv| / (|su| |sv|), is above the ratio. (Squared: a square below `f32`'s range
    // is below the ratio's square, 1e-10, too.) One square root, in the normalisation.
    let direct = || {
        if !(finite(mu) && finite(mv)) {
            return None;
        }
        let (su, sv) = (partial_u / mu, partial_v / mv);
        let n = su.cross(sv);
        let ratio2 = DEGENERATE_RATIO * DEGENERATE_RATIO;
        if n.length_squared() > ratio2 * su.length_squared() * sv.length_squared() {
            normalize(n)
        } else {
            None
        }
    };
    let mut normal = None;
    if mu > DEGENERATE_RATIO * mv && mv > DEGENERATE_RATIO * mu {
        normal = direct();
    } else if mu != mv {
        // The edge along which the vanishing partial would vanish identically.
        let edge = match (mu < mv, t <= 0.5, s <= 0.5) {
            (true, true, _) => Side::V0,
            (true, false, _) => Side::V1,
            (false, _, true) => Side::U0,
            (false, _, false) => Side::U1,
        };
        if !collapsed(edge) {
            normal = direct();
        } else {
            let a_uv = twist();
            let partial_uv =
                (xyz(a_uv) - position * a_uv.w - partial_v * ev.a_u.w - partial_u * ev.a_v.w) / w;
            let duv = normalize(partial_uv);
            let (du, dv) = (normalize(partial_u), normalize(partial_v));
            let limit = match (mu < mv, duv) {
                // S_u vanished along v = 0 or v = 1: the normal tends to sign * (S_uv x S_v).
                (true, Some(duv)) => dv.map(|dv| {
                    let n = duv.cross(dv);
                    if t <= 0.5 {
                        n
                    } else {
                        -n
                    }
                }),
                (false, Some(duv)) => du.map(|du| {
                    let n = du.cross(duv);
                    if s <= 0.5 {
                        n
                    } else {
                        -n
                    }
                }),
                (_, None) => None,
            };
            // The limit is only trusted when its own factors are not parallel.
            if let Some(n) = limit {
                if length(n) > DEGENERATE_RATIO {
                    normal = normalize(n);
                }
            }
        }
    }
    Frame {
        position,
        partial_u,
        partial_v,
        normal,
    }
}

/// The parameter moved a small step towards the middle of `[0, 1]`, used when the normal is
/// undefined both directly and as a one-sided limit (e.g. a corner where two edges collapse).
#[inline]
pub(crate) fn nudge(s: f32) -> f32 {
    s + (0.5 - s) * (1.0 / 1024.0)
}
