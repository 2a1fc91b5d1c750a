//! Links between a hierarchy's triangles, decoded once where there is memory for them (see
//! [`NodeLink`]).

use core::fmt;

use super::hierarchy::{Hierarchy, Pending};

/// No node: a root's parent, or the mate of a triangle whose hypotenuse lies on the model's
/// border.
const NO_NODE: u32 = u32::MAX;

/// Deepest walk down a patch's hierarchy (its root and 24 halvings in a cell, with room to
/// spare).
const DEEPEST: usize = 32;

/// One triangle's links in its hierarchy: its place (its corners on the grid and their
/// vertices), the triangle it is a half of, and the triangle across its hypotenuse that the
/// bake halves with it (its *mate*, the other half of their diamond).
///
/// A frame halves a triangle with the triangle across its hypotenuse, halving coarser ones
/// first where that one is not in the mesh yet. Without links the run time finds it by walking
/// down from its patch's root, deciding at each level which half holds it: on a host that is
/// about a quarter of a cold frame. With links it reads the mate, and walks up its parents to
/// the first that is halved. The mesh is the same either way: it is the view's unique mesh,
/// whatever finds it.
///
/// The links are the caller's, [`Hierarchy::link_slots`] of them (44 bytes each): a host
/// fills them once ([`Hierarchy::fill_links`]) and hands them to its hierarchy
/// ([`Hierarchy::with_links`], which checks them against it). A firmware keeps its RAM and
/// goes without: the bytes and the records are read as they are, and without the feature
/// `links` (default) its walk leaves the lookup out. (The host's `spline_tess::host::Baked`
/// keeps its own.)
///
/// ```
/// # use spline_tess::tessellator::{Hierarchy, NodeLink};
/// # fn run(tree: Hierarchy<'_>) {
/// let mut links = vec![NodeLink::default(); tree.link_slots()];
/// tree.fill_links(&mut links).expect("room for a link a node");
/// let tree = tree.with_links(&links).expect("links of this hierarchy");
/// # let _ = tree;
/// # }
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct NodeLink {
    /// The triangle as the run time names it: node, corners on the grid, vertices.
    pub(super) place: Pending,
    /// The node it is a half of, or [`NO_NODE`] for a root.
    pub(super) parent: u32,
    /// The node across its hypotenuse halved at the same vertex, or [`NO_NODE`] (a leaf of
    /// the bake, or a hypotenuse on the border).
    pub(super) mate: u32,
}

impl Default for NodeLink {
    fn default() -> Self {
        NodeLink {
            place: Pending::NONE,
            parent: NO_NODE,
            mate: NO_NODE,
        }
    }
}

/// Why links could not be filled or were refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LinkError {
    /// Fewer links than the hierarchy's nodes.
    TooShort {
        /// Links needed ([`Hierarchy::link_slots`]).
        needed: usize,
    },
    /// Node `node`'s link is not what this hierarchy has there (links of another hierarchy,
    /// or changed since they were filled).
    Mismatch {
        /// The node.
        node: u32,
    },
}

impl fmt::Display for LinkError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LinkError::TooShort { needed } => write!(f, "links too short: {needed} needed"),
            LinkError::Mismatch { node } => {
                write!(f, "node {node}'s link is not this hierarchy's")
            }
        }
    }
}

impl core::error::Error for LinkError {}

impl<'a> Hierarchy<'a> {
    /// Links a hierarchy takes: one a node.
    pub fn link_slots(&self) -> usize {
        self.node_count()
    }

    /// Fills `links` (at least [`link_slots`](Self::link_slots)) with this hierarchy's links:
    /// a walk of every node, and for each halved one a walk down to its mate.
    pub fn fill_links(&self, links: &mut [NodeLink]) -> Result<(), LinkError> {
        let n = self.node_count();
        let links = links
            .get_mut(..n)
            .ok_or(LinkError::TooShort { needed: n })?;
        links.fill(NodeLink::default());
        let tree = self.without_links();
        each_node(tree, |h, parent| {
            if let Some(l) = links.get_mut(h.node as usize) {
                (l.place, l.parent) = (*h, parent);
            }
        });
        for i in 0..n {
            if links[i].mate != NO_NODE {
                continue;
            }
            if let Some(m) = mate_of(tree, &links[i].place) {
                links[i].mate = m;
                if let Some(l) = links.get_mut(m as usize) {
                    l.mate = i as u32;
                }
            }
        }
        Ok(())
    }

    /// This hierarchy reading `links` (as [`fill_links`](Self::fill_links) filled them for
    /// it), checked: every node's place and parent as a walk finds them, and every mate across
    /// its hypotenuse, halved at the same vertex, and linked back.
    pub fn with_links(self, links: &'a [NodeLink]) -> Result<Hierarchy<'a>, LinkError> {
        let n = self.node_count();
        let links = links.get(..n).ok_or(LinkError::TooShort { needed: n })?;
        let tree = self.without_links();
        let mut bad = None;
        each_node(tree, |h, parent| {
            let ok = links
                .get(h.node as usize)
                .is_some_and(|l| l.place == *h && l.parent == parent);
            if !ok && bad.is_none() {
                bad = Some(h.node);
            }
        });
        if let Some(node) = bad {
            return Err(LinkError::Mismatch { node });
        }
        for (i, l) in links.iter().enumerate() {
            if l.mate == NO_NODE {
                continue;
            }
            let ok = links.get(l.mate as usize).is_some_and(|m| {
                m.mate == i as u32
                    && tree.baked_halving(&l.place).map(|(_, v)| v)
                        == tree.baked_halving(&m.place).map(|(_, v)| v)
                    && tree.baked_halving(&l.place).is_some()
                    && across(tree, &l.place) == Some(m.place.tri)
            });
            if !ok {
                return Err(LinkError::Mismatch { node: i as u32 });
            }
        }
        Ok(Hierarchy { links, ..self })
    }

    /// This hierarchy reading `links` that [`fill_links`](Self::fill_links) filled for it and
    /// nothing changed since (the host's `Baked` keeps its own, out of reach): not checked
    /// again, which would cost a walk of every node each time.
    #[cfg(all(feature = "std", not(target_os = "none")))]
    pub(crate) fn with_own_links(self, links: &'a [NodeLink]) -> Hierarchy<'a> {
        Hierarchy { links, ..self }
    }

    /// The hierarchy without its links (what a walk of the bake's own halvings reads).
    fn without_links(self) -> Hierarchy<'a> {
        Hierarchy { links: &[], ..self }
    }

    /// Node `node`'s links, if the hierarchy has them (none for [`NO_NODE`] or a triangle
    /// below the bake, and none without the feature `links`, which leaves the lookups out).
    pub(super) fn linked(&self, node: u32) -> Option<&'a NodeLink> {
        match cfg!(feature = "links") {
            true => self.links.get(node as usize),
            false => None,
        }
    }
}

/// Calls `f` on every node of `tree` with its parent ([`NO_NODE`] for a root), top-down.
fn each_node(tree: Hierarchy<'_>, mut f: impl FnMut(&Pending, u32)) {
    let mut stack = [(Pending::NONE, NO_NODE); DEEPEST];
    for p in 0..tree.patch_count() as u32 {
        for k in 0..tree.root_count(p) {
            stack[0] = (tree.root(p, k), NO_NODE);
            let mut len = 1;
            while len > 0 {
                len -= 1;
                let (h, parent) = stack[len];
                f(&h, parent);
                if let Some((_, v)) = tree.baked_halving(&h).filter(|_| len + 2 <= DEEPEST) {
                    let [h0, h1] = tree.halves(&h, v);
                    stack[len] = (h1, h.node);
                    stack[len + 1] = (h0, h.node);
                    len += 2;
                }
            }
        }
    }
}

/// The triangle across `h`'s hypotenuse, in its patch or the patch across.
fn across(tree: Hierarchy<'_>, h: &Pending) -> Option<super::address::Tri> {
    h.tri.across(|p, s| tree.link(p, s), |p| tree.cells(p))
}

/// The node across `h`'s hypotenuse halved at the same vertex as `h`, if the bake halves `h`:
/// found by walking down the bake's halvings from its patch's root.
fn mate_of(tree: Hierarchy<'_>, h: &Pending) -> Option<u32> {
    let (_, v) = tree.baked_halving(h)?;
    let t = across(tree, h)?;
    let cells = tree.cells(t.patch);
    let mut at = tree.root(t.patch, t.root_index(cells));
    let target = t.centroid3();
    for _ in 0..DEEPEST {
        if at.tri == t {
            let (_, w) = tree.baked_halving(&at)?;
            return (w == v && at.node != h.node).then_some(at.node);
        }
        let (_, w) = tree.baked_halving(&at)?;
        at = tree.halves(&at, w)[at.tri.half_toward(target, cells)];
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The size the docs give.
    #[test]
    fn a_link_is_44_bytes() {
        assert_eq!(core::mem::size_of::<NodeLink>(), 44);
    }
}
