//! Insertion: the triangle (or edge) holding the point is split, then edges are flipped until
//! they are Delaunay (Lawson).

use super::{
    after, before, in_circle, index_of, orient, DomainIndex, DomainMesh, GridPoint, InsertError,
    MeshTriangle,
};

impl<Ix: DomainIndex> DomainMesh<'_, Ix> {
    /// A live triangle containing `p` (inside or on its boundary).
    pub(super) fn locate(&self, p: GridPoint) -> u16 {
        let mut t = self.hint;
        if !self.triangles.get(t as usize).is_some_and(|x| x.is_live()) {
            t = self.first_live_triangle();
        }
        // A visibility walk terminates in a Delaunay triangulation; the bound only guards
        // against a bug turning into a hang, with a scan as the fallback.
        for _ in 0..self.triangles.len() + 4 {
            let [a, b, c] = self.tri_points(t);
            let n = self.tri(t).n;
            let next = if orient(b, c, p) < 0 {
                n[0]
            } else if orient(c, a, p) < 0 {
                n[1]
            } else if orient(a, b, p) < 0 {
                n[2]
            } else {
                return t;
            };
            if next == Ix::NO_SLOT {
                break;
            }
            t = next;
        }
        self.scan_for(p)
    }

    fn first_live_triangle(&self) -> u16 {
        self.triangles.iter().position(|t| t.is_live()).unwrap_or(0) as u16
    }

    fn scan_for(&self, p: GridPoint) -> u16 {
        (0..self.triangles.len() as u16)
            .find(|&t| {
                self.triangles[t as usize].is_live() && {
                    let [a, b, c] = self.tri_points(t);
                    orient(b, c, p) >= 0 && orient(c, a, p) >= 0 && orient(a, b, p) >= 0
                }
            })
            .unwrap_or_else(|| self.first_live_triangle())
    }

    /// Inserts `p`; returns its vertex index.
    ///
    /// The triangle (or edge) holding `p` is split and the edges around `p` are flipped until
    /// they are Delaunay (Lawson). Needs one vertex slot and two triangle slots (one when `p`
    /// lies on the square's boundary) and no other memory, whatever the number of triangles
    /// that change.
    pub fn insert(&mut self, p: GridPoint) -> Result<u16, InsertError> {
        let t = self.locate(p);
        let tri = self.tri(t);
        if let Some(vertex) = tri.v.into_iter().find(|&v| self.pt(v) == p) {
            return Err(InsertError::Duplicate { vertex });
        }
        if self.free_vertex == Ix::NO_SLOT {
            return Err(InsertError::VerticesFull);
        }
        let [a, b, c] = tri.v.map(|v| self.pt(v));
        // The edge `p` lies on, if any: the one opposite vertex `i`.
        let on_edge = [orient(b, c, p), orient(c, a, p), orient(a, b, p)]
            .iter()
            .position(|&o| o == 0);
        let needed = match on_edge {
            Some(i) if tri.n[i] == Ix::NO_SLOT => 1,
            _ => 2,
        };
        if self.triangles.len() - self.triangle_count < needed {
            return Err(InsertError::TrianglesFull { needed });
        }
        let id = self.take_vertex(p);
        let (start, degree) = match on_edge {
            None => self.split_triangle(t, id),
            Some(i) => self.split_edge(t, i, id),
        };
        self.legalize(id, start, degree);
        self.hint = self.link(id);
        Ok(id)
    }

    /// Splits triangle `t` into three around the new vertex `id` inside it; returns the first
    /// triangle of `id`'s star (as [`DomainMesh::star`] orders it) and the star's size.
    fn split_triangle(&mut self, t: u16, id: u16) -> (u16, usize) {
        let MeshTriangle {
            v: [a, b, c], n, ..
        } = self.tri(t);
        let (t1, t2) = (self.take_triangle(), self.take_triangle());
        // t: (id, b, c), t1: (id, c, a), t2: (id, a, b).
        self.set(t, [id, b, c], [n[0], t1, t2]);
        self.set(t1, [id, c, a], [n[1], t2, t]);
        self.set(t2, [id, a, b], [n[2], t, t1]);
        self.replace_neighbor(n[1], t, t1);
        self.replace_neighbor(n[2], t, t2);
        for (v, tri) in [(id, t), (a, t1), (b, t), (c, t)] {
            self.set_link(v, tri);
        }
        (t, 3)
    }

    /// Splits the edge of `t` opposite its vertex `i`, on which the new vertex `id` lies, and
    /// the triangle across it (if any); returns the first triangle of `id`'s star and the
    /// star's size, as [`DomainMesh::split_triangle`] does.
    fn split_edge(&mut self, t: u16, i: usize, id: u16) -> (u16, usize) {
        let tri = self.tri(t);
        let (c, a, b) = (tri.v[i], tri.v[after(i)], tri.v[before(i)]);
        let (na, nb, o) = (tri.n[after(i)], tri.n[before(i)], tri.n[i]);
        // t: (c, a, id), t1: (c, id, b).
        let t1 = self.take_triangle();
        if o == Ix::NO_SLOT {
            self.set(t, [c, a, id], [Ix::NO_SLOT, t1, nb]);
            self.set(t1, [c, id, b], [Ix::NO_SLOT, na, t]);
            self.replace_neighbor(na, t, t1);
            for (v, tri) in [(id, t), (a, t), (b, t1), (c, t)] {
                self.set_link(v, tri);
            }
            // On the boundary: the star is (c, id, b) then (c, a, id), counter-clockwise.
            return (t1, 2);
        }
        let ot = self.tri(o);
        let j = index_of(&ot.n, t);
        // o is (d, b, a); it becomes o: (d, b, id) and o1: (d, id, a).
        let d = ot.v[j];
        let (oa, ob) = (ot.n[before(j)], ot.n[after(j)]);
        let o1 = self.take_triangle();
        self.set(t, [c, a, id], [o1, t1, nb]);
        self.set(t1, [c, id, b], [o, na, t]);
        self.set(o, [d, b, id], [t1, o1, oa]);
        self.set(o1, [d, id, a], [t, ob, o]);
        self.replace_neighbor(na, t, t1);
        self.replace_neighbor(ob, o, o1);
        for (v, tri) in [(id, t), (a, t), (b, t1), (c, t), (d, o)] {
            self.set_link(v, tri);
        }
        (t, 4)
    }

    /// Flips the edges opposite the new vertex `id` until every one is Delaunay, in one pass
    /// counter-clockwise around its star, which starts at triangle `start` and has `degree`
    /// triangles.
    ///
    /// Flipping the edge `(a, b)` of `(id, a, b)` leaves `(id, a, d)` in the same slot, checked
    /// again at once, and `(id, d, b)` as its counter-clockwise neighbour, checked next; the
    /// rest of the star is untouched. An edge found Delaunay stays so: its test involves only
    /// the two triangles beside it, and a flip elsewhere replaces neither (it removes a
    /// triangle across another star edge). So every triangle of the final star is found clean
    /// exactly once, and the pass ends after `degree` clean tests.
    fn legalize(&mut self, id: u16, start: u16, mut degree: usize) {
        let p = self.pt(id);
        let mut t = start;
        let mut clean = 0usize;
        // A bound on the work, only a guard: each flip removes an edge for good.
        let mut budget = 8 * self.triangles.len() + 16;
        while budget > 0 {
            budget -= 1;
            let tri = self.tri(t);
            let i = index_of(&tri.v, id);
            let o = tri.n[i];
            if o != Ix::NO_SLOT {
                let ot = self.tri(o);
                let j = index_of(&ot.n, t);
                let (a, b) = (tri.v[after(i)], tri.v[before(i)]);
                if in_circle(self.metric, p, self.pt(a), self.pt(b), self.pt(ot.v[j])) {
                    self.flip_across(t, i, &tri, j, &ot);
                    degree += 1;
                    continue;
                }
            }
            clean += 1;
            if clean >= degree {
                break;
            }
            let ccw = tri.n[after(i)];
            t = if ccw == Ix::NO_SLOT {
                self.star_start(id)
            } else {
                ccw
            };
        }
    }

    /// Flips the edge of `t` opposite its vertex `i`: `t = (p, a, b)` and the triangle across,
    /// `(d, b, a)`, become `(p, a, d)` (in slot `t`) and `(p, d, b)`.
    pub(super) fn flip(&mut self, t: u16, i: usize) {
        let tri = self.tri(t);
        let ot = self.tri(tri.n[i]);
        self.flip_across(t, i, &tri, index_of(&ot.n, t), &ot);
    }

    /// [`DomainMesh::flip`] given triangle `t`'s contents `tri`, the contents `ot` of the
    /// triangle across the edge opposite `tri.v[i]`, and the index `j` of `t` among `ot`'s
    /// neighbours.
    fn flip_across(&mut self, t: u16, i: usize, tri: &MeshTriangle, j: usize, ot: &MeshTriangle) {
        let o = tri.n[i];
        let [p, a, b] = [tri.v[i], tri.v[after(i)], tri.v[before(i)]];
        let d = ot.v[j];
        let (across_ad, across_db) = (ot.n[after(j)], ot.n[before(j)]);
        let (across_bp, across_pa) = (tri.n[after(i)], tri.n[before(i)]);
        self.set(t, [p, a, d], [across_ad, o, across_pa]);
        self.set(o, [p, d, b], [across_db, across_bp, t]);
        self.replace_neighbor(across_ad, o, t);
        self.replace_neighbor(across_bp, t, o);
        for (v, tri) in [(p, t), (a, t), (d, t), (b, o)] {
            self.set_link(v, tri);
        }
    }

    /// Writes triangle `t` as `v` with neighbours `n` (`n[i]` across the edge opposite
    /// `v[i]`), rotated to start at its smallest point: a triangle's corner order then depends
    /// on its points alone, not on the history of the mesh (the run time's bounds and
    /// refinement patterns follow the corner order).
    pub(super) fn set(&mut self, t: u16, v: [u16; 3], n: [u16; 3]) {
        // The points in (u, v) order as one number each: `GridPoint`'s order, in one compare.
        let key = |id: u16| {
            let p = self.pt(id);
            (p.u as u32) << 16 | p.v as u32
        };
        let (k0, k1, k2) = (key(v[0]), key(v[1]), key(v[2]));
        let (v, n) = if k1 < k0 && k1 < k2 {
            ([v[1], v[2], v[0]], [n[1], n[2], n[0]])
        } else if k2 < k0 && k2 < k1 {
            ([v[2], v[0], v[1]], [n[2], n[0], n[1]])
        } else {
            (v, n)
        };
        self.put(t, MeshTriangle { v, n });
    }

    /// In triangle `t` (if any), the neighbour `old` becomes `new`.
    pub(super) fn replace_neighbor(&mut self, t: u16, old: u16, new: u16) {
        let old = Ix::narrow(old);
        if let Some(tri) = self.triangles.get_mut(t as usize) {
            if let Some(k) = tri.n.iter().position(|&x| x == old) {
                tri.n[k] = Ix::narrow(new);
            }
        }
    }
}
