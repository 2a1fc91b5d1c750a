//! Computed bounds of a triangle's deviation *on screen*, in `f64`, written for the oracle
//! measurements (`examples/oracle_selection.rs`) and sharing no code with the kernel: an
//! isotropic form (the object-space bound times the largest scale of the projection, the form
//! the kernel uses) and a directional form (the lattice's deviation vectors projected one by
//! one), which also counts that a deviation along the line of sight does not move a pixel.
//!
//! # The bound
//!
//! Let `T` be a domain triangle with corners `p_i`, `L` the linear interpolant of the surface
//! points `P_i = S(p_i)` at the same barycentric coordinates, and `e(x) = S(x) - L(x)`.
//!
//! **In model space.** Take the points `x_k` of the barycentric lattice of step `1/n` on `T`
//! and `e_k = e(x_k)`. The lattice cuts `T` into triangles `T_s` similar to `T` at scale
//! `1/n`. On one of them, with `L_s` the interpolant of `S` at its corners,
//! `e(x) = (S - L_s)(x) + (L_s - L)(x)`. The second term is linear and equals `e_k` at
//! `T_s`'s corners, so it is a convex combination of three `e_k`; the first is at most
//! `R = ½ ρ² / n²` long, where `ρ` is the radius of `T`'s smallest enclosing circle in the
//! coordinates `(√α u, √β v)`, `α = a + b t`, `β = c + b / t` for any `t > 0`, and
//! `a, b, c` bound `|S_uu|, |S_uv|, |S_vv|` over `T` (Taylor's theorem with integral
//! remainder; the kernel's `deviation` module derives the same remainder). So
//!
//! `e(x) ∈ H + B(R)`, with `H = conv{e_k}` and `B(R)` the ball of radius `R`,
//!
//! and `|e(x)| <= m = max_k |e_k| + R`.
//!
//! **On screen.** In view coordinates (right, up, depth) with focal length `f` in pixels, a
//! flat point `l = L(x)` and the surface point `s = l + e` land `f (e_⊥ - τ e_z) / s_z` apart,
//! where `τ = l_⊥ / l_z` is `l`'s view ray (`s_⊥/s_z - l_⊥/l_z = (l_z e_⊥ - l_⊥ e_z) / (l_z s_z)`).
//! Then:
//!
//! - A sample counts only where `s` is on screen (in front of the near plane at depth
//!   `z_near > 0`, inside the side planes) and `l` is in front of the near plane
//!   (`host_tests::screen`'s measure). Then `l`, within `m` of `s`, lies in the part `F` of
//!   the flat triangle in front of the near plane and within `m` of the side planes: a convex
//!   polygon, the triangle clipped plane by plane. So `s_z >= z_min = max(z_near,
//!   min_F l_z - m)` (`|e_z| <= m`; `l_z` is linear, least at a vertex of `F`).
//! - The central projection maps `F` to the polygon of its vertices' rays `τ_i` (segments in
//!   front of the eye project to segments), so `τ ∈ conv{τ_i}`.
//! - `φ(τ, e) = |e_⊥ - τ e_z|` is convex in `e` for a fixed `τ` and in `τ` for a fixed `e`.
//!   Over `e ∈ H + B(R)` its largest value is at most `max_k φ(τ, e_k) + R √(1 + |τ|²)`
//!   (the norm of `e ↦ e_⊥ - τ e_z`), and each of those terms is largest at a corner ray.
//!
//! So the projected deviation of every sample of the triangle that counts is at most
//!
//! `hull = f / z_min · max_i ( max_k φ(τ_i, e_k) + R √(1 + |τ_i|²) )`,
//!
//! and, from `φ(τ, e) <= |e| √(1 + |τ|²)`, at most the isotropic
//! `isotropic = f / z_min · m · max_i √(1 + |τ_i|²)`. Where `F` is empty, nothing of the
//! triangle counts and both are 0.
//!
//! The second-derivative bounds come from the control net of the patch restricted to the
//! triangle's bounding box (de Casteljau), by the convex hull property: `|S_uu| <=
//! p (p - 1) / Δu² · max |Δ²_u P|`, `|S_uv| <= p q / (Δu Δv) · max |Δ_u Δ_v P|`, likewise
//! `S_vv`. Polynomial patches only: a rational patch gives `None`.

use crate::reference::{dot, RefPatch, V3};
use crate::screen::Meter;

/// Lattice steps per side (as the kernel's).
pub const LATTICE: usize = 6;

/// The screen bounds of one triangle, and where its largest deviation on screen was sampled.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScreenBound {
    /// The isotropic bound, pixels.
    pub isotropic: f64,
    /// The directional bound, pixels (at most `isotropic`: the smaller is kept).
    pub hull: f64,
    /// The bound in model units, `m`.
    pub object: f64,
    /// The lattice point (unit parameters) of the largest sampled deviation in model units, or
    /// the centroid where every sampled deviation is 0.
    pub at: [f64; 2],
}

/// `max |S_uu|, max |S_uv|, max |S_vv|` over `[u0, u1] x [v0, v1]` of polynomial patch `r`.
pub fn second_derivative_bounds(r: &RefPatch, [u0, u1, v0, v1]: [f64; 4]) -> Option<[f64; 3]> {
    if r.w.iter().any(|&w| w != r.w[0]) {
        return None;
    }
    let (p, q) = (r.du, r.dv);
    let mut net: Vec<Vec<V3>> = (0..=p)
        .map(|i| (0..=q).map(|j| r.pts[i * (q + 1) + j]).collect())
        .collect();
    for row in net.iter_mut() {
        *row = restrict(row, v0, v1);
    }
    for j in 0..=q {
        let column: Vec<V3> = net.iter().map(|row| row[j]).collect();
        for (row, point) in net.iter_mut().zip(restrict(&column, u0, u1)) {
            row[j] = point;
        }
    }
    let (hu, hv) = (u1 - u0, v1 - v0);
    let largest = |points: &mut dyn Iterator<Item = V3>| {
        points.map(|d| dot(d, d).sqrt()).fold(0.0f64, f64::max)
    };
    let combine = |terms: &[(usize, usize, f64)]| -> V3 {
        let mut d = [0.0; 3];
        for &(i, j, c) in terms {
            for (dk, pk) in d.iter_mut().zip(net[i][j]) {
                *dk += c * pk;
            }
        }
        d
    };
    let a = if p >= 2 {
        let mut it = (0..=p - 2)
            .flat_map(|i| (0..=q).map(move |j| (i, j)))
            .map(|(i, j)| combine(&[(i + 2, j, 1.0), (i + 1, j, -2.0), (i, j, 1.0)]));
        largest(&mut it) * (p * (p - 1)) as f64 / (hu * hu)
    } else {
        0.0
    };
    let c = if q >= 2 {
        let mut it = (0..=p)
            .flat_map(|i| (0..=q - 2).map(move |j| (i, j)))
            .map(|(i, j)| combine(&[(i, j + 2, 1.0), (i, j + 1, -2.0), (i, j, 1.0)]));
        largest(&mut it) * (q * (q - 1)) as f64 / (hv * hv)
    } else {
        0.0
    };
    let b = if p >= 1 && q >= 1 {
        let mut it = (0..p)
            .flat_map(|i| (0..q).map(move |j| (i, j)))
            .map(|(i, j)| {
                combine(&[
                    (i + 1, j + 1, 1.0),
                    (i + 1, j, -1.0),
                    (i, j + 1, -1.0),
                    (i, j, 1.0),
                ])
            });
        largest(&mut it) * (p * q) as f64 / (hu * hv)
    } else {
        0.0
    };
    Some([a, b, c])
}

/// The Bezier net of the curve with net `points` restricted to `[a, b]` of its parameter.
fn restrict(points: &[V3], a: f64, b: f64) -> Vec<V3> {
    // The part after `t`, by de Casteljau.
    let after = |net: &[V3], t: f64| -> Vec<V3> {
        let mut w = net.to_vec();
        let n = w.len();
        let mut right = vec![w[n - 1]];
        for k in 1..n {
            for i in 0..n - k {
                let next = w[i + 1];
                for (c, d) in w[i].iter_mut().zip(next) {
                    *c = *c * (1.0 - t) + d * t;
                }
            }
            right.push(w[n - 1 - k]);
        }
        right.reverse();
        right
    };
    let tail = after(points, a);
    if b >= 1.0 || a >= 1.0 {
        return tail;
    }
    // Restrict the tail (parameter s = (t - a) / (1 - a)) to s <= (b - a) / (1 - a): the part
    // after 1 - s of the reversed net.
    let mut reversed = tail;
    reversed.reverse();
    let mut head = after(&reversed, 1.0 - (b - a) / (1.0 - a));
    head.reverse();
    head
}

/// `½ ρ²` of the triangle with corners `uv` for second-derivative bounds `[a, b, c]`: the
/// smallest over a few splits `t` of the mixed term.
pub fn curvature_term([a, b, c]: [f64; 3], uv: [[f64; 2]; 3]) -> f64 {
    let mut best = f64::INFINITY;
    for t in [0.25, 0.5, 1.0, 2.0, 4.0] {
        let (alpha, beta) = (a + b * t, c + b / t);
        let p = uv.map(|[u, v]| [u * alpha.sqrt(), v * beta.sqrt()]);
        let d2 = |x: [f64; 2], y: [f64; 2]| (x[0] - y[0]).powi(2) + (x[1] - y[1]).powi(2);
        let s = [d2(p[1], p[2]), d2(p[0], p[2]), d2(p[0], p[1])];
        let longest = s.iter().copied().fold(0.0, f64::max);
        let obtuse = 2.0 * longest >= s[0] + s[1] + s[2];
        let rho2 = if obtuse {
            longest / 4.0
        } else {
            let area2 = ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1])
                - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]))
                .abs();
            s[0] * s[1] * s[2] / (4.0 * area2 * area2)
        };
        best = best.min(0.5 * rho2);
    }
    best
}

/// The deviations of one triangle on the lattice of step `1/n` (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct LatticeDeviations {
    /// The surface points at the corners.
    pub corners: [V3; 3],
    /// `e_k`, in model space, the corners' zero vectors included.
    pub vectors: Vec<V3>,
    /// `R`: every deviation is within `R` of the vectors' hull.
    pub remainder: f64,
    /// `m = max_k |e_k| + R`, the bound in model units.
    pub object: f64,
    /// The lattice point (unit parameters) of the largest `|e_k|`, or the centroid where
    /// every one is 0.
    pub at: [f64; 2],
}

/// The deviation vectors of the triangle with corner parameters `uv` on polynomial patch `r`
/// at the points of the barycentric lattice of step `1/n` (`n` at least 1), and the remainder
/// that covers the rest of the triangle; `None` for a rational patch.
pub fn lattice_deviations(r: &RefPatch, uv: [[f64; 2]; 3], n: usize) -> Option<LatticeDeviations> {
    let lo = |k: usize| uv.iter().map(|p| p[k]).fold(1.0, f64::min);
    let hi = |k: usize| uv.iter().map(|p| p[k]).fold(0.0, f64::max);
    let derivatives = second_derivative_bounds(r, [lo(0), hi(0), lo(1), hi(1)])?;
    let n = n.max(1);
    let remainder = curvature_term(derivatives, uv) / (n * n) as f64;
    let corners: [V3; 3] = uv.map(|[u, v]| r.point(u, v));
    let mut vectors = Vec::with_capacity((n + 1) * (n + 2) / 2);
    let centroid = [0, 1].map(|k| (uv[0][k] + uv[1][k] + uv[2][k]) / 3.0);
    let (mut at, mut largest) = (centroid, 0.0f64);
    for i in 0..=n {
        for j in 0..=n - i {
            let (a, b) = (i as f64 / n as f64, j as f64 / n as f64);
            let c = 1.0 - a - b;
            let x = [0, 1].map(|k| uv[0][k] * c + uv[1][k] * a + uv[2][k] * b);
            let l = [0, 1, 2].map(|k| corners[0][k] * c + corners[1][k] * a + corners[2][k] * b);
            let s = r.point(x[0], x[1]);
            let e = [0, 1, 2].map(|k| s[k] - l[k]);
            let length = dot(e, e).sqrt();
            if length > largest {
                (at, largest) = (x, length);
            }
            vectors.push(e);
        }
    }
    Some(LatticeDeviations {
        corners,
        vectors,
        remainder,
        object: largest + remainder,
        at,
    })
}

/// The screen bounds of the triangle with corner parameters `uv` on polynomial patch `r`, or
/// `None` for a rational patch.
pub fn screen_bound(r: &RefPatch, uv: [[f64; 2]; 3], meter: &Meter) -> Option<ScreenBound> {
    screen_bound_kept(r, uv, meter, LATTICE, usize::MAX)
}

/// [`screen_bound`] from the lattice of step `1/n` (`n` at least 1; fewer deviation vectors, a
/// remainder `n²` times smaller), keeping at most `keep` of its deviation vectors as a bake
/// that stores a bound per triangle could keep them (see [`keep_vectors`]): the rest are
/// covered by widening the remainder, so the bound stays sound.
pub fn screen_bound_kept(
    r: &RefPatch,
    uv: [[f64; 2]; 3],
    meter: &Meter,
    n: usize,
    keep: usize,
) -> Option<ScreenBound> {
    let lattice = lattice_deviations(r, uv, n)?;
    let (at, remainder) = (lattice.at, lattice.remainder);
    let flat = lattice.corners.map(|p| meter.view(p));
    let deviations: Vec<V3> = lattice.vectors.iter().map(|&e| meter.rotate(e)).collect();
    let object = lattice.object;
    let (deviations, remainder) = match keep {
        SEGMENT => segment_vectors(deviations, &flat, remainder),
        _ => keep_vectors(deviations, keep, remainder),
    };
    // Where a sample counts, `l` is in front of the near plane and within `m` of the screen.
    let front = meter.clip(&flat, object);
    if front.is_empty() {
        return Some(ScreenBound {
            isotropic: 0.0,
            hull: 0.0,
            object,
            at,
        });
    }
    let nearest = front.iter().map(|v| v[2]).fold(f64::INFINITY, f64::min);
    let z_min = (nearest - object).max(meter.near());
    let (mut hull, mut spread) = (0.0f64, 0.0f64);
    for v in front {
        let tau = [v[0] / v[2], v[1] / v[2]];
        let g = (1.0 + tau[0] * tau[0] + tau[1] * tau[1]).sqrt();
        spread = spread.max(g);
        let phi = deviations
            .iter()
            .map(|e| (e[0] - tau[0] * e[2]).powi(2) + (e[1] - tau[1] * e[2]).powi(2))
            .fold(0.0f64, f64::max)
            .sqrt();
        hull = hull.max(phi + remainder * g);
    }
    let scale = meter.focal() / z_min;
    let isotropic = scale * object * spread;
    Some(ScreenBound {
        isotropic,
        hull: (scale * hull).min(isotropic),
        object,
        at,
    })
}

/// [`screen_bound_kept`]'s `keep` for the segment along the flat triangle's normal
/// ([`segment_vectors`]).
pub const SEGMENT: usize = usize::MAX - 1;

/// In place of `vectors`: the segment along the unit normal of the flat triangle `flat` from
/// the lowest to the highest of their heights over it (zero included), with the remainder
/// widened by the longest of their parts across the normal, so that every vector lies in the
/// segment widened by it (the whole tangential part where the triangle has no normal).
pub fn segment_vectors(vectors: Vec<V3>, flat: &[V3; 3], remainder: f64) -> (Vec<V3>, f64) {
    let sub = |a: V3, b: V3| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let n = crate::reference::cross(sub(flat[1], flat[0]), sub(flat[2], flat[0]));
    let length = dot(n, n).sqrt();
    if length == 0.0 || !length.is_finite() {
        let longest = vectors
            .iter()
            .map(|e| dot(*e, *e).sqrt())
            .fold(0.0, f64::max);
        return (vec![[0.0; 3]], remainder + longest);
    }
    let n = n.map(|x| x / length);
    let (mut low, mut high, mut across) = (0.0f64, 0.0f64, 0.0f64);
    for e in &vectors {
        let h = dot(*e, n);
        low = low.min(h);
        high = high.max(h);
        let t = sub(*e, n.map(|x| x * h));
        across = across.max(dot(t, t).sqrt());
    }
    (
        vec![n.map(|x| x * low), n.map(|x| x * high)],
        remainder + across,
    )
}

/// The directional bound over a *region*: a box in model space that holds a triangle's flat
/// triangle and its piece of surface, with a set of deviation vectors and a remainder that
/// cover its deviations (`e(x) ∈ conv{vectors} + B(remainder)`).
///
/// The derivation of the module docs goes through with the box in place of `F`: where a sample
/// counts, `l` (on the flat triangle) and `s` (on the surface piece) both lie in the box, `l`
/// in front of the near plane and `s` on screen. So `s_z >= max(z_near, least z of the box)`,
/// and `τ` lies in the hull of the rays of the box's part in front of the near plane (its
/// corners there and the points where its edges cross the plane); with `rect`, in the
/// rectangle of their least and largest slopes, a superset that costs 4 rays instead of up
/// to 12. Where every corner of the box is beyond one plane of the view, no sample counts
/// and the bound is 0.
///
/// What makes it useful: it is *monotone*. A box inside another, vectors inside another's
/// hull, a smaller remainder all give a bound no larger, for every view. A bake that stores
/// for each bisection vertex the union of its triangles' regions and its descendants' (the
/// saturation of Lindstrom and Pascucci's terrain meshes) gets a test that a split never
/// passes where the split above it fails, so the mesh a frame selects top-down is conforming
/// without asking any neighbour.
pub fn region_bound(
    meter: &Meter,
    [lo, hi]: [V3; 2],
    vectors: &[V3],
    remainder: f64,
    rect: bool,
) -> f64 {
    let corners: Vec<V3> = (0..8)
        .map(|k| {
            let pick = |c: usize| if k >> c & 1 == 0 { lo[c] } else { hi[c] };
            [pick(0), pick(1), pick(2)]
        })
        .collect();
    if meter.outside_one_plane(&corners) {
        return 0.0;
    }
    let view: Vec<V3> = corners.iter().map(|&p| meter.view(p)).collect();
    let near = meter.near();
    let mut front: Vec<V3> = view.iter().copied().filter(|v| v[2] >= near).collect();
    for a in 0..8 {
        for c in 0..3 {
            let b = a | 1 << c;
            if b == a {
                continue;
            }
            let (p, q) = (view[a], view[b]);
            if (p[2] < near) != (q[2] < near) {
                let t = (near - p[2]) / (q[2] - p[2]);
                front.push([0, 1, 2].map(|k| p[k] + t * (q[k] - p[k])));
            }
        }
    }
    if front.is_empty() {
        return 0.0;
    }
    let z_min = front
        .iter()
        .map(|v| v[2])
        .fold(f64::INFINITY, f64::min)
        .max(near);
    let mut rays: Vec<[f64; 2]> = front.iter().map(|v| [v[0] / v[2], v[1] / v[2]]).collect();
    if rect {
        let (mut a, mut b) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for r in &rays {
            for k in 0..2 {
                a[k] = a[k].min(r[k]);
                b[k] = b[k].max(r[k]);
            }
        }
        rays = vec![a, [b[0], a[1]], b, [a[0], b[1]]];
    }
    let e: Vec<V3> = vectors.iter().map(|&d| meter.rotate(d)).collect();
    let worst = rays
        .iter()
        .map(|tau| {
            let g = (1.0 + tau[0] * tau[0] + tau[1] * tau[1]).sqrt();
            let phi = e
                .iter()
                .map(|e| (e[0] - tau[0] * e[2]).powi(2) + (e[1] - tau[1] * e[2]).powi(2))
                .fold(0.0f64, f64::max)
                .sqrt();
            phi + remainder * g
        })
        .fold(0.0f64, f64::max);
    meter.focal() / z_min * worst
}

/// At most `keep` of `vectors`, besides the zero vector (the corners' deviation, kept for
/// free), and `remainder` widened so that the derivation of the module docs still holds: each
/// vector left out lies within `δ` of the kept ones' hull, so `conv{e_k} + B(R)` lies in
/// `conv{kept} + B(R + δ)`. Vectors are kept farthest from the hull first. The distance to the
/// hull is bounded from above by a point of the hull that Frank-Wolfe steps reach from the
/// nearest kept vector: any point of the hull gives a sound `δ`, a better one a smaller `δ`.
pub fn keep_vectors(vectors: Vec<V3>, keep: usize, remainder: f64) -> (Vec<V3>, f64) {
    if vectors.len() <= keep {
        return (vectors, remainder);
    }
    let sub = |a: V3, b: V3| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let distance = |a: V3, b: V3| dot(sub(a, b), sub(a, b)).sqrt();
    let to_hull = |e: V3, kept: &[V3]| {
        let mut x = *kept
            .iter()
            .min_by(|a, b| distance(e, **a).total_cmp(&distance(e, **b)))
            .expect("the zero vector is kept");
        for _ in 0..40 {
            // The kept vector farthest along the descent of |x - e|², and the best point on
            // the segment to it (x stays in the hull).
            let g = sub(x, e);
            let s = *kept
                .iter()
                .min_by(|a, b| dot(g, **a).total_cmp(&dot(g, **b)))
                .expect("the zero vector is kept");
            let d = sub(s, x);
            let dd = dot(d, d);
            let step = if dd > 0.0 {
                (-dot(g, d) / dd).clamp(0.0, 1.0)
            } else {
                0.0
            };
            if step == 0.0 {
                break;
            }
            x = [0, 1, 2].map(|k| x[k] + step * d[k]);
        }
        distance(e, x)
    };
    let mut kept: Vec<V3> = vec![[0.0; 3]];
    for _ in 0..keep {
        let (k, d) = vectors
            .iter()
            .enumerate()
            .map(|(k, &e)| (k, to_hull(e, &kept)))
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .expect("vectors");
        if d == 0.0 {
            break;
        }
        kept.push(vectors[k]);
    }
    let widen = vectors
        .iter()
        .map(|&e| to_hull(e, &kept))
        .fold(0.0f64, f64::max);
    (kept, remainder + widen)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The curve of net `points` at `t`, by de Casteljau.
    fn at(points: &[V3], t: f64) -> V3 {
        let mut w = points.to_vec();
        while w.len() > 1 {
            w = w
                .windows(2)
                .map(|p| [0, 1, 2].map(|c| p[0][c] * (1.0 - t) + p[1][c] * t))
                .collect();
        }
        w[0]
    }

    #[test]
    fn a_restricted_net_traces_the_same_curve() {
        let net = [
            [0.0, 0.0, 0.0],
            [1.0, 2.0, 0.5],
            [3.0, -1.0, 2.0],
            [4.0, 1.0, -1.0],
        ];
        for (a, b) in [(0.2, 0.7), (0.0, 0.3), (0.6, 1.0), (0.25, 0.25 + 1e-3)] {
            let part = restrict(&net, a, b);
            for s in [0.0, 0.3, 0.5, 1.0] {
                let (x, y) = (at(&part, s), at(&net, a + s * (b - a)));
                let gap = (0..3).map(|c| (x[c] - y[c]).abs()).fold(0.0, f64::max);
                assert!(gap < 1e-12, "[{a}, {b}] at {s}: {x:?} against {y:?}");
            }
        }
    }
}
