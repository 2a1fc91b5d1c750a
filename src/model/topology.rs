//! Which boundary curve each patch edge is: shared with a neighbour, open, or collapsed.
//!
//! Two edges are the same curve when their control points (and weights) are equal bit for bit,
//! in the same or the opposite order. Exact equality is the right test: the models this crate
//! reads repeat shared rows verbatim, [`NurbsSurface::decompose`](crate::NurbsSurface::decompose)
//! copies them, and a crack-free mesh needs the shared vertices to be computed from one curve.
//! Matching is quadratic in the number of edges, which needs no scratch memory and takes a few
//! milliseconds for the largest model here (Gumbo, 512 edges) on a host.

use core::fmt;

use crate::model::PatchSet;
use crate::patch::{BezierPatch, Side};

/// What one patch edge is.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum EdgeLink {
    /// All control points of the edge are one point: no curve, no samples.
    #[default]
    Collapsed,
    /// The edge is boundary curve `curve`.
    Curve {
        /// Index into [`Topology::curves`].
        curve: u32,
        /// True when the edge runs against the curve's direction (the curve's parameter `t`
        /// is the edge's `1 - t`).
        reversed: bool,
    },
}

/// A distinct boundary curve: the first edge that has it, and how many edges use it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BoundaryCurve {
    /// Patch whose edge defines the curve and its direction.
    pub patch: u32,
    /// That patch's side.
    pub side: Side,
    /// Number of patch edges that are this curve: 1 for an open curve, 2 or more when shared.
    pub uses: u32,
}

impl BoundaryCurve {
    /// True when more than one patch edge uses the curve.
    pub fn is_shared(&self) -> bool {
        self.uses > 1
    }
}

/// Numbers of patch edges by kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct EdgeCounts {
    /// Edges whose curve is used by another edge too.
    pub shared: usize,
    /// Edges whose curve no other edge uses.
    pub open: usize,
    /// Edges collapsed to a point.
    pub collapsed: usize,
}

/// Why a topology could not be built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum TopologyError {
    /// The edge or curve buffer is too small; the numbers are what this model needs.
    BufferTooSmall {
        /// Entries needed in the edge buffer (one per patch).
        edges: usize,
        /// Entries needed in the curve buffer.
        curves: usize,
    },
}

impl fmt::Display for TopologyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TopologyError::BufferTooSmall { edges, curves } => write!(
                f,
                "topology buffers too small: need {edges} edge entries and {curves} curves"
            ),
        }
    }
}

impl core::error::Error for TopologyError {}

/// The edge-to-curve map of a [`PatchSet`], in caller storage.
///
/// ```
/// use spline_tess::{BoundaryCurve, EdgeLink, PatchHeader, PatchSet, Topology};
///
/// // Two bilinear patches side by side, sharing the edge x = 1.
/// let headers = [
///     PatchHeader { degree_u: 1, degree_v: 1, first_point: 0 },
///     PatchHeader { degree_u: 1, degree_v: 1, first_point: 4 },
/// ];
/// let points = [
///     [0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0],
///     [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [2.0, 0.0, 0.0], [2.0, 1.0, 0.0],
/// ];
/// let set = PatchSet::new(&headers, &points, None)?;
/// let mut edges = [[EdgeLink::Collapsed; 4]; 2];
/// let mut curves = [BoundaryCurve::default(); 8];
/// let topo = Topology::build(&set, &mut edges, &mut curves).unwrap();
/// let counts = topo.edge_counts();
/// assert_eq!((counts.shared, counts.open, counts.collapsed), (2, 6, 0));
/// assert_eq!(topo.curves().len(), 7);
/// # Ok::<(), spline_tess::PatchSetError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Topology<'a> {
    edges: &'a [[EdgeLink; 4]],
    curves: &'a [BoundaryCurve],
}

impl<'a> Topology<'a> {
    /// Finds the curves of `patches`. `edges` needs one entry per patch; `curves` one per
    /// distinct curve (at most four per patch). On `BufferTooSmall` the error says how much
    /// this model needs.
    pub fn build(
        patches: &PatchSet<'_>,
        edges: &'a mut [[EdgeLink; 4]],
        curves: &'a mut [BoundaryCurve],
    ) -> Result<Self, TopologyError> {
        let n = patches.len();
        if edges.len() < n {
            return Err(TopologyError::BufferTooSmall {
                edges: n,
                curves: count_curves(patches),
            });
        }
        let mut count = 0usize;
        for a in 0..n {
            let Some(pa) = patches.patch(a) else { continue };
            for side in Side::ALL {
                let link = if pa.is_collapsed(side) {
                    EdgeLink::Collapsed
                } else {
                    match find_earlier(patches, &edges[..n], a, &pa, side) {
                        Some((curve, reversed)) => {
                            if let Some(c) = curves.get_mut(curve as usize) {
                                c.uses += 1;
                            }
                            EdgeLink::Curve { curve, reversed }
                        }
                        None => {
                            let curve = count as u32;
                            if let Some(c) = curves.get_mut(count) {
                                *c = BoundaryCurve {
                                    patch: a as u32,
                                    side,
                                    uses: 1,
                                };
                            }
                            count += 1;
                            EdgeLink::Curve {
                                curve,
                                reversed: false,
                            }
                        }
                    }
                };
                edges[a][side.index()] = link;
            }
        }
        if count > curves.len() {
            return Err(TopologyError::BufferTooSmall {
                edges: n,
                curves: count,
            });
        }
        Ok(Topology {
            edges: &edges[..n],
            curves: &curves[..count],
        })
    }

    /// Per patch, the link of each side, indexed by [`Side::index`].
    pub fn edges(&self) -> &'a [[EdgeLink; 4]] {
        self.edges
    }

    /// The distinct curves.
    pub fn curves(&self) -> &'a [BoundaryCurve] {
        self.curves
    }

    /// The link of one patch side, or `None` past the last patch.
    pub fn link(&self, patch: usize, side: Side) -> Option<EdgeLink> {
        self.edges.get(patch).map(|e| e[side.index()])
    }

    /// How many edges are shared, open and collapsed.
    pub fn edge_counts(&self) -> EdgeCounts {
        let mut counts = EdgeCounts::default();
        for link in self.edges.iter().flatten() {
            match *link {
                EdgeLink::Collapsed => counts.collapsed += 1,
                EdgeLink::Curve { curve, .. } => {
                    if self.curves[curve as usize].is_shared() {
                        counts.shared += 1;
                    } else {
                        counts.open += 1;
                    }
                }
            }
        }
        counts
    }
}

/// The number of distinct curves, without storing anything (for error reports).
fn count_curves(patches: &PatchSet<'_>) -> usize {
    let mut count = 0;
    for (a, pa) in patches.iter().enumerate() {
        for side in Side::ALL {
            if pa.is_collapsed(side) {
                continue;
            }
            let seen = patches.iter().enumerate().take(a + 1).any(|(b, pb)| {
                Side::ALL
                    .iter()
                    .take(if b == a { side.index() } else { 4 })
                    .any(|&sb| !pb.is_collapsed(sb) && same_curve(&pa, side, &pb, sb).is_some())
            });
            if !seen {
                count += 1;
            }
        }
    }
    count
}

/// The curve of an earlier edge (an earlier patch, or an earlier side of this one) equal to
/// `(a, side)`, with the direction of `(a, side)` relative to it.
fn find_earlier(
    patches: &PatchSet<'_>,
    edges: &[[EdgeLink; 4]],
    a: usize,
    pa: &BezierPatch<'_>,
    side: Side,
) -> Option<(u32, bool)> {
    for (b, links) in edges.iter().enumerate().take(a + 1) {
        let pb = patches.patch(b)?;
        let sides = if b == a { side.index() } else { 4 };
        for &sb in &Side::ALL[..sides] {
            if let EdgeLink::Curve { curve, reversed } = links[sb.index()] {
                if let Some(flip) = same_curve(pa, side, &pb, sb) {
                    return Some((curve, reversed ^ flip));
                }
            }
        }
    }
    None
}

/// `Some(false)` when the edges are equal in order, `Some(true)` when reversed.
fn same_curve(pa: &BezierPatch<'_>, sa: Side, pb: &BezierPatch<'_>, sb: Side) -> Option<bool> {
    let n = pa.edge_len(sa);
    if pb.edge_len(sb) != n {
        return None;
    }
    let forward = (0..n).all(|k| pa.edge_point(sa, k) == pb.edge_point(sb, k));
    if forward {
        return Some(false);
    }
    let backward = (0..n).all(|k| pa.edge_point(sa, k) == pb.edge_point(sb, n - 1 - k));
    if backward {
        Some(true)
    } else {
        None
    }
}
