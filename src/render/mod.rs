//! Drawing the tessellation onto an [`embedded_graphics`] `DrawTarget` (feature
//! `embedded-graphics`).
//!
//! The [`Renderer`] rasterises in horizontal bands and owns no memory: a 240-pixel-wide display
//! drawn in 16-row bands needs a depth band of `240 * 16` values (7.5 KiB), not a frame's
//! worth, and no framebuffer:
//!
//! - [`draw_bands`](Renderer::draw_bands) renders each band into a caller colour band
//!   buffer and pushes it with one `fill_contiguous` over the band's rectangle, so every pixel
//!   reaches the display exactly once (a driver such as mipidsi turns that into one address
//!   window); [`draw_bands_rgb565`](Renderer::draw_bands_rgb565) hands each band to a
//!   callback as big-endian Rgb565 bytes instead, for DMA or async drivers;
//! - [`draw`](Renderer::draw) sends pixels run by run as they pass the depth test, for
//!   framebuffers.
//!
//! Triangles come from a [`TriangleSource`]. With a caller triangle list
//! ([`Renderer::with_triangle_list`]), the source is asked once per frame and every triangle is
//! projected once and kept in 8-byte [`ListSlot`]s (half a slot for a Gouraud-shaded
//! triangle, a slot for a flat-shaded one, and one for each corner not shared with a triangle
//! before it); each band rasterises from the list. Without one (or when the frame does not fit it), each band asks the source for the
//! triangles that may reach it: a [`Tessellator`](crate::Tessellator) streams them straight
//! from its hierarchy and pool (the patches that cannot reach the band left out), so no mesh
//! buffer is needed. An
//! [`IndexedMesh`] draws what [`write_mesh`](crate::Tessellator::write_mesh) wrote. Both ways
//! give the same pixels: positions snap to 1/16 pixel, depth keys and shades are rounded to
//! what a list entry holds, before either path rasterises.
//!
//! A tessellator names each corner it streams
//! ([`keyed_triangle`](crate::TriangleSink::keyed_triangle)); the renderer keeps 64 corners it
//! took to view space (with their shade) by name, in a two-way cache on the stack, so a vertex
//! shared by neighbouring triangles is transformed once for most of them.
//! Triangles whose corners are all inside the clip planes skip the clipper, and while the list
//! is filled, such a corner is also projected and packed once while the cache holds it. A source
//! that names corners by vertex number (a [`Tessellator`](crate::tessellator::Tessellator)) can be
//! given a vertex map instead ([`Renderer::with_vertex_map`]): every vertex is then projected
//! once and found in the list by its number.
//!
//! Where a source says a patch is one-sided ([`TriangleSource::one_sided`]: a tessellator's
//! patches of a closed model seen from outside), its triangles that face away are left out,
//! listed or streamed ([`RenderStats::culled`]): each was behind one that faces the eye, so the
//! pixels are the same, for about half the triangles' set-up.
//!
//! Each triangle is scanned row by row over its bounding box, each row's columns solved from
//! integer edge functions with one division per edge, and its depth keys and shades stepped
//! in fixed point, exact modulo `2^32`, so that a pixel's values do not depend on which band
//! or which way the triangle came.
//!
//! Each triangle is clipped in view space (the near plane, and a guard band at twice the
//! viewport), snapped to 1/16 pixel and scan-converted with exact integer edge functions and
//! the top-left fill rule, so triangles that share an edge never draw a pixel twice and never
//! leave a gap between them. Depth is a `u16` per pixel, linear in `1/z` between the nearest
//! and farthest point of the source's bounding sphere.
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

mod band;
mod clip;
mod fixed;
mod list;
mod project;
mod raster;
mod source;
mod style;
mod walk;

use core::fmt;

use embedded_graphics::draw_target::DrawTarget;
use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::prelude::{Point, Size};
use embedded_graphics::primitives::Rectangle;

use crate::view::Camera;
use crate::Arithmetic;
use band::{Band, BandOutput, BandPixels, Buffered, Rgb565Be, Runs, Typed};
pub use list::ListSlot;
use project::{CornerCache, Setup};
pub use source::{IndexedMesh, TriangleSource};
pub use style::{Light, Shading, Style, Wireframe};

/// Why a frame could not be drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum RenderError<E> {
    /// The depth buffer holds less than one row of the drawn area.
    DepthTooSmall {
        /// Depth values needed for one row.
        needed: usize,
    },
    /// The colour band buffer holds less than one row of the drawn area.
    ColorsTooSmall {
        /// Pixels needed for one row (for [`draw_bands_rgb565`](Renderer::draw_bands_rgb565),
        /// twice as many bytes).
        needed: usize,
    },
    /// The camera's viewport is wider or taller than [`MAX_VIEWPORT`] pixels (the fixed-point
    /// edge functions are exact up to there).
    ViewportTooLarge,
    /// The target failed; drawing stopped there.
    Target(E),
}

/// Largest viewport width or height the renderer draws, in pixels: 2^20 with the feature
/// `large-viewports` (a default one), 256 without it (see the crate's features).
pub const MAX_VIEWPORT: u32 = if cfg!(feature = "large-viewports") {
    1 << 20
} else {
    256
};

impl<E: fmt::Debug> fmt::Display for RenderError<E> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RenderError::DepthTooSmall { needed } => {
                write!(f, "depth buffer smaller than one row ({needed} values)")
            }
            RenderError::ColorsTooSmall { needed } => {
                write!(
                    f,
                    "colour band buffer smaller than one row ({needed} pixels)"
                )
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
    /// Times the source was asked for triangles: once with a triangle list that held the
    /// frame, once more per band for what the list did not hold, once per band without a
    /// list.
    pub passes: u32,
    /// Triangles handed over by the source, summed over the passes.
    pub triangles: u32,
    /// Screen triangles kept in the triangle list (0 when there was none). When the list
    /// holds only part of the frame, the rest is streamed band by band (`passes` counts them).
    pub listed: u32,
    /// Screen triangles left out for facing away from the eye, on a source's one-sided
    /// patches ([`TriangleSource::one_sided`]), summed over the passes.
    pub culled: u32,
    /// Slots of the triangle list they take, theirs and their corners' (see [`ListSlot`]).
    pub list_slots: u32,
    /// Triangle pixels that passed the depth test (a pixel nearer than an earlier one counts
    /// again).
    pub pixels: u32,
    /// Runs of such pixels along a row ([`draw`](Renderer::draw) sends each with one
    /// `fill_contiguous`).
    pub runs: u32,
    /// Background pixels sent by [`draw`](Renderer::draw).
    pub background: u32,
    /// Pixels pushed as whole bands by [`draw_bands`](Renderer::draw_bands) and
    /// [`draw_bands_rgb565`](Renderer::draw_bands_rgb565): each pixel of the drawn area once.
    pub pushed: u32,
}

/// Draws triangle sources band by band, with a caller depth buffer and, optionally, a caller
/// triangle list.
///
/// - [`draw`](Self::draw) sends the visible pixels to a `DrawTarget` as they are found, run
///   by run (a pixel may be sent again when a nearer triangle covers it): for framebuffers.
/// - [`draw_bands`](Self::draw_bands) renders each band into a caller colour buffer, then
///   pushes it with one `fill_contiguous` over the band's rectangle: every pixel is sent
///   exactly once, as a display driver wants it (one address window per band).
/// - [`draw_bands_rgb565`](Self::draw_bands_rgb565) does the same into big-endian Rgb565
///   bytes and hands each band to a callback, for DMA or async drivers.
///
/// Without a triangle list, every band asks its source again for the triangles that may reach
/// it (a [`Tessellator`](crate::Tessellator) evaluates their vertices again). With one
/// ([`with_triangle_list`](Self::with_triangle_list)), the source is asked once per frame:
/// each triangle is projected once, kept in 4 bytes (8 with flat shading) plus 8 for each
/// corner it does not share with a triangle before it, and every band rasterises from the
/// list.
/// When the frame has more triangles than the list holds, the list keeps the whole patches that
/// fit and every band streams the rest from the source (a source that does not hand its
/// patches in increasing order is then streamed whole, band by band, and
/// [`RenderStats::listed`] is 0). All ways give the same pixels.
#[derive(Debug)]
pub struct Renderer<'d> {
    depth: &'d mut [u16],
    list: &'d mut [ListSlot],
    map: &'d mut [u16],
    arithmetic: Arithmetic,
}

/// The drawn area and its bands.
struct Area {
    columns: [i32; 2],
    rows: [i32; 2],
    band_rows: usize,
}

impl<'d> Renderer<'d> {
    /// A renderer over `depth`, without a triangle list. The depth buffer's length sets the
    /// band: `depth.len() / width` rows, where `width` is the drawn area's width (the
    /// camera's viewport, cut to the target).
    pub fn new(depth: &'d mut [u16]) -> Self {
        Renderer {
            depth,
            list: &mut [],
            map: &mut [],
            arithmetic: Arithmetic::default(),
        }
    }

    /// A renderer over `depth` that keeps each frame's projected triangles in `list` (see
    /// the type's docs): a slot per two Gouraud-shaded triangles or per flat-shaded one, one
    /// per distinct corner, and a header per patch and per 64 triangles; about 1.25 slots a
    /// Gouraud-shaded triangle on a tessellated mesh. The teapot at 240x240 and 1 px (1,230
    /// triangles) takes about 1,500 slots. At most 65,535 slots are used (a corner's slot
    /// number is a `u16`).
    ///
    /// ```
    /// use spline_tess::render::{ListSlot, Renderer};
    /// let mut depth = [0u16; 240 * 16];
    /// let mut list = [ListSlot::default(); 512];
    /// let renderer = Renderer::with_triangle_list(&mut depth, &mut list);
    /// # let _ = renderer;
    /// ```
    pub fn with_triangle_list(depth: &'d mut [u16], list: &'d mut [ListSlot]) -> Self {
        Renderer {
            depth,
            list,
            map: &mut [],
            arithmetic: Arithmetic::default(),
        }
    }

    /// This renderer with a vertex map for its triangle list: one entry per vertex number of
    /// a source that names its corners by vertex number
    /// ([`TriangleSource::vertex_numbers`]: a [`Tessellator`](crate::tessellator::Tessellator) does,
    /// one per vertex of its bake and pool). Filling the list then projects each vertex once
    /// and finds its slot by its number, instead of keeping the last corners in a cache and
    /// looking slots up by value; the pixels are the same. A map shorter than the source's
    /// vertex numbers, or a source without them, leaves it unused.
    ///
    /// ```
    /// use spline_tess::render::{ListSlot, Renderer};
    /// let mut depth = [0u16; 240 * 8];
    /// let mut list = [ListSlot::default(); 512];
    /// let mut map = [0u16; 2000];
    /// let renderer = Renderer::with_triangle_list(&mut depth, &mut list).with_vertex_map(&mut map);
    /// # let _ = renderer;
    /// ```
    pub fn with_vertex_map(self, map: &'d mut [u16]) -> Self {
        Renderer { map, ..self }
    }

    /// This renderer with the depth and shade across each triangle set up in `arithmetic`
    /// (its planes: see [`Arithmetic`]), instead of the target's default. A host takes
    /// [`Arithmetic::Integer`] to draw the pixels a firmware without an FPU draws (the tests
    /// compare them so).
    ///
    /// ```
    /// use spline_tess::render::Renderer;
    /// use spline_tess::Arithmetic;
    /// let mut depth = [0u16; 240 * 8];
    /// let renderer = Renderer::new(&mut depth).with_arithmetic(Arithmetic::Integer);
    /// # let _ = renderer;
    /// ```
    pub fn with_arithmetic(self, arithmetic: Arithmetic) -> Self {
        Renderer { arithmetic, ..self }
    }

    /// Draws `source` as `camera` sees it onto `target`, sending visible pixels run by run.
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
        let Some(area) = self.area(camera, &target.bounding_box(), usize::MAX)? else {
            return Ok(RenderStats::default());
        };
        self.render(source, camera, style, &area, &mut Runs(target))
            .map_err(RenderError::Target)
    }

    /// Draws `source` as `camera` sees it onto `target`, one band at a time: each band is
    /// rendered into `colors` (row-major, the band's width per row) and pushed with one
    /// [`fill_contiguous`](DrawTarget::fill_contiguous) over its rectangle.
    ///
    /// The drawn area is as for [`draw`](Self::draw); a band has as many rows as both `depth`
    /// and `colors` hold. Every pixel of the area is pushed exactly once, in the
    /// [`Style::background`] colour (black when `None`) where no triangle is.
    ///
    /// ```
    /// use embedded_graphics::mock_display::MockDisplay;
    /// use embedded_graphics::pixelcolor::Rgb565;
    /// use spline_tess::render::{IndexedMesh, Renderer, Style};
    /// use spline_tess::{Camera, Projection, Vec3, Vertex};
    ///
    /// let corner = |x: f32, y: f32| Vertex {
    ///     position: [x, y, 0.0],
    ///     normal: [0.0, 0.0, 1.0],
    ///     ..Vertex::default()
    /// };
    /// let vertices = [corner(-1.0, -1.0), corner(1.0, -1.0), corner(1.0, 1.0), corner(-1.0, 1.0)];
    /// let mesh = IndexedMesh { vertices: &vertices, triangles: &[[0u16, 1, 2], [0, 2, 3]] };
    /// let camera = Camera::new(
    ///     Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, Vec3::Y,
    ///     Projection::Orthographic { height: 4.0 }, 0.1, [32, 32],
    /// )?;
    ///
    /// let mut display = MockDisplay::<Rgb565>::new(); // panics if a pixel is drawn twice
    /// let mut depth = [0u16; 32 * 8];
    /// let mut colors = [Rgb565::default(); 32 * 8];
    /// let stats = Renderer::new(&mut depth)
    ///     .draw_bands(&mesh, &camera, &Style::default(), &mut colors, &mut display)
    ///     .unwrap();
    /// assert_eq!((stats.bands, stats.pushed, stats.pixels), (4, 32 * 32, 16 * 16));
    /// # Ok::<(), spline_tess::CameraError>(())
    /// ```
    pub fn draw_bands<S, D>(
        &mut self,
        source: &S,
        camera: &Camera,
        style: &Style,
        colors: &mut [D::Color],
        target: &mut D,
    ) -> Result<RenderStats, RenderError<D::Error>>
    where
        S: TriangleSource,
        D: DrawTarget,
        D::Color: From<Rgb888>,
    {
        let bounds = target.bounding_box();
        let mut out = Buffered::new(
            Typed(colors),
            |area: &Rectangle, pixels: &Typed<'_, D::Color>| {
                let n = (area.size.width * area.size.height) as usize;
                target.fill_contiguous(area, pixels.0.iter().take(n).copied())
            },
            style,
        );
        self.draw_buffered(source, camera, style, &bounds, &mut out)
    }

    /// Like [`draw_bands`](Self::draw_bands), into `bytes` as big-endian Rgb565 (two bytes
    /// per pixel, row-major), handing each band's rectangle and bytes to `push`: what a DMA
    /// transfer to an SPI display's address window takes. The drawn area is the camera's
    /// viewport. When `push` fails, drawing stops and its error is returned.
    ///
    /// ```
    /// use spline_tess::render::{IndexedMesh, Renderer, Style};
    /// use spline_tess::{Camera, Projection, Vec3, Vertex};
    /// # let corner = |x: f32, y: f32| Vertex {
    /// #     position: [x, y, 0.0], normal: [0.0, 0.0, 1.0], ..Vertex::default()
    /// # };
    /// # let vertices = [corner(-1.0, -1.0), corner(1.0, -1.0), corner(1.0, 1.0)];
    /// # let mesh = IndexedMesh { vertices: &vertices, triangles: &[[0u16, 1, 2]] };
    /// # let camera = Camera::new(
    /// #     Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, Vec3::Y,
    /// #     Projection::Orthographic { height: 4.0 }, 0.1, [32, 32],
    /// # )?;
    /// let mut depth = [0u16; 32 * 8];
    /// let mut bytes = [0u8; 2 * 32 * 8];
    /// let mut sent = 0;
    /// Renderer::new(&mut depth)
    ///     .draw_bands_rgb565(&mesh, &camera, &Style::default(), &mut bytes, |area, band| {
    ///         // Here: set the display's address window to `area`, then send `band`.
    ///         assert_eq!(band.len() as u32, 2 * area.size.width * area.size.height);
    ///         sent += band.len();
    ///         Ok::<(), ()>(())
    ///     })
    ///     .unwrap();
    /// assert_eq!(sent, 2 * 32 * 32);
    /// # Ok::<(), spline_tess::CameraError>(())
    /// ```
    pub fn draw_bands_rgb565<S, E>(
        &mut self,
        source: &S,
        camera: &Camera,
        style: &Style,
        bytes: &mut [u8],
        mut push: impl FnMut(&Rectangle, &[u8]) -> Result<(), E>,
    ) -> Result<RenderStats, RenderError<E>>
    where
        S: TriangleSource,
    {
        let mut out = Buffered::new(
            Rgb565Be(bytes),
            |area: &Rectangle, pixels: &Rgb565Be<'_>| {
                let n = 2 * (area.size.width * area.size.height) as usize;
                push(area, pixels.0.get(..n).unwrap_or(&[]))
            },
            style,
        );
        let bounds = Rectangle::new(Point::zero(), Size::new(u32::MAX, u32::MAX));
        self.draw_buffered(source, camera, style, &bounds, &mut out)
    }

    fn draw_buffered<S, P, F, E>(
        &mut self,
        source: &S,
        camera: &Camera,
        style: &Style,
        bounds: &Rectangle,
        out: &mut Buffered<P, F>,
    ) -> Result<RenderStats, RenderError<E>>
    where
        S: TriangleSource,
        P: BandPixels,
        F: FnMut(&Rectangle, &P) -> Result<(), E>,
    {
        let Some(area) = self.area(camera, bounds, out.pixels().pixels())? else {
            return Ok(RenderStats::default());
        };
        self.render(source, camera, style, &area, out)
            .map_err(RenderError::Target)
    }

    /// The drawn area (the viewport cut to `bounds`) and its band height, for a colour buffer
    /// of `colors` pixels; `None` when the area is empty.
    fn area<E>(
        &self,
        camera: &Camera,
        bounds: &Rectangle,
        colors: usize,
    ) -> Result<Option<Area>, RenderError<E>> {
        let [vw, vh] = camera.viewport();
        if vw > MAX_VIEWPORT || vh > MAX_VIEWPORT {
            return Err(RenderError::ViewportTooLarge);
        }
        let clamp = |v: i64| v.clamp(0, i32::MAX as i64) as i32;
        let x0 = clamp(bounds.top_left.x as i64);
        let y0 = clamp(bounds.top_left.y as i64);
        let x1 = clamp(bounds.top_left.x as i64 + bounds.size.width as i64).min(clamp(vw as i64));
        let y1 = clamp(bounds.top_left.y as i64 + bounds.size.height as i64).min(clamp(vh as i64));
        if x0 >= x1 || y0 >= y1 {
            return Ok(None);
        }
        let width = (x1 - x0) as usize;
        if self.depth.len() < width {
            return Err(RenderError::DepthTooSmall { needed: width });
        }
        if colors < width {
            return Err(RenderError::ColorsTooSmall { needed: width });
        }
        Ok(Some(Area {
            columns: [x0, x1],
            rows: [y0, y1],
            band_rows: self.depth.len().min(colors) / width,
        }))
    }

    /// Draws the frame band by band into `out`.
    fn render<S, O>(
        &mut self,
        source: &S,
        camera: &Camera,
        style: &Style,
        area: &Area,
        out: &mut O,
    ) -> Result<RenderStats, O::Error>
    where
        S: TriangleSource,
        O: BandOutput,
    {
        let mut stats = RenderStats::default();
        let setup = Setup::new(
            camera,
            source.bound(),
            style,
            self.arithmetic,
            source.hierarchy(),
        );
        // One cache of corners in view space, for the list's pass and then each band's.
        let mut corners = CornerCache::new();
        let one_sided = |patch| source.one_sided(camera, patch);
        // One pass into the list, when there is one: `Some((n, resume))` when it holds the
        // frame's first `n` triangles, all of them unless patches from `resume` on are left.
        let mut listed = None;
        if !self.list.is_empty() && setup.depth.is_some() {
            let [y0, y1] = area.rows;
            let rows = y0 as u32..y1 as u32;
            let filled = list::fill(&setup, self.list, &mut corners, self.map, source, rows);
            stats.passes += 1;
            stats.triangles += filled.handed;
            stats.culled += filled.culled;
            if let Some(held) = filled.listed {
                listed = Some(held);
                stats.listed = filled.triangles;
                stats.list_slots = filled.slots;
            }
        }
        let [x0, x1] = area.columns;
        let [y0, y1] = area.rows;
        let width = (x1 - x0) as usize;
        let mut top = y0;
        while top < y1 {
            let bottom = (top as i64 + area.band_rows as i64).min(y1 as i64) as i32;
            let depth = &mut self.depth[..width * (bottom - top) as usize];
            clear(depth);
            stats.bands += 1;
            let rect = Rectangle::new(
                Point::new(x0, top),
                Size::new(width as u32, (bottom - top) as u32),
            );
            out.begin(&rect, style);
            let mut band = Band {
                setup: &setup,
                depth,
                area: rect,
                out: &mut *out,
                error: None,
                stats: &mut stats,
                corners: &mut corners,
                one_sided: &one_sided,
                patch: None,
                arithmetic: self.arithmetic,
            };
            let rows = top as u32..bottom as u32;
            match listed {
                Some((n, resume)) => {
                    band.draw_list(self.list, n);
                    if let Some(first) = resume {
                        band.stats.passes += 1;
                        let mut rest = list::Remaining {
                            first,
                            sink: &mut band,
                        };
                        source.stream_rows(camera, rows, &mut rest);
                    }
                }
                None if setup.depth.is_some() => {
                    band.stats.passes += 1;
                    source.stream_rows(camera, rows, &mut band);
                }
                None => {}
            }
            if let Some(e) = band.error.take() {
                return Err(e);
            }
            let depth = &self.depth[..width * (bottom - top) as usize];
            out.finish(&rect, depth, style, &mut stats)?;
            top = bottom;
        }
        Ok(stats)
    }
}

/// Sets `depth` to 0, sixteen values a step, each pair of them the two halves of one `u32`
/// (which the compiler stores as one word). The zero goes through `black_box`, so that the
/// compiler does not turn the loop back into `memset`, which a Cortex-M4F build runs a word a
/// loop (three times the instructions of this loop).
fn clear(depth: &mut [u16]) {
    let zero = core::hint::black_box(0u32);
    let block: [u16; 16] = core::array::from_fn(|i| (zero >> (16 * (i % 2))) as u16);
    let mut blocks = depth.chunks_exact_mut(16);
    for b in &mut blocks {
        for (pair, half) in b.chunks_exact_mut(2).zip(block.chunks_exact(2)) {
            pair[0] = half[0];
            pair[1] = half[1];
        }
    }
    for v in blocks.into_remainder() {
        *v = block[0];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Projection, Vec3, Vertex};
    use embedded_graphics::mock_display::MockDisplay;
    use embedded_graphics::pixelcolor::Rgb565;

    /// Viewports up to [`MAX_VIEWPORT`] draw; past it (257 pixels without the feature
    /// `large-viewports`, whose 32-bit edge functions reach no further) the frame is refused.
    #[test]
    fn viewports_up_to_the_limit_draw() {
        let corner = |x: f32, y: f32| Vertex {
            position: [x, y, 0.0],
            normal: [0.0, 0.0, 1.0],
            ..Vertex::default()
        };
        let vertices = [corner(-1.0, -1.0), corner(1.0, -1.0), corner(0.0, 1.0)];
        let mesh = IndexedMesh {
            vertices: &vertices,
            triangles: &[[0u16, 1, 2]],
        };
        let camera = |width: u32| {
            Camera::new(
                Vec3::Z * 4.0,
                Vec3::ZERO,
                Vec3::Y,
                Projection::Orthographic { height: 3.0 },
                0.1,
                [width, 16],
            )
            .unwrap()
        };
        let mut depth = [0u16; 2048];
        let style = Style::default();
        for width in [256, 257] {
            let mut display = MockDisplay::<Rgb565>::new();
            let drawn = Renderer::new(&mut depth).draw(&mesh, &camera(width), &style, &mut display);
            let fits = width <= MAX_VIEWPORT;
            assert_eq!(drawn.is_ok(), fits, "{width}");
            if !fits {
                assert_eq!(drawn.unwrap_err(), RenderError::ViewportTooLarge);
            }
        }
        assert_eq!(MAX_VIEWPORT == 256, !cfg!(feature = "large-viewports"));
    }
}
