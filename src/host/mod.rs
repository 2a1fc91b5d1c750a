//! On a host (feature `std`): a model from a file or bytes, its bake on all cores (cached in a
//! file or not), and a view's frame as an owned mesh, with OBJ and PLY writers.
//!
//! The `no_std` kernel asks its caller for every buffer; this module sizes and owns them, so
//! that a host program needs one call a step:
//!
//! ```
//! use spline_tess::host::{self, Surfaces};
//! use spline_tess::{Camera, Projection, Vec3, View};
//!
//! let teapot = Surfaces::read("examples/models/teapot.bpt")?;
//! let baked = teapot.bake(&host::BAKE)?;
//! let camera = Camera::new(
//!     Vec3::new(6.0, -6.0, 4.0),
//!     Vec3::new(0.0, 0.0, 1.5),
//!     Vec3::Z,
//!     Projection::Perspective { fov_y_degrees: 40.0 },
//!     0.1,
//!     [1024, 768],
//! )?;
//! let mesh = baked.tessellate(&View::Screen { camera, tolerance_px: 1.0 })?;
//! assert!(mesh.stats.worst_bound <= 1.0);
//! let mut obj = Vec::new();
//! mesh.write_obj(&mut obj)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! [`tessellate`] does it all from a model file's bytes.

mod baked;
mod error;
mod mesh;
mod surfaces;

pub use baked::Baked;
pub use error::HostError;
pub use mesh::{Face, Mesh};
pub use surfaces::Surfaces;

use crate::bake::{BakeSettings, Tolerance};
use crate::tessellator::MAX_CELL_LEVEL;
use crate::View;

/// A host's bake: 2.5e-4 of the model's diagonal, four times finer than a firmware's default
/// (`BakeSettings::default()`), so that views at a pixel or half of one on a large screen stay
/// within it (below a bake, a frame evaluates and bounds its own triangles: slower). It takes
/// half a second for the teapot on two cores (`scripts/bake_speed.sh`).
pub const BAKE: BakeSettings = BakeSettings {
    tolerance: Tolerance::Relative(2.5e-4),
    max_depth: 24,
    max_cell_level: MAX_CELL_LEVEL,
};

/// A view's frame of a model file's bytes (BPT text, or a NURBS surface's JSON), baked with
/// [`BAKE`] on all cores: load, bake and tessellate in one call.
///
/// ```
/// use spline_tess::View;
///
/// let bytes = std::fs::read("examples/models/teaspoon.bpt")?;
/// let mesh = spline_tess::host::tessellate(&bytes, &View::Object { tolerance: 0.01 })?;
/// assert_eq!(mesh.triangles.len(), mesh.faces.len());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn tessellate(model: &[u8], view: &View) -> Result<Mesh, HostError> {
    Surfaces::from_bytes(model)?.bake(&BAKE)?.tessellate(view)
}
