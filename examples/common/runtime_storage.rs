//! Heap storage for the run-time tessellator, for host programs: the examples, and host-tests
//! (which include this file).

use spline_tess::bake::BakedModel;
use spline_tess::tessellator::{
    BoundSlot, CurveSlot, PatchSlot, PointSlot, Settings, StorageSize, Tessellator,
    TessellatorError, TessellatorStorage, TriangleSlot,
};
use spline_tess::{DomainIndex, MeshTriangle, MeshVertex, PatchSet};

/// Heap storage for a [`Tessellator`], its pool's slots indexed by `Ix`.
pub struct RuntimeStorage<Ix: DomainIndex = u16> {
    patches: Vec<PatchSlot>,
    curves: Vec<CurveSlot>,
    order: Vec<u16>,
    vertices: Vec<MeshVertex<Ix>>,
    triangles: Vec<MeshTriangle<Ix>>,
    states: Vec<TriangleSlot>,
    bounds: Vec<BoundSlot>,
    points: Vec<PointSlot>,
    scratch: Vec<u32>,
}

impl RuntimeStorage {
    /// Storage sized for `baked` with `settings`, with a pool for every baked step.
    pub fn new(baked: &BakedModel<'_>, settings: &Settings) -> Self {
        Self::with_size(&StorageSize::of(baked, settings))
    }

    /// Storage of `size`.
    pub fn with_size(s: &StorageSize) -> Self {
        Self::indexed(s)
    }
}

impl<Ix: DomainIndex> RuntimeStorage<Ix> {
    /// Storage of `size`, its pool's slots indexed by `Ix`.
    pub fn indexed(s: &StorageSize) -> Self {
        RuntimeStorage {
            patches: vec![PatchSlot::default(); s.patches],
            curves: vec![CurveSlot::default(); s.curves],
            order: vec![0; s.curve_order],
            vertices: vec![MeshVertex::default(); s.vertices],
            triangles: vec![MeshTriangle::default(); s.triangles],
            states: vec![TriangleSlot::default(); s.triangle_states],
            bounds: vec![BoundSlot::default(); s.bounds],
            points: vec![PointSlot::default(); s.vertex_points],
            scratch: vec![0; s.scratch],
        }
    }

    /// A tessellator over this storage.
    pub fn tessellator<'m>(
        &mut self,
        patches: PatchSet<'m>,
        baked: BakedModel<'m>,
        settings: Settings,
    ) -> Tessellator<'m, '_, Ix> {
        self.try_tessellator(patches, baked, settings)
            .expect("storage sized by StorageSize")
    }

    /// A tessellator over this storage, or why there is none.
    pub fn try_tessellator<'m>(
        &mut self,
        patches: PatchSet<'m>,
        baked: BakedModel<'m>,
        settings: Settings,
    ) -> Result<Tessellator<'m, '_, Ix>, TessellatorError> {
        let storage = TessellatorStorage {
            patches: &mut self.patches,
            curves: &mut self.curves,
            curve_order: &mut self.order,
            vertices: &mut self.vertices,
            triangles: &mut self.triangles,
            triangle_states: &mut self.states,
            bounds: &mut self.bounds,
            vertex_points: &mut self.points,
            scratch: &mut self.scratch,
        };
        Tessellator::indexed(patches, baked, settings, storage)
    }
}
