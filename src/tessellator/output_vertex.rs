//! Output vertices: where an output point is evaluated (its patch and parameters), and its
//! evaluation, a point at a time or queued per patch and evaluated a few at a time
//! ([`BezierPatch::evaluate_into`](crate::BezierPatch): the same bits).

use super::patch_view::Point;
use super::{Tessellator, CORNER_UV};
use crate::domain::DomainIndex;
use crate::frame::SurfacePoint;
use crate::patch::Side;
use crate::sink::Vertex;

/// Output points of one patch waiting to be evaluated together (see
/// [`Tessellator::queue_vertex`]).
#[derive(Default)]
pub(super) struct VertexBatch {
    patch: usize,
    len: usize,
    /// Where each point's vertex goes.
    at: [u32; 4],
    uv: [(f32, f32); 4],
}

impl<Ix: DomainIndex> Tessellator<'_, '_, Ix> {
    /// Vertex data of an output point.
    pub(super) fn vertex_data(&self, p: Point, patch: usize) -> Vertex {
        let (patch, u, v) = self.vertex_params(p, patch);
        let s = self
            .patches
            .patch(patch)
            .map(|bp| bp.evaluate(u, v))
            .map(|e| (e.position.to_array(), e.normal.to_array()))
            .unwrap_or_default();
        Vertex {
            position: s.0,
            normal: s.1,
            uv: [u, v],
            patch: patch as u32,
        }
    }

    /// [`vertex_data`](Self::vertex_data) of `p` into `vs[at]`, through `batch`: written when
    /// the batch is evaluated (when it is full, when a point of another patch comes, or at
    /// [`flush_vertices`](Self::flush_vertices)), with the same bits.
    pub(super) fn queue_vertex(
        &self,
        batch: &mut VertexBatch,
        vs: &mut [Vertex],
        at: u32,
        p: Point,
        patch: usize,
    ) {
        let (patch, u, v) = self.vertex_params(p, patch);
        if batch.len > 0 && batch.patch != patch {
            self.flush_vertices(batch, vs);
        }
        batch.patch = patch;
        batch.at[batch.len] = at;
        batch.uv[batch.len] = (u, v);
        batch.len += 1;
        if batch.len == batch.at.len() {
            self.flush_vertices(batch, vs);
        }
    }

    /// Evaluates and writes the points `batch` holds.
    pub(super) fn flush_vertices(&self, batch: &mut VertexBatch, vs: &mut [Vertex]) {
        let n = core::mem::take(&mut batch.len);
        let Some(bp) = self.patches.patch(batch.patch) else {
            return;
        };
        let mut points = [SurfacePoint::PLACEHOLDER; 4];
        bp.evaluate_into(&batch.uv[..n], &mut points[..n]);
        for ((&at, &(u, v)), s) in batch.at.iter().zip(&batch.uv).zip(&points).take(n) {
            if let Some(out) = vs.get_mut(at as usize) {
                *out = Vertex {
                    position: s.position.to_array(),
                    normal: s.normal.to_array(),
                    uv: [u, v],
                    patch: batch.patch as u32,
                };
            }
        }
    }

    /// The patch and parameters an output point is evaluated at.
    fn vertex_params(&self, p: Point, patch: usize) -> (usize, f32, f32) {
        match p {
            Point::Node(n) => {
                let (owner, k) = self.node_owner(n);
                let (u, v) = CORNER_UV[k];
                (owner, u, v)
            }
            Point::Curve {
                curve, num, den, ..
            } => {
                let t = num as f32 / den as f32;
                match self.storage.curves.get(curve as usize) {
                    Some(cs) => {
                        let (u, v) = match cs.side {
                            Side::V0 => (t, 0.0),
                            Side::U1 => (1.0, t),
                            Side::V1 => (t, 1.0),
                            Side::U0 => (0.0, t),
                        };
                        (cs.owner as usize, u, v)
                    }
                    None => (patch, t, 0.0),
                }
            }
            Point::Vertex { p, .. } => {
                let (u, v) = super::vertex_cache::unit(p);
                (patch, u, v)
            }
            Point::Edge { u, v, den, .. } | Point::Face { u, v, den, .. } => {
                (patch, u as f32 / den as f32, v as f32 / den as f32)
            }
        }
    }

    /// The patch and corner that first has node `n`.
    fn node_owner(&self, n: u32) -> (usize, usize) {
        let count = self.baked.patch_count();
        let patches = &self.storage.patches[..count];
        // Nodes are numbered in order of first appearance, so owners are sorted.
        let p = patches
            .partition_point(|s| s.first_node <= n)
            .saturating_sub(1);
        let k = patches
            .get(p)
            .and_then(|s| s.nodes.iter().position(|&x| x == n))
            .unwrap_or(0);
        (p, k)
    }
}
