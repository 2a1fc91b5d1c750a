//! The domain triangulation: a fixed-capacity Delaunay triangulation of a patch's (u,v) square
//! with insertion and deletion, shared by the bake and the run time.
//!
//! Points live on a 16-bit grid ([`GridPoint`]), so every decision is an exact integer
//! predicate: orientation in `i64`, the in-circle test in `i128`. Ties (four cocircular points,
//! which uniform grids produce everywhere) are broken by *simulation of simplicity*: each point's
//! lift onto the paraboloid is raised by an infinitesimal that ranks the points by their
//! coordinates. The triangulation is then the unique regular triangulation of the lifted points,
//! so the same point set gives the same triangles whatever the order of insertions and
//! deletions (host-tests check this against fresh builds).
//!
//! Insertion splits the triangle (or edge) holding the point and flips edges until they are
//! Delaunay (Lawson); deletion flips "Delaunay ears" off the vertex's link until it has three
//! triangles (two on the boundary) and merges them (Devillers). Both work in place, with no
//! memory beyond the mesh whatever the vertex degrees, and check every capacity first: on an
//! error the mesh is unchanged.
//!
//! The four corners are vertices 0 to 3, `(0,0), (1,0), (1,1), (0,1)`, and cannot be removed.
//! Points on the square's edges are boundary vertices: a triangulation with `b` of them
//! (corners included) and `n` interior vertices has `2n + b - 2` triangles.

mod compact;
mod error;
mod grid;
mod index;
mod insert;
mod predicates;
mod remove;
mod slots;

pub use error::{InsertError, MeshStorageError, RemoveError};
pub use grid::GridPoint;
pub use index::DomainIndex;
use predicates::in_circle;
pub(crate) use predicates::orient;
pub use predicates::Metric;
pub use slots::{MeshTriangle, MeshVertex};

/// An edge on the rim of a hole: `(from, to)` counter-clockwise around it, and
/// the triangle outside it (or `Ix::NO_SLOT` on the square's boundary).
type RimEdge = (u16, u16, u16);

/// The state of a [`DomainMesh`] besides its slots (the run time keeps one per patch).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct MeshHeader {
    free_vertex: u16,
    free_triangle: u16,
    vertex_count: u16,
    triangle_count: u16,
    hint: u16,
    metric: Metric,
}

impl MeshHeader {
    /// The metric of the mesh this header describes.
    pub(crate) fn metric(&self) -> Metric {
        self.metric
    }

    /// Live vertices of the mesh this header describes.
    pub(crate) fn vertex_count(&self) -> u16 {
        self.vertex_count
    }

    /// Live triangles of the mesh this header describes.
    pub(crate) fn triangle_count(&self) -> usize {
        self.triangle_count as usize
    }
}

/// A Delaunay triangulation of the unit square in caller storage.
///
/// ```
/// use spline_tess::{DomainMesh, GridPoint, MeshTriangle, MeshVertex};
///
/// let mut vertices = [MeshVertex::default(); 16];
/// let mut triangles = [MeshTriangle::default(); 32];
/// let mut mesh = DomainMesh::new(&mut vertices, &mut triangles).unwrap();
/// assert_eq!(mesh.triangle_count(), 2);
///
/// let centre = mesh.insert(GridPoint::from_unit(0.5, 0.5)).unwrap();
/// let edge = mesh.insert(GridPoint::from_unit(0.5, 0.0)).unwrap();
/// // 1 interior and 5 boundary vertices: 2 * 1 + 5 - 2 triangles.
/// assert_eq!(mesh.triangle_count(), 5);
/// mesh.remove(edge).unwrap();
/// mesh.remove(centre).unwrap();
/// assert_eq!(mesh.triangle_count(), 2);
/// ```
#[derive(Debug)]
pub struct DomainMesh<'a, Ix: DomainIndex = u16> {
    vertices: &'a mut [MeshVertex<Ix>],
    triangles: &'a mut [MeshTriangle<Ix>],
    free_vertex: u16,
    free_triangle: u16,
    vertex_count: usize,
    triangle_count: usize,
    hint: u16,
    metric: Metric,
}

impl<'a> DomainMesh<'a> {
    /// The two triangles of the square, in the given storage (its contents are overwritten),
    /// with the [`Metric::ISOTROPIC`] Delaunay test.
    pub fn new(
        vertices: &'a mut [MeshVertex],
        triangles: &'a mut [MeshTriangle],
    ) -> Result<Self, MeshStorageError> {
        Self::with_metric(vertices, triangles, Metric::ISOTROPIC)
    }

    /// Like [`DomainMesh::new`], with circles taken in `metric`'s coordinates. (For slots
    /// of another index type, see [`DomainMesh::indexed`].)
    pub fn with_metric(
        vertices: &'a mut [MeshVertex],
        triangles: &'a mut [MeshTriangle],
        metric: Metric,
    ) -> Result<Self, MeshStorageError> {
        Self::indexed(vertices, triangles, metric)
    }

    /// Triangle slots enough for `vertices` vertex slots: `2 * vertices - 6` (at least 2),
    /// whatever the index type.
    pub const fn triangles_for(vertices: usize) -> usize {
        if vertices < 4 {
            2
        } else {
            2 * vertices - 6
        }
    }
}

impl<'a, Ix: DomainIndex> DomainMesh<'a, Ix> {
    /// The mesh's own state besides its slots, to rebuild it later over the same storage.
    pub(crate) fn header(&self) -> MeshHeader {
        MeshHeader {
            free_vertex: self.free_vertex,
            free_triangle: self.free_triangle,
            vertex_count: self.vertex_count as u16,
            triangle_count: self.triangle_count as u16,
            hint: self.hint,
            metric: self.metric,
        }
    }

    /// The mesh whose slots are `vertices` and `triangles` and whose state is `header` (as
    /// saved by [`DomainMesh::header`] over the same slots).
    pub(crate) fn resume(
        vertices: &'a mut [MeshVertex<Ix>],
        triangles: &'a mut [MeshTriangle<Ix>],
        header: MeshHeader,
    ) -> Self {
        DomainMesh {
            vertices,
            triangles,
            free_vertex: header.free_vertex,
            free_triangle: header.free_triangle,
            vertex_count: header.vertex_count as usize,
            triangle_count: header.triangle_count as usize,
            hint: header.hint,
            metric: header.metric,
        }
    }

    /// Like [`DomainMesh::with_metric`], over slots indexed by any [`DomainIndex`] (`u8`
    /// slots take half the bytes per triangle, for at most 255 slots of each kind).
    pub fn indexed(
        vertices: &'a mut [MeshVertex<Ix>],
        triangles: &'a mut [MeshTriangle<Ix>],
        metric: Metric,
    ) -> Result<Self, MeshStorageError> {
        if vertices.len() < 4 || triangles.len() < 2 {
            return Err(MeshStorageError::TooSmall);
        }
        if vertices.len() > Ix::MAX_SLOTS || triangles.len() > Ix::MAX_SLOTS {
            return Err(MeshStorageError::TooLarge);
        }
        let m = GridPoint::MAX;
        let corners = [
            GridPoint::new(0, 0),
            GridPoint::new(m, 0),
            GridPoint::new(m, m),
            GridPoint::new(0, m),
        ];
        let mut mesh = DomainMesh {
            vertices,
            triangles,
            free_vertex: 0,
            free_triangle: 0,
            vertex_count: 0,
            triangle_count: 0,
            hint: 0,
            metric,
        };
        // Every slot free (no live ones before them).
        mesh.chain_free_slots();
        for c in corners {
            mesh.take_vertex(c);
        }
        // The corners are cocircular: the tie-break picks the diagonal. (Each triangle
        // starts at its smallest point, as `set` writes them.)
        let [a, b, c, d] = corners;
        let (t0, t1) = (mesh.take_triangle(), mesh.take_triangle());
        let (v0, v1) = if in_circle(mesh.metric, a, b, c, d) {
            ([0, 1, 3], [3, 1, 2])
        } else {
            ([0, 1, 2], [0, 2, 3])
        };
        mesh.put(
            t0,
            MeshTriangle {
                v: v0,
                n: [Ix::NO_SLOT; 3],
            },
        );
        mesh.put(
            t1,
            MeshTriangle {
                v: v1,
                n: [Ix::NO_SLOT; 3],
            },
        );
        let rim: [RimEdge; 4] = [
            (0, 1, Ix::NO_SLOT),
            (1, 2, Ix::NO_SLOT),
            (2, 3, Ix::NO_SLOT),
            (3, 0, Ix::NO_SLOT),
        ];
        mesh.stitch(&[t0, t1], &rim);
        Ok(mesh)
    }

    /// The metric of the Delaunay test.
    pub fn metric(&self) -> Metric {
        self.metric
    }

    /// Live vertices.
    pub fn vertex_count(&self) -> usize {
        self.vertex_count
    }

    /// Live triangles.
    pub fn triangle_count(&self) -> usize {
        self.triangle_count
    }

    /// The point of vertex `id`, or `None` if it is not live.
    pub fn point(&self, id: u16) -> Option<GridPoint> {
        let v = self.vertices.get(id as usize)?;
        v.live_point()
    }

    /// Live vertices with their points.
    pub fn vertices(&self) -> impl Iterator<Item = (u16, GridPoint)> + '_ {
        self.vertices
            .iter()
            .enumerate()
            .filter(|(_, v)| v.is_live())
            .map(|(k, v)| (k as u16, v.point()))
    }

    /// Live triangles as counter-clockwise vertex triples, each starting at its smallest point
    /// in `(u, v)` order: a triangle's corner order depends on its points alone, not on the
    /// history of the mesh.
    pub fn triangles(&self) -> impl Iterator<Item = [u16; 3]> + '_ {
        self.triangles
            .iter()
            .filter(|t| t.is_live())
            .map(|t| t.widen().v)
    }

    /// Live triangles with, for each, the triangle across the edge opposite each vertex
    /// (`None` on the square's boundary), keyed by slot.
    pub fn triangles_with_neighbors(
        &self,
    ) -> impl Iterator<Item = (u16, [u16; 3], [Option<u16>; 3])> + '_ {
        self.triangles
            .iter()
            .enumerate()
            .filter(|(_, t)| t.is_live())
            .map(|(k, t)| {
                let t = t.widen();
                (k as u16, t.v, t.n.map(|n| (n != Ix::NO_SLOT).then_some(n)))
            })
    }

    /// Vertex slots, live or free.
    pub fn vertex_capacity(&self) -> usize {
        self.vertices.len()
    }

    /// Triangle slots, live or free: the bound of the slot numbers [`DomainMesh::triangle`]
    /// and [`DomainMesh::star`] use.
    pub fn triangle_capacity(&self) -> usize {
        self.triangles.len()
    }

    /// The counter-clockwise vertices of the triangle in slot `slot`, or `None` if it is free.
    pub fn triangle(&self, slot: u16) -> Option<[u16; 3]> {
        let t = self.triangles.get(slot as usize)?;
        t.is_live().then(|| t.widen().v)
    }

    /// The slots of the triangles around vertex `id`, counter-clockwise (empty if `id` is not
    /// live). After an insertion these are exactly the triangles it created.
    pub fn star(&self, id: u16) -> Star<'_, 'a, Ix> {
        let start = match self.vertices.get(id as usize) {
            Some(v) if v.is_live() => self.star_start(id),
            _ => Ix::NO_SLOT,
        };
        Star {
            mesh: self,
            id,
            start,
            next: start,
            steps: 0,
        }
    }

    /// The first triangle of `id`'s star in counter-clockwise order: for a boundary vertex the
    /// one whose clockwise neighbour is outside the square, else the incident triangle.
    fn star_start(&self, id: u16) -> u16 {
        let first = self.link(id);
        let mut t = first;
        for _ in 0..=self.triangles.len() {
            let tri = self.tri(t);
            let i = index_of(&tri.v, id);
            // Clockwise: across the edge (id, v[i+1]), opposite v[i+2].
            let cw = tri.n[before(i)];
            if cw == Ix::NO_SLOT || cw == first {
                break;
            }
            t = cw;
        }
        t
    }

    /// The corners of a live triangle that holds `p` (inside or on its boundary).
    pub(crate) fn holding(&self, p: GridPoint) -> [GridPoint; 3] {
        self.tri_points(self.locate(p))
    }

    /// The vertex at `p`, if any.
    pub fn find(&self, p: GridPoint) -> Option<u16> {
        let t = self.locate(p);
        self.tri(t)
            .v
            .into_iter()
            .find(|&v| self.vertices[v as usize].point() == p)
    }

    fn pt(&self, v: u16) -> GridPoint {
        self.vertices[v as usize].point()
    }

    fn tri_points(&self, t: u16) -> [GridPoint; 3] {
        self.tri(t).v.map(|v| self.pt(v))
    }

    /// Triangle slot `t`, with `u16` slot numbers.
    #[inline(always)]
    fn tri(&self, t: u16) -> MeshTriangle {
        self.triangles[t as usize].widen()
    }

    /// Writes triangle slot `t`.
    #[inline(always)]
    fn put(&mut self, t: u16, tri: MeshTriangle) {
        self.triangles[t as usize] = MeshTriangle::narrow(tri);
    }

    /// The triangle live vertex `v` links to.
    #[inline(always)]
    fn link(&self, v: u16) -> u16 {
        let link = self.vertices[v as usize].link;
        link.widen()
    }

    /// Links live vertex `v` to its triangle `t`.
    #[inline(always)]
    fn set_link(&mut self, v: u16, t: u16) {
        self.vertices[v as usize].link = Ix::narrow(t);
    }

    /// Chains the slots after the live counts as the free lists (the live ones come first).
    fn chain_free_slots(&mut self) {
        let (nv, nt) = (self.vertex_count, self.triangle_count);
        let last = self.vertices.len();
        for (k, slot) in self.vertices.iter_mut().enumerate().skip(nv) {
            *slot = MeshVertex::free(if k + 1 < last {
                k as u16 + 1
            } else {
                Ix::NO_SLOT
            });
        }
        self.free_vertex = if nv < last { nv as u16 } else { Ix::NO_SLOT };
        let last = self.triangles.len();
        for (k, slot) in self.triangles.iter_mut().enumerate().skip(nt) {
            *slot = MeshTriangle::free(if k + 1 < last {
                k as u16 + 1
            } else {
                Ix::NO_SLOT
            });
        }
        self.free_triangle = if nt < last { nt as u16 } else { Ix::NO_SLOT };
        self.hint = 0;
    }

    fn take_vertex(&mut self, p: GridPoint) -> u16 {
        let id = self.free_vertex;
        let slot = &mut self.vertices[id as usize];
        self.free_vertex = slot.point().u;
        // Live from here; the split that follows links it to a triangle of its own.
        *slot = MeshVertex::new(p, 0);
        self.vertex_count += 1;
        id
    }

    fn take_triangle(&mut self) -> u16 {
        let id = self.free_triangle;
        let slot = &mut self.triangles[id as usize];
        self.free_triangle = slot.n[0].widen();
        // Free (its vertices `Ix::NO_SLOT`) until the caller sets them, right after.
        *slot = MeshTriangle::default();
        self.triangle_count += 1;
        id
    }

    fn free_triangle(&mut self, t: u16) {
        self.triangles[t as usize] = MeshTriangle::free(self.free_triangle);
        self.free_triangle = t;
        self.triangle_count -= 1;
    }
}

/// The triangles around a vertex, counter-clockwise: see [`DomainMesh::star`].
#[derive(Debug)]
pub struct Star<'m, 'a, Ix: DomainIndex = u16> {
    mesh: &'m DomainMesh<'a, Ix>,
    id: u16,
    start: u16,
    next: u16,
    steps: usize,
}

impl<Ix: DomainIndex> Iterator for Star<'_, '_, Ix> {
    type Item = u16;

    fn next(&mut self) -> Option<u16> {
        // The step bound only guards against a corrupted mesh turning into a hang.
        if self.next == Ix::NO_SLOT || self.steps > self.mesh.triangles.len() {
            return None;
        }
        let t = self.next;
        let tri = self.mesh.tri(t);
        let i = index_of(&tri.v, self.id);
        // Counter-clockwise: across the edge (v[i+2], id), opposite v[i+1].
        let ccw = tri.n[after(i)];
        self.next = if ccw == self.start { Ix::NO_SLOT } else { ccw };
        self.steps += 1;
        Some(t)
    }
}

/// The index of `id` in `v` (0 when it is not there).
#[inline]
fn index_of(v: &[u16; 3], id: u16) -> usize {
    if v[1] == id {
        1
    } else if v[2] == id {
        2
    } else {
        0
    }
}

/// The index after `i` in counter-clockwise order: `after(i)`.
#[inline]
fn after(i: usize) -> usize {
    if i >= 2 {
        0
    } else {
        i + 1
    }
}

/// The index before `i` in counter-clockwise order: `before(i)`.
#[inline]
fn before(i: usize) -> usize {
    if i == 0 {
        2
    } else {
        i - 1
    }
}
