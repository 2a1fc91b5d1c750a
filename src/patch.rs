//! Rational Bezier patches: views over control-point slices, evaluation and bounds.
//!
//! A patch of degrees `(p, q)` has `(p + 1) * (q + 1)` control points stored u-major: point
//! `(i, j)`, with `i` along u and `j` along v, is `points[i * (q + 1) + j]`. Weights, when
//! present, use the same layout; without them the patch is polynomial (all weights 1).
//! Because a patch only borrows its slices, a model can live in a `static` in flash.

use core::fmt;

use glam::{Vec3, Vec4};

use crate::basis::{bernstein, bernstein_fixed, tensor_point, tensor_with_derivatives, Bezier};
use crate::bound::{Aabb, BoundingSphere};
use crate::frame::{frame, nudge, SurfacePoint};
use crate::math::{clamp_param, max, normalize};
use crate::MAX_DEGREE;

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

    /// The point at `(u, v)`; parameters are clamped to `[0, 1]` (NaN counts as 0). The same
    /// bits as [`evaluate`](Self::evaluate)'s position.
    pub fn position(&self, u: f32, v: f32) -> Vec3 {
        let (p, q) = (self.degree_u(), self.degree_v());
        let u = clamp_param(u, 0.0, 1.0);
        let v = clamp_param(v, 0.0, 1.0);
        if self.weights.is_none() {
            return self.position_direct(u, v);
        }
        let a = tensor_point(p, q, Bezier, Bezier, |i, j| self.homogeneous(i, j), u, v);
        Vec3::new(a.x, a.y, a.z) / a.w
    }

    /// The point at `(u, v)` in `[0, 1]²` as a direct sum over the Bernstein basis (for a
    /// rational patch, of homogeneous points): a third of the work of de Casteljau's triangle,
    /// and as accurate (a sum of convex combinations). A polynomial patch's
    /// [`position`](Self::position) is this; a rational one's is de Casteljau's (the many
    /// points of a deviation bound use this one).
    pub(crate) fn position_direct(&self, u: f32, v: f32) -> Vec3 {
        if let Some(pole) = self.pole_at(u, v) {
            return pole;
        }
        let (p, q) = (self.degree_u(), self.degree_v());
        if self.weights.is_none() {
            // The common degrees with their loops unrolled: the same sums, the same bits.
            match (p, q) {
                (3, 3) => return direct_sum::<4, 4>(self.points, u, v),
                (2, 2) => return direct_sum::<3, 3>(self.points, u, v),
                (1, 1) => return direct_sum::<2, 2>(self.points, u, v),
                _ => {}
            }
        }
        let (bu, bv) = (crate::basis::bernstein(p, u), crate::basis::bernstein(q, v));
        match self.weights {
            None => {
                let mut sum = Vec3::ZERO;
                for (i, &a) in bu.iter().enumerate().take(p + 1) {
                    let mut row = Vec3::ZERO;
                    for (j, &b) in bv.iter().enumerate().take(q + 1) {
                        row += Vec3::from_array(self.points[i * (q + 1) + j]) * b;
                    }
                    sum += row * a;
                }
                sum
            }
            Some(_) => {
                let mut sum = Vec4::ZERO;
                for (i, &a) in bu.iter().enumerate().take(p + 1) {
                    let mut row = Vec4::ZERO;
                    for (j, &b) in bv.iter().enumerate().take(q + 1) {
                        row += self.homogeneous(i, j) * b;
                    }
                    sum += row * a;
                }
                Vec3::new(sum.x, sum.y, sum.z) / sum.w
            }
        }
    }

    /// Position and partials `S_u`, `S_v` at `(u, v)` in `[0, 1]²` (for integrals over the
    /// patch; no special case at poles).
    pub(crate) fn position_and_partials(&self, u: f32, v: f32) -> (Vec3, Vec3, Vec3) {
        let ev = tensor_with_derivatives(
            self.degree_u(),
            self.degree_v(),
            Bezier,
            Bezier,
            |i, j| self.homogeneous(i, j),
            u,
            v,
        );
        let w = ev.a.w;
        let s = ev.a.truncate() / w;
        let su = (ev.a_u.truncate() - s * ev.a_u.w) / w;
        let sv = (ev.a_v.truncate() - s * ev.a_v.w) / w;
        (s, su, sv)
    }

    /// Position, partials and unit normal at `(u, v)`; parameters are clamped to `[0, 1]`
    /// (NaN counts as 0).
    ///
    /// The normal is never NaN or zero: at an edge collapsed to a point it is the limit of the
    /// normals approaching it; where even that is undefined (a corner where two edges collapse,
    /// or a patch flat to a line) it is taken a step of 1/1024 towards the middle of the
    /// square, then from the control net's diagonals, and at last `+z`.
    pub fn evaluate(&self, u: f32, v: f32) -> SurfacePoint {
        let u = clamp_param(u, 0.0, 1.0);
        let v = clamp_param(v, 0.0, 1.0);
        let f = self.frame_at(u, v);
        let normal = match f.normal {
            Some(n) => n,
            None => self
                .frame_at(nudge(u), nudge(v))
                .normal
                .or_else(|| self.net_normal())
                .unwrap_or(Vec3::Z),
        };
        SurfacePoint {
            position: f.position,
            partial_u: f.partial_u,
            partial_v: f.partial_v,
            normal,
        }
    }

    fn frame_at(&self, u: f32, v: f32) -> crate::frame::Frame {
        let (p, q) = (self.degree_u(), self.degree_v());
        match self.weights {
            None => {
                let ev = self.polynomial_derivatives(u, v);
                frame(
                    &ev,
                    u,
                    v,
                    |side| self.is_collapsed(side),
                    || self.polynomial_twist(u, v),
                )
            }
            Some(_) => {
                let ev = tensor_with_derivatives(
                    p,
                    q,
                    Bezier,
                    Bezier,
                    |i, j| self.homogeneous(i, j),
                    u,
                    v,
                );
                frame(&ev, u, v, |side| self.is_collapsed(side), || ev.a_uv)
            }
        }
    }

    /// The point of a collapsed edge when `(u, v)` lies on it: exactly its control point (a
    /// sum over the basis would be off by a rounding).
    fn pole_at(&self, u: f32, v: f32) -> Option<Vec3> {
        let side = if v == 0.0 {
            Side::V0
        } else if v == 1.0 {
            Side::V1
        } else if u == 0.0 {
            Side::U0
        } else if u == 1.0 {
            Side::U1
        } else {
            return None;
        };
        // A corner lies on two sides; either may be the collapsed one.
        let other = match side {
            Side::V0 | Side::V1 if u == 0.0 => Some(Side::U0),
            Side::V0 | Side::V1 if u == 1.0 => Some(Side::U1),
            _ => None,
        };
        [Some(side), other]
            .into_iter()
            .flatten()
            .find(|&s| self.is_collapsed(s))
            .map(|s| self.edge_point(s, 0).0)
    }

    /// Point and derivatives of a polynomial patch as direct sums over the Bernstein basis:
    /// a third of the work of de Casteljau's triangle. The partials sum the control net's
    /// differences, so along a row of equal control points (a collapsed edge) a partial is
    /// exactly zero, as the limit normal needs.
    fn polynomial_derivatives(&self, u: f32, v: f32) -> crate::basis::TensorEval {
        let (p, q) = (self.degree_u(), self.degree_v());
        let (mut s, s_u, s_v) = match (p, q) {
            // The common degrees with their loops unrolled: the same sums, the same bits.
            (3, 3) => derivative_sums(
                self.points,
                &bernstein_fixed::<4>(u),
                &bernstein_fixed::<4>(v),
                &bernstein_fixed::<3>(u),
                &bernstein_fixed::<3>(v),
            ),
            (2, 2) => derivative_sums(
                self.points,
                &bernstein_fixed::<3>(u),
                &bernstein_fixed::<3>(v),
                &bernstein_fixed::<2>(u),
                &bernstein_fixed::<2>(v),
            ),
            _ => derivative_sums(
                self.points,
                &bernstein(p, u)[..=p],
                &bernstein(q, v)[..=q],
                &bernstein(p - 1, u)[..p],
                &bernstein(q - 1, v)[..q],
            ),
        };
        if let Some(pole) = self.pole_at(u, v) {
            s = pole;
        }
        let (pf, qf) = (p as f32, q as f32);
        let h = |x: Vec3, w: f32| Vec4::new(x.x, x.y, x.z, w);
        crate::basis::TensorEval {
            a: h(s, 1.0),
            a_u: h(s_u * pf, 0.0),
            a_v: h(s_v * qf, 0.0),
            // Only a collapsed edge's limit normal needs the twist: `polynomial_twist`.
            a_uv: Vec4::ZERO,
        }
    }

    /// The twist `S_uv` of a polynomial patch, in the homogeneous form of
    /// [`polynomial_derivatives`](Self::polynomial_derivatives).
    fn polynomial_twist(&self, u: f32, v: f32) -> Vec4 {
        let (p, q) = (self.degree_u(), self.degree_v());
        let (du, dv) = (bernstein(p - 1, u), bernstein(q - 1, v));
        let at = |i: usize, j: usize| Vec3::from_array(self.points[i * (q + 1) + j]);
        let mut s_uv = Vec3::ZERO;
        for (i, &d_i) in du.iter().enumerate().take(p) {
            let mut row_v = Vec3::ZERO;
            for (j, &d_j) in dv.iter().enumerate().take(q) {
                row_v += (at(i + 1, j + 1) - at(i + 1, j) - at(i, j + 1) + at(i, j)) * d_j;
            }
            s_uv += row_v * d_i;
        }
        let (pf, qf) = (p as f32, q as f32);
        let t = s_uv * (pf * qf);
        Vec4::new(t.x, t.y, t.z, 0.0)
    }

    /// Normal of the control net's diagonals, oriented like `partial_u x partial_v`.
    fn net_normal(&self) -> Option<Vec3> {
        let (p, q) = (self.degree_u(), self.degree_v());
        let d1 = self.control_point(p, q) - self.control_point(0, 0);
        let d2 = self.control_point(0, q) - self.control_point(p, 0);
        normalize(d1.cross(d2))
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

/// The point of a polynomial patch of degrees `(M - 1, N - 1)` as a direct sum over the
/// Bernstein basis, with fixed bounds: exactly the operations of the general loop in
/// [`BezierPatch::position_direct`], unrolled.
#[inline(always)]
fn direct_sum<const M: usize, const N: usize>(points: &[[f32; 3]], u: f32, v: f32) -> Vec3 {
    let (bu, bv) = (
        crate::basis::bernstein_fixed::<M>(u),
        crate::basis::bernstein_fixed::<N>(v),
    );
    let Some(points) = points.get(..M * N) else {
        return Vec3::ZERO;
    };
    let mut sum = Vec3::ZERO;
    for (i, &a) in bu.iter().enumerate() {
        let mut row = Vec3::ZERO;
        for (&point, &b) in points[i * N..(i + 1) * N].iter().zip(&bv) {
            row += Vec3::from_array(point) * b;
        }
        sum += row * a;
    }
    sum
}

/// Point, `S_u / p` and `S_v / q` of a polynomial patch from the Bernstein values of its
/// degrees (`bu`, `bv`) and one less (`du`, `dv`): direct sums over the net and its
/// differences. With fixed-length arguments the loops unroll; the operations are the same.
#[inline(always)]
fn derivative_sums(
    points: &[[f32; 3]],
    bu: &[f32],
    bv: &[f32],
    du: &[f32],
    dv: &[f32],
) -> (Vec3, Vec3, Vec3) {
    let n = bv.len();
    let Some(points) = points.get(..bu.len() * n) else {
        return (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO);
    };
    let at = |i: usize, j: usize| Vec3::from_array(points[i * n + j]);
    let (mut s, mut s_u, mut s_v) = (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO);
    for (i, &b_i) in bu.iter().enumerate() {
        let (mut row, mut row_v) = (Vec3::ZERO, Vec3::ZERO);
        for (j, &b_j) in bv.iter().enumerate() {
            row += at(i, j) * b_j;
        }
        for (j, &d_j) in dv.iter().enumerate() {
            row_v += (at(i, j + 1) - at(i, j)) * d_j;
        }
        s += row * b_i;
        s_v += row_v * b_i;
    }
    for (i, &d_i) in du.iter().enumerate() {
        let mut row = Vec3::ZERO;
        for (j, &b_j) in bv.iter().enumerate() {
            row += (at(i + 1, j) - at(i, j)) * b_j;
        }
        s_u += row * d_i;
    }
    (s, s_u, s_v)
}
