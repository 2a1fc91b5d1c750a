//! A frame's corners taken to the screen in integers, for parts without an FPU
//! ([`Arithmetic::Integer`](crate::Arithmetic)).
//!
//! Where `f32` is software, taking a vertex to the screen in `f32` costs about 60 library
//! calls: its move into view coordinates, its shade, the clip test and the projection. Here
//! the same steps take integer products and two divisions, from the vertex's `f32` position
//! and normal read as integers by their bits (no `f32` arithmetic). The corners keep the
//! types the rest of the renderer takes (a view position and a shade in `f32`, exact copies
//! of the integers), so that clipping, flat shading and the depth key are the float path's
//! own, run on the same bits on every target: a host that draws with
//! [`Arithmetic::Integer`](crate::Arithmetic) draws what such a firmware draws, bit for bit.
//!
//! # The frame in integers
//!
//! With `o` and `r` the centre and radius of the source's bounding sphere, a point `p` is read
//! as `d = ⌊p 2^k⌋ - ⌊o 2^k⌋` (each coordinate), `k` such that `2^13 <= r 2^k < 2^14`: every
//! point within `2 r` of the centre has `|d| < 2^15`. The rotation's rows are taken to
//! `2^-15` (`R` in `i16` range), so that `R d` is exact in `i32` (each row's entries sum to at
//! most `√3` in magnitude). The view coordinates are `(R d) 2^-(15+k) + T`, `T` the sphere's
//! centre in view coordinates, kept as integers in units of `2^-m`, `m` the largest for which
//! every point within `2 r` of the centre stays below `2^23` units: so each is an exact `f32`.
//!
//! Each coordinate is within `e = r 2^-11` and two units of `2^-m` of its exact value (a
//! unit is at most `2^-21` of the largest coordinate of `T` plus `3.5 r`). `d` is within one unit
//! (`2^-k <= r 2^-13`) of `(p - o) 2^k` in each coordinate (a difference of two floors), so
//! it moves the point by less than `√3 r 2^-13`, which the rotation keeps; the rows' rounding
//! (`2^-16` an entry) adds at most `√3 |p - o| 2^-16 <= √3 r 2^-15` (`|p - o| <= 2 r`); the
//! shift to `2^-m` units and `T`'s rounding add one unit each. The rest is below
//! `2.2 r 2^-13`, and for a point read from a grid (below) below `3.9 r 2^-13`, both within
//! `4 r 2^-13 = e`. On screen that is `e f / z` pixels, `f` the focal length in pixels: two
//! hundredths of a pixel where the sphere spans 100 pixels, a few tenths where it spans
//! several screens (a close-up). A vertex has one position however many triangles share it,
//! so the mesh stays closed on screen; only its place moves, by that much.
//!
//! # Points on a grid
//!
//! A hierarchy's compact bytes hold a vertex as its point on the grid of the model's box,
//! `P_j = min_j + q_j s_j` with `q_j` a `u16` (see `tessellator::quantize`), and its normal
//! as an octahedral code. Where the renderer draws a tessellator's frame in integers, it reads
//! them from there ([`FixedView::grid_corner`]) rather than from the vertex decoded into
//! `f32`, which it would read back into integers:
//!
//! - **The point.** `d_j = ⌊(q_j S_j + B_j) 2^-15⌋` with `S_j` the step `s_j 2^(k+15)`
//!   rounded (about `2^14`: below `2^15`, so that `q_j S_j` is within `i32`) and
//!   `B_j = ⌊min_j 2^(k+15)⌋ - ⌊o_j 2^k⌋ 2^15`, found once a frame
//!   ([`FixedView::grid_reading`], which checks that both ends of each coordinate's range,
//!   `q_j = 0` and `65535`, stay within `i32`: so does every point between). Then
//!   `(q_j S_j + B_j) 2^-15 = (P_j - o_j) 2^k + ω + (q_j σ - μ) 2^-15`, with `ω ∈ [0, 1)`
//!   what the floor took off `o_j 2^k`, `|σ| <= 1/2` the step's rounding and `μ ∈ [0, 1)`
//!   the floor of the corner's term: the last is below `65535 / 2^16 + 2^-15 < 1.0001`, so
//!   `d_j` is within `2.0001` units of `(P_j - o_j) 2^k`. The point moves by less than
//!   `√3 · 2.0001 < 3.47` units, `3.47 r 2^-13`, and with the rows' rounding as above each
//!   view coordinate stays within `3.9 r 2^-13` (and the two units), within `e`.
//! - **The normal.** The code's point on the octahedron `n` (integers, `|a| + |b| + |z| =
//!   127`, so `5377 <= |n|² <= 16129`) over its length: `y ≈ 2^22 / |n|` from a table of 86
//!   entries (one per 128 squares, at their middle: within 0.6%), one Newton step for the
//!   inverse root (`y (3 - |n|² y²) / 2`, its relative error then about `1.5 · 0.006²`, and
//!   the steps' floors add `2^-15`), and `n_i y 2^-8` rounded: `2^14 n_i / |n|` up to a
//!   relative `10^-4` and half a unit, within `2.4` units of `2^14` times the exact unit
//!   normal's coordinate (a test over every code finds 1.1), where the float path's reading
//!   of the `f32` normal is within one. Its shade is then found as below, and
//!   stays within `2^-10` of the float path's.
//!
//! # On screen
//!
//! A corner with view coordinates `(x, y, z)` (units `2^-m`) is inside the clip planes when
//! `z` is at least the near plane (rounded up) and its pixel is within the guard band: `|x| f
//! 16 <= w 16 z`, likewise `y`, `w` the viewport's width (the guard band is twice the
//! viewport), compared on `x, y, z` shifted so that `z < 2^16`. Its pixel position, in
//! sixteenths of a pixel, is `c + round(16 f x / z)` on those shifted values: within `16 f
//! 2^-15 + 1/2` sixteenths of the exact one for these coordinates (the shift takes less than
//! one unit off `x`, where `z >= 2^15`; the rounding half a sixteenth), two thirds of a
//! sixteenth on a 240-pixel display, two and a half at 1024 pixels. (`16 f` must be below
//! `2^16`: a 1024-pixel-high view narrower than about 7 degrees takes the float path.) The
//! depth key is found in integers too (below).
//!
//! # Depth keys
//!
//! The float path's key of depth `z` is `1 + 65534 (1/z - 1/z_f) / (1/z_n - 1/z_f)`, rounded:
//! 1 at the far end `z_f` of the source's sphere, 65535 at its near end `z_n` (or the near
//! plane). In integers, with `Z_n = ⌊z_n 2^m⌋` (at least 1) and `Z_f = ⌈z_f 2^m⌉` the ends
//! in view units and `z` clamped to `[Z_n, Z_f]`, that is `1 + 65534 ρ ζ` with
//! `ρ = (Z_f - z) / (Z_f - Z_n)` and `ζ = Z_n / z`, both in `[0, 1]`: a product, so that the
//! difference `Z_f - z`, exact in integers, keeps its precision however far the range is.
//!
//! - `p = ⌊(Z_f - z) 2^a P 2^-46⌋`, at most 65535, with `a` the shift that takes
//!   `Z_f - Z_n` into `[2^30, 2^31)` and `P = ⌊(2^62 - 1) / ((Z_f - Z_n) 2^a)⌋`, found once a
//!   frame: within 2 of `2^16 ρ` (the reciprocal's floor moves it by a relative `2^-31`, the
//!   product's floor and the cap by one each).
//! - `q = ⌊C / ⌊z 2^-j⌋⌋`, at most 65535, one `u32` quotient, with `j` the shift that takes
//!   `Z_n` into `[2^15, 2^16)` (0 for a smaller one) and `C = Z_n 2^(16 - j)`: `⌊z 2^-j⌋` is
//!   at least `2^15` and off `z 2^-j` by less than one, a relative `2^-15`, so `q` is within
//!   4 of `2^16 ζ`.
//! - `key = 1 + ⌊⌊p q 2^-16⌋ 65534 2^-16⌋`: `p q` is off `2^32 ρ ζ` by at most
//!   `2 q + 4 · 2^16 ρ <= 6 · 2^16`, six keys, and the two floors take less than one each. The key
//!   is within eight of the exact map's (a test over random views finds 3.3), and never
//!   rises with the depth (`p` and `q` fall as `z` rises), so nearer stays in front. The near
//!   end's key is 65533 or more.
//!
//! A range under `2^16` units (a sphere under about `2^-6` of its distance) keeps the float
//! path's keys, whose ends would otherwise round by keys. The float path's key, in `f32`
//! where it is software, took about 700 instructions a corner on ARMv6-M; this one a
//! quotient and three products.
//!
//! The shade of a unit normal `n` (in `2^-14`) is `a + (1 - a) max(0, ±R n · l)`, `l` the
//! light in view coordinates in `2^-14` and the sign the one that turns `n` towards the eye
//! (the sign of `R n · -v`, on `v` shifted to 15 bits): within `2^-10` of the float path's
//! before both are rounded to a level of 255. A normal not of unit length (beyond `2^-10`)
//! takes the float path's shade.

use glam::Vec3;

use crate::bound::BoundingSphere;
pub(super) use crate::math::f32_of;
use crate::math::{leading_zeros, Divisor, INTEGER_FORMS};
use crate::tessellator::grid_view::floor_fixed;
use crate::view::{Camera, Projection};

/// Largest viewport side (in pixels) the integer projection takes: its products stay in
/// `u32` up to here.
const MAX_SIDE: u32 = 1024;

/// A frame's view in integers (see the module docs).
#[derive(Clone, Copy, Debug)]
pub(super) struct FixedView {
    /// The rotation's rows in `2^-15` (the few bytes matter: a firmware's renderer keeps this
    /// on a stack of a few KiB).
    rows: [[i16; 3]; 3],
    /// `⌊o 2^k⌋`.
    origin: [i32; 3],
    /// `k`: a position is read in units of `2^-k`.
    k: i16,
    /// `m`: view coordinates are in units of `2^-m`.
    m: i16,
    /// `15 + k - m`: the shift from `R d` to view units.
    shift: u8,
    /// The sphere's centre in view units.
    centre: [i32; 3],
    /// The near plane in view units, rounded up (at least 1).
    near: i32,
    /// `16 f`: the focal length in sixteenths of a pixel.
    focal: u16,
    /// The viewport's width and height in pixels.
    viewport: [u16; 2],
    /// The light's direction in view coordinates, in `2^-14`.
    light: [i16; 3],
    /// `255 a` and `255 (1 - a)` in `2^-8`, `a` the ambient light.
    ambient: i32,
    diffuse: i32,
    /// The frame's depth keys in integers, where it reads them so (see
    /// [`with_depth`](Self::with_depth)).
    depth: Option<DepthReading>,
}

/// A frame's depth keys in integers (see the module docs, *Depth keys*): `key = 1 +
/// ⌊⌊p q 2^-16⌋ 65534 2^-16⌋` with `p = ⌊(Z_f - z) 2^a P 2^-46⌋` and `q = ⌊C / ⌊z 2^-j⌋⌋`,
/// `z` clamped to `[Z_n, Z_f]`.
#[derive(Clone, Copy, Debug)]
struct DepthReading {
    /// `Z_n`, `Z_f`: the near and far ends of the keys' range in view units.
    near: i32,
    far: i32,
    /// `P = ⌊(2^62 - 1) / ((Z_f - Z_n) 2^a)⌋`.
    inverse: u32,
    /// `C = Z_n 2^(16 - j)`.
    top: u32,
    /// `a` and `j`.
    span_shift: u8,
    depth_shift: u8,
}

/// Fraction bits of a [`GridReading`]: a point's offset is found in `2^-(k + 15)`, then cut
/// to `2^-k`.
const GRID_BITS: i32 = 15;

/// A frame's reading of a grid's points as offsets from the sphere's centre in `2^-k` (see
/// the module docs, *Points on a grid*): `d_j = ⌊(q_j S_j + B_j) 2^-15⌋`.
#[derive(Clone, Copy, Debug)]
pub(super) struct GridReading {
    /// `S_j`: the grid's step `s_j` in `2^-(k + 15)`, rounded; below `2^15`.
    step: [i32; 3],
    /// `B_j = ⌊min_j 2^(k + 15)⌋ - ⌊o_j 2^k⌋ 2^15`.
    start: [i32; 3],
}

/// The unit normal of octahedral code `code` in `2^-14`, each coordinate within `2.4` of
/// `2^14` times the exact one's (see the module docs, *Points on a grid*); `None` for the
/// zero normal's code, or one the bake does not write.
fn unit_normal_of_code(code: [i8; 2]) -> Option<[i32; 3]> {
    let n = crate::tessellator::quantize::octahedral_point(code)?;
    let square = n.iter().map(|c| c * c).sum::<i32>() as u32;
    // A bake's code has `|a| + |b| + |z| = 127`: its square is at least `127² / 3`.
    if !(FIRST_SQUARE..=LAST_SQUARE).contains(&square) {
        return None;
    }
    // `y ≈ 2^22 / √square` from the table, then one Newton step for `1 / √x`,
    // `y (3 - x y²) / 2`, in `u32`: `x y < 2^30`, `x y² 2^-14 ≈ 2^30`.
    let y = u32::from(INVERSE_ROOTS[((square - FIRST_SQUARE) >> ROOT_SPAN) as usize]);
    let t = ((square * y) >> 14) * y;
    let y = (y * (((3 << 30) - t) >> 15)) >> 16;
    // `c y 2^-8 = 2^14 c / √square`, rounded (`|c y| < 2^23`).
    Some(n.map(|c| (c * y as i32 + (1 << 7)) >> 8))
}

/// The least and the largest square of a bake's octahedral point (`127² / 3` rounded up,
/// and `2^14`, above `127²`).
const FIRST_SQUARE: u32 = 5377;
const LAST_SQUARE: u32 = 1 << 14;

/// `log2` of the squares each entry of [`INVERSE_ROOTS`] spans.
const ROOT_SPAN: u32 = 7;

/// `⌊2^22 / √x⌉` at the middle `x` of each span of `2^7` squares from [`FIRST_SQUARE`] (within
/// 0.6% of `2^22 / √square` across the span: one Newton step takes that below `10^-4`).
static INVERSE_ROOTS: [u16; ((LAST_SQUARE - FIRST_SQUARE) >> ROOT_SPAN) as usize + 1] = {
    let mut table = [0; ((LAST_SQUARE - FIRST_SQUARE) >> ROOT_SPAN) as usize + 1];
    let mut k = 0;
    while k < table.len() {
        let middle = FIRST_SQUARE + ((k as u32) << ROOT_SPAN) + (1 << (ROOT_SPAN - 1));
        // `2^44 / x` is below `2^32` for `x >= 4097`; its root is `2^22 / √x`.
        table[k] = crate::math::isqrt(((1u64 << 44) / middle as u64) as u32) as u16;
        k += 1;
    }
    table
};

/// A corner in view units with its shade level: what [`FixedView::corner`] finds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct FixedCorner {
    /// `(x, y, z)` in units of `2^-m`, each below `2^23` in magnitude.
    pub view: [i32; 3],
    /// The shade level (0 to 255), where the normal is of unit length.
    pub level: Option<u8>,
}

impl FixedView {
    /// The view of `camera` in integers around `sphere`, with the view-space light `light`
    /// and ambient `ambient`; `None` where it cannot take it (an orthographic camera, a
    /// viewport side over [`MAX_SIDE`], a sphere or camera whose numbers leave the ranges of
    /// the module docs): the float path draws such frames.
    pub fn new(
        camera: &Camera,
        sphere: &BoundingSphere,
        light: Vec3,
        ambient: f32,
    ) -> Option<FixedView> {
        if !matches!(camera.projection(), Projection::Perspective { .. }) {
            return None;
        }
        let viewport = camera.viewport();
        let r = sphere.radius;
        if viewport.iter().any(|&s| s == 0 || s > MAX_SIDE) || !(r > 0.0 && r.is_finite()) {
            return None;
        }
        // `2^13 <= r 2^k < 2^14`, from the exponent's bits (`r` normal: at least 2^-126).
        let exponent = (r.to_bits() >> 23) as i32 - 127;
        if exponent < -120 {
            return None;
        }
        let k = 13 - exponent;
        let o = sphere.center.to_array();
        let origin = [fixed_of(o[0], k)?, fixed_of(o[1], k)?, fixed_of(o[2], k)?];
        let rows = camera
            .view_rows()
            .map(|row| row.map(|x| round_to_i32(x * 32768.0).clamp(-32767, 32767) as i16));
        if rows
            .iter()
            .any(|row| row.iter().map(|&x| x.unsigned_abs() as u32).sum::<u32>() > 57_000)
        {
            return None;
        }
        let t = camera.to_view(sphere.center);
        // Every point within `2 r` of the centre below `2^22` units (half the range each
        // coordinate may take, for the rounding).
        let reach = t.abs().max_element() + 3.5 * r;
        if !(reach.is_finite() && reach > 0.0) {
            return None;
        }
        let m = 22 - ((reach.to_bits() >> 23) as i32 - 127) - 1;
        let shift = u8::try_from(15 + k - m).ok().filter(|&s| s < 31)?;
        let scale = pow2(m)?;
        let centre = t.to_array().map(|x| round_to_i32(x * scale));
        let near = round_to_i32(ceil(camera.near() * scale)).max(1);
        let focal = camera.focal() * 16.0;
        if !(1.0..65535.0).contains(&focal) {
            return None;
        }
        let light = light
            .to_array()
            .map(|x| round_to_i32(x * 16384.0).clamp(-16384, 16384) as i16);
        let a = ambient.clamp(0.0, 1.0);
        Some(FixedView {
            rows,
            origin,
            k: k as i16,
            m: m as i16,
            shift,
            centre,
            near,
            focal: round_to_i32(focal) as u16,
            viewport: viewport.map(|s| s as u16),
            light,
            ambient: round_to_i32(a * 255.0 * 256.0),
            diffuse: round_to_i32((1.0 - a) * 255.0 * 256.0),
            depth: None,
        })
    }

    /// This view with its depth keys in integers, for the keys' range from depth `near` to
    /// `far` (`0 < near < far`, view coordinates; see the module docs, *Depth keys*). Where
    /// the numbers leave their ranges (a range under `2^16` units, about `2^-6` of its
    /// distance), and on a bare-metal part with an FPU, which leaves the code out (see
    /// `math::INTEGER_FORMS`), the keys stay the float path's.
    pub fn with_depth(mut self, near: f32, far: f32) -> FixedView {
        if !INTEGER_FORMS {
            return self;
        }
        self.depth = pow2(self.m.into()).and_then(|scale| {
            // `Z_n = ⌊z_n 2^m⌋` (at least 1) and `Z_f = ⌈z_f 2^m⌉`, below `2^23` units.
            let (near, far) = (near * scale, ceil(far * scale));
            if !(near >= 0.0 && far < 8_388_608.0) {
                return None;
            }
            let (near, far) = ((near as i32).max(1), far as i32);
            // (A range under `2^16` units keeps the float path's keys: see the module docs.)
            let span = u32::try_from(far - near).ok().filter(|&d| d >= 1 << 16)?;
            // `(Z_f - Z_n) 2^a` in `[2^30, 2^31)`, so `P` in `(2^31, 2^32)`.
            let span_shift = leading_zeros(span) - 1;
            let inverse = ((1u64 << 62) - 1) / u64::from(span << span_shift);
            // `Z_n 2^-j` in `[2^15, 2^16)`, or `j = 0` below.
            let depth_shift = (32 - leading_zeros(near as u32)).saturating_sub(16);
            Some(DepthReading {
                near,
                far,
                inverse: inverse as u32,
                top: (near as u32) << (16 - depth_shift),
                span_shift: span_shift as u8,
                depth_shift: depth_shift as u8,
            })
        });
        self
    }

    /// The depth key (1 far to 65535 near) of view depth `z` (units `2^-m`), where this view
    /// reads its keys in integers (see [`with_depth`](Self::with_depth)).
    #[inline]
    pub fn depth_key(&self, z: i32) -> Option<u16> {
        let d = self.depth.as_ref().filter(|_| INTEGER_FORMS)?;
        let z = z.clamp(d.near, d.far);
        // `p` and `q`: `2^16` times `(Z_f - z) / (Z_f - Z_n)` and `Z_n / z`, each at most
        // 65535. (`(Z_f - z) 2^a < 2^31`; `z 2^-j >= 2^15`, or `z` itself.)
        let n = ((d.far - z) as u32) << d.span_shift;
        let p = ((crate::math::wide(n, d.inverse) >> 46) as u32).min(65535);
        // (Where a division is a library call, by the reciprocal: fewer instructions.)
        let (q, _) = Divisor::new(z as u32 >> d.depth_shift).div_rem(d.top);
        let q = q.min(65535);
        let key = 1 + ((((p * q) >> 16) * 65534) >> 16);
        Some(key.min(65535) as u16)
    }

    /// The exponent of the view units: a corner's coordinates are in `2^-m`.
    pub fn units(&self) -> i32 {
        self.m.into()
    }

    /// Vertex `position` (model coordinates) with unit normal `normal`, in view units with
    /// its shade level; `None` where the position lies beyond `2 r` of the sphere's centre
    /// (the float path takes such a vertex).
    pub fn corner(&self, position: [f32; 3], normal: [f32; 3]) -> Option<FixedCorner> {
        let mut d = [0i32; 3];
        for i in 0..3 {
            let p = fixed_of(position[i], self.k.into())?;
            d[i] = p.checked_sub(self.origin[i])?;
        }
        let view = self.view_of(d)?;
        Some(FixedCorner {
            view,
            level: self.level(normal, view),
        })
    }

    /// How this view reads the points of a grid with corner `min` and steps `step` (a
    /// hierarchy's, see `quantize`) in its units; `None` where the numbers leave the ranges
    /// of the module docs (*Points on a grid*): the frame's corners are then read from their
    /// `f32` points.
    #[inline(never)]
    pub fn grid_reading(&self, min: [f32; 3], step: [f32; 3]) -> Option<GridReading> {
        let e = i32::from(self.k) + GRID_BITS;
        if !(-126..=127).contains(&e) {
            return None;
        }
        let mut reading = GridReading {
            step: [0; 3],
            start: [0; 3],
        };
        for j in 0..3 {
            let s = step[j] * crate::math::power_of_two(e);
            if !(0.0..32768.0).contains(&s) {
                return None;
            }
            let s = round_to_i32(s);
            let start = floor_fixed(min[j], e)? - (i64::from(self.origin[j]) << GRID_BITS);
            let end = start + 65535 * i64::from(s);
            let fits = |x: i64| i32::try_from(x).is_ok();
            if !(fits(start) && fits(end)) {
                return None;
            }
            reading.step[j] = s;
            reading.start[j] = start as i32;
        }
        Some(reading)
    }

    /// The grid point `q` of `grid`, whose normal has octahedral code `code`, in view units,
    /// with its shade level if `shaded` (see the module docs, *Points on a grid*); `None`
    /// where the point lies beyond `2 r` of the sphere's centre or the code is not one of a
    /// unit normal's (the float path takes such a vertex).
    pub fn grid_corner(
        &self,
        grid: &GridReading,
        q: [u16; 3],
        code: [i8; 2],
        shaded: bool,
    ) -> Option<FixedCorner> {
        // (Within `i32`: `grid_reading` checked both ends of each coordinate's range.)
        let d: [i32; 3] =
            core::array::from_fn(|j| (i32::from(q[j]) * grid.step[j] + grid.start[j]) >> GRID_BITS);
        let view = self.view_of(d)?;
        let level = match shaded {
            true => Some(self.level_of_unit(unit_normal_of_code(code)?, view)),
            false => None,
        };
        Some(FixedCorner { view, level })
    }

    /// A point's view coordinates from `d` (its offset from the sphere's centre in `2^-k`);
    /// `None` where it lies beyond `2 r` of the centre.
    #[inline]
    fn view_of(&self, d: [i32; 3]) -> Option<[i32; 3]> {
        if d.iter().any(|x| x.unsigned_abs() >= 30_720) {
            return None;
        }
        let rotated = self.rotate(d);
        Some(core::array::from_fn(|i| {
            (rotated[i] >> self.shift).wrapping_add(self.centre[i])
        }))
    }

    /// `R d`, `d` below `30,720` in magnitude (so within `i32`: see the module docs).
    fn rotate(&self, d: [i32; 3]) -> [i32; 3] {
        self.rows.map(|row| {
            let [a, b, c] = row.map(i32::from);
            a.wrapping_mul(d[0])
                .wrapping_add(b.wrapping_mul(d[1]))
                .wrapping_add(c.wrapping_mul(d[2]))
        })
    }

    /// The shade level of model normal `normal` at view position `view`; `None` for a normal
    /// not of unit length within `2^-10`.
    fn level(&self, normal: [f32; 3], view: [i32; 3]) -> Option<u8> {
        let mut n = [0i32; 3];
        for i in 0..3 {
            n[i] = fixed_of(normal[i], 14)?;
            if n[i].unsigned_abs() > 1 << 14 {
                return None;
            }
        }
        let length2: i32 = n.iter().map(|x| x * x).sum();
        if (length2 - (1 << 28)).unsigned_abs() > 1 << 18 {
            return None;
        }
        Some(self.level_of_unit(n, view))
    }

    /// The shade level of the model normal `n` (of unit length in `2^-14`, each coordinate
    /// at most `2^14` in size) at view position `view`.
    fn level_of_unit(&self, n: [i32; 3], view: [i32; 3]) -> u8 {
        // The normal in view coordinates, in `2^-14`.
        let n = self.rotate(n).map(|x| x >> 15);
        let dot = |a: [i32; 3], b: [i32; 3]| {
            a[0].wrapping_mul(b[0])
                .wrapping_add(a[1].wrapping_mul(b[1]))
                .wrapping_add(a[2].wrapping_mul(b[2]))
        };
        // Towards the eye: `-view`, shifted to 15 bits.
        let big = view.iter().map(|x| x.unsigned_abs()).max().unwrap_or(0);
        let s = (32 - leading_zeros(big)).saturating_sub(15);
        let towards = view.map(|x| -(x >> s));
        let lit = dot(n, self.light.map(i32::from)) >> 14;
        let lit = if dot(n, towards) < 0 { -lit } else { lit };
        let level = self.ambient + ((self.diffuse * lit.max(0)) >> 14);
        ((level + 128) >> 8).clamp(0, 255) as u8
    }

    /// Whether view position `view` (units `2^-m`) is inside the clip planes: in front of the
    /// near plane and within the guard band.
    pub fn inside(&self, view: [i32; 3]) -> bool {
        let Some([x, y, z]) = shifted(view) else {
            return false;
        };
        // `|x| 16 f <= 16 w z`: the pixel within the guard band (twice the viewport). In
        // `u32` (`|x| < 2^16`, `16 f < 2^16`; `16 w <= 2^14`, `z < 2^16`); `|x| >= 2^16 > z`
        // is taken as outside (a ray more than 45 degrees off the axis: the clipper decides).
        let within = |c: i32, side: u16| {
            let c = c.unsigned_abs();
            c < 1 << 16 && c * u32::from(self.focal) <= u32::from(side) * 16 * z as u32
        };
        view[2] >= self.near && within(x, self.viewport[0]) && within(y, self.viewport[1])
    }

    /// The pixel position of view position `view` (units `2^-m`, in front of the eye), in
    /// sixteenths of a pixel: `None` where it lies beyond the guard band's reach or on a ray
    /// more than 45 degrees off the view's axis (the float path projects those).
    pub fn pixel(&self, view: [i32; 3]) -> Option<[i32; 2]> {
        let [x, y, z] = shifted(view)?;
        let z = z as u32;
        if z == 0 {
            return None;
        }
        let focal = u32::from(self.focal);
        // (Two quotients by `z`: where a division is a library call, by one reciprocal.)
        let z_divisor = Divisor::new(z);
        let offset = |c: i32| -> Option<i32> {
            // `round(16 f |c| / z)` (halves up), in `u32` where `|c| < 2^16` (then `16 f |c|
            // + z / 2 < 2^32`, as `16 f < 2^16` and `z < 2^16`).
            let c_abs = c.unsigned_abs();
            if c_abs >= 1 << 16 {
                return None; // a ray more than 45 degrees off the axis: the float path's
            }
            let (q, _) = z_divisor.div_rem(c_abs * focal + z / 2);
            // At most 16 times the viewport's side (a corner the clipper moved a little past
            // the guard band, at most): far inside `i32`.
            let q = (q <= 1 << 20).then_some(q as i32)?;
            Some(if c < 0 { -q } else { q })
        };
        let [w, h] = self.viewport.map(|s| i32::from(s) * 8);
        Some([w + offset(x)?, h - offset(y)?])
    }
}

/// `view` shifted right so that its depth is below `2^16`, where the depth is positive.
fn shifted(view: [i32; 3]) -> Option<[i32; 3]> {
    let z = view[2];
    if z <= 0 {
        return None;
    }
    let s = (32 - leading_zeros(z as u32)).saturating_sub(16);
    Some(view.map(|c| c >> s))
}

/// `⌊x 2^e⌋`, from the bits of `x`: `None` where `x` is not finite or the value is not below
/// `2^30` in magnitude.
pub(super) fn fixed_of(x: f32, e: i32) -> Option<i32> {
    let bits = x.to_bits();
    let negative = bits >> 31 != 0;
    let exponent = ((bits >> 23) & 0xff) as i32;
    if exponent == 255 {
        return None;
    }
    // `x = ±mantissa 2^(exponent - 150)` (a subnormal's exponent is that of the least normal).
    let (mantissa, exponent) = match exponent {
        0 => (bits & 0x7f_ffff, 1),
        e => ((bits & 0x7f_ffff) | 0x80_0000, e),
    };
    if mantissa == 0 {
        return Some(0);
    }
    let up = exponent - 150 + e;
    let magnitude = if up >= 0 {
        if up > 6 {
            return None;
        }
        mantissa << up
    } else {
        let down = (-up).min(31) as u32;
        let whole = mantissa >> down;
        // `⌊-a⌋ = -⌈a⌉`: one more where bits were shifted out.
        if negative && whole << down != mantissa {
            whole + 1
        } else {
            whole
        }
    };
    Some(if negative {
        -(magnitude as i32)
    } else {
        magnitude as i32
    })
}

/// `x 2^e` where it is an integer below `2^22` in magnitude (so that `f32` arithmetic on it
/// and on its halves is exact), from bits; `None` otherwise.
///
/// Read straight from the bits (the mantissa shifted, where the bits shifted out are zero),
/// about a fifth of the instructions of the floor ([`fixed_of`]) and the way back
/// ([`f32_of`]) compared.
#[inline]
pub(super) fn exact_fixed(x: f32, e: i32) -> Option<i32> {
    let bits = x.to_bits();
    let field = (bits >> 23) & 0xff;
    if bits << 1 == 0 {
        return Some(0);
    }
    if field == 0 || field == 255 || !(-64..=64).contains(&e) {
        // Subnormal (below `2^-126`: never `2^-e` times an integer for these `e`), or not
        // finite.
        return None;
    }
    // `|x| = mantissa 2^(field - 150)`, so `|x| 2^e = mantissa 2^-down`.
    let mantissa = (bits & 0x7f_ffff) | 0x80_0000;
    // (`mantissa >= 2^23`: shifted up, or not at all, it is `2^22` or more.)
    let down = 150 - field as i32 - e;
    if !(1..=31).contains(&down) || (mantissa >> down) << down != mantissa {
        return None;
    }
    let magnitude = mantissa >> down;
    (magnitude < 1 << 22).then_some(if bits >> 31 != 0 {
        -(magnitude as i32)
    } else {
        magnitude as i32
    })
}

/// A shade in `[0, 1]` whose level ([`shade_to_u8`](super::project::shade_to_u8)) is `level`,
/// from bits: `level / 255` within a relative `2^-23` of it, below it.
pub(super) fn shade_of_level(level: u8) -> f32 {
    match level {
        0 => 0.0,
        255 => 1.0,
        // `⌊level 2^32 / 255⌋`, then its top 24 bits.
        l => {
            let n = (l as u32) * 16_843_009;
            let top = 31 - leading_zeros(n) as i32;
            let mantissa = n >> (top - 23);
            f32::from_bits(((top - 32 + 127) as u32) << 23 | (mantissa & 0x7f_ffff))
        }
    }
}

/// The level of shade `s` (`⌊255 s + 1/2⌋`, clamped to 0 to 255; 0 for NaN), from bits.
pub(super) fn level_of_shade(s: f32) -> u8 {
    let bits = s.to_bits();
    let exponent = ((bits >> 23) & 0xff) as i32;
    if bits >> 31 != 0 || exponent == 0 {
        return 0; // negative, zero or subnormal (NaN with its sign bit set too)
    }
    if exponent == 255 {
        return if bits & 0x7f_ffff == 0 { 255 } else { 0 };
    }
    if exponent >= 127 {
        return 255; // at least 1
    }
    // `255 s = 255 mantissa 2^(exponent - 150)`, the product within `u32`.
    let product = 255 * ((bits & 0x7f_ffff) | 0x80_0000);
    let down = (150 - exponent) as u32;
    if down >= 33 {
        return 0; // below 1/2 (the product is below `2^32`)
    }
    (((product >> (down - 1)) + 1) >> 1).min(255) as u8
}

/// `x` rounded to the nearest integer (`f32` arithmetic: for a frame's constants only). (Not
/// `libm::roundf` and `ceilf`: linked for these alone they cost the Cortex-M4F's `fw_teapot`
/// 188 bytes of its flash, which has a few hundred to spare.)
fn round_to_i32(x: f32) -> i32 {
    let t = x as i32;
    let r = x - t as f32;
    if r >= 0.5 {
        t + 1
    } else if r <= -0.5 {
        t - 1
    } else {
        t
    }
}

/// `⌈x⌉` for `|x| < 2^31` (a frame's constants only).
fn ceil(x: f32) -> f32 {
    let t = x as i32 as f32;
    if t < x {
        t + 1.0
    } else {
        t
    }
}

/// `2^e` as `f32`, where it is a normal number.
fn pow2(e: i32) -> Option<f32> {
    (-126..=127)
        .contains(&e)
        .then(|| crate::math::power_of_two(e))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::TestRng;
    extern crate std;

    /// A random point within `r` of `c`, from `rng`.
    fn near(rng: &mut TestRng, c: Vec3, r: f32) -> Vec3 {
        loop {
            let v = Vec3::new(
                rng.signed(1000) as f32,
                rng.signed(1000) as f32,
                rng.signed(1000) as f32,
            ) / 1000.0;
            if v.length() <= 1.0 {
                return c + v * r;
            }
        }
    }

    /// A random perspective camera looking at a random sphere from 1.2 to 41 radii away, its
    /// viewport 240, 320 or 1024 pixels wide by `case`, and the view of both in integers (with
    /// a light and ambient 0.2), from `rng`.
    fn random_view(rng: &mut TestRng, case: usize) -> (Camera, BoundingSphere, FixedView) {
        let r = 2f32.powi(rng.signed(12) as i32) * (1.0 + rng.signed(500) as f32 / 1000.0);
        let centre = near(rng, Vec3::ZERO, 4.0 * r);
        let distance = r * (1.2 + (rng.signed(1000) as f32 / 1000.0 + 1.0) * 20.0);
        let eye = centre + near(rng, Vec3::ZERO, 1.0).normalize_or(Vec3::X) * distance;
        let side = [240, 320, 1024][case % 3];
        let camera = Camera::new(
            eye,
            near(rng, centre, r),
            Vec3::Z,
            Projection::Perspective {
                fov_y_degrees: 40.0 + rng.signed(10) as f32,
            },
            0.01 * r,
            [side, side * 3 / 4],
        )
        .unwrap();
        let sphere = BoundingSphere {
            center: centre,
            radius: r,
        };
        let Some(f) = FixedView::new(&camera, &sphere, LIGHT.normalize(), 0.2) else {
            panic!("case {case}: no view in integers");
        };
        (camera, sphere, f)
    }

    /// Depth keys in integers: within eight of the exact map over the rounded range, never
    /// rising with the depth, 1 at the far end.
    #[test]
    fn depth_keys_follow_the_exact_map() {
        let mut rng = TestRng::new(0xde97_0001);
        let mut worst = 0f64;
        for case in 0..600 {
            let (camera, sphere, f) = random_view(&mut rng, case);
            let zc = camera.to_view(sphere.center).z;
            let zn = (zc - sphere.radius).max(camera.near());
            let zf = zc + sphere.radius;
            let f = f.with_depth(zn, zf);
            let d = f.depth.unwrap_or_else(|| panic!("case {case}: no reading"));
            assert!(f.depth_key(d.near) >= Some(65533), "case {case}");
            assert_eq!(f.depth_key(d.far), Some(1), "case {case}");
            let (a, b) = (f64::from(d.near), f64::from(d.far));
            let mut last = u16::MAX;
            for k in 0..=200 {
                let z = d.near + ((i64::from(d.far - d.near) * k) / 200) as i32;
                let key = f.depth_key(z).unwrap();
                assert!(key <= last, "case {case}: keys rise with the depth at {z}");
                last = key;
                let z = f64::from(z);
                let exact = 1.0 + 65534.0 * (1.0 / z - 1.0 / b) / (1.0 / a - 1.0 / b);
                let off = (f64::from(key) - exact).abs();
                worst = worst.max(off);
                assert!(off <= 8.0, "case {case}: key {key} against {exact} at {z}");
            }
            // Beyond the range, clamped.
            assert_eq!(f.depth_key(d.near / 2), f.depth_key(d.near), "case {case}");
            assert_eq!(
                f.depth_key(d.far.saturating_add(1000)),
                Some(1),
                "case {case}"
            );
        }
        assert!(worst > 0.5, "the test reaches its bound's size: {worst}");
    }

    /// A range of depths too short for the keys in integers keeps the float path's.
    #[test]
    fn depth_keys_of_a_thin_range_stay_the_float_paths() {
        let mut rng = TestRng::new(0xde97_0002);
        let (camera, sphere, f) = random_view(&mut rng, 0);
        let zc = camera.to_view(sphere.center).z;
        let r = sphere.radius;
        assert!(f
            .with_depth(zc, zc * (1.0 + 1e-6))
            .depth_key(1000)
            .is_none());
        assert!(f.with_depth(zc - r, zc + r).depth_key(1000).is_some());
        assert!(f.with_depth(zc, zc).depth_key(1000).is_none());
        assert!(f.depth_key(1000).is_none());
    }

    /// The light of the tests' views.
    const LIGHT: Vec3 = Vec3::new(0.3, -0.5, -0.8);

    /// The float path's shade level of unit normal `n` at model point `p`, seen from
    /// `camera`'s eye.
    fn float_level(camera: &Camera, n: Vec3, p: Vec3) -> f64 {
        let towards = camera.eye() - p;
        let d = n.dot(camera.rotate_from_view(LIGHT.normalize())) as f64;
        let d = if n.dot(towards) < 0.0 { -d } else { d };
        255.0 * (0.2 + 0.8 * d.max(0.0))
    }

    /// Over random cameras and spheres, the integer corners are within the module docs'
    /// `e = r 2^-11` (and two units) of the float path's view coordinates, their pixels within
    /// a sixteenth of a pixel more than `e` makes on screen, their shades within a level, and
    /// the clip test the float one's wherever a corner is not within that of a plane.
    #[test]
    fn integer_corners_follow_the_float_ones() {
        let mut rng = TestRng::new(0xf1_3ed);
        let (mut worst_view, mut worst_pixel, mut corners, mut clipped) = (0.0f64, 0.0f64, 0, 0);
        for case in 0..400 {
            let (camera, sphere, f) = random_view(&mut rng, case);
            let (centre, r) = (sphere.center, sphere.radius);
            let m = f.units();
            for _ in 0..50 {
                let p = near(&mut rng, centre, r);
                let n = near(&mut rng, Vec3::ZERO, 1.0).normalize_or(Vec3::Z);
                let c = f
                    .corner(p.to_array(), n.to_array())
                    .expect("a point in the sphere");
                let view = c.view.map(|x| f32_of(x, m) as f64);
                let exact = camera.to_view(p);
                let e = r as f64 / 2048.0 + 2.0 * f32_of(1, m) as f64;
                for (a, b) in view.iter().zip(exact.to_array()) {
                    worst_view = worst_view.max((a - b as f64).abs() / e);
                    assert!((a - b as f64).abs() <= e, "case {case}: {view:?} {exact}");
                }
                let z = exact.z as f64;
                // The clip test is the float frustum's wherever the point lies more than the
                // pixels' error (and a pixel) off the guard band's edges, `e` off the near
                // plane, and on a ray within 45 degrees of the axis (beyond, the integer
                // test leaves the corner to the clipper).
                if exact.z > camera.near() + e as f32 {
                    let frustum =
                        super::super::clip::Frustum::new(camera.near(), camera.half_extent(), true);
                    let [px, py] = camera.view_to_pixel(exact).map(f64::from);
                    let [w, h] = camera.viewport().map(f64::from);
                    let margin = 1.0 + (1.0 + 16.0 * camera.focal() as f64 * 2.0 * e / z) / 16.0;
                    let clear = |p: f64, side: f64| ((p - side / 2.0).abs() - side).abs() > margin;
                    let axis = exact.x.abs() <= 0.9 * exact.z && exact.y.abs() <= 0.9 * exact.z;
                    if axis && clear(px, w) && clear(py, h) {
                        clipped += 1;
                        assert_eq!(f.inside(c.view), frustum.contains(exact), "case {case}");
                    }
                }
                if !(f.inside(c.view) && exact.z > 0.0) {
                    continue;
                }
                corners += 1;
                let pixel = f.pixel(c.view).expect("a pixel");
                let float = camera.view_to_pixel(exact);
                let slack = 1.0 + 16.0 * camera.focal() as f64 * 2.0 * e / z;
                for (a, b) in pixel.iter().zip(float) {
                    let off = (*a as f64 - 16.0 * b as f64).abs();
                    worst_pixel = worst_pixel.max(off);
                    assert!(
                        off <= slack,
                        "case {case}: {pixel:?} {float:?} slack {slack}"
                    );
                }
                // The float path's shade, from the same normal at the same point.
                let level = c.level.expect("a unit normal") as f64;
                let float = float_level(&camera, n, p);
                assert!((level - float).abs() <= 1.0, "{level} {float}");
            }
        }
        assert!(corners > 5_000, "{corners} corners on screen");
        assert!(clipped > 15_000, "{clipped} clip tests compared");
        // (Measured: views within 0.30 e, pixels within 2.3 sixteenths, the largest at 1024
        // pixels, where `16 f` is near `2^14`.)
        assert!(worst_view > 0.0 && worst_pixel > 0.0);
    }

    /// Over random cameras and grids of a box around the sphere's centre (the renderer's
    /// sphere passes through the box's corners), the corners read from grid points are within
    /// the module docs' `e` (and two units) of the exact points' view coordinates, a code's
    /// unit normal within 2.4 units of the exact one, and the shade within a level of the
    /// float path's from the code's `f32` normal.
    #[test]
    fn grid_corners_follow_the_exact_points() {
        use crate::tessellator::quantize::{normal_code, normal_of};
        let mut rng = TestRng::new(0x6_41d);
        let (mut worst_view, mut worst_normal, mut shaded) = (0.0f64, 0.0f64, 0);
        for case in 0..300 {
            let (camera, sphere, f) = random_view(&mut rng, case);
            let r = sphere.radius;
            let half = near(&mut rng, Vec3::ZERO, 1.0)
                .abs()
                .normalize_or(Vec3::ONE)
                * r;
            let min = sphere.center - half;
            let step = 2.0 * half / 65535.0;
            let grid = f
                .grid_reading(min.to_array(), step.to_array())
                .expect("a grid around the sphere");
            let m = f.units();
            let e = r as f64 / 2048.0 + 2.0 * f32_of(1, m) as f64;
            let rows = camera.view_rows();
            let eye = camera.eye().to_array();
            for k in 0..50 {
                // Random points, and the box's corners.
                let q: [u16; 3] = core::array::from_fn(|j| match k {
                    0..8 => [0, 65535][k >> j & 1],
                    _ => rng.next_u32() as u16,
                });
                let n = near(&mut rng, Vec3::ZERO, 1.0).normalize_or(Vec3::Z);
                let code = normal_code(n.to_array());
                let c = f
                    .grid_corner(&grid, q, code, true)
                    .expect("a point of the box");
                let p: [f64; 3] = core::array::from_fn(|j| {
                    min[j] as f64 + q[j] as f64 * step[j] as f64 - eye[j] as f64
                });
                for (i, row) in rows.iter().enumerate() {
                    let exact: f64 = (0..3).map(|j| row[j] as f64 * p[j]).sum();
                    let got = f32_of(c.view[i], m) as f64;
                    worst_view = worst_view.max((got - exact).abs() / e);
                    assert!((got - exact).abs() <= e, "case {case}: {got} {exact}");
                }
                let unit = super::unit_normal_of_code(code).expect("a bake's code");
                let float = normal_of(code);
                for (a, b) in unit.iter().zip(float) {
                    let off = (*a as f64 - 16384.0 * b as f64).abs();
                    worst_normal = worst_normal.max(off);
                    assert!(off <= 2.4, "{unit:?} {float:?}");
                }
                if f.inside(c.view) {
                    shaded += 1;
                    let point = Vec3::from_array(p.map(|x| x as f32)) + camera.eye();
                    let float = float_level(&camera, Vec3::from_array(float), point);
                    let level = c.level.expect("a shade") as f64;
                    assert!((level - float).abs() <= 1.0, "{level} {float}");
                }
            }
        }
        assert!(shaded > 3_000, "{shaded} corners shaded");
        // (Measured: views within 0.44 e, normals within 1.75 units.)
        assert!(
            worst_view > 0.0 && worst_normal > 0.0,
            "{worst_view} {worst_normal}"
        );
    }

    /// Every octahedral code a bake may write: its unit normal in `2^-14` within 2.4 units of
    /// the exact one in every coordinate.
    #[test]
    fn every_code_gives_its_unit_normal() {
        let (mut worst, mut codes) = (0.0f64, 0);
        for a in -127..=127i8 {
            for b in -127..=127i8 {
                let n = crate::tessellator::quantize::octahedral_point([a, b]).unwrap();
                let unit = unit_normal_of_code([a, b]).expect("a bake's code");
                let length = n.iter().map(|&c| (c * c) as f64).sum::<f64>().sqrt();
                for (u, c) in unit.iter().zip(n) {
                    let off = (*u as f64 - 16384.0 * c as f64 / length).abs();
                    worst = worst.max(off);
                    assert!(off <= 2.4, "{a} {b}: {unit:?} {n:?}");
                }
                codes += 1;
            }
        }
        assert_eq!(codes, 255 * 255);
        // (Measured: within 1.10 units.)
        assert!(worst > 0.5, "{worst}");
    }

    /// The readings from bits that parts without an FPU take for a projected corner give what
    /// the float functions give (a host runs the float ones), for every input they accept:
    /// positions on the subpixel grid, integer depth keys, quantised shades of both paths.
    #[test]
    fn readings_from_bits_are_the_float_ones() {
        use super::super::project::{depth_to_u16, shade_from_u8, shade_to_u8};
        use super::super::raster::snap_checked;
        let mut rng = TestRng::new(0x5a_a9);
        let (mut positions, mut keys) = (0, 0);
        for k in 0..400_000 {
            // Random bits, and values on the subpixel grid and integers.
            let x = match k % 3 {
                0 => f32::from_bits(rng.next_u32()),
                1 => rng.signed(1 << 24) as f32 / 16.0,
                _ => rng.signed(70_000) as f32,
            };
            if let Some(s) = exact_fixed(x, 4) {
                positions += 1;
                assert_eq!(snap_checked(x), Some(s), "{x}");
            }
            if let Some(d) = exact_fixed(x, 0) {
                keys += 1;
                assert_eq!(depth_to_u16(x), d.clamp(0, 65535) as u16, "{x}");
            }
        }
        assert!(positions > 150_000 && keys > 100_000, "{positions} {keys}");
        for level in 0..=255u8 {
            for s in [shade_from_u8(level), shade_of_level(level)] {
                assert_eq!(level_of_shade(s), shade_to_u8(s), "{level}");
            }
        }
    }

    /// The exact reading from bits is the floor's where it is exact and below `2^22`, and
    /// `None` everywhere else.
    #[test]
    fn exact_readings_are_the_floors_read_back() {
        let mut rng = TestRng::new(0xe8ac_7001);
        let mut found = 0;
        for k in 0..1_000_000u32 {
            let x = match k % 4 {
                0 => f32::from_bits(rng.next_u32()),
                1 => rng.signed(1 << 24) as f32 / 16.0,
                2 => rng.signed(1 << 23) as f32,
                _ => f32::from_bits(rng.next_u32() & 0x807f_ffff | (100 + k % 60) << 23),
            };
            for e in [-3, 0, 4, 9] {
                let by_floor = fixed_of(x, e).filter(|&v| {
                    x.to_bits() << 1 == 0
                        || v.unsigned_abs() < 1 << 22 && f32_of(v, e).to_bits() == x.to_bits()
                });
                assert_eq!(exact_fixed(x, e), by_floor, "{x} 2^{e}");
                found += u32::from(by_floor.is_some());
            }
        }
        assert!(found > 200_000, "{found}");
    }

    #[test]
    fn fixed_of_is_the_floor() {
        let mut rng = TestRng::new(7);
        for _ in 0..200_000 {
            let x = f32::from_bits(rng.next_u32());
            let e = (rng.next_u32() % 60) as i32 - 30;
            let exact = (x as f64) * 2f64.powi(e);
            match fixed_of(x, e) {
                Some(v) => {
                    assert!(exact.abs() < (1u64 << 30) as f64, "{x} {e}");
                    assert_eq!(v as f64, exact.floor(), "{x} 2^{e}");
                }
                None => assert!(
                    !x.is_finite() || exact.abs() >= (1u64 << 29) as f64,
                    "{x} {e}"
                ),
            }
        }
        assert_eq!(fixed_of(-0.0, 3), Some(0));
        assert_eq!(fixed_of(-1.5, 0), Some(-2));
        assert_eq!(fixed_of(f32::MIN_POSITIVE / 4.0, 0), Some(0));
        assert_eq!(fixed_of(-f32::MIN_POSITIVE / 4.0, 0), Some(-1));
    }

    #[test]
    fn f32_of_is_exact_below_2_pow_24() {
        let mut rng = TestRng::new(11);
        for _ in 0..200_000 {
            let v = (rng.next_u32() as i32) >> (rng.next_u32() % 32);
            let e = (rng.next_u32() % 80) as i32 - 40;
            let got = f32_of(v, e) as f64;
            let exact = v as f64 * 2f64.powi(-e);
            if v.unsigned_abs() < 1 << 24 {
                assert_eq!(got, exact, "{v} 2^-{e}");
            } else {
                assert!(
                    got.abs() <= exact.abs() && got.abs() > exact.abs() * (1.0 - 2f64.powi(-23))
                );
            }
            if v.unsigned_abs() < 1 << 24 {
                assert_eq!(fixed_of(f32_of(v, e), e), Some(v), "round trip {v} 2^-{e}");
            }
        }
    }

    #[test]
    fn shade_levels_round_trip_as_the_float_path_rounds() {
        for level in 0..=255u8 {
            let s = shade_of_level(level);
            assert!((s as f64 - level as f64 / 255.0).abs() <= 1e-7, "{level}");
            assert_eq!(super::super::project::shade_to_u8(s), level);
            assert_eq!(level_of_shade(s), level);
        }
        let mut rng = TestRng::new(3);
        for _ in 0..200_000 {
            let s = f32::from_bits(rng.next_u32() % 0x3f90_0000);
            let exact = ((s as f64).clamp(0.0, 1.0) * 255.0 + 0.5).floor() as u8;
            assert_eq!(level_of_shade(s), exact, "{s}");
        }
        assert_eq!(level_of_shade(f32::NAN), 0);
        assert_eq!(level_of_shade(-0.3), 0);
        assert_eq!(level_of_shade(7.0), 255);
    }
}
