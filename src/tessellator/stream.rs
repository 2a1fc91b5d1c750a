//! Output as a stream of triangles: patch by patch, each triangle with its vertices, evaluated
//! as they come (a small cache spares most repeats), and with its corners' keys for a sink that
//! keeps corners of its own.

use super::patch_view::Point;
use super::Tessellator;
use crate::domain::DomainIndex;
use crate::sink::{TriangleInfo, TriangleSink, Vertex, NO_KEY};

/// Entries of the evaluated-point cache of [`Tessellator::stream_patch`].
const STREAM_CACHE: usize = 32;

/// A hash of a point's identity for the stream cache.
fn point_hash(q: &Point) -> u32 {
    let words = match *q {
        Point::Node(n) => [1, n, 0, 0],
        Point::Curve { curve, j, .. } => [2, curve, j, 0],
        Point::Vertex { id, .. } => [3, id as u32, 0, 0],
        Point::Edge { slot, edge, r, .. } => [4, slot, edge as u32, r],
        Point::Face { u, v, den, .. } => [5, u, v, den],
    };
    words
        .iter()
        .fold(0x811c_9dc5u32, |h, &w| (h ^ w).wrapping_mul(0x0100_0193))
        ^ (words[1] >> 7)
}

impl<Ix: DomainIndex> Tessellator<'_, '_, Ix> {
    /// Hands every triangle of the frame, with its vertices, to `sink`, in the order of
    /// [`write_mesh`](Self::write_mesh)'s triangles (patch by patch, leaving out the patches
    /// the sink does not [want](TriangleSink::wants_patch)).
    pub fn stream(&self, sink: &mut impl TriangleSink) {
        for p in 0..self.baked.patch_count() {
            if sink.wants_patch(p as u32) {
                self.stream_patch(p, sink);
            }
        }
    }

    /// Like [`stream`](Self::stream), also passing each triangle's [`TriangleInfo`]: its own
    /// patch's parameters at the corners and its deviation bound.
    pub fn stream_with_info(&self, mut f: impl FnMut(&TriangleInfo, [&Vertex; 3])) {
        for p in 0..self.baked.patch_count() {
            self.stream_patch_with_info(p, &mut f);
        }
    }

    /// Hands patch `p`'s triangles of the frame to `sink` (nothing when it is culled or out
    /// of range), in the order [`stream`](Self::stream) gives them, with their corners' keys
    /// ([`TriangleSink::keyed_triangle`]). A renderer that draws in bands uses it, with
    /// [`patch_bound`](Self::patch_bound), to skip patches off a band.
    pub fn stream_patch(&self, p: usize, sink: &mut impl TriangleSink) {
        self.stream_patch_keyed::<STREAM_CACHE>(p, |info, keys, corner| {
            sink.keyed_triangle(info.patch, keys, corner)
        });
    }

    /// [`stream_patch`](Self::stream_patch) for a sink that keeps the corners it asks for by
    /// their keys (the renderer's): the stream keeps no evaluated points of its own, and takes
    /// that much less stack.
    #[cfg(feature = "embedded-graphics")]
    pub(crate) fn stream_patch_to_keeper(&self, p: usize, sink: &mut dyn TriangleSink) {
        self.stream_patch_keyed::<0>(p, |info, keys, corner| {
            sink.keyed_triangle(info.patch, keys, corner)
        });
    }

    fn stream_patch_with_info(&self, p: usize, mut f: impl FnMut(&TriangleInfo, [&Vertex; 3])) {
        self.stream_patch_keyed::<STREAM_CACHE>(p, |info, _, corner| {
            let [a, b, c] = [0, 1, 2].map(corner);
            f(info, [&a, &b, &c]);
        });
    }

    /// The traversal behind the streams: each triangle's information, its corners' keys, and
    /// a function that evaluates a corner (through a cache of `CACHE` points).
    fn stream_patch_keyed<const CACHE: usize>(
        &self,
        p: usize,
        mut f: impl FnMut(&TriangleInfo, [u64; 3], &mut dyn FnMut(usize) -> Vertex),
    ) {
        let Some(view) = self.output_view(p) else {
            return;
        };
        // Neighbouring triangles share corners: a small direct-mapped cache of evaluated
        // points saves most evaluations. Entries are named by the points' keys (equal keys,
        // equal data: see `PatchView::key`), kept apart from the data so that no entry pads.
        let mut keys = [NO_KEY; CACHE];
        let mut data = [Vertex::default(); CACHE];
        let vo = view.vo;
        let mut vertex = |q: Point, key: u64| -> Vertex {
            if let Point::Vertex { id, p: g } = q {
                if let Some(v) = self.cached_vertex(p, vo + id as usize, g) {
                    return v;
                }
            }
            if CACHE == 0 {
                return self.vertex_data(q, p);
            }
            let k = point_hash(&q) as usize % CACHE;
            if keys[k] != key {
                keys[k] = key;
                data[k] = self.vertex_data(q, p);
            }
            data[k]
        };
        for t in 0..view.tc {
            if view.hidden(t) {
                continue;
            }
            let bound = view.state(t).pieces;
            view.refine(t, &mut |_| {}, &mut |tri, local| {
                let info = TriangleInfo {
                    patch: p as u32,
                    uv: local.map(|[u, v, d]| [u as f32 / d as f32, v as f32 / d as f32]),
                    bound,
                };
                let keys = tri.map(|q| view.key(t, q));
                f(&info, keys, &mut |i| vertex(tri[i % 3], keys[i % 3]));
            });
        }
    }
}
