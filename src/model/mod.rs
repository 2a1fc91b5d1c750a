//! A model: a set of patches over flat slices, plus the topology of their edges.
//!
//! [`PatchSet`] keeps every patch's control points in one slice (and weights in another), with a
//! small [`PatchHeader`] per patch, so a whole model can be three `static` arrays in flash.
//! [`Topology`] records, for each patch edge, which boundary curve it is.

mod split;
mod topology;

use core::fmt;

use crate::bound::Aabb;
use crate::patch::{check_degree, check_net, BezierPatch, PatchError};

pub use split::{SplitError, SplitSize};
pub use topology::{BoundaryCurve, EdgeCounts, EdgeLink, Topology, TopologyError};

/// Where one patch's control net lies in a [`PatchSet`]'s point slice.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PatchHeader {
    /// Degree in u.
    pub degree_u: u8,
    /// Degree in v.
    pub degree_v: u8,
    /// Index of the patch's first control point; its `(degree_u + 1) * (degree_v + 1)` points
    /// follow, u-major.
    pub first_point: u32,
}

impl PatchHeader {
    /// Number of control points of the patch.
    pub const fn point_count(&self) -> usize {
        (self.degree_u as usize + 1) * (self.degree_v as usize + 1)
    }
}

/// Why slices do not form a [`PatchSet`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum PatchSetError {
    /// A patch's points run past the end of the point slice.
    PointsOutOfRange {
        /// Index of the patch.
        patch: usize,
    },
    /// The weight slice is not as long as the point slice.
    WeightCount {
        /// Weights expected.
        expected: usize,
        /// Weights given.
        found: usize,
    },
    /// The box of the control points has a diagonal `f32` cannot hold: bounds and
    /// tolerances would overflow.
    ExtentOverflow,
    /// A patch is invalid.
    Patch {
        /// Index of the patch.
        patch: usize,
        /// What is wrong with it (indices are within the patch).
        error: PatchError,
    },
}

impl fmt::Display for PatchSetError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PatchSetError::PointsOutOfRange { patch } => {
                write!(f, "patch {patch}: control points run past the point slice")
            }
            PatchSetError::WeightCount { expected, found } => {
                write!(f, "expected {expected} weights, found {found}")
            }
            PatchSetError::Patch { patch, error } => write!(f, "patch {patch}: {error}"),
            PatchSetError::ExtentOverflow => {
                f.write_str("the model is too large: its bounding box's diagonal overflows f32")
            }
        }
    }
}

impl core::error::Error for PatchSetError {}

/// Validated patches over shared point and weight slices.
///
/// ```
/// use spline_tess::{PatchHeader, PatchSet};
///
/// static HEADERS: [PatchHeader; 1] = [PatchHeader { degree_u: 1, degree_v: 1, first_point: 0 }];
/// static POINTS: [[f32; 3]; 4] = [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 1.0]];
///
/// let set = PatchSet::new(&HEADERS, &POINTS, None)?;
/// let patch = set.patch(0).unwrap();
/// assert_eq!(patch.position(1.0, 1.0).to_array(), [1.0, 1.0, 1.0]);
/// # Ok::<(), spline_tess::PatchSetError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PatchSet<'a> {
    headers: &'a [PatchHeader],
    points: &'a [[f32; 3]],
    weights: Option<&'a [f32]>,
}

impl<'a> PatchSet<'a> {
    /// A set of patches already validated by [`new`](Self::new) (the same slices, which the
    /// caller kept unchanged): no check again.
    #[cfg(all(feature = "std", not(target_os = "none")))]
    pub(crate) fn validated(
        headers: &'a [PatchHeader],
        points: &'a [[f32; 3]],
        weights: Option<&'a [f32]>,
    ) -> Self {
        PatchSet {
            headers,
            points,
            weights,
        }
    }

    /// Validates every patch: degrees, ranges, finite points and positive weights, and the
    /// model's extent (a bounding box whose diagonal `f32` holds).
    /// `weights = None` means all weights are 1.
    pub fn new(
        headers: &'a [PatchHeader],
        points: &'a [[f32; 3]],
        weights: Option<&'a [f32]>,
    ) -> Result<Self, PatchSetError> {
        if let Some(w) = weights {
            if w.len() != points.len() {
                return Err(PatchSetError::WeightCount {
                    expected: points.len(),
                    found: w.len(),
                });
            }
        }
        for (patch, h) in headers.iter().enumerate() {
            let wrap = |error| PatchSetError::Patch { patch, error };
            check_degree(h.degree_u as usize).map_err(wrap)?;
            check_degree(h.degree_v as usize).map_err(wrap)?;
            let start = h.first_point as usize;
            let end = start + h.point_count();
            if end > points.len() {
                return Err(PatchSetError::PointsOutOfRange { patch });
            }
            check_net(&points[start..end], weights.map(|w| &w[start..end])).map_err(wrap)?;
        }
        if crate::bound::extent_overflows(points) {
            return Err(PatchSetError::ExtentOverflow);
        }
        Ok(Self::trusted(headers, points, weights))
    }

    /// Slices already validated by the crate.
    pub(crate) fn trusted(
        headers: &'a [PatchHeader],
        points: &'a [[f32; 3]],
        weights: Option<&'a [f32]>,
    ) -> Self {
        PatchSet {
            headers,
            points,
            weights,
        }
    }

    /// Number of patches.
    pub fn len(&self) -> usize {
        self.headers.len()
    }

    /// True when there are no patches.
    pub fn is_empty(&self) -> bool {
        self.headers.is_empty()
    }

    /// The headers.
    pub fn headers(&self) -> &'a [PatchHeader] {
        self.headers
    }

    /// All control points.
    pub fn points(&self) -> &'a [[f32; 3]] {
        self.points
    }

    /// All weights, or `None` when all are 1.
    pub fn weights(&self) -> Option<&'a [f32]> {
        self.weights
    }

    /// Patch `index`, or `None` past the end.
    pub fn patch(&self, index: usize) -> Option<BezierPatch<'a>> {
        let h = self.headers.get(index)?;
        let start = h.first_point as usize;
        let end = start + h.point_count();
        Some(BezierPatch::trusted(
            h.degree_u as usize,
            h.degree_v as usize,
            &self.points[start..end],
            self.weights.map(|w| &w[start..end]),
        ))
    }

    /// The patches in order.
    pub fn iter(&self) -> impl Iterator<Item = BezierPatch<'a>> + '_ {
        (0..self.len()).filter_map(move |i| self.patch(i))
    }

    /// Box containing every patch, or `None` for an empty set.
    pub fn aabb(&self) -> Option<Aabb> {
        self.iter().map(|p| p.aabb()).reduce(Aabb::union)
    }
}

/// Patches together with the topology of their edges.
#[derive(Clone, Copy, Debug)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Model<'a> {
    /// The patches.
    pub patches: PatchSet<'a>,
    /// Which boundary curve each patch edge is.
    pub topology: Topology<'a>,
}

impl<'a> Model<'a> {
    /// Builds the topology of `patches` into the caller's storage (see [`Topology::build`]).
    pub fn build(
        patches: PatchSet<'a>,
        edges: &'a mut [[EdgeLink; 4]],
        curves: &'a mut [BoundaryCurve],
    ) -> Result<Self, TopologyError> {
        let topology = Topology::build(&patches, edges, curves)?;
        Ok(Model { patches, topology })
    }
}
