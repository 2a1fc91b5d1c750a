//! The edge functions as limits on a row's columns, in exact integer arithmetic: 32 bits for
//! the corners of small viewports, 64 bits beyond.

use super::{HALF, SUBPIXELS};
use crate::math::isqrt_by_table;
use crate::render::walk::FixedRamp;

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

/// Whether a triangle of corners `x`, `y` (subpixels, x right, y down), in the order a source
/// hands them (see [`TriangleSource::one_sided`](crate::render::TriangleSource::one_sided)),
/// faces away from the eye: its doubled area as [`counter_clockwise`] finds it is above 0
/// (the corners run clockwise as the screen shows them). (In `i64`: corners anywhere in `i32`.)
#[inline]
pub(in crate::render) fn faces_away(x: [i32; 3], y: [i32; 3]) -> bool {
    let [x, y] = [x, y].map(|c| c.map(i64::from));
    (x[2] - x[1]) * (y[0] - y[1]) - (y[2] - y[1]) * (x[0] - x[1]) > 0
}

/// Puts a triangle's corners counter-clockwise on screen (x right, y down: the doubled area
/// below positive), swapping corners 1 and 2, and their attributes with them, when they are
/// not; the doubled area, 0 for a triangle with none.
#[inline(always)]
pub(super) fn counter_clockwise<I: EdgeInt, D, S>(
    x: &mut [I; 3],
    y: &mut [I; 3],
    depth: &mut [D; 3],
    shade: &mut [S; 3],
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

/// The limit below which a pixel's `E_i - bias_i` puts it on a wireframe line `half_width`
/// pixels wide along an edge with `inv_length = 1 / (16 |edge|)` and top-left bias `bias`:
/// `E_i` is the distance times `16 |edge|`, so the pixel is on the line when `E_i <
/// half_width · 16 |edge|`, that is `E_i - bias_i < ceil(half_width / inv_length - bias_i)`.
///
/// Its `ceil` is taken saturated, and at least 0: a pixel inside the triangle has
/// `E_i - bias_i >= 0`, so a negative limit puts no pixel on the line, as 0 does, and one past
/// `i32` every pixel, as `i32::MAX` does. Within `[0, i32::MAX]`, a scan's `E_i - bias_i -
/// limit` at a pixel inside (`E_i - bias_i` below `2^30`, see [`NARROW_LIMIT`]) stays within
/// `i32`, for any half width (infinite: every pixel; NaN or negative: none); a wide triangle's
/// spans take it in 64 bits ([`wire_ramp`]).
#[inline(always)]
pub(super) fn wire_limit(half_width: f32, inv_length: f32, bias: i32) -> i32 {
    let limit = half_width / inv_length - bias as f32;
    // `ceil`, saturated (`as` saturates, and takes NaN to 0), and at least 0.
    let t = limit as i32;
    t.saturating_add(((t as f32) < limit) as i32).max(0)
}

/// [`wire_limit`] from integers, for [`Arithmetic::Integer`](crate::Arithmetic): the same
/// limit `ceil(half_width 16 |edge| - bias)`, `|edge| = √S`, `S = dx² + dy²` (subpixels),
/// taken up, never down. `√S` in `2^-8`, rounded up: an integer square root of `S 2^16`
/// where that fits `u32`, else `r + (S - r²) / 2r` with `r = ⌊√S⌋ >= 256` (above `√S`, as
/// `√S + r >= 2 r`, by at most `1 / 2r <= 2^-9`); `half_width` read from its bits to 24
/// significant bits, rounded up. So the limit is at most `2^-23` of itself plus
/// `half_width · 16 · 3 · 2^-9` above the exact one before its `ceil`: one unit of `E` on
/// the half widths and triangles a display draws (`wire_limits_from_integers`), a
/// thousandth of a pixel or less across the line. Where `f32` is software this spares a
/// reciprocal square root's products and a division an edge. For the edges of a triangle
/// within [`NARROW_LIMIT`] (`|dx|, |dy| <= 2^14`); a half width not in `(0, 256)` pixels
/// takes [`wire_limit`].
pub(super) fn wire_limit_from_integers(half_width: f32, dx: i32, dy: i32, bias: i32) -> i32 {
    let bits = half_width.to_bits();
    let exponent = (bits >> 23) as i32 - 127; // (the sign bit makes it large: not taken)
    let narrow = dx.unsigned_abs() <= 1 << 14 && dy.unsigned_abs() <= 1 << 14;
    if !((-60..8).contains(&exponent) && narrow) {
        let length2 = (dx as i64 * dx as i64 + dy as i64 * dy as i64) as f32;
        return wire_limit(half_width, super::inv_sqrt(length2) * (1.0 / 16.0), bias);
    }
    // `half_width = a 2^-k` with `a` its 24-bit mantissa, exactly.
    let (a, k) = ((bits & 0x7f_ffff) | 0x80_0000, 23 - exponent);
    let s = dx.unsigned_abs().pow(2) + dy.unsigned_abs().pow(2);
    let root = if s < 1 << 16 {
        let scaled = s << 16;
        let r = isqrt_by_table(scaled);
        r + u32::from(r * r != scaled)
    } else {
        let r = isqrt_by_table(s);
        (r << 8) + ((s - r * r) << 7).div_ceil(r)
    };
    // `ceil(16 a 2^-k root 2^-8)`: `a root < 2^47`.
    // (In 32-bit products: a 64-bit one is a library call on ARMv6-M.)
    let product = crate::math::wide(a, root);
    let shift = (k + 4) as u32;
    let reach = match shift {
        0..=63 => (product + (1u64 << shift) - 1) >> shift,
        _ => u64::from(product != 0),
    };
    (reach.min(i32::MAX as u64) as i32)
        .saturating_sub(bias)
        .max(0)
}

/// The wireframe test along a span of `n` pixels, the scan's own ([`wire_limit`]): pixel `j`
/// of the span lies on the line along an edge when `E - bias < limit` there, where
/// `E - bias = e + k j` (`e` at the span's first pixel, `k` the change per pixel). Those are
/// the pixels before or from one column, which this finds by one exact division; the ramp
/// returned is below 0 exactly there and steps by 1, so its values stay within `±n` whatever
/// the magnitudes of `e` and `k` (64-bit ones far out).
#[inline]
pub(super) fn wire_ramp<I: EdgeInt>(e: I, k: I, limit: i32, n: i32) -> FixedRamp {
    let (zero, one) = (I::from(0), I::from(1));
    // On the line where `d + k j < 0`.
    let d = e - I::from(limit);
    let within = |j: I| j.max(zero).min(I::from(n)).wide() as i32;
    if k > zero {
        // `j < -d / k`, that is `j < ceil(-d / k)`.
        let end = within(ceil_div(-d, k));
        FixedRamp { at: -end, step: 1 }
    } else if k < zero {
        // `j > d / -k`, that is `j >= floor(d / -k) + 1`.
        let start = within(d.floor_div(-k) + one);
        FixedRamp {
            at: start - 1,
            step: -1,
        }
    } else {
        FixedRamp {
            at: if d < zero { -1 } else { 0 },
            step: 0,
        }
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
/// that the 32-bit arithmetic of small viewports keeps its registers.
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

    /// The integer limit is never below the exact one and at most one above it in `E`'s
    /// units over random edges, biases and half widths up to 4 pixels (exact: `f64`), where
    /// the float one is within its own roundings of it.
    #[test]
    fn wire_limits_from_integers() {
        let mut rng = crate::test_rng::TestRng::new(0x31_4e);
        let mut above = 0;
        for k in 0..200_000 {
            let (dx, dy) = (rng.signed(1 << 14) as i32, rng.signed(1 << 14) as i32);
            let dx = if k % 4 == 0 { dx >> 8 } else { dx };
            let bias = rng.signed(1) as i32;
            let half = (rng.signed(4000) as f32 / 1000.0).abs();
            let exact = (half as f64 * 16.0 * ((dx as f64).powi(2) + (dy as f64).powi(2)).sqrt()
                - bias as f64)
                .ceil()
                .max(0.0);
            let got = wire_limit_from_integers(half, dx, dy, bias) as f64;
            assert!(
                got >= exact && got <= exact + 1.0,
                "{half} {dx} {dy} {bias}: {got} {exact}"
            );
            if half > 0.0 {
                // (The float limit, for scale: within its own roundings.)
                let length2 = (dx * dx + dy * dy) as f32;
                let float = wire_limit(half, super::super::inv_sqrt(length2) / 16.0, bias);
                assert!(
                    (float as f64 - exact).abs() <= 1.0 + exact * 1e-6,
                    "{float} {exact}"
                );
            }
            above += usize::from(got > exact);
        }
        // (Measured: 6% one above.)
        assert!(above < 200_000 / 10, "{above} one above");
        assert_eq!(isqrt_by_table(u32::MAX), 65_535);
        assert_eq!(isqrt_by_table(15), 3);
        assert_eq!(isqrt_by_table(16), 4);
    }

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

    /// The wireframe ramp is below 0 exactly where `e + k j < limit`, checked pixel by pixel
    /// in 128 bits, for edge values of any size (64-bit ones far out) and spans up to 2^20
    /// pixels.
    #[test]
    fn a_wire_ramp_is_the_exact_test() {
        let mut rng = crate::test_rng::TestRng::new(0x31c3_0de5_2026);
        let mut on = 0;
        for case in 0..4000 {
            let scale = [1 << 8, 1 << 20, 1 << 30, 1 << 50][case % 4];
            let e = rng.signed(scale);
            let k = match case % 5 {
                0 => 0,
                _ => rng.signed([16, 1 << 10, 1 << 18, 1 << 34][(case / 5) % 4]),
            };
            let limit = rng.signed(1 << 30).abs() as i32;
            let n = [1, 7, 300, 1 << 20][(case / 3) % 4];
            let ramp = wire_ramp(e, k, limit, n);
            let narrow = (i32::try_from(e), i32::try_from(k));
            if let (Ok(e32), Ok(k32)) = narrow {
                // (The scan's edge values are below 2^30 in size.)
                if e32.abs() < 1 << 30 {
                    assert_eq!(wire_ramp(e32, k32, limit, n), ramp, "{e} {k}");
                }
            }
            let probes = [0, 1, n / 2, n - 2, n - 1]
                .into_iter()
                .filter(|&j| (0..n).contains(&j));
            for j in probes {
                let exact = (e as i128 + k as i128 * j as i128) < limit as i128;
                let value = ramp.at as i64 + ramp.step as i64 * j as i64;
                assert!(value.abs() <= n as i64 + 1, "{value}");
                assert_eq!(value < 0, exact, "{e} {k} {limit} {n} at {j}");
                on += usize::from(exact);
            }
        }
        assert!(on > 1000, "{on}");
    }

    /// The limit is at least 0 for any half width and edge, and its `ceil` is exact.
    #[test]
    fn a_wire_limit_is_in_range() {
        for w in [
            f32::INFINITY,
            f32::MAX,
            3e9,
            0.5,
            0.0,
            -0.0,
            -2.0,
            -f32::MAX,
            f32::NEG_INFINITY,
            f32::NAN,
        ] {
            for inv_length in [1.0 / 16.0, 1e-9, 1e-30, 0.0, 1.0] {
                for bias in [0, 1] {
                    let limit = wire_limit(w, inv_length, bias);
                    assert!(limit >= 0, "{w} {inv_length}: {limit}");
                }
            }
        }
        assert_eq!(wire_limit(0.5, 1.0 / 160.0, 1), 79);
        assert_eq!(wire_limit(0.5001, 1.0 / 160.0, 0), 81);
        assert_eq!(wire_limit(f32::INFINITY, 1.0, 0), i32::MAX);
        assert_eq!(wire_limit(f32::NAN, 1.0, 0), 0);
    }
}
