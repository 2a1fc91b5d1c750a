//! A first look at a triangle in integers, from its corners on the grid (see `grid_view`),
//! for parts without an FPU: whether it is certainly in view of every plane, and whether it
//! is certainly within the tolerance, or over it, by the isotropic bound, in integer
//! operations (a software `f32` quotient gives the bound of one within). Where the look
//! decides nothing, the judgement goes on in `f32` as before; where it decides, it decides as
//! the `f32` judgement would, so the frames are the same (the within bound it reports is its
//! own, a little larger).
//!
//! # Notation
//!
//! A corner found in integers is `(X, Y, Z)` in units `U = 2^u` of the frame
//! ([`GridView::fixed`]); the `f32` judgement reads it as `p = (x, y, z)`, each cut to 24 bits
//! toward zero ([`GridView::point_of`]): `|x| <= |X| U`, and `z >= Z U (1 - 2^-23)` for
//! `Z > 0`. `ε = 2^-24`. Every constant of a frame below is found once, in `f32`, rounded the
//! safe way by a factor `1 ± 2^-16` or more, which covers its few roundings.
//!
//! # In view of every plane
//!
//! `judge`'s `beyond_one_plane` leaves a triangle out where all three corners lie beyond one
//! plane: `near - z > w`, or `±x - s_x z > w n_x`, likewise `y`, with `w >= 0`. Take one corner
//! with `Z >= N_z = ⌈near (1 + 2^-21) / U⌉` and `|X| <= S_x ⌊Z / 2^15⌋`, `S_x = ⌊s_x (1 -
//! 2^-12) 2^15⌋` (and `S_y` alike; one 32-bit product each, for `s < 2`). Then `z >= near`,
//! so `fl(near - z) <= 0 <= w`; and `|x| <= s_x Z U (1 - 2^-13) <= fl(s_x z)`, so
//! `fl(±x - fl(s_x z)) <= 0 <= fl(w n_x)`: that corner is beyond no plane in `f32` either,
//! and the triangle is not left out. Where every corner is, `screen::bound_on_screen`'s own
//! test finds each inside every plane (its planes lie further out, by `w = m + η`, its near
//! plane nearer, by `η`), and takes the triangle as its clipped polygon.
//!
//! # Within by the isotropic bound
//!
//! `screen::isotropic_from` bounds the deviation on screen by (see its module docs)
//!
//! `I = f S / z_ℓ · m (c + a + 2 η P / z_ℓ + 16 ε P)`, `a = (m + η) n / z_ℓ`, `P = 1 + s_x
//! + s_y + a`,
//!
//! with `f` the focal length, `S` the screen slack, `c` the corner ray, `n = n_x + n_y`, `m`
//! and `η` as the `f32` judgement finds them (`η` its remainder `r` and a rounding part `H`),
//! and `z_ℓ >= z_c - m - η =: Z`, `z_c` the least corner depth. Take `m / Z <= μ = tol / (f
//! S c)` and `H / Z <= h` (a frame's constant, about `2^-14`): with `r <= m`, `P <= P⁺ = 1 +
//! s_x + s_y + (2 μ + h) n`, and the bracket is at most `G + (r / Z) D` with `G = c + (μ +
//! h) n + 2 h P⁺ + 16 ε P⁺` and `D = n + 2 P⁺`. Then `I <= tol (K m + K_r r) / Z` with `K =
//! f S G / tol` and `K_r = f S μ D / tol`. The test
//!
//! `m (K + 1) + K_r r + η <= z_c`
//!
//! gives `Z >= K m`, so `m / Z <= 1 / K <= μ`; and with `K >= 16` and `H <= 2^-14 z_c`, `Z >=
//! z_c (1 - 2 / (K + 1) - 2^-14)`, which `h` is taken over. The bound `tol (K m + K_r r) /
//! (z_c - m - η)` is convex in `m` and at most the line `tol (m (K + 1) + K_r r + η) / z_c`
//! where the test holds: at `m = 0` as `z_c >= K_r r + η`, and where the line is `tol` both
//! are. So the triangle is within, with bound `tol L / z_c` for the test's left side `L`.
//! Near the tolerance (`m / Z` near `1 / K`) the look's terms are the bound's own, but for
//! `h`.
//!
//! **In integers.** `m`, `r` and `η` are bounded above in units of `U` (an `f32` sum at most
//! `ε` above its terms a rounding; the vectors' longest at most `2^-15` above `√n scale` for
//! the largest squared code `n`, whose root is taken up in four fractional bits), `K + 1`
//! by `K₁ / 2^16` and `K_r` by `K_r₁ / 2^11`, and `z_c (1 - 2^-12)` from below by `Z_min -
//! ⌊Z_min / 2^11⌋ - 1`. The test is then exact, in 64-bit integers: `M K₁ + 2^5 R K_r₁ +
//! 2^16 η⁺ <= 2^16 (Z_min - ⌊Z_min / 2^11⌋ - 1)`; and the bound `tol (1 + 2^-15) L / (2^16
//! Z_min)` in `f32` (two conversions, a quotient, a product: their roundings are within the
//! `2^-15`, and it stays within `tol`). The look also asks that the `f32` bound be finite
//! (see *Near the eye*).
//!
//! **Near the eye.** The `f32` bounds move the near plane in by their rounding `η` (at least
//! the remainder `r`: a sum of nonnegative terms), and are infinite where `near - η <= 0`
//! (`screen`). Where `⌈r / U⌉ > N_z`, `r > N_z U >= near`, so the `f32` judgement is over
//! with an infinite bound, and the look says so (`r` at exactly `N_z U` fails the next
//! test, and the `f32` judgement finds the same). Elsewhere it asks `η⁺ + ⌊(N_z - 1) 2^-19⌋ +
//! 1 <= N_z - 1`: `N_z U` is the ceiling of `near (1 + 2^-20)` rounded to `f32`, at most
//! `near (1 + 2^-19)`, so `near > (N_z - 1)(1 - 2^-19) U > η⁺ U`, and the `f32` bound is
//! finite (the sign of an `f32` difference is exact). (It asked `η <= near / 2` before: on
//! `fw_teapot`'s frame 0, where the near plane is 0.05 from the eye and the coarse nodes'
//! remainders up to 0.125, 20 of its 1,386 judgements then fell to the `f32` one, each about
//! 17,000 instructions on ARMv6-M.)
//!
//! **Over.** Where the test fails, the look asks whether the `f32` isotropic bound is over
//! the tolerance, so that the judgement need not find it (the directional bound decides
//! then). That bound is at least `f S c m / z_ℓ` less its few roundings (every term of its
//! bracket is nonnegative, and `s >= c`), and its `z_ℓ` at most the least corner depth, at
//! most `Z_min U`. So `m K_c > 2^16 Z_min`, with `m` bounded below in units (the floors of
//! `√n`, the scale and the remainder, less `2^-20` of their sum) and `K_c <= 2^16 f S c tol⁻¹
//! (1 - 2^-17)`, finds it over.
//!
//! **The same judgement.** The test leaves `2^-12` of the tolerance: the `f32` isotropic
//! bound is within that of `I`'s exact value, its one difference that can cancel, the least
//! depth `z_f - m - η`, being at least `Z >= z_c / 2` here (its rounding at most `4 ε` of
//! it). So a triangle the look finds within, the `f32` judgement finds within too, and the
//! mesh is the same.
//!
//! Measured (`the_first_look_decides_as_the_float_judgement`, random triangles and cameras):
//! the look finds within 9,461 of the 9,525 triangles the `f32` isotropic bound finds within,
//! its bound at most 4.0% above that bound (0.5% where that is over 0.9 of the tolerance).
//! On `fw_teapot`'s ARMv6-M build the look and the `f32` work it saves take frame 0's update
//! from 26.68M to 18.99M instructions (22.49M with the test for within alone).

use super::directional_look::{Decided, NodeTerms, ViewRows};
use super::grid_view::{floor_fixed, GridView};
use super::judge::Bound;
use super::HierarchyNode;
use crate::deviation::{EPS, SCREEN_SLACK};
use crate::math::{isqrt, isqrt_by_table, wide};
use crate::view::{Camera, Projection};

/// A frame's constants for the first look (see the [module docs](self)), in the units of
/// its [`GridView`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub(crate) struct GridJudge {
    /// `N_z`: at least the near plane's distance.
    near: u32,
    /// `S_x`, `S_y`: the side planes' slopes in 15 fractional bits, taken down.
    slopes: [u16; 2],
    /// The grid's slack, taken up.
    slack: u16,
    /// `K₁`: at least `K + 1`, in 16 fractional bits.
    k: u32,
    /// `K_r`: the remainder's share, in 11 fractional bits.
    k_r: u16,
    /// `K_c`: at most `f S c / tol`, in 16 fractional bits.
    k_c: u32,
    /// `tol (1 + 2^-15) 2^-16`.
    tolerance: f32,
    /// The directional look's constants, where it takes one (see `directional_look`).
    rows: Option<ViewRows>,
}

/// What the first look found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum FirstLook {
    /// Within the tolerance, with this bound (at most the tolerance).
    Within(Bound),
    /// Over the tolerance by the directional bound, with this bound (over the tolerance, at
    /// most that bound): asked for only where any bound over the tolerance will do.
    Over(f32),
    /// Not certainly within: what it found certain.
    Seen(Seen),
}

/// A first look's bound within the tolerance, kept as its terms, whose value is
/// [`value`](Self::value): the isotropic look's `tol (1 + 2^-15) L / (2^16 Z_min)` (see the
/// module docs), or the directional look's `ρ = a / b` of the tolerance (see
/// `directional_look`), as `L = 2^16 a` over `b`. Where `f32` is software, the conversions,
/// the quotient and the products cost about 370 instructions (ARMv6-M), and a frame reads the
/// value only where it may be its worst bound (see [`QuotientLimit`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct WithinQuotient {
    /// `L`, below `2^48`; [`DIRECTIONAL`] set for the directional look's.
    left: u64,
    /// `Z_min`, or `b`.
    below: u32,
    /// The view's tolerance.
    tolerance: f32,
}

/// The bit of [`WithinQuotient::left`] that marks the directional look's.
const DIRECTIONAL: u64 = 1 << 63;

/// `tol (1 + 2^-15) 2^-16` in `f32`: the isotropic look's unit (see the module docs).
#[inline(always)]
fn unit_of(tolerance: f32) -> f32 {
    tolerance * (1.0 + 1.0 / 32768.0) / 65536.0
}

impl WithinQuotient {
    /// The isotropic look's `L / Z_min` at `tolerance`.
    fn isotropic(left: u64, z_min: u32, tolerance: f32) -> WithinQuotient {
        WithinQuotient {
            left,
            below: z_min,
            tolerance,
        }
    }

    /// The directional look's `a / b` at `tolerance` (`a <= b < 2^31`).
    fn directional([a, b]: [u32; 2], tolerance: f32) -> WithinQuotient {
        WithinQuotient {
            left: u64::from(a) << 16 | DIRECTIONAL,
            below: b,
            tolerance,
        }
    }

    /// The bound, in `f32`: for the isotropic look `L` and `Z_min` rounded, their quotient,
    /// times the unit; for the directional one, as [`Decided::Within`]'s.
    #[inline(never)]
    pub fn value(self) -> f32 {
        match self.left & DIRECTIONAL {
            0 => self.left as f32 / self.below as f32 * unit_of(self.tolerance),
            _ => Decided::within_bound(
                [(self.left >> 16) as u32 & 0x7fff_ffff, self.below],
                self.tolerance,
            ),
        }
    }

    /// As a judgement's bound: the quotient kept, where the build keeps one (see
    /// [`KeptQuotient`]).
    #[inline(always)]
    fn into_bound(self) -> Bound {
        #[cfg(all(
            target_os = "none",
            not(any(target_abi = "eabihf", target_feature = "f"))
        ))]
        return Bound::Within(self);
        #[cfg(not(all(
            target_os = "none",
            not(any(target_abi = "eabihf", target_feature = "f"))
        )))]
        return Bound::Value(self.value());
    }
}

/// What a judgement's bound keeps of a first look's quotient: the quotient where `f32` is
/// software (`math::HARD_FLOAT` false, the same targets); elsewhere nothing, an empty type,
/// so that a bound is its value alone, as cheap to move and to read as before the quotient
/// was kept. (Where the value costs a quotient and a product of a few instructions, the
/// bound's tag and tests cost more: a host's cold frame took 0.8% more instructions with a
/// quotient kept, the Cortex-M4F's frame 0 11K more.) A host makes the same frames and the
/// same worst bound, bit for bit, from the values (see [`QuotientLimit`]; the firmware's
/// frames are checked against the host's, worst bound included).
#[cfg(all(
    target_os = "none",
    not(any(target_abi = "eabihf", target_feature = "f"))
))]
pub(crate) type KeptQuotient = WithinQuotient;
/// (See the other definition.)
#[cfg(not(all(
    target_os = "none",
    not(any(target_abi = "eabihf", target_feature = "f"))
)))]
pub(crate) type KeptQuotient = NoQuotient;

/// No quotient: the [`KeptQuotient`] where `f32` is hardware.
#[allow(dead_code)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum NoQuotient {}

#[allow(dead_code)]
impl NoQuotient {
    /// (None is ever made.)
    pub fn value(self) -> f32 {
        match self {}
    }
}

/// The least quotient `L / Z_min` (or `2^16 a / b`) a [`WithinQuotient`] needs to raise a
/// frame's worst bound `W`, from below, so that most quotients are compared with it in
/// integers and never divided out.
///
/// **Why it holds.** With `U` the unit `fl(fl(tol (1 + 2^-15)) 2^-16)` and `u = 2^-24` each
/// rounding's relative error, the limit is `λ = ⌊fl(fl(W / U) (2^16 - 2^-3))⌋` (the constant
/// is `2^16 (1 - 2^-19)`, exact in `f32`), so `λ 2^-16 <= (W / U)(1 + u)² (1 - 2^-19) <= (W /
/// U)(1 - 2^-20)`. A quotient with `L <= ⌊Z_min λ / 2^16⌋` has `L / Z_min <= (W / U)(1 -
/// 2^-20)`. The isotropic value is four roundings from `U L / Z_min` (two conversions, a
/// quotient, a product: a factor at most `(1 + u)³ / (1 - u)` above). The directional one,
/// `fl(fl(fl(a' / b') tol)(1 + 2^-15))` with `a'`, `b'` cut to 24 bits (`a' <= a`, `b' >= b
/// (1 - 2u)`) and then at most the tolerance, is at most `(a / b) tol (1 + 2^-15)(1 + u)³ /
/// (1 - 2u)`, and `tol (1 + 2^-15) <= 2^16 U / (1 - u)`: a factor at most `(1 + u)³ / ((1 -
/// 2u)(1 - u)) < 1 + 8u` above `U L / b`. Either is then below `W (1 - 16u)(1 + 8u) < W`:
/// the worst stays `W`, bit for bit, as it would with the value. (Every value here is a
/// normal `f32`: `L >= 1`, the divisor below `2^32`, and the unit normal.)
#[derive(Clone, Copy, Debug)]
pub(super) struct QuotientLimit {
    /// The worst bound and the tolerance `limit` was found for (their bits).
    worst: u32,
    tolerance: u32,
    /// `λ`.
    limit: u32,
}

impl QuotientLimit {
    /// A limit found for no worst bound yet.
    pub const NONE: QuotientLimit = QuotientLimit {
        worst: u32::MAX,
        tolerance: u32::MAX,
        limit: 0,
    };

    /// `worst` raised to the value of `q` where that is larger: `max(worst, q.value())`,
    /// with the value found only where `q` may be over `worst` (see the type's docs).
    #[inline(always)]
    pub fn raise(&mut self, worst: &mut f32, q: KeptQuotient) {
        #[cfg(not(all(
            target_os = "none",
            not(any(target_abi = "eabihf", target_feature = "f"))
        )))]
        match (q, worst).0 {}
        #[cfg(all(
            target_os = "none",
            not(any(target_abi = "eabihf", target_feature = "f"))
        ))]
        let _ = self.raise_by(worst, q);
    }

    /// [`raise`](Self::raise) by a quotient; whether it was divided out.
    #[allow(dead_code)]
    #[inline(always)]
    fn raise_by(&mut self, worst: &mut f32, q: WithinQuotient) -> bool {
        if (self.worst, self.tolerance) != (worst.to_bits(), q.tolerance.to_bits()) {
            *self = QuotientLimit {
                worst: worst.to_bits(),
                tolerance: q.tolerance.to_bits(),
                limit: (*worst / unit_of(q.tolerance) * (65536.0 - 0.125)) as u32,
            };
        }
        let may_raise = q.left & !DIRECTIONAL > wide(q.below, self.limit) >> 16;
        if may_raise {
            *worst = crate::math::max(*worst, q.value());
        }
        may_raise
    }
}

/// What a first look found certain of a triangle it did not find within.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Seen {
    /// How much of it is in view of every plane.
    pub sight: Sight,
    /// Whether the `f32` isotropic bound is over the tolerance (so that it need not be
    /// found: the directional bound decides).
    pub isotropic_over: bool,
}

impl Seen {
    /// Nothing certain.
    pub const NOTHING: Seen = Seen {
        sight: Sight::Unknown,
        isotropic_over: false,
    };
}

/// How much of a triangle the first look finds in view of every plane of the view, as the
/// `f32` tests would find it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Sight {
    /// Nothing certain.
    Unknown,
    /// A corner: the triangle is not left out as beyond a plane.
    OneCorner,
    /// Every corner: the triangle is also its own polygon clipped to the planes (see
    /// `screen::bound_on_screen`).
    EveryCorner,
}

/// Fractional bits of `K₁` and `K_c`.
const K_BITS: u32 = 16;

/// Fractional bits of `K_r`.
const R_BITS: u32 = 11;

/// `η`'s part other than the remainder is asked to be at most `2^-14` of the least depth.
const ROUNDING_CAP: u32 = 14;

impl GridJudge {
    /// No first look (a frame that takes none).
    pub const OFF: GridJudge = GridJudge {
        near: 0,
        slopes: [0; 2],
        slack: 0,
        k: 0,
        k_r: 0,
        k_c: 0,
        tolerance: 0.0,
        rows: None,
    };

    /// Whether the frame takes a first look (not [`OFF`](Self::OFF)).
    pub fn is_on(&self) -> bool {
        self.k != 0
    }

    /// The constants of a frame of `camera` at `tolerance` (pixels), moved by `grid`: `None`
    /// for an orthographic view, or where the fixed point is too coarse near the eye or a
    /// constant does not fit (the look then leaves every triangle to the `f32` judgement).
    pub fn new(camera: &Camera, tolerance: f32, grid: &GridView) -> Option<GridJudge> {
        if !matches!(camera.projection(), Projection::Perspective { .. }) {
            return None;
        }
        let u = grid.unit_exponent();
        let up = 1.0 + 1.0 / 65536.0;
        let near = ceil_fixed(camera.near() * (1.0 + 1.0 / (1 << 20) as f32), u)?;
        // (`N_z >= 2^12`: the depths' shifts below keep their margins.)
        if !(1 << 12..1 << 30).contains(&near) {
            return None;
        }
        let ([sx, sy], [nx, ny]) = camera.side_planes();
        let slope = |s: f32| {
            let fixed = s * (1.0 - 1.0 / 4096.0) * 32768.0;
            (0.0..65536.0).contains(&fixed).then_some(fixed as u16)
        };
        let slopes = [slope(sx)?, slope(sy)?];
        let slack = u16::try_from(ceil_fixed(grid.slack(), u)?).ok()?;
        let (focal, c) = (camera.focal() * SCREEN_SLACK, camera.corner_ray());
        let mu = tolerance / (focal * c) * up;
        let least_k = focal * c / tolerance * (1.0 - 1.0 / 65536.0);
        if least_k.is_nan() || least_k < 16.0 {
            return None;
        }
        // `h`: the rounding part of `η`, at most `Z_min U / 2^14`, over `Z_ℓ`.
        let below = 1.0 / (1u32 << ROUNDING_CAP) as f32;
        let h = below / (1.0 - 2.0 / (least_k + 1.0) - below * (1.0 + 1.0 / 65536.0)) * up;
        let n = nx + ny;
        let spread = 1.0 + sx + sy + (2.0 * mu + h) * n;
        let g = c + (mu + h) * n + 2.0 * h * spread + 16.0 * EPS * spread;
        let k = (focal * g / tolerance + 1.0) * up * (1u32 << K_BITS) as f32;
        let k_r = focal * mu * (n + 2.0 * spread) / tolerance * up * (1u32 << R_BITS) as f32;
        let fits = |x: f32| (0.0..2147483648.0).contains(&x);
        if !(fits(k) && (0.0..65535.0).contains(&k_r)) {
            return None;
        }
        Some(GridJudge {
            near,
            slopes,
            slack,
            k: k as u32 + 1,
            k_r: k_r as u16 + 1,
            k_c: (least_k * (1u32 << K_BITS) as f32) as u32,
            tolerance: unit_of(tolerance),
            rows: ViewRows::new(camera, tolerance),
        })
    }

    /// The first look at a triangle with fixed corners `corners` ([`GridView::fixed`], in
    /// `grid`'s units) and node `node`, at `tolerance` (the frame's); `exact`: the judgement
    /// asks for the bound itself where it is over the tolerance.
    pub fn look(
        &self,
        grid: &GridView,
        corners: &[[i32; 3]; 3],
        node: &HierarchyNode,
        tolerance: f32,
        exact: bool,
    ) -> FirstLook {
        let (vectors, scale, remainder) = (&node.vectors, node.scale, node.remainder);
        let [sx, sy] = self.slopes.map(u32::from);
        let seen = corners.map(|[x, y, z]| {
            z >= self.near as i32 && {
                let z = (z >> 15) as u32;
                x.unsigned_abs() <= sx * z && y.unsigned_abs() <= sy * z
            }
        });
        let sight = match seen {
            [true, true, true] => Sight::EveryCorner,
            [false, false, false] => return FirstLook::Seen(Seen::NOTHING),
            _ => Sight::OneCorner,
        };
        let z_min = corners.iter().map(|c| c[2]).min().unwrap_or(0);
        if z_min < self.near as i32 {
            return FirstLook::Seen(Seen {
                sight,
                isotropic_over: false,
            });
        }
        let z_min = z_min as u64;
        let u = grid.unit_exponent();
        let (Some(r), Some(s)) = (ceil_fixed(remainder, u), ceil_fixed(abs(scale), u)) else {
            return FirstLook::Seen(Seen {
                sight,
                isotropic_over: false,
            });
        };
        // `η`: the remainder and the grid's slack, `16 ε` of the extent, and `4 ε` of the
        // sum more.
        let extent = corners
            .iter()
            .map(|c| c.iter().map(|v| u64::from(v.unsigned_abs())).sum::<u64>())
            .max()
            .unwrap_or(0);
        let t = u64::from(self.slack) + (extent >> 20) + 1;
        let rounding = t + (t >> 20) + 1;
        let eta = u64::from(r) + u64::from(r >> 20) + 1 + rounding;
        // A remainder as deep as the near plane: the `f32` bound is infinite (see the module
        // docs, *Near the eye*).
        if r > self.near {
            return FirstLook::Over(f32::INFINITY);
        }
        let near = u64::from(self.near) - 1;
        if rounding > z_min >> ROUNDING_CAP || eta + (near >> 19) + 1 > near {
            return FirstLook::Seen(Seen {
                sight,
                isotropic_over: false,
            });
        }
        // `m`: the longest vector (`√n scale`, its `f32` at most `2^-15` above; the root in
        // four fractional bits, taken up), the remainder, and `ε` of the sum.
        let n = vectors
            .iter()
            .map(|c| c.iter().map(|&v| i32::from(v) * i32::from(v)).sum::<i32>())
            .max()
            .unwrap_or(0);
        let root = root_256(n);
        let longest = (wide(root + u32::from(root * root < (n as u32) << 8), s) + 15) >> 4;
        let longest = longest + (longest >> 15) + 1;
        let m = longest + u64::from(r) + ((longest + u64::from(r)) >> 20) + 1;
        let right = (z_min - (z_min >> 11) - 1) << K_BITS;
        // (Below `2^63 + 2^52 + 2^45`: no overflow.)
        let within = u32::try_from(m).ok().and_then(|m| {
            let left = wide(m, self.k)
                + (wide(r, u32::from(self.k_r)) << (K_BITS - R_BITS))
                + (eta << K_BITS);
            (left <= right).then_some(left)
        });
        if let Some(left) = within {
            let bound = WithinQuotient::isotropic(left, z_min as u32, tolerance);
            return FirstLook::Within(bound.into_bound());
        }
        let least = self.least_m(n, scale, remainder, u);
        let isotropic_over = least.is_some_and(|least| self.isotropic_over(z_min, least));
        // Over by the isotropic bound: the directional bound decides, and where every corner
        // is inside the view, a second look may find how (see `directional_look`).
        if let (true, Sight::EveryCorner, Some(rows), Some(least)) =
            (isotropic_over, sight, &self.rows, least)
        {
            let terms = NodeTerms {
                vectors,
                scale,
                remainder,
                m: [least, m],
            };
            match rows.look(tolerance, corners, &terms, z_min, eta, self.near, u, !exact) {
                Some(Decided::Within(ratio)) => {
                    let bound = WithinQuotient::directional(ratio, tolerance);
                    return FirstLook::Within(bound.into_bound());
                }
                Some(Decided::Over(bound)) => return FirstLook::Over(bound),
                None => {}
            }
        }
        FirstLook::Seen(Seen {
            sight,
            isotropic_over,
        })
    }

    /// At least the judgement's `m` (the longest vector and the remainder) in units `2^u`,
    /// for a node's largest squared code `n`, `scale` and `remainder` (see the module docs);
    /// `None` for a negative scale or remainder.
    fn least_m(&self, n: i32, scale: f32, remainder: f32, u: i32) -> Option<u64> {
        if scale.to_bits() >> 31 != 0 || remainder.to_bits() >> 31 != 0 {
            return None;
        }
        let (r, s) = (floor_fixed(remainder, -u)?, floor_fixed(scale, -u)?);
        // (Taken down to `u32`, each stays a lower bound.)
        let down = |x: i64| u32::try_from(x).unwrap_or(u32::MAX);
        let longest = wide(root_256(n), down(s)) >> 4;
        let sum = longest + u64::from(down(r));
        Some(sum.saturating_sub((sum >> 20) + 1))
    }

    /// Whether the `f32` isotropic bound of a triangle whose least corner depth is `Z_min`
    /// units (at least `N_z`), with `m` at least `least` units ([`least_m`](Self::least_m)),
    /// is over the tolerance (see the module docs).
    fn isotropic_over(&self, z_min: u64, least: u64) -> bool {
        wide(u32::try_from(least).unwrap_or(u32::MAX), self.k_c) > z_min << K_BITS
    }
}

/// `|x|`, from its bits (no library call where `f32` is software).
fn abs(x: f32) -> f32 {
    f32::from_bits(x.to_bits() & 0x7fff_ffff)
}

/// `⌈x 2^-u⌉` for a finite `x >= 0` below `2^31` units; `None` otherwise.
fn ceil_fixed(x: f32, u: i32) -> Option<u32> {
    if x.to_bits() >> 31 != 0 && x.to_bits() != 0x8000_0000 {
        return None;
    }
    let fixed = floor_fixed(-x, -u)?;
    u32::try_from(-fixed).ok().filter(|&v| v < 1 << 31)
}

/// `⌊√(256 n)⌋` for a node's largest squared code `n` (at least 0): read from [`ROOTS_256`]
/// where the codes are the bytes' six bits, else found digit by digit.
fn root_256(n: i32) -> u32 {
    match ROOTS_256.get(n as usize) {
        Some(&root) => u32::from(root),
        None => isqrt_by_table((n as u32) << 8),
    }
}

/// `⌊√(256 n)⌋` for every square a node's six-bit codes give (`n <= 3 · 31²`): the first
/// look's two roots a triangle, each a loop of sixteen steps found digit by digit (0.36M
/// of `fw_teapot`'s frame 0 update on ARMv6-M), for 5.8 KB of flash where the look is built
/// (a part with an FPU leaves it out).
static ROOTS_256: [u16; super::LARGEST_SQUARE + 1] = {
    let mut roots = [0; super::LARGEST_SQUARE + 1];
    let mut n = 0;
    while n < roots.len() {
        roots[n] = isqrt((n as u32) << 8) as u16;
        n += 1;
    }
    roots
};

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::deviation::kept::KEPT;
    use crate::deviation::vectors::Quantised;
    use crate::deviation::{bound_on_screen, isotropic_bound_on_screen, view_extent};
    use crate::tessellator::quantize::PositionGrid;
    use crate::tessellator::HierarchyNode;
    use crate::test_rng::TestRng;

    /// `screen::isotropic_from`'s bound in `f64`, its real value for the `f32` judgement's
    /// own inputs: what the look's bound must cover.
    fn isotropic_exact(camera: &Camera, z_corner: f32, size: f32, m: f32, slack: f32) -> f64 {
        let ([sx, sy], [nx, ny]) = camera.side_planes();
        let (sx, sy, nx, ny) = (sx as f64, sy as f64, nx as f64, ny as f64);
        let eps = EPS as f64;
        let (m, near) = (m as f64, camera.near() as f64);
        let eta = (slack + 16.0 * EPS * size) as f64;
        let z_f = (z_corner as f64).max(near - eta);
        let z_least = (z_f - eta).min(near.max(z_f - m - eta));
        let reach = (m + eta) * (nx + ny) / z_least;
        let spread = 1.0 + sx + sy + reach;
        let s = camera.corner_ray() as f64 + reach;
        let g = m * (s + 2.0 * eta * spread / z_least + 16.0 * eps * spread);
        camera.focal() as f64 / z_least * g * SCREEN_SLACK as f64
    }

    /// One random triangle of [`random_cases`]: its frame, its corners (fixed and as the
    /// `f32` judgement reads them) and its node.
    struct Case<'a> {
        k: usize,
        camera: &'a Camera,
        view: &'a GridView,
        judge: &'a GridJudge,
        tolerance: f32,
        fixed: [[i32; 3]; 3],
        points: [Vec3; 3],
        node: HierarchyNode,
    }

    /// How the random cases' nodes deviate.
    #[derive(Clone, Copy, Debug, PartialEq)]
    enum Vectors {
        /// At random.
        Across,
        /// Mostly along the view ray (a surface facing the eye, whose directional bound is
        /// far below its isotropic one).
        Facing,
        /// None, a scale of 0: a leaf of the bake, its bound its remainder alone.
        Bare,
    }

    /// Random grids, cameras, tolerances and triangles (50 each of 600 frames), their
    /// deviation from far within the tolerance to far over it, the node's vectors as
    /// `vectors` says.
    fn random_cases(seed: u64, kind: Vectors, mut each: impl FnMut(Case<'_>)) {
        let facing = kind == Vectors::Facing;
        let mut rng = TestRng::new(seed);
        let mut unit = |scale: f32| rng.signed(1 << 20) as f32 / (1 << 20) as f32 * scale;
        for k in 0..600 {
            let size = [0.05, 1.0, 40.0][k % 3];
            let centre = Vec3::new(unit(2.0), unit(2.0), unit(2.0)) * size;
            let min = centre - Vec3::splat(size);
            let grid = PositionGrid {
                min: min.to_array(),
                step: [2.0 * size / 65535.0; 3],
            };
            let eye = centre
                + Vec3::new(unit(1.0), unit(1.0), unit(1.0)).normalize_or(Vec3::X)
                    * size
                    * (3.0 + unit(2.5));
            let viewport = [[240, 240], [1024, 768], [128, 160]][k % 3];
            let Ok(camera) = Camera::new(
                eye,
                centre + Vec3::new(unit(1.0), unit(1.0), unit(1.0)) * size * 0.3,
                Vec3::Z,
                Projection::Perspective {
                    fov_y_degrees: 30.0 + unit(20.0).abs(),
                },
                size * (0.01 + unit(0.02).abs()),
                viewport,
            ) else {
                continue;
            };
            let tolerance = 0.25 + unit(1.75).abs();
            let Some(view) = GridView::new(&camera, &grid) else {
                continue;
            };
            let Some(judge) = GridJudge::new(&camera, tolerance, &view) else {
                continue;
            };
            let toward = (centre - eye).normalize_or(Vec3::X);
            for _ in 0..50 {
                let base = [0, 1, 2].map(|_| (32768.0 + unit(30000.0)) as i32);
                let corners = [0, 1, 2].map(|_| {
                    let spread = [4000.0, 400.0, 40.0][k % 3];
                    base.map(|b| (b + unit(spread) as i32).clamp(0, 65535) as u16)
                });
                let fixed = corners.map(|q| view.fixed(q));
                let points = fixed.map(|f| view.point_of(f));
                // A deviation from a tenth to ten times what the tolerance allows here (a
                // hundred times, facing the eye).
                let z = points
                    .iter()
                    .map(|p| p.z)
                    .fold(f32::INFINITY, f32::min)
                    .abs();
                let allowed = tolerance * z / camera.focal();
                let m = allowed * 10f32.powf(unit(1.0) + f32::from(u8::from(facing)));
                let vectors = [0; KEPT].map(|_: u8| {
                    let along = if facing { unit(31.0) } else { 0.0 };
                    let across = if facing { 2.0 } else { 31.0 };
                    let v = toward * along + Vec3::new(unit(across), unit(across), unit(across));
                    v.to_array().map(|x| x.clamp(-31.0, 31.0) as i8)
                });
                let node = match kind {
                    Vectors::Bare => HierarchyNode {
                        remainder: m * unit(0.6).abs(),
                        ..HierarchyNode::default()
                    },
                    _ => HierarchyNode {
                        vectors,
                        scale: m / 40.0,
                        remainder: m * unit(if facing { 0.05 } else { 0.6 }).abs(),
                        ..HierarchyNode::default()
                    },
                };
                each(Case {
                    k,
                    camera: &camera,
                    view: &view,
                    judge: &judge,
                    tolerance,
                    fixed,
                    points,
                    node,
                });
            }
        }
    }

    /// Random triangles (see [`random_cases`]): a triangle the look finds in view the `f32`
    /// judgement does not leave out, and one it finds wholly in view has the same bound on
    /// screen whether that bound tests its corners or not; one it finds over by the isotropic
    /// bound, the `f32` isotropic bound finds over; one it finds within, the `f32` isotropic
    /// bound finds within too, and the look's bound covers that bound's exact value and stays
    /// within the tolerance. And the look is worth taking: it finds within most of what the
    /// `f32` bound does, with a bound close to it. (The isotropic look alone: without the
    /// directional one, tested below.)
    #[test]
    fn the_first_look_decides_as_the_float_judgement() {
        let (mut looked, mut in_view, mut within, mut float_within) = (0, 0, 0, 0);
        let (mut every, mut over, mut float_over, mut near_eye) = (0, 0, 0, 0);
        let mut loosest = 1.0f64;
        let mut near_loosest = 1.0f64;
        random_cases(0x0f1f_5757, Vectors::Across, |case| {
            let Case {
                k,
                camera,
                view,
                tolerance,
                fixed,
                points,
                node,
                ..
            } = case;
            let judge = GridJudge {
                rows: None,
                ..*case.judge
            };
            let look = judge.look(view, &fixed, &node, tolerance, false);
            looked += 1;
            // The `f32` judgement's own steps (`judge::judge_vectors`).
            let (big, r) = (node.longest_quantised(), node.remainder);
            let slack = r + view.slack();
            let size = view_extent(&points);
            let beyond =
                super::super::judge::beyond_one_plane(camera, points, size, big + r + view.slack());
            let z_corner = points.iter().map(|p| p.z).fold(f32::INFINITY, f32::min);
            let isotropic = isotropic_bound_on_screen(camera, points, size, big + r, slack);
            // The bound on screen in full, testing its corners or not.
            let e = Quantised::new(node.vectors, node.scale);
            let full_bound = |inside| {
                bound_on_screen(
                    camera,
                    points,
                    size,
                    &e,
                    big,
                    r,
                    slack,
                    f32::INFINITY,
                    inside,
                )
            };
            let seen = match look {
                FirstLook::Within(_) => None,
                FirstLook::Over(bound) => {
                    // Without the directional look, only a remainder as deep as the near
                    // plane: both `f32` bounds are infinite.
                    let full = full_bound(false);
                    assert!(
                        bound == f32::INFINITY && isotropic == bound && full == bound,
                        "case {k}: over by {bound}, the f32 bounds {isotropic} and {full}"
                    );
                    near_eye += 1;
                    None
                }
                FirstLook::Seen(seen) => Some(seen),
            };
            if let Some(Seen {
                isotropic_over: true,
                ..
            }) = seen
            {
                assert!(isotropic > tolerance, "case {k}: {isotropic} not over");
                over += 1;
            }
            if look != FirstLook::Seen(Seen::NOTHING) {
                in_view += 1;
                assert!(!beyond, "case {k}: in view, but left out");
            }
            if seen.is_some_and(|s| s.sight == Sight::EveryCorner) {
                // The bound on screen's own test finds the corners inside: the same bits.
                assert_eq!(
                    full_bound(true).to_bits(),
                    full_bound(false).to_bits(),
                    "case {k}"
                );
                every += 1;
            }
            float_within += usize::from(!beyond && isotropic <= tolerance);
            float_over += usize::from(!beyond && isotropic > tolerance);
            if let FirstLook::Within(bound) = look {
                let bound = bound.value();
                within += 1;
                let exact = isotropic_exact(camera, z_corner, size, big + r, slack);
                assert!(
                    isotropic <= tolerance,
                    "case {k}: {isotropic} over {tolerance}"
                );
                assert!(bound <= tolerance, "case {k}: {bound} over {tolerance}");
                assert!(bound as f64 >= exact, "case {k}: {bound} under {exact}");
                loosest = loosest.max(bound as f64 / isotropic as f64);
                if isotropic > 0.9 * tolerance {
                    near_loosest = near_loosest.max(bound as f64 / isotropic as f64);
                }
            }
        });
        assert!(looked > 20_000, "{looked} triangles looked at");
        // (A triangle found over near the eye is decided before its sight is.)
        assert!(
            (every + near_eye) * 2 > in_view,
            "{every} of {in_view} wholly in view, {near_eye} over near the eye"
        );
        // Measured: over 8,545 of the 13,110 the `f32` isotropic bound finds over.
        assert!(over * 2 > float_over, "over {over} of {float_over}");
        // Measured: 22,365 of 30,000 in view (the others partly off the screen), 2,208 of
        // them over near the eye; within 9,482 of the 9,525 the `f32` bound finds (9,461
        // when the look asked `η <= near / 2`), the look's bound at most 4.0% above it, 0.5%
        // where that is over 0.9 of the tolerance.
        assert!(
            in_view * 10 > looked * 7
                && within * 100 > float_within * 95
                && loosest < 1.08
                && near_loosest < 1.02,
            "in view {in_view} of {looked}, within {within} of {float_within}, loosest \
             {loosest} ({near_loosest} near the tolerance)"
        );
    }

    /// Random triangles (see [`random_cases`]), their vectors at random, mostly along the
    /// view ray, or none: where the look finds within or over past the isotropic bound, the
    /// `f32` judgement (`bound_on_screen` in full, every corner inside) finds the same, and
    /// the look's bound lies on the same side of the `f32` bound as of the tolerance; asked
    /// for the bound in full, it decides the same, and a bound over is at least the `f32`
    /// one. And it is worth taking: it decides most of the triangles the `f32` directional
    /// bound judges, and in full most of those over, close to their bound.
    #[test]
    fn the_directional_look_decides_as_the_float_bound() {
        for (seed, kind) in [
            (0x0d1e_c7ed, Vectors::Across),
            (0xfac1_0001, Vectors::Facing),
            (0xba5e_0001, Vectors::Bare),
        ] {
            let (mut judged, mut within, mut over, mut float_within) = (0, 0, 0, 0);
            let (mut loosest, mut lowest) = (1.0f64, 1.0f64);
            let (mut in_full, mut loosest_in_full) = (0, 1.0f64);
            random_cases(seed, kind, |case| {
                let Case {
                    k,
                    camera,
                    view,
                    judge,
                    tolerance,
                    fixed,
                    points,
                    node,
                } = case;
                // Where the isotropic look decides nothing, it finds nothing more.
                let alone = GridJudge {
                    rows: None,
                    ..*judge
                }
                .look(view, &fixed, &node, tolerance, false);
                let Some(Seen {
                    sight: Sight::EveryCorner,
                    isotropic_over: true,
                }) = (match alone {
                    FirstLook::Seen(seen) => Some(seen),
                    _ => None,
                })
                else {
                    assert_eq!(
                        judge.look(view, &fixed, &node, tolerance, false),
                        alone,
                        "case {k}"
                    );
                    return;
                };
                judged += 1;
                let (big, r) = (node.longest_quantised(), node.remainder);
                let e = Quantised::new(node.vectors, node.scale);
                let size = view_extent(&points);
                let full = bound_on_screen(
                    camera,
                    points,
                    size,
                    &e,
                    big,
                    r,
                    r + view.slack(),
                    f32::INFINITY,
                    true,
                );
                float_within += usize::from(full <= tolerance);
                match judge.look(view, &fixed, &node, tolerance, false) {
                    FirstLook::Within(bound) => {
                        let bound = bound.value();
                        within += 1;
                        assert!(full <= tolerance, "case {k}: {full} over {tolerance}");
                        assert!(bound >= full && bound <= tolerance, "case {k}: {bound}");
                        loosest = loosest.max(bound as f64 / full as f64);
                    }
                    FirstLook::Over(bound) => {
                        over += 1;
                        assert!(full > tolerance, "case {k}: {full} within {tolerance}");
                        assert!(bound <= full && bound > tolerance, "case {k}: {bound}");
                        lowest = lowest.min(bound as f64 / full as f64);
                    }
                    FirstLook::Seen(seen) => assert_eq!(
                        seen,
                        Seen {
                            sight: Sight::EveryCorner,
                            isotropic_over: true
                        }
                    ),
                }
                // Asked for the bound itself: within as above, over with a bound at least
                // the `f32` one.
                match judge.look(view, &fixed, &node, tolerance, true) {
                    FirstLook::Within(_) => assert!(full <= tolerance, "case {k}"),
                    FirstLook::Over(bound) => {
                        in_full += 1;
                        assert!(full > tolerance, "case {k}: {full} within {tolerance}");
                        assert!(bound >= full, "case {k}: {bound} under {full}");
                        loosest_in_full = loosest_in_full.max(bound as f64 / full as f64);
                    }
                    FirstLook::Seen(_) => {}
                }
            });
            std::eprintln!(
                "{kind:?}: {judged} judged by the directional bound, {float_within} within \
                 it; the look finds {within} within (bound at most {loosest} of it) and \
                 {over} over (at least {lowest}); in full {in_full} over (at most \
                 {loosest_in_full})"
            );
            // Measured: 949 of 959 within and 8,742 over of 9,721; facing the eye, 7,041 of
            // 7,070 within and 10,707 over of 17,977; without vectors, 300 of 306 within and
            // 2,563 over of 2,892. In full, every one of those over, at most 2.8%, 6.6% and
            // 2.2% above the `f32` bound.
            assert!(
                judged > [5_000, 2_000][usize::from(kind == Vectors::Bare)],
                "{judged}"
            );
            assert!(
                within * 100 > float_within * 98 && (within + over) * 100 > judged * 98,
                "{within} of {float_within} within, {over} over, of {judged}"
            );
            assert!(
                in_full * 100 > over * 99 && loosest_in_full < 1.08,
                "in full {in_full} of {over} over, at most {loosest_in_full} of the bound"
            );
        }
    }

    /// A frame's worst bound raised through [`QuotientLimit`] (as a part without an FPU
    /// raises it) has the bits it has with every quotient divided out: random quotients, among them many at a hair's breadth of the
    /// worst so far, and bounds given as values between them.
    #[test]
    fn the_limit_keeps_the_worst_bound_bit_for_bit() {
        let mut rng = TestRng::new(0x51ab_1e5e);
        let (mut skipped, mut quotients) = (0, 0);
        for frame in 0..200 {
            let tolerance = 0.25 + (rng.next_u32() % 1750) as f32 / 1000.0;
            let unit = tolerance * (1.0 + 1.0 / 32768.0) / 65536.0;
            let (mut worst, mut eager) = (0.0f32, 0.0f32);
            let mut limit = QuotientLimit::NONE;
            for _ in 0..500 {
                if rng.next_u32().is_multiple_of(16) {
                    let b = (rng.next_u32() % 1000) as f32 / 1000.0 * tolerance;
                    worst = crate::math::max(worst, b);
                    eager = crate::math::max(eager, b);
                    continue;
                }
                let z_min = 256 + rng.next_u32() % ((1 << (8 + frame % 23)) - 255);
                let most = u64::from(z_min) << 16;
                let left = match rng.next_u32() % 3 {
                    // At the worst so far, give or take a few units.
                    0 => {
                        let ratio = f64::from(eager) / f64::from(unit);
                        let at = (ratio * f64::from(z_min)) as i64 + rng.signed(3);
                        at.clamp(1, most as i64) as u64
                    }
                    _ => {
                        1 + (u64::from(rng.next_u32()) << 16 | u64::from(rng.next_u32() >> 16))
                            % most
                    }
                };
                let q = match rng.next_u32() % 4 {
                    0 => {
                        let b = z_min >> 1;
                        // (`left b` may pass `2^64`.)
                        let a = u128::from(left) * u128::from(b) / u128::from(most);
                        let a = a.min(u128::from(b)) as u32;
                        WithinQuotient::directional([a, b], tolerance)
                    }
                    _ => WithinQuotient::isotropic(left, z_min, tolerance),
                };
                quotients += 1;
                skipped += usize::from(!limit.raise_by(&mut worst, q));
                eager = crate::math::max(eager, q.value());
                assert_eq!(worst.to_bits(), eager.to_bits(), "frame {frame}: {q:?}");
            }
        }
        std::eprintln!("{skipped} of {quotients} quotients never divided out");
        assert!(skipped > quotients / 2, "{skipped} of {quotients}");
    }
}
