//! What one frame did: its triangles, its work on the domain meshes, the pool and states it
//! used, and the error it can promise.

use super::pool::PoolSize;

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
    /// Patches culled by the view (off it, or facing away from the eye).
    pub culled_patches: usize,
    /// Of those, patches culled for facing away from the eye.
    pub back_facing_patches: usize,
    /// Largest predicted error of the frame, in the view's units (pixels or model units); at most
    /// the tolerance unless refinement hit [`Settings::max_factor`](super::Settings::max_factor),
    /// was off, or found the triangle-state arena full (see
    /// [`patches_without_states`](Self::patches_without_states)).
    pub max_predicted_error: f32,
    /// Live domain-mesh vertices of the visible patches: the vertex slots the frame uses.
    pub mesh_vertices: usize,
    /// Live domain-mesh triangles of the visible patches: the triangle slots the frame uses.
    pub mesh_triangles: usize,
    /// Pool slots the visible patches would use with every baked step the view asks for: a
    /// pool of at least this (plus four vertex and two triangle slots per culled patch)
    /// gives [`prefix_scale`](Self::prefix_scale) 1.
    pub pool_needed: PoolSize,
    /// 1 when the pool held every baked step the view asks for; otherwise the factor the patches'
    /// thresholds were multiplied by to choose the steps that fit (refinement takes over from them,
    /// within the same bound: see [`StorageSize::minimum`](super::StorageSize::minimum)).
    pub prefix_scale: f32,
    /// Patches whose triangles were to be judged on their own or cut this frame but found the
    /// triangle-state arena
    /// ([`TessellatorStorage::triangle_states`](super::TessellatorStorage::triangle_states)) full:
    /// they are left uncut, within a bound that [`max_predicted_error`](Self::max_predicted_error)
    /// reports.
    pub patches_without_states: usize,
    /// Triangle states the frame's patches asked for (one per live triangle of each patch whose
    /// triangles are judged on their own, hidden or cut): an arena of at least this many
    /// ([`StorageSize::triangle_states`](super::StorageSize::triangle_states)) leaves no patch
    /// without states.
    pub triangle_states_needed: usize,
}
