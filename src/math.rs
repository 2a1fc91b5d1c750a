//! The one place the kernel's floating-point helpers live.
//!
//! Every `libm` call goes through here (as in glam's `f32/math.rs`), and the interpolation the
//! evaluators use is defined once, so host and Cortex-M compute the same bits: only IEEE-754
//! element-wise operations and correctly rounded square roots, in a fixed order.

use glam::{Vec3, Vec4};

/// Whether the target computes `f32` in hardware: a host, an ARM target with the hard-float
/// ABI (the Cortex-M4F's `eabihf`), a RISC-V one with the `F` extension. Elsewhere (ARMv6-M,
/// RV32IMC) every operation is a library call of about a hundred instructions, and work
/// that saves some is worth a little memory (see `Tessellator::viewed`).
pub(crate) const HARD_FLOAT: bool = cfg!(any(
    not(target_os = "none"),
    target_abi = "eabihf",
    target_feature = "f"
));

/// Whether the build carries the integer forms of work that is `f32` elsewhere: where `f32`
/// is software, and on a host (which finds the frames such a part finds). A bare-metal part
/// with an FPU leaves them out (its flash: the grid's integer move alone was 1.3 KB of the
/// Cortex-M4F's), and computes those steps in `f32`.
pub(crate) const INTEGER_FORMS: bool = !HARD_FLOAT || cfg!(not(target_os = "none"));

/// Whether counting a word's leading zero bits is taken as one instruction: everywhere but
/// on 32-bit ARM without an FPU, taken for ARMv6-M (no `CLZ`: `u32::leading_zeros` is a
/// library call, `__clzsi2`; an ARMv7-M part without an FPU has the instruction, but no
/// target setting tells the two apart, as for [`HARD_DIVIDE`]), and on RISC-V without the
/// `Zbb` extension (RV32IMC: the same call).
const HARD_CLZ: bool = HARD_FLOAT
    || cfg!(target_feature = "zbb")
    || !cfg!(any(target_arch = "arm", target_arch = "riscv32"));

/// `x.leading_zeros()`: the instruction where there is one, else two halvings of the word
/// and a table of a byte's leading zeros, in line (about ten instructions, where the
/// library's `__clzsi2` was about 35 with its call and return, and four halvings about
/// fifteen). On ARMv6-M, `fw_teapot`'s frame 0 update took 0.12M instructions fewer, its render
/// 0.13M, than with the halvings in the tessellator and the library's call in the renderer.
#[inline(always)]
pub(crate) fn leading_zeros(x: u32) -> u32 {
    match HARD_CLZ {
        true => x.leading_zeros(),
        false => leading_zeros_in_table(x),
    }
}

/// [`leading_zeros`] without the instruction (on every target: the tests check it).
#[inline(always)]
fn leading_zeros_in_table(x: u32) -> u32 {
    let (x, n) = match x >> 16 {
        0 => (x, 16),
        high => (high, 0),
    };
    let (x, n) = match x >> 8 {
        0 => (x, n + 8),
        high => (high, n),
    };
    n + u32::from(BYTE_LEADING_ZEROS[(x & 0xff) as usize])
}

/// A byte's leading zero bits, of eight (8 for 0).
const BYTE_LEADING_ZEROS: [u8; 256] = {
    let mut table = [0u8; 256];
    let mut i = 0;
    while i < 256 {
        table[i] = (i as u8).leading_zeros() as u8;
        i += 1;
    }
    table
};

/// `x.leading_zeros()` for a `u64`, by [`leading_zeros`] of its halves.
#[inline(always)]
pub(crate) fn leading_zeros_64(x: u64) -> u32 {
    match HARD_CLZ {
        true => x.leading_zeros(),
        false => leading_zeros_64_in_words(x),
    }
}

/// [`leading_zeros_64`] without the instruction.
#[inline(always)]
fn leading_zeros_64_in_words(x: u64) -> u32 {
    match (x >> 32) as u32 {
        0 => 32 + leading_zeros_in_table(x as u32),
        high => leading_zeros_in_table(high),
    }
}

/// Whether a 64-bit shift by a count known only when it runs is a library call: on 32-bit
/// ARM without an FPU, taken for ARMv6-M (`__aeabi_llsl`, `__aeabi_llsr`, `__aeabi_lasr`,
/// each about twenty instructions and a call), as for [`HARD_CLZ`].
const SOFT_SHIFTS: bool = !HARD_FLOAT && cfg!(target_arch = "arm");

/// `x >> k` (`k < 64`), on its two words in line where the shift is a library call.
#[inline(always)]
pub(crate) fn shr_64(x: u64, k: u32) -> u64 {
    match SOFT_SHIFTS {
        true => shr_64_in_words(x, k),
        false => x >> k,
    }
}

/// `x << k` (`k < 64`), as [`shr_64`].
#[inline(always)]
pub(crate) fn shl_64(x: u64, k: u32) -> u64 {
    match SOFT_SHIFTS {
        true => shl_64_in_words(x, k),
        false => x << k,
    }
}

/// `x >> k` of a signed `x` (`k < 64`; the floor of `x 2^-k`), as [`shr_64`].
#[inline(always)]
pub(crate) fn sar_64(x: i64, k: u32) -> i64 {
    match SOFT_SHIFTS {
        true => sar_64_in_words(x, k),
        false => x >> k,
    }
}

/// [`shr_64`] on the two words (on every target: the tests check it).
#[inline(always)]
fn shr_64_in_words(x: u64, k: u32) -> u64 {
    let (low, high) = (x as u32, (x >> 32) as u32);
    match k {
        0 => x,
        1..=31 => u64::from(high >> k) << 32 | u64::from(low >> k | high << (32 - k)),
        _ => u64::from(high >> (k - 32)),
    }
}

/// [`shl_64`] on the two words.
#[inline(always)]
fn shl_64_in_words(x: u64, k: u32) -> u64 {
    let (low, high) = (x as u32, (x >> 32) as u32);
    match k {
        0 => x,
        1..=31 => u64::from(high << k | low >> (32 - k)) << 32 | u64::from(low << k),
        _ => u64::from(low << (k - 32)) << 32,
    }
}

/// [`sar_64`] on the two words.
#[inline(always)]
fn sar_64_in_words(x: i64, k: u32) -> i64 {
    let (low, high) = (x as u32, (x >> 32) as i32);
    match k {
        0 => x,
        1..=31 => i64::from(high >> k) << 32 | i64::from(low >> k | (high as u32) << (32 - k)),
        _ => i64::from(high >> (k - 32)),
    }
}

/// `v 2^-e` as `f32`, exact where `|v| < 2^24`, from bits (no `f32` arithmetic); beyond that
/// the bits that do not fit are cut off. Zero where the value is below `f32`'s normal range,
/// infinite above it.
pub(crate) fn f32_of(v: i32, e: i32) -> f32 {
    if v == 0 {
        return 0.0;
    }
    let sign = (v as u32) & 0x8000_0000;
    let magnitude = v.unsigned_abs();
    let top = 31 - leading_zeros(magnitude) as i32;
    let mantissa = if top > 23 {
        magnitude >> (top - 23)
    } else {
        magnitude << (23 - top)
    };
    let exponent = top - e + 127;
    if exponent <= 0 {
        return f32::from_bits(sign);
    }
    if exponent >= 255 {
        return f32::from_bits(sign | 0x7f80_0000);
    }
    f32::from_bits(sign | (exponent as u32) << 23 | (mantissa & 0x7f_ffff))
}

/// `2^k`, for `k` in `-126..=127`, from its bits.
#[inline(always)]
pub(crate) const fn power_of_two(k: i32) -> f32 {
    f32::from_bits(((127 + k) as u32) << 23)
}

/// `a b`, exact. On 32-bit ARM without an FPU (ARMv6-M has no 32 by 32 to 64-bit multiply),
/// from four 16-bit products rather than the library's 64-bit one.
#[inline(always)]
pub(crate) fn wide(a: u32, b: u32) -> u64 {
    if crate::math::HARD_FLOAT || !cfg!(target_arch = "arm") {
        u64::from(a) * u64::from(b)
    } else {
        wide_in_halves(a, b)
    }
}

/// [`wide`] from 16-bit halves.
#[inline(always)]
pub(crate) fn wide_in_halves(a: u32, b: u32) -> u64 {
    let (ah, al, bh, bl) = (a >> 16, a & 0xffff, b >> 16, b & 0xffff);
    let middle = u64::from(ah * bl) + u64::from(al * bh);
    (u64::from(ah * bh) << 32) + (middle << 16) + u64::from(al * bl)
}

/// `a b` for `i32` operands, exact: [`wide`] of their magnitudes, with their sign.
#[inline(always)]
pub(crate) fn wide_signed(a: i32, b: i32) -> i64 {
    let magnitude = wide(a.unsigned_abs(), b.unsigned_abs()) as i64;
    if (a ^ b) < 0 {
        -magnitude
    } else {
        magnitude
    }
}

/// Whether a division is one instruction: everywhere but on 32-bit ARM without an FPU, taken
/// for ARMv6-M, whose quotients are library calls of 50 to 100 instructions. (An ARMv7-M
/// part without an FPU, which divides in hardware, takes the reciprocal too: no target
/// setting tells the two apart. Not measured there.)
#[cfg(any(feature = "embedded-graphics", test))]
pub(crate) const HARD_DIVIDE: bool = HARD_FLOAT || !cfg!(target_arch = "arm");

/// A positive divisor `a`, ready for many exact quotients: where a division is a library
/// call ([`HARD_DIVIDE`] false), with its reciprocal `⌊(2^32 - 1) / a⌋`, so that each quotient
/// is one product and at most two corrections.
///
/// **Why two.** With `inv = ⌊(2^32 - 1) / a⌋`, `inv <= (2^32 - 1) / a < 2^32 / a` and
/// `inv > (2^32 - 1) / a - 1`. For `x < 2^32` the estimate `q̂ = ⌊x inv / 2^32⌋` is then at
/// most `⌊x / a⌋`, and `x inv / 2^32 > x / a - x / (a 2^32) - x / 2^32 > x / a - 2`, so
/// `q̂ >= ⌊x / a⌋ - 2`: `x - q̂ a` (at most `x`, no overflow) is below `3 a`, and taking `a`
/// off it while it is at least `a` ends in at most two steps at the exact remainder.
#[cfg(any(feature = "embedded-graphics", test))]
#[derive(Clone, Copy, Debug)]
pub(crate) struct Divisor {
    a: u32,
    inv: u32,
    /// `a`'s leading zero bits (no instruction on ARMv6-M: found once).
    zeros: u32,
}

#[cfg(any(feature = "embedded-graphics", test))]
impl Divisor {
    /// `a`, which must be positive (0 gives quotients of 0).
    #[inline(always)]
    pub fn new(a: u32) -> Divisor {
        let zeros = leading_zeros(a);
        let inv = match HARD_DIVIDE {
            true => 0,
            false => reciprocal(a, zeros),
        };
        Divisor { a, inv, zeros }
    }

    /// The divisor's leading zero bits: a remainder shifted left by as many still fits.
    #[inline(always)]
    pub fn leading_zeros(&self) -> u32 {
        self.zeros
    }

    /// `(⌊x / a⌋, x mod a)`, exact: a division where it is one instruction, else the
    /// reciprocal's product and its corrections.
    #[inline(always)]
    pub fn div_rem(&self, x: u32) -> (u32, u32) {
        match HARD_DIVIDE {
            true => match (x.checked_div(self.a), x.checked_rem(self.a)) {
                (Some(q), Some(r)) => (q, r),
                _ => (0, x),
            },
            false => self.div_rem_by_reciprocal(x),
        }
    }

    /// [`div_rem`](Self::div_rem) by the reciprocal (see the type's docs), on every target
    /// (the tests check it against the division).
    #[inline(always)]
    pub fn div_rem_by_reciprocal(&self, x: u32) -> (u32, u32) {
        let inv = match HARD_DIVIDE {
            true => u32::MAX.checked_div(self.a).unwrap_or(0),
            false => self.inv,
        };
        let mut q = (wide(x, inv) >> 32) as u32;
        let mut r = x.wrapping_sub(q.wrapping_mul(self.a));
        // (At most twice; `a = 0` leaves `r = x` and `q = 0`: the bound ends it.)
        for _ in 0..2 {
            if r >= self.a && self.a != 0 {
                r -= self.a;
                q += 1;
            }
        }
        (q, r)
    }

    /// `⌊n 2^shift / a⌋`, exact, for `shift <= 31` and `a` below `2^31`: in 32-bit quotients
    /// by `a`, one and then one per `clz(a)` bits of `shift` (a 64-bit division is a library
    /// call on every 32-bit part; these are hardware on a Cortex-M3 and up, and on ARMv6-M a
    /// product by the reciprocal found once, see the type's docs). Out of line: one copy for
    /// the rasteriser's four slopes of a triangle.
    #[inline(never)]
    pub fn floor_shifted(self, n: i32, shift: u32) -> i64 {
        self.floor_shifted_joining(n, shift, !HARD_FLOAT)
    }

    /// [`floor_shifted`](Self::floor_shifted), joining a remainder's digits of one quotient
    /// in line where `join` (on every target: the tests check both).
    #[inline(always)]
    fn floor_shifted_joining(self, n: i32, shift: u32, join: bool) -> i64 {
        if n == 0 {
            return 0; // (a plane level one way: often the shade's)
        }
        let m = n.unsigned_abs();
        // (Where `m 2^shift` fits 32 bits, as for a plane that changes little or not at
        // all, one quotient.)
        let (q, r) = match m.checked_shl(shift).filter(|w| w >> shift == m) {
            Some(wide) => {
                let (q, r) = self.div_rem(wide);
                (u64::from(q), r)
            }
            None => {
                let (q, r) = self.div_rem(m);
                // (Here `shift >= 1`. Where the remainder's digits take one quotient, as for
                // most of a small triangle's slopes, they are joined in line: the loop kept
                // its values on the stack on ARMv6-M, 0.10M instructions of `fw_teapot`'s
                // frame 0, 0.03M on RV32IMC. With an FPU, the loop alone: the Cortex-M4F
                // counts the same instructions with less code.)
                match join && shift <= self.leading_zeros() {
                    true => {
                        let (digit, r) = self.div_rem(r << shift);
                        let high = u64::from(q >> (32 - shift)) << 32;
                        (high | u64::from(q << shift | digit), r)
                    }
                    false => self.digits(u64::from(q), r, shift),
                }
            }
        };
        // `m 2^shift = q a + r`: for `n < 0` the floor is `-q`, or `-q - 1` with a remainder.
        let q = q as i64;
        if n < 0 {
            -q - i64::from(r != 0)
        } else {
            q
        }
    }

    /// `(⌊(q a + r) 2^left / a⌋, (q a + r) 2^left mod a)` for `r < a`: the remainder's
    /// `left` binary digits of the quotient, in quotients of up to `clz(a)` bits each.
    fn digits(&self, mut q: u64, mut r: u32, mut left: u32) -> (u64, u32) {
        // `r < a < 2^31`: `r << step` fits.
        let step = self.leading_zeros();
        while left > 0 {
            let k = left.min(step);
            let (digit, rest) = self.div_rem(r << k);
            q = shl_64(q, k) + u64::from(digit);
            r = rest;
            left -= k;
        }
        (q, r)
    }
}

/// `⌊2^23 / (256 + i + 1)⌋` for `i` in `0..256`: the reciprocals [`reciprocal`] starts
/// from, each at most `2^15 / x` for every `x` in `[1 + i / 256, 1 + (i + 1) / 256]`.
#[cfg(any(feature = "embedded-graphics", test))]
const RECIPROCALS: [u16; 256] = {
    let mut table = [0u16; 256];
    let mut i = 0;
    while i < 256 {
        table[i] = ((1u32 << 23) / (257 + i as u32)) as u16;
        i += 1;
    }
    table
};

/// `⌊(2^32 - 1) / a⌋`, exact, without a division (0 for `a = 0`); `zeros` is `a`'s leading
/// zero bits. (On ARMv6-M about 60 instructions, where the library's division takes about
/// 200.)
///
/// **How.** With `s` the leading zeros and `a 2^s = x 2^31`, `x` in `[1, 2)`, the table's
/// entry `M` for the eight bits of `x` after the point is at most `2^15 / x` and at least
/// `2^15 (1 - 2^-8) / x - 1`, so `y = M 2^(s - 46)` has `(1 - δ) / a <= y <= 1 / a` with
/// `δ = 2^-8 + 2^-14`. Starting from `q = 0`, each round takes the remainder
/// `r = (2^32 - 1) - q a` (at least 0) and adds `⌊r y⌋`: with `t = r / a` the distance of
/// `q` below the exact quotient, the round leaves `t' = t - ⌊t a y⌋` in `[0, δ t + 1)`, and
/// `q` never passes the exact quotient. From `t <= 2^31` (`a >= 2`) four rounds leave
/// `t < 8.6·10^6`, `33,900`, `136`, then `1.54`: one step more at most makes `q` the floor.
/// `⌊r y⌋` is `⌊(h 2^16 + l) / 2^(46 - s)⌋` for `h = ⌊r / 2^16⌋ M` and `l = (r mod 2^16) M`
/// (each below `2^31`), which is `⌊(h + ⌊l / 2^16⌋) / 2^(30 - s)⌋`: 32-bit products alone.
#[cfg(any(feature = "embedded-graphics", test))]
#[inline(always)]
pub(crate) fn reciprocal(a: u32, zeros: u32) -> u32 {
    if a <= 1 {
        return if a == 1 { u32::MAX } else { 0 };
    }
    // `zeros <= 30` from here.
    let m = u32::from(RECIPROCALS[((a << zeros) >> 23) as usize & 0xff]);
    let down = 30 - zeros;
    let mut q = 0u32;
    for _ in 0..4 {
        let r = u32::MAX - q * a;
        let (h, l) = ((r >> 16) * m, (r & 0xffff) * m);
        q += (h + (l >> 16)) >> down;
    }
    if u32::MAX - q * a >= a {
        q += 1;
    }
    q
}

/// `⌊√n⌋`, digit by digit. (Not `u32::isqrt`: on ARMv6-M it cost `fw_teapot`'s wireframe frame
/// 0.7M instructions more.)
pub(crate) const fn isqrt(n: u32) -> u32 {
    let (mut rest, mut root) = (n, 0u32);
    let mut bit = 1u32 << 30;
    while bit > n {
        bit >>= 2;
    }
    while bit != 0 {
        if rest >= root + bit {
            rest -= root + bit;
            root = (root >> 1) + bit;
        } else {
            root >>= 1;
        }
        bit >>= 2;
    }
    root
}

/// `⌊√(i 2^24)⌋ - 2^15` for `i` in `64..=256`: the roots [`isqrt_by_table`] reads between.
const ROOTS: [u16; 193] = {
    let mut table = [0u16; 193];
    let mut k = 0;
    while k < 192 {
        table[k] = (isqrt(((64 + k) as u32) << 24) - (1 << 15)) as u16;
        k += 1;
    }
    // `√(2^32) = 2^16`.
    table[192] = 1 << 15;
    table
};

/// `⌊√n⌋`, as [`isqrt`] finds it, from a table: `n` shifted up by an even count `2k` into
/// `[2^30, 2^32)`, its root read on the chord between two entries of [`ROOTS`] (within a
/// unit or two of it: `√` bends by about `2^-4` of a unit over an entry's `2^24`), shifted
/// back by `k` (`⌊⌊√(n 4^k)⌋ / 2^k⌋ = ⌊√n⌋`) and put right by a step or two each way, which
/// makes it exact whatever the reading. (On ARMv6-M about 50 instructions, where `isqrt`'s
/// sixteen digits take about 170. A part with an FPU takes the digits: the same roots, and
/// 172 bytes less of the Cortex-M4F's flash, for no change in its frames' counts.)
#[inline]
pub(crate) fn isqrt_by_table(n: u32) -> u32 {
    if HARD_FLOAT && cfg!(target_os = "none") {
        return isqrt(n);
    }
    if n == 0 {
        return 0;
    }
    let shift = leading_zeros(n) & !1;
    let x = n << shift;
    // (`x >> 24` is in `64..256`: the bound only spares a check.)
    let i = ((x >> 24) as usize - 64).min(191);
    let (a, b) = (u32::from(ROOTS[i]), u32::from(ROOTS[i + 1]));
    let read = (1 << 15) + a + (((b - a) * ((x >> 8) & 0xffff)) >> 16);
    let mut r = (read >> (shift / 2)).min(65535);
    while r * r > n {
        r -= 1;
    }
    // (`r² <= n` from here: `n - r²` is at least `2r + 1` where `(r + 1)² <= n`.)
    while n - r * r > 2 * r {
        r += 1;
    }
    r
}

/// Square root (correctly rounded on every target).
#[inline]
pub(crate) fn sqrt(x: f32) -> f32 {
    libm::sqrtf(x)
}

/// Base-2 logarithm (`libm`'s, the same bits on every target).
#[inline]
pub(crate) fn log2(x: f32) -> f32 {
    libm::log2f(x)
}

/// An upper bound of `√x` (for `x >= 0`; NaN for a negative or NaN `x`), above it by at most
/// a few millionths, from element-wise operations alone: where only a bound is wanted, two
/// divisions in place of a library square root (software on a Cortex-M4F, about 50
/// instructions).
///
/// A first guess halves the exponent (within 4% for normal numbers); each Newton step
/// `(y + x / y) / 2` is at least `√x` in exact arithmetic for any `y > 0` (the arithmetic
/// mean of `y` and `x / y` is at least their geometric mean) and squares the relative
/// excess; two steps leave it under `1e-6`. The steps' three roundings take at most `3 ε`
/// off, which the final factor `1 + 2^-20` gives back.
#[inline]
pub(crate) const fn sqrt_above(x: f32) -> f32 {
    if x.is_nan() || x < 0.0 {
        return f32::NAN;
    }
    if x == 0.0 || x == f32::INFINITY {
        return x;
    }
    let mut y = f32::from_bits((x.to_bits() >> 1) + 0x1FBD_1DF5);
    y = 0.5 * (y + x / y);
    y = 0.5 * (y + x / y);
    y * (1.0 + 1.0 / (1u32 << 20) as f32)
}

/// An upper bound of `√(1 + x)` for `x >= 0` (NaN for NaN, infinity for infinity) in one
/// division: a Newton step `(y + (1 + x) / y) / 2` from `y = 1 + x / 2`, which is at least the
/// root (`(1 + x/2)² = 1 + x + x²/4`), so the step is too (see [`sqrt_above`]). Above the root
/// by `(y - √(1 + x))² / 2y`: under `3 · 10^-5` of it for `x <= 1/4`, the rays of a view's
/// corners at a 40 degree field of view; looser, still a bound, beyond. Its three roundings
/// are given back by `1 + 2^-20`.
#[inline]
pub(crate) fn sqrt_one_plus_above(x: f32) -> f32 {
    if x.is_nan() || x == f32::INFINITY {
        return x;
    }
    let (y, square) = (1.0 + 0.5 * x, 1.0 + x);
    0.5 * (y + square / y) * (1.0 + 1.0 / (1u32 << 20) as f32)
}

/// The larger of `a` and `b`, a NaN ignored (IEEE 754-2008 `maxNum`, as `f32::max` and
/// `libm`'s `fmaxf`, which also keeps `a` when they are equal).
///
/// Inline: Thumb has no instruction for `maxNum`, so `f32::max` (and glam's element-wise
/// `max`) is a call into `libm` there, about 15 instructions for one comparison. Host and
/// Cortex-M get the same bits from this one definition, signed zeros included.
#[inline(always)]
pub(crate) fn max(a: f32, b: f32) -> f32 {
    if a.is_nan() || less(a, b) {
        b
    } else {
        a
    }
}

/// [`max`] of a running largest `w` that is never NaN (a fold's, from a number) and `x`: the
/// same bits, a NaN `x` ignored, without `max`'s test of `w` (on a host, one instruction).
#[inline(always)]
pub(crate) fn larger(w: f32, x: f32) -> f32 {
    if less(w, x) {
        x
    } else {
        w
    }
}

/// `a < b`, as IEEE 754 orders `f32` (false with a NaN; the two zeros equal): by the
/// comparison where `f32` is hardware, in integers elsewhere (see [`less_in_integers`]).
#[inline(always)]
pub(crate) fn less(a: f32, b: f32) -> bool {
    match HARD_FLOAT {
        true => a < b,
        false => less_in_integers(a, b, false),
    }
}

/// `a <= b`, as IEEE 754 orders `f32`; see [`less`].
#[inline(always)]
pub(crate) fn at_most(a: f32, b: f32) -> bool {
    match HARD_FLOAT {
        true => a <= b,
        false => less_in_integers(a, b, true),
    }
}

/// `a < b`, or `a <= b` with `or_equal`, from the bits (on every target: the tests check it
/// against the comparison). Where `f32` is software a comparison is a library call of about
/// 25 instructions, which the compiler may also make before it knows it needs it; here, with
/// no NaN, the bits turned into keys that order as the numbers do (a negative number's bits
/// inverted, a positive one's sign bit set), the two zeros taken apart first.
#[inline(always)]
pub(crate) fn less_in_integers(a: f32, b: f32, or_equal: bool) -> bool {
    let (x, y) = (a.to_bits(), b.to_bits());
    if (x & 0x7fff_ffff) > 0x7f80_0000 || (y & 0x7fff_ffff) > 0x7f80_0000 {
        return false;
    }
    if (x | y) << 1 == 0 {
        return or_equal;
    }
    let key = |v: u32| v ^ (((v as i32) >> 31) as u32 | 0x8000_0000);
    match or_equal {
        true => key(x) <= key(y),
        false => key(x) < key(y),
    }
}

/// The smaller of `a` and `b`, a NaN ignored (`minNum`, as `f32::min` and `libm`'s `fminf`);
/// see [`max`].
#[inline(always)]
pub(crate) fn min(a: f32, b: f32) -> f32 {
    if b.is_nan() || less(a, b) {
        a
    } else {
        b
    }
}

/// Linear interpolation that is exact at both ends and when `a == b`.
///
/// `a + (b - a) * t` is exact at `t = 0` and for equal inputs but not at `t = 1`;
/// `(1 - t) * a + t * b` is exact at both ends but not for equal inputs. Switching formula at
/// one half keeps all three properties: corners of a patch are its corner control points bit
/// for bit, and a row of equal control points (a collapsed edge) has an exactly zero
/// derivative along it.
#[inline]
pub(crate) fn lerp4(a: Vec4, b: Vec4, t: f32) -> Vec4 {
    let d = b - a;
    if t <= 0.5 {
        a + d * t
    } else {
        // 1 - t is exact here (Sterbenz), so t = 1 gives b exactly.
        b - d * (1.0 - t)
    }
}

/// Length of a vector.
#[inline]
pub(crate) fn length(v: Vec3) -> f32 {
    sqrt(v.dot(v))
}

/// `v / |v|`, or `None` when `v` is zero or not finite.
///
/// The vector is first scaled by its largest component, so tiny vectors (whose squared length
/// would underflow, as cross products next to a pole do) still normalise.
#[inline]
pub(crate) fn normalize(v: Vec3) -> Option<Vec3> {
    let big = v.abs().max_element();
    if !(big > 0.0 && big.is_finite()) {
        return None;
    }
    let s = v / big;
    let n = s / length(s);
    n.is_finite().then_some(n)
}

/// Clamps a parameter into `[lo, hi]`; NaN maps to `lo`.
#[inline]
pub(crate) fn clamp_param(t: f32, lo: f32, hi: f32) -> f32 {
    if t >= lo {
        if t <= hi {
            t
        } else {
            hi
        }
    } else {
        // Also the NaN case: every comparison with NaN is false.
        lo
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Comparisons from the bits order as the `f32` ones: zeros of either sign, infinities,
    /// NaNs, subnormals, the numbers next to each, and random bits.
    #[test]
    fn comparisons_in_integers_are_the_float_ones() {
        let special = [
            0.0f32,
            -0.0,
            f32::MIN_POSITIVE,
            -f32::MIN_POSITIVE,
            f32::from_bits(1),
            f32::from_bits(0x8000_0001),
            1.0,
            -1.0,
            f32::MAX,
            f32::MIN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            -f32::NAN,
            f32::from_bits(0x7f80_0001),
        ];
        let near = |x: f32| {
            [
                x,
                f32::from_bits(x.to_bits().wrapping_add(1)),
                f32::from_bits(x.to_bits().wrapping_sub(1)),
            ]
        };
        let mut values: std::vec::Vec<f32> = special.iter().flat_map(|&x| near(x)).collect();
        let mut rng = crate::test_rng::TestRng::new(0xc0_4a12);
        values.extend((0..400).map(|_| f32::from_bits(rng.next_u32())));
        for &a in &values {
            for &b in &values {
                assert_eq!(less_in_integers(a, b, false), a < b, "{a:?} < {b:?}");
                assert_eq!(less_in_integers(a, b, true), a <= b, "{a:?} <= {b:?}");
            }
        }
    }

    /// `larger` of a running largest that is not NaN gives `max`'s bits for every value,
    /// NaNs, zeros of either sign and infinities among them; and a fold with it is `max`'s.
    #[test]
    fn larger_is_max_of_a_running_largest() {
        let special = [
            0.0f32,
            -0.0,
            f32::from_bits(1),
            1.0,
            -1.0,
            f32::MAX,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            -f32::NAN,
        ];
        let mut rng = crate::test_rng::TestRng::new(0x1a_5e12);
        let mut values: std::vec::Vec<f32> = special.to_vec();
        values.extend((0..400).map(|_| f32::from_bits(rng.next_u32())));
        for &w in values.iter().filter(|w| !w.is_nan()) {
            for &x in &values {
                assert_eq!(larger(w, x).to_bits(), max(w, x).to_bits(), "{w:?}, {x:?}");
            }
        }
        for run in values.chunks(4) {
            let folded = |f: fn(f32, f32) -> f32| run.iter().fold(0.0f32, |w, &x| f(w, x));
            assert_eq!(folded(larger).to_bits(), folded(max).to_bits(), "{run:?}");
        }
    }

    /// 64-bit shifts on two words are the native ones, for every count and random words.
    #[test]
    fn shifts_in_words_are_the_native_ones() {
        let mut rng = crate::test_rng::TestRng::new(0x5e1f_0001);
        for n in 0..20_000 {
            let x = u64::from(rng.next_u32()) << 32 | u64::from(rng.next_u32());
            let x = x >> (n % 64);
            for k in 0..64 {
                assert_eq!(shr_64_in_words(x, k), x >> k, "{x:#x} >> {k}");
                assert_eq!(shl_64_in_words(x, k), x << k, "{x:#x} << {k}");
                for y in [x as i64, -(x as i64)] {
                    assert_eq!(sar_64_in_words(y, k), y >> k, "{y} >> {k}");
                }
            }
        }
        assert_eq!(shr_64(u64::MAX, 63), 1);
        assert_eq!(shl_64(1, 63), 1 << 63);
        assert_eq!(sar_64(i64::MIN, 63), -1);
    }

    /// The leading zeros counted by the table are the instruction's: every power of two and
    /// its neighbours, and random words of every length; the 64-bit count likewise.
    #[test]
    fn leading_zeros_by_table_are_counted_exactly() {
        let mut rng = crate::test_rng::TestRng::new(0x1ead_0001);
        let mut words = std::vec![0u32, 1, u32::MAX];
        for k in 0..32 {
            words.extend([(1u32 << k) - 1, 1 << k, (1u32 << k) + 1]);
        }
        words.extend((0..100_000).map(|k| rng.next_u32() >> (k % 32)));
        for x in words {
            assert_eq!(leading_zeros_in_table(x), x.leading_zeros(), "{x:#x}");
            assert_eq!(leading_zeros(x), x.leading_zeros(), "{x:#x}");
            for wide in [u64::from(x), u64::from(x) << 32, u64::from(x) << 7 | 1] {
                assert_eq!(leading_zeros_64(wide), wide.leading_zeros(), "{wide:#x}");
                let words = leading_zeros_64_in_words(wide);
                assert_eq!(words, wide.leading_zeros(), "{wide:#x}");
            }
        }
    }

    #[test]
    fn roots_by_table_are_the_digit_roots() {
        for n in (0..1u32 << 22).chain(u32::MAX - (1 << 20)..=u32::MAX) {
            assert_eq!(isqrt_by_table(n), isqrt(n), "{n}");
        }
        for r in 0..=65535u32 {
            for n in [r * r, (r * r).saturating_sub(1), r * r + r, r * r + 2 * r] {
                assert_eq!(isqrt_by_table(n), isqrt(n), "{n}");
            }
        }
        let mut rng = crate::test_rng::TestRng::new(0x5157_0001);
        for k in 0..1_000_000u32 {
            let n = rng.next_u32() >> (k % 32);
            assert_eq!(isqrt_by_table(n), isqrt(n), "{n}");
        }
    }

    #[test]
    fn shifted_quotients_are_the_floor() {
        let mut rng = crate::test_rng::TestRng::new(0x71de_0002);
        for k in 0..100_000u32 {
            let a = (rng.next_u32() >> (1 + k % 31)).max(1);
            let n = (rng.next_u32() as i32) >> (k % 29);
            let shift = (k / 7) % 32;
            let exact = (i128::from(n) << shift).div_euclid(i128::from(a));
            let q = Divisor::new(a).floor_shifted(n, shift);
            assert_eq!(i128::from(q), exact, "{n} 2^{shift} / {a}");
            for join in [false, true] {
                let q = Divisor::new(a).floor_shifted_joining(n, shift, join);
                assert_eq!(i128::from(q), exact, "{n} 2^{shift} / {a}, {join}");
            }
        }
    }

    #[test]
    fn wide_products_are_exact() {
        let mut rng = crate::test_rng::TestRng::new(0x71de_0001);
        for k in 0..100_000 {
            let (a, b) = match k {
                0 => (u32::MAX, u32::MAX),
                1 => (0, u32::MAX),
                2 => (65535, 65536),
                3 => (0x8000_0000, 0x8000_0000),
                _ => (rng.next_u32(), rng.next_u32() >> (k % 32)),
            };
            assert_eq!(wide_in_halves(a, b), u64::from(a) * u64::from(b), "{a} {b}");
            assert_eq!(wide(a, b), u64::from(a) * u64::from(b), "{a} {b}");
            let (a, b) = (a as i32, b as i32);
            assert_eq!(wide_signed(a, b), i64::from(a) * i64::from(b), "{a} {b}");
        }
    }

    /// The reciprocals found without a division are the division's, for every divisor
    /// below `2^20` and at the edges of each power of two, and for a million random ones.
    #[test]
    fn reciprocals_are_the_quotients() {
        let check = |a: u32| {
            let expected = u32::MAX.checked_div(a).unwrap_or(0);
            assert_eq!(reciprocal(a, a.leading_zeros()), expected, "{a}");
        };
        (0..1u32 << 20).for_each(check);
        for k in 0..32 {
            for d in 0..1000u32 {
                check((1u32 << k).wrapping_add(d));
                check((1u32 << k).wrapping_sub(d));
            }
        }
        let mut rng = crate::test_rng::TestRng::new(0x2ec1_0001);
        for k in 0..1_000_000u32 {
            check(rng.next_u32() >> (k % 32));
        }
    }

    /// A divisor's quotients by its reciprocal are the division's, for divisors and
    /// dividends over the whole range, at the edges and where the estimate falls short most
    /// (dividends just below a multiple).
    #[test]
    fn quotients_by_the_reciprocal_are_exact() {
        let mut rng = crate::test_rng::TestRng::new(0xd1f1_50e5);
        let mut corrected = 0;
        for k in 0..200_000u32 {
            let a = match k % 7 {
                0 => 1 + (rng.next_u32() >> (k % 32)),
                1 => 1 + (k / 7) % 300,
                2 => u32::MAX - (k / 7) % 5,
                3 => 1 << (k % 32),
                _ => (rng.next_u32() >> (k % 29)).max(1),
            };
            let x = match k % 5 {
                0 => u32::MAX,
                1 => a.wrapping_mul(rng.next_u32() >> (k % 32)).wrapping_sub(1),
                2 => rng.next_u32() % a,
                _ => rng.next_u32() >> (k % 32),
            };
            let d = Divisor::new(a);
            let expected = (x / a, x % a);
            assert_eq!(d.div_rem_by_reciprocal(x), expected, "{x} / {a}");
            assert_eq!(d.div_rem(x), expected, "{x} / {a}");
            let inv = u32::MAX / a;
            corrected += u32::from((wide(x, inv) >> 32) as u32 != x / a);
        }
        // (Dividends just below a multiple take the corrections: the test reaches them.)
        assert!(corrected > 1000, "{corrected}");
    }

    /// `sqrt_one_plus_above` is at least `√(1 + x)`, within `3 · 10^-5` of it up to `x = 1/4`
    /// and within a factor of 1.1 up to `x = 1`.
    #[test]
    fn sqrt_one_plus_above_bounds_the_root() {
        let mut rng = crate::test_rng::TestRng::new(0x0e1f_2026);
        for k in 0..100_000 {
            let x = match k % 3 {
                0 => rng.signed(1 << 22).unsigned_abs() as f32 / (1u32 << 24) as f32,
                1 => rng.signed(1 << 22).unsigned_abs() as f32 / (1u32 << 22) as f32,
                _ => libm::ldexpf(
                    1.0 + rng.signed(1 << 20) as f32 / (1 << 21) as f32,
                    (k % 200) - 100,
                ),
            };
            let exact = libm::sqrt(1.0 + x as f64);
            let got = sqrt_one_plus_above(x) as f64;
            assert!(got >= exact, "{x}: {got} < {exact}");
            if x <= 0.25 {
                assert!(got <= exact * (1.0 + 3e-5), "{x}: {got} loose over {exact}");
            } else if x <= 1.0 {
                assert!(got <= exact * 1.1, "{x}: {got} loose over {exact}");
            }
        }
        assert_eq!(sqrt_one_plus_above(f32::INFINITY), f32::INFINITY);
        assert!(sqrt_one_plus_above(f32::NAN).is_nan());
    }

    /// `sqrt_above` is at least the square root and at most a millionth and a bit above, over
    /// every binade of the normal numbers and the edge cases.
    #[test]
    fn sqrt_above_bounds_the_root_closely() {
        let mut rng = crate::test_rng::TestRng::new(0x5eed_2026);
        for exponent in -126..=127 {
            for _ in 0..64 {
                let mantissa = 1.0 + (rng.signed(1 << 22) + (1 << 22)) as f32 / (1u32 << 23) as f32;
                let x = libm::ldexpf(mantissa, exponent);
                if !x.is_finite() {
                    continue;
                }
                let exact = libm::sqrt(x as f64);
                let got = sqrt_above(x) as f64;
                assert!(got >= exact, "{x}: {got} < {exact}");
                assert!(
                    got <= exact * (1.0 + 2e-6),
                    "{x}: {got} too far above {exact}"
                );
            }
        }
        assert_eq!(sqrt_above(0.0), 0.0);
        assert_eq!(sqrt_above(f32::INFINITY), f32::INFINITY);
        assert!(sqrt_above(-1.0).is_nan() && sqrt_above(f32::NAN).is_nan());
        // Subnormal: still a bound.
        let tiny = f32::from_bits(3);
        assert!(sqrt_above(tiny) as f64 >= libm::sqrt(tiny as f64));
    }
}
