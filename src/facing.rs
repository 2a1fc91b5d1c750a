//! Back-patch culling: a cone that holds every normal of a patch, and the test that a patch
//! faces away from the eye.
//!
//! # The normal cone
//!
//! For a patch `S = X / w` of degrees `(p, q)` (`X` the homogeneous net `w P`, `w > 0`), the
//! partials are `S_u = (w X_u - w_u X) / w²` and likewise in `v`, so
//!
//! ```text
//! S_u × S_v = (1 / w³) · M,    M = w (X_u × X_v) + w_v (X × X_u) + w_u (X_v × X)
//! ```
//!
//! (the `w_u w_v X × X` term vanishes). `M` points the way of the normal wherever it is not
//! zero, and it is a polynomial of degrees `(3p - 1, 3q - 1)`: each of its three terms is a
//! product of three tensor-product Bernstein polynomials (`X_u` has the net `p ΔX` of degrees
//! `(p - 1, q)`, and so on), and a product of Bernstein polynomials is a Bernstein polynomial
//! of the summed degree with coefficients
//!
//! ```text
//! B_i^a B_j^b B_k^c = C(a,i) C(b,j) C(c,k) / C(a+b+c, i+j+k) · B_{i+j+k}^{a+b+c}.
//! ```
//!
//! So `M`'s Bernstein coefficient `(A, B)` is, up to the positive factor
//! `p q / (C(3p-1, A) C(3q-1, B))` that does not change its direction, the sum over index
//! triples summing to `(A, B)` of the binomial products times the three terms' cross products.
//! `M(u, v)` is a combination of these coefficients with non-negative weights (the Bernstein
//! basis), so it lies in their conical hull. For a polynomial patch (`w = 1`) only the first
//! term is left and the degrees are `(2p - 1, 2q - 1)`.
//!
//! [`NormalCone::of`] takes the coefficients' unit directions, an axis (their normalised
//! mean), and the half-angle `α`: the largest angle between the axis and a coefficient, each
//! widened by the coefficient's rounding (below). Every `M(u, v)`, so every normal of the
//! patch, is within `α` of the axis (a circular cone of half-angle below 90° is convex).
//! There is no cone when `α` reaches 90°, when a coefficient's rounding could be as large as
//! the coefficient (its direction is unknown), or for degrees above 3.
//!
//! **Rounding.** Each coefficient is a sum of `n` products of three factors, each factor a
//! difference or product of `f32` inputs (one rounding each). The computed coefficient is
//! within `e = 4 (n + 16) ε Σ|c| |a| |b| |d|` of the exact one (`ε` the `f32` epsilon; a
//! generous count of the roundings of the inputs, the cross product, the scaling and the
//! sum), so its direction is within `asin(e / |m|) ≤ 2 e / |m|` of the computed one.
//!
//! # Facing away
//!
//! A patch faces away from an eye at `E` when `(P - E) · n ≥ 0` for every point `P` of the
//! patch and every outward normal `n` at it. With `n` within `α` of the axis `a`, it is
//! enough that the angle between `P - E` and `a` is at most `90° - α`, that is
//! `(P - E) · a ≥ |P - E| sin α`. Those `P - E` form a convex cone, and the patch lies in the
//! convex hull of its control points (positive weights), so the test on the control points
//! decides for the whole patch ([`NormalCone::faces_away_from`]). For a parallel projection
//! the rays share the direction `d`: `d · a ≥ sin α` ([`NormalCone::faces_away_along`]).
//!
//! Which way is outward is a property of the whole closed surface; the bake works it out once
//! (see `bake`'s orientation rule), and a tessellator culls with it (its `cull` module).

use glam::Vec3;

use crate::math::{length, normalize, sqrt};
use crate::patch::BezierPatch;

/// Largest degree whose normal cone is computed.
const MAX_CONE_DEGREE: usize = 3;

/// Taken off the cosine of every cone's half-angle (about that angle in radians near 90°, and
/// more elsewhere), for the rounding of the axis, the cosines and the sine.
const ANGLE_MARGIN: f32 = 1e-4;

/// A cone of directions that holds every normal `S_u × S_v` of a patch (see the module docs).
///
/// ```
/// use spline_tess::{BezierPatch, NormalCone, Vec3};
///
/// // A bilinear square in the plane z = 0: its normals all point along +z.
/// let points = [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]];
/// let patch = BezierPatch::new(1, 1, &points).unwrap();
/// let cone = NormalCone::of(&patch).unwrap();
/// assert!(cone.axis().dot(Vec3::Z) > 0.999);
/// // Seen from below, the square shows its back: every normal points away from the eye.
/// assert!(cone.faces_away_from(&points, Vec3::new(0.5, 0.5, -3.0)));
/// assert!(!cone.faces_away_from(&points, Vec3::new(0.5, 0.5, 3.0)));
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct NormalCone {
    axis: [f32; 3],
    /// Sine of the half-angle (margin included).
    sin_half_angle: f32,
}

/// `C(n, k)` for the small degrees here.
fn binomial(n: usize, k: usize) -> f32 {
    let mut c = 1.0f32;
    for i in 0..k {
        c = c * (n - i) as f32 / (i + 1) as f32;
    }
    c
}

/// Homogeneous point `(w P, w)` of control point `(i, j)`.
fn homogeneous(patch: &BezierPatch<'_>, i: usize, j: usize) -> (Vec3, f32) {
    let w = patch.weight(i, j);
    (patch.control_point(i, j) * w, w)
}

/// Coefficient `(a, b)` of `M` (see the module docs), with its rounding bound.
fn coefficient(patch: &BezierPatch<'_>, a: usize, b: usize) -> (Vec3, f32) {
    let (p, q) = (patch.degree_u(), patch.degree_v());
    let du = |i: usize, j: usize| {
        let (x1, w1) = homogeneous(patch, i + 1, j);
        let (x0, w0) = homogeneous(patch, i, j);
        (x1 - x0, w1 - w0)
    };
    let dv = |i: usize, j: usize| {
        let (x1, w1) = homogeneous(patch, i, j + 1);
        let (x0, w0) = homogeneous(patch, i, j);
        (x1 - x0, w1 - w0)
    };
    let (mut sum, mut size, mut terms) = (Vec3::ZERO, 0.0f32, 0usize);
    if patch.weights().is_none() {
        // X_u × X_v: degrees (p - 1, q) and (p, q - 1).
        for i in a.saturating_sub(p)..=a.min(p - 1) {
            let k = a - i;
            for j in b.saturating_sub(q - 1)..=b.min(q) {
                let l = b - j;
                let c = binomial(p - 1, i) * binomial(p, k) * binomial(q, j) * binomial(q - 1, l);
                let (x, y) = (du(i, j).0, dv(k, l).0);
                sum += x.cross(y) * c;
                size += c * length(x) * length(y);
                terms += 1;
            }
        }
    } else {
        // Three factors: the homogeneous net (p, q), the u-differences (p - 1, q), the
        // v-differences (p, q - 1); index triples summing to (a, b).
        for i1 in 0..=p.min(a) {
            for i2 in 0..=(p - 1).min(a - i1) {
                let i3 = a - i1 - i2;
                if i3 > p {
                    continue;
                }
                for j1 in 0..=q.min(b) {
                    for j2 in 0..=q.min(b - j1) {
                        let j3 = b - j1 - j2;
                        if j3 >= q {
                            continue;
                        }
                        let c = binomial(p, i1)
                            * binomial(p - 1, i2)
                            * binomial(p, i3)
                            * binomial(q, j1)
                            * binomial(q, j2)
                            * binomial(q - 1, j3);
                        let (x, w) = homogeneous(patch, i1, j1);
                        let (xu, wu) = du(i2, j2);
                        let (xv, wv) = dv(i3, j3);
                        // w X_u × X_v + w_v X × X_u + w_u X_v × X, all from the same triple.
                        let m = xu.cross(xv) * w + x.cross(xu) * wv + xv.cross(x) * wu;
                        sum += m * c;
                        let (lx, lu, lv) = (length(x), length(xu), length(xv));
                        size += c * (w.abs() * lu * lv + wv.abs() * lx * lu + wu.abs() * lv * lx);
                        terms += 3;
                    }
                }
            }
        }
    }
    let rounding = 4.0 * (terms as f32 + 16.0) * f32::EPSILON * size;
    (sum, rounding)
}

impl NormalCone {
    /// The cone of `patch`'s normals `S_u × S_v`, or `None` where it would be 90° wide or more
    /// (or the patch's degree is above 3, or a weight is not positive).
    pub fn of(patch: &BezierPatch<'_>) -> Option<NormalCone> {
        let (p, q) = (patch.degree_u(), patch.degree_v());
        if p == 0 || q == 0 || p > MAX_CONE_DEGREE || q > MAX_CONE_DEGREE {
            return None;
        }
        if let Some(w) = patch.weights() {
            if w.iter().any(|&w| !(w > 0.0 && w.is_finite())) {
                return None;
            }
        }
        let (na, nb) = match patch.weights() {
            None => (2 * p - 1, 2 * q - 1),
            Some(_) => (3 * p - 1, 3 * q - 1),
        };
        // First pass: the axis, the mean of the coefficients' directions.
        let mut mean = Vec3::ZERO;
        for a in 0..=na {
            for b in 0..=nb {
                let (m, e) = coefficient(patch, a, b);
                let len = length(m);
                if !len.is_finite() || !e.is_finite() {
                    return None;
                }
                if len == 0.0 && e == 0.0 {
                    continue; // an exact zero (a collapsed edge): no direction to hold
                }
                if len <= e {
                    return None;
                }
                mean += m / len;
            }
        }
        let axis = normalize(mean)?;
        // Second pass: the widest coefficient, widened by its rounding `δ`, as the cosine of
        // the half-angle: cos(θ + δ) ≥ cos θ (1 - δ²/2) - sin θ δ for θ, δ ≥ 0 with
        // cos θ ≥ 0 (no trigonometry, and a lower bound on the cosine is a wider cone).
        let mut cos_half = 1.0f32;
        for a in 0..=na {
            for b in 0..=nb {
                let (m, e) = coefficient(patch, a, b);
                let len = length(m);
                if len == 0.0 && e == 0.0 {
                    continue;
                }
                let cos = (axis.dot(m) / len).min(1.0);
                if cos <= 0.0 || cos.is_nan() {
                    return None;
                }
                let sin = sqrt((1.0 - cos * cos).max(0.0));
                let delta = 2.0 * e / len;
                cos_half = cos_half.min(cos * (1.0 - 0.5 * delta * delta) - sin * delta);
            }
        }
        // The margin (an angle of about `ANGLE_MARGIN` near 90°, more elsewhere).
        let cos_half = cos_half - ANGLE_MARGIN;
        (cos_half > ANGLE_MARGIN).then(|| NormalCone {
            axis: axis.to_array(),
            sin_half_angle: sqrt((1.0 - cos_half * cos_half).max(0.0)),
        })
    }

    /// A cone from its unit axis and the sine of its half-angle, as
    /// [`axis`](Self::axis) and [`sin_half_angle`](Self::sin_half_angle) give them (a
    /// hierarchy's records keep them so).
    pub(crate) fn from_parts(axis: [f32; 3], sin_half_angle: f32) -> NormalCone {
        NormalCone {
            axis,
            sin_half_angle,
        }
    }

    /// The cone's unit axis.
    pub fn axis(&self) -> Vec3 {
        Vec3::from_array(self.axis)
    }

    /// Sine of the cone's half-angle (its rounding margins included).
    pub fn sin_half_angle(&self) -> f32 {
        self.sin_half_angle
    }

    /// The opposite cone (the normals `S_v × S_u`).
    pub fn flipped(&self) -> NormalCone {
        NormalCone {
            axis: (-self.axis()).to_array(),
            ..*self
        }
    }

    /// True when every normal in the cone points away from an eye at `eye`, at every point of
    /// the convex hull of `points` (a patch with this cone and these control points shows the
    /// eye its back, or at most its edge).
    pub fn faces_away_from(&self, points: &[[f32; 3]], eye: Vec3) -> bool {
        let axis = self.axis();
        // The rounding of `d · a` and `|d|`: a few epsilons of |d|, well inside this.
        let sin = self.sin_half_angle + 1e-5;
        !points.is_empty()
            && points.iter().all(|&q| {
                let d = Vec3::from_array(q) - eye;
                d.dot(axis) > length(d) * sin
            })
    }

    /// True when every normal in the cone points away along the view direction `forward`
    /// (unit length): a parallel projection sees the back.
    pub fn faces_away_along(&self, forward: Vec3) -> bool {
        forward.dot(self.axis()) > self.sin_half_angle + 1e-5
    }
}

/// Gauss-Legendre nodes and weights on `[0, 1]`, 5 points.
const GAUSS: [(f32, f32); 5] = [
    (0.046_910_077, 0.118_463_44),
    (0.230_765_35, 0.239_314_34),
    (0.5, 0.284_444_45),
    (0.769_234_65, 0.239_314_34),
    (0.953_089_9, 0.118_463_44),
];

/// Three times the signed volume the patch contributes about `center`
/// (`∫∫ (S - center) · (S_u × S_v)`), by 5 x 5 Gauss-Legendre points, and the same integral of
/// its absolute value (the scale a sign is judged against). Summed over a closed surface, the
/// first is three times the enclosed volume, positive when `S_u × S_v` points outward.
pub(crate) fn signed_volume(patch: &BezierPatch<'_>, center: Vec3) -> (f32, f32) {
    let (mut sum, mut size) = (0.0f32, 0.0f32);
    for &(u, wu) in &GAUSS {
        for &(v, wv) in &GAUSS {
            let (s, su, sv) = patch.position_and_partials(u, v);
            let f = (s - center).dot(su.cross(sv)) * wu * wv;
            sum += f;
            size += f.abs();
        }
    }
    (sum, size)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small deterministic generator (fixed seed: the test is the same every run).
    struct Lcg(u64);

    impl Lcg {
        fn next(&mut self) -> f32 {
            self.0 = self
                .0
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (self.0 >> 40) as f32 / (1u64 << 24) as f32
        }
    }

    /// Every sampled normal of many gently curved patches (polynomial and rational, degrees 1
    /// to 3) lies inside the patch's cone, and the cones are not much wider than the normals.
    #[test]
    fn the_cone_holds_every_normal() {
        let mut rng = Lcg(7);
        let (mut cones, mut widest_gap) = (0, 0.0f32);
        for case in 0..300 {
            let (p, q) = (1 + case % 3, 1 + (case / 3) % 3);
            let bend = 0.1 + 0.6 * rng.next();
            let mut points = [[0.0f32; 3]; 16];
            let mut weights = [1.0f32; 16];
            for i in 0..=p {
                for j in 0..=q {
                    let (x, y) = (i as f32 / p as f32, j as f32 / q as f32);
                    let k = i * (q + 1) + j;
                    points[k] = [
                        x + 0.1 * (rng.next() - 0.5),
                        y + 0.1 * (rng.next() - 0.5),
                        bend * (rng.next() - 0.5),
                    ];
                    weights[k] = 0.5 + rng.next();
                }
            }
            let n = (p + 1) * (q + 1);
            let patch = if case % 2 == 0 {
                BezierPatch::new(p, q, &points[..n]).unwrap()
            } else {
                BezierPatch::new_rational(p, q, &points[..n], &weights[..n]).unwrap()
            };
            let Some(cone) = NormalCone::of(&patch) else {
                continue;
            };
            cones += 1;
            let cos = (1.0 - cone.sin_half_angle() * cone.sin_half_angle()).sqrt();
            let mut nearest_edge = 1.0f32;
            for a in 0..=16 {
                for b in 0..=16 {
                    let (_, su, sv) = patch.position_and_partials(a as f32 / 16.0, b as f32 / 16.0);
                    let normal = su.cross(sv).normalize();
                    let along = normal.dot(cone.axis());
                    assert!(
                        along >= cos - 1e-5,
                        "case {case}: a normal outside its cone"
                    );
                    nearest_edge = nearest_edge.min(along - cos);
                }
            }
            widest_gap = widest_gap.max(nearest_edge);
        }
        assert!(cones > 200, "only {cones} cones");
        // Some sampled normal comes within about 0.3 (in cosine) of every cone's edge.
        assert!(
            widest_gap < 0.3,
            "a cone far wider than its normals: {widest_gap}"
        );
    }

    #[test]
    fn a_cone_of_a_half_cylinder_is_too_wide() {
        // Normals over half a turn span 180 degrees: no cone below 90 degrees holds them.
        let points = [
            [1.0, 0.0, 0.0],
            [1.0, 0.0, 1.0],
            [1.0, 2.0, 0.0],
            [1.0, 2.0, 1.0],
            [-1.0, 2.0, 0.0],
            [-1.0, 2.0, 1.0],
            [-1.0, 0.0, 0.0],
            [-1.0, 0.0, 1.0],
        ];
        let patch = BezierPatch::new(3, 1, &points).unwrap();
        assert_eq!(NormalCone::of(&patch), None);
    }
}
