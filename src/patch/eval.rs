//! Evaluation of a [`BezierPatch`]: the point, its partials and its unit normal (the limit
//! where an edge collapses to a pole), in a fixed order of `f32` operations so a host and a
//! microcontroller compute the same bits.

use glam::{Vec3, Vec4};

use super::{BezierPatch, Side};
use crate::basis::{bernstein, bernstein_fixed, tensor_point, tensor_with_derivatives, Bezier};
use crate::frame::{frame, nudge, SurfacePoint};
use crate::math::{clamp_param, normalize};

impl BezierPatch<'_> {
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

    /// [`position_direct`](Self::position_direct) at each parameter pair of `uv`, into
    /// `out`: the same bits per point. A bicubic polynomial patch (the common case) is summed
    /// four points at a time, one per lane of a [`Vec4`] for each coordinate: every lane takes
    /// the scalar sum's operations in its order, and each control point is read once per four
    /// points (SIMD on the host, and fewer loads everywhere). A point on a collapsed side is
    /// its pole, as `position_direct` gives it; other patches are evaluated a point at a time.
    pub(crate) fn positions_direct_into(&self, uv: &[(f32, f32)], out: &mut [Vec3]) {
        let (p, q) = (self.degree_u(), self.degree_v());
        if !(self.weights.is_none() && p == 3 && q == 3) {
            for (point, &(u, v)) in out.iter_mut().zip(uv) {
                *point = self.position_direct(u, v);
            }
            return;
        }
        for (chunk, at) in out.chunks_mut(4).zip(uv.chunks(4)) {
            // Lanes past the end repeat the chunk's first point.
            let first = at.first().copied().unwrap_or_default();
            let lane = |l: usize| at.get(l).copied().unwrap_or(first);
            let (u, v) = (
                Vec4::new(lane(0).0, lane(1).0, lane(2).0, lane(3).0),
                Vec4::new(lane(0).1, lane(1).1, lane(2).1, lane(3).1),
            );
            let lanes = direct_sum4::<4, 4>(self.points, u, v);
            for ((point, &(u, v)), sum) in chunk.iter_mut().zip(at).zip(lanes) {
                let boundary = u == 0.0 || u == 1.0 || v == 0.0 || v == 1.0;
                *point = match boundary.then(|| self.pole_at(u, v)).flatten() {
                    Some(pole) => pole,
                    None => sum,
                };
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
        self.surface_point(self.frame_at(u, v), u, v)
    }

    /// The surface point of frame `f` at clamped `(u, v)`: its normal, or where that is
    /// undefined, the fallbacks [`evaluate`](Self::evaluate) describes.
    fn surface_point(&self, f: crate::frame::Frame, u: f32, v: f32) -> SurfacePoint {
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
        let sums = match (p, q) {
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
        self.polynomial_eval(sums, u, v)
    }

    /// [`polynomial_derivatives`](Self::polynomial_derivatives) from the sums of
    /// [`derivative_sums`] at `(u, v)`: the pole on a collapsed side, and the partials scaled.
    #[inline(always)]
    fn polynomial_eval(
        &self,
        (mut s, s_u, s_v): (Vec3, Vec3, Vec3),
        u: f32,
        v: f32,
    ) -> crate::basis::TensorEval {
        let (p, q) = (self.degree_u(), self.degree_v());
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

/// [`direct_sum`] at four parameter pairs, one per lane: each lane's operations are the
/// scalar sum's, in its order (the Bernstein values as [`bernstein_fixed`] computes them).
fn direct_sum4<const M: usize, const N: usize>(points: &[[f32; 3]], u: Vec4, v: Vec4) -> [Vec3; 4] {
    let (bu, bv) = (bernstein4::<M>(u), bernstein4::<N>(v));
    let Some(points) = points.get(..M * N) else {
        return [Vec3::ZERO; 4];
    };
    let (mut x, mut y, mut z) = (Vec4::ZERO, Vec4::ZERO, Vec4::ZERO);
    for (i, &a) in bu.iter().enumerate() {
        let (mut rx, mut ry, mut rz) = (Vec4::ZERO, Vec4::ZERO, Vec4::ZERO);
        for (&[px, py, pz], &b) in points[i * N..(i + 1) * N].iter().zip(&bv) {
            rx += Vec4::splat(px) * b;
            ry += Vec4::splat(py) * b;
            rz += Vec4::splat(pz) * b;
        }
        x += rx * a;
        y += ry * a;
        z += rz * a;
    }
    [0, 1, 2, 3].map(|l| Vec3::new(x[l], y[l], z[l]))
}

/// [`bernstein_fixed`] at four parameters, one per lane (the same operations per lane).
#[inline(always)]
fn bernstein4<const M: usize>(t: Vec4) -> [Vec4; M] {
    let mut b = [Vec4::ZERO; M];
    b[0] = Vec4::ONE;
    let s = Vec4::ONE - t;
    for k in 1..M {
        b[k] = t * b[k - 1];
        for i in (1..k).rev() {
            b[i] = s * b[i] + t * b[i - 1];
        }
        b[0] *= s;
    }
    b
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::TestRng;

    /// A parameter in `[0, 1]`, about one in eight on the boundary (0 or 1); with `outside`,
    /// also some beyond it (-0.25 and 1.5, which evaluation clamps).
    fn random_unit(rng: &mut TestRng, outside: bool) -> f32 {
        match (rng.signed(8), outside) {
            (-8, _) => 0.0,
            (-7, _) => 1.0,
            (-6, true) => -0.25,
            (-5, true) => 1.5,
            _ => (rng.signed(1 << 20) + (1 << 20)) as f32 / (1 << 21) as f32,
        }
    }

    /// Calls `f` with a plain and a rational patch of each degree pair of `degrees`, each
    /// from a random net (at most 16 points), once with side V0 (j = 0) collapsed to one
    /// point and once not.
    fn for_each_random_patch(
        rng: &mut TestRng,
        degrees: &[(usize, usize)],
        mut f: impl FnMut(&mut TestRng, &BezierPatch<'_>, (usize, usize)),
    ) {
        for &(p, q) in degrees {
            for collapsed in [false, true] {
                let n = (p + 1) * (q + 1);
                let mut points = [[0.0f32; 3]; 16];
                let mut weights = [1.0f32; 16];
                for (k, point) in points.iter_mut().enumerate().take(n) {
                    *point = [0, 1, 2].map(|_| rng.signed(1000) as f32 / 97.0);
                    weights[k] = 1.0 + rng.signed(50).unsigned_abs() as f32 / 40.0;
                }
                if collapsed {
                    for i in 0..=p {
                        points[i * (q + 1)] = points[0];
                    }
                }
                let plain = BezierPatch::new(p, q, &points[..n]).unwrap();
                let rational =
                    BezierPatch::new_rational(p, q, &points[..n], &weights[..n]).unwrap();
                assert_eq!(plain.is_collapsed(Side::V0), collapsed);
                f(rng, &plain, (p, q));
                f(rng, &rational, (p, q));
            }
        }
    }

    /// `positions_direct_into` gives `position_direct`'s bits at every point, for the degrees it
    /// sums four at a time and for one it hands back (and a rational patch), at interior and
    /// boundary parameters, and the pole on a collapsed side; for lengths that fill and that
    /// leave lanes over.
    #[test]
    fn positions_direct_into_is_position_direct_bit_for_bit() {
        let mut rng = TestRng::new(0x5eed_0001);
        let mut compared = 0;
        let degrees = [(3, 3), (2, 2), (1, 1), (3, 2)];
        for_each_random_patch(&mut rng, &degrees, |rng, patch, (p, q)| {
            let mut unit = || random_unit(rng, false);
            for _ in 0..20 {
                let uv3: [(f32, f32); 3] = core::array::from_fn(|_| (unit(), unit()));
                let uv10: [(f32, f32); 10] = core::array::from_fn(|_| (unit(), unit()));
                let uv18: [(f32, f32); 18] = core::array::from_fn(|_| (unit(), unit()));
                let check = |uv: &[(f32, f32)], got: &[Vec3]| {
                    for (&(u, v), g) in uv.iter().zip(got) {
                        let want = patch.position_direct(u, v);
                        assert_eq!(
                            g.to_array().map(f32::to_bits),
                            want.to_array().map(f32::to_bits),
                            "({p}, {q}) at ({u}, {v})"
                        );
                    }
                    uv.len()
                };
                for uv in [&uv3[..], &uv10[..], &uv18[..]] {
                    let mut got = [Vec3::ZERO; 18];
                    patch.positions_direct_into(uv, &mut got[..uv.len()]);
                    compared += check(uv, &got[..uv.len()]);
                }
            }
        });
        assert_eq!(compared, 4 * 2 * 2 * 20 * 31);
    }
}
