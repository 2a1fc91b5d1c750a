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
//! - `z_min` as computed lies in `[(Z_min - m⁺ - η⁺) U, max(Z_min - m⁻, N_z) U]` to within
//!   `2^-21` (two differences of numbers whose result is at least `3/4` of `z_ℓ`; `z_ℓ`
//!   within `2^-23` below `Z_min U`): the look's `z_min⁻` and `z_min⁺`, in units, and the
//!   frame's `tol / (f S)` taken down and up by `(1 ∓ 2^-16) (1 ∓ 2^-18)` makes up for the
//!   `2^-21`.
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
//! and `s_i <= 2^h (|X'| + |Y'| + Z' + 3) / Z = 2^h L / Z`. Then
//!
//! `g_i⁺ = (σ 2^(h + t + j - 14) (ρ + 1 + δ) + r 2^h n⁺ + m⁺ U c 2^h L) / Z`,
//!
//! with `n⁺ = n + 3 + ⌊(n + 3) 2^-k⌋ + 1 >= q (n + 3)` and `c >= 2.75 η⁺ / z_ℓ + 2^-15` in 16
//! fractional bits (from `Z_min`'s top 16 bits, taken down, and `η⁺` in their unit, taken up:
//! one `u32` quotient), is at least `g_i` with `D_i` (the quotient by `Z`, read at most
//! `2^-23` low, only raises it), and
//!
//! `g_i⁻ = (σ 2^(h + t + j - 14) (ρ - δ) + r 2^h (n - 2) - 2^-15 m⁺ U 2^h L) / Z`
//!
//! is at most `g_i` less `D_i`. The `f32` bound is within the tolerance `τ_p` where every
//! `g_i⁺ <= τ_p z_min⁻ / (f S) (1 - 2^-16)`, and over it where one `g_i⁻ > τ_p z_min⁺ / (f S)
//! (1 + 2^-16)`: the `2^-16` covers every relative term above (together under `2^-17`).
//!
//! **The tests in integers.** `σ` and `r` are read exactly from their bits (`m 2^e`, `m <
//! 2^24`), and the right sides `τ_p / (f S)` (the frame's, found in `f32` with the margins
//! above and a few more `ε`) times `z_min⁻` or `z_min⁺` in units (`Z_min - m⁺ - η⁺`, and
//! `max(Z_min - m⁻, N_z)`) are products taken down or up to 31 bits. Each test is then `Z`
//! times its side against the sum of `g_i`'s three terms times `Z`, every one an integer
//! product (below `2^62`) shifted to the units of the within side's last place, taken up for
//! `g_i⁺` and down for `g_i⁻` (a term past `2^62` is held as `2^62`: over anything a sum
//! taken up is compared with, and a bound from below; where the part `g_i⁻` takes off, or
//! the side it is compared with, is past it, the look does not find over). No `f32`
//! operation is left in the tests.
//!
//! **What it reports.** Within, each corner's `g_i⁺ Z` against its side is a fraction at
//! most 1, taken up to 30-bit integers; with the largest, `ρ`, every `g_i` is at most `ρ τ_p
//! z_min⁻ / (f S)` (less the margins), so the `f32` bound is at most `ρ τ_p`: the look reports
//! `ρ τ_p (1 + 2^-15)` in `f32` (its few roundings in the `2^-15`), or the tolerance where that
//! rounds over. Over, it reports the next number above the tolerance: the `f32` bound, a
//! number over it, is at least that, and a judgement that may report any bound over the
//! tolerance (`judge`) needs no more. A corner whose `g_i⁺` is within cannot be over: only
//! after one that is not is `g_i⁻` found, for that corner and the ones after it.
//!
//! **Over, in full.** A judgement that must report its bound where it is over (a leaf of the
//! bake left over, whose bound is the frame's) takes every corner's `g_i⁺` too, in units
//! `2^16` times coarser than the within side's (a bound far over the tolerance may pass the
//! 62 bits those take), taken up, against its side taken down: with the largest fraction
//! `ρ`, every `g_i` is at most `ρ τ_p z_min⁻ / (f S)`, so the `f32` bound is at most `ρ τ_p`,
//! as above. Where a corner's `g_i⁻` finds the bound over, the look reports `ρ τ_p (1 +
//! 2^-15)` (the fractions in `f32`, each cut to 24 bits: their roundings in the `2^-15`).
//! Measured in the test below: every triangle the look finds over it finds so in full,
//! within 6.6% above the `f32` bound. On `fw_teapot`'s ARMv6-M build, frame 3's update (a
//! close-up, whose leaves left over each report their bound) takes 48.8M instructions where
//! the `f32` bound's 64.9M did.
//!
//! The decision needs the isotropic bound over (else the `f32` judgement may stop there), the
//! scale in `f32`'s normal range (else `Quantised::worst` raises it) or a node without
//! vectors (a leaf of the bake: scale 0 and no vector, whose `W_i` is 0 in `f32` too), and is
//! the same on every target (integers, and the frame's constants in `f32` operations in a
//! fixed order).
//!
//! Measured (`the_directional_look_decides_as_the_float_bound`, random triangles and cameras):
//! of 9,721 triangles the `f32` directional bound judged, the look decides 949 of the 959
//! within and 8,742 of the 8,762 over, its within bound at most 0.7% above the `f32` one; of
//! 17,977 facing the eye, 7,041 of the 7,070 within (2.6%) and 10,707 of the 10,907 over; of
//! 2,892 without vectors, 300 of the 306 within and 2,563 of the 2,586 over. On
//! `fw_teapot`'s ARMv6-M build it takes frame 0's update from 18.14M to 9.55M instructions,
//! every frame bit-identical (10.67M with the tests' sums in `f32`).

use crate::deviation::kept::KEPT;
use crate::deviation::vectors::square_of;
use crate::deviation::SCREEN_SLACK;
use crate::math::{
    f32_of, isqrt_by_table, leading_zeros, leading_zeros_64, max, min, power_of_two, shl_64,
    shr_64, wide,
};
use crate::view::Camera;

/// The view's rows in integers, and the frame's other constants of the directional look
/// (see the [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub(crate) struct ViewRows {
    /// `⌊2^14 R⌋` toward zero: right, up, forward.
    rows: [[i16; 3]; 3],
    /// `tol / (f S)` taken down by `(1 - 2^-16) (1 - 2^-18)` and up by `(1 + 2^-16) (1 +
    /// 2^-18)`, exactly as `f32`: a depth times these is the largest `g_i⁺` within, and the
    /// least `g_i⁻` over.
    per_depth: [Scaled; 2],
    /// `k` with `2^-k` at least the root's excess `q - 1`, where `q = 1 + x^4 / 128 + 2^-18`
    /// for the largest `|τ|²` of a corner inside the view, `x`.
    root_excess: u8,
}

/// What the look decided.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Decided {
    /// The `f32` directional bound is within the tolerance: at most `a / b` of it, `[a, b]`
    /// (`a <= b < 2^31`), whose bound is [`within_bound`](Self::within_bound).
    Within([u32; 2]),
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
        let x = (sx * sx + sy * sy) * (1.0 + power_of_two(-20));
        let excess = x * x * x * x / 128.0 * (1.0 + power_of_two(-20)) + power_of_two(-18);
        // (`2^e <= excess < 2^(e + 1)`: `k = -(e + 1)`.)
        let e = ((excess.to_bits() >> 23) & 0xff) as i32 - 127;
        let root_excess = u8::try_from(-(e + 1)).ok()?;
        let focal = camera.focal() * SCREEN_SLACK;
        let per_depth = tolerance / focal;
        let per_depth = [
            per_depth * ((1.0 - power_of_two(-16)) * (1.0 - power_of_two(-18))),
            per_depth * ((1.0 + power_of_two(-16)) * (1.0 + power_of_two(-18))),
        ];
        if !(per_depth[0] > 0.0 && per_depth[1] < f32::INFINITY) {
            return None;
        }
        let per_depth = [Scaled::of_f32(per_depth[0])?, Scaled::of_f32(per_depth[1])?];
        Some(ViewRows {
            rows: [row(r)?, row(u)?, row(f)?],
            per_depth,
            root_excess,
        })
    }

    /// The look at a triangle with fixed corners `corners` (every one inside the view, at
    /// least the near plane deep), least depth `z_least`, `η⁺` `eta` and `N_z >= near` `near`
    /// in units `2^u`, whose `f32` isotropic bound is over `tolerance` (see the [module
    /// docs](self)). `over`: whether a bound over the tolerance may be any value over it (a
    /// judgement not asked for its exact bound); else, over, the look reports a bound at
    /// least the `f32` one from every corner's `g_i⁺` (see *Over, in full*).
    #[allow(clippy::too_many_arguments)]
    pub fn look(
        &self,
        tolerance: f32,
        corners: &[[i32; 3]; 3],
        node: &NodeTerms<'_>,
        z_least: u64,
        eta: u64,
        near: u32,
        u: i32,
        over: bool,
    ) -> Option<Decided> {
        // The scale in the normal range, above `2^-100` (its products stay there), or a node
        // without vectors (a leaf of the bake: no vector and a scale of 0, whose `W_i` is 0
        // in `f32` too); the remainder a number at least 0.
        let sigma_bits = node.scale.to_bits() & 0x7fff_ffff;
        let bare = sigma_bits == 0 && node.vectors.iter().all(|c| *c == [0; 3]);
        if !(bare || ((27 << 23)..0x7f80_0000).contains(&sigma_bits)) {
            return None;
        }
        let sigma = Scaled::of_f32(f32::from_bits(sigma_bits))?;
        let r = Scaled::of_f32(node.remainder)?;
        let [m_low, m_high] = node.m;
        if 4 * (m_high + eta) > z_least {
            return None;
        }
        // The least depth in units, at least and at most (each below `2^30`), and what a
        // corner's `g_i` is compared with, before its depth: `tol / (f S)` times these.
        let z_low = z_least - m_high - eta;
        let z_high = (z_least - m_low).max(u64::from(near));
        let within_at = self.per_depth[0].mul(Scaled::new(z_low as u32, u), false);
        let over_at = self.per_depth[1].mul(Scaled::new(z_high as u32, u), true);
        // `c = 2.75 η⁺ / z_ℓ + 2^-15` taken up, in 16 fractional bits: from `z_ℓ`'s top 16
        // bits (taken down) and `η⁺` in the same unit (taken up, below `2^14`).
        let shift = (64 - leading_zeros_64(z_least)).saturating_sub(16);
        let ratio = (shr_64(eta, shift) as u32 + 1) << 16;
        let ratio = ratio.div_ceil(shr_64(z_least, shift) as u32);
        // `m⁺ U c` and `2^-15 m⁺ U`.
        let m_c = Scaled::new(m_high as u32, u - 16)
            .mul(Scaled::new((11 * ratio).div_ceil(4) + 2, 0), true);
        let m_share = Scaled::new(m_high as u32, u - 15);
        let c1 = node
            .vectors
            .iter()
            .map(|c| c.iter().map(|&x| i32::from(x).abs()).sum::<i32>())
            .max()
            .unwrap_or(0) as u32;
        let [right, up, forward] = self.rows.map(|r| r.map(i32::from));
        // Each corner's terms in units of `within_at`'s last place, `2^base`: exact products
        // of integers, shifted (see `in_units`).
        let base = within_at.e;
        let mut within = true;
        // The largest `g_i⁺` so far against what it is compared with, as 31-bit fractions
        // `a / b` taken up (see `ratio_above`).
        let mut worst = (0u32, 1u32);
        // Asked for the bound in full: whether a corner found it over, and the largest
        // `g_i⁺` against what it is compared with, as a number at least it.
        let (in_full, mut found_over, mut largest) = (!over, false, 0.0f32);
        for &[x, y, z] in corners {
            let top = x.unsigned_abs().max(y.unsigned_abs()).max(z.unsigned_abs());
            let h = (32 - leading_zeros(top)).saturating_sub(15);
            let (xs, ys, zs) = (x >> h, y >> h, z >> h);
            let row = |r: &[i32; 3], p: i32| [0, 1, 2].map(|j| zs * r[j] - p * forward[j]);
            let (mx, my) = (row(&right, xs), row(&up, ys));
            let top_m = mx
                .iter()
                .chain(&my)
                .map(|v| v.unsigned_abs())
                .max()
                .unwrap_or(0);
            let t = (32 - leading_zeros(top_m)).saturating_sub(22);
            let (mx, my) = (mx.map(|v| v >> t), my.map(|v| v >> t));
            let mut square = 0u64;
            for c in node.vectors {
                let c = c.map(i32::from);
                let dot = |p: &[i32; 3]| p[0] * c[0] + p[1] * c[1] + p[2] * c[2];
                square = square.max(square_of(dot(&mx)) + square_of(dot(&my)));
            }
            let j = ((64 - leading_zeros_64(square)).saturating_sub(31)) / 2;
            let root = isqrt_by_table(shr_64(square, 2 * j) as u32);
            let e = ((1u32 << 17) >> t) + 2;
            // (`⌈x / 2^j⌉ <= ⌊x / 2^j⌋ + 1`.)
            let spill = ((3 * e * c1).div_ceil(2) >> j) + 1;
            let w = (h + t + j) as i32 - 14;
            let n = isqrt_by_table((xs * xs) as u32 + (ys * ys) as u32 + (zs * zs) as u32);
            let l = xs.unsigned_abs() + ys.unsigned_abs() + zs as u32 + 3;
            let (h, depth) = (h as i32, z as u32);
            let at = |x: Scaled, v: u32, e: i32, up: bool| in_units(x, v, e - base, up);
            let n_high = || (n + 3) + ((n + 3) >> self.root_excess) + 1;
            let limit = || wide(within_at.m, depth);
            if in_full {
                // `g_i⁺` in units `2^16` times coarser, where it may be far over `limit`
                // (which takes up to 62 bits): taken up, against `limit` taken down.
                let coarse = |x: Scaled, v: u32, e: i32| in_units(x, v, e - base - 16, true);
                let high = coarse(sigma, root + 1 + spill, w)
                    .saturating_add(coarse(r, n_high(), h))
                    .saturating_add(coarse(m_c, l, h));
                if high >= CAP {
                    return None;
                }
                largest = max(largest, f32_cut(high) / f32_cut(shr_64(limit(), 16)));
            }
            if within {
                let high = at(sigma, root + 1 + spill, w, true)
                    .saturating_add(at(r, n_high(), h, true))
                    .saturating_add(at(m_c, l, h, true));
                let limit = limit();
                if high <= limit {
                    let (a, b) = ratio_above(high, limit);
                    if wide(worst.0, b) <= wide(a, worst.1) {
                        worst = (a, b);
                    }
                    continue;
                }
                within = false;
            }
            if found_over {
                continue;
            }
            // Over `within_at` here: over the tolerance too? (Only where neither the part
            // taken off nor the side is capped: a capped one is not a bound that way.)
            let (less, side) = (
                at(m_share, l, h, true),
                in_units(over_at, depth, -base, true),
            );
            let low = at(sigma, root.saturating_sub(spill), w, false)
                .saturating_add(at(r, n.saturating_sub(2), h, false))
                .saturating_sub(less);
            if less < CAP && side < CAP && low > side {
                if !in_full {
                    // (Any number over the tolerance: the bound is at least the next one.)
                    return Some(Decided::Over(f32::from_bits(tolerance.to_bits() + 1)));
                }
                found_over = true;
            }
        }
        if found_over {
            // Every `g_i⁺` is at most `largest` of what it is compared with (to the
            // roundings below): the bound on screen at most `largest` of the tolerance, and
            // over it.
            let bound = largest * tolerance * (1.0 + power_of_two(-15));
            return (bound > tolerance && bound < f32::INFINITY).then_some(Decided::Over(bound));
        }
        if !within {
            return None;
        }
        // The largest `g_i⁺ / Z_i` is at most `a / b` of `within_at`, itself at most
        // `tol z_min⁻ / (f S)`: the bound on screen at most `a / b` of the tolerance.
        let (a, b) = worst;
        Some(Decided::Within([a, b]))
    }
}

impl Decided {
    /// The bound of a look within at `a / b` of `tolerance`: at least the `f32` directional
    /// bound, at most the tolerance.
    pub fn within_bound([a, b]: [u32; 2], tolerance: f32) -> f32 {
        let bound =
            f32_of(a as i32, 0) / f32_of(b as i32, 0) * tolerance * (1.0 + power_of_two(-15));
        min(bound, tolerance)
    }
}

/// What [`in_units`] gives a number it cannot hold.
const CAP: u64 = 1 << 62;

/// `x v 2^e` (`x`'s mantissa at most `2^31`, `v` below `2^31`) as an integer, taken `up` or
/// down; [`CAP`] where it is larger (a bound from below, not from above: over anything a
/// sum taken up is compared with, which is below `2^62`).
fn in_units(x: Scaled, v: u32, e: i32, up: bool) -> u64 {
    let p = wide(x.m, v);
    let e = x.e + e;
    if p == 0 {
        0
    } else if e >= 0 {
        if e >= 62 || p >= shr_64(CAP, e as u32) {
            CAP
        } else {
            shl_64(p, e as u32)
        }
    } else if e > -63 {
        let k = -e as u32;
        let q = shr_64(p, k);
        q + u64::from(up && shl_64(q, k) != p)
    } else {
        u64::from(up)
    }
}

/// `v` in `f32`, its bits past the first 24 cut off: at most `v`, and within a relative
/// `2^-23` of it.
fn f32_cut(v: u64) -> f32 {
    let s = (64 - leading_zeros_64(v)).saturating_sub(31);
    f32_of(shr_64(v, s) as i32, -(s as i32))
}

/// `a / b` (`a <= b`, `b > 0`) as a fraction of integers below `2^31`, at least it.
fn ratio_above(a: u64, b: u64) -> (u32, u32) {
    let s = (64 - leading_zeros_64(b)).saturating_sub(30);
    let (top, below) = (shr_64(a, s), shr_64(b, s));
    // `a / b <= (⌊a 2^-s⌋ + 1) / ⌊b 2^-s⌋`, the bottom at least `2^29` where `s > 0`.
    ((top + u64::from(s > 0)) as u32, below.max(1) as u32)
}

/// A number `m 2^e` at least 0 (`m <= 2^31`): the look's constants, and their products
/// rounded up or down as asked, in integer operations where the `f32` ones are library calls.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
struct Scaled {
    m: u32,
    e: i32,
}

impl Scaled {
    /// `m 2^e`, for `m <= 2^31`.
    fn new(m: u32, e: i32) -> Scaled {
        Scaled { m, e }
    }

    /// `v 2^e`, rounded `up` or down to 31 bits.
    fn wide(v: u64, e: i32, up: bool) -> Scaled {
        let bits = 64 - leading_zeros_64(v);
        if bits <= 31 {
            return Scaled { m: v as u32, e };
        }
        let s = bits - 31;
        let m = shr_64(v, s) as u32;
        let lost = shl_64(m.into(), s) != v;
        Scaled {
            m: m + u32::from(up && lost),
            e: e + s as i32,
        }
    }

    /// `x`, exactly; `None` for a negative number, infinity or NaN.
    fn of_f32(x: f32) -> Option<Scaled> {
        let bits = x.to_bits();
        let biased = (bits >> 23) as i32;
        match biased {
            0 => Some(Scaled::new(bits & 0x7f_ffff, -149)),
            1..=254 => Some(Scaled::new(bits & 0x7f_ffff | 0x80_0000, biased - 150)),
            _ => None,
        }
    }

    /// `self b`, rounded `up` or down.
    fn mul(self, b: Scaled, up: bool) -> Scaled {
        Scaled::wide(wide(self.m, b.m), self.e + b.e, up)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::TestRng;

    /// `m 2^e` against `n 2^k` exactly, in `u128` (both exponents within the range here).
    fn cmp(a: (u128, i32), b: (u128, i32)) -> core::cmp::Ordering {
        let e = a.1.min(b.1);
        (a.0 << (a.1 - e)).cmp(&(b.0 << (b.1 - e)))
    }

    /// Products rounded up are at least the exact product and within a unit of the last
    /// place of it, down at most it; a term in units is its exact value taken up or down (or
    /// capped where it is over `2^62`); a ratio taken up is at least the exact one, and
    /// within `2^-28` of it.
    #[test]
    fn the_integer_steps_round_the_way_they_are_asked() {
        let mut rng = TestRng::new(0x5ca1_ed00);
        let mut random = |bits: u32| {
            let v = u64::from(rng.next_u32()) << 32 | u64::from(rng.next_u32());
            v >> (64 - bits)
        };
        for k in 0..20_000 {
            let a = Scaled::new(random(1 + k % 31) as u32, (k % 40) as i32 - 20);
            let b = Scaled::new(random(1 + (k / 31) % 31) as u32, (k % 7) as i32 - 3);
            let exact = (u128::from(a.m) * u128::from(b.m), a.e + b.e);
            let (up, down) = (a.mul(b, true), a.mul(b, false));
            assert!(up.m <= 1 << 31 && down.m <= 1 << 31);
            assert!(cmp((up.m.into(), up.e), exact).is_ge(), "{a:?} {b:?}");
            assert!(cmp((down.m.into(), down.e), exact).is_le(), "{a:?} {b:?}");
            assert!(
                cmp((u128::from(down.m) + 1, down.e), exact).is_gt(),
                "{a:?} {b:?}"
            );
            assert!(up.m - down.m <= 1 && up.e == down.e || up.m == down.m);
            let v = random(1 + k % 31) as u32;
            let e = (k % 100) as i32 - 70;
            let value = (u128::from(a.m) * u128::from(v), a.e + e);
            for round_up in [true, false] {
                let got = in_units(a, v, e, round_up);
                if got == 1 << 62 {
                    assert!(cmp(value, (1 << 62, 0)).is_ge(), "{a:?} {v} {e}");
                    continue;
                }
                let got = u128::from(got);
                if round_up {
                    assert!(
                        cmp((got, 0), value).is_ge()
                            && (got == 0 || cmp((got - 1, 0), value).is_lt())
                    );
                } else {
                    assert!(cmp((got, 0), value).is_le() && cmp((got + 1, 0), value).is_gt());
                }
            }
            let d = random(62).max(1);
            let n = random(62) % d;
            let (top, below) = ratio_above(n, d);
            assert!(top < 1 << 31 && below < 1 << 31 && below > 0);
            let (x, y) = (
                u128::from(top) * u128::from(d),
                u128::from(n) * u128::from(below),
            );
            assert!(x >= y, "{n} / {d}: {top} / {below}");
            assert!((x - y) as f64 <= (d as f64) * (below as f64) * 2f64.powi(-28) + 1.0);
        }
    }
}
