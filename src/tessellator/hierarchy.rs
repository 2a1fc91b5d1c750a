//! A baked hierarchy as the run time reads it: checked once, then walked by index.

use core::fmt;

use super::address::{root_count, Cells, Tri, MAX_CELL_LEVEL, ONE};
use super::format::{FormatError, HierarchyBytes};
use super::links::NodeLink;
use super::{HierarchyNode, HierarchyPatch, HierarchyVertex, SideLink};
use crate::model::PatchSet;
use crate::patch::{BezierPatch, Side};

/// The node number of a triangle below the bake (the run time's own).
pub(super) const RUN_TIME: u32 = u32::MAX;

/// A baked hierarchy and the patches it was baked from, checked: every index in it is in
/// range, so no frame reads out of bounds. Where a view is finer than the bake, the run time
/// goes on from the patches.
///
/// It reads either the bake's records in RAM ([`new`](Self::new)) or their compact bytes in
/// place, in flash say ([`from_bytes`](Self::from_bytes)): the same hierarchy gives the same
/// meshes either way.
#[derive(Clone, Copy, Debug)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Hierarchy<'a> {
    pub(super) model: PatchSet<'a>,
    pub(super) store: Store<'a>,
    /// The links between its triangles, if the caller gave them (see `links`); else empty.
    pub(super) links: &'a [NodeLink],
}

/// Where a hierarchy's records are. (The bytes' variant carries their layout, read once:
/// a few hundred bytes, held once a tessellator.)
#[derive(Clone, Copy, Debug)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[allow(clippy::large_enum_variant)]
pub(super) enum Store<'a> {
    /// The bake's records.
    Records {
        nodes: &'a [HierarchyNode],
        vertices: &'a [HierarchyVertex],
        patches: &'a [HierarchyPatch],
    },
    /// The compact bytes.
    Bytes(HierarchyBytes<'a>),
}

/// Why a baked hierarchy was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum HierarchyError {
    /// No patch, or fewer nodes than the patches' roots.
    Empty,
    /// The bake has records for another number of patches than the model has.
    PatchCount {
        /// Patches of the model.
        model: usize,
        /// Patch records of the bake.
        baked: usize,
    },
    /// Node `node` names a half or a vertex out of range, or a half before itself.
    BadNode {
        /// The node.
        node: u32,
    },
    /// Vertex `vertex` is written out as a vertex out of range.
    BadVertex {
        /// The vertex.
        vertex: u32,
    },
    /// Patch `patch` names a corner vertex, cell vertex or linked patch out of range, has
    /// more cells than [`MAX_CELL_LEVEL`] allows, roots out of place, or cuts a shared curve
    /// into another number of cells than the patch across.
    BadPatch {
        /// The patch.
        patch: u32,
    },
}

impl fmt::Display for HierarchyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            HierarchyError::Empty => write!(f, "the hierarchy has no patch"),
            HierarchyError::PatchCount { model, baked } => {
                write!(f, "the model has {model} patches, the bake {baked}")
            }
            HierarchyError::BadNode { node } => write!(f, "node {node} is out of range"),
            HierarchyError::BadVertex { vertex } => write!(f, "vertex {vertex} is out of range"),
            HierarchyError::BadPatch { patch } => write!(f, "patch {patch} is out of range"),
        }
    }
}

impl core::error::Error for HierarchyError {}

/// A triangle of the current mesh, or waiting to be judged: its node, where it is, and its
/// corners' vertices.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub(crate) struct Pending {
    pub(super) node: u32,
    pub(super) tri: Tri,
    pub(super) corners: [u32; 3],
    /// How the bake treats the node, found once where the triangle is made (the bytes count
    /// bits to find it, and a frame asks it several times a triangle): see [`Shape`].
    pub(super) shape: Shape,
}

/// Whether the bake halves a node, and where its records are: for the bytes, a halved node's
/// rank among the halved nodes, or a leaf's among the leaves (with [`Shape::LEAF`] set).
/// The records keep only the flag; a triangle below the bake is a leaf.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub(crate) struct Shape(pub(super) u32);

impl Shape {
    /// The flag of a leaf of the bake.
    pub(super) const LEAF: u32 = 1 << 31;

    /// A leaf of the bake (or a triangle below it), `rank`-th among the leaves.
    pub(super) const fn leaf(rank: u32) -> Shape {
        Shape(Self::LEAF | rank)
    }

    /// A node the bake halves, `rank`-th among the halved nodes.
    pub(super) const fn halved(rank: u32) -> Shape {
        Shape(rank & !Self::LEAF)
    }

    /// Whether the bake halves the node.
    pub(super) fn is_halved(self) -> bool {
        self.0 & Self::LEAF == 0
    }

    /// Its rank among the halved nodes or among the leaves.
    pub(super) fn rank(self) -> usize {
        (self.0 & !Self::LEAF) as usize
    }
}

impl Pending {
    /// No triangle (an empty stack slot).
    pub(super) const NONE: Pending = Pending {
        node: 0,
        tri: Tri {
            patch: 0,
            corners: [[0; 2]; 3],
        },
        corners: [0; 3],
        shape: Shape::leaf(0),
    };
}

impl<'a> Hierarchy<'a> {
    /// Checks and wraps a bake's records (as [`bake_hierarchy`](crate::bake::bake_hierarchy)
    /// wrote them, cut to the sizes it returned) and the patches they were baked from.
    pub fn new(
        model: PatchSet<'a>,
        nodes: &'a [HierarchyNode],
        vertices: &'a [HierarchyVertex],
        patches: &'a [HierarchyPatch],
    ) -> Result<Self, HierarchyError> {
        if patches.is_empty() {
            return Err(HierarchyError::Empty);
        }
        if model.len() != patches.len() {
            return Err(HierarchyError::PatchCount {
                model: model.len(),
                baked: patches.len(),
            });
        }
        let mut roots = 0usize;
        for (p, rec) in patches.iter().enumerate() {
            let bad_cells = rec.cells.iter().any(|&c| c > MAX_CELL_LEVEL);
            let bad_roots = bad_cells || rec.first_root as usize != roots;
            if !bad_cells {
                roots += root_count(rec.cells);
            }
            let block = match rec.cells {
                [0, 0] => 0,
                [a, b] if !bad_cells => ((1usize << a) + 1) * ((1usize << b) + 1),
                _ => 0,
            };
            let bad = bad_roots
                || rec.corners.iter().any(|&v| v as usize >= vertices.len())
                || rec.cell_vertices as usize + block > vertices.len()
                || !links_agree(patches.len(), p, |q| {
                    patches.get(q).map(|r| (r.cells, r.links))
                })
                || rec.poles != poles_of(&model, p);
            if bad || !cone_ok(rec.cone) {
                return Err(HierarchyError::BadPatch { patch: p as u32 });
            }
        }
        if nodes.len() < roots {
            return Err(HierarchyError::Empty);
        }
        for (i, n) in nodes.iter().enumerate() {
            let bad = n.children != 0
                && (n.children as usize <= i
                    || n.children as usize + 1 >= nodes.len()
                    || n.vertex as usize >= vertices.len());
            if bad {
                return Err(HierarchyError::BadNode { node: i as u32 });
            }
        }
        for (i, v) in vertices.iter().enumerate() {
            if v.output as usize >= vertices.len() {
                return Err(HierarchyError::BadVertex { vertex: i as u32 });
            }
        }
        Ok(Hierarchy {
            model,
            store: Store::Records {
                nodes,
                vertices,
                patches,
            },
            links: &[],
        })
    }

    /// Checks and wraps a hierarchy's compact bytes (as
    /// [`encode_hierarchy`](crate::bake::encode_hierarchy) wrote them) and the patches they
    /// were baked from, reading the bytes in place: they can be a `static` in flash
    /// (`include_bytes!`), at any alignment. Bad bytes are refused with what is wrong
    /// ([`FormatError`]); none makes a later frame read out of bounds or panic.
    pub fn from_bytes(model: PatchSet<'a>, bytes: &'a [u8]) -> Result<Self, FormatError> {
        let store = HierarchyBytes::parse(bytes, &model)?;
        store.check(&model)?;
        Ok(Hierarchy {
            model,
            store: Store::Bytes(store),
            links: &[],
        })
    }

    /// The bake's records this hierarchy reads, if it reads records ([`new`](Self::new)).
    #[allow(clippy::type_complexity)]
    pub fn records(
        &self,
    ) -> Option<(
        &'a [HierarchyNode],
        &'a [HierarchyVertex],
        &'a [HierarchyPatch],
    )> {
        match self.store {
            Store::Records {
                nodes,
                vertices,
                patches,
            } => Some((nodes, vertices, patches)),
            Store::Bytes(_) => None,
        }
    }

    /// The compact bytes this hierarchy reads, if it reads bytes
    /// ([`from_bytes`](Self::from_bytes)).
    pub fn bytes(&self) -> Option<&'a [u8]> {
        match self.store {
            Store::Bytes(b) => Some(b.as_bytes()),
            Store::Records { .. } => None,
        }
    }

    /// The patches.
    pub fn model(&self) -> PatchSet<'a> {
        self.model
    }

    /// Patch `p` of the model.
    pub(super) fn patch_of(&self, p: u32) -> Option<BezierPatch<'a>> {
        self.model.patch(p as usize)
    }

    /// Triangles of the hierarchy.
    pub fn node_count(&self) -> usize {
        match self.store {
            Store::Records { nodes, .. } => nodes.len(),
            Store::Bytes(b) => b.node_count(),
        }
    }

    /// Vertices of the hierarchy.
    pub fn vertex_count(&self) -> usize {
        match self.store {
            Store::Records { vertices, .. } => vertices.len(),
            Store::Bytes(b) => b.vertex_count(),
        }
    }

    /// Patches of the hierarchy (as many as the model has).
    pub fn patch_count(&self) -> usize {
        self.model.len()
    }

    /// Triangle `i` of the hierarchy: where it is halved and its bound, as the bake recorded
    /// them (`None` past the last). Node numbers are the hierarchy's own: the bytes number
    /// the triangles of the records level by level.
    pub fn node(&self, i: usize) -> Option<HierarchyNode> {
        match self.store {
            Store::Records { nodes, .. } => nodes.get(i).copied(),
            Store::Bytes(b) => b.node(i),
        }
    }

    /// Node `i`'s bound (its kept vectors, scale and remainder; its halving left out), and
    /// whether it is a leaf of the bake (which keeps no vector).
    pub(super) fn node_bound(&self, h: &Pending) -> Option<(HierarchyNode, bool)> {
        match self.store {
            Store::Records { nodes, .. } => {
                nodes.get(h.node as usize).map(|n| (*n, n.children == 0))
            }
            Store::Bytes(b) => b.bound_of_shape(h.node as usize, h.shape),
        }
    }

    /// The point of vertex `v` in model space (`None` past the last).
    pub fn position(&self, v: usize) -> Option<[f32; 3]> {
        match self.store {
            Store::Records { vertices, .. } => vertices.get(v).map(|x| x.position),
            Store::Bytes(b) => b.position(v),
        }
    }

    /// The grid of the model's box the points lie on, where the hierarchy is bytes (the
    /// records hold their points as `f32`).
    pub(crate) fn grid(&self) -> Option<super::quantize::PositionGrid> {
        match self.store {
            Store::Records { .. } => None,
            Store::Bytes(b) => Some(b.grid()),
        }
    }

    /// Vertex `v`'s point on [`grid`](Self::grid) (`None` past the last, or for records).
    pub(crate) fn grid_point(&self, v: usize) -> Option<[u16; 3]> {
        match self.store {
            Store::Records { .. } => None,
            Store::Bytes(b) => b.grid_point(v),
        }
    }

    /// Vertex `v`'s normal as its octahedral code (`None` past the last, or for records).
    #[cfg(feature = "embedded-graphics")]
    pub(crate) fn normal_code(&self, v: usize) -> Option<[i8; 2]> {
        match self.store {
            Store::Records { .. } => None,
            Store::Bytes(b) => b.normal_code(v),
        }
    }

    /// The unit normal of vertex `v` (`None` past the last).
    pub fn normal(&self, v: usize) -> Option<[f32; 3]> {
        match self.store {
            Store::Records { vertices, .. } => vertices.get(v).map(|x| x.normal),
            Store::Bytes(b) => b.normal(v),
        }
    }

    /// How patch `p` is cut into cells, what its sides join, whether it is flipped, and its
    /// normal cone: its record, without the vertex numbers the bytes leave implied.
    pub fn patch(&self, p: usize) -> Option<PatchInfo> {
        match self.store {
            Store::Records { patches, .. } => patches.get(p).map(|r| PatchInfo {
                cells: r.cells,
                links: r.links,
                flip: r.flip,
                poles: r.poles,
                cone: r.cone,
            }),
            Store::Bytes(b) => b.patch(p),
        }
    }

    /// The vertex at corner `k` (`(0, 0)`, `(1, 0)`, `(1, 1)`, `(0, 1)`) of patch `p`.
    pub(super) fn corner(&self, p: u32, k: usize) -> u32 {
        match self.store {
            Store::Records { patches, .. } => patches.get(p as usize).map_or(0, |r| r.corners[k]),
            Store::Bytes(b) => b.corner(p as usize, k),
        }
    }

    /// The pole of side `side` of patch `patch`: the corner vertex it is collapsed to, if it
    /// is (as the bake names it).
    pub(super) fn pole(&self, patch: u32, side: Side) -> Option<u32> {
        let collapsed = self.poles(patch) & (1 << side.index()) != 0;
        let corner = match side {
            Side::V0 | Side::U0 => 0,
            Side::U1 => 1,
            Side::V1 => 2,
        };
        collapsed.then(|| self.corner(patch, corner))
    }

    /// The sides of patch `patch` collapsed to a point, a bit per side (`V0, U1, V1, U0`).
    pub(super) fn poles(&self, patch: u32) -> u8 {
        match self.store {
            Store::Records { patches, .. } => patches.get(patch as usize).map_or(0, |r| r.poles),
            Store::Bytes(b) => b.poles(patch as usize),
        }
    }

    /// How patch `patch` is cut into cells.
    pub(super) fn cells(&self, patch: u32) -> Cells {
        match self.store {
            Store::Records { patches, .. } => {
                patches.get(patch as usize).map_or([0, 0], |p| p.cells)
            }
            Store::Bytes(b) => b.cells(patch as usize),
        }
    }

    /// Whether the bake flipped patch `patch` (see [`HierarchyPatch::flip`]).
    pub(super) fn flip(&self, patch: u32) -> bool {
        match self.store {
            Store::Records { patches, .. } => patches.get(patch as usize).is_some_and(|p| p.flip),
            Store::Bytes(b) => b.flip(patch as usize),
        }
    }

    /// The number of roots of patch `patch`.
    pub(super) fn root_count(&self, patch: u32) -> usize {
        root_count(self.cells(patch))
    }

    /// Root `k` of patch `patch` (see [`HierarchyPatch::first_root`]).
    pub(super) fn root(&self, patch: u32, k: usize) -> Pending {
        let cells = self.cells(patch);
        let tri = Tri::root(patch, cells, k);
        let first = match self.store {
            Store::Records { patches, .. } => {
                patches.get(patch as usize).map_or(0, |r| r.first_root)
            }
            Store::Bytes(b) => b.first_root(patch as usize),
        };
        let node = first + k as u32;
        Pending {
            node,
            tri,
            corners: tri.corners.map(|g| self.grid_vertex(patch, cells, g)),
            shape: self.shapes(node)[0],
        }
    }

    /// The shapes of nodes `node` and `node + 1` (one count of bits for both, as a triangle's
    /// two halves are numbered).
    fn shapes(&self, node: u32) -> [Shape; 2] {
        match self.store {
            Store::Records { nodes, .. } => [node, node + 1].map(|i| {
                match nodes.get(i as usize).is_some_and(|n| n.children != 0) {
                    true => Shape::halved(0),
                    false => Shape::leaf(0),
                }
            }),
            Store::Bytes(b) => b.shapes(node as usize),
        }
    }

    /// The vertex at cell corner `g` (a grid point) of patch `patch`: its corner's, or its
    /// cell corner's (the vertex written out there, where the records hold a copy).
    fn grid_vertex(&self, patch: u32, cells: Cells, g: [u16; 2]) -> u32 {
        let k = match g {
            [0, 0] => 0,
            [ONE, 0] => 1,
            [ONE, ONE] => 2,
            [0, ONE] => 3,
            [u, v] => {
                let (i, j) = (u as u32 >> (15 - cells[0]), v as u32 >> (15 - cells[1]));
                return match self.store {
                    Store::Records {
                        vertices, patches, ..
                    } => patches
                        .get(patch as usize)
                        .map(|rec| rec.cell_vertices + i * ((1 << cells[1]) + 1) + j)
                        .and_then(|x| vertices.get(x as usize))
                        .map_or(0, |x| x.output),
                    Store::Bytes(b) => b.cell_vertex(patch as usize, i, j),
                };
            }
        };
        self.corner(patch, k)
    }

    /// What side `side` of patch `patch` joins.
    pub(super) fn link(&self, patch: u32, side: Side) -> Option<SideLink> {
        match self.store {
            Store::Records { patches, .. } => patches
                .get(patch as usize)
                .and_then(|p| p.links[side.index()]),
            Store::Bytes(b) => b.link(patch as usize, side),
        }
    }

    /// Where the bake halves `h` (its first half's node and its hypotenuse's midpoint), if it
    /// is a triangle of the bake and the bake halves it.
    pub(super) fn baked_halving(&self, h: &Pending) -> Option<(u32, u32)> {
        match self.store {
            Store::Records { nodes, .. } => nodes
                .get(h.node as usize)
                .filter(|n| n.children != 0)
                .map(|n| (n.children, n.vertex)),
            Store::Bytes(b) => b.halving_of_shape(h.node as usize, h.shape),
        }
    }

    /// The node of the first half of `h`, if the bake halves it (without its vertex, which
    /// the bytes take longer to find).
    pub(super) fn baked_first_half(&self, h: &Pending) -> Option<u32> {
        match self.store {
            Store::Records { nodes, .. } => nodes
                .get(h.node as usize)
                .filter(|n| n.children != 0)
                .map(|n| n.children),
            Store::Bytes(b) => b.first_half_of_shape(h.node as usize, h.shape),
        }
    }

    /// Whether `h` is a triangle of the bake (not one the run time made below it).
    pub(super) fn is_baked(&self, h: &Pending) -> bool {
        (h.node as usize) < self.node_count()
    }

    /// The halves of `h`, split at vertex `v`: the bake's nodes, or the run time's.
    pub(super) fn halves(&self, h: &Pending, v: u32) -> [Pending; 2] {
        let ([n0, n1], [s0, s1]) = match self.baked_first_half(h) {
            Some(first) => ([first, first + 1], self.shapes(first)),
            None => ([RUN_TIME; 2], [Shape::leaf(0); 2]),
        };
        let [a, b, c] = h.corners;
        let [t0, t1] = h.tri.children();
        [
            Pending {
                node: n0,
                tri: t0,
                corners: [v, a, b],
                shape: s0,
            },
            Pending {
                node: n1,
                tri: t1,
                corners: [v, c, a],
                shape: s1,
            },
        ]
    }
}

/// A patch's part of a hierarchy: how its square is cut into cells, what its sides join,
/// whether it is flipped, which sides are poles and its normal cone (see [`HierarchyPatch`]).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PatchInfo {
    /// See [`HierarchyPatch::cells`].
    pub cells: Cells,
    /// See [`HierarchyPatch::links`].
    pub links: [Option<SideLink>; 4],
    /// See [`HierarchyPatch::flip`].
    pub flip: bool,
    /// See [`HierarchyPatch::poles`].
    pub poles: u8,
    /// See [`HierarchyPatch::cone`].
    pub cone: [f32; 4],
}

/// A cone as culling trusts it: a unit axis (to rounding) and a sine in `[0, 1)`, or a sine
/// of 1 or more for none. Anything else (NaN included) is refused.
pub(super) fn cone_ok([x, y, z, sin]: [f32; 4]) -> bool {
    let length2 = x * x + y * y + z * z;
    sin >= 1.0 || (sin >= 0.0 && (length2 - 1.0).abs() < 1e-3)
}

/// Whether patch `p`'s links name patches in range (of `count`) that link back to the same
/// side, cutting the shared curve into as many cells (`record` gives a patch's cells and
/// links).
pub(super) fn links_agree(
    count: usize,
    p: usize,
    record: impl Fn(usize) -> Option<(Cells, [Option<SideLink>; 4])>,
) -> bool {
    let Some((cells, links)) = record(p) else {
        return false;
    };
    links.iter().enumerate().all(|(side, l)| {
        let Some(l) = l else { return true };
        let q = l.patch as usize;
        match record(q).filter(|_| q < count) {
            None => false,
            Some((theirs, back)) => {
                along(Side::ALL[side], cells) == along(l.side, theirs)
                    && back[l.side.index()].is_some_and(|b| {
                        b.patch as usize == p && b.side == Side::ALL[side] && b.flip == l.flip
                    })
            }
        }
    })
}

/// The sides of patch `p` of `model` collapsed to a point, a bit per side.
pub(crate) fn poles_of(model: &PatchSet<'_>, p: usize) -> u8 {
    let Some(patch) = model.patch(p) else {
        return 0;
    };
    Side::ALL
        .iter()
        .filter(|&&s| patch.is_collapsed(s))
        .fold(0, |m, s| m | 1 << s.index())
}

/// Deepest walk of a mesh: the second halves waiting, one a level (24 halvings in a cell,
/// and its root, with room to spare).
const WALK: usize = 26;

/// Walks every patch's triangles top-down, first halves first, calling `visit` on each: it
/// returns the vertex the triangle is halved at, if it is (the walk then goes into its
/// halves). `visit` may halve triangles: the walk goes by what `visit` returns when it gets
/// to each.
pub(super) fn walk(tree: Hierarchy<'_>, mut visit: impl FnMut(&Pending) -> Option<u32>) {
    walk_patches(tree, &mut (), |_, _| true, |_, h| visit(h));
}

/// [`walk`] over the patches `wants` takes, both callbacks given `state`.
pub(super) fn walk_patches<S: ?Sized>(
    tree: Hierarchy<'_>,
    state: &mut S,
    wants: impl FnMut(&mut S, u32) -> bool,
    visit: impl FnMut(&mut S, &Pending) -> Option<u32>,
) {
    walk_roots(tree, state, wants, |_, _| true, visit);
}

/// [`walk_patches`], from the roots `root` takes (root `k` of patch `p`) of the patches
/// `wants` takes.
pub(super) fn walk_roots<S: ?Sized>(
    tree: Hierarchy<'_>,
    state: &mut S,
    mut wants: impl FnMut(&mut S, u32) -> bool,
    root: impl Fn(u32, usize) -> bool,
    mut visit: impl FnMut(&mut S, &Pending) -> Option<u32>,
) {
    let mut stack = [Pending::default(); WALK];
    for p in 0..tree.patch_count() as u32 {
        if !wants(state, p) {
            continue;
        }
        for k in (0..tree.root_count(p)).filter(|&k| root(p, k)) {
            // The first half is visited next, straight from the halving: only second halves
            // go through the stack. (A triangle copied out of the stack just after it was
            // written there waits for the stores of its 16-bit fields to reach the cache
            // before the copy's wider loads can read them: a quarter of `write_mesh`'s
            // samples in `perf annotate`, on an AMD EPYC.)
            let mut h = tree.root(p, k);
            let mut n = 0;
            loop {
                match visit(state, &h).filter(|_| n < WALK) {
                    Some(v) => {
                        let [h0, h1] = tree.halves(&h, v);
                        stack[n] = h1;
                        n += 1;
                        h = h0;
                    }
                    None if n > 0 => {
                        n -= 1;
                        h = stack[n];
                    }
                    None => break,
                }
            }
        }
    }
}

/// Which direction of a patch's cells runs along `side`: `u` (0) along `V0` and `V1`.
fn along(side: Side, cells: Cells) -> u8 {
    match side {
        Side::V0 | Side::V1 => cells[0],
        Side::U1 | Side::U0 => cells[1],
    }
}

/// The vertex at cell corner `g` (a grid point) of patch record `rec`: its corner's, or its
/// cell vertex.
pub(crate) fn cell_corner(rec: &HierarchyPatch, g: [u16; 2]) -> u32 {
    match g {
        [0, 0] => rec.corners[0],
        [ONE, 0] => rec.corners[1],
        [ONE, ONE] => rec.corners[2],
        [0, ONE] => rec.corners[3],
        [u, v] => {
            let [a, b] = rec.cells;
            let (i, j) = (u as u32 >> (15 - a), v as u32 >> (15 - b));
            rec.cell_vertices + i * ((1 << b) + 1) + j
        }
    }
}
