// What `fw_teapot` draws, shared (through `#[path]`) with the host test that writes its
// expected checksums (host-tests/tests/firmware_data.rs): the views, the styles, one frame's
// update and band-by-band rendering into an Rgb565 framebuffer, and the checksum. Uses the
// teapot bake, storage and settings of `fw_tessellate_frames.rs` (module `frames` beside this
// one). `no_std`, no allocation. Hand-written.

use embedded_graphics::pixelcolor::raw::RawU16;
use embedded_graphics::pixelcolor::{Rgb565, Rgb888};
use embedded_graphics::prelude::RawData;
use spline_tess::render::{RenderStats, Renderer, Shading, Style, Wireframe};
use spline_tess::{Camera, FrameStats, Projection, Tessellator, Vec3, View};

use super::framebuffer::Framebuffer;
use super::frames::Fnv;

/// Display size.
pub const WIDTH: u32 = 240;
/// Display size.
pub const HEIGHT: u32 = 240;
/// Rows per band: the depth buffer holds `WIDTH * BAND_ROWS` values.
pub const BAND_ROWS: u32 = 16;
/// Pixels of the framebuffer.
pub const PIXELS: usize = (WIDTH * HEIGHT) as usize;
/// Depth values of one band.
pub const DEPTH: usize = (WIDTH * BAND_ROWS) as usize;

/// The frames: eye, tolerance in pixels, shading, wireframe. All look at the teapot's middle.
pub const FRAMES: [([f32; 3], f32, Shading, bool); 4] = [
    ([9.0, -12.0, 7.0], 1.0, Shading::Gouraud, false),
    ([9.2, -11.85, 7.0], 1.0, Shading::Gouraud, true),
    ([5.0, -6.5, 4.0], 1.0, Shading::Flat, false),
    ([2.6, -3.4, 2.6], 1.0, Shading::Gouraud, true),
];

/// The camera of frame `k`.
pub fn camera(k: usize) -> Option<Camera> {
    let (eye, ..) = FRAMES.get(k).copied()?;
    Camera::new(
        Vec3::from_array(eye),
        Vec3::new(0.0, 0.0, 1.5),
        Vec3::Z,
        Projection::Perspective {
            fov_y_degrees: 40.0,
        },
        0.05,
        [WIDTH, HEIGHT],
    )
    .ok()
}

/// The style of frame `k`.
pub fn style(k: usize) -> Option<Style> {
    let (_, _, shading, wire) = FRAMES.get(k).copied()?;
    Some(Style {
        shading,
        color: Rgb888::new(222, 196, 150),
        wireframe: wire.then_some(Wireframe {
            color: Rgb888::new(60, 40, 30),
            half_width: 0.35,
        }),
        background: Some(Rgb888::new(24, 28, 40)),
        ..Style::default()
    })
}

/// Brings `tess` to frame `k`.
pub fn update(tess: &mut Tessellator<'_, '_>, k: usize) -> Option<FrameStats> {
    let camera = camera(k)?;
    let tolerance_px = FRAMES.get(k)?.1;
    tess.update(&View::Screen {
        camera,
        tolerance_px,
    })
    .ok()
}

/// Draws `tess`'s current frame as frame `k` into `pixels` (`WIDTH * HEIGHT`), band by band
/// with `depth` (`WIDTH * BAND_ROWS`).
pub fn render(
    tess: &Tessellator<'_, '_>,
    k: usize,
    pixels: &mut [Rgb565],
    depth: &mut [u16],
) -> Option<RenderStats> {
    let camera = camera(k)?;
    let style = style(k)?;
    let mut target = Framebuffer::new(pixels, WIDTH, HEIGHT)?;
    let depth = depth.get_mut(..DEPTH)?;
    Renderer::new(depth)
        .draw(tess, &camera, &style, &mut target)
        .ok()
}

/// FNV-1a of the framebuffer's raw Rgb565 values.
pub fn checksum(pixels: &[Rgb565]) -> u32 {
    let mut h = Fnv(0x811c_9dc5);
    for p in pixels {
        h.word(RawU16::from(*p).into_inner() as u32);
    }
    h.0
}
