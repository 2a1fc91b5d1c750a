// What `fw_bake` bakes, shared with the host test that writes its expected bytes
// (host-tests/tests/firmware_data.rs). Hand-written.

/// The teapot patch to bake (a rim patch; `TEAPOT_POINTS[16 * PATCH..][..16]`).
pub const PATCH: usize = 0;
/// Most samples per boundary curve.
pub const CURVE_CAP: usize = 32;
/// Most interior samples.
pub const INTERIOR_CAP: usize = 128;
/// Bake settings: a thousandth of the patch's bounding-box diagonal.
pub const SETTINGS: spline_tess::bake::BakeSettings = spline_tess::bake::BakeSettings {
    tolerance: spline_tess::bake::Tolerance::Relative(1e-3),
    max_curve_samples: CURVE_CAP as u16,
    max_interior_samples: INTERIOR_CAP as u16,
};
/// The patch's header within the teapot's points.
pub const HEADER: [spline_tess::PatchHeader; 1] = [spline_tess::PatchHeader {
    degree_u: 3,
    degree_v: 3,
    first_point: (16 * PATCH) as u32,
}];
