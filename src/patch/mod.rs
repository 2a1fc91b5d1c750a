//! Rational Bezier patches: views over control-point slices, their bounds, and (in `eval`) their
//! evaluation.
//!
//! A patch of degrees `(p, q)` has `(p + 1) * (q + 1)` control points stored u-major: point
//! `(i, j)`, with `i` along u and `j` along v, is `points[i * (q + 1) + j]`. Weights, when
//! present, use the same layout; without them the patch is polynomial (all weights 1).
//! Because a patch only borrows its slices, a model can live in a `static` in flash.

use core::fmt;

use glam::{Vec3, Vec4};

use crate::bound::{Aabb, BoundingSphere};
use crate::math::max;
use crate::MAX_DEGREE;

mod eval;

/// One of the four boundary edges of a patch's unit parameter square.
///
/// Each edge is traversed in the direction of its own parameter: `V0` and `V1` along
/// increasing u, `U0` and `U1` along increasing v.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Side {
    /// The edge `v = 0`.
    #[default]
    V0,
    /// The edge `u = 1`.
    U1,
    /// The edge `v = 1`.
    V1,
    /// The edge `u = 0`.
    U0,
}

impl Side {
    /// All four sides, in the order `V0, U1, V1, U0` (counter-clockwise in the (u,v) square).
    pub const ALL: [Side; 4] = [Side::V0, Side::U1, Side::V1, Side::U0];

    /// Position of this side in [`Side::ALL`].
    pub const fn index(self) -> usize {
        self as usize
    }
}

/// Why a control net cannot form a patch.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum PatchError {
    /// A degree is 0 or above [`MAX_DEGREE`].
    DegreeOutOfRange {
        /// The offending degree.
        degree: usize,
    },
    /// The number of control points is not `(p + 1) * (q + 1)`.
    PointCount {
        /// Points the degrees call for.
        expected: usize,
        /// Points given.
        found: usize,
    },
    /// The number of weights differs from the number of control points.
    WeightCount {
        /// Weights the degrees call for.
        expected: usize,
        /// Weights given.
        found: usize,
    },
    /// A control point has a NaN or infinite coordinate.
    NonFinitePoint {
        /// Index of the point in the slice.
        index: usize,
    },
    /// A weight is zero, negative, NaN or infinite.
    InvalidWeight {
        /// Index of the weight in the slice.
        index: usize,
    },
}

impl fmt::Display for PatchError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            PatchError::DegreeOutOfRange { degree } => {
                write!(f, "degree {degree} is outside 1..={MAX_DEGREE}")
            }
            PatchError::PointCount { expected, found } => {
                write!(f, "expected {expected} control points, found {found}")
            }
            PatchError::WeightCount { expected, found } => {
                write!(f, "expected {expected} weights, found {found}")
            }
            PatchError::NonFinitePoint { index } => {
                write!(f, "control point {index} is not finite")
            }
            PatchError::InvalidWeight { index } => {
                write!(f, "weight {index} is not a finite positive number")
            }
        }
    }
}

impl core::error::Error for PatchError {}

/// Checks a degree against `1..=MAX_DEGREE`.
pub(crate) fn check_degree(degree: usize) -> Result<(), PatchError> {
    if (1..=MAX_DEGREE).contains(&degree) {
        Ok(())
    } else {
        Err(PatchError::DegreeOutOfRange { degree })
    }
}

/// Index of the first point with a NaN or infinite coordinate.
pub(crate) fn first_non_finite(points: &[[f32; 3]]) -> Option<usize> {
    points
        .iter()
        .position(|p| !(p[0].is_finite() && p[1].is_finite() && p[2].is_finite()))
}

/// Index of the first weight that is not finite and positive.
pub(crate) fn first_invalid_weight(weights: &[f32]) -> Option<usize> {
    weights.iter().position(|w| !(w.is_finite() && *w > 0.0))
}

/// Checks a control net's points and (optional) weights.
pub(crate) fn check_net(points: &[[f32; 3]], weights: Option<&[f32]>) -> Result<(), PatchError> {
    if let Some(index) = first_non_finite(points) {
        return Err(PatchError::NonFinitePoint { index });
    }
    if let Some(index) = weights.and_then(first_invalid_weight) {
        return Err(PatchError::InvalidWeight { index });
    }
    Ok(())
}

/// A rational Bezier patch borrowing its control net.
///
/// ```
/// use spline_tess::BezierPatch;
///
/// // A bilinear patch: the unit square in the plane z = 0.
/// let points = [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]];
/// let patch = BezierPatch::new(1, 1, &points)?;
/// let p = patch.evaluate(0.25, 0.5);
/// assert_eq!(p.position.to_array(), [0.25, 0.5, 0.0]);
/// assert_eq!(p.normal.to_array(), [0.0, 0.0, 1.0]);
/// # Ok::<(), spline_tess::PatchError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BezierPatch<'a> {
    degree_u: u8,
    degree_v: u8,
    points: &'a [[f32; 3]],
    weights: Option<&'a [f32]>,
}

impl<'a> BezierPatch<'a> {
    /// A polynomial patch (all weights 1) of degrees `(degree_u, degree_v)`.
    pub fn new(
        degree_u: usize,
        degree_v: usize,
        points: &'a [[f32; 3]],
    ) -> Result<Self, PatchError> {
        Self::checked(degree_u, degree_v, points, None)
    }

    /// A rational patch; `weights` has the layout of `points`.
    pub fn new_rational(
        degree_u: usize,
        degree_v: usize,
        points: &'a [[f32; 3]],
        weights: &'a [f32],
    ) -> Result<Self, PatchError> {
        Self::checked(degree_u, degree_v, points, Some(weights))
    }

    fn checked(
        degree_u: usize,
        degree_v: usize,
        points: &'a [[f32; 3]],
        weights: Option<&'a [f32]>,
    ) -> Result<Self, PatchError> {
        check_degree(degree_u)?;
        check_degree(degree_v)?;
        let expected = (degree_u + 1) * (degree_v + 1);
        if points.len() != expected {
            return Err(PatchError::PointCount {
                expected,
                found: points.len(),
            });
        }
        if let Some(w) = weights {
            if w.len() != expected {
                return Err(PatchError::WeightCount {
                    expected,
                    found: w.len(),
                });
            }
        }
        check_net(points, weights)?;
        Ok(Self::trusted(degree_u, degree_v, points, weights))
    }

    /// A patch from slices already validated by the caller (lengths, finiteness, weights).
    pub(crate) fn trusted(
        degree_u: usize,
        degree_v: usize,
        points: &'a [[f32; 3]],
        weights: Option<&'a [f32]>,
    ) -> Self {
        BezierPatch {
            degree_u: degree_u as u8,
            degree_v: degree_v as u8,
            points,
            weights,
        }
    }

    /// Degree in u.
    pub fn degree_u(&self) -> usize {
        self.degree_u as usize
    }

    /// Degree in v.
    pub fn degree_v(&self) -> usize {
        self.degree_v as usize
    }

    /// The control points, u-major.
    pub fn points(&self) -> &'a [[f32; 3]] {
        self.points
    }

    /// The weights, u-major, or `None` for a polynomial patch.
    pub fn weights(&self) -> Option<&'a [f32]> {
        self.weights
    }

    /// Index of control point `(i, j)` in [`points`](Self::points).
    #[inline]
    pub fn index(&self, i: usize, j: usize) -> usize {
        i * (self.degree_v as usize + 1) + j
    }

    /// Control point `(i, j)`.
    #[inline]
    pub fn control_point(&self, i: usize, j: usize) -> Vec3 {
        Vec3::from_array(self.points[self.index(i, j)])
    }

    /// Weight of control point `(i, j)` (1 for a polynomial patch).
    #[inline]
    pub fn weight(&self, i: usize, j: usize) -> f32 {
        match self.weights {
            Some(w) => w[self.index(i, j)],
            None => 1.0,
        }
    }

    /// Homogeneous control point `(w x, w y, w z, w)`.
    #[inline]
    fn homogeneous(&self, i: usize, j: usize) -> Vec4 {
        let k = self.index(i, j);
        let p = self.points[k];
        match self.weights {
            Some(w) => {
                let w = w[k];
                Vec4::new(p[0] * w, p[1] * w, p[2] * w, w)
            }
            None => Vec4::new(p[0], p[1], p[2], 1.0),
        }
    }

    /// Number of control points along `side`.
    pub fn edge_len(&self, side: Side) -> usize {
        match side {
            Side::V0 | Side::V1 => self.degree_u as usize + 1,
            Side::U0 | Side::U1 => self.degree_v as usize + 1,
        }
    }

    /// Control point and weight number `k` along `side`, in the side's own direction.
    pub fn edge_point(&self, side: Side, k: usize) -> (Vec3, f32) {
        let (i, j) = match side {
            Side::V0 => (k, 0),
            Side::U1 => (self.degree_u as usize, k),
            Side::V1 => (k, self.degree_v as usize),
            Side::U0 => (0, k),
        };
        (self.control_point(i, j), self.weight(i, j))
    }

    /// True when every control point of `side` is the same point: the edge is collapsed.
    pub fn is_collapsed(&self, side: Side) -> bool {
        let (first, _) = self.edge_point(side, 0);
        (1..self.edge_len(side)).all(|k| self.edge_point(side, k).0 == first)
    }

    /// Axis-aligned box containing the patch.
    pub fn aabb(&self) -> Aabb {
        // A validated patch has at least four points.
        let b = Aabb::of_points(self.points).unwrap_or(Aabb {
            min: Vec3::ZERO,
            max: Vec3::ZERO,
        });
        let pad = Vec3::splat(self.rounding());
        Aabb {
            min: b.min - pad,
            max: b.max + pad,
        }
    }

    /// Sphere containing the patch.
    pub fn bounding_sphere(&self) -> BoundingSphere {
        let s = BoundingSphere::of_points(self.points).unwrap_or(BoundingSphere {
            center: Vec3::ZERO,
            radius: 0.0,
        });
        BoundingSphere {
            radius: s.radius + 2.0 * self.rounding(),
            ..s
        }
    }

    /// How far a computed point can stray outside the control points' hull per coordinate:
    /// every evaluation is a sum of convex combinations of them, off by a few roundings of
    /// the largest coordinate.
    fn rounding(&self) -> f32 {
        let big = self.points.iter().fold(0.0f32, |m, p| {
            max(max(max(m, p[0].abs()), p[1].abs()), p[2].abs())
        });
        let n = (2 * (self.degree_u() + self.degree_v()) + 8) as f32;
        n * f32::EPSILON * big
    }
}
