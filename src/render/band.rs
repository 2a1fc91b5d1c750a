//! One band of the frame: depth-tested scan conversion into the band's depth buffer, and
//! where its visible pixels go (runs to a draw target, or a colour band buffer pushed once).

use core::ops::Range;

use embedded_graphics::draw_target::DrawTarget;
use embedded_graphics::pixelcolor::raw::{RawData, RawU16};
use embedded_graphics::pixelcolor::{PixelColor, Rgb565, Rgb888, RgbColor};
use embedded_graphics::prelude::{Point, Size};
use embedded_graphics::primitives::Rectangle;

use super::clip::ClipVertex;
use super::list::{for_each_listed, ListSlot, SubpixelRows};
use super::project::{shade_level, CornerCache, Setup};
use super::raster::{Span, Triangle};
use super::{RenderStats, Style};
use crate::sink::{TriangleSink, Vertex};

/// Where a band's visible pixels go.
pub(super) trait BandOutput {
    type Error;
    /// A band covering `area` starts.
    fn begin(&mut self, area: &Rectangle, style: &Style);
    /// Pixels `x0..x1` of `row` passed the depth test; their colours come from `span`.
    fn run(
        &mut self,
        area: &Rectangle,
        row: i32,
        x0: i32,
        x1: i32,
        span: &Span,
        style: &Style,
    ) -> Result<(), Self::Error>;
    /// The band is rasterised; `depth` is 0 where no triangle drew.
    fn finish(
        &mut self,
        area: &Rectangle,
        depth: &[u16],
        style: &Style,
        stats: &mut RenderStats,
    ) -> Result<(), Self::Error>;
}

/// Runs along a row go straight to a draw target, one `fill_contiguous` each.
pub(super) struct Runs<'t, D>(pub &'t mut D);

impl<D> BandOutput for Runs<'_, D>
where
    D: DrawTarget,
    D::Color: From<Rgb888>,
{
    type Error = D::Error;

    fn begin(&mut self, _: &Rectangle, _: &Style) {}

    fn run(
        &mut self,
        _: &Rectangle,
        row: i32,
        x0: i32,
        x1: i32,
        span: &Span,
        style: &Style,
    ) -> Result<(), D::Error> {
        let area = Rectangle::new(Point::new(x0, row), Size::new((x1 - x0) as u32, 1));
        let colors = (x0..x1).map(|px| color(style, span, px).into());
        self.0.fill_contiguous(&area, colors)
    }

    fn finish(
        &mut self,
        area: &Rectangle,
        depth: &[u16],
        style: &Style,
        stats: &mut RenderStats,
    ) -> Result<(), D::Error> {
        let Some(bg) = style.background else {
            return Ok(());
        };
        let color: D::Color = bg.into();
        let width = area.size.width as usize;
        for (r, line) in depth.chunks_exact(width).enumerate() {
            let mut x = 0;
            while x < width {
                if line[x] != 0 {
                    x += 1;
                    continue;
                }
                let start = x;
                while x < width && line[x] == 0 {
                    x += 1;
                }
                let run = Rectangle::new(
                    area.top_left + Point::new(start as i32, r as i32),
                    Size::new((x - start) as u32, 1),
                );
                self.0.fill_solid(&run, color)?;
                stats.background += (x - start) as u32;
            }
        }
        Ok(())
    }
}

/// A band's colours in caller memory, row-major.
pub(super) trait BandPixels {
    /// One pixel as the memory holds it.
    type Pixel: Copy;
    /// A colour as the memory holds it.
    fn convert(c: Rgb888) -> Self::Pixel;
    /// Pixels it holds.
    fn pixels(&self) -> usize;
    /// Sets pixel `i` (ignored when out of range).
    fn set(&mut self, i: usize, p: Self::Pixel);
    /// Sets the first `n` pixels.
    fn fill(&mut self, n: usize, p: Self::Pixel);
}

/// Colours of the target's type.
pub(super) struct Typed<'c, C>(pub &'c mut [C]);

impl<C: PixelColor + From<Rgb888>> BandPixels for Typed<'_, C> {
    type Pixel = C;

    fn convert(c: Rgb888) -> C {
        c.into()
    }

    fn pixels(&self) -> usize {
        self.0.len()
    }

    fn set(&mut self, i: usize, p: C) {
        if let Some(slot) = self.0.get_mut(i) {
            *slot = p;
        }
    }

    fn fill(&mut self, n: usize, p: C) {
        let n = n.min(self.0.len());
        fill_doubling(&mut self.0[..n], 1, |first| first[0] = p);
    }
}

/// Rgb565 as two big-endian bytes per pixel, as SPI displays take them.
pub(super) struct Rgb565Be<'c>(pub &'c mut [u8]);

impl BandPixels for Rgb565Be<'_> {
    type Pixel = [u8; 2];

    fn convert(c: Rgb888) -> [u8; 2] {
        RawU16::from(Rgb565::from(c)).into_inner().to_be_bytes()
    }

    fn pixels(&self) -> usize {
        self.0.len() / 2
    }

    fn set(&mut self, i: usize, p: [u8; 2]) {
        if let Some(slot) = self.0.get_mut(2 * i..2 * i + 2) {
            slot.copy_from_slice(&p);
        }
    }

    fn fill(&mut self, n: usize, p: [u8; 2]) {
        let n = n.min(self.0.len() / 2);
        fill_doubling(&mut self.0[..2 * n], 2, |first| first.copy_from_slice(&p));
    }
}

/// Fills `slice` with copies of its first `unit` elements, which `first` writes: the filled
/// part is copied after itself, doubling it, so that the copies are `memcpy`s (on the
/// Cortex-M4F a band's background took 5 instructions a pixel element by element, and about
/// a tenth of that this way; the two halves of each copy are split apart, so that it is a
/// `memcpy` rather than a `memmove`, which a firmware then need not link: 1.6 KB of flash).
/// `slice.len()` is a multiple of `unit`.
fn fill_doubling<T: Copy>(slice: &mut [T], unit: usize, first: impl FnOnce(&mut [T])) {
    let Some(head) = slice.get_mut(..unit) else {
        return;
    };
    first(head);
    let mut filled = unit;
    while filled < slice.len() {
        let n = filled.min(slice.len() - filled);
        let (done, rest) = slice.split_at_mut(filled);
        rest[..n].copy_from_slice(&done[..n]);
        filled += n;
    }
}

/// A colour band buffer, pushed whole when the band is done.
pub(super) struct Buffered<P: BandPixels, F> {
    pixels: P,
    push: F,
    /// The surface colour at each shade level, converted once per frame (as [`color`] gives
    /// it, so the pixels are the same as converting each one).
    palette: [P::Pixel; 256],
    /// The wireframe's colour, converted once per frame.
    wire: Option<P::Pixel>,
}

impl<P: BandPixels, F> Buffered<P, F> {
    /// Pixels `pixels`, handed to `push` band by band, drawn in `style`.
    pub fn new(pixels: P, push: F, style: &Style) -> Self {
        Buffered {
            pixels,
            push,
            palette: core::array::from_fn(|level| P::convert(shaded(style.color, level as u32))),
            wire: style.wireframe.map(|w| P::convert(w.color)),
        }
    }

    /// The pixels.
    pub fn pixels(&self) -> &P {
        &self.pixels
    }
}

impl<P, F, E> BandOutput for Buffered<P, F>
where
    P: BandPixels,
    F: FnMut(&Rectangle, &P) -> Result<(), E>,
{
    type Error = E;

    fn begin(&mut self, area: &Rectangle, style: &Style) {
        let n = (area.size.width * area.size.height) as usize;
        let background = P::convert(style.background.unwrap_or(Rgb888::BLACK));
        self.pixels.fill(n, background);
    }

    fn run(
        &mut self,
        area: &Rectangle,
        row: i32,
        x0: i32,
        x1: i32,
        span: &Span,
        style: &Style,
    ) -> Result<(), E> {
        let width = area.size.width as usize;
        let base = (row - area.top_left.y) as usize * width;
        for x in x0..x1 {
            let i = base + (x - area.top_left.x) as usize;
            let column = (x - span.x0) as u32;
            let p = match self.wire.filter(|_| on_wire(style, span, column)) {
                Some(wire) => wire,
                None => self.palette[span_level(span, column) as usize],
            };
            self.pixels.set(i, p);
        }
        Ok(())
    }

    fn finish(
        &mut self,
        area: &Rectangle,
        _: &[u16],
        _: &Style,
        stats: &mut RenderStats,
    ) -> Result<(), E> {
        stats.pushed += area.size.width * area.size.height;
        (self.push)(area, &self.pixels)
    }
}

/// One band being drawn: the sink a source streams into, or what the triangle list is drawn
/// into.
pub(super) struct Band<'a, 'b, O: BandOutput> {
    pub setup: &'a Setup<'a>,
    pub depth: &'b mut [u16],
    pub area: Rectangle,
    pub out: &'b mut O,
    pub error: Option<O::Error>,
    pub stats: &'b mut RenderStats,
    /// Corners in view space by key.
    pub corners: &'b mut CornerCache,
}

impl<O: BandOutput> TriangleSink for Band<'_, '_, O> {
    fn triangle(&mut self, _patch: u32, corners: [&Vertex; 3]) {
        if self.error.is_some() {
            return;
        }
        let (corners, inside) = self.setup.corners(corners);
        self.draw(corners, inside);
    }

    fn keyed_triangle(
        &mut self,
        _patch: u32,
        keys: [u64; 3],
        corner: &mut dyn FnMut(usize) -> Vertex,
    ) {
        if self.error.is_some() {
            return;
        }
        let (corners, inside) = self.corners.corners(self.setup, keys, corner);
        self.draw(corners, inside);
    }
}

impl<O: BandOutput> Band<'_, '_, O> {
    /// Projects and draws one triangle, its corners in view space (`inside`: all inside the
    /// clip planes).
    fn draw(&mut self, corners: [ClipVertex; 3], inside: bool) {
        self.stats.triangles += 1;
        let setup = self.setup;
        setup.project(corners, inside, |v, wire| {
            if let Some(tri) = Triangle::new(v, wire) {
                self.rasterise(&tri);
            }
        });
    }

    /// Draws the triangles in the first `front` slots of `list` (its groups and triangles)
    /// that reach the band, in order.
    #[inline(never)]
    pub fn draw_list(&mut self, list: &[ListSlot], front: usize) {
        let rows = SubpixelRows::new(&self.rows());
        for_each_listed(list, front, &rows, |t| {
            if t.meets(&rows) {
                if let Some(tri) = t.triangle() {
                    self.rasterise(&tri);
                }
            }
        });
    }

    fn rows(&self) -> Range<i32> {
        self.area.top_left.y..self.area.top_left.y + self.area.size.height as i32
    }

    fn columns(&self) -> Range<i32> {
        self.area.top_left.x..self.area.top_left.x + self.area.size.width as i32
    }

    fn rasterise(&mut self, tri: &Triangle) {
        if self.error.is_some() {
            return;
        }
        let [first, last] = tri.rows();
        let (rows, columns) = (self.rows(), self.columns());
        let width = columns.len();
        let style = self.setup.style;
        for row in first.max(rows.start)..=last.min(rows.end - 1) {
            let Some(span) = tri.span(row, columns.clone()) else {
                continue;
            };
            let base = (row - rows.start) as usize * width;
            let mut x = span.x0;
            while x < span.x1 {
                // Skip hidden pixels, then take the run of visible ones.
                let start = x;
                while x < span.x1 {
                    let i = base + (x - columns.start) as usize;
                    let key = depth_key(&span, x);
                    match self.depth.get_mut(i) {
                        Some(d) if key > *d => {
                            *d = key;
                            x += 1;
                        }
                        _ => break,
                    }
                }
                if x > start {
                    if let Err(e) = self.out.run(&self.area, row, start, x, &span, style) {
                        self.error = Some(e);
                        return;
                    }
                    self.stats.pixels += (x - start) as u32;
                    self.stats.runs += 1;
                }
                x += 1;
            }
        }
    }
}

/// Depth key of pixel column `x` of `span`: 1 (far) to 65535 (near), rounded, so that
/// surfaces at one depth (whose corner keys are the same integer) get the same key.
fn depth_key(span: &Span, x: i32) -> u16 {
    let k = span.depth.at((x - span.x0) as u32);
    // The same as `((k + 0.5) as u16).max(1)` (both saturate, NaN to 0), where the
    // conversion to `u32` is one instruction on a Cortex-M4F and to `u16` is four.
    ((k + 0.5) as u32).clamp(1, u16::MAX as u32) as u16
}

/// Colour of pixel column `x` of `span`.
fn color(style: &Style, span: &Span, x: i32) -> Rgb888 {
    let i = (x - span.x0) as u32;
    wire_color(style, span, i).unwrap_or_else(|| shaded(style.color, span_level(span, i)))
}

/// The wireframe's colour when column `i` of `span` lies on a drawn edge.
fn wire_color(style: &Style, span: &Span, i: u32) -> Option<Rgb888> {
    let w = style.wireframe?;
    on_wire(style, span, i).then_some(w.color)
}

/// Whether column `i` of `span` lies on a drawn edge of the wireframe.
fn on_wire(style: &Style, span: &Span, i: u32) -> bool {
    style
        .wireframe
        .is_some_and(|w| span.edge.iter().any(|e| e.at(i) < w.half_width))
}

/// The shade of column `i` of `span` as a level from 0 to 255.
fn span_level(span: &Span, i: u32) -> u32 {
    shade_level(span.shade.at(i))
}

/// Colour `c` at shade level `level` (0 to 255).
fn shaded(c: Rgb888, level: u32) -> Rgb888 {
    let ch = |v: u8| ((v as u32 * level + 127) / 255) as u8;
    Rgb888::new(ch(c.r()), ch(c.g()), ch(c.b()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::raster::Ramp;

    #[test]
    fn depth_keys_saturate_as_a_conversion_to_u16_does() {
        let span = |start: f32| Span {
            x0: 0,
            x1: 1,
            depth: Ramp { start, step: 0.0 },
            ..Span::default()
        };
        for k in [
            f32::NAN,
            f32::NEG_INFINITY,
            -1.0e9,
            -0.6,
            -0.5,
            -0.0,
            0.3,
            0.5,
            1.49,
            1.5,
            777.5,
            65_534.4,
            65_534.5,
            65_535.0,
            65_535.5,
            65_536.0,
            4.3e9,
            f32::INFINITY,
        ] {
            let old = ((k + 0.5) as u16).max(1);
            assert_eq!(depth_key(&span(k), 0), old, "{k}");
        }
    }
}
