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

/// Twice the signed area of `abc`: positive when counter-clockwise.
#[inline]
pub(crate) fn orient(a: GridPoint, b: GridPoint, c: GridPoint) -> i64 {
    let (ax, ay) = (a.u as i64, a.v as i64);
    (b.u as i64 - ax) * (c.v as i64 - ay) - (b.v as i64 - ay) * (c.u as i64 - ax)
}

/// How the Delaunay test weighs u against v: circles are taken in the coordinates
/// `(u * metric.u, v * metric.v)`, so a patch whose surface bends faster along one parameter gets
/// triangles stretched along the other.
///
/// Orientation does not depend on it, so a mesh's validity does not either; only which of the
/// valid triangulations is chosen. Factors are whole numbers from 1 to [`Metric::MAX`], which
/// keeps the predicates exact.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Metric {
    u: u8,
    v: u8,
}

impl Default for Metric {
    fn default() -> Self {
        Metric::ISOTROPIC
    }
}

impl Metric {
    /// The largest factor.
    pub const MAX: u8 = 16;
    /// Plain Delaunay in `(u, v)`.
    pub const ISOTROPIC: Metric = Metric { u: 1, v: 1 };

    /// Factors for u and v, each clamped into `1..=MAX`.
    pub const fn new(u: u8, v: u8) -> Self {
        Metric {
            u: clamp_factor(u),
            v: clamp_factor(v),
        }
    }

    /// The factor of u.
    pub const fn u(self) -> u8 {
        self.u
    }

    /// The factor of v.
    pub const fn v(self) -> u8 {
        self.v
    }
}

const fn clamp_factor(x: u8) -> u8 {
    if x < 1 {
        1
    } else if x > Metric::MAX {
        Metric::MAX
    } else {
        x
    }
}

/// True when `d` lies inside the circumcircle of the counter-clockwise triangle `abc` (in the
/// coordinates `metric` scales), with ties broken by simulation of simplicity (the largest point
/// in `(u, v)` order is perturbed most).
fn in_circle(metric: Metric, a: GridPoint, b: GridPoint, c: GridPoint, d: GridPoint) -> bool {
    // Differences up to 2^20 (in i32, and exact in f32): the lifts are below 2^41, the
    // determinant below 2^85.
    let dx = |p: GridPoint| (p.u as i32 - d.u as i32) * metric.u as i32;
    let dy = |p: GridPoint| (p.v as i32 - d.v as i32) * metric.v as i32;
    let differences = [dx(a), dy(a), dx(b), dy(b), dx(c), dy(c)];
    if let Some(inside) = in_circle_filter(differences.map(|x| x as f32)) {
        return inside;
    }
    let [adx, ady, bdx, bdy, cdx, cdy] = differences.map(i64::from);
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

/// Shewchuk's first in-circle error bound ("Adaptive precision floating-point arithmetic and
/// fast robust geometric predicates", 1997, `iccerrboundA`), for `f32`: its unit roundoff is
/// 2^-24.
const IN_CIRCLE_ERROR: f32 = (10.0 + 96.0 * F32_ROUNDOFF) * F32_ROUNDOFF;
const F32_ROUNDOFF: f32 = 1.0 / 16_777_216.0;

/// The in-circle sign in `f32` when it is certain, else `None`.
///
/// The differences (`[adx, ady, bdx, bdy, cdx, cdy]`, below 2^20 in magnitude) are exact in
/// `f32`, which is what Shewchuk's bound assumes: the rounded determinant is within
/// `IN_CIRCLE_ERROR` times the permanent (the same sum over absolute values, also rounded) of
/// the exact one, so a larger magnitude has the exact sign. Nothing can overflow (the
/// determinant is below 2^85); a NaN would fail the comparison and fall through. The exact
/// `i128` test decides the rest, so the answer never depends on the filter.
#[inline]
fn in_circle_filter([adx, ady, bdx, bdy, cdx, cdy]: [f32; 6]) -> Option<bool> {
    let (bc, cb) = (bdx * cdy, cdx * bdy);
    let (ca, ac) = (cdx * ady, adx * cdy);
    let (ab, ba) = (adx * bdy, bdx * ady);
    let (la, lb, lc) = (
        adx * adx + ady * ady,
        bdx * bdx + bdy * bdy,
        cdx * cdx + cdy * cdy,
    );
    let det = la * (bc - cb) + lb * (ca - ac) + lc * (ab - ba);
    let permanent =
        la * (bc.abs() + cb.abs()) + lb * (ca.abs() + ac.abs()) + lc * (ab.abs() + ba.abs());
    let error = IN_CIRCLE_ERROR * permanent;
    if det > error {
        Some(true)
    } else if -det > error {
        Some(false)
    } else {
        None
    }
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

impl MeshVertex {
    /// The point of a live slot.
    pub(crate) fn live_point(&self) -> Option<GridPoint> {
        self.alive.then_some(self.point)
    }
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

impl MeshTriangle {
    /// Vertices (counter-clockwise) and neighbours (`n[i]` across the edge opposite `v[i]`,
    /// `None` on the square's boundary) of a live slot.
    pub(crate) fn live_parts(&self) -> Option<([u16; 3], [Option<u16>; 3])> {
        self.alive
            .then(|| (self.v, self.n.map(|n| (n != NONE).then_some(n))))
    }
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
}

/// Why a vertex could not be removed. The mesh is unchanged.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum RemoveError {
    /// The four corners stay.
    Corner,
    /// No live vertex has this index.
    NotAVertex,
    /// No Delaunay ear was found; exact predicates make this unreachable for a mesh built by
    /// this type, so it means the storage was tampered with.
    NoEar,
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
        }
    }
}

impl fmt::Display for RemoveError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            RemoveError::Corner => "the corners cannot be removed",
            RemoveError::NotAVertex => "no such vertex",
            RemoveError::NoEar => "no Delaunay ear found (corrupted mesh)",
        })
    }
}

impl core::error::Error for MeshStorageError {}
impl core::error::Error for InsertError {}
impl core::error::Error for RemoveError {}

/// An edge on the rim of a hole: `(from, to)` counter-clockwise around it, and
/// the triangle outside it (or `NONE` on the square's boundary).
type RimEdge = (u16, u16, u16);

/// The state of a [`DomainMesh`] besides its slots (the run time keeps one per patch).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct MeshHeader {
    free_vertex: u16,
    free_triangle: u16,
    vertex_count: u16,
    triangle_count: u32,
    hint: u16,
    metric: Metric,
}

impl MeshHeader {
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
pub struct DomainMesh<'a> {
    vertices: &'a mut [MeshVertex],
    triangles: &'a mut [MeshTriangle],
    free_vertex: u16,
    free_triangle: u16,
    vertex_count: usize,
    triangle_count: usize,
    hint: u16,
    metric: Metric,
}

impl<'a> DomainMesh<'a> {
    /// The mesh's own state besides its slots, to rebuild it later over the same storage.
    pub(crate) fn header(&self) -> MeshHeader {
        MeshHeader {
            free_vertex: self.free_vertex,
            free_triangle: self.free_triangle,
            vertex_count: self.vertex_count as u16,
            triangle_count: self.triangle_count as u32,
            hint: self.hint,
            metric: self.metric,
        }
    }

    /// The mesh whose slots are `vertices` and `triangles` and whose state is `header` (as
    /// saved by [`DomainMesh::header`] over the same slots).
    pub(crate) fn resume(
        vertices: &'a mut [MeshVertex],
        triangles: &'a mut [MeshTriangle],
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

    /// Triangle slots enough for `vertices` vertex slots: `2 * vertices - 6` (at least 2).
    pub const fn triangles_for(vertices: usize) -> usize {
        if vertices < 4 {
            2
        } else {
            2 * vertices - 6
        }
    }

    /// The two triangles of the square, in the given storage (its contents are overwritten),
    /// with the [`Metric::ISOTROPIC`] Delaunay test.
    pub fn new(
        vertices: &'a mut [MeshVertex],
        triangles: &'a mut [MeshTriangle],
    ) -> Result<Self, MeshStorageError> {
        Self::with_metric(vertices, triangles, Metric::ISOTROPIC)
    }

    /// Like [`DomainMesh::new`], with circles taken in `metric`'s coordinates.
    pub fn with_metric(
        vertices: &'a mut [MeshVertex],
        triangles: &'a mut [MeshTriangle],
        metric: Metric,
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
            metric,
        };
        for c in corners {
            mesh.take_vertex(c);
        }
        // The corners are cocircular: the tie-break picks the diagonal.
        let [a, b, c, d] = corners;
        let (t0, t1) = (mesh.take_triangle(), mesh.take_triangle());
        if in_circle(mesh.metric, a, b, c, d) {
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
        for _ in 0..=self.triangles.len() {
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
    ///
    /// The triangle (or edge) holding `p` is split and the edges around `p` are flipped until
    /// they are Delaunay (Lawson). Needs one vertex slot and two triangle slots (one when `p`
    /// lies on the square's boundary) and no other memory, whatever the number of triangles
    /// that change.
    pub fn insert(&mut self, p: GridPoint) -> Result<u16, InsertError> {
        let t = self.locate(p);
        let tri = self.triangles[t as usize];
        if let Some(vertex) = tri.v.into_iter().find(|&v| self.pt(v) == p) {
            return Err(InsertError::Duplicate { vertex });
        }
        if self.free_vertex == NONE {
            return Err(InsertError::VerticesFull);
        }
        let [a, b, c] = tri.v.map(|v| self.pt(v));
        // The edge `p` lies on, if any: the one opposite vertex `i`.
        let on_edge = [orient(b, c, p), orient(c, a, p), orient(a, b, p)]
            .iter()
            .position(|&o| o == 0);
        let needed = match on_edge {
            Some(i) if tri.n[i] == NONE => 1,
            _ => 2,
        };
        if self.triangles.len() - self.triangle_count < needed {
            return Err(InsertError::TrianglesFull { needed });
        }
        let id = self.take_vertex(p);
        match on_edge {
            None => self.split_triangle(t, id),
            Some(i) => self.split_edge(t, i, id),
        }
        self.legalize(id);
        self.hint = self.vertices[id as usize].link;
        Ok(id)
    }

    /// Splits triangle `t` into three around the new vertex `id` inside it.
    fn split_triangle(&mut self, t: u16, id: u16) {
        let MeshTriangle {
            v: [a, b, c], n, ..
        } = self.triangles[t as usize];
        let (t1, t2) = (self.take_triangle(), self.take_triangle());
        // t: (id, b, c), t1: (id, c, a), t2: (id, a, b).
        self.set(t, [id, b, c], [n[0], t1, t2]);
        self.set(t1, [id, c, a], [n[1], t2, t]);
        self.set(t2, [id, a, b], [n[2], t, t1]);
        self.replace_neighbor(n[1], t, t1);
        self.replace_neighbor(n[2], t, t2);
        for (v, tri) in [(id, t), (a, t1), (b, t), (c, t)] {
            self.vertices[v as usize].link = tri;
        }
    }

    /// Splits the edge of `t` opposite its vertex `i`, on which the new vertex `id` lies, and
    /// the triangle across it (if any).
    fn split_edge(&mut self, t: u16, i: usize, id: u16) {
        let tri = self.triangles[t as usize];
        let (c, a, b) = (tri.v[i], tri.v[(i + 1) % 3], tri.v[(i + 2) % 3]);
        let (na, nb, o) = (tri.n[(i + 1) % 3], tri.n[(i + 2) % 3], tri.n[i]);
        // t: (c, a, id), t1: (c, id, b).
        let t1 = self.take_triangle();
        if o == NONE {
            self.set(t, [c, a, id], [NONE, t1, nb]);
            self.set(t1, [c, id, b], [NONE, na, t]);
            self.replace_neighbor(na, t, t1);
            for (v, tri) in [(id, t), (a, t), (b, t1), (c, t)] {
                self.vertices[v as usize].link = tri;
            }
            return;
        }
        let ot = self.triangles[o as usize];
        let j = ot.n.iter().position(|&x| x == t).unwrap_or(0);
        // o is (d, b, a); it becomes o: (d, b, id) and o1: (d, id, a).
        let d = ot.v[j];
        let (oa, ob) = (ot.n[(j + 2) % 3], ot.n[(j + 1) % 3]);
        let o1 = self.take_triangle();
        self.set(t, [c, a, id], [o1, t1, nb]);
        self.set(t1, [c, id, b], [o, na, t]);
        self.set(o, [d, b, id], [t1, o1, oa]);
        self.set(o1, [d, id, a], [t, ob, o]);
        self.replace_neighbor(na, t, t1);
        self.replace_neighbor(ob, o, o1);
        for (v, tri) in [(id, t), (a, t), (b, t1), (c, t), (d, o)] {
            self.vertices[v as usize].link = tri;
        }
    }

    /// Flips the edges opposite the new vertex `id` until every one is Delaunay, in one pass
    /// counter-clockwise around its star.
    ///
    /// Flipping the edge `(a, b)` of `(id, a, b)` leaves `(id, a, d)` in the same slot, checked
    /// again at once, and `(id, d, b)` as its counter-clockwise neighbour, checked next; the
    /// rest of the star is untouched. An edge found Delaunay stays so: its test involves only
    /// the two triangles beside it, and a flip elsewhere replaces neither (it removes a
    /// triangle across another star edge). So every triangle of the final star is found clean
    /// exactly once, and the pass ends after `degree` clean tests.
    fn legalize(&mut self, id: u16) {
        let mut t = self.star_start(id);
        let mut clean = 0usize;
        // The star's size: each flip adds a triangle to it.
        let mut degree = self.star(id).count();
        // A bound on the work, only a guard: each flip removes an edge for good.
        let mut budget = 8 * self.triangles.len() + 16;
        while budget > 0 {
            budget -= 1;
            let tri = self.triangles[t as usize];
            let i = index_of(&tri.v, id);
            let o = tri.n[i];
            if o != NONE {
                let ot = self.triangles[o as usize];
                let j = ot.n.iter().position(|&x| x == t).unwrap_or(0);
                let [p, a, b] = [tri.v[i], tri.v[(i + 1) % 3], tri.v[(i + 2) % 3]];
                if in_circle(
                    self.metric,
                    self.pt(p),
                    self.pt(a),
                    self.pt(b),
                    self.pt(ot.v[j]),
                ) {
                    self.flip(t, i);
                    degree += 1;
                    continue;
                }
            }
            clean += 1;
            if clean >= degree {
                break;
            }
            let ccw = tri.n[(i + 1) % 3];
            t = if ccw == NONE {
                self.star_start(id)
            } else {
                ccw
            };
        }
    }

    /// Flips the edge of `t` opposite its vertex `i`: `t = (p, a, b)` and the triangle across,
    /// `(d, b, a)`, become `(p, a, d)` (in slot `t`) and `(p, d, b)`.
    fn flip(&mut self, t: u16, i: usize) {
        let tri = self.triangles[t as usize];
        let o = tri.n[i];
        let ot = self.triangles[o as usize];
        let j = ot.n.iter().position(|&x| x == t).unwrap_or(0);
        let [p, a, b] = [tri.v[i], tri.v[(i + 1) % 3], tri.v[(i + 2) % 3]];
        let d = ot.v[j];
        let (across_ad, across_db) = (ot.n[(j + 1) % 3], ot.n[(j + 2) % 3]);
        let (across_bp, across_pa) = (tri.n[(i + 1) % 3], tri.n[(i + 2) % 3]);
        self.set(t, [p, a, d], [across_ad, o, across_pa]);
        self.set(o, [p, d, b], [across_db, across_bp, t]);
        self.replace_neighbor(across_ad, o, t);
        self.replace_neighbor(across_bp, t, o);
        for (v, tri) in [(p, t), (a, t), (d, t), (b, o)] {
            self.vertices[v as usize].link = tri;
        }
    }

    fn set(&mut self, t: u16, v: [u16; 3], n: [u16; 3]) {
        let slot = &mut self.triangles[t as usize];
        slot.v = v;
        slot.n = n;
    }

    /// In triangle `t` (if any), the neighbour `old` becomes `new`.
    fn replace_neighbor(&mut self, t: u16, old: u16, new: u16) {
        if let Some(tri) = self.triangles.get_mut(t as usize) {
            if let Some(k) = tri.n.iter().position(|&x| x == old) {
                tri.n[k] = new;
            }
        }
    }

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
        if !self.vertices.get(id as usize).is_some_and(|v| v.alive) {
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
            let tri = self.triangles[t as usize].v;
            let i = index_of(&tri, id);
            [tri[(i + 1) % 3], tri[(i + 2) % 3]].into_iter().all(|x| {
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
            let tri = self.triangles[t as usize].v;
            let i = index_of(&tri, id);
            let (x, y) = (tri[(i + 1) % 3], tri[(i + 2) % 3]);
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
        let i = index_of(&self.triangles[t as usize].v, a);
        self.flip(t, i);
        true
    }

    /// The last step of a removal: the triangles left around `id` (three around an interior
    /// vertex, two around a boundary one) become one.
    fn merge(&mut self, id: u16, boundary: bool) {
        let mut star = [NONE; 3];
        for (slot, t) in star.iter_mut().zip(self.star(id)) {
            *slot = t;
        }
        let count = if boundary { 2 } else { 3 };
        // The outer neighbours and the link vertices, counter-clockwise.
        let mut link = [NONE; 4];
        let mut outer = [NONE; 3];
        for k in 0..count {
            let tri = self.triangles[star[k] as usize];
            let i = index_of(&tri.v, id);
            link[k] = tri.v[(i + 1) % 3];
            link[k + 1] = tri.v[(i + 2) % 3];
            outer[k] = tri.n[i];
        }
        let keep = star[0];
        let (v, n) = if boundary {
            // (q0, q1, q2), q0 and q2 on the boundary with id between them.
            ([link[0], link[1], link[2]], [outer[1], NONE, outer[0]])
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
            self.vertices[x as usize].link = keep;
        }
        self.free_vertex_slot(id);
        self.hint = keep;
    }

    /// Removal of an interior vertex of degree four lying on the diagonal its hole's Delaunay
    /// triangulation uses: the four triangles become two.
    fn merge_four(&mut self, id: u16) {
        let mut star = [NONE; 4];
        for (slot, t) in star.iter_mut().zip(self.star(id)) {
            *slot = t;
        }
        let mut q = [NONE; 4];
        let mut outer = [NONE; 4];
        for k in 0..4 {
            let tri = self.triangles[star[k] as usize];
            let i = index_of(&tri.v, id);
            q[k] = tri.v[(i + 1) % 3];
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
        if use_02 {
            self.set(t0, [q[0], q[1], q[2]], [outer[1], t1, outer[0]]);
            self.set(t1, [q[0], q[2], q[3]], [outer[2], outer[3], t0]);
            self.replace_neighbor(outer[1], star[1], t0);
            self.replace_neighbor(outer[2], star[2], t1);
            self.replace_neighbor(outer[3], star[3], t1);
        } else {
            self.set(t0, [q[1], q[2], q[3]], [outer[2], t1, outer[1]]);
            self.set(t1, [q[1], q[3], q[0]], [outer[3], outer[0], t0]);
            self.replace_neighbor(outer[0], star[0], t1);
            self.replace_neighbor(outer[1], star[1], t0);
            self.replace_neighbor(outer[2], star[2], t0);
            self.replace_neighbor(outer[3], star[3], t1);
        }
        for k in 0..4 {
            let t = if use_02 {
                [t0, t0, t0, t1][k]
            } else {
                [t1, t0, t0, t0][k]
            };
            self.vertices[q[k] as usize].link = t;
        }
        self.free_vertex_slot(id);
        self.hint = t0;
    }

    fn free_vertex_slot(&mut self, id: u16) {
        self.vertices[id as usize] = MeshVertex {
            point: GridPoint::default(),
            link: self.free_vertex,
            alive: false,
        };
        self.free_vertex = id;
        self.vertex_count -= 1;
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

#[cfg(test)]
mod tests {
    use super::in_circle_filter;

    /// The exact determinant's sign, as `in_circle` computes it.
    fn exact(d: [i64; 6]) -> i128 {
        let [adx, ady, bdx, bdy, cdx, cdy] = d;
        let lift = |x: i64, y: i64| (x * x + y * y) as i128;
        lift(adx, ady) * (bdx * cdy - bdy * cdx) as i128
            + lift(bdx, bdy) * (cdx * ady - cdy * adx) as i128
            + lift(cdx, cdy) * (adx * bdy - ady * bdx) as i128
    }

    fn check(d: [i64; 6]) -> bool {
        let det = exact(d);
        match in_circle_filter(d.map(|x| x as f32)) {
            Some(inside) => {
                assert!(det != 0 && inside == (det > 0), "{d:?}: filter wrong");
                true
            }
            None => false,
        }
    }

    #[test]
    fn the_filter_never_contradicts_the_exact_test() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = |range: i64| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % (2 * range as u64 + 1)) as i64 - range
        };
        let (mut decided, mut total) = (0, 0);
        // Random differences at every scale up to the grid's 2^20.
        for scale in [3i64, 100, 65_535, (1 << 20) - 1] {
            for _ in 0..20_000 {
                let d = core::array::from_fn(|_| next(scale));
                decided += check(d) as usize;
                total += 1;
            }
        }
        // Cocircular points at every scale, and nearly cocircular ones: the hard cases.
        let ring = [
            (5, 0),
            (4, 3),
            (3, 4),
            (0, 5),
            (-3, 4),
            (-4, -3),
            (0, -5),
            (3, -4),
        ];
        for _ in 0..20_000 {
            let k = next(40_000).abs() + 1;
            let pick = |i: i64| ring[(i.unsigned_abs() % 8) as usize];
            let [a, b, c, d] = [pick(next(8)), pick(next(8)), pick(next(8)), pick(next(8))];
            let nudge = next(1);
            let d = [
                (a.0 - d.0) * k + nudge,
                (a.1 - d.1) * k,
                (b.0 - d.0) * k,
                (b.1 - d.1) * k,
                (c.0 - d.0) * k,
                (c.1 - d.1) * k,
            ];
            if d.iter().all(|x| x.abs() < 1 << 20) {
                decided += check(d) as usize;
                total += 1;
            }
        }
        // The filter decides the bulk of the random cases.
        assert!(decided * 2 > total, "{decided} of {total}");
    }
}
