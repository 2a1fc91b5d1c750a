//! De Boor's algorithm on homogeneous points: the single evaluation core.
//!
//! A rational Bezier patch is a B-spline patch over the knots `0..0, 1..1`, and a span of a
//! NURBS surface is a piece of one, so both evaluate here. The same triangle with a different
//! parameter per level is the *blossom*, which extracts the exact Bezier pieces of a NURBS
//! surface (see [`crate::nurbs`]).
//!
//! Local knots for a span of degree `p` are the `2p` knots `U[k-p+1 ..= k+p]` around span
//! `[U[k], U[k+1])`; for a Bezier patch they are `p` zeros then `p` ones.

use glam::Vec4;

use crate::math::lerp4;
use crate::MAX_DEGREE;

/// The knots of one span, as far as de Boor's triangle needs them.
pub(crate) trait Span: Copy {
    /// True when every factor of a level is the same (the Bezier case).
    const CONSTANT: bool = false;
    /// Interpolation factor of point `a` at level `r` of a degree-`p` triangle at `t`.
    fn alpha(self, a: usize, p: usize, r: usize, t: f32) -> f32;
    /// Length of the span in parameter.
    fn width(self, p: usize) -> f32;
}

/// A Bezier segment: knots `0..0, 1..1`, so every factor is `t` itself, with no division.
/// (The general formula gives `(t - 0) / (1 - 0)`, which is `t` exactly: both agree bit for bit.)
#[derive(Clone, Copy)]
pub(crate) struct Bezier;

impl Span for Bezier {
    const CONSTANT: bool = true;
    #[inline(always)]
    fn alpha(self, _: usize, _: usize, _: usize, t: f32) -> f32 {
        t
    }
    #[inline(always)]
    fn width(self, _: usize) -> f32 {
        1.0
    }
}

/// The `2p` local knots `U[k-p+1 ..= k+p]` of span `k` of a B-spline.
impl Span for &[f32] {
    #[inline(always)]
    fn alpha(self, a: usize, p: usize, r: usize, t: f32) -> f32 {
        let left = self[a - 1];
        let right = self[a + p - r];
        // right > left for every valid span (see the module docs), so no division by zero.
        (t - left) / (right - left)
    }
    #[inline(always)]
    fn width(self, p: usize) -> f32 {
        self[p] - self[p - 1]
    }
}

/// One level of de Boor's triangle: turns `d[r-1..=p]` of level `r - 1` into `d[r..=p]` of
/// level `r`, at parameter `t`.
#[inline(always)]
fn level<S: Span>(d: &mut [Vec4], knots: S, p: usize, r: usize, t: f32) {
    if S::CONSTANT {
        // Every factor is `t`: the formula of [`lerp4`] is chosen once for the level (the
        // same bits as choosing it per point).
        let t = knots.alpha(p, p, r, t);
        if t <= 0.5 {
            for a in (r..=p).rev() {
                d[a] = d[a - 1] + (d[a] - d[a - 1]) * t;
            }
        } else {
            let s = 1.0 - t;
            for a in (r..=p).rev() {
                d[a] = d[a] - (d[a] - d[a - 1]) * s;
            }
        }
        return;
    }
    let mut a = p;
    while a >= r {
        d[a] = lerp4(d[a - 1], d[a], knots.alpha(a, p, r, t));
        a -= 1;
    }
}

/// Point and first derivative of one span at `t`; `d` holds the `p + 1` local control points
/// (destroyed).
#[inline]
pub(crate) fn point_and_derivative<S: Span>(d: &mut [Vec4], knots: S, t: f32) -> (Vec4, Vec4) {
    let p = d.len() - 1;
    for r in 1..p {
        level(d, knots, p, r, t);
    }
    let derivative = (d[p] - d[p - 1]) * (p as f32 / knots.width(p));
    level(d, knots, p, p, t);
    (d[p], derivative)
}

/// Point of one span at `t` (see [`point_and_derivative`]).
#[inline]
pub(crate) fn point<S: Span>(d: &mut [Vec4], knots: S, t: f32) -> Vec4 {
    let p = d.len() - 1;
    for r in 1..=p {
        level(d, knots, p, r, t);
    }
    d[p]
}

/// The blossom of one span: level `r` uses parameter `args[r - 1]`. With every argument equal
/// it is the point; with arguments `a` (`p - i` times) then `b` (`i` times) it is the `i`-th
/// Bezier control point of the piece over `[a, b]`.
#[inline]
pub(crate) fn blossom(d: &mut [Vec4], knots: &[f32], args: &[f32]) -> Vec4 {
    let p = d.len() - 1;
    for r in 1..=p {
        level(d, knots, p, r, args[r - 1]);
    }
    d[p]
}

/// The Bernstein polynomials `B_{i,n}(t)`, `i = 0..=n`, by their recurrence (each a sum of
/// products of `t` and `1 - t` with non-negative terms, so each is correct to a few roundings).
#[inline]
pub(crate) fn bernstein(n: usize, t: f32) -> [f32; MAX_DEGREE + 1] {
    let mut b = [0.0f32; MAX_DEGREE + 1];
    b[0] = 1.0;
    let s = 1.0 - t;
    for k in 1..=n {
        b[k] = t * b[k - 1];
        for i in (1..k).rev() {
            b[i] = s * b[i] + t * b[i - 1];
        }
        b[0] *= s;
    }
    b
}

/// [`bernstein`] for a degree known at compile time (`M = n + 1` values): the same operations
/// in the same order, so the same bits, unrolled.
#[inline(always)]
pub(crate) fn bernstein_fixed<const M: usize>(t: f32) -> [f32; M] {
    let mut b = [0.0f32; M];
    b[0] = 1.0;
    let s = 1.0 - t;
    for k in 1..M {
        b[k] = t * b[k - 1];
        for i in (1..k).rev() {
            b[i] = s * b[i] + t * b[i - 1];
        }
        b[0] *= s;
    }
    b
}

/// Homogeneous point and partial derivatives of a tensor-product span.
pub(crate) struct TensorEval {
    /// Homogeneous point `(w x, w y, w z, w)`.
    pub(crate) a: Vec4,
    /// Derivative in u.
    pub(crate) a_u: Vec4,
    /// Derivative in v.
    pub(crate) a_v: Vec4,
    /// Mixed derivative.
    pub(crate) a_uv: Vec4,
}

/// Evaluates a tensor-product span with degrees `(p, q)` whose homogeneous control point
/// `(i, j)` is `net(i, j)`, with `i` along u.
pub(crate) fn tensor_with_derivatives<U: Span, V: Span>(
    p: usize,
    q: usize,
    knots_u: U,
    knots_v: V,
    net: impl Fn(usize, usize) -> Vec4,
    u: f32,
    v: f32,
) -> TensorEval {
    let mut rows = [Vec4::ZERO; MAX_DEGREE + 1];
    let mut rows_u = [Vec4::ZERO; MAX_DEGREE + 1];
    let mut work = [Vec4::ZERO; MAX_DEGREE + 1];
    for j in 0..=q {
        for (i, w) in work[..=p].iter_mut().enumerate() {
            *w = net(i, j);
        }
        let (c, c_u) = point_and_derivative(&mut work[..=p], knots_u, u);
        rows[j] = c;
        rows_u[j] = c_u;
    }
    let (a, a_v) = point_and_derivative(&mut rows[..=q], knots_v, v);
    let (a_u, a_uv) = point_and_derivative(&mut rows_u[..=q], knots_v, v);
    TensorEval { a, a_u, a_v, a_uv }
}

/// Homogeneous point of a tensor-product span (see [`tensor_with_derivatives`]).
pub(crate) fn tensor_point<U: Span, V: Span>(
    p: usize,
    q: usize,
    knots_u: U,
    knots_v: V,
    net: impl Fn(usize, usize) -> Vec4,
    u: f32,
    v: f32,
) -> Vec4 {
    let mut rows = [Vec4::ZERO; MAX_DEGREE + 1];
    let mut work = [Vec4::ZERO; MAX_DEGREE + 1];
    for (j, row) in rows[..=q].iter_mut().enumerate() {
        for (i, w) in work[..=p].iter_mut().enumerate() {
            *w = net(i, j);
        }
        *row = point(&mut work[..=p], knots_u, u);
    }
    point(&mut rows[..=q], knots_v, v)
}
