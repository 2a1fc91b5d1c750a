//! A frame's mesh written out: streamed to a sink, or into caller buffers with shared
//! vertices shared by index.

use super::address::unit;
use super::select::{is_split, Selection};
use super::tree::{walk, Pending};
use crate::sink::{MeshIndex, MeshSize, TriangleInfo, TriangleSink, Vertex, WriteError};

impl Selection<'_, '_> {
    /// Calls `f` on every written leaf of the current mesh, patch by patch, with its
    /// vertices.
    fn each_written(&self, mut f: impl FnMut(&Pending, [u32; 3])) {
        let tree = self.tree;
        walk(tree, |h| {
            if is_split(&tree, self.active(), h) {
                return true;
            }
            if !self.is_hidden(h) {
                if let Some(corners) = tree.written(h) {
                    f(h, corners);
                }
            }
            false
        });
    }

    /// The output vertex of baked vertex `v`.
    fn vertex(&self, v: u32) -> Vertex {
        let b = &self.tree.vertices[v as usize];
        let (u, w) = unit(b.uv);
        Vertex {
            position: b.position,
            normal: b.normal,
            uv: [u, w],
            patch: b.patch,
        }
    }

    /// Streams the current mesh to `sink`, patch by patch (patches the sink does not want
    /// are skipped). Triangles are counter-clockwise in their patch's `(u, v)` square.
    pub fn stream(&self, sink: &mut impl TriangleSink) {
        self.each_written(|h, corners| {
            if sink.wants_patch(h.tri.patch) {
                let [a, b, c] = corners.map(|v| self.vertex(v));
                sink.triangle(h.tri.patch, [&a, &b, &c]);
            }
        });
    }

    /// Streams the current mesh with each triangle's parameters in its own patch and its
    /// bound in model units.
    pub fn stream_with_info(&self, mut f: impl FnMut(&TriangleInfo, [&Vertex; 3])) {
        self.each_written(|h, corners| {
            let info = TriangleInfo {
                patch: h.tri.patch,
                uv: h.tri.corners.map(|p| {
                    let (u, v) = unit(p);
                    [u, v]
                }),
                bound: self.tree.node(h).object_bound(),
            };
            let [a, b, c] = corners.map(|v| self.vertex(v));
            f(&info, [&a, &b, &c]);
        });
    }

    /// Size of the mesh [`write_mesh`](Self::write_mesh) writes.
    pub fn mesh_size(&self) -> MeshSize {
        MeshSize {
            vertices: self.stats.vertices,
            triangles: self.stats.triangles,
        }
    }

    /// Writes the current mesh: vertices in order of first use, each shared vertex once.
    /// `remap` needs one entry per baked vertex. On an error the buffers are untouched.
    pub fn write_mesh<I: MeshIndex>(
        &self,
        vertices: &mut [Vertex],
        triangles: &mut [[I; 3]],
        remap: &mut [u32],
    ) -> Result<MeshSize, WriteError> {
        let size = self.mesh_size();
        if vertices.len() < size.vertices || triangles.len() < size.triangles {
            return Err(WriteError::BuffersTooSmall { needed: size });
        }
        if size.vertices > I::LIMIT {
            return Err(WriteError::IndexOverflow {
                vertices: size.vertices,
            });
        }
        let baked = self.tree.vertices.len();
        if remap.len() < baked {
            return Err(WriteError::ScratchTooSmall { needed: baked });
        }
        remap[..baked].fill(u32::MAX);
        let (mut nv, mut nt) = (0usize, 0usize);
        self.each_written(|_, corners| {
            let mut out = [I::default(); 3];
            for (o, v) in out.iter_mut().zip(corners) {
                let slot = &mut remap[v as usize];
                if *slot == u32::MAX {
                    *slot = nv as u32;
                    if let Some(x) = vertices.get_mut(nv) {
                        *x = self.vertex(v);
                    }
                    nv += 1;
                }
                *o = I::from_index(*slot);
            }
            if let Some(t) = triangles.get_mut(nt) {
                *t = out;
            }
            nt += 1;
        });
        Ok(MeshSize {
            vertices: nv,
            triangles: nt,
        })
    }
}
