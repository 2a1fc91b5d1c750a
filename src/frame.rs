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

/// Below this ratio of partial lengths a partial is treated as vanished and the analytic limit
/// is used. The limit differs from the true normal by `O(ratio)` there, and above it rounding
/// of the small partial in `f32` stays well under 1e-3 rad.
const DEGENERATE_RATIO: f32 = 1.0e-3;

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
/// `[0, 1]` over the piece, used only to orient a limit normal (which edge is nearer).
pub(crate) fn frame(ev: &TensorEval, s: f32, t: f32) -> Frame {
    let w = ev.a.w;
    let position = xyz(ev.a) / w;
    let partial_u = (xyz(ev.a_u) - position * ev.a_u.w) / w;
    let partial_v = (xyz(ev.a_v) - position * ev.a_v.w) / w;
    let lu = length(partial_u);
    let lv = length(partial_v);
    let mut normal = None;
    if lu > DEGENERATE_RATIO * lv && lv > DEGENERATE_RATIO * lu {
        let n = partial_u.cross(partial_v);
        if length(n) > DEGENERATE_RATIO * lu * lv {
            normal = normalize(n);
        }
    } else if lu != lv {
        let partial_uv = (xyz(ev.a_uv)
            - position * ev.a_uv.w
            - partial_v * ev.a_u.w
            - partial_u * ev.a_v.w)
            / w;
        let limit = if lu < lv {
            // S_u vanished along v = 0 or v = 1.
            let n = partial_uv.cross(partial_v);
            if t <= 0.5 {
                n
            } else {
                -n
            }
        } else {
            let n = partial_u.cross(partial_uv);
            if s <= 0.5 {
                n
            } else {
                -n
            }
        };
        // The limit is only trusted when its own factors are not parallel.
        let big = if lu < lv { lv } else { lu };
        if length(limit) > DEGENERATE_RATIO * length(partial_uv) * big {
            normal = normalize(limit);
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
