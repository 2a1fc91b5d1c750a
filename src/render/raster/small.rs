//! Small triangles scanned row by row over their bounding box, in integers and fixed point.
//!
//! Most triangles of a tessellation at a pixel tolerance cover a few pixels over two or three
//! rows. For them, [`Triangle::span`]'s `f32` attributes at each row's first pixel cost more
//! than the pixels. A scan keeps each edge's value `E_i - bias_i` at the row's first column of
//! the box, stepped by a constant per row, and solves the same exact integer inequality `span`
//! solves (a pixel centre is inside edge `i` when `E_i - bias_i >= 0`, see [`Triangle`]) for
//! the row's columns, one division per edge. So both ways cover the same pixels, and
//! triangles scanned either way still meet without gaps or overlaps. (Testing every pixel of
//! the box instead, three additions and a sign test each, was measured slower on `fw_teapot`:
//! most of a box is outside its triangle.)
//!
//! The attributes are planes in fixed point anchored at the triangle's first corner: a depth
//! key plus 1/2 with 14 fractional bits, a shade level plus 1/2 with 16, each with its change
//! per subpixel step right and down, evaluated at pixel centres in wrapping `i32` arithmetic.
//! That is exact modulo `2^32`, so a pixel's value does not depend on where a scan starts
//! (which band, which column), and values inside the triangle are within range even where
//! the plane overflows off it. Over a box at most [`SMALL_COLUMNS`] pixels wide the slopes'
//! rounding moves a value by at most `16 * SMALL_COLUMNS * 2^-15` of a key (0.008).
//! A wireframe edge's test is on the integer edge function too: the pixel is on the line when
//! `E_i < half_width * 16 |edge_i|`, the distance in pixels times the edge's scale.

use core::ops::Range;

use super::edge::{ceil_div, Edges};
use super::{Triangle, HALF, SUBPIXELS};
use crate::render::walk::{FixedRamp, SpanWalk, DEPTH_BITS, LEVEL_BITS};

/// Widest bounding box, in pixel columns, a triangle is scanned over (wider ones take
/// [`Triangle::span`]). Measured on `fw_teapot` (QEMU, 2026-11-26): see the figures.
pub(crate) const SMALL_COLUMNS: i32 = 12;

/// A plane in fixed point: its value at an anchor pixel and its change per pixel right and
/// per row down.
#[derive(Clone, Copy, Debug)]
struct FixedPlane {
    at: i32,
    right: i32,
    down: i32,
}

impl FixedPlane {
    /// The value `start + slope · (X - x0, Y - y0)` at subpixel `(X, Y)`, where the plane is
    /// `start` at `(x0, y0)` with `slope` per subpixel, all times `2^bits`.
    fn new(start: f32, slope: [f32; 2], bits: u32, from: [i32; 2], at: [i32; 2]) -> FixedPlane {
        let scale = (1u32 << bits) as f32;
        let [sx, sy] = slope.map(|s| (s * scale) as i32);
        let base = (start * scale) as i32;
        let (dx, dy) = (at[0].wrapping_sub(from[0]), at[1].wrapping_sub(from[1]));
        FixedPlane {
            at: base
                .wrapping_add(sx.wrapping_mul(dx))
                .wrapping_add(sy.wrapping_mul(dy)),
            right: sx.wrapping_mul(SUBPIXELS as i32),
            down: sy.wrapping_mul(SUBPIXELS as i32),
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

/// A small triangle's scan, row by row over its bounding box's columns (within a band's).
#[derive(Clone, Copy, Debug)]
pub(in crate::render) struct SmallScan {
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

impl Triangle {
    /// The scan of this triangle from row `row` on, over columns `columns`, when its bounding
    /// box is at most [`SMALL_COLUMNS`] columns wide (else `None`: [`span`](Self::span) draws
    /// it), with wireframe lines `half_width` wide (`None`: no wireframe).
    pub fn small_scan(
        &self,
        row: i32,
        columns: Range<i32>,
        half_width: Option<f32>,
    ) -> Option<SmallScan> {
        let Edges::Narrow { k, m0 } = &self.edges else {
            return None;
        };
        let (sub, half) = (SUBPIXELS as i32, HALF as i32);
        let [a, b, c] = self.x;
        let first = ceil_div(a.min(b).min(c) - half, sub);
        let last = (a.max(b).max(c) - half).div_euclid(sub);
        if last - first >= SMALL_COLUMNS {
            return None;
        }
        let x0 = first.max(columns.start);
        let width = last.min(columns.end - 1) - x0 + 1;
        let yc = row * sub + half;
        // Inside edge `i`: `k px >= m0 - dx yc` (see `edge::inside_columns`).
        let edge = core::array::from_fn(|i| k[i] * x0 + self.dx[i] * yc - m0[i]);
        let down = self.dx.map(|d| d * sub);
        // `E_i = F_i + bias_i`, where `F_i` is the edge value above and `E_i` the edge function
        // at the pixel centre; on the line when `E_i` is below `half_width · 16 |edge|`:
        // `F_i < ceil(half_width / inv_length - bias_i)`.
        let wire = core::array::from_fn(|i| match half_width {
            Some(w) if self.inv_length[i] != 0.0 => {
                let limit = w / self.inv_length[i] - self.bias(i) as f32;
                let t = limit as i32;
                // `ceil` of a value within `i32` (saturated otherwise).
                t + ((t as f32) < limit) as i32
            }
            _ => i32::MIN,
        });
        let slopes = [self.depth.dx, self.depth.dy].map(|s| s * (1u32 << DEPTH_BITS) as f32);
        let shades = [self.shade.dx, self.shade.dy].map(|s| s * (255u32 << LEVEL_BITS) as f32);
        // Slopes that would not fit in fixed point (slivers a fraction of a pixel across,
        // where the depth changes by thousands of keys per pixel): the span's `f32` takes them.
        let limit = (1u32 << 30) as f32;
        if !slopes.iter().chain(&shades).all(|s| s.abs() < limit) {
            return None;
        }
        let xc = x0 * sub + half;
        let from = [self.x[0], self.y[0]];
        let at = [xc, yc];
        Some(SmallScan {
            x0,
            width,
            edge,
            right: *k,
            down,
            wire,
            depth: FixedPlane::new(
                self.depth.at + 0.5,
                [self.depth.dx, self.depth.dy],
                DEPTH_BITS,
                from,
                at,
            ),
            level: FixedPlane::new(
                255.0 * self.shade.at + 0.5,
                [255.0 * self.shade.dx, 255.0 * self.shade.dy],
                LEVEL_BITS,
                from,
                at,
            ),
        })
    }
}

impl SmallScan {
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
    use crate::render::raster::ScreenVertex;
    use crate::test_rng::TestRng;

    /// Random small triangles, mostly a few pixels across, some slivers, with depth and shade
    /// varying across them.
    fn triangles(n: usize, spread: i64) -> impl Iterator<Item = (Triangle, [bool; 3])> {
        let mut rng = TestRng::new(0x5ca1_ab1e_2026);
        (0..n).filter_map(move |k| {
            let size = [3, 40, 200][k % 3];
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
            Triangle::new(v, wire).map(|t| (t, wire))
        })
    }

    /// The scan covers exactly the pixels `span` covers, row by row (so triangles drawn either
    /// way still tile), with depth keys and shade levels within one of the spans' and the same
    /// wireframe pixels but at the lines' rounding.
    #[test]
    fn a_scan_covers_what_spans_cover() {
        let (mut scanned, mut rows, mut far_keys, mut wire_apart) = (0, 0, 0, 0);
        for (tri, _) in triangles(3000, 2000) {
            let [first, last] = tri.rows();
            for columns in [0..400, 195..205] {
                let Some(mut scan) = tri.small_scan(first, columns.clone(), Some(0.35)) else {
                    continue;
                };
                scanned += 1;
                for row in first..=last {
                    let got = scan.next_row();
                    let want = tri.span(row, columns.clone());
                    assert_eq!(
                        got.map(|(x0, n, _)| (x0, x0 + n as i32)),
                        want.map(|s| (s.x0, s.x1)),
                        "row {row}"
                    );
                    let (Some((_, n, mut walk)), Some(span)) = (got, want) else {
                        continue;
                    };
                    rows += 1;
                    let mut float = SpanWalk::new(&span, Some(0.35));
                    for _ in 0..n {
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
        assert!(far_keys < rows / 10, "{far_keys} of {rows}");
        assert!(wire_apart < rows / 20, "{wire_apart} of {rows}");
    }

    /// `draw` depth-tests and paints the pixels `next_row` walks, with the same values.
    #[test]
    fn drawing_a_scan_in_one_loop_walks_its_rows() {
        const WIDTH: usize = 64;
        const HEIGHT: usize = 48;
        let (width, height) = (WIDTH, HEIGHT);
        let mut drawn_total = 0;
        for (tri, _) in triangles(600, 300) {
            let [first, last] = tri.rows();
            let (top, bottom) = (first.max(80), last.min(80 + height as i32 - 1));
            let columns = 170..170 + width as i32;
            if top > bottom {
                continue;
            }
            let Some(scan) = tri.small_scan(top, columns.clone(), Some(0.35)) else {
                continue;
            };
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

    /// Wide boxes and slivers too steep for fixed point are left to the spans.
    #[test]
    fn wide_triangles_are_left_to_spans() {
        let v = |x: f32, y: f32, depth: f32| ScreenVertex {
            xy: [x, y],
            depth,
            shade: 0.5,
        };
        let wide = Triangle::new(
            [v(0.5, 0.5, 1.0), v(40.5, 2.5, 1.0), v(3.5, 9.5, 1.0)],
            [false; 3],
        );
        assert!(wide.unwrap().small_scan(0, 0..100, None).is_none());
        let small = Triangle::new(
            [v(0.5, 0.5, 1.0), v(4.5, 2.5, 1.0), v(3.5, 9.5, 1.0)],
            [false; 3],
        );
        assert!(small.unwrap().small_scan(0, 0..100, None).is_some());
        // A sliver 1/16 pixel high whose depth changes by 60,000 keys along a pixel of its
        // base, its apex 9 pixels aside: the plane falls by 560,000 keys a subpixel down.
        let sliver = Triangle::new(
            [
                v(0.5, 0.5, 1.0),
                v(1.5, 0.5, 60_000.0),
                v(9.875, 0.5625, 1.0),
            ],
            [false; 3],
        );
        assert!(sliver.unwrap().small_scan(0, 0..100, None).is_none());
    }
}
