//! Host-side helpers for the tessellator (`spline_tess::tessellator`): a bake in `Vec`s
//! (`model_file::BakedHierarchy`, which the examples share), run-time storage in `Vec`s, and a
//! frame as an indexed mesh or as streamed triangles, with the checks the tests and figures
//! share.

use std::collections::HashMap;

use spline_tess::tessellator::{Hierarchy, PoolSlot, StackSlot, Tessellator};
use spline_tess::{TriangleInfo, Vertex};

pub use crate::model_file::BakedHierarchy;

/// Run-time storage for a [`Tessellator`] in `Vec`s.
#[derive(Debug)]
pub struct VecStorage {
    bits: Vec<u32>,
    stack: Vec<StackSlot>,
    pool: Vec<PoolSlot>,
}

impl VecStorage {
    /// Storage for `tree` with a stack of `stack` entries and a pool of `pool` vertices
    /// below the bake.
    pub fn new(tree: &Hierarchy<'_>, stack: usize, pool: usize) -> Self {
        VecStorage {
            bits: vec![0; tree.bit_words()],
            stack: vec![StackSlot::default(); stack],
            pool: vec![PoolSlot::default(); pool],
        }
    }

    /// A run time over `tree` in this storage.
    pub fn tessellator<'t>(&mut self, tree: Hierarchy<'t>) -> Tessellator<'t, '_> {
        Tessellator::from_slices(tree, &mut self.bits, &mut self.stack, &mut self.pool)
            .expect("storage sized for the tree")
    }
}

/// An indexed mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Vertices.
    pub vertices: Vec<Vertex>,
    /// Triangles.
    pub triangles: Vec<[u32; 3]>,
}

/// The current frame as an indexed mesh.
pub fn indexed(selection: &mut Tessellator<'_, '_>) -> Mesh {
    let size = selection.mesh_size();
    let mut mesh = Mesh {
        vertices: vec![Vertex::default(); size.vertices],
        triangles: vec![[0; 3]; size.triangles],
    };
    let mut remap = vec![0u32; selection.remap_len()];
    selection
        .write_mesh(&mut mesh.vertices, &mut mesh.triangles, &mut remap)
        .expect("buffers sized by mesh_size");
    mesh
}

/// One streamed triangle: its patch, vertices, own-patch parameters and bound.
#[derive(Clone, Debug)]
pub struct Streamed {
    /// The patch.
    pub patch: u32,
    /// Vertices.
    pub corners: [Vertex; 3],
    /// Parameters in the patch.
    pub uv: [[f32; 2]; 3],
    /// The kernel's deviation bound, in model units.
    pub bound: f32,
}

impl Streamed {
    /// A streamed triangle as a `stream_with_info` hands it out.
    pub fn of(info: &TriangleInfo, c: [&Vertex; 3]) -> Streamed {
        Streamed {
            patch: info.patch,
            corners: [*c[0], *c[1], *c[2]],
            uv: info.uv,
            bound: info.bound,
        }
    }
}

/// The current frame as streamed triangles.
pub fn streamed(selection: &Tessellator<'_, '_>) -> Vec<Streamed> {
    let mut out = Vec::new();
    selection.stream_with_info(|info, c| out.push(Streamed::of(info, c)));
    out
}

/// The frame's triangles as a sorted list of corner sets `(patch, u bits, v bits)`.
pub fn triangle_set(tris: &[Streamed]) -> Vec<[(u32, u32, u32); 3]> {
    let mut set: Vec<[(u32, u32, u32); 3]> = tris
        .iter()
        .map(|t| {
            let mut c = t.uv.map(|[u, v]| (t.patch, u.to_bits(), v.to_bits()));
            c.sort();
            c
        })
        .collect();
    set.sort();
    set
}

/// Edge use counts of an indexed mesh, keyed by sorted vertex pair, with one triangle per
/// edge for reporting.
pub fn edge_uses(mesh: &Mesh) -> HashMap<(u32, u32), (usize, usize)> {
    let mut uses: HashMap<(u32, u32), (usize, usize)> = HashMap::new();
    for (k, t) in mesh.triangles.iter().enumerate() {
        for i in 0..3 {
            let (a, b) = (t[i], t[(i + 1) % 3]);
            let key = (a.min(b), a.max(b));
            uses.entry(key).or_insert((0, k)).0 += 1;
        }
    }
    uses
}
