//! The renderer under arbitrary input: bytes give triangles (any `f32` bits, indices out of
//! range), a camera, a style, a band height and a target that may be smaller or larger than
//! the viewport, may start anywhere in it, and may fail after some pixels. Viewports reach
//! tens of thousands of pixels (feature `large-viewports`, a default one), so that corners
//! take the 64-bit spans, while the target, and so the work, stays small.
//!
//! What must hold: no panic; every pixel sent lies in the target and the viewport; the same
//! draw twice sends the same pixels; the final image does not depend on the band height; a
//! failing target stops the draw with its error.

use std::collections::HashMap;

use embedded_graphics::draw_target::DrawTarget;
use embedded_graphics::geometry::Dimensions;
use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::prelude::{Pixel, Point, Size};
use embedded_graphics::primitives::Rectangle;
use spline_tess::render::{
    IndexedMesh, Light, RenderError, RenderStats, Renderer, Shading, Style, Wireframe,
};
use spline_tess::Arithmetic;
use spline_tess::{Camera, Projection, Vec3, Vertex};

use super::bytes::Bytes;

/// A target that records the last colour of every pixel, checks bounds, and fails after
/// `fail_after` pixels if asked to.
struct Recorder {
    area: Rectangle,
    viewport: [u32; 2],
    image: HashMap<(i32, i32), Rgb888>,
    sent: u64,
    fail_after: Option<u64>,
}

#[derive(Debug, PartialEq)]
struct Refused;

impl Dimensions for Recorder {
    fn bounding_box(&self) -> Rectangle {
        self.area
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
                self.area.contains(p)
                    && p.x >= 0
                    && p.y >= 0
                    && (p.x as u32) < self.viewport[0]
                    && (p.y as u32) < self.viewport[1],
                "pixel {p:?} outside the target {:?} or the viewport {:?}",
                self.area,
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
    area: Rectangle,
    band_values: usize,
    fail_after: Option<u64>,
    arithmetic: Arithmetic,
) -> (Result<RenderStats, RenderError<Refused>>, Recorder) {
    let mut target = Recorder {
        area,
        viewport: camera.viewport(),
        image: HashMap::new(),
        sent: 0,
        fail_after,
    };
    let mut depth = vec![0u16; band_values];
    let result = Renderer::new(&mut depth).with_arithmetic(arithmetic).draw(
        mesh,
        camera,
        style,
        &mut target,
    );
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
    let mut viewport = [(r.u8() % 97) as u32, (r.u8() % 97) as u32];
    let camera_at = |viewport| Camera::new(eye, target, up, projection, near, viewport);
    if camera_at(viewport).is_err() {
        return;
    }
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
    // Either set-up of the depth and shade, by the band's parity.
    let arithmetic = match band_values % 2 {
        0 => Arithmetic::Float,
        _ => Arithmetic::Integer,
    };
    let stop = r.u8();
    // Past the bytes the target read before its viewports grew (0 past the end: what it did
    // then): a viewport up to 300 times larger, and a target that starts anywhere in it.
    let scale = [1, 7, 60, 300][r.u8() as usize % 4];
    viewport = viewport.map(|v| v * scale);
    let start = [r.u16(), r.u16()];
    let top_left = Point::new(
        (u32::from(start[0]) % viewport[0].max(1)) as i32,
        (u32::from(start[1]) % viewport[1].max(1)) as i32,
    );
    let Ok(camera) = camera_at(viewport) else {
        return;
    };
    let area = Rectangle::new(top_left, size);
    let (first, image) = draw(&mesh, &camera, &style, area, band_values, None, arithmetic);
    let (second, again) = draw(&mesh, &camera, &style, area, band_values, None, arithmetic);
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
    // The whole drawn area (within the target) as one band gives the same image.
    let whole = (size.width as usize + 1) * (size.height as usize + 1);
    let (one_band, whole_image) = draw(&mesh, &camera, &style, area, whole, None, arithmetic);
    let one_band = one_band.expect("a larger depth buffer draws too");
    assert!(one_band.bands <= 1, "{one_band:?}");
    assert!(
        whole_image.image == image.image,
        "the image depends on the band height"
    );
    // A target that fails stops the draw with its error.
    if image.sent > 0 {
        let stop = u64::from(stop) % image.sent;
        let (failed, partial) = draw(
            &mesh,
            &camera,
            &style,
            area,
            band_values,
            Some(stop),
            arithmetic,
        );
        assert_eq!(failed, Err(RenderError::Target(Refused)));
        assert_eq!(partial.sent, stop);
    }
}
