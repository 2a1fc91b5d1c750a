//! A frame's mesh written out: streamed to a sink, or into caller buffers with shared
//! vertices shared by index.

use super::address::{unit, Point};
use super::hierarchy::{walk_roots, Pending};
use super::select::{Part, Tessellator};
use crate::sink::{MeshIndex, MeshSize, TriangleInfo, TriangleSink, Vertex, WriteError};

impl Tessellator<'_, '_> {
    /// Calls `f` on every written leaf of the current mesh, patch by patch, with its
    /// vertices.
    fn each_written(&self, f: impl FnMut(&Pending, [u32; 3])) {
        self.each_written_in(None, f);
    }

    /// [`each_written`](Self::each_written) from the roots of `part` alone (`None`: all), in
    /// the same order.
    pub(super) fn each_written_in(
        &self,
        part: Option<Part>,
        mut f: impl FnMut(&Pending, [u32; 3]),
    ) {
        let wants = |_: &mut (), p| super::select::patch_in_part(part, p);
        let root = |p, k| super::select::root_in_part(part, (p, k as u32));
        self.each_written_of(&mut (), wants, root, |_, h, corners| f(h, corners));
    }

    /// [`each_written`](Self::each_written) over the patches `wants` takes, from the roots
    /// `root` takes (root `k` of patch `p`), both callbacks given `state`.
    fn each_written_of<S: ?Sized>(
        &self,
        state: &mut S,
        wants: impl FnMut(&mut S, u32) -> bool,
        root: impl Fn(u32, usize) -> bool,
        mut f: impl FnMut(&mut S, &Pending, [u32; 3]),
    ) {
        let mut bounds = None;
        walk_roots(self.tree, state, wants, root, |state, h| {
            if let Some(v) = self.split_vertex(h) {
                return Some(v);
            }
            if !self.is_hidden(h, &mut bounds) {
                if let Some(corners) = self.written(h) {
                    f(state, h, corners);
                }
            }
            None
        });
    }

    /// The output vertex of vertex `v`, written at grid point `at` of patch `patch` (a
    /// written triangle's corner), with the parameters every triangle gives it (see
    /// [`params`](Self::params)).
    #[cfg_attr(not(target_os = "none"), inline(always))]
    pub(super) fn vertex(&self, v: u32, patch: u32, at: Point) -> Vertex {
        let (q, g) = self.params(v, patch, at);
        let (u, w) = unit(g);
        Vertex {
            uv: [u, w],
            patch: q,
            ..self.bare_vertex(v)
        }
    }

    /// The output vertex of vertex `v` without its parameters (zero), for a sink that reads
    /// none ([`TriangleSink::wants_parameters`]).
    fn bare_vertex(&self, v: u32) -> Vertex {
        Vertex {
            position: self.position(v),
            normal: self.normal(v),
            uv: [0.0; 2],
            patch: 0,
        }
    }

    /// The patch and parameters of vertex `v` written at grid point `at` of patch `patch`,
    /// the same from every triangle that has it: at a patch corner (or on a side collapsed to
    /// a pole, written as the corner there) those of the first patch with the vertex at a
    /// corner; on a shared curve those of the patch of lower index; else its own.
    fn params(&self, v: u32, patch: u32, at: Point) -> (u32, Point) {
        let tree = &self.tree;
        let corner = at.iter().all(|&x| x == 0 || x == super::address::ONE);
        let pole = tree.poles(patch) != 0
            && crate::patch::Side::ALL.iter().any(|&s| {
                tree.poles(patch) & (1 << s.index()) != 0 && super::address::on_side(s, at)
            });
        if corner || pole {
            let m = super::address::ONE;
            for q in 0..tree.patch_count() as u32 {
                for (k, g) in [[0, 0], [m, 0], [m, m], [0, m]].into_iter().enumerate() {
                    if tree.corner(q, k) == v {
                        return (q, g);
                    }
                }
            }
        }
        super::refine::key(tree, patch, at)
    }

    /// The output vertices of leaf `h`, written at `corners` (in [`written`](Self::written)'s
    /// order).
    fn vertices_of(&self, h: &Pending, corners: [u32; 3]) -> [Vertex; 3] {
        let grid = self.oriented(h, h.tri.corners);
        [0, 1, 2].map(|i| self.vertex(corners[i], h.tri.patch, grid[i]))
    }

    /// Streams the current mesh to `sink`, patch by patch (patches the sink does not want
    /// are skipped). Triangles are counter-clockwise seen from outside, and normals point out
    /// (see `bake`'s orientation rule).
    pub fn stream(&self, sink: &mut impl TriangleSink) {
        self.each_written(|h, corners| {
            if sink.wants_patch(h.tri.patch) {
                let [a, b, c] = self.vertices_of(h, corners);
                sink.triangle(h.tri.patch, [&a, &b, &c]);
            }
        });
    }

    /// Streams the current mesh's triangles of the patches `wants` takes to `sink` as
    /// [`keyed_triangle`](TriangleSink::keyed_triangle)s: their corners' keys are their vertex
    /// numbers (equal keys, equal vertices, within a frame).
    #[cfg(feature = "embedded-graphics")]
    pub(crate) fn stream_keyed(
        &self,
        sink: &mut dyn TriangleSink,
        mut wants: impl FnMut(&mut dyn TriangleSink, u32) -> bool,
    ) {
        self.each_written_of(
            sink,
            |sink, p| wants(sink, p),
            |_, _| true,
            |sink, h, corners| {
                let grid = self.oriented(h, h.tri.corners);
                let parameters = sink.wants_parameters();
                let mut corner = |i: usize| match parameters {
                    true => self.vertex(corners[i % 3], h.tri.patch, grid[i % 3]),
                    false => self.bare_vertex(corners[i % 3]),
                };
                sink.keyed_triangle(h.tri.patch, corners.map(u64::from), &mut corner);
            },
        );
    }

    /// Streams the current mesh with each triangle's parameters in its own patch and its
    /// bound in model units.
    pub fn stream_with_info(&self, mut f: impl FnMut(&TriangleInfo, [&Vertex; 3])) {
        self.each_written(|h, corners| {
            let info = TriangleInfo {
                patch: h.tri.patch,
                uv: self.oriented(h, h.tri.corners).map(|p| {
                    let (u, v) = unit(p);
                    [u, v]
                }),
                bound: self.object_bound(h),
            };
            let [a, b, c] = self.vertices_of(h, corners);
            f(&info, [&a, &b, &c]);
        });
    }

    /// Each triangle of the current mesh as [`stream_with_info`](Self::stream_with_info)
    /// gives it, its patch and its corners' parameters alone (no vertex, no bound), in the
    /// same order: what the host's `Mesh` keeps per face.
    #[cfg(all(feature = "std", not(target_os = "none")))]
    pub(crate) fn each_face(&self, mut f: impl FnMut(u32, [[f32; 2]; 3])) {
        self.each_written(|h, _| {
            let uv = self.oriented(h, h.tri.corners).map(|p| {
                let (u, v) = unit(p);
                [u, v]
            });
            f(h.tri.patch, uv);
        });
    }

    /// Entries of [`write_mesh`](Self::write_mesh)'s `remap`: one per vertex of the bake and
    /// of the pool.
    pub fn remap_len(&self) -> usize {
        self.tree.vertex_count() + self.pool.entries.len()
    }

    /// The bound of leaf `h` in model units: its node's, or below the bake its own lattice's.
    fn object_bound(&self, h: &Pending) -> f32 {
        super::judge::judge(
            self,
            &crate::View::Object { tolerance: 0.0 },
            h,
            true,
            crate::deviation::certificate::Asked::NONE,
        )
        .bound
        .value()
    }

    /// Size of the mesh [`write_mesh`](Self::write_mesh) writes: the frame's triangles, and
    /// the vertices they use, counted by a walk of the mesh (a frame that is only drawn
    /// needs no count of its vertices, so [`update`](Self::update) leaves it to this).
    pub fn mesh_size(&mut self) -> MeshSize {
        let vertices = match self.vertices {
            Some(n) => n,
            None => {
                self.count();
                self.vertices.unwrap_or(0)
            }
        };
        MeshSize {
            vertices,
            triangles: self.stats.triangles,
        }
    }

    /// Writes the current mesh: vertices in order of first use, each shared vertex once.
    /// `remap` needs one entry per vertex of the bake and of the pool
    /// ([`remap_len`](Self::remap_len)). On an error the buffers are untouched.
    ///
    /// Buffers with room for three vertices a triangle (or for every vertex there is) are
    /// written in one walk of the mesh; smaller ones take a walk first that counts the
    /// vertices (as [`mesh_size`](Self::mesh_size) does, which a caller sizing its buffers has
    /// called already).
    pub fn write_mesh<I: MeshIndex>(
        &self,
        vertices: &mut [Vertex],
        triangles: &mut [[I; 3]],
        remap: &mut [u32],
    ) -> Result<MeshSize, WriteError> {
        let remap = self.cleared_remap(remap)?;
        // The mesh's size first, so that a mesh that does not fit leaves the buffers
        // untouched: known without a walk (see `known_size`), or else counted here (`remap`
        // marks the vertices seen, as [`SEEN`]).
        let size = match self.known_size::<I>(vertices.len()) {
            Some(size) => size,
            None => {
                let mut size = MeshSize::default();
                self.each_written(|_, corners| {
                    for v in corners {
                        if let Some(slot) = remap.get_mut(v as usize).filter(|s| **s == u32::MAX) {
                            *slot = SEEN;
                            size.vertices += 1;
                        }
                    }
                    size.triangles += 1;
                });
                size
            }
        };
        check_room::<I>(size, vertices.len(), triangles.len())?;
        let (mut nv, mut nt) = (0usize, 0usize);
        self.each_written(|h, corners| {
            let mut out = [I::default(); 3];
            let grid = self.oriented(h, h.tri.corners);
            for ((o, v), at) in out.iter_mut().zip(corners).zip(grid) {
                let Some(slot) = remap.get_mut(v as usize) else {
                    continue; // (never: every vertex of the frame has its entry)
                };
                if *slot >= SEEN {
                    *slot = nv as u32;
                    if let Some(x) = vertices.get_mut(nv) {
                        *x = self.vertex(v, h.tri.patch, at);
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

    /// The entries of `remap` a frame's write reads: the pool's vertices are anywhere in it
    /// (a hash table), but most frames make none, and then only the bake's vertices have
    /// entries to read or mark.
    fn remap_read(&self) -> usize {
        let pool = match self.pool.used > 0 {
            true => self.pool.entries.len(),
            false => 0,
        };
        self.tree.vertex_count() + pool
    }

    /// The part of `remap` a frame's write reads, every entry cleared (`u32::MAX`), or the
    /// error of a `remap` shorter than [`remap_len`](Self::remap_len).
    pub(super) fn cleared_remap<'r>(
        &self,
        remap: &'r mut [u32],
    ) -> Result<&'r mut [u32], WriteError> {
        let needed = self.remap_len();
        let Some(remap) = remap.get_mut(..needed) else {
            return Err(WriteError::RemapTooSmall { needed });
        };
        let remap = &mut remap[..self.remap_read()];
        remap.fill(u32::MAX);
        Ok(remap)
    }

    /// The size of the mesh to write where it is known without a walk, for a vertex buffer
    /// of `room` entries: counted by `update` or `mesh_size`, or else found to fit without a
    /// count (at most three vertices a triangle, and no more than there are), as a size of
    /// that many vertices. `None`: a walk must count it.
    pub(super) fn known_size<I: MeshIndex>(&self, room: usize) -> Option<MeshSize> {
        let triangles = self.stats.triangles;
        let most = self.remap_read().min(3 * triangles);
        match self.vertices {
            Some(vertices) => Some(MeshSize {
                vertices,
                triangles,
            }),
            None => (most <= room.min(I::LIMIT)).then_some(MeshSize {
                vertices: most,
                triangles,
            }),
        }
    }
}

/// A remap entry whose vertex has been seen by a count, and has no number yet.
const SEEN: u32 = u32::MAX - 1;

/// Whether buffers of `vertices` and `triangles` entries, indexed by `I`, hold a mesh of
/// `size`.
pub(super) fn check_room<I: MeshIndex>(
    size: MeshSize,
    vertices: usize,
    triangles: usize,
) -> Result<(), WriteError> {
    if vertices < size.vertices || triangles < size.triangles {
        return Err(WriteError::BuffersTooSmall { needed: size });
    }
    if size.vertices > I::LIMIT {
        return Err(WriteError::IndexOverflow {
            vertices: size.vertices,
        });
    }
    Ok(())
}
