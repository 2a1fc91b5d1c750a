//! A frame's mesh written on a host's cores ([`Tessellator::write_mesh_parallel`], feature
//! `std`): the same buffers as [`Tessellator::write_mesh`] writes, bit for bit.
//!
//! # How
//!
//! [`write_mesh`](Tessellator::write_mesh) walks the mesh once, numbering each vertex where a
//! triangle first uses it and writing it there. Here that is two passes:
//!
//! 1. The threads walk the mesh in parts, runs of its roots as a frame's search cuts them
//!    (see `parallel`), taking parts as [`Runs`] deals them out. Each part writes its
//!    triangles with numbers of its own for their vertices, in order of first use within the
//!    part, and those vertices (a vertex's parameters are the same from every triangle that
//!    has it, so the part that first uses it writes what the one walk writes).
//! 2. The calling thread takes the parts in order and numbers each part's vertices in the
//!    order the part first used them, but for those a part before it used (on their
//!    border): the order of first use in the one walk, which goes part after part. It copies
//!    each vertex once and writes the triangles with the frame's numbers.
//!
//! A vertex on a border between parts is written by each part that has it; the walk and the
//! vertices (decoding the hierarchy's points and normals, finding parameters) are what is
//! shared out, and the second pass is a lookup and a copy per vertex and per triangle.
//!
//! Measured on two cores against `write_mesh` (`frame_loop`, `PARALLEL=1`, best of 3,000
//! frames at the 2.5e-4 bake, 1024x768, in one run): the rational torus 0.331 -> 0.307 ms a
//! frame, the teapot 0.588 -> 0.550 ms, the single-patch threejs surface (four parts)
//! 0.200 -> 0.199 ms; with the calling thread spinning at the end of the threads' work (see
//! `parallel`'s `spin_until`) and each thread's table kept ([`NUMBERS`]), the medians fell
//! by a further 10-17%.

use core::cell::RefCell;
use std::vec;
use std::vec::Vec;

use super::output::check_room;
use super::parallel::{on_each, parts, Runs, PARTS_PER_THREAD};
use super::select::Tessellator;
use crate::sink::{MeshIndex, MeshSize, Vertex, WriteError};

/// A mesh of fewer triangles than this is written on the calling thread: waking the threads
/// costs more than they save.
const SMALL_MESH: usize = 1024;

/// What a part's walk wrote: its triangles, each corner its number among the part's
/// vertices, and those vertices in the order the part first used them, with their numbers
/// in the frame (of the bake or the pool).
#[derive(Default)]
struct Part {
    triangles: Vec<[u32; 3]>,
    vertices: Vec<(u32, Vertex)>,
}

std::thread_local! {
    /// A thread's table of a part's numbers for the frame's vertices (`u32::MAX`: none yet),
    /// kept from write to write so that a write neither allocates nor clears an entry a
    /// vertex of the hierarchy: a part sets the entries of its vertices, and clears them when
    /// it is done. (Each thread that writes keeps four bytes a vertex of the largest
    /// hierarchy it wrote, for the thread's life.)
    static NUMBERS: RefCell<Vec<u32>> = const { RefCell::new(Vec::new()) };
}

impl Tessellator<'_, '_> {
    /// [`write_mesh`](Self::write_mesh), with the walk of the mesh and its vertices on
    /// rayon's threads (all cores, or those of the pool it is called in): the same buffers,
    /// bit for bit, and the same errors. It takes storage for the frame on the heap: a copy
    /// of the tessellator's bits and a vertex table a thread, and each part's triangles and
    /// vertices.
    ///
    /// Written on the calling thread, as `write_mesh` writes it: a mesh of fewer than 1,024
    /// triangles (waking the threads costs more than they save), a frame with vertices below
    /// the bake, and a mesh whose vertex count is not known without a walk (see
    /// [`write_mesh`](Self::write_mesh)) for a vertex buffer of fewer than three entries a
    /// triangle.
    ///
    /// ```
    /// # use spline_tess::tessellator::{Hierarchy, PoolSlot, StackSlot, Tessellator};
    /// # use spline_tess::{Vertex, View};
    /// # fn run(tree: Hierarchy<'_>, view: &View) {
    /// let mut bits = vec![0; tree.bit_words()];
    /// let mut stack = vec![StackSlot::default(); 4096];
    /// let mut pool = vec![PoolSlot::default(); 1 << 16];
    /// let mut tessellator =
    ///     Tessellator::from_slices(tree, &mut bits, &mut stack, &mut pool).expect("storage");
    /// let stats = tessellator.update_parallel(view).expect("a valid view");
    /// // Room for three vertices a triangle: no walk first to count them.
    /// let mut vertices = vec![Vertex::default(); 3 * stats.triangles];
    /// let mut triangles = vec![[0u32; 3]; stats.triangles];
    /// let mut remap = vec![0; tessellator.remap_len()];
    /// let size = tessellator
    ///     .write_mesh_parallel(&mut vertices, &mut triangles, &mut remap)
    ///     .expect("room for the mesh");
    /// vertices.truncate(size.vertices);
    /// # }
    /// ```
    pub fn write_mesh_parallel<I: MeshIndex>(
        &self,
        vertices: &mut [Vertex],
        triangles: &mut [[I; 3]],
        remap: &mut [u32],
    ) -> Result<MeshSize, WriteError> {
        let threads = rayon::current_num_threads();
        let size = self.known_size::<I>(vertices.len());
        let Some(size) = size.filter(|s| s.triangles >= SMALL_MESH && threads > 1) else {
            return self.write_mesh(vertices, triangles, remap);
        };
        // A copy of the frame for each thread to read (see `reading_copy`): none where the
        // frame has vertices below the bake.
        let words = self.tree.bit_words();
        let mut bits: Vec<Vec<u32>> = (0..threads).map(|_| vec![0; words]).collect();
        let copies: Option<Vec<Tessellator>> =
            bits.iter_mut().map(|b| self.reading_copy(b)).collect();
        let Some(copies) = copies else {
            return self.write_mesh(vertices, triangles, remap);
        };
        let remap = self.cleared_remap(remap)?;
        check_room::<I>(size, vertices.len(), triangles.len())?;
        // 1. Each part's triangles, indexing its own vertices, and its vertices.
        let parts = parts(self, threads * PARTS_PER_THREAD);
        let runs = Runs::new(parts.len(), threads);
        let vertex_count = remap.len();
        let items: Vec<_> = copies.into_iter().enumerate().collect();
        let walked = on_each(items, |(me, copy)| {
            NUMBERS.with_borrow_mut(|numbers| {
                if numbers.len() < vertex_count {
                    numbers.resize(vertex_count, u32::MAX);
                }
                let mut found = Vec::new();
                while let Some(number) = runs.next(me) {
                    found.push((number, copy.write_part(parts[number], numbers)));
                }
                found
            })
        });
        let mut found: Vec<(usize, Part)> = walked.into_iter().flatten().collect();
        found.sort_unstable_by_key(|(number, _)| *number);
        // 2. The vertices numbered in order of first use: a part's in the order it first
        // used them, but those a part before it used (on their border).
        let (mut nv, mut nt) = (0usize, 0usize);
        let mut numbers = Vec::new();
        for (_, part) in &found {
            numbers.clear();
            for (v, vertex) in &part.vertices {
                let Some(slot) = remap.get_mut(*v as usize) else {
                    numbers.push(0);
                    continue; // (never: every vertex of the frame has its entry)
                };
                if *slot == u32::MAX {
                    *slot = nv as u32;
                    if let Some(x) = vertices.get_mut(nv) {
                        *x = *vertex;
                    }
                    nv += 1;
                }
                numbers.push(*slot);
            }
            for t in &part.triangles {
                if let Some(out) = triangles.get_mut(nt) {
                    *out = t.map(|k| I::from_index(numbers.get(k as usize).copied().unwrap_or(0)));
                }
                nt += 1;
            }
        }
        Ok(MeshSize {
            vertices: nv,
            triangles: nt,
        })
    }

    /// The triangles of `part`'s roots with numbers of the part's own for their vertices, in
    /// order of first use, and those vertices; `numbers` has an entry a vertex, every one
    /// `u32::MAX`, and is left so.
    fn write_part(&self, part: super::select::Part, numbers: &mut [u32]) -> Part {
        let mut out = Part::default();
        self.each_written_in(Some(part), |h, corners| {
            let grid = self.oriented(h, h.tri.corners);
            let mut triangle = [0; 3];
            for ((t, v), at) in triangle.iter_mut().zip(corners).zip(grid) {
                let Some(slot) = numbers.get_mut(v as usize) else {
                    continue; // (never: every vertex of the frame has its entry)
                };
                if *slot == u32::MAX {
                    *slot = out.vertices.len() as u32;
                    out.vertices.push((v, self.vertex(v, h.tri.patch, at)));
                }
                *t = *slot;
            }
            out.triangles.push(triangle);
        });
        for &(v, _) in &out.vertices {
            if let Some(slot) = numbers.get_mut(v as usize) {
                *slot = u32::MAX;
            }
        }
        out
    }
}
