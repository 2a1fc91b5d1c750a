//! # spline-tess
//!
//! A `no_std`, allocation-free kernel that tessellates rational Bezier and NURBS surfaces into
//! crack-free triangle meshes whose error on screen stays within a pixel tolerance, for
//! firmware that drives small displays and for host programs. The method is Chhugani &
//! Kumar's view-dependent adaptive tessellation (I3D 2001), with a hierarchy of halvings for
//! its samples.
//!
//! 1. **Load** the surfaces: [`parse`] reads BPT text and NURBS JSON into caller buffers; a
//!    [`PatchSet`] is rational Bezier patches ([`BezierPatch`], degree 1 to [`MAX_DEGREE`])
//!    over flat slices, so a model can be a `static` in flash; a [`NurbsSurface`] decomposes
//!    into one; [`Model`] adds which curve each patch side is, so that neighbours share it.
//! 2. **Bake** once ([`bake`]): each patch's `(u, v)` square is halved at a hypotenuse, and
//!    halved again, until every triangle is within the bake's tolerance of the surface; each
//!    triangle records a bound that provably covers the surface over it. The result is a
//!    [`Hierarchy`]; a firmware bakes on the host and compiles the hierarchy in
//!    ([`bake::write_rust_source`]).
//! 3. **Tessellate** a [`View`] ([`Tessellator`]): a [`Camera`] with a tolerance in pixels, or
//!    a tolerance in model units. A frame's mesh is the coarsest conforming mesh of the
//!    hierarchy whose triangles are all within the tolerance, each judged by its own bound on
//!    screen; where the view is finer than the bake, halving goes on into a caller pool. The
//!    mesh depends on the view alone, shared curves share their vertices (no cracks), and in a
//!    closed model patches facing away are culled.
//! 4. **Write** it: into caller buffers of vertices and indices
//!    ([`Tessellator::write_mesh`]), streamed to a [`TriangleSink`], or drawn band by band
//!    onto a display (`render`, feature `embedded-graphics`).
//!
//! Nothing allocates: every capacity is a const generic or a caller slice, and running out of
//! room is an error that states what was needed, or a frame that reports the bound it keeps.
//! Triangles come counter-clockwise seen from outside, with outward normals (the bake's
//! orientation rule, [`bake`]).
//!
//! ## On a host
//!
//! With feature `std`, `spline_tess::host` does each step in one call and owns the buffers. Without it,
//! load, bake, tessellate, write into buffers of one's own: one bicubic patch here, a model
//! file the same way.
//!
//! ```
//! use spline_tess::bake::{bake_hierarchy, BakeBuffers, BakeError, BakeScratch, BakeSettings};
//! use spline_tess::tessellator::{HierarchyNode, HierarchyPatch, HierarchyVertex};
//! use spline_tess::tessellator::{PoolSlot, StackSlot};
//! use spline_tess::{parse, BoundaryCurve, EdgeLink, Hierarchy, Model, PatchHeader, Tessellator};
//! use spline_tess::{Vertex, View};
//!
//! // Load: BPT text (a patch count, then per patch its degrees and its control points).
//! let text = "1\n3 3\n\
//!     0 0 0\n0 1 0\n0 2 0\n0 3 0\n1 0 0\n1 1 1\n1 2 1\n1 3 0\n\
//!     2 0 0\n2 1 1\n2 2 1\n2 3 0\n3 0 0\n3 1 0\n3 2 0\n3 3 0\n";
//! let size = parse::bpt_size(text)?;
//! let mut headers = vec![PatchHeader::default(); size.patches];
//! let mut points = vec![[0.0; 3]; size.points];
//! let patches = parse::parse_bpt(text, &mut headers, &mut points)?;
//! let mut edges = vec![[EdgeLink::Collapsed; 4]; patches.len()];
//! let mut curves = vec![BoundaryCurve::default(); 4 * patches.len()];
//! let model = Model::build(patches, &mut edges, &mut curves)?;
//!
//! // Bake: a hierarchy's size is known once it is baked, so grow until it fits.
//! let mut capacity = 1024;
//! let (nodes, vertices, records) = loop {
//!     let mut nodes = vec![HierarchyNode::default(); capacity];
//!     let mut vertices = vec![HierarchyVertex::default(); capacity];
//!     let mut records = vec![HierarchyPatch::default(); patches.len()];
//!     let mut scratch = vec![BakeScratch::default(); capacity];
//!     let buffers = BakeBuffers {
//!         nodes: &mut nodes,
//!         vertices: &mut vertices,
//!         patches: &mut records,
//!         scratch: &mut scratch,
//!     };
//!     match bake_hierarchy(&model, &BakeSettings::default(), buffers) {
//!         Ok(size) => {
//!             nodes.truncate(size.nodes);
//!             vertices.truncate(size.vertices);
//!             break (nodes, vertices, records);
//!         }
//!         Err(BakeError::NodesFull { .. } | BakeError::VerticesFull { .. }) => capacity *= 2,
//!         Err(e) => return Err(e.into()),
//!     }
//! };
//! let hierarchy = Hierarchy::new(patches, &nodes, &vertices, &records)?;
//!
//! // Tessellate: storage for the hierarchy, a stack, and a pool below the bake.
//! let mut bits = vec![0; hierarchy.bit_words()];
//! let mut stack = vec![StackSlot::EMPTY; 256];
//! let mut pool = vec![PoolSlot::EMPTY; 4096];
//! let mut tessellator = Tessellator::from_slices(hierarchy, &mut bits, &mut stack, &mut pool)?;
//! let stats = tessellator.update(&View::Object { tolerance: 1e-3 })?;
//! assert!(stats.left_over == 0 && stats.worst_bound <= 1e-3);
//!
//! // Write: vertices shared by index.
//! let size = tessellator.mesh_size();
//! let mut vertices = vec![Vertex::default(); size.vertices];
//! let mut triangles = vec![[0u32; 3]; size.triangles];
//! let mut remap = vec![0; tessellator.remap_len()];
//! tessellator.write_mesh(&mut vertices, &mut triangles, &mut remap)?;
//! assert_eq!(triangles.len(), stats.triangles);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! ## On a microcontroller
//!
//! The hierarchy is baked on the host, written as compact bytes
//! ([`bake::encode_hierarchy`]) and kept as a static ([`bake::write_rust_source`], or
//! `include_bytes!`) that the firmware reads in place from flash
//! ([`Hierarchy::from_bytes`]). The tessellator's storage is sized
//! at compile time ([`tessellator::TessellatorStorage`]): bits for the hierarchy, a stack of
//! waiting triangles, and a pool of vertices below the bake, which may be empty (a view finer
//! than the bake then leaves its triangles whole, and the frame reports the bound it keeps).
//!
//! ```
//! # use spline_tess::bake::{bake_hierarchy, BakeBuffers, BakeScratch, BakeSettings};
//! # use spline_tess::bake::{encode_hierarchy, encode_scratch_len};
//! # use spline_tess::tessellator::{HierarchyNode, HierarchyPatch, HierarchyVertex};
//! # use spline_tess::{BoundaryCurve, EdgeLink, Model, PatchHeader, PatchSet};
//! use spline_tess::tessellator::{bit_words_for, TessellatorStorage};
//! use spline_tess::{Camera, Hierarchy, Projection, Tessellator, Vec3, View};
//!
//! // The counts `write_rust_source` writes beside the bytes (here baked in place) size the
//! // storage.
//! const NODES: usize = 2048;
//! const VERTICES: usize = 1024;
//! # let mut points = [[0.0f32; 3]; 16];
//! # for (k, p) in points.iter_mut().enumerate() {
//! #     let (i, j) = (k / 4, k % 4);
//! #     let z = if (1..3).contains(&i) && (1..3).contains(&j) { 1.0 } else { 0.0 };
//! #     *p = [i as f32, j as f32, z];
//! # }
//! # let headers = [PatchHeader { degree_u: 3, degree_v: 3, first_point: 0 }];
//! # let patches = PatchSet::new(&headers, &points, None)?;
//! # let (mut edges, mut curves) = ([[EdgeLink::Collapsed; 4]], [BoundaryCurve::default(); 4]);
//! # let model = Model::build(patches, &mut edges, &mut curves)?;
//! # let mut nodes = [HierarchyNode::default(); NODES];
//! # let mut vertices = [HierarchyVertex::default(); VERTICES];
//! # let mut records = [HierarchyPatch::default()];
//! # let mut scratch = vec![BakeScratch::default(); NODES];
//! # let buffers = BakeBuffers {
//! #     nodes: &mut nodes,
//! #     vertices: &mut vertices,
//! #     patches: &mut records,
//! #     scratch: &mut scratch,
//! # };
//! # let size = bake_hierarchy(&model, &BakeSettings::default(), buffers)?;
//! # let baked = Hierarchy::new(patches, &nodes[..size.nodes], &vertices[..size.vertices], &records)?;
//! # let mut work = vec![0u32; encode_scratch_len(size.nodes, size.vertices)];
//! # let mut bytes = vec![0u8; 1 << 16];
//! # let len = encode_hierarchy(&baked, &mut work, &mut bytes)?;
//! # let hierarchy_bytes: &[u8] = &bytes[..len];
//! // The bytes, read in place (a `static` in flash).
//! let hierarchy = Hierarchy::from_bytes(patches, hierarchy_bytes)?;
//!
//! // Bits, a stack of 64 and no pool, sized at compile time.
//! let mut storage = TessellatorStorage::<{ bit_words_for(NODES, VERTICES, 1) }, 64, 0>::new();
//! let mut tessellator = Tessellator::new(hierarchy, &mut storage)?;
//!
//! // A frame: 1 px on a 240x240 display, streamed (to a renderer, here a count).
//! let camera = Camera::new(
//!     Vec3::new(6.0, -4.0, 5.0),
//!     Vec3::new(1.5, 1.5, 0.5),
//!     Vec3::Z,
//!     Projection::Perspective { fov_y_degrees: 40.0 },
//!     0.1,
//!     [240, 240],
//! )?;
//! let stats = tessellator.update(&View::Screen { camera, tolerance_px: 1.0 })?;
//! assert!(stats.left_over > 0 || stats.worst_bound <= 1.0);
//! let mut drawn = 0;
//! tessellator.stream_with_info(|_info, _corners| drawn += 1);
//! assert_eq!(drawn, stats.triangles);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! ## Crate features
//!
//! - `refine` (default): refinement below the bake, into the caller's pool. A firmware whose
//!   views stay within its bake can leave it out: its code then holds no surface evaluation,
//!   and a view finer than the bake leaves its triangles whole, within the bound the frame
//!   reports, as with a full pool.
//! - `large-viewports` (default): the renderer draws viewports up to `render::MAX_VIEWPORT`
//!   = 2^20 pixels across, with 64-bit edge functions where corners lie far out. Without it,
//!   up to 256 pixels, in 32-bit arithmetic only.
//! - `std`: `spline_tess::host`: models read from files or bytes, bakes on all cores (with rayon, the
//!   same bytes as one core: `bake::Parallel`), a view's frame as an owned mesh, OBJ and PLY. On
//!   a bare-metal target (`target_os = "none"`) it does nothing.
//! - `defmt`: every public type implements `defmt::Format`.
//! - `embedded-graphics`: `render`, a band-by-band, z-buffered rasteriser that draws a
//!   tessellator's frame (streamed, no mesh buffer) or an indexed mesh onto any
//!   `embedded_graphics` `DrawTarget` with RGB colours, with a caller depth band.
//!
//! ## Numbers
//!
//! Evaluation is in `f32` (the single-precision FPU of a Cortex-M4F) using only element-wise
//! IEEE-754 operations in a fixed order, so a host and a microcontroller compute the same bits.
//! `host-tests/` checks it against an `f64` reference and against `curvo` and `truck-geometry`,
//! and every frame's triangles against dense `f64` sampling on screen.

#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]
#![deny(missing_debug_implementations)]
#![deny(rustdoc::broken_intra_doc_links)]

#[cfg(all(feature = "std", not(target_os = "none")))]
extern crate std;

mod arithmetic;
pub mod bake;
mod basis;
mod bound;
#[cfg(feature = "defmt")]
mod defmt_impls;
mod deviation;
mod facing;
mod frame;
#[cfg(all(feature = "std", not(target_os = "none")))]
pub mod host;
mod math;
mod model;
mod nurbs;
pub mod parse;
mod patch;
#[cfg(feature = "embedded-graphics")]
pub mod render;
mod sink;
pub mod tessellator;
#[cfg(test)]
mod test_rng;
mod view;

pub use arithmetic::Arithmetic;
pub use bound::{Aabb, BoundingSphere};
pub use facing::NormalCone;
pub use frame::SurfacePoint;
pub use model::{
    BoundaryCurve, EdgeCounts, EdgeLink, Model, PatchHeader, PatchSet, PatchSetError, SplitError,
    SplitSize, Topology, TopologyError,
};
pub use nurbs::{
    DecomposeError, DecompositionSize, Direction, NurbsError, NurbsSurface, ParamRect,
};
pub use patch::{BezierPatch, PatchError, Side};
pub use sink::{MeshIndex, MeshSize, TriangleInfo, TriangleSink, Vertex, WriteError};
pub use tessellator::{FrameStats, Hierarchy, Tessellator};
pub use view::{Camera, CameraError, Projection, View};

/// The README's examples, run as doc tests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;

/// Re-export of the vector type used in the API.
pub use glam::Vec3;

/// Highest degree, in u or in v, of a patch or NURBS surface.
///
/// Evaluation keeps `3 * (MAX_DEGREE + 1)` homogeneous points on the stack (384 bytes).
pub const MAX_DEGREE: usize = 7;
