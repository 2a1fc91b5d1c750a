//! The vertex cache: each interior domain vertex's surface point and normal, evaluated once
//! and kept in a caller slice beside the pool while the vertex lives.
//!
//! Output evaluates the surface at every corner it hands out. Without the cache, a frame
//! evaluates each vertex about three times (once per run of triangles around it that the
//! streaming path's small cache of recent points catches), and every frame again. With it, an
//! interior vertex is evaluated when a frame first keeps it, and then read: an orbit step
//! evaluates only the vertices its update inserted.
//!
//! An entry is keyed by its patch and grid point, and what it holds is a function of those
//! alone (the same evaluation the output makes), so a stale entry is never used and what the
//! cache holds changes a frame's cost, never its output. Entries do not follow their vertex
//! when the pool is laid out again: the keys no longer match, and the vertices are evaluated
//! again. Boundary vertices are shared with the neighbouring patches and are not cached here.

use crate::domain::DomainIndex;
use crate::domain::GridPoint;
use crate::frame::SurfacePoint;
use crate::math::SIMD_LANES;
use crate::patch::BezierPatch;
use crate::sink::Vertex;

use super::Tessellator;

/// One pool vertex slot's evaluated surface point (storage slot; contents are private).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointSlot {
    /// The patch of the vertex the entry holds (`u32::MAX`: none).
    patch: u32,
    /// Its grid point.
    point: GridPoint,
    position: [f32; 3],
    normal: [f32; 3],
}

impl Default for PointSlot {
    fn default() -> Self {
        PointSlot {
            patch: u32::MAX,
            point: GridPoint::default(),
            position: [0.0; 3],
            normal: [0.0; 3],
        }
    }
}

/// Points [`Tessellator::fill_vertex_points`] evaluates together.
const FILL_BATCH: usize = if SIMD_LANES { 4 } else { 1 };

impl<Ix: DomainIndex> Tessellator<'_, '_, Ix> {
    /// Evaluates the live interior vertices of the visible patches that the cache does not
    /// hold.
    pub(super) fn fill_vertex_points(&mut self) {
        let len = self.storage.vertex_points.len();
        if len == 0 {
            return;
        }
        for p in 0..self.baked.patch_count() {
            let slot = self.storage.patches[p];
            if slot.culled {
                continue;
            }
            let Some(patch) = self.patches.patch(p) else {
                continue;
            };
            // Evaluated four at a time where `Vec4` has SIMD lanes
            // (`BezierPatch::evaluate_into`: the same bits), else one at a time.
            let mut batch = [(0usize, GridPoint::default()); FILL_BATCH];
            let mut n = 0;
            for i in slot.vertex_range().skip(4).take_while(|&i| i < len) {
                let Some(g) = self.storage.vertices[i].live_point() else {
                    continue;
                };
                let entry = &self.storage.vertex_points[i];
                if g.on_boundary() || (entry.patch == p as u32 && entry.point == g) {
                    continue;
                }
                batch[n] = (i, g);
                n += 1;
                if n == FILL_BATCH {
                    self.fill_points(p, &patch, &batch);
                    n = 0;
                }
            }
            self.fill_points(p, &patch, &batch[..n]);
        }
    }

    /// Evaluates the interior grid points `points` (with their pool vertex slots) of patch
    /// `p` into the cache, together.
    fn fill_points(&mut self, p: usize, patch: &BezierPatch<'_>, points: &[(usize, GridPoint)]) {
        let n = points.len().min(FILL_BATCH);
        let uv: [(f32, f32); FILL_BATCH] =
            core::array::from_fn(|k| points.get(k).map_or((0.0, 0.0), |&(_, g)| unit(g)));
        let mut evaluated = [SurfacePoint::PLACEHOLDER; FILL_BATCH];
        patch.evaluate_into(&uv[..n], &mut evaluated[..n]);
        for (&(i, g), s) in points.iter().zip(&evaluated) {
            self.storage.vertex_points[i] = PointSlot {
                patch: p as u32,
                point: g,
                position: s.position.to_array(),
                normal: s.normal.to_array(),
            };
        }
    }

    /// The output vertex of interior grid point `g` of patch `p` in pool vertex slot `i`, if
    /// the cache holds it.
    pub(super) fn cached_vertex(&self, p: usize, i: usize, g: GridPoint) -> Option<Vertex> {
        let entry = self.storage.vertex_points.get(i)?;
        (entry.patch == p as u32 && entry.point == g).then(|| {
            let (u, v) = unit(g);
            Vertex {
                position: entry.position,
                normal: entry.normal,
                uv: [u, v],
                patch: p as u32,
            }
        })
    }
}

/// The parameters of a grid point, as the output computes them for an interior vertex (the
/// cache and the output evaluate at exactly these, so their points agree bit for bit).
pub(super) fn unit(g: GridPoint) -> (f32, f32) {
    let max = GridPoint::MAX as f32;
    (g.u as f32 / max, g.v as f32 / max)
}
