// What `fw_teapot` draws, shared (through `#[path]`) with the host test that writes its
// expected checksums (host-tests/tests/firmware_data.rs): the views, the styles, one frame's
// update, and its rendering band by band into a colour band buffer pushed to the SPI display
// model (module `spi_display` beside this one, which also hashes the pixels). Uses the
// teapot's hierarchy of `fw_bisect` (baked at 2e-3 of the diagonal with
// `fw_bisect_frames::BAKE`), in its own storage: a short stack and no pool of vertices below
// the bake. `no_std`, no allocation. Hand-written.

use embedded_graphics::pixelcolor::Rgb888;
use spline_tess::render::{ListSlot, RenderStats, Renderer, Shading, Style, Wireframe};
use spline_tess::tessellator::{FrameStats, Tessellator};
use spline_tess::Arithmetic;
use spline_tess::{Camera, Projection, Vec3, View};

use super::spi_display::SpiDisplay;

/// Display size.
pub const WIDTH: u32 = 240;
/// Display size.
pub const HEIGHT: u32 = 240;
/// Rows per band: the depth and colour band buffers hold `WIDTH * BAND_ROWS` values each.
/// A triangle is set up once per band it meets, and a band decodes the list's groups that meet
/// it, so taller bands cost fewer instructions and more RAM. Measured 2026-11-26 under QEMU,
/// with the list below: 16 rows and 2,000 slots render frames 0 to 3 in 3.01M, 3.23M, 9.98M
/// and 12.25M instructions; 8 rows and 2,900 slots in 3.21M, 3.47M, 10.3M and 11.9M (1,280
/// bytes less RAM); 20 rows and 1,300 slots in 2.99M, 3.22M, 10.7M and 13.1M.
pub const BAND_ROWS: u32 = 16;
/// Pixels of one band: depth values, and colours (two bytes each).
pub const BAND: usize = (WIDTH * BAND_ROWS) as usize;
/// Slots of the triangle list (8 bytes each: a group header per patch, one slot per two
/// Gouraud-shaded or one flat-shaded triangle, and one per distinct corner), with a vertex map
/// beside it (2 bytes per vertex of the hierarchy). Frames 0 and 1 take 1,131 and 1,135 (the
/// firmware prints `list_slots`) and fit; frames 2 (flat-shaded) and 3 keep their first
/// patches there and stream the rest band by band (see `BAND_ROWS` for what that costs).
/// 1,800 slots keep the demo's RAM, all of it counted from the top of the stack, within
/// 48 KiB on every part class; 2,000 (1,600 bytes more) took 49,896 bytes on the Cortex-M4F
/// and 50,528 on ARMv6-M, and rendered frames 2 and 3 in 10.13M and 10.75M instructions
/// (Cortex-M4F) where 1,800 take 11.10M and 12.26M (measured 2026-11-28 under QEMU).
/// `--cfg fw_no_list` builds the demo without a list, to measure the streaming path on every
/// frame.
pub const LIST: usize = if cfg!(fw_no_list) { 0 } else { 1800 };

/// Triangles waiting to be judged (`StackSlot`, 32 bytes each). Measured 2026-11-25 under QEMU:
/// 256 entries instead of 64 (6 KiB more) spare frames 0 and 1 2% of their update.
pub const STACK: usize = 64;
/// Vertices below the bake (`PoolSlot`, 48 bytes each): none. Frames 0 to 2 are within
/// the bake; frame 3 is not, and leaves 250 triangles whole, within the bound it reports
/// (`FrameStats::worst_bound`, printed by the host run as `bound_px`: 1.9 px). Measured
/// 2026-11-25: a pool of 64 (3 KB) makes 56 vertices in frame 3 and leaves its bound at 1.9 px,
/// so the demo keeps none, and is built without the crate's `refine` feature (20 KB less code
/// at opt-level "s"; `scripts/footprint.sh`).
pub const POOL: usize = 0;
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

/// Brings `selection` to frame `k`. Not inlined, so that a profile finds where the update
/// starts (`scripts/fw_profile.py`).
#[inline(never)]
pub fn update(selection: &mut Tessellator<'_, '_>, k: usize) -> Option<FrameStats> {
    let camera = camera(k)?;
    let tolerance_px = FRAMES.get(k)?.1;
    selection
        .update(&View::Screen {
            camera,
            tolerance_px,
        })
        .ok()
}

/// Draws `selection`'s current frame as frame `k` onto `display`, band by band: `depth` (`BAND`
/// values) and `colors` (`2 * BAND` bytes, big-endian Rgb565) hold one band, each band's bytes
/// are pushed as they are (as to a DMA transfer), `list` (may be empty) the frame's triangles,
/// `map` (may be empty) the list's vertex map (one entry per vertex of the hierarchy), the
/// depth and shade set up in `arithmetic` (the target's default on the device). Not
/// inlined: the renderer's locals then take the stack after the update's, not beside them.
#[inline(never)]
#[allow(clippy::too_many_arguments)] // (each a buffer of the caller's, or the frame's choice)
pub fn render(
    selection: &Tessellator<'_, '_>,
    k: usize,
    depth: &mut [u16],
    colors: &mut [u8],
    list: &mut [ListSlot],
    map: &mut [u16],
    display: &mut SpiDisplay,
    arithmetic: Arithmetic,
) -> Option<RenderStats> {
    let camera = camera(k)?;
    let style = style(k)?;
    display.begin_frame();
    Renderer::with_triangle_list(depth, list)
        .with_vertex_map(map)
        .with_arithmetic(arithmetic)
        .draw_bands_rgb565(selection, &camera, &style, colors, |area, bytes| {
            display.push_band(area, bytes);
            Ok::<(), core::convert::Infallible>(())
        })
        .ok()
}
