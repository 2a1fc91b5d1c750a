//! The edge functions as limits on a row's columns, in exact integer arithmetic: 32 bits for
//! the corners of small viewports, 64 bits beyond.

use super::{HALF, SUBPIXELS};

/// The edges as limits on the columns of each row: at the row through subpixel height `yc`,
/// column `px` is inside the edge opposite corner `i` when `k[i] * px >= m0[i] - dx[i] * yc`
/// (see [`Triangle::span`](super::Triangle::span)).
#[derive(Clone, Copy, Debug)]
pub(super) enum Edges {
    /// Every corner within [`NARROW_LIMIT`] subpixels of the origin: 32-bit arithmetic.
    Narrow { k: [i32; 3], m0: [i32; 3] },
    /// 64-bit arithmetic, for corners up to [`COORDINATE_LIMIT`](super::COORDINATE_LIMIT) pixels away.
    Wide { k: [i64; 3], m0: [i64; 3] },
}

/// Corners within this many subpixels (512 pixels) of the origin take the 32-bit edge
/// arithmetic of [`Edges::Narrow`]. Those of a viewport up to 256 pixels always do: the clip's
/// guard band keeps corners between `-W/2` and `3W/2` pixels across a viewport `W` pixels wide,
/// and likewise down. With `L = 2^13`, every quantity then fits `i32` with room to spare:
/// differences of corners `|dx|, |dy| <= 2L`, so `dx² + dy² <= 2^29`; twice the area at most
/// `(2L)² = 2^28`; `c = dy x_p - dx y_p` at most `2 (2L) L = 2^28`;
/// `|m0| <= 2^28 + 1 + 8 (2L) < 2^29`; `|k| = 16 |dy| <= 2^18`; and at a row of the triangle
/// (`|yc| <= L`), `|m0 - dx yc| < 2^29 + 2^28`. The results are the same integers as in 64
/// bits.
pub(super) const NARROW_LIMIT: i64 = 1 << 13;

/// The integer type of the edge functions: `i32` or `i64`, with the same exact results
/// wherever both apply.
pub(super) trait EdgeInt:
    Copy
    + Ord
    + From<i32>
    + core::ops::Add<Output = Self>
    + core::ops::Sub<Output = Self>
    + core::ops::Mul<Output = Self>
    + core::ops::Neg<Output = Self>
{
    /// `floor(self / b)` for `b > 0`.
    fn floor_div(self, b: Self) -> Self;
    /// As `i64`.
    fn wide(self) -> i64;
    /// As `f32` (see [`wide_to_f32`]).
    fn to_f32(self) -> f32;
    /// The edges with these coefficients.
    fn edges(k: [Self; 3], m0: [Self; 3]) -> Edges;
}

impl EdgeInt for i32 {
    #[inline]
    fn floor_div(self, b: i32) -> i32 {
        self.div_euclid(b)
    }
    #[inline]
    fn wide(self) -> i64 {
        self as i64
    }
    #[inline]
    fn to_f32(self) -> f32 {
        self as f32
    }
    #[inline]
    fn edges(k: [i32; 3], m0: [i32; 3]) -> Edges {
        Edges::Narrow { k, m0 }
    }
}

impl EdgeInt for i64 {
    #[inline]
    fn floor_div(self, b: i64) -> i64 {
        floor_div(self, b)
    }
    #[inline]
    fn wide(self) -> i64 {
        self
    }
    #[inline]
    fn to_f32(self) -> f32 {
        wide_to_f32(self)
    }
    #[inline]
    fn edges(k: [i64; 3], m0: [i64; 3]) -> Edges {
        Edges::Wide { k, m0 }
    }
}

/// Puts a triangle's corners counter-clockwise on screen (x right, y down: the doubled area
/// below positive), swapping corners 1 and 2, and their attributes with them, when they are
/// not; the doubled area, 0 for a triangle with none.
#[inline(always)]
pub(super) fn counter_clockwise<I: EdgeInt>(
    x: &mut [I; 3],
    y: &mut [I; 3],
    depth: &mut [f32; 3],
    shade: &mut [f32; 3],
    wire: &mut [bool; 3],
) -> I {
    let area = (x[2] - x[1]) * (y[0] - y[1]) - (y[2] - y[1]) * (x[0] - x[1]);
    if area >= I::from(0) {
        return area;
    }
    x.swap(1, 2);
    y.swap(1, 2);
    depth.swap(1, 2);
    shade.swap(1, 2);
    wire.swap(1, 2);
    -area
}

/// Edge `i` of a counter-clockwise triangle, from corner `i + 1` to corner `i + 2`, set up for
/// the inside test at pixel centres: what both the spans and the scan take, so that they cover
/// the same pixels.
#[derive(Clone, Copy)]
pub(super) struct EdgeSetUp<I> {
    /// The edge's extent.
    pub dx: I,
    pub dy: I,
    /// The top-left rule: 0 for an edge going up (y down) or a horizontal edge going right,
    /// else 1.
    pub bias: i32,
    /// `E(X, Y) = dx (Y - y_p) - dy (X - x_p) = a X + dx Y + c`, with `a = -dy` and
    /// `c = dy x_p - dx y_p`. At the centre `X = S px + H` of pixel column `px`:
    /// `E >= bias  <=>  k px >= m0 - dx Y`, with `k = S a` and `m0 = bias - c - H a`.
    pub k: I,
    pub m0: I,
}

/// [`EdgeSetUp`] of edge `i` of the counter-clockwise corners `x`, `y`.
#[inline(always)]
pub(super) fn edge_set_up<I: EdgeInt>(x: &[I; 3], y: &[I; 3], i: usize) -> EdgeSetUp<I> {
    let zero = I::from(0);
    let (sub, half) = (I::from(SUBPIXELS as i32), I::from(HALF as i32));
    let (p, q) = ((i + 1) % 3, (i + 2) % 3);
    let (dx, dy) = (x[q] - x[p], y[q] - y[p]);
    let bias = i32::from(!(dy < zero || (dy == zero && dx > zero)));
    let (a, c) = (-dy, dy * x[p] - dx * y[p]);
    EdgeSetUp {
        dx,
        dy,
        bias,
        k: sub * a,
        m0: I::from(bias) - c - half * a,
    }
}

/// `ceil(a / b)` for `b > 0`.
#[inline]
pub(super) fn ceil_div<I: EdgeInt>(a: I, b: I) -> I {
    -(-a).floor_div(b)
}

/// The columns `lo..=hi` (within the given ones) of the row through subpixel height `yc`
/// that lie inside every edge.
#[inline]
pub(super) fn inside_columns<I: EdgeInt>(
    k: &[I; 3],
    m0: &[I; 3],
    dx: &[i32; 3],
    yc: I,
    mut lo: I,
    mut hi: I,
) -> Option<(I, I)> {
    let zero = I::from(0);
    for i in 0..3 {
        let m = m0[i] - I::from(dx[i]) * yc;
        let k = k[i];
        if k > zero {
            lo = lo.max(ceil_div(m, k));
        } else if k < zero {
            hi = hi.min((-m).floor_div(-k));
        } else if m > zero {
            return None;
        }
    }
    (lo <= hi).then_some((lo, hi))
}

/// [`inside_columns`] in 64 bits, for rows of [`Edges::Wide`] triangles: out of line, so
/// that the 32-bit arithmetic of small viewports keeps its registers (measured on the
/// Cortex-M4F: 0.1M instructions of a `fw_teapot` frame).
#[inline(never)]
pub(super) fn wide_columns(
    k: &[i64; 3],
    m0: &[i64; 3],
    dx: &[i32; 3],
    yc: i32,
    lo: i32,
    hi: i32,
) -> Option<(i32, i32)> {
    let (lo, hi) = inside_columns(k, m0, dx, yc as i64, lo as i64, hi as i64)?;
    // Within the columns asked for: `i32`.
    Some((lo as i32, hi as i32))
}

/// `v` as `f32`: exactly rounded when it fits `i32` (one instruction on a 32-bit core, where
/// a 64-bit conversion is a library call), within two roundings otherwise.
#[inline]
fn wide_to_f32(v: i64) -> f32 {
    let low = v as i32;
    if low as i64 == v {
        low as f32
    } else {
        (v >> 32) as i32 as f32 * 4_294_967_296.0 + (v as u32) as f32
    }
}

/// `floor(a / b)` for `b > 0`, in 32 bits when both fit (64-bit division is a library call
/// on 32-bit cores; the operands of small viewports fit).
fn floor_div(a: i64, b: i64) -> i64 {
    match (i32::try_from(a), i32::try_from(b)) {
        (Ok(a), Ok(b)) if a != i32::MIN => a.div_euclid(b) as i64,
        _ => a.div_euclid(b),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn divisions_agree_with_64_bit_ones() {
        let big = i32::MAX as i64;
        for a in [
            0,
            1,
            -1,
            7,
            -7,
            15,
            -17,
            big,
            big + 1,
            -big,
            -big - 1,
            -big - 2,
            1 << 40,
        ] {
            for b in [1, 2, 16, 17, big, big + 1, 1 << 40] {
                assert_eq!(floor_div(a, b), a.div_euclid(b), "{a} / {b}");
                assert_eq!(ceil_div(a, b), -((-a).div_euclid(b)), "{a} / {b}");
            }
        }
    }
}
