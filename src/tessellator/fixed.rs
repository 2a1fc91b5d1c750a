//! Storage with capacities fixed at compile time, for firmware: one value to put in a
//! `static`, or on the stack, sized by const generics.

use super::storage::{CurveSlot, PatchSlot, TessellatorStorage, TriangleSlot};
use super::StorageSize;
use super::{BoundSlot, PointSlot};
use crate::domain::{DomainIndex, MeshTriangle, MeshVertex};

/// [`TessellatorStorage`] in arrays: `PATCHES` patch slots, `CURVES` curve slots, `ORDER`
/// curve-order slots, a pool of `VERTICES` vertex and `TRIANGLES` triangle slots, `STATES`
/// triangle states, a bound cache of `BOUNDS` entries, a vertex cache of `POINTS` entries,
/// and `SCRATCH` scratch ([`StorageSize::scratch`]: three per patch, or a writer's index
/// tables). [`FixedStorage::covers`] checks it against what a bake needs
/// ([`StorageSize::minimum`]); a pool larger than that lets frames keep more baked steps.
/// `Ix` numbers the pool's slots: `u16` (the default), or `u8` for half the bytes per
/// triangle slot where a patch's mesh holds at most 130 vertices (see [`DomainIndex`]; such a
/// storage goes to [`Tessellator::indexed`](super::Tessellator::indexed)).
///
/// ```
/// use spline_tess::tessellator::{FixedStorage, StorageSize};
///
/// // Four patches with up to 16 curve samples each side, a pool for about 300 triangles,
/// // states for 128 judged or cut triangles, a bound cache of 64 entries and a vertex cache
/// // for every vertex slot.
/// type Storage = FixedStorage<4, 16, 256, 192, 320, 128, 64, 192, 1024>;
/// let mut storage = Storage::new();
/// let slices = storage.as_storage();
/// assert_eq!((slices.vertices.len(), slices.triangles.len()), (192, 320));
/// let least = StorageSize { patches: 4, curves: 12, curve_order: 200, vertices: 16,
///                           triangles: 8, triangle_states: 0, bounds: 0, vertex_points: 0,
///                           scratch: 12 };
/// assert!(Storage::covers(&least));
///
/// // With one-byte slot numbers: 6 bytes less per triangle slot and 1 per vertex slot.
/// type Narrow = FixedStorage<4, 16, 256, 192, 320, 128, 64, 192, 1024, u8>;
/// use core::mem::size_of;
/// assert_eq!(size_of::<Storage>() - size_of::<Narrow>(), 320 * 6 + 192);
/// ```
#[derive(Debug)]
pub struct FixedStorage<
    const PATCHES: usize,
    const CURVES: usize,
    const ORDER: usize,
    const VERTICES: usize,
    const TRIANGLES: usize,
    const STATES: usize,
    const BOUNDS: usize,
    const POINTS: usize,
    const SCRATCH: usize,
    Ix: DomainIndex = u16,
> {
    patches: [PatchSlot; PATCHES],
    curves: [CurveSlot; CURVES],
    order: [u16; ORDER],
    vertices: [MeshVertex<Ix>; VERTICES],
    triangles: [MeshTriangle<Ix>; TRIANGLES],
    states: [TriangleSlot; STATES],
    bounds: [BoundSlot; BOUNDS],
    points: [PointSlot; POINTS],
    scratch: [u32; SCRATCH],
}

impl<
        const PATCHES: usize,
        const CURVES: usize,
        const ORDER: usize,
        const VERTICES: usize,
        const TRIANGLES: usize,
        const STATES: usize,
        const BOUNDS: usize,
        const POINTS: usize,
        const SCRATCH: usize,
        Ix: DomainIndex,
    >
    FixedStorage<PATCHES, CURVES, ORDER, VERTICES, TRIANGLES, STATES, BOUNDS, POINTS, SCRATCH, Ix>
{
    /// Empty storage.
    pub fn new() -> Self {
        FixedStorage {
            patches: [PatchSlot::default(); PATCHES],
            curves: [CurveSlot::default(); CURVES],
            order: [0; ORDER],
            vertices: [MeshVertex::default(); VERTICES],
            triangles: [MeshTriangle::default(); TRIANGLES],
            states: [TriangleSlot::default(); STATES],
            bounds: [BoundSlot::default(); BOUNDS],
            points: [PointSlot::default(); POINTS],
            scratch: [0; SCRATCH],
        }
    }

    /// The capacities, as a [`StorageSize`].
    pub const SIZE: StorageSize = StorageSize {
        patches: PATCHES,
        curves: CURVES,
        curve_order: ORDER,
        vertices: VERTICES,
        triangles: TRIANGLES,
        triangle_states: STATES,
        bounds: BOUNDS,
        vertex_points: POINTS,
        scratch: SCRATCH,
    };

    /// True when every capacity is at least `size`'s.
    pub fn covers(size: &StorageSize) -> bool {
        let s = Self::SIZE;
        size.patches <= s.patches
            && size.curves <= s.curves
            && size.curve_order <= s.curve_order
            && size.vertices <= s.vertices
            && size.triangles <= s.triangles
            && size.triangle_states <= s.triangle_states
            && size.bounds <= s.bounds
            && size.vertex_points <= s.vertex_points
            && size.scratch <= s.scratch
    }

    /// The slices a [`Tessellator`](super::Tessellator) takes.
    pub fn as_storage(&mut self) -> TessellatorStorage<'_, Ix> {
        TessellatorStorage {
            patches: &mut self.patches,
            curves: &mut self.curves,
            curve_order: &mut self.order,
            vertices: &mut self.vertices,
            triangles: &mut self.triangles,
            triangle_states: &mut self.states,
            bounds: &mut self.bounds,
            vertex_points: &mut self.points,
            scratch: &mut self.scratch,
        }
    }
}

impl<
        const PATCHES: usize,
        const CURVES: usize,
        const ORDER: usize,
        const VERTICES: usize,
        const TRIANGLES: usize,
        const STATES: usize,
        const BOUNDS: usize,
        const POINTS: usize,
        const SCRATCH: usize,
        Ix: DomainIndex,
    > Default
    for FixedStorage<
        PATCHES,
        CURVES,
        ORDER,
        VERTICES,
        TRIANGLES,
        STATES,
        BOUNDS,
        POINTS,
        SCRATCH,
        Ix,
    >
{
    fn default() -> Self {
        Self::new()
    }
}
