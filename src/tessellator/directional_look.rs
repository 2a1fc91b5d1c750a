//! The first look's second step, for parts without an FPU: where the isotropic bound is over
//! the tolerance (see `grid_judge`), whether the `f32` directional bound
//! (`deviation::bound_on_screen`) is within it or over it, found mostly in integers from the
//! corners on the grid and the node's quantised vectors. Where it decides, it decides as the
//! `f32` bound would, so the frames are the same; near the tolerance it leaves the triangle to
//! that bound. It saves the `f32` bound's per-corner work (a ray's quotient, its widening, two
//! roots) and the corners' moves into `f32`, each a software routine there.
//!
//! # What it brackets
//!
//! It looks at a triangle whose three corners the first look found inside every plane, at
//! least `N_z >= near` deep (the `f32` bound then clips nothing), where that look found the
//! `f32` isotropic bound over the tolerance (so the judgement is the directional bound's).
//! With the corners `v_i = (x_i, y_i, z_i)` the `f32` judgement reads (each `(X_i, Y_i, Z_i)
//! U` cut toward zero to 24 bits, `grid_view`), its rays `τ_i = (x_i, y_i) / z_i`, `s_i = 1 +
//! |τ_i|_1`, the node's vectors `e_k = σ R c_k` (`R` the view's rows, as `f32`), `m = big + r`
//! and its `η`, the `f32` bound is, to relative roundings of a few `ε` (`ε = 2^-24`),
//!
//! `B = f S / z_min · max_i g_i`, `z_min = max(near, z_ℓ - m - η)`,
//! `g_i = W_i + r √(1 + |τ_i|²) + m (2 η s_i / (z_i - η) + 16 ε s_i)`, `W_i = max_k |e_k⊥ -
//! τ_i e_kz|`,
//!
//! with `z_ℓ` the least `z_i` (exactly `Z_min U`'s `f32`, as the grid reads it). Against the
//! exact value of that expression, the computed one differs by these, each bounded:
//!
//! - `W_i` as `Quantised::worst` finds it (`deviation/vectors.rs`): at least the exact value
//!   at the ray as computed, and at most `2^-18` of it plus `2 √2 u |c|_1 σ 2^-s` above,
//!   with `2^-s <= 2^-21 max |P_ij| <= 2^-21 s_i` and `σ max |c_k|_1 <= √3 m`: under `2^-17
//!   m s_i`. The ray's own two roundings move it by at most `2 ε m |τ|`. Both are in `D_i =
//!   2^-16 m s_i`.
//! - `sqrt_one_plus_above(x)` is at least `a = √(1 + x)` and above it by `(a - 1)^4 / 8y`
//!   (`y >= 1`, see `math`), `a - 1 <= x / 2`: with `x` at most the view's `s_x² + s_y²` (the
//!   corner is inside) the factor `q = 1 + x^4 / 128 + 2^-18` covers it and its roundings;
//!   the look takes `1 + 2^-k >= q` (the frame's `root_excess`, `k`).
//! - The first look bounds `m` in units `U`, `m⁻ U <= m <= m⁺ U`, and `η <= η⁺ U`
//!   (`grid_judge`); the look asks `4 (m⁺ + η⁺) <= Z_min`. The last term of `g_i` is then at
//!   most `m s_i (8/3 η / z_i + 2^-20)` (`η <= z_i / 4`).
//! - `z_min` as computed lies in `[max(near, (Z_min - m⁺ - η⁺) U), max(near, (Z_min - m⁻)
//!   U)]` to within `2^-21` (two differences of numbers whose result is at least `3/4` of
//!   `z_ℓ`; `z_ℓ` within `2^-23` below `Z_min U`); each end is read into `f32` toward zero,
//!   and the frame's `tol / (f S)` taken down and up by `(1 ∓ 2^-16) (1 ∓ 2^-18)` makes up
//!   for it.
//! - The sums, the quotient by `z_min` and the products: a few `ε` relative.
//!
//! # In integers
//!
//! `z_i W_i = σ max_k |(z_i R_⊥ - v_i⊥ R_f) c_k|` is bilinear in the corner and the vectors:
//! no ray is divided out. Per corner, shift `(X, Y, Z)` right by `h` to put the largest
//! magnitude below `2^15` (floors: each off by under `1`, and by `2^-8` more for the cut to 24
//! bits), with the rows `R̃ = ⌊2^14 R⌋` (toward zero, off by under `1`; at most `2^14`):
//!
//! `M = Z' R̃_⊥ - (X', Y')^T R̃_f`, `|M| < 2^30`,
//!
//! which is `2^14 (z R_⊥ - v_⊥ R_f) / (U 2^h)` to within `(1 + 2^-8) 2^15 + 2^16 < 2^17` an
//! entry. Shifted right by `t` to below `2^22` (a floor), each entry is off by `E < 2^(17 -
//! t) + 1` units of `2^t`; `a = M̃ c_k` is exact in `i32` (`|c|_1 <= 384`), and the exact
//! product differs from it by at most `√2 E |c_k|_1` in length. The largest `|a|²` over `k`
//! (in `u64`) has its root bracketed by `isqrt` of its top 32 bits, `[ρ, ρ + 1] 2^j`. So with
//! `C = max_k |c_k|_1` and `δ = ⌈1.5 E C / 2^j⌉`,
//!
//! `W_i ∈ σ 2^(h + t + j - 14) [ρ - δ, ρ + 1 + δ] / Z`
//!
//! (`z_i` is `Z U`, to `2^-23` below). Likewise `|v_i| / z_i` is `2^h [n - 2, n + 3] / Z` for
//! `n = isqrt(X'² + Y'² + Z'²)` (each coordinate's floor moves the length by under `√3`),
//! and `s_i <= 2^h (|X'| + |Y'| + Z' + 3) / Z = 2^h L / Z`. Every integer here is below `2^17`
//! and reads into `f32` exactly (`math::f32_of`, its power of two in the exponent). Then
//!
//! `g_i⁺ = (σ 2^(h + t + j - 14) (ρ + 1 + δ) + r 2^h n⁺ + m⁺ U c 2^h L) / Z`,
//!
//! with `n⁺ = n + 3 + ⌊(n + 3) 2^-k⌋ + 1 >= q (n + 3)` and `c >= 2.75 η⁺ / z_ℓ + 2^-15` in 16
//! fractional bits (from `Z_min`'s top 16 bits, taken down, and `η⁺` in their unit, taken up:
//! one `u32` quotient),
//! is at least `g_i` with `D_i` (each product and sum of nonnegative numbers rounds by `ε`,
//! the quotient by a `Z` read at most `2^-23` low only raises it), and
//!
//! `g_i⁻ = (σ 2^(h + t + j - 14) (ρ - δ) + r 2^h (n - 2) - 2^-15 m⁺ U 2^h L) / Z`
//!
//! is at most `g_i` less `D_i`, to the relative `2^-22` of its roundings. The `f32` bound is
//! within the tolerance `τ_p` where every `g_i⁺ <= τ_p z_min⁻ / (f S) (1 - 2^-16)`, and over it
//! where one `g_i⁻ > τ_p z_min⁺ / (f S) (1 + 2^-16)`: the `2^-16` covers every relative term
//! above (together under `2^-17`). The look reports `f S max g_i⁺ / z_min⁻ (1 + 2^-15)` (at
//! least the `f32` bound; at most the tolerance, which it reports where that rounds over)
//! within, and `f S g_i⁻ / z_min⁺ (1 - 2^-15)` over (at most the `f32` bound; at least the
//! next number above the tolerance). A corner whose `g_i⁺` is within cannot be over: only
//! after one that is not is `g_i⁻` found, for that corner and the ones after it.
//!
//! The decision needs the isotropic bound over (else the `f32` judgement may stop there), the
//! scale in `f32`'s normal range (else `Quantised::worst` raises it), and is the same on every
//! target (integers, and `f32` operations in a fixed order).
//!
//! Measured (`the_directional_look_decides_as_the_float_bound`, random triangles and cameras):
//! of 7,873 triangles the `f32` directional bound judged, the look decides 914 of the 921
//! within and 6,933 of the 6,952 over, its within bound at most 0.7% above the `f32` one; of
//! 16,069 facing the eye, 6,991 of the 7,018 within (2.6%) and 8,929 of the 9,051 over. On
//! `fw_teapot`'s ARMv6-M build it takes frame 0's update from 18.14M to 10.67M instructions,
//! every frame bit-identical.

use crate::deviation::kept::KEPT;
use crate::deviation::vectors::square_of;
use crate::deviation::SCREEN_SLACK;
use crate::math::{f32_of, isqrt, max, min};
use crate::view::Camera;

/// The view's rows in integers, and the frame's other constants of the directional look
/// (see the [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub(crate) struct ViewRows {
    /// `⌊2^14 R⌋` toward zero: right, up, forward.
    rows: [[i16; 3]; 3],
    /// `tol / (f S)` taken down by `(1 - 2^-16) (1 - 2^-18)` and up by `(1 + 2^-16) (1 +
    /// 2^-18)`: a depth times these is the largest `g_i⁺` within, and the least `g_i⁻` over.
    per_depth: [f32; 2],
    /// `f S`.
    focal: f32,
    /// `k` with `2^-k` at least the root's excess `q - 1`, where `q = 1 + x^4 / 128 + 2^-18`
    /// for the largest `|τ|²` of a corner inside the view, `x`.
    root_excess: u8,
}

/// What the look decided.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Decided {
    /// The `f32` directional bound is within the tolerance: a bound at least it, at most the
    /// tolerance.
    Within(f32),
    /// The `f32` directional bound is over the tolerance: a bound at most it, over the
    /// tolerance.
    Over(f32),
}

/// A node's quantised vectors and its bound's numbers, as the look reads them.
pub(crate) struct NodeTerms<'a> {
    /// The kept vectors.
    pub vectors: &'a [[i8; 3]; KEPT],
    /// Their scale `σ`.
    pub scale: f32,
    /// The remainder `r`.
    pub remainder: f32,
    /// At least and at most the judgement's `m = big + r`, in the grid's units.
    pub m: [u64; 2],
}

/// `2^-k` for `k` in `0..=126`.
fn below_one(k: u32) -> f32 {
    f32::from_bits((127 - k) << 23)
}

impl ViewRows {
    /// The constants of `camera` at `tolerance`.
    pub fn new(camera: &Camera, tolerance: f32) -> Option<ViewRows> {
        let fixed = |x: f32| {
            let v = x * 16384.0;
            (-16385.0 < v && v < 16385.0).then_some(v as i16)
        };
        let [r, u, f] = camera.view_rows();
        let row =
            |r: [f32; 3]| -> Option<[i16; 3]> { Some([fixed(r[0])?, fixed(r[1])?, fixed(r[2])?]) };
        let ([sx, sy], _) = camera.side_planes();
        let x = (sx * sx + sy * sy) * (1.0 + below_one(20));
        let excess = x * x * x * x / 128.0 * (1.0 + below_one(20)) + below_one(18);
        // (`2^e <= excess < 2^(e + 1)`: `k = -(e + 1)`.)
        let e = ((excess.to_bits() >> 23) & 0xff) as i32 - 127;
        let root_excess = u8::try_from(-(e + 1)).ok()?;
        let focal = camera.focal() * SCREEN_SLACK;
        let per_depth = tolerance / focal;
        let per_depth = [
            per_depth * ((1.0 - below_one(16)) * (1.0 - below_one(18))),
            per_depth * ((1.0 + below_one(16)) * (1.0 + below_one(18))),
        ];
        if !(per_depth[0] > 0.0 && per_depth[1] < f32::INFINITY) {
            return None;
        }
        Some(ViewRows {
            rows: [row(r)?, row(u)?, row(f)?],
            per_depth,
            focal,
            root_excess,
        })
    }

    /// The look at a triangle with fixed corners `corners` (every one inside the view, at
    /// least the near plane deep), least depth `z_least` and `η⁺` `eta` in units `2^u`, whose
    /// `f32` isotropic bound is over `tolerance` (see the [module docs](self)). `over`:
    /// whether a bound over the tolerance may be any value over it (a judgement not asked
    /// for its exact bound).
    #[allow(clippy::too_many_arguments)]
    pub fn look(
        &self,
        camera: &Camera,
        tolerance: f32,
        corners: [[i32; 3]; 3],
        node: &NodeTerms<'_>,
        z_least: u64,
        eta: u64,
        u: i32,
        over: bool,
    ) -> Option<Decided> {
        // The scale in the normal range, above `2^-100` (its products stay there), the
        // remainder a number at least 0.
        let sigma_bits = node.scale.to_bits() & 0x7fff_ffff;
        if !((27 << 23)..0x7f80_0000).contains(&sigma_bits)
            || node.remainder.to_bits() >= 0x7f80_0000
        {
            return None;
        }
        let (sigma, r) = (f32::from_bits(sigma_bits), node.remainder);
        let [m_low, m_high] = node.m;
        if 4 * (m_high + eta) > z_least {
            return None;
        }
        // (Each below `2^30`.)
        let least_depth = |z: u64| max(camera.near(), f32_of(z as i32, -u));
        let z_low = least_depth(z_least - m_high - eta);
        let z_high = least_depth(z_least - m_low);
        let within_at = z_low * self.per_depth[0];
        let over_at = z_high * self.per_depth[1];
        // `c = 2.75 η⁺ / z_ℓ + 2^-15` taken up, in 16 fractional bits: from `z_ℓ`'s top 16
        // bits (taken down) and `η⁺` in the same unit (taken up, below `2^14`).
        let shift = (64 - z_least.leading_zeros()).saturating_sub(16);
        let ratio = ((eta >> shift) as u32 + 1) << 16;
        let ratio = ratio.div_ceil((z_least >> shift) as u32);
        let m_c = f32_of(m_high as i32, -u) * f32_of((11 * ratio).div_ceil(4) as i32 + 2, 16);
        let m = f32_of(m_high as i32, -u);
        let c1 = node
            .vectors
            .iter()
            .map(|c| c.iter().map(|&x| i32::from(x).abs()).sum::<i32>())
            .max()
            .unwrap_or(0) as u32;
        let [right, up, forward] = self.rows.map(|r| r.map(i32::from));
        let mut within = true;
        let mut worst = 0.0f32;
        for [x, y, z] in corners {
            let top = x.unsigned_abs().max(y.unsigned_abs()).max(z.unsigned_abs());
            let h = (32 - top.leading_zeros()).saturating_sub(15);
            let (xs, ys, zs) = (x >> h, y >> h, z >> h);
            let row = |r: &[i32; 3], p: i32| [0, 1, 2].map(|j| zs * r[j] - p * forward[j]);
            let (mx, my) = (row(&right, xs), row(&up, ys));
            let top_m = mx
                .iter()
                .chain(&my)
                .map(|v| v.unsigned_abs())
                .max()
                .unwrap_or(0);
            let t = (32 - top_m.leading_zeros()).saturating_sub(22);
            let (mx, my) = (mx.map(|v| v >> t), my.map(|v| v >> t));
            let mut square = 0u64;
            for c in node.vectors {
                let c = c.map(i32::from);
                let dot = |p: &[i32; 3]| p[0] * c[0] + p[1] * c[1] + p[2] * c[2];
                square = square.max(square_of(dot(&mx)) + square_of(dot(&my)));
            }
            let j = ((64 - square.leading_zeros()).saturating_sub(31)) / 2;
            let root = isqrt((square >> (2 * j)) as u32) as i32;
            let e = ((1u32 << 17) >> t) + 2;
            let spill = (3 * e * c1).div_ceil(2).div_ceil(1 << j) as i32;
            if spill >= 1 << 22 {
                return None;
            }
            let w = (h + t + j) as i32 - 14;
            let n = isqrt((xs * xs) as u32 + (ys * ys) as u32 + (zs * zs) as u32) as i32;
            let l = xs.abs() + ys.abs() + zs + 3;
            let (h, depth) = (h as i32, f32_of(z, 0));
            if within {
                let n_high = (n + 3) + ((n + 3) >> self.root_excess) + 1;
                let high = (sigma * f32_of(root + 1 + spill, -w)
                    + r * f32_of(n_high, -h)
                    + m_c * f32_of(l, -h))
                    / depth;
                if high <= within_at {
                    worst = max(worst, high);
                    continue;
                }
                within = false;
                if !over {
                    return None;
                }
            }
            // Over `within_at` here: over the tolerance too?
            let low = sigma * f32_of((root - spill).max(0), -w) + r * f32_of((n - 2).max(0), -h)
                - m * f32_of(l, -(h - 15));
            if low > over_at * depth {
                let bound = self.focal * (low / depth) / z_high * (1.0 - below_one(15));
                return Some(Decided::Over(max(
                    bound,
                    f32::from_bits(tolerance.to_bits() + 1),
                )));
            }
        }
        within.then(|| {
            Decided::Within(min(
                self.focal * worst / z_low * (1.0 + below_one(15)),
                tolerance,
            ))
        })
    }
}
