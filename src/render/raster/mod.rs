//! Triangle set-up and scan conversion from fixed-point edge functions.
//!
//! Vertices snap to 1/16 pixel. A pixel belongs to a triangle when its centre is inside, with
//! ties on an edge broken by the top-left rule: as if the centre were nudged right by `ε` and
//! down by `ε²`. That perturbation is the same for every triangle, so triangles that share
//! edges (and vertices) cover each pixel of their union exactly once. Every inside test is exact
//! integer arithmetic; the attributes (depth, shade) are planes through the first corner, set
//! up once per triangle in `f32` ([`Arithmetic::Float`]) or in integers ([`Arithmetic::Integer`]) and
//! put in fixed point for the scan (`scan`). Triangles
//! with a corner beyond 512 pixels of the origin (only with feature `large-viewports`) go span
//! by span in 64-bit edge arithmetic instead ([`Triangle::span`]), with `f32` attributes at
//! each row's first pixel.

use core::ops::Range;

mod edge;
mod scan;

pub(super) use edge::faces_away;
pub(super) use scan::{BandScan, Scan};

use super::project::{depth_from_u16, depth_to_u16, quantized_level, shade_from_u8};
use super::walk::FixedRamp;
use edge::{
    ceil_div, counter_clockwise, edge_set_up, inside_columns, wide_columns, wire_limit, wire_ramp,
    EdgeInt, Edges, NARROW_LIMIT,
};

/// Subpixel steps per pixel.
pub(crate) const SUBPIXELS: i64 = 16;
pub(crate) const HALF: i64 = SUBPIXELS / 2;

/// A corner after projection: pixel position and the attributes interpolated across the
/// triangle.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct ScreenVertex {
    /// Pixel coordinates (x right, y down).
    pub xy: [f32; 2],
    /// Depth key: larger is nearer.
    pub depth: f32,
    /// Light intensity in `[0, 1]`.
    pub shade: f32,
}

/// A linear function of the pixel column along one row: `at(x) = start + step * (x - x0)`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Ramp {
    pub start: f32,
    pub step: f32,
}

impl Ramp {
    /// Value at `i` pixels from the span's first.
    #[cfg(test)]
    pub fn at(&self, i: u32) -> f32 {
        self.start + self.step * i as f32
    }
}

/// One row's pixels of a triangle: columns `x0..x1` and the attributes along them.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Span {
    pub x0: i32,
    pub x1: i32,
    pub depth: Ramp,
    pub shade: Ramp,
    /// For each edge, a value below 0 exactly at the pixels on its wireframe line (the scan's
    /// test, [`edge::wire_ramp`]); `i32::MAX` and no step for the edges not drawn.
    pub wire: [FixedRamp; 3],
}

/// A linear function of the position: its value at a triangle's first corner and its change
/// per subpixel step right and down.
#[derive(Clone, Copy, Debug, Default)]
struct Plane {
    at: f32,
    dx: f32,
    dy: f32,
}

impl Plane {
    /// The plane through values `v` at a triangle's corners, whose edges (corner to corner,
    /// opposite each corner) are `edges` in subpixels and whose doubled area is
    /// `1 / inv_area`.
    #[inline(always)]
    fn through(v: [f32; 3], edges: &[[f32; 2]; 3], inv_area: f32) -> Plane {
        let (d1, d2) = (v[1] - v[0], v[2] - v[0]);
        Plane {
            at: v[0],
            dx: -(d1 * edges[1][1] + d2 * edges[2][1]) * inv_area,
            dy: (d1 * edges[1][0] + d2 * edges[2][0]) * inv_area,
        }
    }

    /// Its value `rx`, `ry` subpixels right of and below the first corner, and its change per
    /// pixel along the row.
    #[inline]
    fn ramp(&self, rx: f32, ry: f32) -> Ramp {
        Ramp {
            start: self.at + self.dx * rx + self.dy * ry,
            step: SUBPIXELS as f32 * self.dx,
        }
    }
}

/// A triangle ready for scan conversion.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Triangle {
    /// Corners in subpixels (within [`COORDINATE_LIMIT`] pixels, so `i32` holds them and
    /// their differences).
    x: [i32; 3],
    y: [i32; 3],
    edges: Edges,
    /// `dx[i]`: the change of `x` along the edge opposite corner `i`.
    dx: [i32; 3],
    depth: Plane,
    shade: Plane,
    /// `1 / (SUBPIXELS * |edge|)` for wireframe edges, 0 for the others.
    inv_length: [f32; 3],
    /// Each edge's top-left bias.
    bias: [i32; 3],
    rows: [i32; 2],
}

fn snap(v: f32) -> i32 {
    // `floor` without the library call: `x` is within `±2^28`, so truncation is exact in
    // `i32` and one comparison corrects it for negative non-integers.
    let x = v * SUBPIXELS as f32 + 0.5;
    let t = x as i32;
    t - ((t as f32) > x) as i32
}

/// `v` snapped to 1/16 pixel, when it is a finite pixel position within [`COORDINATE_LIMIT`]
/// (the comparison is false for NaN).
pub(crate) fn snap_checked(v: f32) -> Option<i32> {
    // Where `f32` is software, a position on the subpixel grid already (as the integer
    // path's are) is read from its bits: the same value.
    if !crate::math::HARD_FLOAT {
        if let Some(s) = super::fixed::exact_fixed(v, 4) {
            return Some(s);
        }
    }
    (v.abs() <= COORDINATE_LIMIT).then(|| snap(v))
}

/// A triangle's corners snapped to 1/16 pixel, with what is interpolated across it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Snapped {
    /// Corners in subpixels, within [`COORDINATE_LIMIT`] pixels.
    pub x: [i32; 3],
    pub y: [i32; 3],
    /// Depth keys at the corners.
    pub depth: [u16; 3],
    /// Shade levels (0 to 255) at the corners.
    pub shade: [u8; 3],
    /// `wire[i]`: the edge opposite corner `i` is drawn for the wireframe.
    pub wire: [bool; 3],
}

impl Snapped {
    /// Corners `v` snapped, their depths and shades as the integer key and level they were
    /// quantised to (see `project`); `None` when one is not a finite pixel position within
    /// [`COORDINATE_LIMIT`].
    pub fn new(v: [ScreenVertex; 3], wire: [bool; 3]) -> Option<Snapped> {
        let [x0, x1, x2] = v.map(|p| snap_checked(p.xy[0]));
        let [y0, y1, y2] = v.map(|p| snap_checked(p.xy[1]));
        Some(Snapped {
            x: [x0?, x1?, x2?],
            y: [y0?, y1?, y2?],
            depth: v.map(|p| depth_to_u16(p.depth)),
            shade: v.map(|p| quantized_level(p.shade)),
            wire,
        })
    }

    /// The triangle set up for spans ([`Triangle::from_snapped`]).
    pub fn triangle(&self) -> Option<Triangle> {
        let (depth, shade) = (
            self.depth.map(depth_from_u16),
            self.shade.map(shade_from_u8),
        );
        Triangle::from_snapped(self.x, self.y, depth, shade, self.wire)
    }
}

/// Largest pixel coordinate, in magnitude, a triangle may have: clipping keeps every corner
/// within twice the viewport (at most [`MAX_VIEWPORT`](super::MAX_VIEWPORT) pixels), and up
/// to here the edge functions' products stay far inside `i64`. Only non-finite or
/// astronomically large input gets past the clip with more.
const COORDINATE_LIMIT: f32 = (1u32 << 24) as f32;

impl Triangle {
    /// Sets up a triangle; `None` when it has no area after snapping, or when a corner is not
    /// a finite pixel position within [`COORDINATE_LIMIT`]. `wire[i]` marks the edge opposite
    /// corner `i` for the wireframe. (The renderer snaps corners with [`Snapped::new`].)
    #[cfg(test)]
    pub fn new(v: [ScreenVertex; 3], wire: [bool; 3]) -> Option<Triangle> {
        Snapped::new(v, wire)?.triangle()
    }

    /// Sets up a triangle from corners already snapped to 1/16 pixel (`x`, `y` in subpixels,
    /// within [`COORDINATE_LIMIT`] pixels) with their depth keys and shades; `None` when it
    /// has no area.
    pub fn from_snapped(
        x: [i32; 3],
        y: [i32; 3],
        depth: [f32; 3],
        shade: [f32; 3],
        wire: [bool; 3],
    ) -> Option<Triangle> {
        let narrow = NARROW_LIMIT as i32;
        if x.iter().chain(&y).all(|&v| -narrow <= v && v <= narrow) {
            Triangle::set_up(x, y, depth, shade, wire)
        } else if cfg!(feature = "large-viewports") {
            Triangle::set_up_wide(x.map(i64::from), y.map(i64::from), depth, shade, wire)
        } else {
            // (Never for the viewports a build without the feature draws: see `edge`.)
            None
        }
    }

    /// [`set_up`](Self::set_up) in 64 bits, out of line (see [`wide_columns`]).
    #[inline(never)]
    fn set_up_wide(
        x: [i64; 3],
        y: [i64; 3],
        depth: [f32; 3],
        shade: [f32; 3],
        wire: [bool; 3],
    ) -> Option<Triangle> {
        Triangle::set_up(x, y, depth, shade, wire)
    }

    /// [`from_snapped`](Self::from_snapped) in the integer type `I`, which holds every edge
    /// quantity of these corners.
    fn set_up<I: EdgeInt>(
        mut x: [I; 3],
        mut y: [I; 3],
        mut depth: [f32; 3],
        mut shade: [f32; 3],
        mut wire: [bool; 3],
    ) -> Option<Triangle> {
        let zero = I::from(0);
        let area = counter_clockwise(&mut x, &mut y, &mut depth, &mut shade, &mut wire);
        if area == zero {
            return None;
        }
        let (sub, half) = (I::from(SUBPIXELS as i32), I::from(HALF as i32));
        let (mut k, mut m0, mut dxs) = ([zero; 3], [zero; 3], [0i32; 3]);
        let (mut inv_length, mut bias) = ([0f32; 3], [0i32; 3]);
        let mut edges = [[0f32; 2]; 3];
        for i in 0..3 {
            let e = edge_set_up(&x, &y, i);
            // Corners are within `COORDINATE_LIMIT` pixels: `|dx| < 2^30`.
            let (dx32, dy32) = (e.dx.wide() as i32, e.dy.wide() as i32);
            edges[i] = [dx32 as f32, dy32 as f32];
            (k[i], m0[i], dxs[i], bias[i]) = (e.k, e.m0, dx32, e.bias);
            if wire[i] {
                let length2 = e.dx * e.dx + e.dy * e.dy;
                inv_length[i] = inv_sqrt(length2.to_f32()) * (1.0 / SUBPIXELS as f32);
            }
        }
        // An attribute is `v_0 + Σ_{i=1,2} (v_i - v_0) E_i(p) / area` (the barycentric
        // weights sum to 1), and `E_i` changes by `-dy_i` per step right and `dx_i` per step
        // down; through the differences, an attribute equal at the corners stays exactly
        // constant.
        let inv_area = 1.0 / area.to_f32();
        let plane = |v: [f32; 3]| Plane::through(v, &edges, inv_area);
        let top = *y.iter().min()?;
        let bottom = *y.iter().max()?;
        let first = ceil_div(top - half, sub).wide();
        let last = (bottom - half).floor_div(sub).wide();
        let clamp = |r: i64| r.clamp(i32::MIN as i64, i32::MAX as i64) as i32;
        Some(Triangle {
            x: x.map(|v| v.wide() as i32),
            y: y.map(|v| v.wide() as i32),
            edges: I::edges(k, m0),
            dx: dxs,
            depth: plane(depth),
            shade: plane(shade),
            inv_length,
            bias,
            rows: [clamp(first), clamp(last)],
        })
    }

    /// First and last pixel row whose centres the triangle may cover.
    pub fn rows(&self) -> [i32; 2] {
        self.rows
    }

    /// The pixels of row `row` inside the triangle, clipped to columns `columns`, with
    /// wireframe lines `half_width` wide (`None`: none).
    pub fn span(&self, row: i32, columns: Range<i32>, half_width: Option<f32>) -> Option<Span> {
        // Rows off the triangle's have no pixel; on its rows `|yc|` stays within the bounds
        // [`NARROW_LIMIT`] assumes.
        if row < self.rows[0] || row > self.rows[1] || columns.is_empty() {
            return None;
        }
        let yc = row * SUBPIXELS as i32 + HALF as i32;
        let (lo, hi) = (columns.start, columns.end - 1);
        let (lo, hi, wire) = match &self.edges {
            Edges::Narrow { k, m0 } => {
                let (lo, hi) = inside_columns(k, m0, &self.dx, yc, lo, hi)?;
                (lo, hi, self.wire(k, m0, yc, lo, hi, half_width))
            }
            Edges::Wide { k, m0 } if cfg!(feature = "large-viewports") => {
                let (lo, hi) = wide_columns(k, m0, &self.dx, yc, lo, hi)?;
                let wire = self.wire(k, m0, i64::from(yc), lo, hi, half_width);
                (lo, hi, wire)
            }
            Edges::Wide { .. } => return None,
        };
        let xc = lo * SUBPIXELS as i32 + HALF as i32;
        let (rx, ry) = ((xc - self.x[0]) as f32, (yc - self.y[0]) as f32);
        Some(Span {
            x0: lo,
            x1: hi + 1,
            depth: self.depth.ramp(rx, ry),
            shade: self.shade.ramp(rx, ry),
            wire,
        })
    }

    /// The wireframe tests of the span of columns `lo..=hi` of the row through subpixel
    /// height `yc` (inside the triangle): [`edge::wire_ramp`] from `E_i - bias_i` at `lo`.
    fn wire<I: EdgeInt>(
        &self,
        k: &[I; 3],
        m0: &[I; 3],
        yc: I,
        lo: i32,
        hi: i32,
        half_width: Option<f32>,
    ) -> [FixedRamp; 3] {
        let none = FixedRamp {
            at: i32::MAX,
            step: 0,
        };
        let Some(w) = half_width else {
            return [none; 3];
        };
        core::array::from_fn(|i| {
            if self.inv_length[i] == 0.0 {
                return none;
            }
            // `E_i - bias_i = k px - m0 + dx yc` at column `px` (see `EdgeSetUp`).
            let e = k[i] * I::from(lo) - m0[i] + I::from(self.dx[i]) * yc;
            let limit = wire_limit(w, self.inv_length[i], self.bias[i]);
            wire_ramp(e, k[i], limit, hi - lo + 1)
        })
    }
}

/// `1 / sqrt(x)` for a positive, finite `x`, to within 1.2e-7 relative (measured over 1 to 2^40
/// by the test below): a first guess from the bits of `x` (the exponent halved and negated,
/// with Lomont's constant `0x5f37_5a86` for the mantissa: within 3.5%), then three Newton steps,
/// each about squaring the error. Plain `f32` operations in a fixed order, so every target
/// computes the same bits. A wireframe edge's distance scale needs no more; `libm`'s correctly
/// rounded `sqrtf` and a division cost about 65 instructions on a Cortex-M4F, whose
/// square-root instruction the crate cannot reach without `asm!`.
fn inv_sqrt(x: f32) -> f32 {
    let mut y = f32::from_bits(0x5f37_5a86 - (x.to_bits() >> 1));
    for _ in 0..3 {
        y *= 1.5 - 0.5 * x * y * y;
    }
    y
}

#[cfg(test)]
mod tests {
    use super::*;

    fn corner(x: f32, y: f32) -> ScreenVertex {
        ScreenVertex {
            xy: [x, y],
            depth: 1.0,
            shade: 1.0,
        }
    }

    fn covered(t: &Triangle, width: i32, hits: &mut [u8], rows: i32) {
        for row in t.rows()[0].max(0)..=t.rows()[1].min(rows - 1) {
            if let Some(s) = t.span(row, 0..width, None) {
                for x in s.x0..s.x1 {
                    hits[(row * width + x) as usize] += 1;
                }
            }
        }
    }

    #[test]
    fn a_square_split_either_way_covers_each_pixel_once() {
        // Corners on pixel centres: the diagonal and the sides pass through centres.
        let (a, b, c, d) = (
            corner(0.5, 0.5),
            corner(8.5, 0.5),
            corner(8.5, 8.5),
            corner(0.5, 8.5),
        );
        for tris in [[[a, b, c], [a, c, d]], [[a, b, d], [b, c, d]]] {
            let mut hits = [0u8; 100];
            for t in tris {
                covered(&Triangle::new(t, [false; 3]).unwrap(), 10, &mut hits, 10);
            }
            for y in 0..10 {
                for x in 0..10 {
                    // Top-left: the top row and left column of centres are in, the others not.
                    let want = (x < 8 && y < 8) as u8;
                    assert_eq!(hits[y * 10 + x], want, "pixel {x},{y}");
                }
            }
        }
    }

    #[test]
    fn a_fan_around_a_pixel_centre_covers_it_once() {
        let centre = corner(4.5, 4.5);
        let ring = [
            corner(0.5, 0.5),
            corner(4.5, 0.2),
            corner(8.5, 0.5),
            corner(8.7, 4.5),
            corner(8.5, 8.5),
            corner(4.5, 8.5),
            corner(0.5, 8.5),
            corner(0.5, 4.5),
        ];
        let mut hits = [0u8; 100];
        for k in 0..ring.len() {
            let t = [centre, ring[k], ring[(k + 1) % ring.len()]];
            covered(&Triangle::new(t, [false; 3]).unwrap(), 10, &mut hits, 10);
        }
        assert!(hits.iter().all(|&h| h <= 1));
        assert_eq!(hits[4 * 10 + 4], 1);
    }

    #[test]
    #[cfg(feature = "large-viewports")]
    fn narrow_and_wide_edges_give_the_same_spans() {
        // Corners up to the narrow limit, with wireframe edges, through both arithmetics.
        let mut rng = crate::test_rng::TestRng::new(0x2545_f491_4f6c_dd1d);
        let mut next = |range: i64| rng.signed(range);
        let mut spans = 0;
        for n in 0..400 {
            // Mostly small triangles, some reaching the limit.
            let (reach, size) = if n % 4 == 0 {
                (NARROW_LIMIT, NARROW_LIMIT)
            } else {
                (800, 60)
            };
            let (cx, cy) = (next(reach - size), next(reach - size));
            let x: [i64; 3] = core::array::from_fn(|_| cx + next(size));
            let y: [i64; 3] = core::array::from_fn(|_| cy + next(size));
            let (depth, shade, wire) = ([0.3, 0.9, 0.5], [1.0, 0.2, 0.6], [true, n % 2 == 0, true]);
            let narrow =
                Triangle::set_up(x.map(|v| v as i32), y.map(|v| v as i32), depth, shade, wire);
            let wide = Triangle::set_up(x, y, depth, shade, wire);
            let (Some(narrow), Some(wide)) = (narrow, wide) else {
                assert!(narrow.is_none() && wide.is_none());
                continue;
            };
            assert!(matches!(narrow.edges, Edges::Narrow { .. }));
            assert!(matches!(wide.edges, Edges::Wide { .. }));
            assert_eq!(narrow.rows(), wide.rows());
            let [first, last] = wide.rows();
            for row in first - 2..=last + 2 {
                for columns in [-600..600, -3..4, 0..240, 5..5] {
                    let s = wide.span(row, columns.clone(), Some(0.6));
                    assert_eq!(narrow.span(row, columns, Some(0.6)), s);
                    spans += s.is_some() as u32;
                }
            }
        }
        assert!(spans > 1000, "{spans}");
    }

    #[test]
    fn snapping_is_floor_of_sixteen_times_plus_a_half() {
        let limit = COORDINATE_LIMIT;
        let mut values = [
            0.0, -0.0, 0.03125, -0.03125, 0.0312, -0.0313, 1.0, -1.0, 2.46875, -2.46875, 239.97,
            -479.99, 1e-30, -1e-30, limit, -limit, 1234567.8, -1234567.8,
        ];
        // Then the same values with the other sign and a little smaller.
        for _ in 0..2 {
            for &v in &values {
                let expect = libm::floorf(v * SUBPIXELS as f32 + 0.5) as i32;
                assert_eq!(snap(v), expect, "{v}");
                assert_eq!(snap_checked(v), Some(expect), "{v}");
            }
            for v in &mut values {
                *v = -*v * 0.999_7;
            }
        }
        // And a sweep in steps that are not dyadic.
        let mut v = -40.0f32;
        while v < 40.0 {
            assert_eq!(snap(v), libm::floorf(v * 16.0 + 0.5) as i32, "{v}");
            v += 0.007_812_5 * 0.37;
        }
        assert_eq!(snap_checked(f32::NAN), None);
        assert_eq!(snap_checked(2.0 * limit), None);
    }

    #[test]
    fn degenerate_triangles_are_dropped() {
        let t = [corner(0.0, 0.0), corner(5.0, 5.0), corner(10.0, 10.0)];
        assert!(Triangle::new(t, [false; 3]).is_none());
    }

    #[test]
    fn corners_off_the_fixed_point_range_are_dropped() {
        // What only non-finite or astronomically large input brings past the clip (found by
        // the `render` fuzz target: the edge function overflowed).
        for bad in [f32::INFINITY, f32::NEG_INFINITY, f32::NAN, 3.0e7, -1.0e30] {
            let t = [corner(0.5, 0.5), corner(bad, 0.5), corner(0.5, 8.5)];
            assert!(Triangle::new(t, [true; 3]).is_none(), "{bad}");
        }
        // The far end of the range takes 64-bit edge functions, which only the feature
        // `large-viewports` builds in.
        let far = corner(COORDINATE_LIMIT, 0.5);
        let set_up = Triangle::new([corner(0.5, 0.5), far, corner(0.5, 8.5)], [true; 3]);
        assert_eq!(set_up.is_some(), cfg!(feature = "large-viewports"));
    }

    #[test]
    fn attributes_interpolate_at_pixel_centres() {
        let mut t = [corner(0.5, 0.5), corner(10.5, 0.5), corner(0.5, 10.5)];
        t[1].depth = 11.0;
        let tri = Triangle::new(t, [true; 3]).unwrap();
        let s = tri.span(0, 0..20, Some(0.25)).unwrap();
        assert_eq!((s.x0, s.x1), (0, 10));
        assert!((s.depth.at(0) - 1.0).abs() < 1e-5);
        assert!((s.depth.at(5) - 6.0).abs() < 1e-5);
        // Row 0 lies on the top edge: every pixel is on its line.
        let mut walk = crate::render::walk::SpanWalk::new(&s);
        for _ in 0..10 {
            assert!(walk.on_wire());
            walk.step::<true>();
        }
    }

    /// The wireframe's `1 / sqrt` is within 2.5e-7 of the exact value (1.2e-7 measured) over
    /// the squared edge lengths a viewport makes (1 to 2^40 in subpixels), checked in `f64`.
    #[test]
    fn inverse_square_root_is_close() {
        let mut worst = 0.0f64;
        let mut x = 1.0f32;
        while x < 1.1e12 {
            for k in 0..64 {
                let v = x * (1.0 + k as f32 / 64.0);
                let exact = 1.0 / libm::sqrt(v as f64);
                let err = ((inv_sqrt(v) as f64 - exact) / exact).abs();
                worst = worst.max(err);
            }
            x *= 2.0;
        }
        assert!(worst < 2.5e-7, "{worst}");
        assert!(worst > 0.0);
    }
}
