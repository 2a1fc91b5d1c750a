// What `fw_teapot` draws, shared (through `#[path]`) with the host test that writes its
// expected checksums (host-tests/tests/firmware_data.rs): the views, the styles, one frame's
// update, and its rendering band by band into a colour band buffer pushed to the SPI display
// model (module `spi_display` beside this one, which also hashes the pixels). Uses the
// teapot bake and settings of `fw_tessellate_frames.rs`, in its own storage: a pool of
// domain-mesh slots sized for the far frames. `no_std`, no allocation. Hand-written.

use embedded_graphics::pixelcolor::Rgb888;
use spline_tess::render::{ListSlot, RenderStats, Renderer, Shading, Style, Wireframe};
use spline_tess::tessellator::FixedStorage;
use spline_tess::{Camera, FrameStats, Projection, Vec3, View};

use super::spi_display::SpiDisplay;

/// Display size.
pub const WIDTH: u32 = 240;
/// Display size.
pub const HEIGHT: u32 = 240;
/// Rows per band: the depth and colour band buffers hold `WIDTH * BAND_ROWS` values each.
/// Measured 2026-11-24 under QEMU: 8 rows instead of 16 saved 7,680 bytes for 0.28M more
/// render instructions in frame 0 and 0.34M in frame 1; 4 rows instead of 8 save 3,840 more
/// for 0.46M more in frame 0 (9.46M in all) and 0.55M in frame 1 (a triangle is set up once
/// per band it meets). The near frames, which stream most patches band by band, pay more:
/// frame 3's render then went from 27.6M to 39.8M (later work on the renderer brought it
/// down again: README has today's figures).
pub const BAND_ROWS: u32 = 4;
/// Pixels of one band: depth values, and colours (two bytes each).
pub const BAND: usize = (WIDTH * BAND_ROWS) as usize;
/// Slots of the triangle list (8 bytes each: a group header per patch, one slot per two
/// Gouraud-shaded or one flat-shaded triangle, and one per distinct corner). Frames 0 and 1
/// take 1,493 and 1,541 (the host run prints `list_slots`); the near frames keep their first
/// patches there and stream the rest band by band. `--cfg fw_no_list` builds the demo without
/// a list, to measure the streaming path on every frame.
pub const LIST: usize = if cfg!(fw_no_list) { 0 } else { 1552 };

/// Patch slots: the teapot's 32 patches.
pub const PATCHES: usize = 32;
/// Curve slots: the teapot's 68 boundary curves.
pub const CURVES: usize = 68;
/// Curve-order slots: one per baked curve sample.
pub const ORDER: usize = 364;
/// The pool's vertex slots (5 bytes each): frames 0 and 1 hold every baked step they ask for
/// (888 vertices and 1,239 triangles: the host run prints `pool_vertices` and
/// `pool_triangles`); the near frames cut their prefixes to fit and refine more
/// (`FrameStats::prefix_scale`). Measured 2026-11-24 under QEMU: with 896 and 1,248 slots,
/// 272 bytes less, frame 1's patches find no spare room and the pool is laid out again, for
/// 68k more instructions in its update.
pub const POOL_VERTICES: usize = 912;
/// The pool's triangle slots (6 bytes each).
pub const POOL_TRIANGLES: usize = 1280;
/// Triangle states (20 bytes each), one per live triangle of the patches whose triangles a
/// frame judges on their own or cuts. Frames 0 and 1 judge those of four patches, along
/// sides holding curve samples their neighbours asked for: 196 states (the host run prints
/// `states_needed`, from `FrameStats::triangle_states_needed`). The near frames judge every
/// patch's, and the patches that find no room stay uncut, within the bound the frame reports
/// (`FrameStats::patches_without_states`).
pub const STATES: usize = 200;
/// Bound-cache entries (88 bytes each): the bounds the frames compute, kept for the next
/// frames. Measured 2026-11-24 under QEMU (frames that judge only the triangles along extra
/// curve samples), frame 1's update takes 0.73M instructions with 64 entries, 0.76M with 32
/// and 0.78M with none, and frames 0, 2 and 3 change by less than 0.3%: the demo keeps none,
/// 5,632 bytes less RAM for 0.7% more instructions in frame 1.
pub const BOUNDS: usize = 0;
/// Vertex-cache entries: none. One per pool vertex slot (32 bytes each, 32,768 in all) would
/// spare frame 1 about 0.5M of its 9.2M instructions (measured 2026-11-24); the demo keeps the
/// RAM instead.
pub const POINTS: usize = 0;
/// The pool's slot numbers: the fw bake's patches hold at most 116 vertices (4 corners, 16
/// curve samples a side, 48 interior samples), within the 130 a `u8`-indexed mesh numbers,
/// so one-byte indices lose no sample and halve the triangle slots (6 bytes instead of 12).
pub type Index = u8;
/// Scratch: three per patch, to build the tessellator. The demo only streams its frames to
/// the renderer; writing them as an indexed mesh would need 542 (`StorageSize::scratch`).
pub const SCRATCH: usize = 3 * PATCHES;

/// fw_teapot's tessellator.
pub type Tessellator<'m, 's> = spline_tess::Tessellator<'m, 's, Index>;

/// fw_teapot's tessellator storage.
pub type Storage = FixedStorage<
    PATCHES,
    CURVES,
    ORDER,
    POOL_VERTICES,
    POOL_TRIANGLES,
    STATES,
    BOUNDS,
    POINTS,
    SCRATCH,
    Index,
>;

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

/// Draws `tess`'s current frame as frame `k` onto `display`, band by band: `depth` (`BAND`
/// values) and `colors` (`2 * BAND` bytes, big-endian Rgb565) hold one band, each band's bytes
/// are pushed as they are (as to a DMA transfer), `list` (may be empty) the frame's triangles. Not
/// inlined: the renderer's locals then take the stack after the update's, not beside them.
#[inline(never)]
pub fn render(
    tess: &Tessellator<'_, '_>,
    k: usize,
    depth: &mut [u16],
    colors: &mut [u8],
    list: &mut [ListSlot],
    display: &mut SpiDisplay,
) -> Option<RenderStats> {
    let camera = camera(k)?;
    let style = style(k)?;
    display.begin_frame();
    Renderer::with_triangle_list(depth, list)
        .draw_bands_rgb565(tess, &camera, &style, colors, |area, bytes| {
            display.push_band(area, bytes);
            Ok::<(), core::convert::Infallible>(())
        })
        .ok()
}
