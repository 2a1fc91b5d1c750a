// A model of an SPI display for the firmware demo, `no_std`: it stands for a panel behind a
// driver such as mipidsi, where every band becomes one address window and a stream of
// big-endian Rgb565 bytes (two per pixel). It keeps no pixels: it counts the windows and bytes
// of a frame, hashes the byte stream in order, and checks that the windows tile the screen top
// to bottom, so that no pixel is sent twice or left out. Bands come as bytes
// ([`SpiDisplay::push_band`], what a DMA transfer takes) or as colours through `DrawTarget`;
// both hash the same bytes. The host test that writes the firmware's expected checksums uses
// it too (through `#[path]`). Hand-written.

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
    /// Bytes after the last hashed word, waiting for the rest of it.
    pending: [u8; 4],
    pending_len: usize,
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
            pending: [0; 4],
            pending_len: 0,
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

    /// Hash of the bytes sent this frame, in order: one step ([`hash_step`]) per 32-bit
    /// little-endian word of four bytes (two pixels), and a last step for the bytes of a word
    /// left incomplete. It is counted in the render's instructions: about 1.2 per pixel on the
    /// Cortex-M4 when bands come as bytes (measured with `scripts/fw_profile.py`, 2026-11-26;
    /// FNV-1a's steps took about 2.3, and a step per pixel through `fill_contiguous`'s colour
    /// iterator about 8).
    pub fn checksum(&self) -> u32 {
        match self.pending_len {
            0 => self.hash,
            n => {
                let mut word = [0; 4];
                word[..n].copy_from_slice(&self.pending[..n]);
                hash_step(self.hash, u32::from_le_bytes(word))
            }
        }
    }

    /// Whether this frame's windows were full-width bands, top to bottom, covering the
    /// screen once.
    pub fn tiled_once(&self) -> bool {
        self.tiled && self.next_row == self.height && self.bytes == 2 * self.width * self.height
    }

    /// Sets the address window to `area` (a band, for the windows to tile the screen) and
    /// sends `bytes`, big-endian Rgb565 row by row: what a DMA transfer of a band does.
    pub fn push_band(&mut self, area: &Rectangle, bytes: &[u8]) {
        self.window(area);
        self.send(bytes);
    }

    /// Counts an address window over `area`.
    fn window(&mut self, area: &Rectangle) {
        self.windows += 1;
        let band =
            area.top_left == Point::new(0, self.next_row as i32) && area.size.width == self.width;
        self.tiled &= band;
        self.next_row += area.size.height;
    }

    /// Sends `bytes` and hashes them.
    fn send(&mut self, mut bytes: &[u8]) {
        self.bytes += bytes.len() as u32;
        if self.pending_len > 0 {
            let take = (4 - self.pending_len).min(bytes.len());
            self.pending[self.pending_len..self.pending_len + take].copy_from_slice(&bytes[..take]);
            self.pending_len += take;
            bytes = &bytes[take..];
            if self.pending_len < 4 {
                return;
            }
            self.hash = hash_step(self.hash, u32::from_le_bytes(self.pending));
            self.pending_len = 0;
        }
        let whole = bytes.len() - bytes.len() % 4;
        let (words, rest) = bytes.split_at(whole);
        self.hash = hash_words(self.hash, words);
        self.pending[..rest.len()].copy_from_slice(rest);
        self.pending_len = rest.len();
    }

    /// Sends one pixel.
    fn send_pixel(&mut self, c: Rgb565) {
        self.send(&RawU16::from(c).into_inner().to_be_bytes());
    }
}

/// The hash after the whole words of `bytes` (a multiple of 4 long). Not inlined: in a
/// caller's loop with its own values in registers, the multiplier was loaded again for every
/// word.
#[inline(never)]
fn hash_words(mut hash: u32, bytes: &[u8]) -> u32 {
    for w in bytes.chunks_exact(4) {
        hash = hash_step(hash, u32::from_le_bytes([w[0], w[1], w[2], w[3]]));
    }
    hash
}

/// One step of the hash over a 32-bit word: a multiply-add, so that the whole is the
/// polynomial `Σ word_i P^(n-i)` modulo `2^32` (with FNV's odd prime `P`, every power of it is
/// odd, so a change of any one word always changes the hash). One instruction a word on the
/// Cortex-M4 (FNV-1a's `xor` then multiply took two, and the hash is counted in the render's
/// instructions).
#[inline(always)]
fn hash_step(hash: u32, word: u32) -> u32 {
    hash.wrapping_mul(0x0100_0193).wrapping_add(word)
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
            self.send_pixel(c);
        }
        Ok(())
    }

    /// One window, its pixels sent one by one.
    fn fill_contiguous<I>(&mut self, area: &Rectangle, colors: I) -> Result<(), Infallible>
    where
        I: IntoIterator<Item = Rgb565>,
    {
        self.window(area);
        let n = (area.size.width * area.size.height) as usize;
        for c in colors.into_iter().take(n) {
            self.send_pixel(c);
        }
        Ok(())
    }
}
