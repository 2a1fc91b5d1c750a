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
use super::project::{CornerCache, Setup};
use super::raster::{faces_away, BandScan, Scan, Snapped, Triangle};
use super::walk::{draw_span, SpanWalk};
use super::{RenderStats, Style};
use crate::sink::{TriangleSink, Vertex};
use crate::Arithmetic;

/// Where a band's visible pixels go.
pub(super) trait BandOutput {
    type Error;
    /// A band covering `area` starts.
    fn begin(&mut self, area: &Rectangle, style: &Style);
    /// Draws the pixels of `row` from column `x0` on that pass the depth test against
    /// `depth` (the band's values under them, one per pixel), along `walk`; the pixels drawn
    /// and the runs of them.
    fn span(
        &mut self,
        area: &Rectangle,
        row: i32,
        x0: i32,
        depth: &mut [u16],
        walk: SpanWalk,
        style: &Style,
    ) -> Result<Drawn, Self::Error>;
    /// Draws `rows` rows of a triangle's `scan` from row `top` on, against the band's
    /// `depth`; by default span by span.
    fn scan(
        &mut self,
        area: &Rectangle,
        top: i32,
        rows: usize,
        mut scan: Scan,
        depth: &mut [u16],
        style: &Style,
    ) -> Result<Drawn, Self::Error> {
        let width = area.size.width as usize;
        let mut drawn = Drawn::default();
        for row in top..top + rows as i32 {
            if let Some((x0, n, walk)) = scan.next_row() {
                let at = (row - area.top_left.y) as usize * width + (x0 - area.top_left.x) as usize;
                if let Some(depth) = depth.get_mut(at..at + n as usize) {
                    let d = self.span(area, row, x0, depth, walk, style)?;
                    drawn.pixels += d.pixels;
                    drawn.runs += d.runs;
                }
            }
        }
        Ok(drawn)
    }
    /// The band is rasterised; `depth` is 0 where no triangle drew.
    fn finish(
        &mut self,
        area: &Rectangle,
        depth: &[u16],
        style: &Style,
        stats: &mut RenderStats,
    ) -> Result<(), Self::Error>;
}

/// What one span drew.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Drawn {
    /// Pixels that passed the depth test.
    pub pixels: u32,
    /// Runs of them along the row, each sent at once (0 where a band buffer takes them).
    pub runs: u32,
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

    fn span(
        &mut self,
        _: &Rectangle,
        row: i32,
        x0: i32,
        depth: &mut [u16],
        walk: SpanWalk,
        style: &Style,
    ) -> Result<Drawn, D::Error> {
        let mut drawn = Drawn::default();
        let mut at = walk;
        let mut x = 0;
        while x < depth.len() {
            // Skip hidden pixels, then take the run of visible ones.
            let start = x;
            let mut w = at;
            while let Some(d) = depth.get_mut(x) {
                let key = w.key();
                if key <= *d {
                    break;
                }
                *d = key;
                x += 1;
                w.step::<true>();
            }
            if x > start {
                let n = (x - start) as u32;
                let area = Rectangle::new(Point::new(x0 + start as i32, row), Size::new(n, 1));
                let mut c = at;
                let colors = (0..n).map(|_| {
                    let color = walk_color(style, &c);
                    c.step::<true>();
                    color.into()
                });
                self.0.fill_contiguous(&area, colors)?;
                drawn.pixels += n;
                drawn.runs += 1;
            }
            x += 1;
            at = walk;
            at.skip(x as u32);
        }
        Ok(drawn)
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
    /// Draws a span into pixels `at..at + depth.len()` ([`draw_span`]), with the surface
    /// colour at each shade level `palette` and the wireframe's colour `wire`; the pixels
    /// drawn (none when they are out of range).
    fn draw(
        &mut self,
        at: usize,
        depth: &mut [u16],
        walk: SpanWalk,
        palette: &[Self::Pixel; 256],
        wire: Option<Self::Pixel>,
    ) -> u32;
    /// Sets pixel `i` (ignored when out of range).
    fn set(&mut self, i: usize, p: Self::Pixel);
    /// Sets the first `n` pixels.
    fn fill(&mut self, n: usize, p: Self::Pixel);
}

/// [`draw_span`] with the colours of `palette` and `wire`, each written by `put`.
#[inline(always)]
fn paint_span<P: Copy, T>(
    depth: &mut [u16],
    pixels: impl Iterator<Item = T>,
    walk: SpanWalk,
    palette: &[P; 256],
    wire: Option<P>,
    put: impl Fn(T, P),
) -> u32 {
    match wire {
        Some(line) => draw_span::<true, T>(depth, pixels, walk, |slot, level| {
            put(slot, level.map_or(line, |l| palette[l]))
        }),
        None => draw_span::<false, T>(depth, pixels, walk, |slot, level| {
            put(slot, palette[level.unwrap_or(0)])
        }),
    }
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

    fn draw(
        &mut self,
        at: usize,
        depth: &mut [u16],
        walk: SpanWalk,
        palette: &[C; 256],
        wire: Option<C>,
    ) -> u32 {
        let Some(pixels) = self.0.get_mut(at..at + depth.len()) else {
            return 0;
        };
        paint_span(depth, pixels.iter_mut(), walk, palette, wire, |slot, p| {
            *slot = p
        })
    }

    #[inline(always)]
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

    fn draw(
        &mut self,
        at: usize,
        depth: &mut [u16],
        walk: SpanWalk,
        palette: &[[u8; 2]; 256],
        wire: Option<[u8; 2]>,
    ) -> u32 {
        let Some(bytes) = self.0.get_mut(2 * at..2 * (at + depth.len())) else {
            return 0;
        };
        let pixels = bytes.chunks_exact_mut(2);
        paint_span(depth, pixels, walk, palette, wire, |slot, p| {
            slot.copy_from_slice(&p)
        })
    }

    #[inline(always)]
    fn set(&mut self, i: usize, p: [u8; 2]) {
        if let Some(slot) = self.0.get_mut(2 * i..2 * i + 2) {
            slot.copy_from_slice(&p);
        }
    }

    fn fill(&mut self, n: usize, p: [u8; 2]) {
        let n = n.min(self.0.len() / 2);
        // Sixteen pixels a step, as word stores (a copy of the filled part after itself,
        // as `fill_doubling` does, is a `memcpy` of a word a loop on the Cortex-M4F).
        let block: [u8; 32] = core::array::from_fn(|i| p[i % 2]);
        let mut blocks = self.0[..2 * n].chunks_exact_mut(32);
        for b in &mut blocks {
            b.copy_from_slice(&block);
        }
        for (i, b) in blocks.into_remainder().iter_mut().enumerate() {
            *b = p[i % 2];
        }
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

    fn span(
        &mut self,
        area: &Rectangle,
        row: i32,
        x0: i32,
        depth: &mut [u16],
        walk: SpanWalk,
        _: &Style,
    ) -> Result<Drawn, E> {
        let width = area.size.width as usize;
        let at = (row - area.top_left.y) as usize * width + (x0 - area.top_left.x) as usize;
        let pixels = self.pixels.draw(at, depth, walk, &self.palette, self.wire);
        Ok(Drawn { pixels, runs: 0 })
    }

    fn scan(
        &mut self,
        area: &Rectangle,
        top: i32,
        rows: usize,
        scan: Scan,
        depth: &mut [u16],
        _: &Style,
    ) -> Result<Drawn, E> {
        let width = area.size.width as usize;
        let at = (top - area.top_left.y) as usize * width
            + (scan.first_column() - area.top_left.x) as usize;
        let (pixels, palette) = (&mut self.pixels, &self.palette);
        let drawn = match self.wire {
            Some(line) => scan.draw::<true>(rows, depth, at, width, |i, level| {
                pixels.set(i, level.map_or(line, |l| palette[l]))
            }),
            None => scan.draw::<false>(rows, depth, at, width, |i, level| {
                pixels.set(i, palette[level.unwrap_or(0)])
            }),
        };
        Ok(Drawn {
            pixels: drawn,
            runs: 0,
        })
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
    /// Whether a patch's triangles that face away are left out (the source's
    /// [`one_sided`](super::TriangleSource::one_sided)), and the last patch asked about.
    pub one_sided: &'a dyn Fn(u32) -> bool,
    pub patch: Option<(u32, bool)>,
    /// How triangles' depth and shade are set up.
    pub arithmetic: Arithmetic,
}

impl<O: BandOutput> TriangleSink for Band<'_, '_, O> {
    fn wants_parameters(&self) -> bool {
        false
    }

    fn triangle(&mut self, patch: u32, corners: [&Vertex; 3]) {
        if self.error.is_some() {
            return;
        }
        let (corners, inside) = self.setup.corners(corners);
        self.draw(patch, corners, inside);
    }

    fn keyed_triangle(
        &mut self,
        patch: u32,
        keys: [u64; 3],
        corner: &mut dyn FnMut(usize) -> Vertex,
    ) {
        if self.error.is_some() {
            return;
        }
        let (corners, inside) = self.corners.corners(self.setup, keys, corner);
        self.draw(patch, corners, inside);
    }
}

impl<O: BandOutput> Band<'_, '_, O> {
    /// Projects and draws one triangle of patch `patch`, its corners in view space
    /// (`inside`: all inside the clip planes).
    fn draw(&mut self, patch: u32, corners: [ClipVertex; 3], inside: bool) {
        self.stats.triangles += 1;
        let cull = match self.patch {
            Some((p, cull)) if p == patch => cull,
            _ => {
                let cull = (self.one_sided)(patch);
                self.patch = Some((patch, cull));
                cull
            }
        };
        let setup = self.setup;
        setup.project(corners, inside, |v, wire| {
            if let Some(snapped) = Snapped::new(v, wire) {
                if cull && faces_away(snapped.x, snapped.y) {
                    // Behind a triangle that faces the eye.
                    self.stats.culled += 1;
                } else {
                    self.rasterise(&snapped);
                }
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
                self.rasterise(&t.snapped());
            }
        });
    }

    fn rows(&self) -> Range<i32> {
        self.area.top_left.y..self.area.top_left.y + self.area.size.height as i32
    }

    fn columns(&self) -> Range<i32> {
        self.area.top_left.x..self.area.top_left.x + self.area.size.width as i32
    }

    /// Draws a triangle's pixels in the band.
    fn rasterise(&mut self, snapped: &Snapped) {
        if self.error.is_some() {
            return;
        }
        let style = self.setup.style;
        let half_width = style.wireframe.map(|w| w.half_width);
        match snapped.band_scan(self.rows(), self.columns(), half_width, self.arithmetic) {
            BandScan::Off => {}
            BandScan::Rows { scan, top, rows } => {
                match self
                    .out
                    .scan(&self.area, top, rows, scan, self.depth, style)
                {
                    Ok(drawn) => {
                        self.stats.pixels += drawn.pixels;
                        self.stats.runs += drawn.runs;
                    }
                    Err(e) => self.error = Some(e),
                }
            }
            BandScan::Wide => {
                if cfg!(feature = "large-viewports") {
                    if let Some(tri) = snapped.triangle() {
                        self.rasterise_spans(&tri, half_width);
                    }
                }
            }
        }
    }

    /// Draws a triangle's pixels in the band span by span (corners beyond the 32-bit edge
    /// arithmetic's reach).
    fn rasterise_spans(&mut self, tri: &Triangle, half_width: Option<f32>) {
        let [first, last] = tri.rows();
        let (rows, columns) = (self.rows(), self.columns());
        let width = columns.len();
        let (top, bottom) = (first.max(rows.start), last.min(rows.end - 1));
        for row in top..=bottom {
            let Some(span) = tri.span(row, columns.clone(), half_width) else {
                continue;
            };
            let at = (row - rows.start) as usize * width + (span.x0 - columns.start) as usize;
            let n = (span.x1 - span.x0) as usize;
            let walk = SpanWalk::new(&span);
            if !self.draw_span(row, span.x0, at, n, walk) {
                return;
            }
        }
    }

    /// Draws `n` pixels of `row` from column `x0`, the band's pixel `at` on, along `walk`;
    /// false when the output failed (the error is kept).
    #[inline(always)]
    fn draw_span(&mut self, row: i32, x0: i32, at: usize, n: usize, walk: SpanWalk) -> bool {
        let Some(depth) = self.depth.get_mut(at..at + n) else {
            return true;
        };
        match self
            .out
            .span(&self.area, row, x0, depth, walk, self.setup.style)
        {
            Ok(drawn) => {
                self.stats.pixels += drawn.pixels;
                self.stats.runs += drawn.runs;
                true
            }
            Err(e) => {
                self.error = Some(e);
                false
            }
        }
    }
}

/// Colour of the pixel `walk` is at.
fn walk_color(style: &Style, walk: &SpanWalk) -> Rgb888 {
    match style.wireframe {
        Some(w) if walk.on_wire() => w.color,
        _ => shaded(style.color, walk.level() as u32),
    }
}

/// Colour `c` at shade level `level` (0 to 255).
fn shaded(c: Rgb888, level: u32) -> Rgb888 {
    let ch = |v: u8| ((v as u32 * level + 127) / 255) as u8;
    Rgb888::new(ch(c.r()), ch(c.g()), ch(c.b()))
}
