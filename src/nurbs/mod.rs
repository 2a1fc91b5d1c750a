//! NURBS surfaces: views over knots, control points and weights; validation, evaluation and
//! exact decomposition into rational Bezier patches.
//!
//! Control points are u-major as in [`crate::patch`]: point `(i, j)` is
//! `points[i * count_v + j]` with `count_u = knots_u.len() - degree_u - 1` and likewise in v.
//! Knot vectors must be clamped (end knots of multiplicity exactly `degree + 1`), non-decreasing,
//! with interior multiplicities of at most `degree`.

use core::fmt;

use glam::{Vec3, Vec4};

use crate::basis::{tensor_point, tensor_with_derivatives};
use crate::frame::{frame, nudge, SurfacePoint};
use crate::math::{clamp_param, normalize};
use crate::patch::{check_degree, first_invalid_weight, first_non_finite, Side};
use crate::MAX_DEGREE;

mod decompose;

pub use decompose::{DecomposeError, DecompositionSize};

/// A parameter direction of a surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Direction {
    /// The first parameter.
    U,
    /// The second parameter.
    V,
}

impl fmt::Display for Direction {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Direction::U => "u",
            Direction::V => "v",
        })
    }
}

/// Why knots, control points and weights do not form a NURBS surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum NurbsError {
    /// A degree is 0 or above [`MAX_DEGREE`].
    DegreeOutOfRange {
        /// Which degree.
        direction: Direction,
        /// Its value.
        degree: usize,
    },
    /// Fewer than `2 * (degree + 1)` knots.
    TooFewKnots {
        /// Which knot vector.
        direction: Direction,
        /// Knots given.
        found: usize,
        /// Knots needed at least.
        needed: usize,
    },
    /// A knot is NaN or infinite.
    NonFiniteKnot {
        /// Which knot vector.
        direction: Direction,
        /// Index of the knot.
        index: usize,
    },
    /// `knots[index] < knots[index - 1]`.
    DecreasingKnots {
        /// Which knot vector.
        direction: Direction,
        /// Index of the smaller knot.
        index: usize,
    },
    /// The first or last `degree + 1` knots are not all equal.
    NotClamped {
        /// Which knot vector.
        direction: Direction,
    },
    /// A run of equal knots is longer than allowed: `degree + 1` at the ends, `degree` inside.
    KnotMultiplicity {
        /// Which knot vector.
        direction: Direction,
        /// Index of the first knot of the run.
        index: usize,
        /// Length of the run.
        multiplicity: usize,
    },
    /// The number of control points is not `count_u * count_v`.
    PointCount {
        /// Points the knot vectors call for.
        expected: usize,
        /// Points given.
        found: usize,
    },
    /// The number of weights differs from the number of control points.
    WeightCount {
        /// Weights expected.
        expected: usize,
        /// Weights given.
        found: usize,
    },
    /// A control point has a NaN or infinite coordinate.
    NonFinitePoint {
        /// Index of the point.
        index: usize,
    },
    /// A weight is zero, negative, NaN or infinite.
    InvalidWeight {
        /// Index of the weight.
        index: usize,
    },
    /// The surface is too large: its control points' bounding box has a diagonal `f32`
    /// cannot hold.
    ExtentOverflow,
}

impl fmt::Display for NurbsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            NurbsError::DegreeOutOfRange { direction, degree } => {
                write!(
                    f,
                    "degree in {direction} is {degree}, outside 1..={MAX_DEGREE}"
                )
            }
            NurbsError::TooFewKnots {
                direction,
                found,
                needed,
            } => write!(f, "{found} knots in {direction}, at least {needed} needed"),
            NurbsError::NonFiniteKnot { direction, index } => {
                write!(f, "knot {index} in {direction} is not finite")
            }
            NurbsError::DecreasingKnots { direction, index } => {
                write!(
                    f,
                    "knot {index} in {direction} is smaller than the one before"
                )
            }
            NurbsError::NotClamped { direction } => {
                write!(f, "knot vector in {direction} is not clamped")
            }
            NurbsError::KnotMultiplicity {
                direction,
                index,
                multiplicity,
            } => write!(
                f,
                "knot {index} in {direction} repeats {multiplicity} times, more than allowed"
            ),
            NurbsError::PointCount { expected, found } => {
                write!(f, "expected {expected} control points, found {found}")
            }
            NurbsError::WeightCount { expected, found } => {
                write!(f, "expected {expected} weights, found {found}")
            }
            NurbsError::NonFinitePoint { index } => {
                write!(f, "control point {index} is not finite")
            }
            NurbsError::InvalidWeight { index } => {
                write!(f, "weight {index} is not a finite positive number")
            }
            NurbsError::ExtentOverflow => {
                f.write_str("the surface is too large: its bounding box's diagonal overflows f32")
            }
        }
    }
}

impl core::error::Error for NurbsError {}

fn check_knots(direction: Direction, degree: usize, knots: &[f32]) -> Result<(), NurbsError> {
    if check_degree(degree).is_err() {
        return Err(NurbsError::DegreeOutOfRange { direction, degree });
    }
    let needed = 2 * (degree + 1);
    if knots.len() < needed {
        return Err(NurbsError::TooFewKnots {
            direction,
            found: knots.len(),
            needed,
        });
    }
    if let Some(index) = knots.iter().position(|k| !k.is_finite()) {
        return Err(NurbsError::NonFiniteKnot { direction, index });
    }
    if let Some(index) = (1..knots.len()).find(|&i| knots[i] < knots[i - 1]) {
        return Err(NurbsError::DecreasingKnots { direction, index });
    }
    let n = knots.len();
    if knots[degree] != knots[0] || knots[n - 1 - degree] != knots[n - 1] {
        return Err(NurbsError::NotClamped { direction });
    }
    let mut start = 0;
    while start < n {
        let mut end = start + 1;
        while end < n && knots[end] == knots[start] {
            end += 1;
        }
        let multiplicity = end - start;
        let at_end = start == 0 || end == n;
        let allowed = if at_end { degree + 1 } else { degree };
        if multiplicity > allowed {
            return Err(NurbsError::KnotMultiplicity {
                direction,
                index: start,
                multiplicity,
            });
        }
        start = end;
    }
    Ok(())
}

/// A rectangle of a surface's parameter domain.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ParamRect {
    /// Smallest u.
    pub u0: f32,
    /// Largest u.
    pub u1: f32,
    /// Smallest v.
    pub v0: f32,
    /// Largest v.
    pub v1: f32,
}

/// A NURBS surface borrowing its knots, control points and weights.
///
/// ```
/// use spline_tess::NurbsSurface;
///
/// // A quarter cylinder of radius 1 about x: degree 1 in u, rational degree 2 in v.
/// let knots_u = [0.0, 0.0, 1.0, 1.0];
/// let knots_v = [0.0, 0.0, 0.0, 1.0, 1.0, 1.0];
/// let points = [
///     [1.0, 1.0, 0.0], [1.0, 1.0, 1.0], [1.0, 0.0, 1.0],
///     [-1.0, 1.0, 0.0], [-1.0, 1.0, 1.0], [-1.0, 0.0, 1.0],
/// ];
/// let weights = [1.0, 1.0, 2.0, 1.0, 1.0, 2.0];
/// let s = NurbsSurface::new(1, 2, &knots_u, &knots_v, &points, Some(&weights))?;
/// let p = s.evaluate(0.5, 0.5).position;
/// assert!((p.y * p.y + p.z * p.z - 1.0).abs() < 1e-6);
/// # Ok::<(), spline_tess::NurbsError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct NurbsSurface<'a> {
    degree_u: u8,
    degree_v: u8,
    knots_u: &'a [f32],
    knots_v: &'a [f32],
    points: &'a [[f32; 3]],
    weights: Option<&'a [f32]>,
}

impl<'a> NurbsSurface<'a> {
    /// Validates and wraps the slices. `weights = None` means all weights are 1.
    pub fn new(
        degree_u: usize,
        degree_v: usize,
        knots_u: &'a [f32],
        knots_v: &'a [f32],
        points: &'a [[f32; 3]],
        weights: Option<&'a [f32]>,
    ) -> Result<Self, NurbsError> {
        check_knots(Direction::U, degree_u, knots_u)?;
        check_knots(Direction::V, degree_v, knots_v)?;
        let expected = (knots_u.len() - degree_u - 1) * (knots_v.len() - degree_v - 1);
        if points.len() != expected {
            return Err(NurbsError::PointCount {
                expected,
                found: points.len(),
            });
        }
        if let Some(index) = first_non_finite(points) {
            return Err(NurbsError::NonFinitePoint { index });
        }
        if crate::bound::extent_overflows(points) {
            return Err(NurbsError::ExtentOverflow);
        }
        if let Some(w) = weights {
            if w.len() != expected {
                return Err(NurbsError::WeightCount {
                    expected,
                    found: w.len(),
                });
            }
            if let Some(index) = first_invalid_weight(w) {
                return Err(NurbsError::InvalidWeight { index });
            }
        }
        Ok(NurbsSurface {
            degree_u: degree_u as u8,
            degree_v: degree_v as u8,
            knots_u,
            knots_v,
            points,
            weights,
        })
    }

    /// Degree in u.
    pub fn degree_u(&self) -> usize {
        self.degree_u as usize
    }

    /// Degree in v.
    pub fn degree_v(&self) -> usize {
        self.degree_v as usize
    }

    /// Knots in u.
    pub fn knots_u(&self) -> &'a [f32] {
        self.knots_u
    }

    /// Knots in v.
    pub fn knots_v(&self) -> &'a [f32] {
        self.knots_v
    }

    /// Control points, u-major.
    pub fn points(&self) -> &'a [[f32; 3]] {
        self.points
    }

    /// Weights, u-major, or `None` when all are 1.
    pub fn weights(&self) -> Option<&'a [f32]> {
        self.weights
    }

    /// Number of control points along u.
    pub fn count_u(&self) -> usize {
        self.knots_u.len() - self.degree_u() - 1
    }

    /// Number of control points along v.
    pub fn count_v(&self) -> usize {
        self.knots_v.len() - self.degree_v() - 1
    }

    /// The parameter domain `[u_p, u_n] x [v_q, v_m]`.
    pub fn domain(&self) -> ParamRect {
        let (p, q) = (self.degree_u(), self.degree_v());
        ParamRect {
            u0: self.knots_u[p],
            u1: self.knots_u[self.count_u()],
            v0: self.knots_v[q],
            v1: self.knots_v[self.count_v()],
        }
    }

    #[inline]
    fn homogeneous(&self, i: usize, j: usize) -> Vec4 {
        let k = i * self.count_v() + j;
        let p = self.points[k];
        let w = match self.weights {
            Some(w) => w[k],
            None => 1.0,
        };
        Vec4::new(p[0] * w, p[1] * w, p[2] * w, w)
    }

    /// The point at `(u, v)`, clamped into the domain (NaN counts as its start).
    pub fn position(&self, u: f32, v: f32) -> Vec3 {
        let (p, q) = (self.degree_u(), self.degree_v());
        let d = self.domain();
        let u = clamp_param(u, d.u0, d.u1);
        let v = clamp_param(v, d.v0, d.v1);
        let ku = span(self.knots_u, p, self.count_u(), u);
        let kv = span(self.knots_v, q, self.count_v(), v);
        let a = tensor_point(
            p,
            q,
            &self.knots_u[ku + 1 - p..=ku + p],
            &self.knots_v[kv + 1 - q..=kv + q],
            |i, j| self.homogeneous(ku - p + i, kv - q + j),
            u,
            v,
        );
        Vec3::new(a.x, a.y, a.z) / a.w
    }

    /// Position, partials (with respect to the knot parameters) and unit normal at `(u, v)`,
    /// clamped into the domain. The normal follows the rules of
    /// [`BezierPatch::evaluate`](crate::BezierPatch::evaluate).
    pub fn evaluate(&self, u: f32, v: f32) -> SurfacePoint {
        let d = self.domain();
        let u = clamp_param(u, d.u0, d.u1);
        let v = clamp_param(v, d.v0, d.v1);
        let s = (u - d.u0) / (d.u1 - d.u0);
        let t = (v - d.v0) / (d.v1 - d.v0);
        let f = self.frame_at(u, v, s, t);
        let normal = match f.normal {
            Some(n) => n,
            None => {
                let (s2, t2) = (nudge(s), nudge(t));
                let u2 = d.u0 + s2 * (d.u1 - d.u0);
                let v2 = d.v0 + t2 * (d.v1 - d.v0);
                self.frame_at(u2, v2, s2, t2)
                    .normal
                    .or_else(|| self.net_normal())
                    .unwrap_or(Vec3::Z)
            }
        };
        SurfacePoint {
            position: f.position,
            partial_u: f.partial_u,
            partial_v: f.partial_v,
            normal,
        }
    }

    fn frame_at(&self, u: f32, v: f32, s: f32, t: f32) -> crate::frame::Frame {
        let (p, q) = (self.degree_u(), self.degree_v());
        let ku = span(self.knots_u, p, self.count_u(), u);
        let kv = span(self.knots_v, q, self.count_v(), v);
        let ev = tensor_with_derivatives(
            p,
            q,
            &self.knots_u[ku + 1 - p..=ku + p],
            &self.knots_v[kv + 1 - q..=kv + q],
            |i, j| self.homogeneous(ku - p + i, kv - q + j),
            u,
            v,
        );
        frame(&ev, s, t, |side| self.is_collapsed(side), || ev.a_uv)
    }

    /// True when every control point along `side` of the surface is the same point.
    fn is_collapsed(&self, side: Side) -> bool {
        let (nu, nv) = (self.count_u(), self.count_v());
        let at = |k: usize| {
            let (i, j) = match side {
                Side::V0 => (k, 0),
                Side::U1 => (nu - 1, k),
                Side::V1 => (k, nv - 1),
                Side::U0 => (0, k),
            };
            self.points[i * nv + j]
        };
        let n = match side {
            Side::V0 | Side::V1 => nu,
            Side::U0 | Side::U1 => nv,
        };
        (1..n).all(|k| at(k) == at(0))
    }

    fn net_normal(&self) -> Option<Vec3> {
        let (nu, nv) = (self.count_u(), self.count_v());
        let at = |i: usize, j: usize| Vec3::from_array(self.points[i * nv + j]);
        let d1 = at(nu - 1, nv - 1) - at(0, 0);
        let d2 = at(0, nv - 1) - at(nu - 1, 0);
        normalize(d1.cross(d2))
    }
}

/// The index `k` of the non-empty span `[knots[k], knots[k+1])` holding `t` (the last span for
/// the domain's end), for a validated knot vector with `count` control points.
fn span(knots: &[f32], degree: usize, count: usize, t: f32) -> usize {
    let idx = knots[..=count].partition_point(|&x| x <= t);
    // t in [knots[degree], knots[count]] gives idx in degree + 1..=count + 1.
    idx.saturating_sub(1).clamp(degree, count - 1)
}
