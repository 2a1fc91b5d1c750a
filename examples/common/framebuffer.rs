// A framebuffer `DrawTarget` over a caller slice, `no_std`: the firmware demo renders into it,
// the host examples and tests too (through `#[path]`). Hand-written.

use core::convert::Infallible;

use embedded_graphics::draw_target::DrawTarget;
use embedded_graphics::pixelcolor::PixelColor;
use embedded_graphics::prelude::{OriginDimensions, Pixel, Size};
use embedded_graphics::primitives::{PointsIter, Rectangle};

/// `width x height` pixels, row-major, in a caller slice.
pub struct Framebuffer<'a, C> {
    /// The pixels (at least `width * height`).
    pub pixels: &'a mut [C],
    /// Columns.
    pub width: u32,
    /// Rows.
    pub height: u32,
}

impl<'a, C: PixelColor> Framebuffer<'a, C> {
    /// A framebuffer over `pixels`; `None` when the slice is too small.
    pub fn new(pixels: &'a mut [C], width: u32, height: u32) -> Option<Self> {
        (pixels.len() >= width as usize * height as usize).then_some(Framebuffer {
            pixels,
            width,
            height,
        })
    }

    fn index(&self, x: i32, y: i32) -> Option<usize> {
        let inside = x >= 0 && y >= 0 && (x as u32) < self.width && (y as u32) < self.height;
        inside.then(|| y as usize * self.width as usize + x as usize)
    }
}

impl<C: PixelColor> OriginDimensions for Framebuffer<'_, C> {
    fn size(&self) -> Size {
        Size::new(self.width, self.height)
    }
}

impl<C: PixelColor> DrawTarget for Framebuffer<'_, C> {
    type Color = C;
    type Error = Infallible;

    fn draw_iter<I>(&mut self, pixels: I) -> Result<(), Infallible>
    where
        I: IntoIterator<Item = Pixel<C>>,
    {
        for Pixel(p, c) in pixels {
            if let Some(i) = self.index(p.x, p.y) {
                self.pixels[i] = c;
            }
        }
        Ok(())
    }

    fn fill_contiguous<I>(&mut self, area: &Rectangle, colors: I) -> Result<(), Infallible>
    where
        I: IntoIterator<Item = C>,
    {
        // A run along one row, wholly inside: straight copy.
        let row = area.size.height == 1 && area.size.width > 0;
        let first = self.index(area.top_left.x, area.top_left.y);
        let last = self.index(
            area.top_left.x + area.size.width as i32 - 1,
            area.top_left.y,
        );
        if let (true, Some(i), Some(_)) = (row, first, last) {
            let run = &mut self.pixels[i..i + area.size.width as usize];
            for (p, c) in run.iter_mut().zip(colors) {
                *p = c;
            }
            return Ok(());
        }
        self.draw_iter(area.points().zip(colors).map(|(p, c)| Pixel(p, c)))
    }
}
