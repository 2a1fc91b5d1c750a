//! The caller's storage for a [`Tessellator`](super::Tessellator): its slots, their sizes, and
//! the errors of building one.

use core::fmt;

use crate::bake::{BakedModel, BakedPatch};
use crate::deviation::PatchBounds;
use crate::domain::{DomainIndex, DomainMesh, MeshHeader, MeshTriangle, MeshVertex};
use crate::facing::NormalCone;
use crate::model::EdgeLink;
use crate::patch::Side;

use super::{BoundSlot, PointSlot, PoolSize, Settings};

/// One patch's run-time state (storage slot; contents are private).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PatchSlot {
    pub(super) vertex_offset: u32,
    pub(super) vertex_capacity: u32,
    pub(super) triangle_offset: u32,
    pub(super) triangle_capacity: u32,
    pub(super) mesh: MeshHeader,
    /// The patch's steps (interior samples and curve requests) in the mesh.
    pub(super) steps: u16,
    /// Curve samples the steps in the mesh request, per side.
    pub(super) requests: [u16; 4],
    /// Curve samples in the mesh, per side (at least the requests).
    pub(super) sides: [u16; 4],
    /// Steps the storage holds, at most.
    pub(super) step_cap: u16,
    /// Steps of the frame's target prefix.
    pub(super) target: u16,
    /// Interior points among them.
    pub(super) target_interior: u16,
    /// Vertex slots the patch could ever need (its stretch of the pool is never longer).
    pub(super) vertex_limit: u16,
    /// Triangle slots the patch could ever need.
    pub(super) triangle_limit: u16,
    pub(super) center: [f32; 3],
    pub(super) radius: f32,
    pub(super) nodes: [u32; 4],
    /// The patch's output triangles in the current frame.
    pub(super) triangles: [u32; 2],
    /// Nodes created by the patches before this one.
    pub(super) first_node: u32,
    /// Threshold of the current frame, in object units.
    pub(super) c: f32,
    /// Recorded bound of the current prefix (every triangle of the baked prefix is within it).
    pub(super) recorded: f32,
    pub(super) culled: bool,
    /// Whether its control points' hull lies wholly inside the view this frame (so none of
    /// its triangles is hidden).
    pub(super) inside: bool,
    /// Largest refinement factor of the frame.
    pub(super) factor: u8,
    /// Largest bound over threshold of the frame's triangles.
    pub(super) error_ratio: f32,
    /// Whether the patch's patterns were checked with its factors and its curves' factors
    /// `checked_curves` as they are now (refinement rounds skip it then).
    pub(super) settled: bool,
    /// Its sides' curve factors when it was last checked.
    pub(super) checked_curves: [u8; 4],
    /// The whole patch's bounds, once computed (they do not depend on the view).
    pub(super) whole: Option<PatchBounds>,
    /// The cone of its outward normals, in a closed model whose outside is known (see `back`).
    pub(super) cone: Option<NormalCone>,
    /// Whether it is culled this frame for facing away from the eye.
    pub(super) back_facing: bool,
    /// Where its triangles' states start in the frame's arena (see `states`).
    pub(super) states: u32,
    /// How many states it has: its live triangles, in its first triangle slots (0: it has
    /// none, and every triangle has [`TriangleSlot::plain`] of `plain`).
    pub(super) state_count: u16,
    /// For a patch without states: a bound of every triangle's pieces this frame.
    pub(super) plain: f32,
    /// Whether it asked for states this frame and found the arena full.
    pub(super) short: bool,
}

impl PatchSlot {
    /// Where triangle `t`'s state is in the frame's arena, if the patch has one for it.
    pub(super) fn state_index(&self, t: usize) -> Option<usize> {
        (t < self.state_count as usize).then(|| self.states as usize + t)
    }

    /// Writes triangle `t`'s state into `arena`. In a patch without states, its pieces'
    /// bound joins the patch's `plain` bound instead.
    pub(super) fn put_state(&mut self, arena: &mut [TriangleSlot], t: usize, state: TriangleSlot) {
        match self.state_index(t).and_then(|i| arena.get_mut(i)) {
            Some(s) => *s = state,
            None => self.plain = crate::math::max(self.plain, state.pieces),
        }
    }

    /// Its stretch of the pool's vertex slots.
    pub(super) fn vertex_range(&self) -> core::ops::Range<usize> {
        let start = self.vertex_offset as usize;
        start..start + self.vertex_capacity as usize
    }

    /// Its stretch of the pool's triangle slots (and triangle states).
    pub(super) fn triangle_range(&self) -> core::ops::Range<usize> {
        let start = self.triangle_offset as usize;
        start..start + self.triangle_capacity as usize
    }

    /// True when the baked prefix does not reach the threshold: every triangle needs its own
    /// bound.
    pub(super) fn exhausted(&self) -> bool {
        self.recorded.partial_cmp(&self.c) == Some(core::cmp::Ordering::Greater)
    }
}

/// One boundary curve's run-time state (storage slot; contents are private).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CurveSlot {
    /// First slot in the sorted-parameter storage.
    pub(super) order_offset: u32,
    /// Active samples: the largest request of the visible patches that share the curve.
    pub(super) count: u16,
    /// Scratch count of the budget prediction.
    pub(super) predict: u16,
    pub(super) used: bool,
    pub(super) factor: u8,
    /// First output vertex of the curve in the current [`write_mesh`](super::Tessellator::write_mesh).
    pub(super) base: u32,
    /// The patch that owns the curve, and its side.
    pub(super) owner: u32,
    pub(super) side: Side,
}

/// One domain triangle's state in the current frame: its refinement factor and the bounds
/// that judged it (storage slot, 20 bytes; contents are private). Only the patches whose
/// triangles are judged on their own or cut take slots, from an arena of any length (see
/// [`TessellatorStorage::triangle_states`]). Every frame writes them afresh, so they keep
/// nothing from one frame to the next (what does is in [`BoundSlot`]s).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TriangleSlot {
    /// Its refinement factor in the current frame.
    pub(super) factor: u8,
    /// The factor a round of agreement raises it to, applied when the round ends (0: none).
    pub(super) pending: u8,
    /// [`JUDGED`], [`HIDDEN`], and the edges to halve ([`HALVED`] shifted by the edge).
    flags: u8,
    /// The factor and edge factors of the non-uniform pattern `pieces` bounds this frame
    /// (zeros when none); once agreement ends, of the pattern it is cut in, whatever it is
    /// (see `agree::record_patterns`).
    pub(super) pattern: [u8; 4],
    /// Bound of every piece it is cut into in the current frame, in object units.
    pub(super) pieces: f32,
    /// Its threshold in the current frame (object units): its own where it was judged on its
    /// own, otherwise its patch's.
    pub(super) threshold: f32,
    /// A bound of its deviation this frame (the one that judged it, or the prefix's recorded
    /// bound): its surface piece, and every flat piece it is cut into, lie within it of the
    /// flat triangle of its corners' surface points.
    pub(super) margin: f32,
}

/// [`TriangleSlot`] flag: it was judged on its own bounds this frame (else it is a baked
/// prefix triangle within the recorded bound).
const JUDGED: u8 = 1;
/// [`TriangleSlot`] flag: it lies wholly outside the view this frame, with its surface piece,
/// and is not written (refined frames only).
const HIDDEN: u8 = 2;
/// [`TriangleSlot`] flag, shifted left by `i`: edge `i` (opposite corner `i`) is asked to be
/// halved this frame beyond the triangle's own factor (a bisection where a uniform cut would
/// overshoot).
const HALVED: u8 = 4;
/// [`TriangleSlot`] flag: it was left uncut by its bound on screen (see `refine`), and its
/// `threshold` is the one that bound implies, not one an object-space bound may be held to
/// (a piece of it, where it is cut after all, is judged by its own isotropic threshold).
const ON_SCREEN: u8 = 32;

impl TriangleSlot {
    fn set_flag(&mut self, flag: u8, on: bool) {
        if on {
            self.flags |= flag;
        } else {
            self.flags &= !flag;
        }
    }

    /// Whether it was judged on its own bounds this frame.
    pub(super) fn judged(&self) -> bool {
        self.flags & JUDGED != 0
    }

    /// Sets [`TriangleSlot::judged`].
    pub(super) fn set_judged(&mut self, on: bool) {
        self.set_flag(JUDGED, on);
    }

    /// Whether it was left uncut by its bound on screen this frame.
    pub(super) fn on_screen(&self) -> bool {
        self.flags & ON_SCREEN != 0
    }

    /// Sets [`TriangleSlot::on_screen`].
    pub(super) fn set_on_screen(&mut self, on: bool) {
        self.set_flag(ON_SCREEN, on);
    }

    /// Whether it is off the view this frame (not written).
    pub(super) fn hidden(&self) -> bool {
        self.flags & HIDDEN != 0
    }

    /// Sets [`TriangleSlot::hidden`].
    pub(super) fn set_hidden(&mut self, on: bool) {
        self.set_flag(HIDDEN, on);
    }

    /// The factor edge `i` (opposite corner `i`) is asked to take this frame beyond the
    /// triangle's own: 2 for a halved edge, 0 for none.
    pub(super) fn asked(&self, i: usize) -> u8 {
        if self.flags & (HALVED << i) != 0 {
            2
        } else {
            0
        }
    }

    /// Whether any edge is asked to be halved.
    pub(super) fn halves(&self) -> bool {
        self.flags & (HALVED * 7) != 0
    }

    /// Asks edge `i` to be halved where `split[i]` is 2, and nothing of the others (a split
    /// holds only 0 and 2: see `pieces::halving`).
    pub(super) fn set_split(&mut self, split: [u8; 3]) {
        for (i, &f) in split.iter().enumerate() {
            debug_assert!(f == 0 || f == 2, "a split halves an edge or leaves it");
            self.set_flag(HALVED << i, f > 1);
        }
    }
}

/// Storage sizes a [`Tessellator`](super::Tessellator) needs for a baked model.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StorageSize {
    /// [`PatchSlot`]s: one per patch.
    pub patches: usize,
    /// [`CurveSlot`]s: one per curve.
    pub curves: usize,
    /// `u16`s for the curves' sorted parameters: one per curve sample.
    pub curve_order: usize,
    /// [`MeshVertex`] slots: the pool shared by all patches.
    pub vertices: usize,
    /// [`MeshTriangle`] slots: the pool shared by all patches.
    pub triangles: usize,
    /// [`TriangleSlot`]s: the arena of the frame's judged and cut triangles (any number
    /// works, none included; a patch whose triangles are judged or cut takes one per triangle
    /// slot, and one that finds the arena full is left uncut, its bound reported like a
    /// budget fit's).
    pub triangle_states: usize,
    /// [`BoundSlot`]s: the bound cache, one per pool triangle slot (any number works, none
    /// included; with fewer, slots share entries, and more frames recompute bounds they
    /// computed before).
    pub bounds: usize,
    /// [`PointSlot`]s: the vertex cache, one per pool vertex slot from the first (any number
    /// works, none included; the slots past it are evaluated at every output).
    pub vertex_points: usize,
    /// `u32` scratch: three per patch when the tessellator is built (to orient a closed
    /// model's patches), and for [`write_mesh`](super::Tessellator::write_mesh) the largest
    /// patch's vertex slots plus three per triangle slot. A tessellator whose frames are only
    /// streamed ([`stream`](super::Tessellator::stream), the renderer) needs no more than the
    /// first; [`write_mesh`](super::Tessellator::write_mesh) with less than the second
    /// returns [`WriteError::ScratchTooSmall`](crate::WriteError::ScratchTooSmall).
    pub scratch: usize,
}

impl StorageSize {
    /// What `baked` needs with `settings` for every frame to hold every step it asks for:
    /// a pool of every patch's slots, a bound cache of one entry per triangle slot, a vertex
    /// cache of one per vertex slot, and the scratch of
    /// [`write_mesh`](super::Tessellator::write_mesh) for any frame. (A smaller pool and
    /// cache work, and a frame that is only streamed needs less scratch: see
    /// [`StorageSize::minimum`].) For a pool of `u16`-indexed slots, the default; see
    /// [`StorageSize::of_indexed`] for others.
    pub fn of(baked: &BakedModel<'_>, settings: &Settings) -> StorageSize {
        StorageSize::of_indexed::<u16>(baked, settings)
    }

    /// [`StorageSize::of`] for a pool whose slots are indexed by `Ix`: a patch's mesh holds
    /// no more than `Ix` numbers (see [`DomainIndex`]), so with `u8` a patch of many baked
    /// samples needs fewer slots, and its frames refine where the samples stop. (The
    /// [`Tessellator`](super::Tessellator) docs show one.)
    pub fn of_indexed<Ix: DomainIndex>(baked: &BakedModel<'_>, settings: &Settings) -> StorageSize {
        let mut size = StorageSize::minimum(baked, settings);
        size.vertices = 0;
        size.triangles = 0;
        for k in 0..baked.patch_count() {
            if let Some(bp) = baked.patch(k) {
                let (v, t, _) = patch_capacity::<Ix>(baked, &bp, settings);
                size.vertices += v;
                size.triangles += t;
                size.scratch = size.scratch.max(v + 3 * t);
            }
        }
        size.triangle_states = size.triangles;
        size.bounds = size.triangles;
        size.vertex_points = size.vertices;
        size
    }

    /// The least storage a [`Tessellator`](super::Tessellator) works with: a pool of four
    /// vertex and two triangle slots per patch, no triangle states, no caches, and the
    /// scratch of building it (three per patch: enough to stream its frames, not to
    /// [write](super::Tessellator::write_mesh) them; see [`StorageSize::scratch`]). Frames then
    /// cut their prefixes of baked steps to what the pool holds (see
    /// [`FrameStats::prefix_scale`](super::FrameStats::prefix_scale)); refinement takes over,
    /// within the same error bound, in the patches the triangle-state arena holds, and the
    /// others report their bound (see
    /// [`FrameStats::patches_without_states`](super::FrameStats::patches_without_states)).
    pub fn minimum(baked: &BakedModel<'_>, settings: &Settings) -> StorageSize {
        // The least storage does not depend on the settings (what a frame holds does).
        let _ = settings;
        StorageSize {
            patches: baked.patch_count(),
            curves: baked.curve_count(),
            curve_order: baked.curve_sample_count(),
            vertices: 4 * baked.patch_count(),
            triangles: 2 * baked.patch_count(),
            triangle_states: 0,
            bounds: 0,
            vertex_points: 0,
            scratch: 3 * baked.patch_count(),
        }
    }

    /// This size with a pool of `pool`'s slots, and a triangle state for each of its triangle
    /// slots (so that refinement can take over wherever the pool cuts the prefixes).
    pub fn with_pool(self, pool: PoolSize) -> StorageSize {
        StorageSize {
            vertices: pool.vertices,
            triangles: pool.triangles,
            triangle_states: pool.triangles,
            ..self
        }
    }
}

/// The most vertex slots one mesh indexed by `Ix` takes: its `2v - 6` triangle slots
/// ([`DomainMesh::triangles_for`]) must be numbered by `Ix` too (and then so are its `v`).
pub(super) fn max_patch_vertices<Ix: DomainIndex>() -> usize {
    (Ix::MAX_SLOTS + 6) / 2
}

/// Vertex and triangle slots of one patch, and its step cap, in a pool indexed by `Ix`. The
/// vertices are more than [`max_patch_vertices`] when its curve samples alone are.
pub(super) fn patch_capacity<Ix: DomainIndex>(
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
    let room = max_patch_vertices::<Ix>().saturating_sub(v);
    let cap = bp
        .samples
        .len()
        .min(settings.max_interior_samples as usize)
        .min(room);
    v += cap;
    (v, DomainMesh::triangles_for(v), cap as u16)
}

/// The caller's storage for a [`Tessellator`](super::Tessellator), at least
/// [`StorageSize::minimum`] (longer slices are fine). `vertices` and `triangles` are the pool
/// all patches share; [`StorageSize::of`] sizes it for every baked step. `triangle_states` is
/// the arena of the frame's judged and cut triangles, and `bounds` and `vertex_points` are
/// caches: all three of any length.
#[derive(Debug)]
pub struct TessellatorStorage<'s, Ix: DomainIndex = u16> {
    /// Per patch.
    pub patches: &'s mut [PatchSlot],
    /// Per curve.
    pub curves: &'s mut [CurveSlot],
    /// Per curve sample.
    pub curve_order: &'s mut [u16],
    /// The pool's domain-mesh vertices.
    pub vertices: &'s mut [MeshVertex<Ix>],
    /// The pool's domain-mesh triangles.
    pub triangles: &'s mut [MeshTriangle<Ix>],
    /// The frame's states of the triangles of the patches that judge their triangles on
    /// their own or cut them, one per triangle slot of each such patch: any length, none
    /// included. A patch that finds it full is left uncut this frame, within a bound it
    /// reports (in [`FrameStats::max_predicted_error`](super::FrameStats::max_predicted_error)).
    pub triangle_states: &'s mut [TriangleSlot],
    /// The bound cache: any length, none included.
    pub bounds: &'s mut [BoundSlot],
    /// The vertex cache, for the pool's first vertex slots: any length, none included.
    pub vertex_points: &'s mut [PointSlot],
    /// Scratch: see [`StorageSize::scratch`].
    pub scratch: &'s mut [u32],
}

/// Why a [`Tessellator`](super::Tessellator) cannot be built.
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
    /// A patch's curve samples alone exceed what one domain mesh numbers (32,770 vertices
    /// with `u16` indices, 130 with `u8`: see [`DomainIndex`]).
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

#[cfg(test)]
mod tests {
    use super::*;
    use core::mem::size_of;

    #[test]
    fn pool_slots_are_as_small_as_documented() {
        assert_eq!(size_of::<MeshVertex>(), 6);
        assert_eq!(size_of::<MeshTriangle>(), 12);
        assert_eq!(size_of::<MeshVertex<u8>>(), 5);
        assert_eq!(size_of::<MeshTriangle<u8>>(), 6);
        assert_eq!(size_of::<TriangleSlot>(), 20);
        assert_eq!(size_of::<PatchSlot>(), 172);
    }

    #[test]
    fn flags_keep_apart() {
        let mut s = TriangleSlot::default();
        assert!(!s.judged() && !s.hidden() && !s.halves());
        s.set_split([0, 2, 2]);
        s.set_hidden(true);
        assert_eq!([0, 1, 2].map(|i| s.asked(i)), [0, 2, 2]);
        assert!(s.halves() && s.hidden() && !s.judged());
        s.set_judged(true);
        s.set_split([2, 0, 0]);
        s.set_hidden(false);
        assert_eq!([0, 1, 2].map(|i| s.asked(i)), [2, 0, 0]);
        assert!(s.halves() && !s.hidden() && s.judged());
        s.set_split([0; 3]);
        assert!(!s.halves() && s.judged());
    }
}
