// What `fw_tessellate` renders, shared (through `#[path]`) with the host test that writes its
// expected checksums (host-tests/tests/firmware_data.rs): the views, the storage capacities,
// and one frame's tessellation and checksum. `no_std`, no allocation. Hand-written.

use spline_tess::bake::BakedModel;
use spline_tess::tessellator::{BackPatches, FixedStorage, Settings, StorageSize, Tessellator};
use spline_tess::{PatchSet, Vertex};

/// Bake settings of the firmware's teapot: 2e-3 of the diagonal, small caps.
pub const BAKE: spline_tess::bake::BakeSettings = spline_tess::bake::BakeSettings {
    tolerance: spline_tess::bake::Tolerance::Relative(2e-3),
    max_curve_samples: 16,
    max_interior_samples: 48,
};

/// Run-time settings.
pub const SETTINGS: Settings = Settings {
    max_interior_samples: 48,
    max_factor: 8,
    back_patches: BackPatches::CullWhenClosed,
};

/// Capacities of the firmware's storage (the host test checks they cover the bake).
pub const PATCHES: usize = 32;
/// Curve slots.
pub const CURVES: usize = 128;
/// Curve-order slots.
pub const ORDER: usize = 128 * 16;
/// Domain vertex slots.
pub const VERTICES: usize = 32 * (4 + 4 * 16 + 48);
/// Domain triangle slots.
pub const TRIANGLES: usize = 2 * VERTICES;
/// Bound-cache entries.
pub const BOUNDS: usize = 1024;
/// Vertex-cache entries.
pub const POINTS: usize = VERTICES;
/// Scratch for `write_mesh`'s index tables: the largest patch's vertex slots plus three per
/// triangle slot.
pub const SCRATCH: usize = 4 * (4 + 4 * 16 + 48) * 3;
/// Output vertices.
pub const OUT_VERTICES: usize = 6000;
/// Output triangles.
pub const OUT_TRIANGLES: usize = 12000;

// The views and checksum (`fw_views.rs`), which the includer declares as `fw_views`.
#[allow(unused_imports)]
pub use super::fw_views::{checksum, view, FRAMES};

/// One frame's numbers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Frame {
    /// Triangles written.
    pub triangles: u32,
    /// Vertices written.
    pub vertices: u32,
    /// Samples inserted.
    pub inserted: u32,
    /// Checksum of the mesh.
    pub checksum: u32,
}

/// The firmware's storage, in caller memory (on the device: the stack).
pub type Storage =
    FixedStorage<PATCHES, CURVES, ORDER, VERTICES, TRIANGLES, TRIANGLES, BOUNDS, POINTS, SCRATCH>;

/// A tessellator over `storage`, if its pool holds every baked step of `baked` (so the
/// frames' triangles are the error-control figures'; the bound cache may be any size).
pub fn tessellator<'m, 's>(
    storage: &'s mut Storage,
    patches: PatchSet<'m>,
    baked: BakedModel<'m>,
) -> Option<Tessellator<'m, 's>> {
    let every_step = StorageSize {
        bounds: 0,
        vertex_points: 0,
        ..StorageSize::of(&baked, &SETTINGS)
    };
    if !Storage::covers(&every_step) {
        return None;
    }
    Tessellator::new(patches, baked, SETTINGS, storage.as_storage()).ok()
}

/// Updates `tess` to frame `k` and writes its mesh; `None` on any error.
pub fn frame(
    tess: &mut Tessellator<'_, '_>,
    k: usize,
    vertices: &mut [Vertex],
    triangles: &mut [[u16; 3]],
) -> Option<Frame> {
    frame_timed(tess, k, vertices, triangles, &mut || 0).map(|(f, _)| f)
}

/// [`frame`], with the `clock` ticks that the update and the write took (the checksum after
/// them is not counted).
pub fn frame_timed(
    tess: &mut Tessellator<'_, '_>,
    k: usize,
    vertices: &mut [Vertex],
    triangles: &mut [[u16; 3]],
    clock: &mut dyn FnMut() -> u64,
) -> Option<(Frame, u64)> {
    let view = view(k)?;
    let start = clock();
    let stats = tess.update(&view).ok()?;
    let size = tess.write_mesh(vertices, triangles).ok()?;
    let used = clock().saturating_sub(start);
    let frame = Frame {
        triangles: size.triangles as u32,
        vertices: size.vertices as u32,
        inserted: stats.inserted as u32,
        checksum: checksum(&vertices[..size.vertices], &triangles[..size.triangles]),
    };
    Some((frame, used))
}
