//! Compaction: the live slots moved to the front of the storage, so a mesh can be carried to
//! a shorter (or longer) stretch of slots.
//!
//! The triangulation does not change: a live triangle in a slot past the live count moves to
//! a free slot before it, and its neighbours and corners follow; then a live vertex past the
//! live count moves the same way, and the triangles around it follow. Vertices 0 to 3 (the
//! corners) never move. The work is one pass over the slots plus, per moved vertex, a walk
//! around it.

use super::{after, index_of, DomainIndex, DomainMesh, MeshHeader, MeshTriangle, MeshVertex};

impl<'a, Ix: DomainIndex> DomainMesh<'a, Ix> {
    /// Moves the live triangles to slots `0..triangle_count()` and the live vertices to
    /// `0..vertex_count()`, calling `moved(from, to)` for every triangle moved (so data kept
    /// per triangle slot can follow). The free slots after them are chained again.
    pub(crate) fn compact(&mut self, mut moved: impl FnMut(u16, u16)) {
        let nt = self.triangle_count;
        let mut high = self.triangles.len();
        for low in 0..nt {
            if self.triangles[low].is_live() {
                continue;
            }
            // As many live slots lie after `nt` as free ones before it.
            let mut from = None;
            while high > nt {
                high -= 1;
                if self.triangles[high].is_live() {
                    from = Some(high as u16);
                    break;
                }
            }
            let Some(from) = from else { break };
            self.move_triangle(from, low as u16);
            moved(from, low as u16);
        }
        let nv = self.vertex_count;
        let mut high = self.vertices.len();
        for low in 0..nv {
            if self.vertices[low].is_live() {
                continue;
            }
            let mut from = None;
            while high > nv {
                high -= 1;
                if self.vertices[high].is_live() {
                    from = Some(high as u16);
                    break;
                }
            }
            let Some(from) = from else { break };
            self.move_vertex(from, low as u16);
        }
        self.chain_free_slots();
    }

    /// The mesh of `header` (saved from a mesh after [`DomainMesh::compact`]) over new
    /// storage that starts with its live slots: the slots after them are chained as free.
    pub(crate) fn resume_compacted(
        vertices: &'a mut [MeshVertex<Ix>],
        triangles: &'a mut [MeshTriangle<Ix>],
        header: MeshHeader,
    ) -> Self {
        let mut mesh = DomainMesh::resume(vertices, triangles, header);
        mesh.chain_free_slots();
        mesh
    }

    /// Moves live triangle `from` to free slot `to`.
    fn move_triangle(&mut self, from: u16, to: u16) {
        let tri = self.triangles[from as usize];
        self.triangles[to as usize] = tri;
        self.triangles[from as usize] = MeshTriangle::default();
        let (from, to) = (Ix::narrow(from), Ix::narrow(to));
        for n in tri.n {
            if let Some(other) = self.triangles.get_mut(n.widen() as usize) {
                for m in other.n.iter_mut() {
                    if *m == from {
                        *m = to;
                    }
                }
            }
        }
        for v in tri.v {
            if let Some(vertex) = self.vertices.get_mut(v.widen() as usize) {
                let link = vertex.link;
                if link == from {
                    vertex.link = to;
                }
            }
        }
    }

    /// Moves live vertex `from` to free slot `to`.
    fn move_vertex(&mut self, from: u16, to: u16) {
        let start = self.star_start(from);
        let mut t = start;
        // The step bound only guards against a corrupted mesh turning into a hang.
        for _ in 0..=self.triangles.len() {
            let mut tri = self.tri(t);
            let i = index_of(&tri.v, from);
            tri.v[i] = to;
            self.put(t, tri);
            // Counter-clockwise: across the edge (v[i+2], from), opposite v[i+1].
            let ccw = tri.n[after(i)];
            if ccw == Ix::NO_SLOT || ccw == start {
                break;
            }
            t = ccw;
        }
        self.vertices[to as usize] = self.vertices[from as usize];
        self.vertices[from as usize] = MeshVertex::default();
    }
}

#[cfg(test)]
mod tests {
    use super::super::{DomainMesh, GridPoint, MeshTriangle, MeshVertex};

    /// The mesh's triangles as sorted point triples (rotated to start at the smallest point),
    /// written to `out`; returns how many.
    fn canonical(mesh: &DomainMesh<'_>, out: &mut [[(u16, u16); 3]]) -> usize {
        let mut n = 0;
        for v in mesh.triangles() {
            let p = v.map(|id| mesh.point(id).map_or((0, 0), |g| (g.u, g.v)));
            let k = (0..3).min_by_key(|&k| p[k]).unwrap_or(0);
            out[n] = [p[k], p[(k + 1) % 3], p[(k + 2) % 3]];
            n += 1;
        }
        out[..n].sort_unstable();
        n
    }

    /// A small deterministic generator.
    fn next(state: &mut u32) -> u32 {
        *state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        *state >> 8
    }

    #[test]
    fn compaction_keeps_the_triangulation_and_packs_the_slots() {
        let mut total_moves = 0;
        for seed in 1..20u32 {
            let mut vertices = [MeshVertex::default(); 64];
            let mut triangles = [MeshTriangle::default(); 128];
            let mut mesh = DomainMesh::new(&mut vertices, &mut triangles).unwrap();
            let mut state = seed;
            let mut ids = [0u16; 64];
            let mut live = 0;
            for step in 0..80 {
                if step % 3 == 2 && live > 0 {
                    let k = next(&mut state) as usize % live;
                    mesh.remove(ids[k]).unwrap();
                    ids[k] = ids[live - 1];
                    live -= 1;
                } else if live < 40 {
                    // Random points, some on the square's sides.
                    let (u, v) = match next(&mut state) % 4 {
                        0 => (0, next(&mut state) as u16),
                        1 => (next(&mut state) as u16, 0),
                        _ => (next(&mut state) as u16, next(&mut state) as u16),
                    };
                    if let Ok(id) = mesh.insert(GridPoint::new(u, v)) {
                        ids[live] = id;
                        live += 1;
                    }
                }
            }
            // Free slots in the middle: every other point goes.
            for &id in ids[..live].iter().step_by(2) {
                mesh.remove(id).unwrap();
            }
            let mut before = [[(0, 0); 3]; 128];
            let n = canonical(&mesh, &mut before);
            let mut moves = 0;
            mesh.compact(|from, to| {
                assert!(from as usize >= n && (to as usize) < n);
                moves += 1;
            });
            let mut after = [[(0, 0); 3]; 128];
            assert_eq!(canonical(&mesh, &mut after), n);
            assert_eq!(before[..n], after[..n]);
            let (nv, nt) = (mesh.vertex_count(), mesh.triangle_count());
            assert!(mesh.vertices().all(|(id, _)| (id as usize) < nv));
            assert!(mesh
                .triangles_with_neighbors()
                .all(|(t, ..)| (t as usize) < nt));
            // Carried to a shorter stretch of slots, it still takes insertions and deletions.
            let header = mesh.header();
            let (nv2, nt2) = (nv + 6, nt + 12);
            let mut mesh =
                DomainMesh::resume_compacted(&mut vertices[..nv2], &mut triangles[..nt2], header);
            for k in 0..6u16 {
                mesh.insert(GridPoint::new(1000 + 9000 * k, 3333 + 1111 * k))
                    .unwrap();
            }
            assert!(mesh.insert(GridPoint::new(5, 7)).is_err());
            let first = mesh.vertices().find(|&(id, _)| id >= 4).map(|(id, _)| id);
            if let Some(id) = first {
                mesh.remove(id).unwrap();
            }
            // The same points built afresh give the same triangles.
            let mut points = [GridPoint::default(); 64];
            let mut np = 0;
            for (id, p) in mesh.vertices() {
                if id >= 4 {
                    points[np] = p;
                    np += 1;
                }
            }
            let mut got = [[(0, 0); 3]; 128];
            let n = canonical(&mesh, &mut got);
            let (mut fv, mut ft) = ([MeshVertex::default(); 64], [MeshTriangle::default(); 128]);
            let mut fresh = DomainMesh::new(&mut fv, &mut ft).unwrap();
            for p in &points[..np] {
                fresh.insert(*p).unwrap();
            }
            let mut want = [[(0, 0); 3]; 128];
            assert_eq!(canonical(&fresh, &mut want), n);
            assert_eq!(got[..n], want[..n], "seed {seed}, {moves} moves");
            total_moves += moves;
        }
        assert!(total_moves > 20);
    }
}
