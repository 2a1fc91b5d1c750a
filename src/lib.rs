//! # spline-tess
//!
//! A `no_std`, allocation-free kernel that tessellates rational Bezier and NURBS surfaces into
//! crack-free triangle meshes, for firmware that drives small displays and for host programs.
//! The algorithm is Chhugani & Kumar's view-dependent adaptive tessellation (I3D 2001).
//!
//! What it holds:
//!
//! - [`BezierPatch`]: rational Bezier patches of degree 1 to [`MAX_DEGREE`] in u and in v,
//!   as views over control-point slices, with position, partials, a unit normal that is the
//!   correct limit at collapsed edges, and conservative bounds;
//! - [`NurbsSurface`]: validated NURBS views, evaluation, and exact decomposition into Bezier
//!   patches written into caller buffers;
//! - [`PatchSet`], [`Topology`] and [`Model`]: patches over flat slices (so a model can be a
//!   `static` in flash) and which boundary curve each patch edge is;
//! - [`parse`]: the BPT text format and the NURBS JSON fixtures, read into caller buffers;
//! - [`DomainMesh`]: the fixed-capacity Delaunay triangulation of a patch's (u,v) square with
//!   insertion and deletion and exact, history-independent decisions, which the bake and the
//!   run time share.
//! - [`bake`]: ordered samples per curve and patch by greedy maximum deviation, in a compact
//!   format read in place from flash;
//! - [`tessellator`]: the run time. A [`View`] (a [`Camera`] and a pixel tolerance, or an
//!   object-space tolerance) selects each patch's and curve's prefix of samples, the domain
//!   meshes are updated in place, triangles past the samples are refined with edge factors
//!   both sides agree on, and the crack-free mesh is written to caller buffers or streamed to a
//!   [`TriangleSink`];
//! - [`bisect`]: the other run time, by longest-edge bisection. Its bake halves every patch's
//!   square until each triangle is within the tolerance and records each triangle's bound (a
//!   few deviation vectors and a remainder, so the bound is a bound); a frame selects every
//!   triangle by its own bound on screen (the coarsest conforming mesh within the tolerance,
//!   history-free), goes on below the bake into a caller pool where a view is finer, fits
//!   budgets, and streams or writes its mesh. Fewer triangles for the same verified error than
//!   the prefixes (BENCHMARKS.md), at several times the bake's flash; see
//!   [`Tessellator::update_to_budget`](bisect::Tessellator::update_to_budget) for a whole use;
//! - `render` (feature `embedded-graphics`): the band renderer for displays.
//!
//! Nothing allocates: every capacity is a caller slice, and running out of room is an error that
//! states what was needed.
//!
//! The run time's domain meshes share one pool of slots that the caller sizes (see
//! [`Tessellator`]'s example): [`StorageSize::of`](tessellator::StorageSize::of) holds every
//! baked step, and any pool down to
//! [`StorageSize::minimum`](tessellator::StorageSize::minimum) works. A frame that needs more
//! than the pool holds cuts its steps to fit and refines instead, within the same bound
//! ([`FrameStats::prefix_scale`]); [`FrameStats::pool_needed`] tells what a view needs. The
//! pool's slots are numbered by `u16`, or by `u8` ([`DomainIndex`]) at half the bytes per
//! triangle slot, for meshes of up to 130 vertices a patch ([`Tessellator::indexed`], and the
//! last parameter of [`FixedStorage`](tessellator::FixedStorage), firmware's storage).
//!
//! ## On a microcontroller
//!
//! A bisection hierarchy is baked on the host ([`bisect::bake_hierarchy`]) and written as
//! statics ([`bisect::write_rust_source`]) that the firmware reads in place from flash. The run
//! time's storage is three arrays sized at compile time, whatever the view: bits for the
//! hierarchy ([`bisect::bit_words_for`]), a stack of waiting triangles (any length from
//! [`Tessellator::MIN_STACK`](bisect::Tessellator::MIN_STACK); a short one walks the patches of
//! what it had no room for again), and a pool of vertices below the bake (empty here: a view
//! finer than the bake leaves its triangles whole, and the frame reports the bound it keeps).
//! The firmware demo `fw_teapot` does this in 5.4 KB, and draws the frame band by band with
//! `render` (README, *Footprint*).
//!
//! ```
//! # use spline_tess::bake::{bake_hierarchy, BakeBuffers, BakeScratch, BakeSettings};
//! # use spline_tess::tessellator::{Hierarchy, HierarchyNode, HierarchyPatch, HierarchyVertex};
//! # use spline_tess::{BoundaryCurve, EdgeLink, Model, PatchHeader, PatchSet};
//! use spline_tess::tessellator::{bit_words_for, Pending, RefinedVertex, Tessellator};
//! use spline_tess::{Camera, Projection, Vec3, View};
//!
//! // The hierarchy's statics, as `write_rust_source` writes them (here baked in place).
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
//! # let mut scratch = vec![BakeScratch::default(); 4096];
//! # let buffers = BakeBuffers {
//! #     nodes: &mut nodes,
//! #     vertices: &mut vertices,
//! #     patches: &mut records,
//! #     scratch: &mut scratch,
//! # };
//! # let size = bake_hierarchy(&model, &BakeSettings::default(), buffers)?;
//! # let (nodes, vertices) = (&nodes[..size.nodes], &vertices[..size.vertices]);
//! let tree = Hierarchy::new(patches, nodes, vertices, &records)?;
//!
//! // The run time's storage: bits, a stack, no pool.
//! let mut bits = [0u32; bit_words_for(NODES, VERTICES)];
//! let mut stack = [Pending::default(); 64];
//! let mut pool: [RefinedVertex; 0] = [];
//! let mut selection = Tessellator::new(tree, &mut bits, &mut stack, &mut pool)?;
//!
//! // A frame: 1 px on a 240x240 display.
//! let camera = Camera::new(
//!     Vec3::new(6.0, -4.0, 5.0),
//!     Vec3::new(1.5, 1.5, 0.5),
//!     Vec3::Z,
//!     Projection::Perspective { fov_y_degrees: 40.0 },
//!     0.1,
//!     [240, 240],
//! )?;
//! let stats = selection.update(&View::Screen { camera, tolerance_px: 1.0 });
//! assert!(stats.left_over > 0 || stats.worst_bound <= 1.0);
//! let mut drawn = 0;
//! selection.stream_with_info(|_info, _corners| drawn += 1);
//! assert_eq!(drawn, stats.triangles);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! ## Example
//!
//! ```
//! use spline_tess::{parse, BoundaryCurve, EdgeLink, Model, PatchHeader};
//!
//! // One bicubic patch of the Utah teapot's lid (BPT text: count, degrees, 16 points).
//! let text = "1\n3 3\n0 0 3.15\n0 0 3.15\n0 0 3.15\n0 0 3.15\n\
//!             0.8 0 3.15\n0.8 -0.45 3.15\n0.45 -0.8 3.15\n0 -0.8 3.15\n\
//!             0 0 2.85\n0 0 2.85\n0 0 2.85\n0 0 2.85\n\
//!             0.2 0 2.7\n0.2 -0.112 2.7\n0.112 -0.2 2.7\n0 -0.2 2.7\n";
//! let size = parse::bpt_size(text)?;
//! let mut headers = [PatchHeader::default(); 1];
//! let mut points = [[0.0; 3]; 16];
//! assert_eq!((size.patches, size.points), (1, 16));
//! let patches = parse::parse_bpt(text, &mut headers, &mut points)?;
//!
//! // The edge u = 0 is collapsed to the pole; the normal there is the limit, not NaN.
//! let pole = patches.patch(0).unwrap().evaluate(0.0, 0.3);
//! assert_eq!(pole.position.to_array(), [0.0, 0.0, 3.15]);
//! assert!(pole.normal.z.abs() > 0.999);
//!
//! let mut edges = [[EdgeLink::Collapsed; 4]; 1];
//! let mut curves = [BoundaryCurve::default(); 4];
//! let model = Model::build(patches, &mut edges, &mut curves).unwrap();
//! assert_eq!(model.topology.edge_counts().collapsed, 1);
//! # Ok::<(), spline_tess::parse::BptError>(())
//! ```
//!
//! ## Crate features
//!
//! - `refine` (default): refinement below a bisection hierarchy's bake, in the caller's pool
//!   of vertices ([`bisect`]). A firmware whose views stay within its bake can leave it out:
//!   its code then holds no surface evaluation (20 KB less at opt-level "s" in `fw_teapot`),
//!   and a view finer than the bake leaves its triangles whole, within the bound the frame
//!   reports, as with a full pool.
//! - `large-viewports` (default): the renderer draws viewports up to
//!   `render::MAX_VIEWPORT` = 2^20 pixels across, with 64-bit edge functions where corners
//!   lie far out. Without it, up to 256 pixels, in 32-bit arithmetic only (2.5 KB less code
//!   in `fw_teapot`).
//! - `defmt`: every public type implements `defmt::Format`.
//! - `embedded-graphics`: `render`, a band-by-band, z-buffered rasteriser that draws a
//!   tessellator's triangles (streamed, no mesh buffer) or an indexed mesh onto any
//!   `embedded_graphics` `DrawTarget` with RGB colours, with a caller depth band.
//!
//! ## Numbers
//!
//! Evaluation is in `f32` (the single-precision FPU of a Cortex-M4F) using only element-wise
//! IEEE-754 operations in a fixed order, so a host and a microcontroller compute the same bits.
//! `host-tests/` checks it against an `f64` reference and against `curvo` and `truck-geometry`.

#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]
#![deny(missing_debug_implementations)]
#![deny(rustdoc::broken_intra_doc_links)]

pub mod bake;
mod basis;
mod bound;
#[cfg(feature = "defmt")]
mod defmt_impls;
mod deviation;
mod facing;
mod frame;
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
