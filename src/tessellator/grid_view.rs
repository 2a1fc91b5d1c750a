//! The bake's points moved into a frame's view coordinates in integers, for parts without an
//! FPU (`Arithmetic::Integer` over a hierarchy's bytes): a judged triangle's corners from
//! their points on the model box's grid, without a software `f32` operation.
//!
//! # How
//!
//! A point of the bytes is `P = min + q s` (per coordinate, `q` a `u16`; see `quantize`), and
//! its view coordinates are `V_i = Σ_k r_ik (P_k - eye_k)` with the camera's rows `r_i`. So
//! `V_i = Σ_k a_ik q_k + c_i` with `a_ik = r_ik s_k` and `c_i = r_i · (min - eye)`, both
//! found once a frame in `f32` and held in fixed point, `A_ik = ⌊a_ik 2^e⌋` (below `2^30`)
//! and `C_i = ⌊c_i 2^e⌋`; a corner is then nine products of a 30-bit and a 16-bit integer
//! (each as two 32-bit ones), summed in 64 bits, and the sum, shifted right by a frame's
//! `s` bits to fit 30, read back into `f32` from its bits as a multiple of `2^(s - e)`.
//!
//! # How far from the float corners
//!
//! The bake measured every bound against the `f32` point `P' = fl(min + fl(q s))`, and the
//! bounds on screen take corners within a slack of `R (P' - eye)` (`deviation/screen.rs`:
//! *Rounding*). Per coordinate, the corner found here is off it by at most:
//!
//! - `65535 Σ_k (ε |a_ik| + 2^-e)`: each `a_ik`'s product rounding (`ε = 2^-24` of it) and its
//!   floor, times `q_k`;
//! - `5 ε Σ_k |r_ik| |min_k - eye_k| + 2^-e`: `c_i`'s roundings (the differences, the three
//!   products and two sums) and its floor;
//! - `2 ε Σ_k |r_ik| (|min_k| + 65535 s_k)`: `P'` against `min + q s` (two roundings, each
//!   within `ε` of a value at most `|min_k| + q_k s_k`);
//! - `2^(s - e)`: the shift's floor;
//! - `2^-23 (|c_i| + 65535 Σ_k |a_ik|)` and a little: the read back into `f32`, which cuts
//!   the bits that do not fit.
//!
//! [`GridView::slack`] is twice the largest sum over the three coordinates, taken up by 2
//! again: the point's distance (at most `√3` times the largest coordinate's) and the few
//! roundings of computing it in `f32`. The judgement adds it to the corners' slack, so
//! every bound stays a bound.
//!
//! It is small: on `fw_teapot`'s four frames 2.7e-5 to 5.2e-5 model units, under a
//! hundred-thousandth of the teapot's size (and the test below finds the corners at most
//! 0.07 of it away).

use glam::Vec3;

use super::quantize::PositionGrid;
use crate::deviation::EPS;
use crate::math::{f32_of, max};
use crate::view::Camera;

/// A frame's move of the grid's points into view coordinates, in fixed point (see the
/// [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub(crate) struct GridView {
    /// `⌊r_ik s_k 2^e⌋`.
    a: [[i32; 3]; 3],
    /// `⌊r_i · (min - eye) 2^e⌋`.
    c: [i64; 3],
    /// The fixed point's exponent `e`.
    e: i32,
    /// Bits a sum is shifted right by to fit 30 (its `f32` keeps 24 of them).
    shift: i32,
    /// At least the distance of a corner found here from the `f32` one.
    slack: f32,
}

/// Largest `|a_ik| 2^e`: `2^30`.
const A_BITS: i32 = 30;

/// Largest `|c_i| 2^e`: `2^60` (with the products, below `2^61`).
const C_BITS: i32 = 60;

impl GridView {
    /// The move of `grid`'s points into `camera`'s view coordinates; `None` where a value is
    /// not finite or too large for the fixed point (far beyond any view of the model).
    pub fn new(camera: &Camera, grid: &PositionGrid) -> Option<GridView> {
        let rows = camera.view_rows();
        let eye = camera.eye().to_array();
        let a = rows.map(|r| [0, 1, 2].map(|k| r[k] * grid.step[k]));
        let d = [0, 1, 2].map(|k| grid.min[k] - eye[k]);
        let c = rows.map(|r| r[0] * d[0] + r[1] * d[1] + r[2] * d[2]);
        let mut big = 0.0f32;
        for x in a.iter().flatten() {
            big = max(big, x.abs());
        }
        if !(big >= f32::MIN_POSITIVE && big.is_finite()) {
            return None;
        }
        // The largest `e` with `big 2^e` below `2^30` (`2^-e` a normal `f32`).
        let exponent = ((big.to_bits() >> 23) & 0xff) as i32 - 127;
        let e = A_BITS - 1 - exponent;
        if !(-126..=126).contains(&e) {
            return None;
        }
        let mut fixed = [[0i32; 3]; 3];
        for (row, out) in a.iter().zip(&mut fixed) {
            for (x, o) in row.iter().zip(out.iter_mut()) {
                *o = i32::try_from(floor_fixed(*x, e)?).ok()?;
            }
        }
        let mut wide = [0i64; 3];
        for (x, o) in c.iter().zip(&mut wide) {
            *o = floor_fixed(*x, e)?;
            if o.unsigned_abs() >= 1 << C_BITS {
                return None;
            }
        }
        // The largest sum, and the shift that brings it below `2^30`.
        let mut most = 0u64;
        for (row, c) in fixed.iter().zip(&wide) {
            let products: u64 = row
                .iter()
                .map(|a| u64::from(a.unsigned_abs()) * 65535)
                .sum();
            most = most.max(c.unsigned_abs() + products);
        }
        let shift = (64 - crate::math::leading_zeros_64(most) as i32 - A_BITS).max(0);
        if !(-126..=126).contains(&(e - shift)) {
            return None;
        }
        // The slack (see the module docs), per coordinate, then the largest.
        let unit = f32::from_bits(((127 - e) as u32) << 23); // 2^-e
        let cut = f32::from_bits(((127 - e + shift) as u32) << 23); // 2^(shift - e)
        let q_max = 65535.0f32;
        let mut worst = 0.0f32;
        for i in 0..3 {
            let (mut products, mut offset, mut decoded, mut reach) = (0.0f32, 0.0f32, 0.0f32, 0.0);
            for k in 0..3 {
                let r = rows[i][k].abs();
                products += EPS * a[i][k].abs() + unit;
                offset += r * (grid.min[k] - eye[k]).abs();
                decoded += r * (grid.min[k].abs() + q_max * grid.step[k]);
                reach += a[i][k].abs();
            }
            let sum = q_max * products
                + 5.0 * EPS * offset
                + unit
                + cut
                + 2.0 * EPS * decoded
                + 2.0 * EPS * (c[i].abs() + q_max * reach + offset + decoded);
            worst = max(worst, sum);
        }
        let slack = 4.0 * worst;
        slack.is_finite().then_some(GridView {
            a: fixed,
            c: wide,
            e,
            shift,
            slack,
        })
    }

    /// Grid point `q` in the frame's view coordinates.
    #[cfg(test)]
    pub fn point(&self, q: [u16; 3]) -> Vec3 {
        self.point_of(self.fixed(q))
    }

    /// Grid point `q` in the frame's view coordinates in fixed point: multiples of
    /// `2^`[`unit_exponent`](Self::unit_exponent), each below `2^30` in magnitude.
    #[inline(always)]
    pub fn fixed(&self, q: [u16; 3]) -> [i32; 3] {
        [0, 1, 2].map(|i| {
            let mut sum = self.c[i];
            for (a, q) in self.a[i].iter().zip(q) {
                sum += product(*a, q);
            }
            // (Below `2^30` after the shift: see `new`.)
            crate::math::sar_64(sum, self.shift as u32) as i32
        })
    }

    /// The point [`point`](Self::point) reads from its [`fixed`](Self::fixed) coordinates:
    /// each cut to the 24 bits an `f32` keeps (toward zero).
    #[inline(always)]
    pub fn point_of(&self, fixed: [i32; 3]) -> Vec3 {
        let e = self.e - self.shift;
        Vec3::new(
            f32_of(fixed[0], e),
            f32_of(fixed[1], e),
            f32_of(fixed[2], e),
        )
    }

    /// The exponent `u` of the fixed point's unit `2^u` (see [`fixed`](Self::fixed)).
    pub fn unit_exponent(&self) -> i32 {
        self.shift - self.e
    }

    /// At least the distance of a corner [`point`](Self::point) finds from the one the
    /// float path finds from the same point (see the [module docs](self)).
    pub fn slack(&self) -> f32 {
        self.slack
    }
}

/// `a q` for `|a| < 2^30`, from two 32-bit products (no 64-bit multiplication, which a
/// part without one makes in software).
#[inline(always)]
fn product(a: i32, q: u16) -> i64 {
    let q = i32::from(q);
    // `a = hi 2^15 + lo`, `0 <= lo < 2^15`: `|hi q| < 2^31`, `lo q < 2^31`.
    let (hi, lo) = (a >> 15, a & 0x7fff);
    (i64::from(hi * q) << 15) + i64::from(lo * q)
}

/// `⌊x 2^e⌋` from the bits of `x`, where it is below `2^62` in magnitude; `None` for a
/// value not finite or larger. (The renderer's `fixed_of` is this in 32 bits: it reads
/// every corner it draws, where 64-bit shifts cost ARMv6-M 0.25M instructions a frame.)
pub(crate) fn floor_fixed(x: f32, e: i32) -> Option<i64> {
    let bits = x.to_bits();
    let negative = bits >> 31 != 0;
    let exponent = ((bits >> 23) & 0xff) as i32;
    if exponent == 255 {
        return None;
    }
    let (mantissa, exponent) = match exponent {
        0 => (u64::from(bits & 0x7f_ffff), 1),
        x => (u64::from((bits & 0x7f_ffff) | 0x80_0000), x),
    };
    if mantissa == 0 {
        return Some(0);
    }
    let up = exponent - 150 + e;
    let magnitude = if up >= 0 {
        if up > 38 {
            return None;
        }
        crate::math::shl_64(mantissa, up as u32)
    } else {
        // (In 32 bits: the mantissa has 24.)
        let (mantissa, down) = (mantissa as u32, (-up) as u32);
        let whole = mantissa.checked_shr(down).unwrap_or(0);
        // `⌊-y⌋ = -⌈y⌉`: one more where bits were shifted out.
        let cut = whole.checked_shl(down).unwrap_or(0) != mantissa;
        u64::from(whole + u32::from(negative && cut))
    };
    let magnitude = magnitude as i64;
    Some(if negative { -magnitude } else { magnitude })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::TestRng;
    use crate::view::Projection;

    /// Random grids and cameras (near and far from the model, the grid's box anywhere): every
    /// corner found in integers is within the slack of the `f32` one (measured in `f64`
    /// against the exact move of the `f32` point), and the slack is small.
    #[test]
    fn grid_corners_are_within_their_slack_of_the_float_ones() {
        let mut rng = TestRng::new(0x6a1d_7e55);
        let mut unit = |scale: f32| rng.signed(1 << 20) as f32 / (1 << 20) as f32 * scale;
        let mut worst_ratio = 0.0f64;
        let mut corners = 0;
        for k in 0..400 {
            let size = [0.01, 1.0, 40.0, 3000.0][k % 4];
            let centre =
                Vec3::new(unit(2.0), unit(2.0), unit(2.0)) * size * [0.0, 1.0, 50.0][k % 3];
            let min = centre - Vec3::new(1.0 + unit(0.5), 1.0 + unit(0.5), 1.0 + unit(0.5)) * size;
            let max = centre + Vec3::new(1.0 + unit(0.5), 1.0 + unit(0.5), 1.0 + unit(0.5)) * size;
            let grid = PositionGrid {
                min: min.to_array(),
                step: ((max - min) / 65535.0).to_array(),
            };
            let eye = centre
                + Vec3::new(unit(1.0), unit(1.0), unit(1.0)).normalize_or(Vec3::X)
                    * size
                    * (2.5 + unit(2.0));
            let Ok(camera) = Camera::new(
                eye,
                centre + Vec3::new(unit(1.0), unit(1.0), unit(1.0)) * size * 0.2,
                Vec3::Z,
                Projection::Perspective {
                    fov_y_degrees: 40.0,
                },
                size * 0.01,
                [240, 240],
            ) else {
                continue;
            };
            let Some(g) = GridView::new(&camera, &grid) else {
                panic!("case {k}: no grid view");
            };
            let rows = camera.view_rows();
            let eye = camera.eye().to_array();
            for _ in 0..200 {
                let q: [u16; 3] = [0, 1, 2].map(|_| (unit(32768.0) + 32767.0) as u16);
                let q = match corners % 7 {
                    0 => [65535; 3],
                    1 => [0; 3],
                    _ => q,
                };
                let p = grid.decode(q);
                let exact: [f64; 3] = rows.map(|r| {
                    (0..3)
                        .map(|k| r[k] as f64 * (p[k] as f64 - eye[k] as f64))
                        .sum()
                });
                let got = g.point(q);
                let d = (0..3)
                    .map(|i| (got.to_array()[i] as f64 - exact[i]).powi(2))
                    .sum::<f64>()
                    .sqrt();
                assert!(d <= g.slack() as f64, "case {k}: {d} > {}", g.slack());
                worst_ratio = worst_ratio.max(d / g.slack() as f64);
                corners += 1;
            }
            // A few millionths of the model's size, at most.
            assert!(
                g.slack() < 2e-5 * size * 60.0,
                "case {k}: slack {}",
                g.slack()
            );
        }
        assert!(
            corners > 70_000 && worst_ratio > 0.01,
            "{corners} {worst_ratio}"
        );
    }

    #[test]
    fn fixed_values_and_products() {
        for x in [1.5f32, -2.25, 3.0e-7, -1234.5678] {
            let v = floor_fixed(x, 20).unwrap();
            assert_eq!(v, (x as f64 * 2f64.powi(20)).floor() as i64, "{x}");
        }
        assert_eq!(floor_fixed(f32::INFINITY, 0), None);
        // Random bits at every exponent it takes: the floor, or none beyond `2^62`.
        let mut rng = TestRng::new(0xf100_4001);
        for k in 0..300_000 {
            let x = f32::from_bits(rng.next_u32());
            let e = (k % 160) - 80;
            let exact = x as f64 * 2f64.powi(e);
            match floor_fixed(x, e) {
                Some(v) => assert_eq!(v as f64, exact.floor(), "{x} 2^{e}"),
                None => assert!(!x.is_finite() || exact.abs() >= 2f64.powi(61), "{x} 2^{e}"),
            }
        }
        assert_eq!(product(-(1 << 29) - 7, 65535), (-(1i64 << 29) - 7) * 65535);
        assert_eq!(product((1 << 30) - 1, 40_000), ((1i64 << 30) - 1) * 40_000);
    }
}
