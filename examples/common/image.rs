//! RGB images on the host: PNG output and a contact sheet of several frames.

use std::io::BufWriter;
use std::path::Path;

use embedded_graphics::pixelcolor::{Rgb888, RgbColor};

/// An RGB image.
#[derive(Clone)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<Rgb888>,
}

impl Image {
    /// An image filled with `color`.
    pub fn new(width: u32, height: u32, color: Rgb888) -> Self {
        Image {
            width,
            height,
            pixels: vec![color; width as usize * height as usize],
        }
    }

    /// Writes the image as an 8-bit RGB PNG, creating the folder.
    pub fn write_png(&self, path: &Path) -> Result<(), String> {
        if let Some(dir) = path.parent() {
            if !dir.as_os_str().is_empty() {
                std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
            }
        }
        let file = std::fs::File::create(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let mut encoder = png::Encoder::new(BufWriter::new(file), self.width, self.height);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_compression(png::Compression::High);
        let data: Vec<u8> = self
            .pixels
            .iter()
            .flat_map(|c| [c.r(), c.g(), c.b()])
            .collect();
        let err = |e: png::EncodingError| format!("{}: {e}", path.display());
        let mut writer = encoder.write_header().map_err(err)?;
        writer.write_image_data(&data).map_err(err)?;
        writer.finish().map_err(err)
    }

    /// This image shrunk by `factor` in each direction (box filter).
    pub fn shrink(&self, factor: u32) -> Image {
        let (w, h) = (self.width / factor, self.height / factor);
        let mut out = Image::new(w, h, Rgb888::BLACK);
        let n = factor * factor;
        for y in 0..h {
            for x in 0..w {
                let mut sum = [0u32; 3];
                for dy in 0..factor {
                    for dx in 0..factor {
                        let c = self.pixels
                            [((y * factor + dy) * self.width + x * factor + dx) as usize];
                        sum[0] += c.r() as u32;
                        sum[1] += c.g() as u32;
                        sum[2] += c.b() as u32;
                    }
                }
                let [r, g, b] = sum.map(|s| ((s + n / 2) / n) as u8);
                out.pixels[(y * w + x) as usize] = Rgb888::new(r, g, b);
            }
        }
        out
    }

    /// Tiles `frames` (all the same size) `columns` to a row with a `gap`-pixel border.
    pub fn contact_sheet(frames: &[Image], columns: u32, gap: u32, color: Rgb888) -> Option<Image> {
        let first = frames.first()?;
        let (fw, fh) = (first.width, first.height);
        let rows = (frames.len() as u32).div_ceil(columns);
        let width = columns * (fw + gap) + gap;
        let height = rows * (fh + gap) + gap;
        let mut sheet = Image::new(width, height, color);
        for (k, f) in frames.iter().enumerate() {
            let (cx, cy) = (k as u32 % columns, k as u32 / columns);
            let (ox, oy) = (gap + cx * (fw + gap), gap + cy * (fh + gap));
            for y in 0..fh.min(f.height) {
                for x in 0..fw.min(f.width) {
                    sheet.pixels[((oy + y) * width + ox + x) as usize] =
                        f.pixels[(y * f.width + x) as usize];
                }
            }
        }
        Some(sheet)
    }
}
