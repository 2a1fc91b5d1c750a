//! Drawing the tessellation onto an [`embedded_graphics`] `DrawTarget` (feature
//! `embedded-graphics`).
//!
//! The [`Renderer`] rasterises in horizontal bands: it owns no memory, only the caller's depth
//! buffer, and a 240-pixel-wide display drawn in 16-row bands needs `240 * 16` depth values
//! (7.5 KiB), not a frame's worth. For every band it asks its [`TriangleSource`] for the
//! triangles that may reach the band: a [`Tessellator`](crate::Tessellator) streams them
//! straight from its domain meshes (patches off the band skipped by their bounding spheres),
//! so no mesh buffer is needed; an [`IndexedMesh`] draws what
//! [`write_mesh`](crate::Tessellator::write_mesh) wrote, for callers with the RAM to keep it.
//!
//! Each triangle is clipped in view space (the near plane, and a guard band at twice the
//! viewport), snapped to 1/16 pixel and scan-converted with exact integer edge functions and
//! the top-left fill rule, so triangles that share an edge never draw a pixel twice and never
//! leave a gap between them. Depth is a `u16` per pixel, linear in `1/z` between the nearest
//! and farthest point of the source's bounding sphere. Pixels that pass the depth test go to
//! the target in runs along a row, one
//! [`fill_contiguous`](embedded_graphics::draw_target::DrawTarget::fill_contiguous) per run.
//!
//! Colours are computed as [`Rgb888`] and converted to the target's colour type (any RGB type
//! of `embedded-graphics`: `Rgb565`, `Rgb888`, `Bgr565`, ...). Shading is flat (one normal per
//! triangle) or Gouraud (vertex normals, shade interpolated), lit from one directional light,
//! two-sided. A wireframe overlay draws each triangle's edges inside the same pass.
//!
//! ```
//! use embedded_graphics::mock_display::MockDisplay;
//! use embedded_graphics::pixelcolor::{Rgb565, Rgb888};
//! use spline_tess::render::{IndexedMesh, Renderer, Shading, Style};
//! use spline_tess::{Camera, Projection, Vec3, Vertex};
//!
//! // A unit square facing the camera, as two triangles.
//! let corner = |x: f32, y: f32| Vertex {
//!     position: [x, y, 0.0],
//!     normal: [0.0, 0.0, 1.0],
//!     ..Vertex::default()
//! };
//! let vertices = [corner(-1.0, -1.0), corner(1.0, -1.0), corner(1.0, 1.0), corner(-1.0, 1.0)];
//! let triangles = [[0u16, 1, 2], [0, 2, 3]];
//! let mesh = IndexedMesh { vertices: &vertices, triangles: &triangles };
//!
//! let camera = Camera::new(
//!     Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, Vec3::Y,
//!     Projection::Orthographic { height: 4.0 }, 0.1, [32, 32],
//! )?;
//! let mut display = MockDisplay::<Rgb565>::new(); // panics if a pixel is drawn twice
//! let mut depth = [0u16; 32 * 8]; // 8-row bands
//! let style = Style { shading: Shading::Flat, ..Style::default() };
//! let stats = Renderer::new(&mut depth).draw(&mesh, &camera, &style, &mut display).unwrap();
//!
//! // The square covers the middle half of the view: 16 x 16 pixels, each drawn once.
//! assert_eq!(stats.pixels, 16 * 16);
//! assert_eq!(stats.bands, 4);
//! assert!(display.get_pixel(embedded_graphics::prelude::Point::new(16, 16)).is_some());
//! assert!(display.get_pixel(embedded_graphics::prelude::Point::new(4, 4)).is_none());
//! # Ok::<(), spline_tess::CameraError>(())
//! ```

mod clip;
mod raster;
mod source;

use core::fmt;
use core::ops::Range;

use embedded_graphics::draw_target::DrawTarget;
use embedded_graphics::pixelcolor::{Rgb888, RgbColor};
use embedded_graphics::prelude::{Point, Size};
use embedded_graphics::primitives::Rectangle;
use glam::Vec3;

use crate::bound::BoundingSphere;
use crate::math::normalize;
use crate::sink::{TriangleSink, Vertex};
use crate::view::{Camera, Projection};
use clip::{ClipVertex, Frustum};
use raster::{ScreenVertex, Span, Triangle};
pub use source::{IndexedMesh, TriangleSource};

/// How a triangle's colour varies.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Shading {
    /// One shade per triangle, from its geometric normal.
    Flat,
    /// Shades at the corners from the vertex normals, interpolated across.
    #[default]
    Gouraud,
}

/// A directional light, fixed to the camera.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Light {
    /// Direction towards the light in view coordinates: x right, y up, z away from the eye.
    /// Need not be unit length; zero means a headlight.
    pub direction: [f32; 3],
    /// Shade of a surface facing away from the light, in `[0, 1]`.
    pub ambient: f32,
}

impl Default for Light {
    /// From above left of the eye, with 0.2 ambient.
    fn default() -> Self {
        Light {
            direction: [-0.4, 0.6, -0.7],
            ambient: 0.2,
        }
    }
}

/// Triangle edges drawn over the shading.
///
/// (With feature `defmt`, this and [`Style`] implement `defmt::Format` by hand:
/// `embedded-graphics` colours support only the older defmt.)
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wireframe {
    /// Line colour.
    pub color: Rgb888,
    /// Pixels within this distance of an edge, on either side, take the line colour (0.5 gives
    /// lines about one pixel wide).
    pub half_width: f32,
}

/// What the renderer draws with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Style {
    /// Flat or Gouraud.
    pub shading: Shading,
    /// The light.
    pub light: Light,
    /// Surface colour at full light.
    pub color: Rgb888,
    /// Edges to overlay, if any.
    pub wireframe: Option<Wireframe>,
    /// Colour for the pixels no triangle covers; `None` leaves them untouched (clear the
    /// target first).
    pub background: Option<Rgb888>,
}

impl Default for Style {
    /// Gouraud, the default light, a light grey surface, no wireframe, no background.
    fn default() -> Self {
        Style {
            shading: Shading::Gouraud,
            light: Light::default(),
            color: Rgb888::new(230, 230, 230),
            wireframe: None,
            background: None,
        }
    }
}

/// Why a frame could not be drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum RenderError<E> {
    /// The depth buffer holds less than one row of the drawn area.
    DepthTooSmall {
        /// Depth values needed for one row.
        needed: usize,
    },
    /// The camera's viewport is wider or taller than [`MAX_VIEWPORT`] pixels (the fixed-point
    /// edge functions are exact up to there).
    ViewportTooLarge,
    /// The target failed; drawing stopped there.
    Target(E),
}

/// Largest viewport width or height the renderer draws, in pixels.
pub const MAX_VIEWPORT: u32 = 1 << 20;

impl<E: fmt::Debug> fmt::Display for RenderError<E> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RenderError::DepthTooSmall { needed } => {
                write!(f, "depth buffer smaller than one row ({needed} values)")
            }
            RenderError::ViewportTooLarge => {
                write!(f, "viewport larger than {MAX_VIEWPORT} pixels")
            }
            RenderError::Target(e) => write!(f, "draw target failed: {e:?}"),
        }
    }
}

impl<E: fmt::Debug> core::error::Error for RenderError<E> {}

/// What a frame cost.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RenderStats {
    /// Bands drawn.
    pub bands: u32,
    /// Triangles handed over by the source, summed over the bands.
    pub triangles: u32,
    /// Triangle pixels sent to the target (a pixel nearer than an earlier one is sent again).
    pub pixels: u32,
    /// `fill_contiguous` calls for those pixels.
    pub runs: u32,
    /// Background pixels sent.
    pub background: u32,
}

/// Draws triangle sources onto `DrawTarget`s, band by band, with a caller depth buffer.
#[derive(Debug)]
pub struct Renderer<'d> {
    depth: &'d mut [u16],
}

impl<'d> Renderer<'d> {
    /// A renderer over `depth`. Its length sets the band: `depth.len() / width` rows, where
    /// `width` is the drawn area's width (the camera's viewport, cut to the target).
    pub fn new(depth: &'d mut [u16]) -> Self {
        Renderer { depth }
    }

    /// Draws `source` as `camera` sees it onto `target`.
    ///
    /// The drawn area is the camera's viewport (pixel `(0, 0)` at the top left) cut to the
    /// target's bounding box. Triangle pixels are drawn where they are nearer than what the
    /// band has so far; with [`Style::background`] every other pixel of the area is drawn
    /// too. On a target error, drawing stops and the error is returned.
    pub fn draw<S, D>(
        &mut self,
        source: &S,
        camera: &Camera,
        style: &Style,
        target: &mut D,
    ) -> Result<RenderStats, RenderError<D::Error>>
    where
        S: TriangleSource,
        D: DrawTarget,
        D::Color: From<Rgb888>,
    {
        let [vw, vh] = camera.viewport();
        if vw > MAX_VIEWPORT || vh > MAX_VIEWPORT {
            return Err(RenderError::ViewportTooLarge);
        }
        let bb = target.bounding_box();
        let clamp = |v: i64| v.clamp(0, i32::MAX as i64) as i32;
        let x0 = clamp(bb.top_left.x as i64);
        let y0 = clamp(bb.top_left.y as i64);
        let x1 = clamp(bb.top_left.x as i64 + bb.size.width as i64).min(clamp(vw as i64));
        let y1 = clamp(bb.top_left.y as i64 + bb.size.height as i64).min(clamp(vh as i64));
        let mut stats = RenderStats::default();
        if x0 >= x1 || y0 >= y1 {
            return Ok(stats);
        }
        let width = (x1 - x0) as usize;
        let band_rows = self.depth.len() / width;
        if band_rows == 0 {
            return Err(RenderError::DepthTooSmall { needed: width });
        }
        let setup = Setup::new(camera, source.bound(), style);
        let mut top = y0;
        while top < y1 {
            let bottom = (top as i64 + band_rows as i64).min(y1 as i64) as i32;
            let depth = &mut self.depth[..width * (bottom - top) as usize];
            depth.fill(0);
            stats.bands += 1;
            let mut band = Band {
                setup: &setup,
                depth,
                columns: x0..x1,
                rows: top..bottom,
                target: &mut *target,
                error: None,
                stats: &mut stats,
            };
            if setup.depth.is_some() {
                source.stream_rows(camera, top as u32..bottom as u32, &mut band);
            }
            if let Some(e) = band.error.take() {
                return Err(RenderError::Target(e));
            }
            if let Some(bg) = style.background {
                band.fill_background(bg.into())
                    .map_err(RenderError::Target)?;
            }
            top = bottom;
        }
        Ok(stats)
    }
}

/// Per-frame constants.
struct Setup<'a> {
    camera: &'a Camera,
    style: &'a Style,
    frustum: Frustum,
    /// `key = offset + scale * q`, with `q = 1/z` (perspective) or `z` (orthographic).
    depth: Option<(f32, f32)>,
    light: Vec3,
    perspective: bool,
}

impl<'a> Setup<'a> {
    fn new(camera: &'a Camera, bound: Option<BoundingSphere>, style: &'a Style) -> Self {
        let perspective = matches!(camera.projection(), Projection::Perspective { .. });
        let near = camera.near();
        let depth = bound.and_then(|s| {
            let zc = camera.to_view(s.center).z;
            let zn = (zc - s.radius).max(near);
            let zf = (zc + s.radius).max(zn);
            let (qn, qf) = if perspective {
                (1.0 / zn, 1.0 / zf)
            } else {
                (zn, zf)
            };
            // Keys 1 (far) to 65535 (near); 0 is an empty pixel.
            let scale = if qn != qf { 65534.0 / (qn - qf) } else { 0.0 };
            let ok = scale.is_finite() && zc.is_finite();
            ok.then_some((1.0 - qf * scale, scale))
        });
        let light = normalize(Vec3::from_array(style.light.direction)).unwrap_or(-Vec3::Z);
        Setup {
            camera,
            style,
            frustum: Frustum::new(near, camera.half_extent(), perspective),
            depth,
            light,
            perspective,
        }
    }

    /// Shade of a surface with view-space normal `n` (any length) seen at view position `at`.
    fn shade(&self, n: Vec3, at: Vec3) -> f32 {
        let Some(n) = normalize(n) else {
            return self.style.light.ambient;
        };
        let towards_eye = if self.perspective { -at } else { -Vec3::Z };
        let n = if n.dot(towards_eye) < 0.0 { -n } else { n };
        let a = self.style.light.ambient;
        a + (1.0 - a) * n.dot(self.light).max(0.0)
    }

    fn depth_key(&self, z: f32) -> f32 {
        let (offset, scale) = self.depth.unwrap_or((0.0, 0.0));
        let q = if self.perspective { 1.0 / z } else { z };
        offset + scale * q
    }
}

/// One band being drawn: the sink the source streams into.
struct Band<'a, 'b, D: DrawTarget> {
    setup: &'a Setup<'a>,
    depth: &'b mut [u16],
    columns: Range<i32>,
    rows: Range<i32>,
    target: &'b mut D,
    error: Option<D::Error>,
    stats: &'b mut RenderStats,
}

impl<D> TriangleSink for Band<'_, '_, D>
where
    D: DrawTarget,
    D::Color: From<Rgb888>,
{
    fn triangle(&mut self, _patch: u32, corners: [&Vertex; 3]) {
        if self.error.is_some() {
            return;
        }
        self.stats.triangles += 1;
        let setup = self.setup;
        let camera = setup.camera;
        let view = corners.map(|c| camera.to_view(Vec3::from_array(c.position)));
        let shade = match setup.style.shading {
            Shading::Gouraud => [0, 1, 2].map(|i| {
                let n = camera.rotate_to_view(Vec3::from_array(corners[i].normal));
                setup.shade(n, view[i])
            }),
            Shading::Flat => {
                let n = (view[1] - view[0]).cross(view[2] - view[0]);
                [setup.shade(n, (view[0] + view[1] + view[2]) / 3.0); 3]
            }
        };
        let wire = setup.style.wireframe.is_some();
        let t = [0, 1, 2].map(|i| ClipVertex {
            view: view[i],
            shade: shade[i],
        });
        let poly = setup.frustum.clip(t, [wire; 3]);
        // Project only the polygon's corners (usually 3 of the 8 slots).
        let n = poly.len;
        let mut screen = [ScreenVertex::default(); clip::MAX_CORNERS];
        for (s, c) in screen.iter_mut().zip(&poly.corners[..n]) {
            *s = ScreenVertex {
                xy: camera.view_to_pixel(c.view),
                depth: setup.depth_key(c.view.z),
                shade: c.shade,
            };
        }
        for k in 1..n.saturating_sub(1) {
            let edges = [
                poly.wire[k],
                k + 2 == n && poly.wire[n - 1],
                k == 1 && poly.wire[0],
            ];
            if let Some(tri) = Triangle::new([screen[0], screen[k], screen[k + 1]], edges) {
                if let Err(e) = self.rasterise(&tri) {
                    self.error = Some(e);
                    return;
                }
            }
        }
    }
}

impl<D> Band<'_, '_, D>
where
    D: DrawTarget,
    D::Color: From<Rgb888>,
{
    fn rasterise(&mut self, tri: &Triangle) -> Result<(), D::Error> {
        let [first, last] = tri.rows();
        let width = self.columns.len();
        for row in first.max(self.rows.start)..=last.min(self.rows.end - 1) {
            let Some(span) = tri.span(row, self.columns.clone()) else {
                continue;
            };
            let base = (row - self.rows.start) as usize * width;
            let mut x = span.x0;
            while x < span.x1 {
                // Skip hidden pixels, then take the run of visible ones.
                let start = x;
                while x < span.x1 {
                    let i = base + (x - self.columns.start) as usize;
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
                    let area =
                        Rectangle::new(Point::new(start, row), Size::new((x - start) as u32, 1));
                    let style = self.setup.style;
                    let colors = (start..x).map(|px| color(style, &span, px).into());
                    self.target.fill_contiguous(&area, colors)?;
                    self.stats.pixels += (x - start) as u32;
                    self.stats.runs += 1;
                }
                x += 1;
            }
        }
        Ok(())
    }

    /// Draws the band's empty pixels in `color`, a run at a time.
    fn fill_background(&mut self, color: D::Color) -> Result<(), D::Error> {
        let width = self.columns.len();
        for (r, row) in self.rows.clone().enumerate() {
            let line = &self.depth[r * width..(r + 1) * width];
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
                let area = Rectangle::new(
                    Point::new(self.columns.start + start as i32, row),
                    Size::new((x - start) as u32, 1),
                );
                self.target.fill_solid(&area, color)?;
                self.stats.background += (x - start) as u32;
            }
        }
        Ok(())
    }
}

/// Depth key of pixel column `x` of `span`: 1 (far) to 65535 (near).
fn depth_key(span: &Span, x: i32) -> u16 {
    let k = span.depth.at((x - span.x0) as u32);
    (k as u16).max(1)
}

/// Colour of pixel column `x` of `span`.
fn color(style: &Style, span: &Span, x: i32) -> Rgb888 {
    let i = (x - span.x0) as u32;
    if let Some(w) = style.wireframe {
        let near_edge = span.edge.iter().any(|e| e.at(i) < w.half_width);
        if near_edge {
            return w.color;
        }
    }
    let level = (span.shade.at(i).clamp(0.0, 1.0) * 255.0 + 0.5) as u32;
    let c = style.color;
    let ch = |v: u8| ((v as u32 * level + 127) / 255) as u8;
    Rgb888::new(ch(c.r()), ch(c.g()), ch(c.b()))
}
