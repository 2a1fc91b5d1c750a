// A model of an SPI display for the firmware demo, `no_std`: a `DrawTarget` that stands for a
// panel behind a driver such as mipidsi, where every `fill_contiguous` becomes one address
// window and a stream of Rgb565 pixels (two bytes each). It keeps no pixels: it counts the
// windows and bytes of a frame, hashes the pixel stream in order, and checks that the windows
// tile the screen top to bottom, so that no pixel is sent twice or left out. The host test
// that writes the firmware's expected checksums uses it too (through `#[path]`).
// Hand-written.

use core::convert::Infallible;

use embedded_graphics::draw_target::DrawTarget;
use embedded_graphics::pixelcolor::raw::{RawData, RawU16};
use embedded_graphics::pixelcolor::Rgb565;
use embedded_graphics::prelude::{OriginDimensions, Pixel, Point, Size};
use embedded_graphics::primitives::Rectangle;

/// What one frame sent to the display.
pub struct SpiDisplay {
    width: u32,
    height: u32,
    /// Address windows set.
    pub windows: u32,
    /// Pixel bytes sent.
    pub bytes: u32,
    hash: u32,
    /// The row the next window must start at for the windows to tile the screen.
    next_row: u32,
    tiled: bool,
}

impl SpiDisplay {
    /// A `width x height` panel.
    pub fn new(width: u32, height: u32) -> Self {
        SpiDisplay {
            width,
            height,
            windows: 0,
            bytes: 0,
            hash: 0x811c_9dc5,
            next_row: 0,
            tiled: true,
        }
    }

    /// Starts counting a new frame.
    pub fn begin_frame(&mut self) {
        *self = SpiDisplay::new(self.width, self.height);
    }

    /// Pixels sent this frame.
    pub fn pixels_pushed(&self) -> u32 {
        self.bytes / 2
    }

    /// Hash of the raw Rgb565 values sent this frame, in order: FNV-1a with one step per
    /// 16-bit pixel. It is counted in the render's instructions: about 8 per pixel on the
    /// Cortex-M4, 0.45M of a 240x240 frame (measured 2026-11-24 with `scripts/fw_profile.py`).
    pub fn checksum(&self) -> u32 {
        self.hash
    }

    /// Whether this frame's windows were full-width bands, top to bottom, covering the
    /// screen once.
    pub fn tiled_once(&self) -> bool {
        self.tiled && self.next_row == self.height && self.bytes == 2 * self.width * self.height
    }

    fn send(&mut self, c: Rgb565) {
        self.bytes += 2;
        self.hash = fnv_step(self.hash, c);
    }
}

/// One FNV-1a step over a 16-bit pixel.
#[inline(always)]
fn fnv_step(hash: u32, c: Rgb565) -> u32 {
    (hash ^ RawU16::from(c).into_inner() as u32).wrapping_mul(0x0100_0193)
}

impl OriginDimensions for SpiDisplay {
    fn size(&self) -> Size {
        Size::new(self.width, self.height)
    }
}

impl DrawTarget for SpiDisplay {
    type Color = Rgb565;
    type Error = Infallible;

    /// Pixel by pixel: a one-pixel window each (what a driver does for `draw_iter`).
    fn draw_iter<I>(&mut self, pixels: I) -> Result<(), Infallible>
    where
        I: IntoIterator<Item = Pixel<Rgb565>>,
    {
        for Pixel(_, c) in pixels {
            self.windows += 1;
            self.tiled = false;
            self.send(c);
        }
        Ok(())
    }

    fn fill_contiguous<I>(&mut self, area: &Rectangle, colors: I) -> Result<(), Infallible>
    where
        I: IntoIterator<Item = Rgb565>,
    {
        self.windows += 1;
        let band =
            area.top_left == Point::new(0, self.next_row as i32) && area.size.width == self.width;
        self.tiled &= band;
        self.next_row += area.size.height;
        let n = (area.size.width * area.size.height) as usize;
        // The hash in a local: through `self`, each pixel would store it (and the byte count)
        // back to memory, which doubled this loop's instructions on the Cortex-M4.
        let (mut hash, mut sent) = (self.hash, 0u32);
        for c in colors.into_iter().take(n) {
            hash = fnv_step(hash, c);
            sent += 1;
        }
        self.hash = hash;
        self.bytes += 2 * sent;
        Ok(())
    }
}
