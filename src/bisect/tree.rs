//! A baked hierarchy as the run time reads it: checked once, then walked by index.

use core::fmt;

use super::address::Tri;
use super::{BintreeNode, BintreePatch, BintreeVertex, SideLink};
use crate::patch::Side;

/// A baked hierarchy, checked: every index in it is in range, so no frame reads out of
/// bounds.
#[derive(Clone, Copy, Debug)]
pub struct Bintree<'a> {
    pub(super) nodes: &'a [BintreeNode],
    pub(super) vertices: &'a [BintreeVertex],
    pub(super) patches: &'a [BintreePatch],
}

/// Why a baked hierarchy was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum BintreeError {
    /// No patch, or fewer nodes than the patches' squares.
    Empty,
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
    /// Patch `patch` names a corner vertex or linked patch out of range.
    BadPatch {
        /// The patch.
        patch: u32,
    },
}

impl fmt::Display for BintreeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BintreeError::Empty => write!(f, "the hierarchy has no patch"),
            BintreeError::BadNode { node } => write!(f, "node {node} is out of range"),
            BintreeError::BadVertex { vertex } => write!(f, "vertex {vertex} is out of range"),
            BintreeError::BadPatch { patch } => write!(f, "patch {patch} is out of range"),
        }
    }
}

impl core::error::Error for BintreeError {}

/// A triangle of the current mesh, or waiting to be judged: its node, where it is, and its
/// corners' vertices.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Pending {
    pub(super) node: u32,
    pub(super) tri: Tri,
    pub(super) corners: [u32; 3],
}

impl<'a> Bintree<'a> {
    /// Checks and wraps a bake's records (as [`bake_bintree`](super::bake_bintree) wrote them,
    /// cut to the sizes it returned).
    pub fn new(
        nodes: &'a [BintreeNode],
        vertices: &'a [BintreeVertex],
        patches: &'a [BintreePatch],
    ) -> Result<Self, BintreeError> {
        if patches.is_empty() || nodes.len() < 2 * patches.len() {
            return Err(BintreeError::Empty);
        }
        for (p, rec) in patches.iter().enumerate() {
            let bad = rec.corners.iter().any(|&v| v as usize >= vertices.len())
                || rec
                    .links
                    .iter()
                    .flatten()
                    .any(|l| l.patch as usize >= patches.len());
            if bad {
                return Err(BintreeError::BadPatch { patch: p as u32 });
            }
        }
        for (i, n) in nodes.iter().enumerate() {
            let bad = n.children != 0
                && (n.children as usize <= i
                    || n.children as usize + 1 >= nodes.len()
                    || n.vertex as usize >= vertices.len());
            if bad {
                return Err(BintreeError::BadNode { node: i as u32 });
            }
        }
        for (i, v) in vertices.iter().enumerate() {
            if v.output as usize >= vertices.len() {
                return Err(BintreeError::BadVertex { vertex: i as u32 });
            }
        }
        Ok(Bintree {
            nodes,
            vertices,
            patches,
        })
    }

    /// The nodes.
    pub fn nodes(&self) -> &'a [BintreeNode] {
        self.nodes
    }

    /// The vertices.
    pub fn vertices(&self) -> &'a [BintreeVertex] {
        self.vertices
    }

    /// The patches.
    pub fn patches(&self) -> &'a [BintreePatch] {
        self.patches
    }

    /// Root `k` (0 or 1) of patch `patch`.
    pub(super) fn root(&self, patch: u32, k: usize) -> Pending {
        let c = self.patches[patch as usize].corners;
        Pending {
            node: 2 * patch + k as u32,
            tri: Tri::roots(patch)[k],
            corners: if k == 0 {
                [c[0], c[1], c[3]]
            } else {
                [c[2], c[3], c[1]]
            },
        }
    }

    /// What side `side` of patch `patch` joins.
    pub(super) fn link(&self, patch: u32, side: Side) -> Option<SideLink> {
        self.patches
            .get(patch as usize)
            .and_then(|p| p.links[side.index()])
    }

    /// The node of `h`.
    pub(super) fn node(&self, h: &Pending) -> &'a BintreeNode {
        &self.nodes[h.node as usize]
    }

    /// The halves of `h`, split at its node's vertex.
    pub(super) fn halves(&self, h: &Pending) -> [Pending; 2] {
        let node = self.node(h);
        let (first, v) = (node.children, node.vertex);
        let [a, b, c] = h.corners;
        let [t0, t1] = h.tri.children();
        [
            Pending {
                node: first,
                tri: t0,
                corners: [v, a, b],
            },
            Pending {
                node: first + 1,
                tri: t1,
                corners: [v, c, a],
            },
        ]
    }

    /// The vertices written out for `h`, or `None` where two are one: a triangle with two
    /// corners on a side collapsed to a pole is a segment, which its neighbours' sides
    /// already draw.
    pub(super) fn written(&self, h: &Pending) -> Option<[u32; 3]> {
        let [a, b, c] = h.corners.map(|v| self.vertices[v as usize].output);
        (a != b && b != c && c != a).then_some([a, b, c])
    }
}

/// Deepest walk of a mesh (the bake's depth limit, 30, and its roots).
const WALK: usize = 34;

/// Walks every patch's triangles top-down, first halves first, calling `visit` on each: it
/// returns whether the triangle is halved (the walk then goes into its halves). `visit` may
/// halve triangles: the walk goes by what `visit` returns when it gets to each.
pub(super) fn walk(tree: Bintree<'_>, mut visit: impl FnMut(&Pending) -> bool) {
    let mut stack = [Pending::default(); WALK];
    for p in 0..tree.patches.len() as u32 {
        stack[0] = tree.root(p, 1);
        stack[1] = tree.root(p, 0);
        let mut n = 2;
        while n > 0 {
            n -= 1;
            let h = stack[n];
            if visit(&h) && n + 2 <= WALK {
                let [h0, h1] = tree.halves(&h);
                stack[n] = h1;
                stack[n + 1] = h0;
                n += 2;
            }
        }
    }
}
