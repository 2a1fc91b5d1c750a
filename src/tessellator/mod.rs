//! The run time: per-frame selection of baked samples, incremental update of every patch's
//! domain triangulation, refinement past the samples, and output.
//!
//! A [`Tessellator`] keeps, per patch and per boundary curve, how long its active prefix of
//! baked samples is. [`Tessellator::update`] takes a [`View`], derives each patch's
//! object-space threshold `c` (each curve takes the smallest `c` of the patches using it),
//! and inserts or deletes samples so that exactly those recorded with a deviation above `c`
//! are in. A frame's work on the triangulations is proportional to the samples that changed.
//!
//! # The error bound at run time
//!
//! The bake records each patch's deviation with *all* its curve samples in, but at run time a
//! curve carries only the prefix its `c` needs, and a patch's interior may be capped by its
//! storage or exhausted. So the run time does not take the recorded values on trust: it
//! estimates every triangle's deviation when the triangle first appears (a scan of the
//! triangle's 6-step barycentric lattice, 25 surface points; cached per triangle slot and
//! reused as long as the triangle stays) and multiplies it by [`ESTIMATE_SAFETY`]. A triangle
//! whose estimate exceeds `c` is refined uniformly by the smallest factor `N` with
//! `estimate / N² <= c`, at most [`Settings::max_factor`]. Each edge takes the larger factor
//! of its two triangles, and each boundary curve the largest factor of the triangles along it
//! in any patch, so both sides of every edge place the same points (see `pattern`).
//!
//! # Output
//!
//! [`Tessellator::write_mesh`] writes an indexed mesh; [`Tessellator::stream`] hands every
//! triangle with its vertices to a [`TriangleSink`](crate::TriangleSink). Vertices at patch
//! corners and on boundary curves are computed once, from the curve's owner, so both patches
//! along a curve use the same bits (and, in indexed output, the same index). A collapsed edge
//! is one vertex, and triangles that would have two corners on it are dropped.

mod budget;
mod emit;
mod pattern;

pub use budget::{BudgetError, BudgetFit};

use core::fmt;

use glam::Vec3;

use crate::bake::{boundary_point, BakedModel, BakedPatch};
use crate::bound::BoundingSphere;
use crate::domain::{DomainMesh, GridPoint, InsertError, MeshHeader, MeshTriangle, MeshVertex};
use crate::math::{length, sqrt};
use crate::model::{EdgeLink, PatchSet};
use crate::patch::{BezierPatch, Side};
use crate::view::View;

use emit::MeshCounts;

/// Factor applied to a triangle's scanned deviation before it is compared with `c`: the scan
/// can miss the true maximum between its points (by 5% for a cubic bubble, the worst case of
/// a smooth patch's error between lattice points).
pub const ESTIMATE_SAFETY: f32 = 1.1;

/// Barycentric steps of the run-time deviation scan.
const SCAN: u32 = 6;

/// Largest refinement factor (a refined triangle has at most `MAX_FACTOR²` pieces plus
/// `3 MAX_FACTOR` along its sides); [`Settings::max_factor`] is capped here.
pub const MAX_FACTOR: u8 = 64;

/// Largest frame, in triangles, that refinement may produce: comfortably inside the `u32`
/// indices and counts of the output. A frame whose refinement could exceed it is not refined
/// (its [`FrameStats::max_predicted_error`] says how far above the tolerance it is).
const MAX_REFINED_TRIANGLES: u64 = (u32::MAX / 8) as u64;

/// Run-time settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Settings {
    /// Interior samples per patch the storage holds, at most (the rest of a patch's list is
    /// never used; refinement takes over).
    pub max_interior_samples: u16,
    /// Largest refinement factor of a triangle (1 turns refinement off; values above
    /// [`MAX_FACTOR`] count as it).
    pub max_factor: u8,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            max_interior_samples: u16::MAX,
            max_factor: 16,
        }
    }
}

/// One patch's run-time state (storage slot; contents are private).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PatchSlot {
    vertex_offset: u32,
    vertex_capacity: u32,
    triangle_offset: u32,
    triangle_capacity: u32,
    mesh: MeshHeader,
    /// Curve samples in the mesh, per side.
    sides: [u16; 4],
    /// Interior samples in the mesh.
    interior: u16,
    interior_cap: u16,
    center: [f32; 3],
    radius: f32,
    nodes: [u32; 4],
    /// The patch's output triangles in the current frame.
    triangles: [u32; 2],
    /// Nodes created by the patches before this one.
    first_node: u32,
    /// Threshold of the current frame.
    c: f32,
    culled: bool,
    /// Largest refinement factor of the frame.
    factor: u8,
    /// Largest predicted deviation over `c`.
    error_ratio: f32,
}

/// One boundary curve's run-time state (storage slot; contents are private).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CurveSlot {
    /// First slot in the sorted-parameter storage.
    order_offset: u32,
    /// Active samples.
    count: u16,
    c: f32,
    /// Scratch threshold of the budget prediction.
    predict_c: f32,
    used: bool,
    factor: u8,
    /// First output vertex of the curve in the current [`Tessellator::write_mesh`].
    base: u32,
}

/// One domain triangle's cached deviation (storage slot; contents are private).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TriangleSlot {
    corners: [GridPoint; 3],
    deviation: f32,
    factor: u8,
}

/// Storage sizes a [`Tessellator`] needs for a baked model.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StorageSize {
    /// [`PatchSlot`]s: one per patch.
    pub patches: usize,
    /// [`CurveSlot`]s: one per curve.
    pub curves: usize,
    /// `u16`s for the curves' sorted parameters: one per curve sample.
    pub curve_order: usize,
    /// [`MeshVertex`] slots, over all patches.
    pub vertices: usize,
    /// [`MeshTriangle`] and [`TriangleSlot`] slots, over all patches.
    pub triangles: usize,
    /// `u32` scratch for output: the largest patch's vertex slots plus three per triangle
    /// slot.
    pub scratch: usize,
}

impl StorageSize {
    /// What `baked` needs with `settings`.
    pub fn of(baked: &BakedModel<'_>, settings: &Settings) -> StorageSize {
        let mut size = StorageSize {
            patches: baked.patch_count(),
            curves: baked.curve_count(),
            curve_order: baked.curve_sample_count(),
            ..StorageSize::default()
        };
        for k in 0..baked.patch_count() {
            if let Some(bp) = baked.patch(k) {
                let (v, t, _) = patch_capacity(baked, &bp, settings);
                size.vertices += v;
                size.triangles += t;
                size.scratch = size.scratch.max(v + 3 * t);
            }
        }
        size
    }
}

/// Vertex and triangle slots of one patch, and its interior cap.
fn patch_capacity(
    baked: &BakedModel<'_>,
    bp: &BakedPatch<'_>,
    settings: &Settings,
) -> (usize, usize, u16) {
    let mut v = 4usize;
    for link in bp.edges {
        if let EdgeLink::Curve { curve, .. } = link {
            v += baked.curve(curve as usize).map_or(0, |c| c.samples.len());
        }
    }
    let room = (u16::MAX as usize - 1).saturating_sub(v);
    let cap = bp
        .samples
        .len()
        .min(settings.max_interior_samples as usize)
        .min(room);
    v += cap;
    (v, DomainMesh::triangles_for(v), cap as u16)
}

/// The caller's storage for a [`Tessellator`], sized by [`StorageSize::of`] (longer slices are
/// fine).
#[derive(Debug)]
pub struct TessellatorStorage<'s> {
    /// Per patch.
    pub patches: &'s mut [PatchSlot],
    /// Per curve.
    pub curves: &'s mut [CurveSlot],
    /// Per curve sample.
    pub curve_order: &'s mut [u16],
    /// Domain-mesh vertices of every patch.
    pub vertices: &'s mut [MeshVertex],
    /// Domain-mesh triangles of every patch.
    pub triangles: &'s mut [MeshTriangle],
    /// Cached deviations, one per domain triangle slot.
    pub triangle_states: &'s mut [TriangleSlot],
    /// Output scratch.
    pub scratch: &'s mut [u32],
}

/// Why a [`Tessellator`] cannot be built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum TessellatorError {
    /// The baked model was not baked from these patches.
    ModelMismatch,
    /// Some storage slice is shorter than needed.
    StorageTooSmall {
        /// What is needed.
        needed: StorageSize,
    },
    /// A patch's curve samples alone exceed a domain mesh's capacity (65 535 vertices).
    PatchTooLarge {
        /// The patch.
        patch: usize,
    },
}

impl fmt::Display for TessellatorError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TessellatorError::ModelMismatch => {
                f.write_str("the baked model was not baked from these patches")
            }
            TessellatorError::StorageTooSmall { needed } => write!(
                f,
                "storage too small: needs {} patch, {} curve, {} order, {} vertex, {} triangle \
                 and {} scratch slots",
                needed.patches,
                needed.curves,
                needed.curve_order,
                needed.vertices,
                needed.triangles,
                needed.scratch
            ),
            TessellatorError::PatchTooLarge { patch } => {
                write!(
                    f,
                    "patch {patch} has too many curve samples for one domain mesh"
                )
            }
        }
    }
}

impl core::error::Error for TessellatorError {}

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

/// Numbers of one frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct FrameStats {
    /// Triangles of the frame's mesh.
    pub triangles: usize,
    /// Vertices of the frame's indexed mesh.
    pub vertices: usize,
    /// Domain-mesh insertions this frame (a curve sample counts once per patch using it).
    pub inserted: usize,
    /// Domain-mesh deletions this frame.
    pub deleted: usize,
    /// Triangles whose deviation was estimated this frame (new since the last frame).
    pub estimated: usize,
    /// Patches with at least one refined triangle or edge.
    pub refined_patches: usize,
    /// Patches culled by the view.
    pub culled_patches: usize,
    /// Largest predicted error of the frame, in the view's units (pixels or model units);
    /// at most the tolerance unless refinement hit [`Settings::max_factor`] or was off.
    pub max_predicted_error: f32,
}

/// The run-time tessellator of one baked model, over caller storage.
///
/// ```
/// use spline_tess::bake::{bake_model, BakeScratch, BakeSettings, BakedModel, Tolerance};
/// use spline_tess::bake::{CurveSample, CurveSegment, InteriorSample, TriangleDeviation};
/// use spline_tess::tessellator::{Settings, StorageSize, Tessellator, TessellatorStorage};
/// use spline_tess::tessellator::{CurveSlot, PatchSlot, TriangleSlot};
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
/// let mut ts = vec![TriangleSlot::default(); size.triangles];
/// let mut scratch = vec![0u32; size.scratch];
/// let storage = TessellatorStorage { patches: &mut ps, curves: &mut cv, curve_order: &mut order,
///     vertices: &mut mv, triangles: &mut mt, triangle_states: &mut ts, scratch: &mut scratch };
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
/// ```
#[derive(Debug)]
pub struct Tessellator<'m, 's> {
    patches: PatchSet<'m>,
    baked: BakedModel<'m>,
    settings: Settings,
    storage: TessellatorStorage<'s>,
    nodes: u32,
    view: Option<View>,
    refine: bool,
    counts: MeshCounts,
}

/// Count of samples recorded with a deviation above `c` in a non-increasing list whose value
/// before the first sample is `initial`.
fn prefix(initial: f32, len: usize, deviation: impl Fn(usize) -> f32, c: f32) -> usize {
    // NaN thresholds and deviations count as "not above".
    if initial.partial_cmp(&c) != Some(core::cmp::Ordering::Greater) {
        return 0;
    }
    // Smallest n in 1..=len with deviation(n - 1) <= c, or len.
    let (mut lo, mut hi) = (1usize, len);
    if len == 0 {
        return 0;
    }
    if deviation(len - 1) > c {
        return len;
    }
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        if deviation(mid - 1) <= c {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    lo
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

/// Scanned deviation of the patch from the flat triangle `corners`.
fn estimate(patch: &BezierPatch<'_>, corners: [GridPoint; 3]) -> f32 {
    let uv = corners.map(GridPoint::to_unit);
    let pos = uv.map(|(u, v)| patch.position(u, v));
    let mut best = 0.0f32;
    let inv = 1.0 / SCAN as f32;
    for i in 0..=SCAN {
        for j in 0..=SCAN - i {
            let k = SCAN - i - j;
            if i == SCAN || j == SCAN || k == SCAN {
                continue;
            }
            let (a, b, c) = (i as f32 * inv, j as f32 * inv, k as f32 * inv);
            let u = uv[0].0 * a + uv[1].0 * b + uv[2].0 * c;
            let v = uv[0].1 * a + uv[1].1 * b + uv[2].1 * c;
            let linear: Vec3 = pos[0] * a + pos[1] * b + pos[2] * c;
            let d = length(patch.position(u.clamp(0.0, 1.0), v.clamp(0.0, 1.0)) - linear);
            if d > best {
                best = d;
            }
        }
    }
    best
}

/// Smallest factor `n <= max` with `deviation / n² <= c`.
fn factor_for(deviation: f32, c: f32, max: u8) -> u8 {
    if deviation.partial_cmp(&c) != Some(core::cmp::Ordering::Greater) {
        return 1;
    }
    let n = libm::ceilf(sqrt(deviation / c));
    if n >= max as f32 {
        max
    } else {
        (n as u8).max(1)
    }
}

impl<'m, 's> Tessellator<'m, 's> {
    /// A tessellator for `patches` baked as `baked`, holding no samples yet.
    pub fn new(
        patches: PatchSet<'m>,
        baked: BakedModel<'m>,
        settings: Settings,
        storage: TessellatorStorage<'s>,
    ) -> Result<Self, TessellatorError> {
        if !baked.matches(&patches) {
            return Err(TessellatorError::ModelMismatch);
        }
        let settings = Settings {
            max_factor: settings.max_factor.clamp(1, MAX_FACTOR),
            ..settings
        };
        let needed = StorageSize::of(&baked, &settings);
        let s = &storage;
        if s.patches.len() < needed.patches
            || s.curves.len() < needed.curves
            || s.curve_order.len() < needed.curve_order
            || s.vertices.len() < needed.vertices
            || s.triangles.len() < needed.triangles
            || s.triangle_states.len() < needed.triangles
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
        };
        tess.lay_out()?;
        Ok(tess)
    }

    /// Assigns storage to patches and curves, starts every mesh, and finds the corner nodes.
    fn lay_out(&mut self) -> Result<(), TessellatorError> {
        let baked = self.baked;
        let mut order = 0u32;
        for k in 0..baked.curve_count() {
            let n = baked.curve(k).map_or(0, |c| c.samples.len());
            self.storage.curves[k] = CurveSlot {
                order_offset: order,
                ..CurveSlot::default()
            };
            order += n as u32;
        }
        let (mut vo, mut to) = (0usize, 0usize);
        for p in 0..baked.patch_count() {
            let (Some(bp), Some(patch)) = (baked.patch(p), self.patches.patch(p)) else {
                return Err(TessellatorError::ModelMismatch);
            };
            let (vc, tc, cap) = patch_capacity(&baked, &bp, &self.settings);
            if vc > u16::MAX as usize {
                return Err(TessellatorError::PatchTooLarge { patch: p });
            }
            let mesh = DomainMesh::with_metric(
                &mut self.storage.vertices[vo..vo + vc],
                &mut self.storage.triangles[to..to + tc],
                bp.metric,
            )
            .map_err(|_| TessellatorError::PatchTooLarge { patch: p })?;
            let header = mesh.header();
            for t in &mut self.storage.triangle_states[to..to + tc] {
                *t = TriangleSlot::default();
            }
            let sphere = BoundingSphere::of_points(patch.points()).unwrap_or(BoundingSphere {
                center: Vec3::ZERO,
                radius: 0.0,
            });
            self.storage.patches[p] = PatchSlot {
                vertex_offset: vo as u32,
                vertex_capacity: vc as u32,
                triangle_offset: to as u32,
                triangle_capacity: tc as u32,
                mesh: header,
                interior_cap: cap,
                center: sphere.center.to_array(),
                radius: sphere.radius,
                ..PatchSlot::default()
            };
            vo += vc;
            to += tc;
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
        self.select(view, tol);
        // Bring the meshes of the visible patches to their targets.
        for p in 0..baked.patch_count() {
            if self.storage.patches[p].culled {
                stats.culled_patches += 1;
                continue;
            }
            self.sync_patch(p, &mut stats)
                .map_err(|error| UpdateError::Mesh { patch: p, error })?;
        }
        self.choose_factors(refine, &mut stats);
        if refine && self.refined_bound() > MAX_REFINED_TRIANGLES {
            // Only an absurd tolerance asks for this much: draw the samples alone.
            self.choose_factors(false, &mut stats);
        }
        self.counts = self.count();
        stats.triangles = self.counts.triangles as usize;
        stats.vertices = self.counts.vertices as usize;
        let mut worst = 0.0f32;
        for slot in self.storage.patches[..baked.patch_count()].iter() {
            if !slot.culled {
                worst = worst.max(slot.error_ratio);
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

    /// Thresholds, culling, and the curves' target prefixes (sorted parameters kept up to
    /// date).
    fn select(&mut self, view: &View, tol: f32) {
        let baked = self.baked;
        for p in 0..baked.patch_count() {
            let slot = &mut self.storage.patches[p];
            let sphere = BoundingSphere {
                center: Vec3::from_array(slot.center),
                radius: slot.radius,
            };
            let (scale, culled) = view.scale(&sphere);
            slot.c = tol * scale;
            slot.culled = culled;
        }
        for c in self.storage.curves[..baked.curve_count()].iter_mut() {
            c.c = f32::INFINITY;
            c.used = false;
        }
        for p in 0..baked.patch_count() {
            let slot = self.storage.patches[p];
            if slot.culled {
                continue;
            }
            let Some(bp) = baked.patch(p) else { continue };
            for link in bp.edges {
                if let EdgeLink::Curve { curve, .. } = link {
                    let cs = &mut self.storage.curves[curve as usize];
                    cs.c = cs.c.min(slot.c);
                    cs.used = true;
                }
            }
        }
        for k in 0..baked.curve_count() {
            let cs = self.storage.curves[k];
            let Some(curve) = baked.curve(k) else {
                continue;
            };
            if !cs.used {
                continue;
            }
            let samples = curve.samples;
            let target = prefix(
                curve.initial_deviation,
                samples.len(),
                |i| samples.get(i).map_or(0.0, |s| s.deviation),
                cs.c,
            ) as u16;
            let off = cs.order_offset as usize;
            let order = &mut self.storage.curve_order[off..off + samples.len()];
            let mut n = cs.count as usize;
            while n < target as usize {
                let t = samples.get(n).map_or(0, |s| s.t);
                let at = order[..n].partition_point(|&x| x < t);
                order.copy_within(at..n, at + 1);
                order[at] = t;
                n += 1;
            }
            while n > target as usize {
                n -= 1;
                let t = samples.get(n).map_or(0, |s| s.t);
                let at = order[..=n].partition_point(|&x| x < t);
                order.copy_within(at + 1..=n, at);
            }
            self.storage.curves[k].count = target;
        }
    }

    /// The mesh of patch `p`, over its storage.
    fn mesh<'b>(storage: &'b mut TessellatorStorage<'s>, slot: &PatchSlot) -> DomainMesh<'b> {
        let (vo, vc) = (slot.vertex_offset as usize, slot.vertex_capacity as usize);
        let (to, tc) = (
            slot.triangle_offset as usize,
            slot.triangle_capacity as usize,
        );
        DomainMesh::resume(
            &mut storage.vertices[vo..vo + vc],
            &mut storage.triangles[to..to + tc],
            slot.mesh,
        )
    }

    /// Deletes, then inserts, samples of patch `p` until it holds its curves' prefixes and its
    /// own.
    fn sync_patch(&mut self, p: usize, stats: &mut FrameStats) -> Result<(), InsertError> {
        let baked = self.baked;
        let Some(bp) = baked.patch(p) else {
            return Ok(());
        };
        let mut slot = self.storage.patches[p];
        let samples = bp.samples;
        let target = prefix(
            bp.initial_deviation,
            samples.len(),
            |i| samples.get(i).map_or(0.0, |s| s.deviation),
            slot.c,
        )
        .min(slot.interior_cap as usize) as u16;
        let curve_targets = bp.edges.map(|link| match link {
            EdgeLink::Curve { curve, .. } => self.storage.curves[curve as usize].count,
            EdgeLink::Collapsed => 0,
        });
        if target == slot.interior && curve_targets == slot.sides {
            return Ok(());
        }
        let mut mesh = Self::mesh(&mut self.storage, &slot);
        // Deletions first, so the mesh never needs more than its capacity.
        while slot.interior > target {
            slot.interior -= 1;
            if let Some(s) = samples.get(slot.interior as usize) {
                if let Some(id) = mesh.find(s.point) {
                    if mesh.remove(id).is_ok() {
                        stats.deleted += 1;
                    }
                }
            }
        }
        for (s, link) in bp.edges.into_iter().enumerate() {
            let EdgeLink::Curve { curve, reversed } = link else {
                continue;
            };
            let Some(bc) = baked.curve(curve as usize) else {
                continue;
            };
            while slot.sides[s] > curve_targets[s] {
                slot.sides[s] -= 1;
                if let Some(cs) = bc.samples.get(slot.sides[s] as usize) {
                    let point = boundary_point(Side::ALL[s], cs.t, reversed);
                    if let Some(id) = mesh.find(point) {
                        if mesh.remove(id).is_ok() {
                            stats.deleted += 1;
                        }
                    }
                }
            }
        }
        let mut result = Ok(());
        'insert: {
            for (s, link) in bp.edges.into_iter().enumerate() {
                let EdgeLink::Curve { curve, reversed } = link else {
                    continue;
                };
                let Some(bc) = baked.curve(curve as usize) else {
                    continue;
                };
                while slot.sides[s] < curve_targets[s] {
                    if let Some(cs) = bc.samples.get(slot.sides[s] as usize) {
                        let point = boundary_point(Side::ALL[s], cs.t, reversed);
                        if let Err(e) = mesh.insert(point) {
                            result = Err(e);
                            break 'insert;
                        }
                        stats.inserted += 1;
                    }
                    slot.sides[s] += 1;
                }
            }
            while slot.interior < target {
                if let Some(s) = samples.get(slot.interior as usize) {
                    if let Err(e) = mesh.insert(s.point) {
                        result = Err(e);
                        break 'insert;
                    }
                    stats.inserted += 1;
                }
                slot.interior += 1;
            }
        }
        slot.mesh = mesh.header();
        self.storage.patches[p] = slot;
        result
    }

    /// Estimates new triangles, and chooses every triangle's and curve's refinement factor.
    fn choose_factors(&mut self, refine: bool, stats: &mut FrameStats) {
        let baked = self.baked;
        let max = if refine { self.settings.max_factor } else { 1 };
        for c in self.storage.curves[..baked.curve_count()].iter_mut() {
            c.factor = 1;
        }
        for p in 0..baked.patch_count() {
            let mut slot = self.storage.patches[p];
            if slot.culled {
                continue;
            }
            let (Some(patch), Some(bp)) = (self.patches.patch(p), baked.patch(p)) else {
                continue;
            };
            slot.factor = 1;
            slot.error_ratio = 0.0;
            let (vo, to, tc) = (
                slot.vertex_offset as usize,
                slot.triangle_offset as usize,
                slot.triangle_capacity as usize,
            );
            for t in 0..tc {
                let Some((v, n)) = self.storage.triangles[to + t].live_parts() else {
                    continue;
                };
                let corners = v.map(|id| {
                    self.storage.vertices[vo + id as usize]
                        .live_point()
                        .unwrap_or_default()
                });
                let state = &mut self.storage.triangle_states[to + t];
                if state.corners != corners {
                    state.corners = corners;
                    state.deviation = estimate(&patch, corners) * ESTIMATE_SAFETY;
                    stats.estimated += 1;
                }
                let f = factor_for(state.deviation, slot.c, max);
                state.factor = f;
                slot.factor = slot.factor.max(f);
                let ff = f as f32;
                slot.error_ratio = slot.error_ratio.max(state.deviation / (ff * ff) / slot.c);
                // Boundary edges hand their factor to the curve.
                for i in 0..3 {
                    if n[i].is_some() {
                        continue;
                    }
                    let (a, b) = (corners[(i + 1) % 3], corners[(i + 2) % 3]);
                    if let Some(side) = common_side(a, b) {
                        if let EdgeLink::Curve { curve, .. } = bp.edges[side.index()] {
                            let cs = &mut self.storage.curves[curve as usize];
                            cs.factor = cs.factor.max(f);
                        }
                    }
                }
            }
            self.storage.patches[p] = slot;
        }
        // A curve's factor can exceed every triangle's along it in one patch: that patch is
        // refined too.
        for p in 0..baked.patch_count() {
            if self.storage.patches[p].culled {
                continue;
            }
            if let Some(bp) = baked.patch(p) {
                for link in bp.edges {
                    if let EdgeLink::Curve { curve, .. } = link {
                        let f = self.storage.curves[curve as usize].factor;
                        let slot = &mut self.storage.patches[p];
                        slot.factor = slot.factor.max(f);
                    }
                }
            }
        }
    }
}

/// Domain corners in mesh order: `(0,0), (1,0), (1,1), (0,1)`.
pub(crate) const CORNER_UV: [(f32, f32); 4] = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];

#[cfg(test)]
mod tests {
    use super::prefix;

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
