//! A baked hierarchy as the run time reads it: checked once, then walked by index.

use core::fmt;

use super::address::{root_count, Cells, Tri, MAX_CELL_LEVEL, ONE};
use super::{HierarchyNode, HierarchyPatch, HierarchyVertex, SideLink};
use crate::model::PatchSet;
use crate::patch::{BezierPatch, Side};

/// The node number of a triangle below the bake (the run time's own).
pub(super) const RUN_TIME: u32 = u32::MAX;

/// A baked hierarchy and the patches it was baked from, checked: every index in it is in
/// range, so no frame reads out of bounds. Where a view is finer than the bake, the run time
/// goes on from the patches.
#[derive(Clone, Copy, Debug)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Hierarchy<'a> {
    pub(super) model: PatchSet<'a>,
    pub(super) nodes: &'a [HierarchyNode],
    pub(super) vertices: &'a [HierarchyVertex],
    pub(super) patches: &'a [HierarchyPatch],
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
    };
}

impl<'a> Hierarchy<'a> {
    /// Checks and wraps a bake's records (as [`bake_hierarchy`](crate::bake::bake_hierarchy) wrote them,
    /// cut to the sizes it returned) and the patches they were baked from.
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
                || rec.links.iter().enumerate().any(|(side, l)| {
                    l.is_some_and(|l| match patches.get(l.patch as usize) {
                        None => true,
                        Some(other) => {
                            along(Side::ALL[side], rec.cells) != along(l.side, other.cells)
                        }
                    })
                });
            // A cone: a unit axis (to rounding) and a sine in [0, 1); a sine of 1 or more is
            // none. Anything else (NaN included) is refused: culling trusts it.
            let [x, y, z, sin] = rec.cone;
            let length2 = x * x + y * y + z * z;
            let cone_ok = sin >= 1.0 || (sin >= 0.0 && (length2 - 1.0).abs() < 1e-3);
            if bad || !cone_ok {
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
            nodes,
            vertices,
            patches,
        })
    }

    /// The patches.
    pub fn model(&self) -> PatchSet<'a> {
        self.model
    }

    /// Patch `p` of the model.
    pub(super) fn patch_of(&self, p: u32) -> Option<BezierPatch<'a>> {
        self.model.patch(p as usize)
    }

    /// The corner vertex of side `side` of patch `patch`, if that side is collapsed to a pole
    /// (as the bake names it).
    pub(super) fn pole(&self, patch: u32, side: Side) -> Option<u32> {
        let collapsed = self.patch_of(patch)?.is_collapsed(side);
        let corner = match side {
            Side::V0 | Side::U0 => 0,
            Side::U1 => 1,
            Side::V1 => 2,
        };
        collapsed.then(|| self.patches[patch as usize].corners[corner])
    }

    /// The nodes.
    pub fn nodes(&self) -> &'a [HierarchyNode] {
        self.nodes
    }

    /// The vertices.
    pub fn vertices(&self) -> &'a [HierarchyVertex] {
        self.vertices
    }

    /// The patch records.
    pub fn patches(&self) -> &'a [HierarchyPatch] {
        self.patches
    }

    /// How patch `patch` is cut into cells.
    pub(super) fn cells(&self, patch: u32) -> Cells {
        self.patches.get(patch as usize).map_or([0, 0], |p| p.cells)
    }

    /// The number of roots of patch `patch`.
    pub(super) fn root_count(&self, patch: u32) -> usize {
        root_count(self.cells(patch))
    }

    /// Root `k` of patch `patch` (see [`HierarchyPatch::first_root`]).
    pub(super) fn root(&self, patch: u32, k: usize) -> Pending {
        let rec = &self.patches[patch as usize];
        let tri = Tri::root(patch, rec.cells, k);
        Pending {
            node: rec.first_root + k as u32,
            tri,
            corners: tri.corners.map(|g| cell_corner(rec, g)),
        }
    }

    /// What side `side` of patch `patch` joins.
    pub(super) fn link(&self, patch: u32, side: Side) -> Option<SideLink> {
        self.patches
            .get(patch as usize)
            .and_then(|p| p.links[side.index()])
    }

    /// The node of `h`, if it is a triangle of the bake.
    pub(super) fn node(&self, h: &Pending) -> Option<&'a HierarchyNode> {
        self.nodes.get(h.node as usize)
    }

    /// The bake's halves of `h`, if the bake halves it.
    pub(super) fn baked_halves(&self, h: &Pending) -> Option<u32> {
        self.node(h).map(|n| n.children).filter(|&c| c != 0)
    }

    /// The halves of `h`, split at vertex `v`: the bake's nodes, or the run time's.
    pub(super) fn halves(&self, h: &Pending, v: u32) -> [Pending; 2] {
        let [n0, n1] = match self.baked_halves(h) {
            Some(first) => [first, first + 1],
            None => [RUN_TIME; 2],
        };
        let [a, b, c] = h.corners;
        let [t0, t1] = h.tri.children();
        [
            Pending {
                node: n0,
                tri: t0,
                corners: [v, a, b],
            },
            Pending {
                node: n1,
                tri: t1,
                corners: [v, c, a],
            },
        ]
    }
}

/// Deepest walk of a mesh (24 halvings in a cell, and its root, with room to spare).
const WALK: usize = 28;

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
    mut wants: impl FnMut(&mut S, u32) -> bool,
    mut visit: impl FnMut(&mut S, &Pending) -> Option<u32>,
) {
    let mut stack = [Pending::default(); WALK];
    for p in 0..tree.patches.len() as u32 {
        if !wants(state, p) {
            continue;
        }
        for k in 0..tree.root_count(p) {
            stack[0] = tree.root(p, k);
            let mut n = 1;
            while n > 0 {
                n -= 1;
                let h = stack[n];
                if let Some(v) = visit(state, &h).filter(|_| n + 2 <= WALK) {
                    let [h0, h1] = tree.halves(&h, v);
                    stack[n] = h1;
                    stack[n + 1] = h0;
                    n += 2;
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
