// What `fw_bisect` renders, shared (through `#[path]`) with the host test that writes its
// baked hierarchy and expected checksums (host-tests/tests/firmware_data.rs): the bake's
// settings, the storage, and one frame's selection and checksum. `no_std`, no allocation.
// Hand-written.

use spline_tess::bake::BakeSettings;
use spline_tess::bake::Tolerance;
use spline_tess::tessellator::{FrameStats, Tessellator};
use spline_tess::Vertex;

// The views and checksum (`fw_views.rs`), which the includer declares as `fw_views`.
#[allow(unused_imports)]
pub use super::fw_views::{checksum, view, FRAMES};

/// Bake settings of the firmware's teapot: 2e-3 of the diagonal.
pub const BAKE: BakeSettings = BakeSettings {
    tolerance: Tolerance::Relative(2e-3),
    max_depth: 24,
    max_cell_level: spline_tess::tessellator::MAX_CELL_LEVEL,
};

/// Triangles waiting to be judged: a short stack walks the mesh for those it has no room
/// for (`FrameStats::sweeps`).
pub const STACK: usize = 256;
/// Vertices below the bake (frames finer than the bake make them).
pub const POOL: usize = 2048;
/// Output vertices.
pub const OUT_VERTICES: usize = 6000;
/// Output triangles.
pub const OUT_TRIANGLES: usize = 12000;

/// One frame's numbers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Frame {
    /// Triangles written.
    pub triangles: u32,
    /// Vertices written.
    pub vertices: u32,
    /// Triangles judged.
    pub judged: u32,
    /// Checksum of the mesh.
    pub checksum: u32,
}

/// Selects frame `k` in `selection` and writes its mesh (`remap` as long as
/// `Tessellator::remap_len`), with the `clock` ticks that the selection and the write took (the checksum after
/// them is not counted); `None` on any error.
pub fn frame_timed(
    selection: &mut Tessellator<'_, '_>,
    k: usize,
    vertices: &mut [Vertex],
    triangles: &mut [[u16; 3]],
    remap: &mut [u32],
    clock: &mut dyn FnMut() -> u64,
) -> Option<(Frame, FrameStats, u64)> {
    let view = view(k)?;
    let start = clock();
    let stats = selection.update(&view).ok()?;
    let size = selection.write_mesh(vertices, triangles, remap).ok()?;
    let used = clock().saturating_sub(start);
    let frame = Frame {
        triangles: size.triangles as u32,
        vertices: size.vertices as u32,
        judged: stats.judged as u32,
        checksum: checksum(&vertices[..size.vertices], &triangles[..size.triangles]),
    };
    Some((frame, stats, used))
}
