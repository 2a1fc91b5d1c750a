//! The run time: per-frame selection of baked steps, incremental update of every patch's
//! domain triangulation, refinement past the steps, and output.
//!
//! A [`Tessellator`] keeps, per patch, how long its active prefix of baked steps is, and per
//! boundary curve how many samples it carries. [`Tessellator::update`] takes a [`View`],
//! derives each patch's object-space threshold `c`, and brings every patch to the steps
//! recorded with a bound above `c` (see `select`): a frame's work on the triangulations is
//! proportional to what changed.
//!
//! # The error bound
//!
//! Every triangle written is within a computed bound of the surface (see
//! [`crate::bake::PatchBounds`] for the bound and its derivation, and `refine` for how the
//! run time uses it): the baked prefix's triangles are within their recorded bound, every
//! other triangle (next to curve points a neighbour asked for, in a patch whose steps run out,
//! and every refined piece) gets its own bound and is cut until its pieces are within its own
//! threshold. [`FrameStats::max_predicted_error`] is the largest bound over threshold of the
//! frame, in the view's units.
//!
//! # Back-patch culling
//!
//! In a closed model, a patch that shows the eye only its back is culled like one off the
//! view (see [`BackPatches`]); every ray that meets it has met the front of the surface
//! before.
//!
//! # Output
//!
//! [`Tessellator::write_mesh`] writes an indexed mesh; [`Tessellator::stream`] hands every
//! triangle with its vertices to a [`TriangleSink`](crate::TriangleSink). Vertices at patch
//! corners and on boundary curves are computed once, from the curve's owner, so both patches
//! along a curve use the same bits (and, in indexed output, the same index). A collapsed edge
//! is one vertex, and triangles that would have two corners on it are dropped.

mod agree;
mod back;
mod bound_cache;
mod budget;
mod emit;
mod fixed;
mod output_vertex;
mod patch_view;
mod pattern;
mod pieces;
mod pool;
mod refine;
mod select;
mod settings;
mod states;
mod stats;
mod storage;
mod stream;
mod vertex_cache;

pub use bound_cache::BoundSlot;
pub use budget::{BudgetError, BudgetFit};
pub use fixed::FixedStorage;
pub use pool::PoolSize;
pub use settings::{BackPatches, Settings, MAX_FACTOR};
pub use stats::FrameStats;
pub use storage::{
    CurveSlot, PatchSlot, StorageSize, TessellatorError, TessellatorStorage, TriangleSlot,
};
pub use vertex_cache::PointSlot;

use crate::domain::DomainIndex;
use core::fmt;

use glam::Vec3;

use crate::bake::BakedModel;
#[cfg(feature = "embedded-graphics")]
use crate::bound::Aabb;
use crate::bound::BoundingSphere;
use crate::domain::{DomainMesh, GridPoint, InsertError};
use crate::math::max;
use crate::model::PatchSet;
use crate::patch::Side;
use crate::view::View;

use emit::MeshCounts;
use storage::{max_patch_vertices, patch_capacity};

/// Largest frame, in triangles, that refinement may produce: comfortably inside the `u32`
/// indices and counts of the output. A frame whose refinement could exceed it is not refined
/// (its [`FrameStats::max_predicted_error`] says how far above the tolerance it is).
const MAX_REFINED_TRIANGLES: u64 = (u32::MAX / 8) as u64;

/// Why a frame could not be updated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum UpdateError {
    /// The tolerance is not a positive finite number.
    BadTolerance,
    /// A domain mesh refused a baked sample (a baked model whose samples coincide); the
    /// tessellator is left in an unspecified but valid state.
    Mesh {
        /// The patch.
        patch: usize,
        /// What went wrong.
        error: InsertError,
    },
}

impl fmt::Display for UpdateError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            UpdateError::BadTolerance => f.write_str("tolerance must be positive and finite"),
            UpdateError::Mesh { patch, error } => write!(f, "patch {patch}: {error}"),
        }
    }
}

impl core::error::Error for UpdateError {}

/// The run-time tessellator of one baked model, over caller storage.
///
/// ```
/// use spline_tess::bake::{bake_model, BakeScratch, BakeSettings, BakedModel, Tolerance};
/// use spline_tess::bake::{CurveSample, CurveSegment, InteriorSample, TriangleDeviation};
/// use spline_tess::tessellator::{Settings, StorageSize, Tessellator, TessellatorStorage};
/// use spline_tess::tessellator::{BoundSlot, CurveSlot, PatchSlot, PointSlot, TriangleSlot};
/// use spline_tess::{BoundaryCurve, EdgeLink, MeshTriangle, MeshVertex, Model};
/// use spline_tess::{PatchHeader, PatchSet, Vertex, View};
///
/// // One biquadratic bump, baked to 1e-3.
/// let mut points = [[0.0f32; 3]; 9];
/// for i in 0..3 {
///     for j in 0..3 {
///         let z = if i == 1 && j == 1 { 1.0 } else { 0.0 };
///         points[i * 3 + j] = [i as f32, j as f32, z];
///     }
/// }
/// let headers = [PatchHeader { degree_u: 2, degree_v: 2, first_point: 0 }];
/// let patches = PatchSet::new(&headers, &points, None).unwrap();
/// let (mut edges, mut curves) = ([[EdgeLink::Collapsed; 4]; 1], [BoundaryCurve::default(); 4]);
/// let model = Model::build(patches, &mut edges, &mut curves).unwrap();
/// let settings = BakeSettings { tolerance: Tolerance::Absolute(1e-3), max_curve_samples: 64,
///                               max_interior_samples: 256 };
/// let s = settings.scratch_size();
/// let (mut v, mut t) = (vec![MeshVertex::default(); s.vertices], vec![MeshTriangle::default(); s.triangles]);
/// let mut d = vec![TriangleDeviation::default(); s.triangles];
/// let mut seg = vec![CurveSegment::default(); s.segments];
/// let mut cs = vec![CurveSample::default(); s.curve_samples];
/// let mut is = vec![InteriorSample::default(); s.interior_samples];
/// let scratch = BakeScratch { vertices: &mut v, triangles: &mut t, deviations: &mut d,
///     segments: &mut seg, curve_samples: &mut cs, interior_samples: &mut is };
/// let mut bytes = vec![0u8; 1 << 16];
/// let n = bake_model(&model, &settings, scratch, &mut bytes).unwrap().bytes;
/// let baked = BakedModel::from_bytes(&bytes[..n]).unwrap();
///
/// // Storage for the run time, sized from the bake.
/// let settings = Settings::default();
/// let size = StorageSize::of(&baked, &settings);
/// let mut ps = vec![PatchSlot::default(); size.patches];
/// let mut cv = vec![CurveSlot::default(); size.curves];
/// let mut order = vec![0u16; size.curve_order];
/// let mut mv = vec![MeshVertex::default(); size.vertices];
/// let mut mt = vec![MeshTriangle::default(); size.triangles];
/// let mut ts = vec![TriangleSlot::default(); size.triangle_states];
/// let mut bounds = vec![BoundSlot::default(); size.bounds];
/// let mut points = vec![PointSlot::default(); size.vertex_points];
/// let mut scratch = vec![0u32; size.scratch];
/// let storage = TessellatorStorage { patches: &mut ps, curves: &mut cv, curve_order: &mut order,
///     vertices: &mut mv, triangles: &mut mt, triangle_states: &mut ts, bounds: &mut bounds,
///     vertex_points: &mut points, scratch: &mut scratch };
/// let mut tess = Tessellator::new(patches, baked, settings, storage).unwrap();
///
/// // A coarse frame, then a finer one: samples are inserted, not rebuilt.
/// let coarse = tess.update(&View::Object { tolerance: 0.05 }).unwrap();
/// let fine = tess.update(&View::Object { tolerance: 0.002 }).unwrap();
/// assert!(fine.triangles > coarse.triangles && fine.inserted > 0);
/// assert!(fine.max_predicted_error <= 0.002);
///
/// let mut vertices = vec![Vertex::default(); fine.vertices];
/// let mut triangles = vec![[0u16; 3]; fine.triangles];
/// tess.write_mesh(&mut vertices, &mut triangles).unwrap();
///
/// // The pool (vertices, triangles) may be any size from the least one, four vertex and two
/// // triangle slots per patch. A frame that needs more cuts its baked steps to fit, and
/// // refinement takes over within the same bound in the patches whose triangles find room
/// // for their states (here, all). The caches may be empty: bounds and points are then
/// // computed again whenever a frame needs them.
/// let least = StorageSize::minimum(&baked, &settings);
/// let mut mv = [MeshVertex::default(); 4];
/// let mut mt = [MeshTriangle::default(); 2];
/// let mut ts = [TriangleSlot::default(); 2];
/// assert!(mv.len() >= least.vertices && mt.len() >= least.triangles);
/// let storage = TessellatorStorage { patches: &mut ps, curves: &mut cv, curve_order: &mut order,
///     vertices: &mut mv, triangles: &mut mt, triangle_states: &mut ts, bounds: &mut [],
///     vertex_points: &mut [], scratch: &mut scratch };
/// let mut small = Tessellator::new(patches, baked, settings, storage).unwrap();
/// let cut = small.update(&View::Object { tolerance: 0.002 }).unwrap();
/// assert!(cut.prefix_scale > 1.0 && cut.max_predicted_error <= 0.002);
/// assert_eq!(cut.patches_without_states, 0);
/// // What this view needs for every baked step it asks for:
/// assert_eq!(cut.pool_needed.vertices, fine.mesh_vertices);
/// drop(small);
///
/// // A pool of `u8`-indexed slots (`DomainIndex`) takes 6 bytes per triangle slot instead
/// // of 12. A patch's mesh then holds at most 130 vertices; a patch baked with more samples
/// // stops there and refines, within the same bound.
/// let narrow = StorageSize::of_indexed::<u8>(&baked, &settings);
/// assert!(narrow.vertices <= size.vertices);
/// let mut mv = vec![MeshVertex::<u8>::default(); narrow.vertices];
/// let mut mt = vec![MeshTriangle::<u8>::default(); narrow.triangles];
/// let mut ts = vec![TriangleSlot::default(); narrow.triangle_states];
/// let storage = TessellatorStorage { patches: &mut ps, curves: &mut cv, curve_order: &mut order,
///     vertices: &mut mv, triangles: &mut mt, triangle_states: &mut ts, bounds: &mut [],
///     vertex_points: &mut [], scratch: &mut scratch };
/// let mut compact = Tessellator::indexed(patches, baked, settings, storage).unwrap();
/// assert!(compact.update(&View::Object { tolerance: 0.002 }).unwrap().max_predicted_error <= 0.002);
/// ```
#[derive(Debug)]
pub struct Tessellator<'m, 's, Ix: DomainIndex = u16> {
    patches: PatchSet<'m>,
    baked: BakedModel<'m>,
    settings: Settings,
    storage: TessellatorStorage<'s, Ix>,
    nodes: u32,
    view: Option<View>,
    refine: bool,
    counts: MeshCounts,
    /// The model's bounding sphere when back-facing patches may be culled (see `back`).
    closed: Option<BoundingSphere>,
    /// The bound-cache entry used when the caller's cache is empty.
    spare_bound: BoundSlot,
    /// Triangle states the frame's patches have taken from the arena.
    states_taken: usize,
    /// Triangle states the frame's patches have asked for.
    states_wanted: usize,
    /// The box around every patch (computed once: a renderer asks for it every frame).
    #[cfg(feature = "embedded-graphics")]
    model_box: Option<Aabb>,
}

#[cfg(feature = "embedded-graphics")]
impl<Ix: DomainIndex> Tessellator<'_, '_, Ix> {
    /// The box around every patch of the model.
    pub(crate) fn model_box(&self) -> Option<Aabb> {
        self.model_box
    }
}

/// The side both points lie on, if any.
pub(crate) fn common_side(a: GridPoint, b: GridPoint) -> Option<Side> {
    let m = GridPoint::MAX;
    if a.v == 0 && b.v == 0 {
        Some(Side::V0)
    } else if a.u == m && b.u == m {
        Some(Side::U1)
    } else if a.v == m && b.v == m {
        Some(Side::V1)
    } else if a.u == 0 && b.u == 0 {
        Some(Side::U0)
    } else {
        None
    }
}

/// Position of a grid point along `side`, as the edge's own parameter.
pub(crate) fn along(side: Side, p: GridPoint) -> u16 {
    match side {
        Side::V0 | Side::V1 => p.u,
        Side::U0 | Side::U1 => p.v,
    }
}

impl<'m, 's> Tessellator<'m, 's> {
    /// A tessellator for `patches` baked as `baked`, holding no samples yet. (For a pool of
    /// another index type, see [`Tessellator::indexed`].)
    pub fn new(
        patches: PatchSet<'m>,
        baked: BakedModel<'m>,
        settings: Settings,
        storage: TessellatorStorage<'s>,
    ) -> Result<Self, TessellatorError> {
        Self::indexed(patches, baked, settings, storage)
    }
}

impl<'m, 's, Ix: DomainIndex> Tessellator<'m, 's, Ix> {
    /// Like [`Tessellator::new`], over a pool of slots indexed by any [`DomainIndex`]:
    /// `u8` slots take half the bytes per triangle, and hold at most 130 vertices per patch
    /// (a patch baked with more samples stops there and refines, within the same bound;
    /// [`StorageSize::of_indexed`] sizes such a pool).
    pub fn indexed(
        patches: PatchSet<'m>,
        baked: BakedModel<'m>,
        settings: Settings,
        storage: TessellatorStorage<'s, Ix>,
    ) -> Result<Self, TessellatorError> {
        if !baked.matches(&patches) {
            return Err(TessellatorError::ModelMismatch);
        }
        let settings = Settings {
            max_factor: settings.max_factor.clamp(1, MAX_FACTOR),
            ..settings
        };
        let needed = StorageSize::minimum(&baked, &settings);
        let s = &storage;
        if s.patches.len() < needed.patches
            || s.curves.len() < needed.curves
            || s.curve_order.len() < needed.curve_order
            || s.vertices.len() < needed.vertices
            || s.triangles.len() < needed.triangles
            || s.scratch.len() < needed.scratch
        {
            return Err(TessellatorError::StorageTooSmall { needed });
        }
        let mut tess = Tessellator {
            patches,
            baked,
            settings,
            storage,
            nodes: 0,
            view: None,
            refine: true,
            counts: MeshCounts::default(),
            closed: None,
            spare_bound: BoundSlot::default(),
            states_taken: 0,
            states_wanted: 0,
            #[cfg(feature = "embedded-graphics")]
            model_box: patches.aabb(),
        };
        tess.lay_out()?;
        if settings.back_patches == BackPatches::CullWhenClosed {
            tess.closed = tess.orient_patches();
        }
        Ok(tess)
    }

    /// Assigns storage to patches and curves, starts every mesh, and finds the corner nodes.
    fn lay_out(&mut self) -> Result<(), TessellatorError> {
        let baked = self.baked;
        let mut order = 0u32;
        for k in 0..baked.curve_count() {
            let curve = baked.curve(k);
            let n = curve.map_or(0, |c| c.samples.len());
            self.storage.curves[k] = CurveSlot {
                order_offset: order,
                owner: curve.map_or(0, |c| c.patch),
                side: curve.map_or(Side::V0, |c| c.side),
                ..CurveSlot::default()
            };
            order += n as u32;
        }
        // Every mesh starts as its two triangles, packed at the front of the pool.
        for p in 0..baked.patch_count() {
            let (Some(bp), Some(patch)) = (baked.patch(p), self.patches.patch(p)) else {
                return Err(TessellatorError::ModelMismatch);
            };
            let (vc, tc, cap) = patch_capacity::<Ix>(&baked, &bp, &self.settings);
            if vc > max_patch_vertices::<Ix>() {
                return Err(TessellatorError::PatchTooLarge { patch: p });
            }
            let (vo, to) = (4 * p, 2 * p);
            let mesh = DomainMesh::indexed(
                &mut self.storage.vertices[vo..vo + 4],
                &mut self.storage.triangles[to..to + 2],
                bp.metric,
            )
            .map_err(|_| TessellatorError::PatchTooLarge { patch: p })?;
            let header = mesh.header();
            let sphere = BoundingSphere::of_points(patch.points()).unwrap_or(BoundingSphere {
                center: Vec3::ZERO,
                radius: 0.0,
            });
            self.storage.patches[p] = PatchSlot {
                vertex_offset: vo as u32,
                vertex_capacity: 4,
                triangle_offset: to as u32,
                triangle_capacity: 2,
                // (Within `max_patch_vertices`, so both fit.)
                vertex_limit: vc as u16,
                triangle_limit: tc as u16,
                mesh: header,
                step_cap: cap,
                center: sphere.center.to_array(),
                radius: sphere.radius,
                ..PatchSlot::default()
            };
        }
        // Corner nodes: corners with the same control point (bit for bit) are one vertex.
        let mut nodes = 0u32;
        for p in 0..baked.patch_count() {
            self.storage.patches[p].first_node = nodes;
            for k in 0..4 {
                let here = self.corner_position(p, k);
                let mut found = None;
                'search: for q in 0..=p {
                    for j in 0..4 {
                        if (q, j) == (p, k) {
                            break 'search;
                        }
                        if self.corner_position(q, j).to_array().map(f32::to_bits)
                            == here.to_array().map(f32::to_bits)
                        {
                            found = Some(self.storage.patches[q].nodes[j]);
                            break 'search;
                        }
                    }
                }
                self.storage.patches[p].nodes[k] = found.unwrap_or_else(|| {
                    nodes += 1;
                    nodes - 1
                });
            }
        }
        self.nodes = nodes;
        Ok(())
    }

    /// Control point at corner `k` (domain corner order) of patch `p`: the corner's position,
    /// read without evaluating the surface (node matching compares every pair of corners).
    fn corner_position(&self, p: usize, k: usize) -> Vec3 {
        self.patches.patch(p).map_or(Vec3::ZERO, |patch| {
            let (du, dv) = (patch.degree_u(), patch.degree_v());
            let (i, j) = [(0, 0), (du, 0), (du, dv), (0, dv)][k];
            patch.control_point(i, j)
        })
    }

    /// The patches.
    pub fn patches(&self) -> &PatchSet<'m> {
        &self.patches
    }

    /// The baked model.
    pub fn baked(&self) -> &BakedModel<'m> {
        &self.baked
    }

    /// The settings in use.
    pub fn settings(&self) -> Settings {
        self.settings
    }

    /// Size of the mesh the current frame writes.
    pub fn mesh_size(&self) -> crate::sink::MeshSize {
        crate::sink::MeshSize {
            vertices: self.counts.vertices as usize,
            triangles: self.counts.triangles as usize,
        }
    }

    /// The range of [`write_mesh`](Self::write_mesh)'s triangles that belong to patch `p`
    /// (empty when culled).
    pub fn patch_triangles(&self, p: usize) -> core::ops::Range<usize> {
        match self.storage.patches.get(p) {
            Some(s) if !s.culled && p < self.baked.patch_count() => {
                s.triangles[0] as usize..s.triangles[1] as usize
            }
            _ => 0..0,
        }
    }

    /// A sphere around patch `p`'s control points (so around the patch and every triangle
    /// written for it); `None` when `p` is out of range.
    pub fn patch_bound(&self, p: usize) -> Option<BoundingSphere> {
        if p >= self.baked.patch_count() {
            return None;
        }
        let slot = self.storage.patches.get(p)?;
        Some(BoundingSphere {
            center: Vec3::from_array(slot.center),
            radius: slot.radius,
        })
    }

    /// True when patch `p` was culled in the current frame.
    pub fn is_culled(&self, p: usize) -> bool {
        self.storage.patches.get(p).is_some_and(|s| s.culled)
    }

    /// True when patch `p` was culled in the current frame for facing away from the eye.
    pub fn is_back_facing(&self, p: usize) -> bool {
        self.storage.patches.get(p).is_some_and(|s| s.back_facing)
    }

    /// True when this model's back-facing patches may be culled: it is closed, its normals
    /// agree and its outside is known (checked when the tessellator was made).
    pub fn culls_back_patches(&self) -> bool {
        self.closed.is_some()
    }

    /// Brings every patch to `view`: inserts and deletes samples, estimates new triangles,
    /// chooses refinement factors. Returns the frame's numbers.
    pub fn update(&mut self, view: &View) -> Result<FrameStats, UpdateError> {
        self.apply(view, true)
    }

    /// Like [`update`](Self::update), with refinement turned off: the mesh is exactly the
    /// active samples' triangulation (the budget mode's mesh).
    pub fn update_unrefined(&mut self, view: &View) -> Result<FrameStats, UpdateError> {
        self.apply(view, false)
    }

    fn apply(&mut self, view: &View, refine: bool) -> Result<FrameStats, UpdateError> {
        let tol = view.tolerance();
        if !(tol > 0.0 && tol.is_finite()) {
            return Err(UpdateError::BadTolerance);
        }
        self.view = Some(*view);
        self.refine = refine;
        let mut stats = FrameStats::default();
        let baked = self.baked;
        let fit = self.select(view, tol);
        stats.pool_needed = fit.needed;
        stats.prefix_scale = fit.scale;
        if fit.release {
            self.release_culled();
        }
        // Bring the meshes of the visible patches to their targets: deletions, the pool laid
        // out for the targets if they outgrew it, insertions.
        for p in 0..baked.patch_count() {
            if self.storage.patches[p].culled {
                stats.culled_patches += 1;
                stats.back_facing_patches += usize::from(self.storage.patches[p].back_facing);
            } else {
                self.shrink_patch(p, &mut stats);
            }
        }
        self.lay_out_pool();
        for p in 0..baked.patch_count() {
            if !self.storage.patches[p].culled {
                self.grow_patch(p, &mut stats)
                    .map_err(|error| UpdateError::Mesh { patch: p, error })?;
            }
        }
        self.choose_factors(view, tol, refine, &mut stats);
        if refine && self.refined_bound() > MAX_REFINED_TRIANGLES {
            // Only an absurd tolerance asks for this much: draw the steps alone.
            self.choose_factors(view, tol, false, &mut stats);
        }
        self.counts = self.count();
        self.fill_vertex_points();
        stats.triangles = self.counts.triangles as usize;
        stats.vertices = self.counts.vertices as usize;
        let mut worst = 0.0f32;
        for slot in self.storage.patches[..baked.patch_count()].iter() {
            if !slot.culled {
                stats.mesh_vertices += usize::from(slot.mesh.vertex_count());
                stats.mesh_triangles += slot.mesh.triangle_count();
                worst = max(worst, slot.error_ratio);
                if slot.factor > 1 {
                    stats.refined_patches += 1;
                }
            }
        }
        stats.max_predicted_error = worst * tol;
        Ok(stats)
    }

    /// An upper bound on the frame's triangles with the chosen factors: a domain triangle
    /// whose factors are at most `f` is cut into at most `f² + 3f` (see `pattern`).
    fn refined_bound(&self) -> u64 {
        self.storage.patches[..self.baked.patch_count()]
            .iter()
            .filter(|s| !s.culled)
            .map(|s| {
                let f = u64::from(s.factor.max(1));
                s.mesh.triangle_count() as u64 * (f * f + 3 * f)
            })
            .sum()
    }
}

/// Domain corners in mesh order: `(0,0), (1,0), (1,1), (0,1)`.
pub(crate) const CORNER_UV: [(f32, f32); 4] = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];

#[cfg(test)]
mod tests {
    use super::select::prefix;

    #[test]
    fn prefix_takes_samples_recorded_above_the_threshold() {
        let d = [0.5f32, 0.25, 0.25, 0.1];
        let f = |i: usize| d[i];
        assert_eq!(prefix(1.0, 4, f, 2.0), 0);
        assert_eq!(prefix(1.0, 4, f, 1.0), 0);
        assert_eq!(prefix(1.0, 4, f, 0.9), 1);
        assert_eq!(prefix(1.0, 4, f, 0.5), 1);
        assert_eq!(prefix(1.0, 4, f, 0.3), 2);
        assert_eq!(prefix(1.0, 4, f, 0.25), 2);
        assert_eq!(prefix(1.0, 4, f, 0.2), 4);
        assert_eq!(prefix(1.0, 4, f, 0.1), 4);
        assert_eq!(prefix(1.0, 4, f, 0.01), 4);
        assert_eq!(prefix(1.0, 0, f, 0.01), 0);
    }
}
