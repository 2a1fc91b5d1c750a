//! A patch's second-derivative bounds and the rounding slack of its sampled deviations (see
//! the parent module's docs: "Second derivatives of a rational patch" and "Rounding").

use glam::{Vec3, Vec4};

use super::{enclosing_radius_sq, EPS, REMAINDER_SLACK};
use crate::math::{max, min, sqrt};
use crate::patch::BezierPatch;
use crate::MAX_DEGREE;

/// What a patch's bounds need besides its samples: second-derivative bounds and the rounding
/// slack of one sampled deviation.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PatchBounds {
    /// Upper bounds of `|S_uu|`, `|S_uv|`, `|S_vv|` over the patch.
    pub second: [f32; 3],
    /// Upper bound of the rounding error of one sampled deviation.
    pub slack: f32,
}

/// The largest norm of the points `f(i, j)` of a `rows` by `cols` net (xyz part and w part),
/// rounded up.
///
/// One square root, of the largest squared norm: the correctly rounded square root is
/// monotone, so that is the largest of the norms `math::length` gives, bit for bit (a software
/// square root costs about 50 instructions on a Cortex-M4F).
fn max_norm(rows: usize, cols: usize, f: impl Fn(usize, usize) -> Vec4) -> (f32, f32) {
    let mut xyz = 0.0f32;
    let mut w = 0.0f32;
    for i in 0..rows {
        for j in 0..cols {
            let d = f(i, j);
            let v = Vec3::new(d.x, d.y, d.z);
            xyz = max(xyz, v.dot(v));
            w = max(w, d.w.abs());
        }
    }
    (sqrt(xyz) * (1.0 + 8.0 * EPS), w * (1.0 + 8.0 * EPS))
}

/// Cuts the Bezier polygon `d` (homogeneous) to the parameter interval `[t0, t1]` in place.
fn cut(d: &mut [Vec4], t0: f32, t1: f32) {
    let n = d.len();
    // Left part at t1: d[k] becomes the k-th point of [0, t1].
    for r in 1..n {
        for k in (r..n).rev() {
            d[k] = crate::math::lerp4(d[k - 1], d[k], t1);
        }
    }
    // Right part of [0, t1] at t0 / t1.
    if t1 > 0.0 {
        let s = min(t0 / t1, 1.0);
        for r in 1..n {
            for k in 0..n - r {
                d[k] = crate::math::lerp4(d[k], d[k + 1], s);
            }
        }
    }
}

/// A homogeneous control net of degrees `(p, q)`, point `(i, j)` at `[i][j]`.
type Net = [[Vec4; MAX_DEGREE + 1]; MAX_DEGREE + 1];

impl PatchBounds {
    /// The bounds of `patch` over its whole domain.
    pub fn of(patch: &BezierPatch<'_>) -> PatchBounds {
        Self::over(patch, [0.0, 1.0, 0.0, 1.0])
    }

    /// The bounds of `patch` over the parameter box `[u0, u1, v0, v1]`: the sub-patch's
    /// second derivatives, in the patch's own parameters.
    pub fn over(patch: &BezierPatch<'_>, area: [f32; 4]) -> PatchBounds {
        let (p, q) = (patch.degree_u(), patch.degree_v());
        let mut net: Net = [[Vec4::ZERO; MAX_DEGREE + 1]; MAX_DEGREE + 1];
        let mut big = 0.0f32;
        let (mut w_max, mut w_low) = (0.0f32, f32::INFINITY);
        for (i, row) in net.iter_mut().enumerate().take(p + 1) {
            for (j, cell) in row.iter_mut().enumerate().take(q + 1) {
                let (pt, w) = (patch.control_point(i, j), patch.weight(i, j));
                big = max(big, pt.abs().max_element());
                w_max = max(w_max, w);
                w_low = min(w_low, w);
                *cell = Vec4::new(pt.x * w, pt.y * w, pt.z * w, w);
            }
        }
        let whole = area == [0.0, 1.0, 0.0, 1.0];
        if !whole {
            let mut line = [Vec4::ZERO; MAX_DEGREE + 1];
            for j in 0..=q {
                for (l, row) in line.iter_mut().zip(&net).take(p + 1) {
                    *l = row[j];
                }
                cut(&mut line[..=p], area[0], area[1]);
                for (l, row) in line.iter().zip(net.iter_mut()).take(p + 1) {
                    row[j] = *l;
                }
            }
            for row in net.iter_mut().take(p + 1) {
                cut(&mut row[..=q], area[2], area[3]);
            }
        }
        // Rounding of the cut net: every step is a convex combination.
        let n = (3 * (p + q) + 8) as f32;
        let gamma = n * EPS / (1.0 - n * EPS);
        let net_error = if whole {
            0.0
        } else {
            gamma * big * w_max * 2.0
        };
        // Euclidean points, the centre, radius and weights of the (cut) net.
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        let mut w_min = f32::INFINITY;
        // (Each point divided by its weight lane by lane: the bits of `Vec3 / f32`.)
        let euclidean = |h: &Vec4| (*h / Vec4::splat(h.w)).truncate();
        for row in net.iter().take(p + 1) {
            for h in row.iter().take(q + 1) {
                let e = euclidean(h);
                lo = lo.min(e);
                hi = hi.max(e);
                w_min = min(w_min, h.w);
            }
        }
        // A cut net's weights are convex combinations of the patch's: at least the smallest.
        let w_min = max(max(w_min - net_error, w_low), f32::MIN_POSITIVE);
        let center = (lo + hi) * 0.5;
        // (The largest squared distance, then its root: see `max_norm`.)
        let mut radius = 0.0f32;
        for row in net.iter().take(p + 1) {
            for h in row.iter().take(q + 1) {
                let d = euclidean(h) - center;
                radius = max(radius, d.dot(d));
            }
        }
        let radius = sqrt(radius) * (1.0 + 8.0 * EPS) + 2.0 * net_error / w_min;
        // The net about its centre, in place, once (the difference nets below read each
        // point up to ten times).
        for row in net.iter_mut().take(p + 1) {
            for c in row.iter_mut().take(q + 1) {
                *c = Vec4::new(
                    c.x - center.x * c.w,
                    c.y - center.y * c.w,
                    c.z - center.z * c.w,
                    c.w,
                );
            }
        }
        let h = |i: usize, j: usize| net[i][j];
        let (pf, qf) = (p as f32, q as f32);
        // A derivative net of order k mixes 2^k net points: its points are off by at most
        // 2^k net_error times its scale.
        let grow = |(x, w): (f32, f32), scale: f32, k: f32| {
            let e = scale * net_error * k * 2.0;
            (x + e, w + e)
        };
        let (au, wu) = grow(
            max_norm(p, q + 1, |i, j| (h(i + 1, j) - h(i, j)) * pf),
            pf,
            2.0,
        );
        let (av, wv) = grow(
            max_norm(p + 1, q, |i, j| (h(i, j + 1) - h(i, j)) * qf),
            qf,
            2.0,
        );
        let (auu, wuu) = if p >= 2 {
            grow(
                max_norm(p - 1, q + 1, |i, j| {
                    (h(i + 2, j) - h(i + 1, j) * 2.0 + h(i, j)) * (pf * (pf - 1.0))
                }),
                pf * (pf - 1.0),
                4.0,
            )
        } else {
            (0.0, 0.0)
        };
        let (avv, wvv) = if q >= 2 {
            grow(
                max_norm(p + 1, q - 1, |i, j| {
                    (h(i, j + 2) - h(i, j + 1) * 2.0 + h(i, j)) * (qf * (qf - 1.0))
                }),
                qf * (qf - 1.0),
                4.0,
            )
        } else {
            (0.0, 0.0)
        };
        let (auv, wuv) = grow(
            max_norm(p, q, |i, j| {
                (h(i + 1, j + 1) - h(i + 1, j) - h(i, j + 1) + h(i, j)) * (pf * qf)
            }),
            pf * qf,
            4.0,
        );
        let up = 1.0 + 16.0 * EPS;
        let (s_u, s_v, second) = if patch.weights().is_none() {
            (au, av, [auu, auv, avv])
        } else {
            let s_u = (au + wu * radius) / w_min * up;
            let s_v = (av + wv * radius) / w_min * up;
            let suu = (auu + 2.0 * wu * s_u + wuu * radius) / w_min * up;
            let suv = (auv + wu * s_v + wv * s_u + wuv * radius) / w_min * up;
            let svv = (avv + 2.0 * wv * s_v + wvv * radius) / w_min * up;
            (s_u, s_v, [suu, suv, svv])
        };
        // A sub-box's own parameters run over [0, 1]: derivatives in the patch's parameters
        // are the sub-patch's divided by the box's extents.
        let (su, sv) = if whole {
            (1.0, 1.0)
        } else {
            let e = |d: f32| if d > 0.0 { 1.0 / d } else { 0.0 };
            (e(area[1] - area[0]), e(area[3] - area[2]))
        };
        let second = [
            second[0] * su * su * up,
            second[1] * su * sv * up,
            second[2] * sv * sv * up,
        ];
        // Rounding of one sampled deviation: three positions (a sample and, through the
        // interpolant, the corners), the interpolant's own arithmetic and the lattice
        // parameters' rounding.
        let position = gamma * (2.0 * big * w_max) / w_low * 1.75; // 1.75 > sqrt(3): a norm
        let slack =
            (4.0 * position + 16.0 * EPS * big * 1.75 + 4.0 * EPS * (s_u * su + s_v * sv)) * up;
        PatchBounds { second, slack }
    }

    /// The bounds to use over the triangle `uv`: the patch cut to the triangle's box. Its
    /// second derivatives vary less there (for a rational patch, its weights far less), which
    /// halves the remainder's excess (`host-tests/tests/deviation.rs`: bound / true from 1.10
    /// to 1.05 on the teapot, from 20 to 1.3 on the tinynurbs hemisphere).
    pub fn around(patch: &BezierPatch<'_>, uv: [(f32, f32); 3]) -> PatchBounds {
        let lo = |f: fn((f32, f32)) -> f32| min(min(f(uv[0]), f(uv[1])), f(uv[2]));
        let hi = |f: fn((f32, f32)) -> f32| max(max(f(uv[0]), f(uv[1])), f(uv[2]));
        let area = [lo(|p| p.0), hi(|p| p.0), lo(|p| p.1), hi(|p| p.1)];
        PatchBounds::over(patch, area)
    }

    /// `½ ρ²` for the domain triangle with unit parameters `uv`: the bound of linear
    /// interpolation over it from the second derivatives alone (see the module docs).
    pub fn curvature_term(&self, uv: [(f32, f32); 3]) -> f32 {
        self.prepared().curvature_term(uv)
    }

    /// These bounds with what [`curvature_term`](Self::curvature_term) computes from them
    /// alone done once, for the many triangles one patch's bounds are applied to.
    pub(crate) fn prepared(&self) -> PreparedBounds {
        let [a, _, c] = self.second;
        let t0 = if a > 0.0 && c > 0.0 { sqrt(c / a) } else { 1.0 };
        let pair = |t: f32| {
            let (alpha, beta) = weights_for(self.second, t);
            (alpha, beta, sqrt(alpha * beta))
        };
        PreparedBounds {
            second: self.second,
            t0,
            fixed: [pair(t0), pair(1.0)],
        }
    }
}

/// `α = a + b t` and `β = c + b / t` for the second-derivative bounds `[a, b, c]` (`(a, c)`
/// without a mixed term): `|D²S[h, h]| <= α h_u² + β h_v²` (see the module docs).
fn weights_for([a, b, c]: [f32; 3], t: f32) -> (f32, f32) {
    if b > 0.0 {
        (a + b * t, c + b / t)
    } else {
        (a, c)
    }
}

/// [`PatchBounds`] prepared for many triangles: the choices of the curvature term's
/// parameter `t` that do not depend on the triangle (`sqrt(c / a)` and 1), with their
/// `α`, `β` and `sqrt(α β)`, computed once. Its terms are [`PatchBounds::curvature_term`]'s,
/// bit for bit.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PreparedBounds {
    /// [`PatchBounds::second`].
    second: [f32; 3],
    /// The first choice of `t`.
    t0: f32,
    /// `α`, `β` and `sqrt(α β)` for `t = t0` and `t = 1`.
    fixed: [(f32, f32, f32); 2],
}

impl PreparedBounds {
    /// [`PatchBounds::curvature_term`]: the smallest enclosing-circle term over the choices
    /// `t0`, the triangle's box aspect and 1 (a choice equal to an earlier one gives the same
    /// term and is skipped).
    pub(crate) fn curvature_term(&self, uv: [(f32, f32); 3]) -> f32 {
        let [a, b, c] = self.second;
        if a == 0.0 && b == 0.0 && c == 0.0 {
            return 0.0;
        }
        let fixed = |k: usize| {
            let (alpha, beta, root) = self.fixed[k];
            enclosing_radius_sq(uv, alpha, beta, || root)
        };
        let mut best = fixed(0);
        if b == 0.0 {
            // Every choice gives (a, c).
            return 0.5 * best * REMAINDER_SLACK;
        }
        let (lo_u, hi_u) = (
            min(min(uv[0].0, uv[1].0), uv[2].0),
            max(max(uv[0].0, uv[1].0), uv[2].0),
        );
        let (lo_v, hi_v) = (
            min(min(uv[0].1, uv[1].1), uv[2].1),
            max(max(uv[0].1, uv[1].1), uv[2].1),
        );
        let (hu, hv) = (hi_u - lo_u, hi_v - lo_v);
        let t1 = if hu > 0.0 && hv > 0.0 { hv / hu } else { 1.0 };
        if t1 != self.t0 {
            let (alpha, beta) = weights_for(self.second, t1);
            best = min(
                best,
                enclosing_radius_sq(uv, alpha, beta, || sqrt(alpha * beta)),
            );
        }
        if self.t0 != 1.0 && t1 != 1.0 {
            best = min(best, fixed(1));
        }
        0.5 * best * REMAINDER_SLACK
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::TestRng;

    /// The curvature term with every choice of `t` computed afresh (as it was before the
    /// choices that depend on the bounds alone were prepared).
    fn reference(second: [f32; 3], uv: [(f32, f32); 3]) -> f32 {
        let [a, b, c] = second;
        if a == 0.0 && b == 0.0 && c == 0.0 {
            return 0.0;
        }
        let lo_hi = |f: fn((f32, f32)) -> f32| {
            let (x, y, z) = (f(uv[0]), f(uv[1]), f(uv[2]));
            (min(min(x, y), z), max(max(x, y), z))
        };
        let ((lo_u, hi_u), (lo_v, hi_v)) = (lo_hi(|p| p.0), lo_hi(|p| p.1));
        let (hu, hv) = (hi_u - lo_u, hi_v - lo_v);
        let mut best = f32::INFINITY;
        let candidates = [
            if a > 0.0 && c > 0.0 { sqrt(c / a) } else { 1.0 },
            if hu > 0.0 && hv > 0.0 { hv / hu } else { 1.0 },
            1.0,
        ];
        for t in candidates {
            let (alpha, beta) = if b > 0.0 {
                (a + b * t, c + b / t)
            } else {
                (a, c)
            };
            best = min(
                best,
                enclosing_radius_sq(uv, alpha, beta, || sqrt(alpha * beta)),
            );
            if b == 0.0 {
                break;
            }
        }
        0.5 * best * REMAINDER_SLACK
    }

    /// `PreparedBounds::curvature_term` gives the fresh computation's bits, for bounds with
    /// zero terms and equal ones, and for acute, right, obtuse and axis-aligned triangles
    /// (whose box aspect is 1 or equal to `sqrt(c / a)`).
    /// `z = 4 u (1 - u)`: `S_uu = (0, 0, -8)` everywhere, `S_uv = S_vv = 0`.
    #[test]
    fn a_parabola_has_its_second_derivative() {
        let net = [
            [0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.5, 0.0, 2.0],
            [0.5, 1.0, 2.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
        ];
        let b = PatchBounds::of(&BezierPatch::new(2, 1, &net).unwrap());
        assert!((b.second[0] - 8.0).abs() < 1e-4 && b.second[1] < 1e-6 && b.second[2] == 0.0);
    }

    #[test]
    fn prepared_curvature_term_is_the_fresh_one_bit_for_bit() {
        let mut rng = TestRng::new(0x5eed_0002);
        let value = |rng: &mut TestRng| match rng.signed(5) {
            -5 => 0.0,
            -4 => 4.0,
            _ => rng.signed(1 << 16).unsigned_abs() as f32 / 1000.0,
        };
        let mut compared = 0;
        for _ in 0..2000 {
            let second = [value(&mut rng), value(&mut rng), value(&mut rng)];
            let bounds = PatchBounds { second, slack: 0.0 };
            let prepared = bounds.prepared();
            for _ in 0..10 {
                let coordinate = |rng: &mut TestRng| (rng.signed(32) + 32) as f32 / 64.0;
                let mut uv: [(f32, f32); 3] =
                    core::array::from_fn(|_| (coordinate(&mut rng), coordinate(&mut rng)));
                if rng.signed(2) == 0 {
                    // A right isosceles triangle: a square box (aspect 1).
                    let (u, v) = uv[0];
                    uv[1] = (u + 0.125, v);
                    uv[2] = (u, v + 0.125);
                }
                let want = reference(second, uv);
                let got = prepared.curvature_term(uv);
                assert_eq!(got.to_bits(), want.to_bits(), "{second:?} {uv:?}");
                assert_eq!(bounds.curvature_term(uv).to_bits(), want.to_bits());
                compared += 1;
            }
        }
        assert_eq!(compared, 20_000);
    }
}
