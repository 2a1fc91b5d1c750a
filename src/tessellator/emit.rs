//! Output as indexed buffers: the frame's vertices, then its triangles as index triples (the
//! same triangles as a stream: see `stream`; their points and pieces: see `patch_view`).
//!
//! Vertices come in a fixed order: the corner nodes (all of them, also those of culled
//! patches), then every curve used by a visible patch from its start to its end, then per
//! visible patch its interior domain vertices, the points on its interior edges and the
//! points inside its refined triangles. Every refined point's parameter is an exact integer
//! combination of grid coordinates divided once, so it does not depend on which triangle
//! asks for it, nor on the history of the mesh.

use super::output_vertex::VertexBatch;
use super::patch_view::{Point, MAX};
use super::Tessellator;
use crate::domain::DomainIndex;
use crate::patch::Side;
use crate::sink::{MeshIndex, MeshSize, Vertex, WriteError};

/// Vertex and triangle counts of the current frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct MeshCounts {
    pub(crate) vertices: u32,
    pub(crate) triangles: u32,
}

impl<Ix: DomainIndex> Tessellator<'_, '_, Ix> {
    /// Counts the frame's mesh and each patch's range of its triangles, as
    /// [`write_mesh`](Self::write_mesh) would write them (without the scratch).
    pub(crate) fn count(&mut self) -> MeshCounts {
        self.emit::<u32>(None).unwrap_or_default()
    }

    /// The `u32` scratch [`write_mesh`](Self::write_mesh) needs for the current frame: the
    /// largest visible patch's vertex slots plus three per triangle slot (its index tables).
    pub(crate) fn write_scratch(&self) -> usize {
        (0..self.baked.patch_count())
            .filter(|&p| !self.storage.patches[p].culled)
            .map(|p| {
                let s = &self.storage.patches[p];
                s.vertex_capacity as usize + 3 * s.triangle_capacity as usize
            })
            .max()
            .unwrap_or(0)
    }

    /// Writes the frame's mesh: vertices, then triangles as index triples
    /// ([`MeshIndex`]: `u16` or `u32`). Returns the mesh's size; on an error the buffers are
    /// untouched.
    pub fn write_mesh<I: MeshIndex>(
        &mut self,
        vertices: &mut [Vertex],
        triangles: &mut [[I; 3]],
    ) -> Result<MeshSize, WriteError> {
        let needed = self.mesh_size();
        if vertices.len() < needed.vertices || triangles.len() < needed.triangles {
            return Err(WriteError::BuffersTooSmall { needed });
        }
        if needed.vertices > I::LIMIT {
            return Err(WriteError::IndexOverflow {
                vertices: needed.vertices,
            });
        }
        let scratch = self.write_scratch();
        if self.storage.scratch.len() < scratch {
            return Err(WriteError::ScratchTooSmall { needed: scratch });
        }
        let written = self.emit(Some((vertices, triangles)));
        // (The count's shortcuts give what writing does.)
        debug_assert_eq!(
            written,
            Some(self.counts),
            "the mesh written is the one counted"
        );
        Ok(needed)
    }

    /// The traversal behind [`write_mesh`] and the counts: with buffers, assigns indices in
    /// the scratch tables (at least [`write_scratch`](Self::write_scratch) long) and writes;
    /// without, only counts.
    fn emit<I: MeshIndex>(
        &mut self,
        mut out: Option<(&mut [Vertex], &mut [[I; 3]])>,
    ) -> Option<MeshCounts> {
        let baked = self.baked;
        let mut next = self.nodes;
        // Points are evaluated a few at a time (the same bits).
        let mut batch = VertexBatch::default();
        if let Some((vs, _)) = out.as_mut() {
            for n in 0..self.nodes {
                vs[n as usize] = self.vertex_data(Point::Node(n), 0);
            }
        }
        // Curves.
        for k in 0..baked.curve_count() {
            let cs = self.storage.curves[k];
            if !cs.used {
                continue;
            }
            self.storage.curves[k].base = next;
            let f = cs.factor.max(1) as u32;
            let cnt = cs.count as u32;
            if let Some((vs, _)) = out.as_mut() {
                let off = cs.order_offset as usize;
                for s in 0..=cnt {
                    let t0 = if s == 0 {
                        0
                    } else {
                        self.storage.curve_order[off + s as usize - 1] as u32
                    };
                    let t1 = if s == cnt {
                        MAX
                    } else {
                        self.storage.curve_order[off + s as usize] as u32
                    };
                    for r in 0..f {
                        let j = s * f + r;
                        if j == 0 {
                            continue;
                        }
                        let p = Point::Curve {
                            curve: k as u32,
                            j,
                            num: (f - r) * t0 + r * t1,
                            den: f * MAX,
                        };
                        self.queue_vertex(&mut batch, vs, next + j - 1, p, 0);
                    }
                }
                self.flush_vertices(&mut batch, vs);
            }
            next += (cnt + 1) * f - 1;
        }
        let mut triangles = 0u32;
        let (mut vs_out, mut ts_out) = match out {
            Some((vs, ts)) => (Some(vs), Some(ts)),
            None => (None, None),
        };
        // The index tables, when writing (counting needs none).
        let scratch = core::mem::take(&mut self.storage.scratch);
        let tables = if ts_out.is_some() {
            &mut scratch[..]
        } else {
            &mut []
        };
        for p in 0..baked.patch_count() {
            let Some(view) = self.output_view(p) else {
                continue;
            };
            let vc = self.storage.patches[p].vertex_capacity as usize;
            let (vidx, ebase) = tables.split_at_mut(vc.min(tables.len()));
            // Domain vertices: only the interior ones are new output vertices (a corner is a
            // node, a boundary vertex a node or a curve point), which is all a count needs.
            if vs_out.is_none() && vidx.is_empty() {
                next += (4..vc)
                    .filter(|&id| {
                        self.storage.vertices[view.vo + id]
                            .live_point()
                            .is_some_and(|g| !g.on_boundary())
                    })
                    .count() as u32;
            } else {
                for id in 0..vc {
                    if self.storage.vertices[view.vo + id].live_point().is_none() {
                        continue;
                    }
                    let point = view.vertex(id as u16);
                    let index = match point {
                        Point::Node(n) => n,
                        Point::Curve { curve, j, .. } => self.curve_index(curve, j),
                        Point::Vertex { p: g, .. } => {
                            if let Some(vs) = vs_out.as_mut() {
                                vs[next as usize] = self
                                    .cached_vertex(p, view.vo + id, g)
                                    .unwrap_or_else(|| self.vertex_data(point, p));
                            }
                            next += 1;
                            next - 1
                        }
                        _ => {
                            if let Some(vs) = vs_out.as_mut() {
                                vs[next as usize] = self.vertex_data(point, p);
                            }
                            next += 1;
                            next - 1
                        }
                    };
                    if let Some(slot) = vidx.get_mut(id) {
                        *slot = index;
                    }
                }
            }
            if self.storage.patches[p].factor <= 1 {
                // Nothing refined in or around the patch: its triangles as they are (what the
                // pattern of factor 1 gives, corners from the smallest point on), without
                // the pattern's machinery.
                let first_triangle = triangles;
                let may_flatten = view.may_flatten();
                for t in 0..view.tc {
                    let Some((v, _)) = view.triangle(t) else {
                        continue;
                    };
                    if view.hidden(t) {
                        continue;
                    }
                    let node = |id: u16| -> Option<u32> {
                        match view.vertex(id) {
                            Point::Node(n) => Some(n),
                            _ => None,
                        }
                    };
                    // On a collapsed edge two corners are one node: the triangle is flat.
                    // (Only where a side collapses or two corners share a node.)
                    let same = |a: Option<u32>, b: Option<u32>| a.is_some() && a == b;
                    let flat = may_flatten && {
                        let nodes = v.map(|id| {
                            (id < 4 || view.point_of(id).on_boundary())
                                .then(|| node(id))
                                .flatten()
                        });
                        same(nodes[0], nodes[1])
                            || same(nodes[1], nodes[2])
                            || same(nodes[2], nodes[0])
                    };
                    if flat {
                        continue;
                    }
                    if let Some(ts) = ts_out.as_mut() {
                        // From the smallest point on, as `DomainMesh::triangles` lists them.
                        ts[triangles as usize] = v.map(|id| I::from_index(vidx[id as usize]));
                    }
                    triangles += 1;
                }
                self.storage.patches[p].triangles = [first_triangle, triangles];
                continue;
            }
            // Interior edges: points written once, by the triangle with the smaller slot.
            for t in 0..view.tc {
                let Some((v, n)) = view.triangle(t) else {
                    continue;
                };
                for i in 0..3 {
                    let Some(nb) = n[i] else { continue };
                    let nb = nb as usize;
                    if nb < t {
                        if !ebase.is_empty() {
                            let j = view
                                .triangle(nb)
                                .and_then(|(_, nn)| nn.iter().position(|&x| x == Some(t as u16)))
                                .unwrap_or(0);
                            ebase[3 * t + i] = ebase[3 * nb + j];
                        }
                        continue;
                    }
                    if let Some(slot) = ebase.get_mut(3 * t + i) {
                        *slot = next;
                    }
                    let f = view.output_edge_factor(t, v, n, i) as u32;
                    if f <= 1 {
                        continue;
                    }
                    if let Some(vs) = vs_out.as_mut() {
                        let (a, b) = (view.point_of(v[(i + 1) % 3]), view.point_of(v[(i + 2) % 3]));
                        let (lo, hi) = if a < b { (a, b) } else { (b, a) };
                        for r in 1..f {
                            let point = Point::Edge {
                                slot: t as u32,
                                edge: i as u8,
                                r,
                                u: (f - r) * lo.u as u32 + r * hi.u as u32,
                                v: (f - r) * lo.v as u32 + r * hi.v as u32,
                                den: f * MAX,
                            };
                            self.queue_vertex(&mut batch, vs, next + r - 1, point, p);
                        }
                    }
                    next += f - 1;
                }
            }
            // Refined triangles (counted from their patterns where every piece is written).
            let first_triangle = triangles;
            let every_piece = view.writes_every_piece();
            let closed_form = ts_out.is_none() && every_piece;
            // An uncut triangle that cannot be flat is its corners' output points, which the
            // domain vertices' table holds.
            let may_flatten = view.may_flatten();
            for t in 0..view.tc {
                if view.hidden(t) {
                    continue;
                }
                if closed_form {
                    let (faces, pieces) = view.piece_counts(t);
                    next += faces;
                    triangles += pieces;
                    continue;
                }
                if let (false, Some((v, n))) = (may_flatten, view.triangle(t)) {
                    if view.pattern_of(t, v, n) == (1, [1; 3]) {
                        if let Some(ts) = ts_out.as_mut() {
                            // From the smallest point on, as `refine` writes it.
                            ts[triangles as usize] = v.map(|id| I::from_index(vidx[id as usize]));
                        }
                        triangles += 1;
                        continue;
                    }
                }
                let face_base = next;
                let before = triangles;
                let mut faces = 0u32;
                view.refine(
                    t,
                    &mut |point| {
                        if let Some(vs) = vs_out.as_mut() {
                            self.queue_vertex(&mut batch, vs, face_base + faces, point, p);
                        }
                        faces += 1;
                    },
                    &mut |tri, _| {
                        if let Some(ts) = ts_out.as_mut() {
                            let index = |q: Point| -> u32 {
                                match q {
                                    Point::Node(n) => n,
                                    Point::Curve { curve, j, .. } => self.curve_index(curve, j),
                                    Point::Vertex { id, .. } => vidx[id as usize],
                                    Point::Edge { slot, edge, r, .. } => {
                                        ebase[3 * slot as usize + edge as usize] + r - 1
                                    }
                                    Point::Face { k, .. } => face_base + k,
                                }
                            };
                            ts[triangles as usize] = tri.map(|q| I::from_index(index(q)));
                        }
                        triangles += 1;
                    },
                );
                next += faces;
                // The walk and the closed form agree (which a count relies on).
                debug_assert!(
                    !every_piece || view.piece_counts(t) == (faces, triangles - before),
                    "patch {p} triangle {t}"
                );
            }
            if let Some(vs) = vs_out.as_mut() {
                self.flush_vertices(&mut batch, vs);
            }
            self.storage.patches[p].triangles = [first_triangle, triangles];
        }
        self.storage.scratch = scratch;
        Some(MeshCounts {
            vertices: next,
            triangles,
        })
    }

    /// Output index of place `j` on curve `curve` (`0` and the end are nodes).
    fn curve_index(&self, curve: u32, j: u32) -> u32 {
        let cs = self.storage.curves[curve as usize];
        let f = cs.factor.max(1) as u32;
        let end = (cs.count as u32 + 1) * f;
        if j == 0 || j >= end {
            // The curve's end points are corners of its owner.
            let (p, side) = (cs.owner as usize, cs.side);
            let k = match (side, j == 0) {
                (Side::V0, true) | (Side::U0, true) => 0,
                (Side::V0, false) | (Side::U1, true) => 1,
                (Side::U1, false) | (Side::V1, false) => 2,
                (Side::V1, true) | (Side::U0, false) => 3,
            };
            return self.storage.patches[p].nodes[k];
        }
        cs.base + j - 1
    }
}
