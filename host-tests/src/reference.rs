//! The `f64` reference: direct Bernstein sums for Bezier patches and Cox-de Boor basis
//! functions for NURBS, written for the tests and sharing no code with the kernel.

use serde_json::Value;

/// 3-vector helpers.
pub type V3 = [f64; 3];

/// `a - b`.
pub fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
/// `a + b`.
pub fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
/// `a * s`.
pub fn scale(a: V3, s: f64) -> V3 {
    [a[0] * s, a[1] * s, a[2] * s]
}
/// Dot product.
pub fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
/// Cross product.
pub fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
/// Length.
pub fn norm(a: V3) -> f64 {
    dot(a, a).sqrt()
}
/// Distance.
pub fn dist(a: V3, b: V3) -> f64 {
    norm(sub(a, b))
}

/// Point, partials and mixed partial of a surface, in `f64`.
#[derive(Clone, Copy, Debug)]
pub struct RefFrame {
    /// Point.
    pub p: V3,
    /// dS/du.
    pub su: V3,
    /// dS/dv.
    pub sv: V3,
    /// d2S/dudv.
    pub suv: V3,
}

impl RefFrame {
    /// Unit normal `su x sv`, or `None` when the partials are (nearly) parallel or vanish.
    pub fn normal(&self) -> Option<V3> {
        let n = cross(self.su, self.sv);
        let len = norm(n);
        (len > 1e-12 * norm(self.su) * norm(self.sv) && len > 0.0).then(|| scale(n, 1.0 / len))
    }

    /// The analytic limit normal at an edge where `su` (or `sv`) vanishes identically:
    /// `su(u, v) = (v - v0) suv + O((v - v0)^2)`, so the normal tends to
    /// `sign(v - v0) suv x sv`. `toward` is +1 when the interior lies at larger parameter.
    pub fn limit_normal_su_vanishes(&self, toward: f64) -> V3 {
        let n = scale(cross(self.suv, self.sv), toward);
        scale(n, 1.0 / norm(n))
    }

    /// As [`Self::limit_normal_su_vanishes`] with the roles of u and v swapped.
    pub fn limit_normal_sv_vanishes(&self, toward: f64) -> V3 {
        let n = scale(cross(self.su, self.suv), toward);
        scale(n, 1.0 / norm(n))
    }
}

/// Homogeneous accumulation of a tensor-product sum with basis values and derivatives.
fn combine(
    pts: &[V3],
    w: &[f64],
    nv: usize,
    bu: &[(usize, f64, f64)],
    bv: &[(usize, f64, f64)],
) -> RefFrame {
    // a = sum w P B, and its derivatives; ww = sum w B, and its derivatives.
    let (mut a, mut au, mut av, mut auv) = ([0.0; 3], [0.0; 3], [0.0; 3], [0.0; 3]);
    let (mut ww, mut wu, mut wv, mut wuv) = (0.0, 0.0, 0.0, 0.0);
    for &(i, b, db) in bu {
        for &(j, c, dc) in bv {
            let k = i * nv + j;
            let wp = scale(pts[k], w[k]);
            a = add(a, scale(wp, b * c));
            au = add(au, scale(wp, db * c));
            av = add(av, scale(wp, b * dc));
            auv = add(auv, scale(wp, db * dc));
            ww += w[k] * b * c;
            wu += w[k] * db * c;
            wv += w[k] * b * dc;
            wuv += w[k] * db * dc;
        }
    }
    let p = scale(a, 1.0 / ww);
    let su = scale(sub(au, scale(p, wu)), 1.0 / ww);
    let sv = scale(sub(av, scale(p, wv)), 1.0 / ww);
    let suv = scale(
        sub(sub(sub(auv, scale(p, wuv)), scale(sv, wu)), scale(su, wv)),
        1.0 / ww,
    );
    RefFrame { p, su, sv, suv }
}

fn binomial(n: usize, k: usize) -> f64 {
    (0..k).fold(1.0, |acc, i| acc * (n - i) as f64 / (i + 1) as f64)
}

/// Bernstein polynomial `B_{i,n}(t)`, zero outside `0..=n`.
pub fn bernstein(n: usize, i: isize, t: f64) -> f64 {
    if i < 0 || i as usize > n {
        return 0.0;
    }
    let i = i as usize;
    binomial(n, i) * t.powi(i as i32) * (1.0 - t).powi((n - i) as i32)
}

/// `B_{i,n}(t)` for `i = 0..=n` (n <= 7), by the recurrence.
fn bernstein_row(n: usize, t: f64) -> [f64; 8] {
    let mut b = [0.0; 8];
    b[0] = 1.0;
    for k in 1..=n {
        for i in (1..=k).rev() {
            b[i] = (1.0 - t) * b[i] + t * b[i - 1];
        }
        b[0] *= 1.0 - t;
    }
    b
}

/// `(i, B_{i,n}(t), B'_{i,n}(t))` for `i = 0..=n`.
fn bernstein_all(n: usize, t: f64) -> Vec<(usize, f64, f64)> {
    (0..=n)
        .map(|i| {
            let ii = i as isize;
            let d = n as f64 * (bernstein(n - 1, ii - 1, t) - bernstein(n - 1, ii, t));
            (i, bernstein(n, ii, t), d)
        })
        .collect()
}

/// A rational Bezier patch in `f64` (u-major control net).
#[derive(Clone, Debug)]
pub struct RefPatch {
    /// Degree in u.
    pub du: usize,
    /// Degree in v.
    pub dv: usize,
    /// Control points.
    pub pts: Vec<V3>,
    /// Weights.
    pub w: Vec<f64>,
}

impl RefPatch {
    /// Evaluates by direct Bernstein sums.
    pub fn eval(&self, u: f64, v: f64) -> RefFrame {
        combine(
            &self.pts,
            &self.w,
            self.dv + 1,
            &bernstein_all(self.du, u),
            &bernstein_all(self.dv, v),
        )
    }

    /// The point at `(u, v)` alone, without allocating (for dense sampling).
    pub fn point(&self, u: f64, v: f64) -> V3 {
        let (bu, bv) = (bernstein_row(self.du, u), bernstein_row(self.dv, v));
        let (mut a, mut w) = ([0.0; 3], 0.0);
        for (i, bi) in bu.iter().enumerate().take(self.du + 1) {
            for (j, bj) in bv.iter().enumerate().take(self.dv + 1) {
                let k = i * (self.dv + 1) + j;
                let f = bi * bj * self.w[k];
                w += f;
                for (ac, pc) in a.iter_mut().zip(self.pts[k]) {
                    *ac += f * pc;
                }
            }
        }
        scale(a, 1.0 / w)
    }

    /// Builds the reference of a kernel patch (its `f32` data widened).
    pub fn from_kernel(patch: &spline_tess::BezierPatch<'_>) -> Self {
        let (du, dv) = (patch.degree_u(), patch.degree_v());
        let mut pts = Vec::new();
        let mut w = Vec::new();
        for i in 0..=du {
            for j in 0..=dv {
                let p = patch.control_point(i, j);
                pts.push([p.x as f64, p.y as f64, p.z as f64]);
                w.push(patch.weight(i, j) as f64);
            }
        }
        RefPatch { du, dv, pts, w }
    }

    /// Control point `(i, j)`.
    pub fn at(&self, i: usize, j: usize) -> V3 {
        self.pts[i * (self.dv + 1) + j]
    }

    /// Which edges are collapsed to a point: `[v = 0, u = 1, v = 1, u = 0]`.
    pub fn collapsed(&self) -> [bool; 4] {
        let (p, q) = (self.du, self.dv);
        let all_eq = |f: &dyn Fn(usize) -> V3, n: usize| (1..=n).all(|k| f(k) == f(0));
        [
            all_eq(&|k| self.at(k, 0), p),
            all_eq(&|k| self.at(p, k), q),
            all_eq(&|k| self.at(k, q), p),
            all_eq(&|k| self.at(0, k), q),
        ]
    }
}

/// Reads a BPT text in `f64` with its own parser (independent of the kernel's).
pub fn read_bpt(text: &str) -> Vec<RefPatch> {
    let mut words = text
        .split_whitespace()
        .map(|w| w.parse::<f64>().expect("number"));
    let n = words.next().expect("patch count") as usize;
    (0..n)
        .map(|_| {
            let du = words.next().unwrap() as usize;
            let dv = words.next().unwrap() as usize;
            let pts: Vec<V3> = (0..(du + 1) * (dv + 1))
                .map(|_| {
                    [
                        words.next().unwrap(),
                        words.next().unwrap(),
                        words.next().unwrap(),
                    ]
                })
                .collect();
            let w = vec![1.0; pts.len()];
            RefPatch { du, dv, pts, w }
        })
        .collect()
}

/// Bounding-box diagonal of a set of points.
pub fn diagonal<'a>(points: impl IntoIterator<Item = &'a V3>) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    dist(lo, hi)
}

/// A NURBS surface in `f64` read from a fixture.
#[derive(Clone, Debug)]
pub struct RefNurbs {
    /// Degree in u.
    pub du: usize,
    /// Degree in v.
    pub dv: usize,
    /// u knots.
    pub ku: Vec<f64>,
    /// v knots.
    pub kv: Vec<f64>,
    /// Control points, u-major.
    pub pts: Vec<V3>,
    /// Weights, u-major.
    pub w: Vec<f64>,
    /// Number of control points along v.
    pub nv: usize,
    /// The whole JSON document (for `expected`, `tolerance`).
    pub json: Value,
}

impl RefNurbs {
    /// Reads a fixture with `serde_json`.
    pub fn read(text: &str) -> Self {
        let json: Value = serde_json::from_str(text).expect("JSON");
        let num = |v: &Value| v.as_f64().expect("number");
        let du = json["degree_u"].as_u64().unwrap() as usize;
        let dv = json["degree_v"].as_u64().unwrap() as usize;
        let ku: Vec<f64> = json["knots_u"]
            .as_array()
            .unwrap()
            .iter()
            .map(num)
            .collect();
        let kv: Vec<f64> = json["knots_v"]
            .as_array()
            .unwrap()
            .iter()
            .map(num)
            .collect();
        let rows = json["control_points"].as_array().unwrap();
        let nv = rows[0].as_array().unwrap().len();
        let mut pts = Vec::new();
        let mut w = Vec::new();
        for (i, row) in rows.iter().enumerate() {
            for (j, p) in row.as_array().unwrap().iter().enumerate() {
                let p = p.as_array().unwrap();
                pts.push([num(&p[0]), num(&p[1]), num(&p[2])]);
                w.push(match json.get("weights") {
                    Some(ws) => num(&ws[i][j]),
                    None => 1.0,
                });
            }
        }
        RefNurbs {
            du,
            dv,
            ku,
            kv,
            pts,
            w,
            nv,
            json,
        }
    }

    /// Parameter domain `(u0, u1, v0, v1)`.
    pub fn domain(&self) -> (f64, f64, f64, f64) {
        let nu = self.ku.len() - self.du - 1;
        (
            self.ku[self.du],
            self.ku[nu],
            self.kv[self.dv],
            self.kv[self.nv],
        )
    }

    /// Evaluates with Cox-de Boor basis functions.
    pub fn eval(&self, u: f64, v: f64) -> RefFrame {
        let nu = self.ku.len() - self.du - 1;
        combine(
            &self.pts,
            &self.w,
            self.nv,
            &basis_with_derivative(&self.ku, self.du, nu, u),
            &basis_with_derivative(&self.kv, self.dv, self.nv, v),
        )
    }
}

/// `(i, N_{i,p}(t), N'_{i,p}(t))` for the `p + 1` functions that are non-zero at `t`
/// (Piegl & Tiller, The NURBS Book, algorithms A2.1-A2.3, written out here in `f64`).
pub fn basis_with_derivative(knots: &[f64], p: usize, n: usize, t: f64) -> Vec<(usize, f64, f64)> {
    // Span: the last k in p..n with knots[k] <= t < knots[k+1], or the last non-empty one.
    let mut k = p;
    for i in p..n {
        if knots[i] <= t && knots[i] < knots[i + 1] {
            k = i;
        }
    }
    // ndu[j][r]: basis values of degree j in the upper triangle, knot differences below.
    let mut ndu = vec![vec![0.0; p + 1]; p + 1];
    let mut left = vec![0.0; p + 1];
    let mut right = vec![0.0; p + 1];
    ndu[0][0] = 1.0;
    for j in 1..=p {
        left[j] = t - knots[k + 1 - j];
        right[j] = knots[k + j] - t;
        let mut saved = 0.0;
        for r in 0..j {
            ndu[j][r] = right[r + 1] + left[j - r];
            let tmp = ndu[r][j - 1] / ndu[j][r];
            ndu[r][j] = saved + right[r + 1] * tmp;
            saved = left[j - r] * tmp;
        }
        ndu[j][j] = saved;
    }
    (0..=p)
        .map(|r| {
            let value = ndu[r][p];
            // First derivative: p * (N_{r-1,p-1} / (u_{i+p} - u_i) - N_{r,p-1} / (...)).
            let mut d = 0.0;
            if r >= 1 {
                d += ndu[r - 1][p - 1] / ndu[p][r - 1];
            }
            if r < p {
                d -= ndu[r][p - 1] / ndu[p][r];
            }
            (k - p + r, value, d * p as f64)
        })
        .collect()
}

/// A bound on the angle between the kernel's `f32` normal of `r` at `(u, v)` and the exact
/// one, from a forward error analysis of the kernel's evaluation; `None` where `f32` does not
/// determine the normal at all (the bound would exceed a right angle).
///
/// The kernel evaluates the homogeneous net `h = (w x, w y, w z, w)` by de Casteljau's
/// algorithm, row by row in u, then across the rows in v, and takes each first derivative as
/// the difference of the last level's two points times the degree (`spline_tess` `basis.rs`).
/// With the unit roundoff `ε = 2^-24`:
///
/// - one lerp level `a + (b - a) t` (or its mirror for `t > 1/2`) has an error of at most
///   `3ε ((1 - t)|a| + t|b|)`, so after `r` levels every component is off by at most
///   `3rε` times the Bernstein combination of the absolute values `|h|`;
/// - so, componentwise, with `γ = nε / (1 - nε)`, `n = 3(p + q) + 8` (all levels, the
///   products `w x`, the derivative's difference and scaling, with room to spare):
///   `|δA| <= γ M0`, `M0 = Σ B^p_i(u) B^q_j(v) |h_ij|`;
///   `|δA_u| <= γ Mu`, `Mu = p Σ (B^{p-1}_{i-1}(u) + B^{p-1}_i(u)) B^q_j(v) |h_ij|`;
///   `|δA_v| <= γ Mv` likewise in v;
/// - `S = A / w` and `S_u = (A_u - S w_u) / w` then carry, per component,
///   `|δS| <= (γ M0 + |S| γ M0_w) / w + 2ε|S|` and
///   `|δS_u| <= (γ Mu + |S| γ Mu_w + |δS| |w_u| + |S_u| γ M0_w) / w +
///   2ε (|A_u| + 2 |S w_u|) / w + 2ε |S_u|` (the last two terms are the rounding of the subtraction, product and division);
/// - with `ρ_u = |δS_u| / |S_u|` and `ρ_v` likewise (relative errors of the partials), the
///   cross product of the perturbed partials is off by at most
///   `|S_u| |S_v| (ρ_u + ρ_v + ρ_u ρ_v)`, so its direction turns by at most
///   `asin((ρ_u + ρ_v + ρ_u ρ_v + 8ε) / sin θ)`, `θ` the angle between the partials; the
///   `8ε` and the final `4ε` cover normalising the partials, the cross product and the
///   final normalisation.
///
/// Everything on the right is computed here in `f64` from the exact partials, so the bound
/// holds wherever the kernel takes the direct normal `S_u x S_v` (not its limit or fallback
/// rules). It is a worst case: on random rational patches with weights over six decades the
/// kernel's error is at most a few percent of it (`properties.rs` measures the ratio).
pub fn normal_bound(r: &RefPatch, u: f64, v: f64) -> Option<f64> {
    let (p, q) = (r.du, r.dv);
    let eps = f64::powi(2.0, -24);
    let n = (3 * (p + q) + 8) as f64;
    let gamma = n * eps / (1.0 - n * eps);
    let b = |n: usize, i: isize, t: f64| bernstein(n, i, t);
    let (mut m0, mut mu, mut mv) = ([0.0f64; 4], [0.0f64; 4], [0.0f64; 4]);
    let (mut w, mut wu, mut wv) = (0.0, 0.0, 0.0);
    for i in 0..=p {
        for j in 0..=q {
            let k = i * (q + 1) + j;
            let pw = scale(r.pts[k], r.w[k]);
            let h = [pw[0], pw[1], pw[2], r.w[k]];
            let (ii, jj) = (i as isize, j as isize);
            let c0 = b(p, ii, u) * b(q, jj, v);
            let cu = p as f64 * (b(p - 1, ii - 1, u) + b(p - 1, ii, u)) * b(q, jj, v);
            let cv = q as f64 * b(p, ii, u) * (b(q - 1, jj - 1, v) + b(q - 1, jj, v));
            for c in 0..4 {
                m0[c] += c0 * h[c].abs();
                mu[c] += cu * h[c].abs();
                mv[c] += cv * h[c].abs();
            }
            w += c0 * r.w[k];
            wu += p as f64 * (b(p - 1, ii - 1, u) - b(p - 1, ii, u)) * b(q, jj, v) * r.w[k];
            wv += q as f64 * b(p, ii, u) * (b(q - 1, jj - 1, v) - b(q - 1, jj, v)) * r.w[k];
        }
    }
    let f = r.eval(u, v);
    let s = f.p;
    let ds = [0, 1, 2]
        .map(|c| (gamma * m0[c] + s[c].abs() * gamma * m0[3]) / w + 2.0 * eps * s[c].abs());
    let relative = |m: [f64; 4], partial: V3, w_d: f64| {
        let d = [0, 1, 2].map(|c| {
            let a = partial[c] * w + s[c] * w_d;
            (gamma * m[c]
                + s[c].abs() * gamma * m[3]
                + ds[c] * w_d.abs()
                + partial[c].abs() * gamma * m0[3])
                / w
                + 2.0 * eps * (a.abs() + 2.0 * (s[c] * w_d).abs()) / w
                + 2.0 * eps * partial[c].abs()
        });
        norm(d) / norm(partial)
    };
    let (ru, rv) = (relative(mu, f.su, wu), relative(mv, f.sv, wv));
    let sin = norm(cross(f.su, f.sv)) / (norm(f.su) * norm(f.sv));
    let x = (ru + rv + ru * rv + 8.0 * eps) / sin;
    (x < 1.0).then(|| x.asin() + 4.0 * eps)
}
