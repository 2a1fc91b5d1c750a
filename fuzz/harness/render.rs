//! The renderer under arbitrary input: bytes give triangles (any `f32` bits, indices out of
//! range), a camera, a style, a band height and a target that may be smaller or larger than
//! the viewport, and that may fail after some pixels.
//!
//! What must hold: no panic; every pixel sent lies in the target and the viewport; the same
//! draw twice sends the same pixels; the final image does not depend on the band height; a
//! failing target stops the draw with its error.

use std::collections::HashMap;

use embedded_graphics::draw_target::DrawTarget;
use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::prelude::{OriginDimensions, Pixel, Size};
use spline_tess::render::{
    IndexedMesh, Light, RenderError, RenderStats, Renderer, Shading, Style, Wireframe,
};
use spline_tess::{Camera, Projection, Vec3, Vertex};

use super::bytes::Bytes;

/// A target that records the last colour of every pixel, checks bounds, and fails after
/// `fail_after` pixels if asked to.
struct Recorder {
    size: Size,
    viewport: [u32; 2],
    image: HashMap<(i32, i32), Rgb888>,
    sent: u64,
    fail_after: Option<u64>,
}

#[derive(Debug, PartialEq)]
struct Refused;

impl OriginDimensions for Recorder {
    fn size(&self) -> Size {
        self.size
    }
}

impl DrawTarget for Recorder {
    type Color = Rgb888;
    type Error = Refused;

    fn draw_iter<I>(&mut self, pixels: I) -> Result<(), Refused>
    where
        I: IntoIterator<Item = Pixel<Rgb888>>,
    {
        for Pixel(p, c) in pixels {
            if self.fail_after.is_some_and(|n| self.sent >= n) {
                return Err(Refused);
            }
            assert!(
                p.x >= 0
                    && p.y >= 0
                    && (p.x as u32) < self.size.width.min(self.viewport[0])
                    && (p.y as u32) < self.size.height.min(self.viewport[1]),
                "pixel {p:?} outside the target {:?} or the viewport {:?}",
                self.size,
                self.viewport
            );
            self.image.insert((p.x, p.y), c);
            self.sent += 1;
        }
        Ok(())
    }
}

fn draw(
    mesh: &IndexedMesh<'_, u16>,
    camera: &Camera,
    style: &Style,
    size: Size,
    band_values: usize,
    fail_after: Option<u64>,
) -> (Result<RenderStats, RenderError<Refused>>, Recorder) {
    let mut target = Recorder {
        size,
        viewport: camera.viewport(),
        image: HashMap::new(),
        sent: 0,
        fail_after,
    };
    let mut depth = vec![0u16; band_values];
    let result = Renderer::new(&mut depth).draw(mesh, camera, style, &mut target);
    (result, target)
}

fn coordinate(r: &mut Bytes<'_>) -> f32 {
    match r.u8() % 8 {
        0 => r.f32_bits(),
        _ => r.i8() as f32 / 16.0,
    }
}

/// The `render` target.
pub fn render(data: &[u8]) {
    let mut r = Bytes::new(data);
    let n = 3 + r.u8() as usize % 14;
    let vertices: Vec<Vertex> = (0..n)
        .map(|_| Vertex {
            position: [coordinate(&mut r), coordinate(&mut r), coordinate(&mut r)],
            normal: [coordinate(&mut r), coordinate(&mut r), coordinate(&mut r)],
            ..Vertex::default()
        })
        .collect();
    let triangles: Vec<[u16; 3]> = (0..r.u8() % 24)
        .map(|_| [0; 3].map(|_| (r.u8() as usize % (n + 2)) as u16))
        .collect();
    let mesh = IndexedMesh {
        vertices: &vertices,
        triangles: &triangles,
    };
    let eye = Vec3::new(coordinate(&mut r), coordinate(&mut r), coordinate(&mut r)) * 2.0;
    let target = Vec3::new(coordinate(&mut r), coordinate(&mut r), coordinate(&mut r)) * 0.25;
    let up = [Vec3::Z, Vec3::Y, Vec3::X][r.u8() as usize % 3];
    let projection = if r.u8().is_multiple_of(3) {
        Projection::Orthographic {
            height: r.log_scale(4.0),
        }
    } else {
        Projection::Perspective {
            fov_y_degrees: r.u8() as f32 * 0.75,
        }
    };
    let near = r.log_scale(0.05);
    let viewport = [(r.u8() % 97) as u32, (r.u8() % 97) as u32];
    let Ok(camera) = Camera::new(eye, target, up, projection, near, viewport) else {
        return;
    };
    let style = Style {
        shading: if r.u8().is_multiple_of(2) {
            Shading::Flat
        } else {
            Shading::Gouraud
        },
        light: Light {
            direction: [coordinate(&mut r), coordinate(&mut r), coordinate(&mut r)],
            ambient: r.value(&[0.0, 1.0, -1.0, 2.0, f32::NAN], 0.2),
        },
        color: Rgb888::new(r.u8(), r.u8(), r.u8()),
        wireframe: (r.u8().is_multiple_of(2)).then(|| Wireframe {
            color: Rgb888::new(255, 0, 0),
            half_width: r.value(&[0.0, -1.0, f32::NAN, f32::INFINITY], 0.5),
        }),
        background: (r.u8().is_multiple_of(3)).then(|| Rgb888::new(1, 2, 3)),
    };
    let size = Size::new((r.u8() % 112) as u32, (r.u8() % 112) as u32);
    let band_values = r.u16() as usize % 4096;
    let (first, image) = draw(&mesh, &camera, &style, size, band_values, None);
    let (second, again) = draw(&mesh, &camera, &style, size, band_values, None);
    assert_eq!(first, second, "the same draw twice differs");
    assert!(
        image.image == again.image && image.sent == again.sent,
        "the same draw twice differs"
    );
    let Ok(stats) = first else {
        return;
    };
    assert_eq!(
        u64::from(stats.pixels) + u64::from(stats.background),
        image.sent
    );
    // The whole drawn area as one band gives the same image.
    let whole = (viewport[0] as usize + 1) * (viewport[1] as usize + 1);
    let (one_band, whole_image) = draw(&mesh, &camera, &style, size, whole, None);
    let one_band = one_band.expect("a larger depth buffer draws too");
    assert!(one_band.bands <= 1, "{one_band:?}");
    assert!(
        whole_image.image == image.image,
        "the image depends on the band height"
    );
    // A target that fails stops the draw with its error.
    if image.sent > 0 {
        let stop = u64::from(r.u8()) % image.sent;
        let (failed, partial) = draw(&mesh, &camera, &style, size, band_values, Some(stop));
        assert_eq!(failed, Err(RenderError::Target(Refused)));
        assert_eq!(partial.sent, stop);
    }
}
