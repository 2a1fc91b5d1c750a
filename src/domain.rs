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
//! Insertion is Bowyer-Watson (remove the triangles whose circumcircle holds the point, fan the
//! cavity); deletion clips "Delaunay ears" off the deleted vertex's link polygon (Devillers). Both
//! first check every capacity, and on an error the mesh is unchanged.
//!
//! The four corners are vertices 0 to 3, `(0,0), (1,0), (1,1), (0,1)`, and cannot be removed.
//! Points on the square's edges are boundary vertices: a triangulation with `b` of them
//! (corners included) and `n` interior vertices has `2n + b - 2` triangles.

use core::fmt;

/// Coordinates on the 16-bit parameter grid: `0` is parameter 0, [`GridPoint::MAX`] is 1.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct GridPoint {
    /// u on the grid.
    pub u: u16,
    /// v on the grid.
    pub v: u16,
}

impl GridPoint {
    /// The grid value of parameter 1.
    pub const MAX: u16 = u16::MAX;

    /// A point from grid coordinates.
    pub const fn new(u: u16, v: u16) -> Self {
        GridPoint { u, v }
    }

    /// The nearest grid point to parameters `(u, v)`, clamped into `[0, 1]` (NaN counts as 0).
    pub fn from_unit(u: f32, v: f32) -> Self {
        let q = |t: f32| {
            let t = crate::math::clamp_param(t, 0.0, 1.0);
            // t in [0, 1], so the product is in [0, 65535.5) and the cast is exact after floor.
            libm::floorf(t * Self::MAX as f32 + 0.5) as u16
        };
        GridPoint { u: q(u), v: q(v) }
    }

    /// The parameters `(u, v)` of this grid point.
    pub fn to_unit(self) -> (f32, f32) {
        let s = 1.0 / Self::MAX as f32;
        (self.u as f32 * s, self.v as f32 * s)
    }

    /// True when the point lies on the square's boundary.
    pub fn on_boundary(self) -> bool {
        self.u == 0 || self.v == 0 || self.u == Self::MAX || self.v == Self::MAX
    }
}

/// "No vertex / no triangle" in index fields.
const NONE: u16 = u16::MAX;

/// Most triangles a single insertion may replace (and link edges a deletion may re-fill).
/// Delaunay cavities and stars of well-spread samples hold a handful; 64 bounds the stack use.
pub const STAR_CAPACITY: usize = 64;

/// Twice the signed area of `abc`: positive when counter-clockwise.
#[inline]
fn orient(a: GridPoint, b: GridPoint, c: GridPoint) -> i64 {
    let (ax, ay) = (a.u as i64, a.v as i64);
    (b.u as i64 - ax) * (c.v as i64 - ay) - (b.v as i64 - ay) * (c.u as i64 - ax)
}

/// True when `d` lies inside the circumcircle of the counter-clockwise triangle `abc`, with ties
/// broken by simulation of simplicity (the largest point in `(u, v)` order is perturbed most).
fn in_circle(a: GridPoint, b: GridPoint, c: GridPoint, d: GridPoint) -> bool {
    let dx = |p: GridPoint| p.u as i64 - d.u as i64;
    let dy = |p: GridPoint| p.v as i64 - d.v as i64;
    let (adx, ady, bdx, bdy, cdx, cdy) = (dx(a), dy(a), dx(b), dy(b), dx(c), dy(c));
    let lift = |x: i64, y: i64| (x * x + y * y) as i128;
    let det = lift(adx, ady) * (bdx * cdy - bdy * cdx) as i128
        + lift(bdx, bdy) * (cdx * ady - cdy * adx) as i128
        + lift(cdx, cdy) * (adx * bdy - ady * bdx) as i128;
    if det != 0 {
        return det > 0;
    }
    // Raising p's lift by eps_p adds eps_p times p's cofactor; the largest point's term wins.
    // Its cofactor is the orientation of the other three, which are distinct points on one
    // circle and so never collinear.
    let top = a.max(b).max(c).max(d);
    let term = if top == a {
        orient(d, b, c)
    } else if top == b {
        orient(d, c, a)
    } else if top == c {
        orient(d, a, b)
    } else {
        -orient(a, b, c)
    };
    term > 0
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
/// One vertex slot of a [`DomainMesh`].
pub struct MeshVertex {
    point: GridPoint,
    /// An incident triangle; for a free slot, the next free slot.
    link: u16,
    alive: bool,
}

impl Default for MeshVertex {
    fn default() -> Self {
        MeshVertex {
            point: GridPoint::default(),
            link: NONE,
            alive: false,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
/// One triangle slot of a [`DomainMesh`].
pub struct MeshTriangle {
    /// Vertices, counter-clockwise.
    v: [u16; 3],
    /// `n[i]`: the triangle across the edge opposite `v[i]`; for a free slot `n[0]` is the
    /// next free slot.
    n: [u16; 3],
    alive: bool,
}

impl Default for MeshTriangle {
    fn default() -> Self {
        MeshTriangle {
            v: [NONE; 3],
            n: [NONE; 3],
            alive: false,
        }
    }
}

/// Why storage cannot hold a [`DomainMesh`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum MeshStorageError {
    /// Fewer than 4 vertex slots or 2 triangle slots.
    TooSmall,
    /// More than 65535 slots of either kind (indices are `u16`).
    TooLarge,
}

/// Why a point could not be inserted. The mesh is unchanged.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum InsertError {
    /// A vertex already has these coordinates.
    Duplicate {
        /// The existing vertex.
        vertex: u16,
    },
    /// Every vertex slot is in use.
    VerticesFull,
    /// Too few free triangle slots.
    TrianglesFull {
        /// Free slots the insertion needs.
        needed: usize,
    },
    /// The insertion would replace more than [`STAR_CAPACITY`] triangles.
    CavityTooLarge,
}

/// Why a vertex could not be removed. The mesh is unchanged.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum RemoveError {
    /// The four corners stay.
    Corner,
    /// No live vertex has this index.
    NotAVertex,
    /// The vertex has more than [`STAR_CAPACITY`] neighbours.
    StarTooLarge,
}

impl fmt::Display for MeshStorageError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            MeshStorageError::TooSmall => "mesh storage needs 4 vertex and 2 triangle slots",
            MeshStorageError::TooLarge => "mesh storage is limited to 65535 slots of each kind",
        })
    }
}

impl fmt::Display for InsertError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            InsertError::Duplicate { vertex } => write!(f, "vertex {vertex} is already there"),
            InsertError::VerticesFull => f.write_str("no free vertex slot"),
            InsertError::TrianglesFull { needed } => {
                write!(f, "needs {needed} free triangle slots")
            }
            InsertError::CavityTooLarge => {
                write!(f, "would replace more than {STAR_CAPACITY} triangles")
            }
        }
    }
}

impl fmt::Display for RemoveError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            RemoveError::Corner => "the corners cannot be removed",
            RemoveError::NotAVertex => "no such vertex",
            RemoveError::StarTooLarge => "vertex has too many neighbours to remove",
        })
    }
}

impl core::error::Error for MeshStorageError {}
impl core::error::Error for InsertError {}
impl core::error::Error for RemoveError {}

/// An edge on the rim of a cavity or star: `(from, to)` counter-clockwise around the hole, and
/// the triangle outside it (or `NONE` on the square's boundary).
type RimEdge = (u16, u16, u16);

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
pub struct DomainMesh<'a> {
    vertices: &'a mut [MeshVertex],
    triangles: &'a mut [MeshTriangle],
    free_vertex: u16,
    free_triangle: u16,
    vertex_count: usize,
    triangle_count: usize,
    hint: u16,
}

impl<'a> DomainMesh<'a> {
    /// Triangle slots enough for `vertices` vertex slots: `2 * vertices - 6` (at least 2).
    pub const fn triangles_for(vertices: usize) -> usize {
        if vertices < 4 {
            2
        } else {
            2 * vertices - 6
        }
    }

    /// The two triangles of the square, in the given storage (its contents are overwritten).
    pub fn new(
        vertices: &'a mut [MeshVertex],
        triangles: &'a mut [MeshTriangle],
    ) -> Result<Self, MeshStorageError> {
        if vertices.len() < 4 || triangles.len() < 2 {
            return Err(MeshStorageError::TooSmall);
        }
        if vertices.len() > NONE as usize || triangles.len() > NONE as usize {
            return Err(MeshStorageError::TooLarge);
        }
        let m = GridPoint::MAX;
        let corners = [
            GridPoint::new(0, 0),
            GridPoint::new(m, 0),
            GridPoint::new(m, m),
            GridPoint::new(0, m),
        ];
        let (nv, nt) = (vertices.len(), triangles.len());
        for (k, slot) in vertices.iter_mut().enumerate() {
            *slot = MeshVertex::default();
            slot.link = if k + 1 < nv { k as u16 + 1 } else { NONE };
        }
        for (k, slot) in triangles.iter_mut().enumerate() {
            *slot = MeshTriangle::default();
            slot.n[0] = if k + 1 < nt { k as u16 + 1 } else { NONE };
        }
        let mut mesh = DomainMesh {
            vertices,
            triangles,
            free_vertex: 0,
            free_triangle: 0,
            vertex_count: 0,
            triangle_count: 0,
            hint: 0,
        };
        for c in corners {
            mesh.take_vertex(c);
        }
        // The corners are cocircular: the tie-break picks the diagonal.
        let [a, b, c, d] = corners;
        let (t0, t1) = (mesh.take_triangle(), mesh.take_triangle());
        if in_circle(a, b, c, d) {
            mesh.triangles[t0 as usize].v = [0, 1, 3];
            mesh.triangles[t1 as usize].v = [1, 2, 3];
        } else {
            mesh.triangles[t0 as usize].v = [0, 1, 2];
            mesh.triangles[t1 as usize].v = [0, 2, 3];
        }
        let rim: [RimEdge; 4] = [(0, 1, NONE), (1, 2, NONE), (2, 3, NONE), (3, 0, NONE)];
        mesh.stitch(&[t0, t1], &rim);
        Ok(mesh)
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
        v.alive.then_some(v.point)
    }

    /// Live vertices with their points.
    pub fn vertices(&self) -> impl Iterator<Item = (u16, GridPoint)> + '_ {
        self.vertices
            .iter()
            .enumerate()
            .filter(|(_, v)| v.alive)
            .map(|(k, v)| (k as u16, v.point))
    }

    /// Live triangles as counter-clockwise vertex triples.
    pub fn triangles(&self) -> impl Iterator<Item = [u16; 3]> + '_ {
        self.triangles.iter().filter(|t| t.alive).map(|t| t.v)
    }

    /// Live triangles with, for each, the triangle across the edge opposite each vertex
    /// (`None` on the square's boundary), keyed by slot.
    pub fn triangles_with_neighbors(
        &self,
    ) -> impl Iterator<Item = (u16, [u16; 3], [Option<u16>; 3])> + '_ {
        self.triangles
            .iter()
            .enumerate()
            .filter(|(_, t)| t.alive)
            .map(|(k, t)| (k as u16, t.v, t.n.map(|n| (n != NONE).then_some(n))))
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
        t.alive.then_some(t.v)
    }

    /// The slots of the triangles around vertex `id`, counter-clockwise (empty if `id` is not
    /// live). After an insertion these are exactly the triangles it created.
    pub fn star(&self, id: u16) -> Star<'_, 'a> {
        let start = match self.vertices.get(id as usize) {
            Some(v) if v.alive => self.star_start(id),
            _ => NONE,
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
        let first = self.vertices[id as usize].link;
        let mut t = first;
        for _ in 0..=STAR_CAPACITY {
            let tri = self.triangles[t as usize];
            let i = index_of(&tri.v, id);
            // Clockwise: across the edge (id, v[i+1]), opposite v[i+2].
            let cw = tri.n[(i + 2) % 3];
            if cw == NONE || cw == first {
                break;
            }
            t = cw;
        }
        t
    }

    /// The vertex at `p`, if any.
    pub fn find(&self, p: GridPoint) -> Option<u16> {
        let t = self.locate(p);
        self.triangles[t as usize]
            .v
            .into_iter()
            .find(|&v| self.vertices[v as usize].point == p)
    }

    fn pt(&self, v: u16) -> GridPoint {
        self.vertices[v as usize].point
    }

    fn tri_points(&self, t: u16) -> [GridPoint; 3] {
        self.triangles[t as usize].v.map(|v| self.pt(v))
    }

    fn take_vertex(&mut self, p: GridPoint) -> u16 {
        let id = self.free_vertex;
        let slot = &mut self.vertices[id as usize];
        self.free_vertex = slot.link;
        *slot = MeshVertex {
            point: p,
            link: NONE,
            alive: true,
        };
        self.vertex_count += 1;
        id
    }

    fn take_triangle(&mut self) -> u16 {
        let id = self.free_triangle;
        let slot = &mut self.triangles[id as usize];
        self.free_triangle = slot.n[0];
        *slot = MeshTriangle {
            v: [NONE; 3],
            n: [NONE; 3],
            alive: true,
        };
        self.triangle_count += 1;
        id
    }

    fn free_triangle(&mut self, t: u16) {
        self.triangles[t as usize] = MeshTriangle {
            v: [NONE; 3],
            n: [self.free_triangle, NONE, NONE],
            alive: false,
        };
        self.free_triangle = t;
        self.triangle_count -= 1;
    }

    /// A live triangle containing `p` (inside or on its boundary).
    fn locate(&self, p: GridPoint) -> u16 {
        let mut t = self.hint;
        if !self.triangles.get(t as usize).is_some_and(|x| x.alive) {
            t = self.first_live_triangle();
        }
        // A visibility walk terminates in a Delaunay triangulation; the bound only guards
        // against a bug turning into a hang, with a scan as the fallback.
        for _ in 0..self.triangles.len() + 4 {
            let [a, b, c] = self.tri_points(t);
            let n = self.triangles[t as usize].n;
            let next = if orient(b, c, p) < 0 {
                n[0]
            } else if orient(c, a, p) < 0 {
                n[1]
            } else if orient(a, b, p) < 0 {
                n[2]
            } else {
                return t;
            };
            if next == NONE {
                break;
            }
            t = next;
        }
        self.scan_for(p)
    }

    fn first_live_triangle(&self) -> u16 {
        self.triangles.iter().position(|t| t.alive).unwrap_or(0) as u16
    }

    fn scan_for(&self, p: GridPoint) -> u16 {
        (0..self.triangles.len() as u16)
            .find(|&t| {
                self.triangles[t as usize].alive && {
                    let [a, b, c] = self.tri_points(t);
                    orient(b, c, p) >= 0 && orient(c, a, p) >= 0 && orient(a, b, p) >= 0
                }
            })
            .unwrap_or_else(|| self.first_live_triangle())
    }

    /// Inserts `p`; returns its vertex index.
    pub fn insert(&mut self, p: GridPoint) -> Result<u16, InsertError> {
        let start = self.locate(p);
        if let Some(vertex) = self.triangles[start as usize]
            .v
            .into_iter()
            .find(|&v| self.pt(v) == p)
        {
            return Err(InsertError::Duplicate { vertex });
        }
        if self.free_vertex == NONE {
            return Err(InsertError::VerticesFull);
        }
        // The cavity: triangles whose circumcircle holds p, grown from the one containing it.
        let mut cavity = [NONE; STAR_CAPACITY];
        cavity[0] = start;
        let mut len = 1;
        let mut k = 0;
        while k < len {
            let t = cavity[k];
            for nb in self.triangles[t as usize].n {
                if nb == NONE || cavity[..len].contains(&nb) {
                    continue;
                }
                let [a, b, c] = self.tri_points(nb);
                if in_circle(a, b, c, p) {
                    if len == STAR_CAPACITY {
                        return Err(InsertError::CavityTooLarge);
                    }
                    cavity[len] = nb;
                    len += 1;
                }
            }
            k += 1;
        }
        // Its rim, counter-clockwise around p; a boundary edge through p is split, not fanned.
        let mut rim = [(NONE, NONE, NONE); STAR_CAPACITY + 2];
        let mut rim_len = 0;
        for &t in &cavity[..len] {
            let tri = self.triangles[t as usize];
            for i in 0..3 {
                let nb = tri.n[i];
                if nb != NONE && cavity[..len].contains(&nb) {
                    continue;
                }
                let (a, b) = (tri.v[(i + 1) % 3], tri.v[(i + 2) % 3]);
                if nb == NONE && orient(self.pt(a), self.pt(b), p) == 0 {
                    // p lies on this boundary edge: it becomes the edges a-p and p-b.
                    continue;
                }
                if rim_len == rim.len() {
                    return Err(InsertError::CavityTooLarge);
                }
                rim[rim_len] = (a, b, nb);
                rim_len += 1;
            }
        }
        let free = self.triangles.len() - self.triangle_count;
        if rim_len > len && rim_len - len > free {
            return Err(InsertError::TrianglesFull {
                needed: rim_len - len,
            });
        }
        // Commit: free the cavity, fan the rim from p.
        for &t in &cavity[..len] {
            self.free_triangle(t);
        }
        let id = self.take_vertex(p);
        let mut fan = [NONE; STAR_CAPACITY + 2];
        for (slot, &(a, b, _)) in fan.iter_mut().zip(&rim[..rim_len]) {
            let t = self.take_triangle();
            self.triangles[t as usize].v = [id, a, b];
            *slot = t;
        }
        self.stitch(&fan[..rim_len], &rim[..rim_len]);
        self.hint = fan[0];
        Ok(id)
    }

    /// Removes vertex `id` and re-triangulates the hole.
    pub fn remove(&mut self, id: u16) -> Result<(), RemoveError> {
        if id < 4 {
            return Err(RemoveError::Corner);
        }
        if !self.vertices.get(id as usize).is_some_and(|v| v.alive) {
            return Err(RemoveError::NotAVertex);
        }
        // The star, counter-clockwise from its first triangle.
        let mut t = self.star_start(id);
        let mut star = [NONE; STAR_CAPACITY];
        let mut poly = [NONE; STAR_CAPACITY + 1];
        let mut rim = [(NONE, NONE, NONE); STAR_CAPACITY + 1];
        let mut len = 0;
        let start = t;
        let closed = loop {
            if len == STAR_CAPACITY {
                return Err(RemoveError::StarTooLarge);
            }
            let tri = self.triangles[t as usize];
            let i = index_of(&tri.v, id);
            let (x, y) = (tri.v[(i + 1) % 3], tri.v[(i + 2) % 3]);
            star[len] = t;
            poly[len] = x;
            rim[len] = (x, y, tri.n[i]);
            len += 1;
            // Counter-clockwise: across the edge (y, id), opposite x.
            let ccw = tri.n[(i + 1) % 3];
            if ccw == NONE {
                poly[len] = y;
                break false;
            }
            if ccw == start {
                break true;
            }
            t = ccw;
        };
        let mut m = if closed { len } else { len + 1 };
        let mut rim_len = len;
        if !closed {
            // The hole is closed by the boundary edge that passed through the vertex.
            rim[rim_len] = (poly[m - 1], poly[0], NONE);
            rim_len += 1;
        }
        // Clip Delaunay ears: a convex corner whose circumcircle holds no other hole vertex.
        let mut ears = [[NONE; 3]; STAR_CAPACITY];
        let mut count = 0;
        while m >= 3 {
            let found = (0..m).find(|&k| {
                let (a, b, c) = (poly[(k + m - 1) % m], poly[k], poly[(k + 1) % m]);
                let (pa, pb, pc) = (self.pt(a), self.pt(b), self.pt(c));
                orient(pa, pb, pc) > 0
                    && (0..m)
                        .filter(|&j| j != k && j != (k + m - 1) % m && j != (k + 1) % m)
                        .all(|j| !in_circle(pa, pb, pc, self.pt(poly[j])))
            });
            // A Delaunay ear always exists; if arithmetic said otherwise, leave the mesh as is.
            let Some(k) = found else {
                return Err(RemoveError::StarTooLarge);
            };
            ears[count] = [poly[(k + m - 1) % m], poly[k], poly[(k + 1) % m]];
            count += 1;
            if m == 3 {
                break;
            }
            poly.copy_within(k + 1..m, k);
            m -= 1;
        }
        // Commit: the star's slots are freed and the ears take them.
        for &t in &star[..len] {
            self.free_triangle(t);
        }
        let v = &mut self.vertices[id as usize];
        *v = MeshVertex {
            point: GridPoint::default(),
            link: self.free_vertex,
            alive: false,
        };
        self.free_vertex = id;
        self.vertex_count -= 1;
        let mut new = [NONE; STAR_CAPACITY];
        for (slot, ear) in new.iter_mut().zip(&ears[..count]) {
            let t = self.take_triangle();
            self.triangles[t as usize].v = *ear;
            *slot = t;
        }
        self.stitch(&new[..count], &rim[..rim_len]);
        self.hint = new[0];
        Ok(())
    }

    /// Sets the neighbours of the new triangles `new`: among themselves, and across the `rim`
    /// edges to the triangles outside (whose pointers are updated too). Also refreshes the
    /// incident-triangle link of every vertex of `new`.
    fn stitch(&mut self, new: &[u16], rim: &[RimEdge]) {
        for &t in new {
            let v = self.triangles[t as usize].v;
            for i in 0..3 {
                let (a, b) = (v[(i + 1) % 3], v[(i + 2) % 3]);
                let inner = new.iter().copied().find(|&s| {
                    s != t && {
                        let w = self.triangles[s as usize].v;
                        (0..3).any(|j| w[j] == b && w[(j + 1) % 3] == a)
                    }
                });
                let across = match inner {
                    Some(s) => s,
                    None => {
                        let outside = rim
                            .iter()
                            .find(|&&(x, y, _)| x == a && y == b)
                            .map_or(NONE, |&(_, _, o)| o);
                        if outside != NONE {
                            let o = &mut self.triangles[outside as usize];
                            for j in 0..3 {
                                if o.v[(j + 1) % 3] == b && o.v[(j + 2) % 3] == a {
                                    o.n[j] = t;
                                }
                            }
                        }
                        outside
                    }
                };
                self.triangles[t as usize].n[i] = across;
                self.vertices[v[i] as usize].link = t;
            }
        }
    }
}

/// The triangles around a vertex, counter-clockwise: see [`DomainMesh::star`].
#[derive(Debug)]
pub struct Star<'m, 'a> {
    mesh: &'m DomainMesh<'a>,
    id: u16,
    start: u16,
    next: u16,
    steps: usize,
}

impl Iterator for Star<'_, '_> {
    type Item = u16;

    fn next(&mut self) -> Option<u16> {
        // The step bound only guards against a corrupted mesh turning into a hang.
        if self.next == NONE || self.steps > self.mesh.triangles.len() {
            return None;
        }
        let t = self.next;
        let tri = self.mesh.triangles[t as usize];
        let i = index_of(&tri.v, self.id);
        // Counter-clockwise: across the edge (v[i+2], id), opposite v[i+1].
        let ccw = tri.n[(i + 1) % 3];
        self.next = if ccw == self.start { NONE } else { ccw };
        self.steps += 1;
        Some(t)
    }
}

fn index_of(v: &[u16; 3], id: u16) -> usize {
    v.iter().position(|&x| x == id).unwrap_or(0)
}
