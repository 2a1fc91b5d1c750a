//! Deletion: "Delaunay ears" are flipped off the vertex's link until three triangles are left
//! (two on the boundary), which merge into one (Devillers).

use super::{
    after, before, in_circle, index_of, orient, DomainIndex, DomainMesh, MeshVertex, RemoveError,
    RimEdge,
};

impl<Ix: DomainIndex> DomainMesh<'_, Ix> {
    /// Removes vertex `id` and re-triangulates the hole.
    ///
    /// Delaunay ears of the vertex's link are flipped off one at a time (each is a triangle of
    /// the final triangulation), until three triangles are left around an interior vertex or
    /// two around a boundary one; those merge into one. Needs no memory beyond the mesh; the
    /// work grows with the cube of the vertex's degree, which greedy samples keep small.
    pub fn remove(&mut self, id: u16) -> Result<(), RemoveError> {
        if id < 4 {
            return Err(RemoveError::Corner);
        }
        if !self.vertices.get(id as usize).is_some_and(|v| v.is_live()) {
            return Err(RemoveError::NotAVertex);
        }
        let boundary = self.pt(id).on_boundary();
        let last = if boundary { 2 } else { 3 };
        loop {
            let degree = self.star(id).count();
            if degree <= last {
                break;
            }
            if !self.flip_ear(id, boundary) {
                if degree == 4 && !boundary {
                    self.merge_four(id);
                    return Ok(());
                }
                return Err(RemoveError::NoEar);
            }
        }
        self.merge(id, boundary);
        Ok(())
    }

    /// True when `(a, b, c)`, three consecutive vertices of `id`'s link, is a Delaunay ear:
    /// convex, with `id` beyond its diagonal, and no other link vertex in its circumcircle.
    fn is_ear(&self, id: u16, a: u16, b: u16, c: u16) -> bool {
        let (pa, pb, pc, v) = (self.pt(a), self.pt(b), self.pt(c), self.pt(id));
        if orient(pa, pb, pc) <= 0 || orient(v, pa, pc) <= 0 {
            return false;
        }
        self.star(id).all(|t| {
            let tri = self.tri(t).v;
            let i = index_of(&tri, id);
            [tri[after(i)], tri[before(i)]].into_iter().all(|x| {
                x == a || x == b || x == c || !in_circle(self.metric, pa, pb, pc, self.pt(x))
            })
        })
    }

    /// Flips one Delaunay ear off the link of `id`; false if there is none.
    fn flip_ear(&mut self, id: u16, boundary: bool) -> bool {
        // Consecutive triangles (id, a, b) and (id, b, c) of the star make the ear (a, b, c).
        let mut found = None;
        let mut first: Option<(u16, u16, u16)> = None;
        let mut prev: Option<(u16, u16, u16)> = None;
        for t in self.star(id) {
            let tri = self.tri(t).v;
            let i = index_of(&tri, id);
            let (x, y) = (tri[after(i)], tri[before(i)]);
            if let Some((pt, a, b)) = prev {
                if self.is_ear(id, a, b, y) {
                    found = Some((pt, a));
                    break;
                }
            }
            prev = Some((t, x, y));
            first = first.or(prev);
        }
        if found.is_none() && !boundary {
            // The closing pair: the last triangle and the first.
            if let (Some((pt, a, b)), Some((_, _, c))) = (prev, first) {
                if self.is_ear(id, a, b, c) {
                    found = Some((pt, a));
                }
            }
        }
        let Some((t, a)) = found else {
            return false;
        };
        // Flipping the edge (b, id) of (id, a, b), opposite a, cuts the ear off.
        let i = index_of(&self.tri(t).v, a);
        self.flip(t, i);
        true
    }

    /// The last step of a removal: the triangles left around `id` (three around an interior
    /// vertex, two around a boundary one) become one.
    fn merge(&mut self, id: u16, boundary: bool) {
        let mut star = [Ix::NO_SLOT; 3];
        for (slot, t) in star.iter_mut().zip(self.star(id)) {
            *slot = t;
        }
        let count = if boundary { 2 } else { 3 };
        // The outer neighbours and the link vertices, counter-clockwise.
        let mut link = [Ix::NO_SLOT; 4];
        let mut outer = [Ix::NO_SLOT; 3];
        for k in 0..count {
            let tri = self.tri(star[k]);
            let i = index_of(&tri.v, id);
            link[k] = tri.v[after(i)];
            link[k + 1] = tri.v[before(i)];
            outer[k] = tri.n[i];
        }
        let keep = star[0];
        let (v, n) = if boundary {
            // (q0, q1, q2), q0 and q2 on the boundary with id between them.
            (
                [link[0], link[1], link[2]],
                [outer[1], Ix::NO_SLOT, outer[0]],
            )
        } else {
            ([link[0], link[1], link[2]], [outer[1], outer[2], outer[0]])
        };
        for &t in &star[1..count] {
            self.free_triangle(t);
        }
        self.set(keep, v, n);
        for k in 1..count {
            self.replace_neighbor(outer[k], star[k], keep);
        }
        for x in v {
            self.set_link(x, keep);
        }
        self.free_vertex_slot(id);
        self.hint = keep;
    }

    /// Removal of an interior vertex of degree four lying on the diagonal its hole's Delaunay
    /// triangulation uses: the four triangles become two.
    fn merge_four(&mut self, id: u16) {
        let mut star = [Ix::NO_SLOT; 4];
        for (slot, t) in star.iter_mut().zip(self.star(id)) {
            *slot = t;
        }
        let mut q = [Ix::NO_SLOT; 4];
        let mut outer = [Ix::NO_SLOT; 4];
        for k in 0..4 {
            let tri = self.tri(star[k]);
            let i = index_of(&tri.v, id);
            q[k] = tri.v[after(i)];
            outer[k] = tri.n[i];
        }
        let p = q.map(|x| self.pt(x));
        // Diagonal q0-q2 unless q3 is inside the circle of q0 q1 q2 (or that diagonal is
        // outside the hole).
        let use_02 = !in_circle(self.metric, p[0], p[1], p[2], p[3])
            && orient(p[0], p[1], p[2]) > 0
            && orient(p[0], p[2], p[3]) > 0;
        let (t0, t1) = (star[0], star[1]);
        self.free_triangle(star[2]);
        self.free_triangle(star[3]);
        let none = [Ix::NO_SLOT; 3];
        if use_02 {
            self.set(t0, [q[0], q[1], q[2]], none);
            self.set(t1, [q[0], q[2], q[3]], none);
        } else {
            self.set(t0, [q[1], q[2], q[3]], none);
            self.set(t1, [q[1], q[3], q[0]], none);
        }
        // Neighbours by edge, not by the old pointers: where the hole is not convex, one
        // triangle outside borders two of its sides, and holds two of the old pointers.
        let rim: [RimEdge; 4] = core::array::from_fn(|k| (q[k], q[(k + 1) % 4], outer[k]));
        self.stitch(&[t0, t1], &rim);
        self.free_vertex_slot(id);
        self.hint = t0;
    }

    fn free_vertex_slot(&mut self, id: u16) {
        self.vertices[id as usize] = MeshVertex::free(self.free_vertex);
        self.free_vertex = id;
        self.vertex_count -= 1;
    }

    /// Sets the neighbours of the new triangles `new`: among themselves, and across the `rim`
    /// edges to the triangles outside (whose pointers are updated too). Also refreshes the
    /// incident-triangle link of every vertex of `new`.
    pub(super) fn stitch(&mut self, new: &[u16], rim: &[RimEdge]) {
        for &t in new {
            let v = self.tri(t).v;
            for i in 0..3 {
                let (a, b) = (v[after(i)], v[before(i)]);
                let inner = new.iter().copied().find(|&s| {
                    s != t && {
                        let w = self.tri(s).v;
                        (0..3).any(|j| w[j] == b && w[after(j)] == a)
                    }
                });
                let across = match inner {
                    Some(s) => s,
                    None => {
                        let outside = rim
                            .iter()
                            .find(|&&(x, y, _)| x == a && y == b)
                            .map_or(Ix::NO_SLOT, |&(_, _, o)| o);
                        if outside != Ix::NO_SLOT {
                            let mut o = self.tri(outside);
                            for j in 0..3 {
                                if o.v[after(j)] == b && o.v[before(j)] == a {
                                    o.n[j] = t;
                                }
                            }
                            self.put(outside, o);
                        }
                        outside
                    }
                };
                self.triangles[t as usize].n[i] = Ix::narrow(across);
                self.set_link(v[i], t);
            }
        }
    }
}
