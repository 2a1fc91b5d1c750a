//! Triangles scanned row by row over their bounding box, in integers and fixed point.
//!
//! Most triangles of a tessellation at a pixel tolerance cover a few pixels over two or three
//! rows, so what a triangle costs before its first pixel counts: a band sets a triangle up in
//! one pass from its snapped corners ([`Snapped::band_scan`]), to integer edge values and
//! fixed-point planes, and leaves it there when it meets no row of the band. A scan keeps each
//! edge's value `E_i - bias_i` at the row's first column of the box, stepped by a constant per
//! row, and solves the exact integer inequality of the module above (a pixel centre is inside
//! edge `i` when `E_i - bias_i >= 0`) for the row's columns, one division per edge. (Testing
//! every pixel of the box instead, three additions and a sign test each, is slower: most of a
//! box is outside its triangle.) Where a division is a library call (ARMv6-M), a box at most
//! [`STEPPED_WIDTH`] pixels wide is solved by stepping along the row from each end instead:
//! the same pixels, for a few additions a pixel outside. Triangles with a corner beyond
//! [`NARROW_LIMIT`] take the 64-bit spans of [`Triangle`] instead (feature
//! `large-viewports`): the same inequality, so both still tile.
//!
//! # The planes in fixed point
//!
//! With [`Arithmetic::Float`], depth and shade are the `f32` planes of the module above
//! ([`Plane::through`], per subpixel from the first corner), put in fixed point once per
//! triangle and band: a depth key plus 1/2
//! with `b = 14` fractional bits, a shade level plus 1/2 with `b = 16`. The value is computed
//! in `f32` at `A`, the pixel centre nearest the first corner (within 8 subpixels of it each
//! way), and its changes per pixel right `R` and per row down `D` are rounded from 16 times
//! the plane's slopes; a pixel `(Δx, Δy)` pixels from `A` takes `A + R Δx + D Δy` in wrapping
//! `i32` arithmetic. That is exact modulo `2^32`, so a pixel's value does not depend on where
//! a scan starts (which band, which column, which way the triangle came: listed or streamed),
//! and values inside the triangle, which lie between the corners' (at most `2^16 · 2^b`), come
//! out right even where the plane wraps off it.
//!
//! Precision: `A`, `R` and `D` are rounded toward zero from `f32` values below
//! `limit = |v| + 16 (|s_x| + |s_y|)` in size (`v` the value at the corner, `s` the slopes), so
//! each is within `2^-b` of its `f32` value plus that value's own rounding (a few `2^-24` of
//! `limit`: 0.03 of a key at most for depth, whose keys are below `2^16`). A pixel inside the
//! triangle lies within its box, so its value is off the `f32` plane by at most
//! `2^-b (1 + Δx + Δy)` plus that: 0.06 of a key for a triangle across a 480-pixel box. A
//! plane steep enough that `limit` reaches `2^(31 - b)` (depth changing by 65,536 keys or
//! more per pixel, its whole range: a sliver under a pixel across) keeps as many fractional
//! bits `f` as fit below `2^31` and is shifted back to `b` modulo `2^32`, so its values inside
//! are still right to `2^-f`; one whose `limit` reaches `2^31` itself (`2^27` keys per
//! subpixel: a sliver of a few square subpixels) is taken flat, at its first corner's value.
//! The tests below check the scan against the spans and a steep sliver against its plane in
//! `f64`.
//!
//! # The planes in integers ([`Arithmetic::Integer`])
//!
//! Where `f32` is software, the same fixed-point planes come from integers alone. The corners'
//! values `v_i` are integers (depth keys, shade levels), so the plane's change per subpixel is
//! `n_x / a` right and `n_y / a` down, with `a` twice the area and
//! `n_x = -(d_1 dy_1 + d_2 dy_2)`, `n_y = d_1 dx_1 + d_2 dx_2` (`d_i = v_i - v_0`, the edges as
//! in [`Plane::through`]): integers below `2^31` (`|d_i| < 2^16`, edges within
//! `2^14` subpixels). Per pixel, in fixed point: `R = floor(n_x 2^(b+4) / a)` and likewise `D`,
//! exact, in 32-bit quotients (`Divisor::floor_shifted`; on ARMv6-M each a product by the reciprocal of
//! `a`, found once for the triangle's four slopes, and a correction). At the anchor,
//! `(o_x, o_y)` subpixels from the first corner (each in `-7..=8`),
//! `A = v_0 2^b + 2^(b-1) + floor((R o_x + D o_y) / 16)`.
//!
//! Precision: `R` and `D` are below their exact values by less than 1, so
//! `(R o_x + D o_y) / 16` is off the exact change to the anchor by less than `(|o_x| + |o_y|) /
//! 16 <= 1`, and the floor takes less than 1 more: `A` is within 2 of its exact value. A pixel
//! `(Δx, Δy)` pixels from the anchor takes `A + R Δx + D Δy`, within `2 + |Δx| + |Δy|` of the
//! exact plane (a test checks this against the plane in `f64`, and finds it reached to 1%),
//! whatever the plane's steepness: the sums are taken modulo `2^32` (`R`, `D` may be up to
//! `2^49`), exact there, and the values inside the triangle fit. A depth key is then within
//! `(2 + 480 + 480) 2^-14 = 0.06` of the plane's across a 480-pixel box, as above.
//!
//! A wireframe edge's test is on the integer edge function too: the pixel is on the line when
//! `E_i < half_width * 16 |edge_i|`, the distance in pixels times the edge's scale.

use core::ops::Range;

use super::edge::{
    ceil_div, counter_clockwise, edge_set_up, wire_limit, wire_limit_from_integers, EdgeSetUp,
    NARROW_LIMIT,
};
#[cfg(doc)]
use super::Triangle;
use super::{inv_sqrt, Plane, Snapped, HALF, SUBPIXELS};
use crate::math::{Divisor, HARD_DIVIDE};
use crate::render::project::{depth_from_u16, shade_from_u8};
use crate::render::walk::{FixedRamp, SpanWalk, DEPTH_BITS, LEVEL_BITS};
use crate::Arithmetic;

/// A plane in fixed point: its value at the scan's first pixel and its change per pixel
/// right and per row down.
#[derive(Clone, Copy, Debug, Default)]
struct FixedPlane {
    at: i32,
    right: i32,
    down: i32,
}

impl FixedPlane {
    /// The plane through the integers `v` at a triangle's corners (depth keys or shade
    /// levels) plus 1/2, times `2^bits`, at the centre of pixel `first`: the corners' edges
    /// (corner to corner, opposite each corner) are `edges` in subpixels, twice the area
    /// `area > 0`, the first corner `from` (see the module docs for its precision).
    #[inline(never)]
    fn through(
        v: [i32; 3],
        edges: &[[i32; 2]; 3],
        area: Divisor,
        bits: u32,
        from: [i32; 2],
        first: [i32; 2],
    ) -> FixedPlane {
        let (d1, d2) = (v[1] - v[0], v[2] - v[0]);
        let e = edges;
        // `area` times the change per subpixel right and down, in 32 bits: each product is
        // below `2^30` in size (corner values below `2^16`, edges within `2^14` subpixels),
        // each sum below `2^31`.
        let nx = -(d1 * e[1][1] + d2 * e[2][1]);
        let ny = d1 * e[1][0] + d2 * e[2][0];
        // The change per pixel in fixed point, rounded down (below `2^49`).
        let shift = bits + SUBPIXELS.trailing_zeros();
        let (right, down) = (area.floor_shifted(nx, shift), area.floor_shifted(ny, shift));
        // The pixel whose centre is nearest the corner, `(ox, oy)` subpixels from it (each
        // in `-7..=8`), and the plane there. (`>> 4` is `div_euclid(16)`.)
        let shift_sub = SUBPIXELS.trailing_zeros();
        let anchor = from.map(|c| c >> shift_sub);
        let [ox, oy] = [0, 1].map(|i| anchor[i] * SUBPIXELS as i32 + HALF as i32 - from[i]);
        // `⌊(R o_x + D o_y) / 16⌋` modulo `2^32`, in 32 bits: with `R = 16 R₁ + R₀` (`R₀` in
        // `0..16`), likewise `D`, it is `R₁ o_x + D₁ o_y + ⌊(R₀ o_x + D₀ o_y) / 16⌋`, whose
        // first two products are needed modulo `2^32` alone. (The 64-bit products were
        // library calls on ARMv6-M.)
        let high_low = |s: i64| ((s >> shift_sub) as i32, (s & (SUBPIXELS - 1)) as i32);
        let ((r1, r0), (d1, d0)) = (high_low(right), high_low(down));
        let offset = r1
            .wrapping_mul(ox)
            .wrapping_add(d1.wrapping_mul(oy))
            .wrapping_add((r0 * ox + d0 * oy) >> shift_sub);
        // Modulo `2^32` from here on (the corner's value in 32 bits: its bits past 32 go).
        let (right, down) = (right as i32, down as i32);
        let at = (v[0] << bits)
            .wrapping_add(1 << (bits - 1))
            .wrapping_add(offset)
            .wrapping_add(right.wrapping_mul(first[0].wrapping_sub(anchor[0])))
            .wrapping_add(down.wrapping_mul(first[1].wrapping_sub(anchor[1])));
        FixedPlane { at, right, down }
    }

    /// `scale` times the plane `plane` (per subpixel, through corner `from`) plus 1/2, times
    /// `2^bits`, at the centre of pixel `first` (see the module docs for its precision).
    #[inline(always)]
    fn new(plane: &Plane, scale: f32, bits: u32, from: [i32; 2], first: [i32; 2]) -> FixedPlane {
        let (sx, sy) = (scale * plane.dx, scale * plane.dy);
        let start = scale * plane.at + 0.5;
        // The plane at the anchor below and its change over a pixel are within `limit`: with
        // `fraction` fractional bits, below `2^31`.
        let limit = start.abs() + SUBPIXELS as f32 * (sx.abs() + sy.abs());
        let fits = limit < 2_147_483_648.0;
        if !fits {
            // A sliver of a few square subpixels: taken flat, at the corner's value (see the
            // module docs).
            return FixedPlane {
                at: (start * (1u32 << bits) as f32) as i32,
                right: 0,
                down: 0,
            };
        }
        let fraction = if limit < (1u32 << (31 - bits)) as f32 {
            bits
        } else {
            bits.min(crate::math::leading_zeros(limit as u32) - 1)
        };
        let fixed = f32::from_bits((127 + fraction) << 23);
        // The pixel whose centre is nearest the corner, and the plane there.
        let (sub, half) = (SUBPIXELS as i32, HALF as i32);
        // (`>> 4` is `div_euclid(16)`.)
        let anchor = from.map(|c| c >> SUBPIXELS.trailing_zeros());
        let [ox, oy] = [0, 1].map(|i| (anchor[i] * sub + half - from[i]) as f32);
        let at = ((start + sx * ox + sy * oy) * fixed) as i32;
        let step = SUBPIXELS as f32 * fixed;
        let (right, down) = ((sx * step) as i32, (sy * step) as i32);
        let at = at
            .wrapping_add(right.wrapping_mul(first[0].wrapping_sub(anchor[0])))
            .wrapping_add(down.wrapping_mul(first[1].wrapping_sub(anchor[1])));
        // Back to `bits` fractional bits, modulo `2^32`.
        let up = bits - fraction;
        FixedPlane {
            at: at.wrapping_shl(up),
            right: right.wrapping_shl(up),
            down: down.wrapping_shl(up),
        }
    }

    /// Its ramp along the row from `n` pixels right of the anchor.
    #[inline(always)]
    fn ramp(&self, n: i32) -> FixedRamp {
        FixedRamp {
            at: self.at.wrapping_add(self.right.wrapping_mul(n)),
            step: self.right,
        }
    }

    #[inline(always)]
    fn next_row(&mut self) {
        self.at = self.at.wrapping_add(self.down);
    }
}

/// Widest box whose rows [`Scan::inside`] solves by stepping along them, where a division
/// is a library call (ARMv6-M): in a box this narrow a few steps cost less than a quotient.
const STEPPED_WIDTH: i32 = 32;

/// A small triangle's scan, row by row over its bounding box's columns (within a band's).
#[derive(Clone, Copy, Debug)]
pub(in crate::render) struct Scan {
    /// The box's first column and its width in pixels.
    x0: i32,
    width: i32,
    /// `E_i - bias_i` at the current row's first column: the pixel is inside when all three
    /// are at least 0.
    edge: [i32; 3],
    /// Their change per pixel right and per row down.
    right: [i32; 3],
    down: [i32; 3],
    /// `E_i - bias_i` below which a pixel is on wireframe edge `i` (`i32::MIN`: not drawn).
    wire: [i32; 3],
    depth: FixedPlane,
    level: FixedPlane,
}

/// How a triangle meets one band ([`Snapped::band_scan`]).
#[derive(Clone, Copy, Debug)]
pub(in crate::render) enum BandScan {
    /// It covers no pixel centre of the band.
    Off,
    /// Its scan from row `top` on, over `rows` rows.
    Rows { scan: Scan, top: i32, rows: usize },
    /// A corner lies beyond [`NARROW_LIMIT`]: the 64-bit spans of [`Triangle`] draw it
    /// (with feature `large-viewports`; never for the viewports a build without it draws).
    Wide,
}

impl Snapped {
    /// How this triangle meets the band of rows `rows` and columns `columns`, with wireframe
    /// lines `half_width` wide (`None`: no wireframe): set up in one pass from its corners,
    /// to the edge values [`Triangle::from_snapped`] gives (the same integer operations) and
    /// the same planes ([`Plane::through`], shared).
    #[inline(always)]
    pub fn band_scan(
        &self,
        rows: Range<i32>,
        columns: Range<i32>,
        half_width: Option<f32>,
        arithmetic: Arithmetic,
    ) -> BandScan {
        let narrow = NARROW_LIMIT as i32;
        if !self
            .x
            .iter()
            .chain(&self.y)
            .all(|&v| -narrow <= v && v <= narrow)
        {
            return BandScan::Wide;
        }
        let (sub, half) = (SUBPIXELS as i32, HALF as i32);
        let (mut x, mut y) = (self.x, self.y);
        let top = ceil_div(y[0].min(y[1]).min(y[2]) - half, sub).max(rows.start);
        let bottom = (y[0].max(y[1]).max(y[2]) - half)
            .div_euclid(sub)
            .min(rows.end - 1);
        let first = ceil_div(x[0].min(x[1]).min(x[2]) - half, sub);
        let last = (x[0].max(x[1]).max(x[2]) - half).div_euclid(sub);
        // A band's columns may lie anywhere a viewport does: where they miss the box, or the
        // box holds no pixel centre's column (a sliver), the scan would have no pixel.
        let (x0, end) = (first.max(columns.start), last.min(columns.end - 1));
        if top > bottom || end < x0 {
            return BandScan::Off;
        }
        let (mut depth, mut shade, mut wire) = (self.depth, self.shade, self.wire);
        let area = counter_clockwise(&mut x, &mut y, &mut depth, &mut shade, &mut wire);
        if area == 0 {
            return BandScan::Off;
        }
        // The edge values below are taken modulo 2^32: only within the box do they keep the
        // bounds of `NARROW_LIMIT`, and no pixel outside it is looked at.
        let yc = top * sub + half;
        let mut edges = [[0i32; 2]; 3];
        let mut scan = Scan {
            x0,
            width: end - x0 + 1,
            edge: [0; 3],
            right: [0; 3],
            down: [0; 3],
            wire: [i32::MIN; 3],
            depth: FixedPlane::default(),
            level: FixedPlane::default(),
        };
        for i in 0..3 {
            // Edge `i` as `Triangle::set_up` sets it up, at the box's first column and row
            // `top`.
            let EdgeSetUp {
                dx,
                dy,
                bias,
                k,
                m0,
            } = edge_set_up(&x, &y, i);
            edges[i] = [dx, dy];
            scan.edge[i] = k.wrapping_mul(x0).wrapping_add(dx * yc).wrapping_sub(m0);
            scan.right[i] = k;
            scan.down[i] = dx * sub;
            if let (Some(w), true) = (half_width, wire[i]) {
                scan.wire[i] = if arithmetic == Arithmetic::Integer {
                    wire_limit_from_integers(w, dx, dy, bias)
                } else {
                    let length2 = (dx * dx + dy * dy) as f32;
                    wire_limit(w, inv_sqrt(length2) * (1.0 / SUBPIXELS as f32), bias)
                };
            }
        }
        let (corner, first) = ([x[0], y[0]], [x0, top]);
        match arithmetic {
            Arithmetic::Integer => {
                let (depth, level) = (depth.map(i32::from), shade.map(i32::from));
                // (`area > 0`: `counter_clockwise` turns the corners so.)
                let area = Divisor::new(area as u32);
                scan.depth = FixedPlane::through(depth, &edges, area, DEPTH_BITS, corner, first);
                scan.level = FixedPlane::through(level, &edges, area, LEVEL_BITS, corner, first);
            }
            Arithmetic::Float => {
                let edges = edges.map(|e| e.map(|v| v as f32));
                let inv_area = 1.0 / area as f32;
                let depth = Plane::through(depth.map(depth_from_u16), &edges, inv_area);
                scan.depth = FixedPlane::new(&depth, 1.0, DEPTH_BITS, corner, first);
                let shade = Plane::through(shade.map(shade_from_u8), &edges, inv_area);
                scan.level = FixedPlane::new(&shade, 255.0, LEVEL_BITS, corner, first);
            }
        }
        BandScan::Rows {
            scan,
            top,
            rows: (bottom - top + 1) as usize,
        }
    }
}

impl Scan {
    /// Its first column.
    pub fn first_column(&self) -> i32 {
        self.x0
    }

    /// Scans `rows` rows: each pixel inside that passes the depth test against `depth` (the
    /// band's values, `stride` a row, the scan's first pixel at `at`) is handed to `paint`
    /// with its index in the band and its shade level, or `None` on a wireframe edge (`WIRE`:
    /// whether the triangle has drawn edges); the pixels drawn. The same pixels and values as
    /// [`next_row`](Self::next_row) gives, in one loop.
    #[inline(always)]
    pub fn draw<const WIRE: bool>(
        mut self,
        rows: usize,
        depth: &mut [u16],
        at: usize,
        stride: usize,
        mut paint: impl FnMut(usize, Option<usize>),
    ) -> u32 {
        let mut drawn = 0;
        for r in 0..rows {
            let (lo, hi) = self.inside();
            let first = at + r * stride + lo as usize;
            if let Some(run) = depth.get_mut(first..first + (hi - lo).max(0) as usize) {
                let mut d = self.depth.ramp(lo).at;
                let mut l = self.level.ramp(lo).at;
                let mut e = self.edge;
                if WIRE {
                    for (v, r) in e.iter_mut().zip(&self.right) {
                        *v = v.wrapping_add(r.wrapping_mul(lo));
                    }
                }
                for (i, slot) in (first..).zip(run) {
                    let key = (d >> DEPTH_BITS).clamp(1, u16::MAX as i32) as u16;
                    if key > *slot {
                        *slot = key;
                        let wire = WIRE
                            && (e[0] < self.wire[0] || e[1] < self.wire[1] || e[2] < self.wire[2]);
                        let level = (l >> LEVEL_BITS).clamp(0, 255) as usize;
                        paint(i, (!wire).then_some(level));
                        drawn += 1;
                    }
                    if WIRE {
                        for (v, r) in e.iter_mut().zip(&self.right) {
                            *v = v.wrapping_add(*r);
                        }
                    }
                    d = d.wrapping_add(self.depth.right);
                    l = l.wrapping_add(self.level.right);
                }
            }
            self.next();
        }
        drawn
    }

    /// The current row's pixels inside the triangle, as offsets `lo..hi` from the box's first
    /// column (empty when `lo >= hi`): the exact solution of `E_i + n right_i >= 0` for `n`,
    /// edge by edge, by one division each (the edge values are below `2^30` in size, see
    /// [`NARROW_LIMIT`](super::edge::NARROW_LIMIT), so nothing here overflows).
    #[inline(always)]
    fn inside(&self) -> (i32, i32) {
        if !HARD_DIVIDE && self.width <= STEPPED_WIDTH {
            return self.inside_stepped();
        }
        self.inside_by_quotients()
    }

    /// [`inside`](Self::inside) by a quotient an edge.
    #[inline(always)]
    fn inside_by_quotients(&self) -> (i32, i32) {
        let (mut lo, mut hi) = (0, self.width);
        for (&e, &k) in self.edge.iter().zip(&self.right) {
            if k > 0 {
                // `n >= -e / k`: `n >= ceil(-e / k) = -floor(e / k)`.
                lo = lo.max(-e.div_euclid(k));
            } else if k < 0 {
                // `n <= e / -k`: `n < floor(e / -k) + 1`.
                hi = hi.min(e.div_euclid(-k) + 1);
            } else if e < 0 {
                hi = 0;
            }
        }
        (lo, hi)
    }

    /// [`inside`](Self::inside) for a box at most [`STEPPED_WIDTH`] wide, where a division
    /// is a library call: each edge's first pixel inside (or last) found by stepping along the
    /// row, two additions and a test a pixel. The same pixels: `lo` is the least `n >= 0` with
    /// every `E_i + n right_i >= 0` for the edges with `right_i > 0` (the quotients' solution,
    /// or `width` where that is beyond the box), `hi` one past the greatest for the others;
    /// where the quotients find no pixel, `lo >= hi` here too.
    #[inline(always)]
    fn inside_stepped(&self) -> (i32, i32) {
        let (mut lo, mut hi) = (0, self.width);
        for (&e, &k) in self.edge.iter().zip(&self.right) {
            if k > 0 {
                // (Every `n` below `lo` is out already: start there.)
                let mut at = e.wrapping_add(k.wrapping_mul(lo));
                while lo < hi && at < 0 {
                    at = at.wrapping_add(k);
                    lo += 1;
                }
            } else if k < 0 {
                // The last pixel inside is before `hi`: step back from there.
                let mut at = e.wrapping_add(k.wrapping_mul(hi - 1));
                while hi > lo && at < 0 {
                    at = at.wrapping_sub(k);
                    hi -= 1;
                }
            } else if e < 0 {
                hi = 0;
            }
        }
        (lo, hi)
    }

    /// On to the next row.
    #[inline(always)]
    fn next(&mut self) {
        for (v, d) in self.edge.iter_mut().zip(&self.down) {
            *v = v.wrapping_add(*d);
        }
        self.depth.next_row();
        self.level.next_row();
    }

    /// The current row's pixels inside the triangle: the first column and the walk along them,
    /// and how many there are (`None` when none); then on to the next row.
    #[inline(always)]
    pub fn next_row(&mut self) -> Option<(i32, u32, SpanWalk)> {
        let (lo, hi) = self.inside();
        let found = (lo < hi).then(|| {
            let wire = core::array::from_fn(|i| match self.wire[i] {
                i32::MIN => FixedRamp {
                    at: i32::MAX,
                    step: 0,
                },
                limit => FixedRamp {
                    at: self.edge[i]
                        .wrapping_add(self.right[i].wrapping_mul(lo))
                        .wrapping_sub(limit),
                    step: self.right[i],
                },
            });
            let walk = SpanWalk::from_ramps(self.depth.ramp(lo), self.level.ramp(lo), wire);
            (self.x0 + lo, (hi - lo) as u32, walk)
        });
        self.next();
        found
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::raster::{ScreenVertex, Triangle};

    /// The scan `band_scan` sets up over rows `rows` and columns `columns`, with lines 0.35
    /// pixels wide, and its first row; `None` when it leaves the triangle to spans.
    fn small(
        s: &Snapped,
        rows: Range<i32>,
        columns: Range<i32>,
        arithmetic: Arithmetic,
    ) -> Option<(Scan, i32)> {
        match s.band_scan(rows, columns, Some(0.35), arithmetic) {
            BandScan::Rows { scan, top, .. } => Some((scan, top)),
            _ => None,
        }
    }
    use crate::test_rng::TestRng;

    /// Random triangles, most a few pixels across, some slivers, some 200 pixels across, with
    /// depth and shade varying across them.
    fn triangles(n: usize, spread: i64) -> impl Iterator<Item = (Triangle, Snapped)> {
        let mut rng = TestRng::new(0x5ca1_ab1e_2026);
        (0..n).filter_map(move |k| {
            let size = [3, 40, 200, 3000][(k / 4) % 4];
            let (cx, cy) = (rng.signed(spread) + 200 * 16, rng.signed(spread) + 100 * 16);
            // Every fourth triangle has its corners on pixel centres, so that its edges pass
            // through centres (where the top-left rule decides).
            let centred = |v: i64| match k % 4 {
                0 => v - v.rem_euclid(16) + 8,
                _ => v,
            };
            let corner = |rng: &mut TestRng| ScreenVertex {
                xy: [
                    centred(cx + rng.signed(size)) as f32 / 16.0,
                    centred(cy + rng.signed(size)) as f32 / 16.0,
                ],
                depth: (30_000 + rng.signed(20_000)) as f32,
                shade: (128 + rng.signed(127)) as f32 / 255.0,
            };
            let v = [corner(&mut rng), corner(&mut rng), corner(&mut rng)];
            let wire = [k % 2 == 0, k % 3 == 0, true];
            let snapped = Snapped::new(v, wire)?;
            snapped.triangle().map(|t| (t, snapped))
        })
    }

    /// The scan covers exactly the pixels `span` covers, row by row (so triangles drawn either
    /// way still tile), with depth keys and shade levels within one of the spans' and the same
    /// wireframe pixels.
    #[test]
    fn a_scan_covers_what_spans_cover() {
        for arithmetic in [Arithmetic::Float, Arithmetic::Integer] {
            scan_covers_what_spans_cover(arithmetic);
        }
    }

    fn scan_covers_what_spans_cover(arithmetic: Arithmetic) {
        let (mut scanned, mut rows, mut pixels, mut far_keys, mut wire_apart) = (0, 0, 0, 0, 0);
        for (tri, snapped) in triangles(3000, 2000) {
            let [first, last] = tri.rows();
            for columns in [0..400, 195..205] {
                let Some((mut scan, top)) =
                    small(&snapped, first..last + 1, columns.clone(), arithmetic)
                else {
                    continue;
                };
                assert_eq!(top, first);
                scanned += 1;
                for row in first..=last {
                    let got = scan.next_row();
                    let want = tri.span(row, columns.clone(), Some(0.35));
                    assert_eq!(
                        got.map(|(x0, n, _)| (x0, x0 + n as i32)),
                        want.map(|s| (s.x0, s.x1)),
                        "row {row}"
                    );
                    let (Some((_, n, mut walk)), Some(span)) = (got, want) else {
                        continue;
                    };
                    rows += 1;
                    let mut float = SpanWalk::new(&span);
                    for _ in 0..n {
                        pixels += 1;
                        let apart = (walk.key() as i32 - float.key() as i32).abs();
                        assert!(apart <= 1, "row {row}: keys {apart} apart");
                        far_keys += usize::from(apart > 0);
                        assert!((walk.level() as i32 - float.level() as i32).abs() <= 1);
                        wire_apart += usize::from(walk.on_wire() != float.on_wire());
                        walk.step::<true>();
                        float.step::<true>();
                    }
                }
            }
        }
        assert!(
            scanned > 1500 && rows > 3000,
            "{scanned} scans, {rows} rows"
        );
        assert!(far_keys < pixels / 100, "{far_keys} of {pixels}");
        assert_eq!(wire_apart, 0, "of {pixels}");
    }

    /// Stepping along a row (for narrow boxes where a division is a library call) finds the
    /// pixels the quotients find, row by row, on small and large triangles and bands that
    /// cut them anywhere.
    #[test]
    fn stepping_along_rows_finds_the_quotients_pixels() {
        let (mut rows, mut inside, mut narrow) = (0, 0, 0);
        for (k, (tri, snapped)) in triangles(4000, 400).enumerate() {
            let [first, last] = tri.rows();
            let columns = [0..400, 190..206, 200..203][k % 3].clone();
            let Some((mut scan, top)) =
                small(&snapped, first..last + 1, columns, Arithmetic::Integer)
            else {
                continue;
            };
            narrow += usize::from(scan.width <= STEPPED_WIDTH);
            for row in top..=last {
                let (lo, hi) = scan.inside_by_quotients();
                let (slo, shi) = scan.inside_stepped();
                match lo < hi {
                    true => {
                        assert_eq!((slo, shi), (lo, hi), "row {row}");
                        inside += 1;
                    }
                    false => assert!(slo >= shi, "row {row}: {slo}..{shi}, not {lo}..{hi}"),
                }
                assert!(0 <= slo && shi <= scan.width.max(0));
                rows += 1;
                scan.next();
            }
        }
        assert!(
            rows > 20_000 && inside > 10_000 && narrow > 1000,
            "{rows} {inside} {narrow}"
        );
    }

    /// `draw` depth-tests and paints the pixels `next_row` walks, with the same values.
    #[test]
    fn drawing_a_scan_in_one_loop_walks_its_rows() {
        for arithmetic in [Arithmetic::Float, Arithmetic::Integer] {
            drawing_walks_rows(arithmetic);
        }
    }

    fn drawing_walks_rows(arithmetic: Arithmetic) {
        const WIDTH: usize = 64;
        const HEIGHT: usize = 48;
        let (width, height) = (WIDTH, HEIGHT);
        let mut drawn_total = 0;
        for (tri, snapped) in triangles(600, 300) {
            let [first, last] = tri.rows();
            let (top, bottom) = (first.max(80), last.min(80 + height as i32 - 1));
            let columns = 170..170 + width as i32;
            let band = 80..80 + height as i32;
            let Some((scan, first_row)) = small(&snapped, band, columns.clone(), arithmetic) else {
                continue;
            };
            assert_eq!(first_row, top);
            // A band with some depth already there.
            let mut rng = TestRng::new(top as u64);
            let band: [u16; WIDTH * HEIGHT] =
                core::array::from_fn(|_| (30_000 + rng.signed(25_000)) as u16);
            let rows = (bottom - top + 1) as usize;
            let at = (top - 80) as usize * width + (scan.first_column() - 170) as usize;
            let mut one = band;
            let mut painted = [None; WIDTH * HEIGHT];
            let n = scan.draw::<true>(rows, &mut one, at, width, |i, level| {
                painted[i] = Some(level)
            });
            let (mut each, mut expect) = (band, [None; WIDTH * HEIGHT]);
            let mut walked = scan;
            let mut m = 0;
            for row in top..=bottom {
                if let Some((x0, count, mut walk)) = walked.next_row() {
                    for x in x0..x0 + count as i32 {
                        let i = (row - 80) as usize * width + (x - 170) as usize;
                        if walk.key() > each[i] {
                            each[i] = walk.key();
                            expect[i] = Some((!walk.on_wire()).then(|| walk.level()));
                            m += 1;
                        }
                        walk.step::<true>();
                    }
                }
            }
            assert_eq!(one, each);
            assert_eq!(painted, expect);
            assert_eq!(n, m);
            drawn_total += n;
        }
        assert!(drawn_total > 1000, "{drawn_total}");
    }

    /// The integer arithmetic' values are the exact plane's (in `f64`, from the corners) plus 1/2,
    /// in fixed point, to within `2 + |Δx| + |Δy|` of their last bit at a pixel `(Δx, Δy)`
    /// pixels from the anchor, as the module docs derive: for small triangles, slivers and
    /// triangles across the whole 32-bit reach, depth keys and shade levels alike.
    #[test]
    fn integer_planes_are_the_exact_plane_to_their_last_bits() {
        let mut rng = TestRng::new(0x01e9_a120_2611);
        let (mut checked, mut worst) = (0, 0.0f64);
        for k in 0..4000 {
            let size = [24, 400, 4000, 8000][k % 4];
            let mut x: [i32; 3] = core::array::from_fn(|_| rng.signed(size) as i32);
            let mut y: [i32; 3] = core::array::from_fn(|_| rng.signed(size) as i32);
            let (bits, top) = [(DEPTH_BITS, 65_535), (LEVEL_BITS, 255)][k % 2];
            let mut v: [i32; 3] = core::array::from_fn(|_| (rng.signed(top / 2) + top / 2) as i32);
            if k % 7 == 0 {
                // A sliver: two corners a subpixel or two apart across.
                (x[2], y[2]) = ((x[0] + x[1]) / 2 + 1, (y[0] + y[1]) / 2 - 2);
            }
            let (mut shade, mut wire) = ([0u8; 3], [false; 3]);
            let area = counter_clockwise(&mut x, &mut y, &mut v, &mut shade, &mut wire);
            if area == 0 {
                continue;
            }
            let edges: [[i32; 2]; 3] = core::array::from_fn(|i| {
                let e = edge_set_up(&x, &y, i);
                [e.dx, e.dy]
            });
            let from = [x[0], y[0]];
            let first = [x.iter().min().unwrap() >> 4, y.iter().min().unwrap() >> 4];
            let plane =
                FixedPlane::through(v, &edges, Divisor::new(area as u32), bits, from, first);
            let anchor = from.map(|c| c >> 4);
            // The exact plane (its values at the corners `v`), plus 1/2, times `2^bits`.
            let (w, f) = (v.map(f64::from), f64::from(1u32 << bits));
            let exact = |px: f64, py: f64| {
                let [(ax, ay), (bx, by), (cx, cy)] = [0, 1, 2].map(|i| (x[i] as f64, y[i] as f64));
                let d = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
                let wb = ((px - ax) * (cy - ay) - (py - ay) * (cx - ax)) / d;
                let wc = ((bx - ax) * (py - ay) - (by - ay) * (px - ax)) / d;
                (w[0] + wb * (w[1] - w[0]) + wc * (w[2] - w[0]) + 0.5) * f
            };
            let (lo, hi) = (
                f * w.iter().fold(f64::MAX, |a, &b| a.min(b)),
                f * (top as f64 + 1.0),
            );
            for _ in 0..16 {
                let [px, py] = [0, 1].map(|i| {
                    let (a, b) = (
                        [x, y][i].iter().min().copied(),
                        [x, y][i].iter().max().copied(),
                    );
                    let (a, b) = (a.unwrap() >> 4, b.unwrap() >> 4);
                    a + rng.signed(i64::from(b - a) + 1).unsigned_abs() as i32 % (b - a + 1)
                });
                let want = exact(f64::from(px * 16 + 8), f64::from(py * 16 + 8));
                if !(lo..hi).contains(&want) {
                    continue; // (off the triangle's values: `f64` may not hold it exactly)
                }
                let got = plane
                    .at
                    .wrapping_add(plane.right.wrapping_mul(px - first[0]))
                    .wrapping_add(plane.down.wrapping_mul(py - first[1]));
                let off = (f64::from(got) - want).abs();
                let allowed = 2.0 + f64::from((px - anchor[0]).abs() + (py - anchor[1]).abs());
                assert!(
                    off <= allowed,
                    "{k}: ({px}, {py}) off by {off}, at most {allowed}"
                );
                worst = worst.max(off / allowed);
                checked += 1;
            }
        }
        assert!(checked > 20_000, "{checked}");
        assert!(worst > 0.5, "{worst}");
    }

    /// Only triangles with a corner beyond the 32-bit edge arithmetic's reach are left to the
    /// spans; wide ones and steep slivers are scanned, and what meets no row of the band is
    /// off it.
    #[test]
    fn only_far_corners_are_left_to_spans() {
        for arithmetic in [Arithmetic::Float, Arithmetic::Integer] {
            far_corners_to_spans(arithmetic);
        }
    }

    fn far_corners_to_spans(arithmetic: Arithmetic) {
        let v = |x: f32, y: f32, depth: f32| ScreenVertex {
            xy: [x, y],
            depth,
            shade: 0.5,
        };
        let scan = |corners: [ScreenVertex; 3]| {
            Snapped::new(corners, [false; 3])
                .unwrap()
                .band_scan(0..100, 0..100, None, arithmetic)
        };
        let wide = scan([v(0.5, 0.5, 1.0), v(40.5, 2.5, 1.0), v(3.5, 9.5, 1.0)]);
        assert!(matches!(
            wide,
            BandScan::Rows {
                top: 0,
                rows: 10,
                ..
            }
        ));
        let small = scan([v(0.5, 0.5, 1.0), v(4.5, 2.5, 1.0), v(3.5, 9.5, 1.0)]);
        assert!(matches!(
            small,
            BandScan::Rows {
                top: 0,
                rows: 10,
                ..
            }
        ));
        // A sliver 1/8 pixel high along row 0 (its corners on the 1/16 grid) whose depth
        // changes by 60,000 keys along its base and is 1 at its apex, two subpixels up: about
        // 15,000 keys a subpixel down, beyond what 14 fractional bits hold.
        let corners = [
            (0.1875, 0.4375, 1.0),
            (9.8125, 0.4375, 60_000.0),
            (5.0, 0.5625, 1.0),
        ];
        let sliver = scan(corners.map(|(x, y, d)| v(x as f32, y as f32, d as f32)));
        let BandScan::Rows {
            scan: mut sliver_scan,
            top: 0,
            rows: 1,
        } = sliver
        else {
            panic!("{sliver:?}");
        };
        // Its pixels take the plane's keys at their centres all the same (in `f64`, from
        // the corners' barycentric weights).
        let (x0, n, mut walk) = sliver_scan.next_row().unwrap();
        let plane = |x: f64, y: f64| {
            let [(ax, ay, a), (bx, by, b), (cx, cy, c)] = corners;
            let area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
            let wb = ((x - ax) * (cy - ay) - (y - ay) * (cx - ax)) / area;
            let wc = ((bx - ax) * (y - ay) - (by - ay) * (x - ax)) / area;
            a + wb * (b - a) + wc * (c - a)
        };
        assert!(n >= 4, "{n} pixels");
        for x in x0..x0 + n as i32 {
            let exact = plane(x as f64 + 0.5, 0.5).clamp(1.0, 65_535.0);
            assert!(
                (walk.key() as f64 - exact).abs() <= 1.0,
                "{x}: {}",
                walk.key()
            );
            walk.step::<false>();
        }
        // No area, or no row of the band: nothing to draw.
        let flat = scan([v(0.5, 0.5, 1.0), v(4.5, 2.5, 1.0), v(8.5, 4.5, 1.0)]);
        assert!(matches!(flat, BandScan::Off));
        let below = scan([v(0.5, 100.5, 1.0), v(4.5, 102.5, 1.0), v(3.5, 109.5, 1.0)]);
        assert!(matches!(below, BandScan::Off));
        // Corners beyond the 32-bit edge arithmetic's reach: spans (in 64 bits).
        let far = scan([v(0.5, 0.5, 1.0), v(4.5, 2.5, 1.0), v(3.5, 600.0, 1.0)]);
        assert!(matches!(far, BandScan::Wide));
    }

    /// Wireframe lines of any half width, the extremes included (found by the `render` fuzz
    /// target: an infinite one overflowed the limit's `ceil`): a line wider than the triangle
    /// covers every pixel of it, a negative or NaN one none, and the scan's pixels are the
    /// spans' either way.
    #[test]
    fn wireframe_lines_of_any_width() {
        let widths = [
            f32::INFINITY,
            f32::MAX,
            1e12,
            3e9,
            2.1e9,
            1e6,
            0.0,
            -0.3,
            -1e6,
            -2.1e9,
            -f32::MAX,
            f32::NEG_INFINITY,
            f32::NAN,
        ];
        let (mut all, mut none) = (0, 0);
        for (tri, snapped) in triangles(200, 2000) {
            let [first, last] = tri.rows();
            for &w in &widths {
                let columns = 0..400;
                let BandScan::Rows { mut scan, top, .. } =
                    snapped.band_scan(first..last + 1, columns.clone(), Some(w), Arithmetic::Float)
                else {
                    continue;
                };
                for row in top..=last {
                    let got = scan.next_row();
                    let want = tri.span(row, columns.clone(), Some(w));
                    let (Some((_, n, mut walk)), Some(span)) = (got, want) else {
                        assert!(got.is_none() && want.is_none());
                        continue;
                    };
                    let mut float = SpanWalk::new(&span);
                    for _ in 0..n {
                        let on = walk.on_wire();
                        assert_eq!(on, float.on_wire(), "width {w}");
                        // (Only drawn edges: at least one edge of every triangle is drawn.)
                        if w >= 1e6 {
                            assert!(on, "width {w}");
                            all += 1;
                        } else if w < 0.0 || w.is_nan() {
                            assert!(!on, "width {w}");
                            none += 1;
                        }
                        walk.step::<true>();
                        float.step::<true>();
                    }
                }
            }
        }
        assert!(all > 10_000 && none > 10_000, "{all} {none}");
    }

    /// A band's rows and columns may lie anywhere a viewport's do (2^20 pixels out with
    /// feature `large-viewports`): a triangle that meets none of them draws nothing, and its
    /// set-up does not overflow (an edge value computed out there overflowed `i32`).
    #[test]
    fn a_band_far_from_a_triangle_draws_nothing() {
        let far = 1 << 20;
        for (_, snapped) in triangles(200, 2000) {
            for (rows, columns) in [
                (0..400, far - 64..far),
                (far - 16..far, 0..400),
                (far - 16..far, far - 64..far),
                (0..400, i32::MAX - 64..i32::MAX),
                (i32::MAX - 16..i32::MAX, 0..400),
                (0..400, -400..-300),
            ] {
                let arithmetic = [Arithmetic::Float, Arithmetic::Integer][rows.start as usize % 2];
                let scan = snapped.band_scan(
                    rows.clone(),
                    columns.clone(),
                    Some(f32::INFINITY),
                    arithmetic,
                );
                let drawn = match scan {
                    BandScan::Off => 0,
                    BandScan::Rows { scan, rows, .. } => {
                        let mut depth = [0u16; 64];
                        scan.draw::<true>(rows, &mut depth, 0, 0, |_, _| {})
                    }
                    BandScan::Wide => panic!("a narrow triangle"),
                };
                assert_eq!(drawn, 0, "{rows:?} {columns:?}: {scan:?}");
            }
        }
    }
}
