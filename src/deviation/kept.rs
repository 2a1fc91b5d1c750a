//! A few deviation vectors in place of a lattice's many, with the remainder widened so that
//! the bound they give is still a bound.
//!
//! # Why it holds
//!
//! The deviation of a triangle lies in `conv{e_k} + B(R)` (the lattice's vectors, the
//! corners' included, and the remainder; see `deviation`'s module docs). Keep the vectors
//! `d_1 .. d_K` and the zero vector (a corner's deviation, free), quantised, and let `δ` be at
//! least the distance of every `e_k` from `H = conv{0, d_1 .. d_K}`. Then each `e_k` lies in
//! `H + B(δ)`, so does their hull (`H + B(δ)` is convex), and the deviation lies in
//! `H + B(R + δ)`: every bound of the `deviation` module holds with the kept vectors and the
//! remainder `R + δ`.
//!
//! `δ` is bounded from above by a point of `H`: the distance from `e_k` to any point of `H` is
//! at least its distance to `H`. The point taken is the nearest one, found among few
//! candidates (see [`Hull`]): `H` has at most five vertices, and the point of a convex hull
//! nearest `e` is a vertex, or the projection of `e` on an edge, a triangle or (inside) a
//! tetrahedron of them that falls in its own simplex. Each candidate is computed in `f32`
//! from barycentric weights checked to be at least 0 and to sum to at most 1, so it lies
//! within `16ε` of the longest vertex of `H` of a point of `H` (see [`Hull`]); that drift is
//! added, and the distance's own roundings are covered by `1 + 8ε` (see
//! [`distance_to_hull`]). (Frank-Wolfe steps found such points before, about
//! five times slower for bounds as large or larger.)
//!
//! Vectors are kept farthest from the kept ones' hull first: the longest, then the one the
//! hull reaches least, and so on.

use glam::Vec3;

use crate::deviation::EPS;
use crate::math::{length, max};

/// Deviation vectors a node keeps (besides zero): 12 bytes a triangle. With the bake's lattice
/// of step 1/12 (a remainder a quarter of the 1/6 lattice's), four give about the triangles
/// eight do (CHANGELOG.md has the measurement).
pub const KEPT: usize = 4;

/// Largest quantised coordinate: six bits a coordinate (what the compact bytes keep). Against
/// eight bits (127), the firmware teapot's frames take -0.4% to +0.8% triangles (the rounding
/// is a small part of the widening), and a diamond's bound 3 bytes less.
pub(crate) const Q: f32 = 31.0;

/// Kept vectors, quantised: vector `i` is `scale * vectors[i]`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Kept {
    /// Quantised coordinates.
    pub vectors: [[i8; 3]; KEPT],
    /// Model units per quantisation step.
    pub scale: f32,
    /// `δ`: every input vector's distance to `conv{0, kept}` is at most this.
    pub widening: f32,
}

/// The vectors of `q` at `scale`, as the run time reads them.
pub(crate) fn dequantize(q: &[[i8; 3]; KEPT], scale: f32) -> [Vec3; KEPT] {
    q.map(|[x, y, z]| Vec3::new(x as f32, y as f32, z as f32) * scale)
}

/// Most vertices of `conv{0, kept}`.
const VERTICES: usize = KEPT + 1;
/// Its edges, triangles and tetrahedra: pairs, triples and quadruples of vertices.
const PAIRS: usize = VERTICES * (VERTICES - 1) / 2;
const TRIPLES: usize = PAIRS * (VERTICES - 2) / 3;
const QUADRUPLES: usize = TRIPLES * (VERTICES - 3) / 4;

/// One simplex of the hull's vertices (an edge, a triangle or a tetrahedron) ready to take a
/// point's barycentric coordinates: `λ_i = rows[i] · (e - origin)` are the weights of its
/// other vertices `origin + sides[i]` (exact for a point of its affine hull, in exact
/// arithmetic), the origin's weight `1 - Σ λ_i`.
#[derive(Clone, Copy)]
struct Simplex<const D: usize> {
    origin: Vec3,
    sides: [Vec3; D],
    rows: [Vec3; D],
}

impl<const D: usize> Simplex<D> {
    const EMPTY: Self = Simplex {
        origin: Vec3::ZERO,
        sides: [Vec3::ZERO; D],
        rows: [Vec3::ZERO; D],
    };

    /// The point of the simplex that `e`'s coordinates name, where they are all at least 0
    /// and sum to at most 1 (the projection of `e` on its affine hull lies in it): its
    /// squared distance from `e`.
    #[inline(always)]
    fn distance2(&self, e: Vec3) -> Option<f32> {
        let p = e - self.origin;
        let mut point = self.origin;
        let mut total = 0.0f32;
        for (row, side) in self.rows.iter().zip(&self.sides) {
            let l = row.dot(p);
            // (NaN is not at least 0 either.)
            if l.is_nan() || l < 0.0 {
                return None;
            }
            total += l;
            point += *side * l;
        }
        let d = e - point;
        (total <= 1.0).then(|| d.dot(d))
    }
}

/// `conv{0, kept}` ready for [`distance_to_hull`]: its vertices, zero first, every edge,
/// triangle and tetrahedron of them set up to project a point, and the drift allowed for the
/// roundings of a point of it (from its longest vertex); all computed once for the vectors
/// measured against it.
///
/// The point of a convex hull nearest `e` lies in a face of it, a vertex, an edge or a
/// triangle whose projection of `e` is that point, or inside it (in a tetrahedron of its
/// vertices). So the least distance over the vertices and over the projections that fall in
/// their own edge, triangle or tetrahedron is the distance to the hull; with the projections
/// computed in `f32`, each candidate is still a point of the hull up to the drift, and its
/// distance an upper bound of the distance up to that (see [`distance_to_hull`]).
struct Hull {
    vertices: [Vec3; VERTICES],
    n: usize,
    edges: [Simplex<1>; PAIRS],
    triangles: [Simplex<2>; TRIPLES],
    tetrahedra: [Simplex<3>; QUADRUPLES],
    counts: [usize; 3],
    drift: f32,
}

impl Hull {
    fn new(hull: &[Vec3]) -> Hull {
        let mut h = Hull {
            vertices: [Vec3::ZERO; VERTICES],
            n: hull.len().min(KEPT) + 1,
            edges: [Simplex::EMPTY; PAIRS],
            triangles: [Simplex::EMPTY; TRIPLES],
            tetrahedra: [Simplex::EMPTY; QUADRUPLES],
            counts: [0; 3],
            drift: 0.0,
        };
        let n = h.n;
        h.vertices[1..n].copy_from_slice(&hull[..n - 1]);
        let v = h.vertices;
        let mut big = 0.0f32;
        for &x in &v[..n] {
            big = max(big, length(x));
        }
        // The candidates' roundings, with `big` the longest vertex: a side (up to `2 big`
        // long) rounds by `2ε big`; its product with a weight at most 1 by as much again;
        // the three additions onto the origin by `ε` of a point at most `big` from zero
        // each; and the origin's weight `1 - Σ` may be `-2ε` where the computed sum is at
        // most 1 (`4ε big`): about `11ε big` in all, and `16ε big` is taken.
        h.drift = 16.0 * EPS * big;
        for i in 0..n {
            for j in i + 1..n {
                let u = v[j] - v[i];
                let uu = u.dot(u);
                if uu > 0.0 && uu.is_finite() {
                    h.edges[h.counts[0]] = Simplex {
                        origin: v[i],
                        sides: [u],
                        rows: [u / uu],
                    };
                    h.counts[0] += 1;
                }
                for k in j + 1..n {
                    let w = v[k] - v[i];
                    let (uw, ww) = (u.dot(w), w.dot(w));
                    let det = uu * ww - uw * uw;
                    if det > 0.0 && det.is_finite() {
                        let ru = (u * ww - w * uw) / det;
                        let rw = (w * uu - u * uw) / det;
                        h.triangles[h.counts[1]] = Simplex {
                            origin: v[i],
                            sides: [u, w],
                            rows: [ru, rw],
                        };
                        h.counts[1] += 1;
                    }
                    for l in k + 1..n {
                        let z = v[l] - v[i];
                        let det = u.dot(w.cross(z));
                        if det != 0.0 && det.is_finite() {
                            h.tetrahedra[h.counts[2]] = Simplex {
                                origin: v[i],
                                sides: [u, w, z],
                                rows: [w.cross(z) / det, z.cross(u) / det, u.cross(w) / det],
                            };
                            h.counts[2] += 1;
                        }
                    }
                }
            }
        }
        h
    }
}

/// Added to every distance: covers the square roots of squared distances that underflow
/// (below `2^-126` a square keeps no relative precision; its root is below `2^-63`).
const FLOOR: f32 = 1.0 / (1u64 << 62) as f32;

/// An upper bound of the distance from `e` to `hull` (`conv{0, kept}`): the distance from `e`
/// to a candidate of [`Hull`] (the least, unless one already puts the bound at most
/// `enough`), plus the drift of a computed candidate from the hull and [`FLOOR`], with the
/// roundings of the distance itself covered by `1 + 8ε`: the difference `e - p` (one), the
/// three-term dot product (one and a half, on the root), the root, the two sums and the
/// product (one each) make at most `5.5ε` of relative error. Where the vertices alone put it
/// at most `enough`, that bound (the others can only lower it).
fn distance_to_hull(e: Vec3, hull: &Hull, enough: f32) -> f32 {
    let bound = |d2: f32| (crate::math::sqrt(d2) + hull.drift + FLOOR) * (1.0 + 8.0 * EPS);
    let mut best = f32::INFINITY;
    for &v in &hull.vertices[..hull.n] {
        let d = (e - v).dot(e - v);
        if d < best {
            best = d;
        }
    }
    if bound(best) <= enough {
        return bound(best);
    }
    // A squared distance at most `close` puts the bound at most `enough` (the root's and the
    // sum's roundings given a margin): then the other candidates need not be looked at.
    let t = enough / (1.0 + 16.0 * EPS) - hull.drift - FLOOR;
    let close = if t > 0.0 {
        t * t * (1.0 - 1.0 / (1u32 << 20) as f32)
    } else {
        -1.0
    };
    // Inside first (most vectors are: their distance is all but 0), then the triangles and
    // edges.
    let tetrahedra = hull.tetrahedra[..hull.counts[2]]
        .iter()
        .map(|s| s.distance2(e));
    let triangles = hull.triangles[..hull.counts[1]]
        .iter()
        .map(|s| s.distance2(e));
    let edges = hull.edges[..hull.counts[0]].iter().map(|s| s.distance2(e));
    for d in tetrahedra.chain(triangles).chain(edges).flatten() {
        if d < best {
            best = d;
            if best <= close {
                break;
            }
        }
    }
    bound(best)
}

/// Search for the vector farthest from a hull that only grows: each vector keeps an upper
/// bound of its distance (its distance from a smaller hull is one), and only vectors whose
/// bound is above the farthest measured so far are measured.
struct Farthest {
    /// Upper bound of each vector's distance to the hull.
    bound: [f32; MAX_VECTORS],
}

impl Farthest {
    /// The vector farthest from `conv{0, hull}` and that distance's bound (each bound lowered
    /// to its measurement), or `None` when every bound is 0. The vector with the largest
    /// bound is measured first, so that the others are mostly measured only until they are
    /// below it.
    fn next(&mut self, vectors: &[Vec3], hull: &[Vec3]) -> Option<(usize, f32)> {
        let hull = Hull::new(hull);
        let bounds = &mut self.bound[..vectors.len()];
        let mut top = (0.0f32, None);
        for (k, &b) in bounds.iter().enumerate() {
            if b > top.0 {
                top = (b, Some(k));
            }
        }
        let first = top.1?;
        bounds[first] = bounds[first].min(distance_to_hull(vectors[first], &hull, 0.0));
        let mut best = (0.0f32, None);
        if bounds[first] > 0.0 {
            best = (bounds[first], Some(first));
        }
        for (k, (b, e)) in bounds.iter_mut().zip(vectors).enumerate() {
            if k != first && *b > best.0 {
                // Measured only as far as it matters: a bound at most the best one's is
                // enough.
                *b = b.min(distance_to_hull(*e, &hull, best.0));
                if *b > best.0 {
                    best = (*b, Some(k));
                }
            }
        }
        best.1.map(|k| (k, best.0))
    }
}

/// Most vectors [`keep`] looks at.
pub(crate) const MAX_VECTORS: usize = 192;

/// Keeps at most [`KEPT`] of `candidates` in place of `vectors` (at most [`MAX_VECTORS`] of
/// each: two lattices of the bake; see the module docs): the candidates are chosen from, the
/// widening covers every one of `vectors` (infinite where there are more than it looks at).
/// All must be finite. The scale is `round_scale` of the smallest
/// that fits (at least that: a coarser one only widens the remainder; one that is not gives no
/// vectors).
pub(crate) fn keep(
    vectors: &[Vec3],
    candidates: &[Vec3],
    round_scale: impl Fn(f32) -> f32,
) -> Kept {
    if vectors.len() > MAX_VECTORS {
        return Kept {
            widening: f32::INFINITY,
            ..Kept::default()
        };
    }
    let candidates = &candidates[..candidates.len().min(MAX_VECTORS)];
    let mut far = Farthest {
        bound: [0.0; MAX_VECTORS],
    };
    for (b, e) in far.bound.iter_mut().zip(candidates) {
        *b = length(*e);
    }
    let mut chosen = [Vec3::ZERO; KEPT];
    let mut n = 0;
    while n < KEPT {
        match far.next(candidates, &chosen[..n]) {
            Some((k, _)) => {
                chosen[n] = candidates[k];
                far.bound[k] = 0.0;
                n += 1;
            }
            None => break,
        }
    }
    let mut big = 0.0f32;
    for c in &chosen[..n] {
        big = max(big, max(max(c.x.abs(), c.y.abs()), c.z.abs()));
    }
    // The scale rounded (up) to the grid the bytes hold it on: every coordinate still fits.
    let scale = if big > 0.0 { round_scale(big / Q) } else { 0.0 };
    let scale = if scale >= big / Q && scale.is_finite() {
        scale
    } else {
        0.0
    };
    let mut q = [[0i8; 3]; KEPT];
    if scale > 0.0 {
        for (out, c) in q.iter_mut().zip(&chosen[..n]) {
            *out = c
                .to_array()
                .map(|x| libm::roundf(x / scale).clamp(-Q, Q) as i8);
        }
    }
    let hull = dequantize(&q, scale);
    // Every vector's distance bounded from the kept vertices alone, then the largest ones
    // measured in full until the largest measured one is above every other bound.
    let kept = Hull::new(&hull[..n]);
    let mut near = [0.0f32; MAX_VECTORS];
    let near = &mut near[..vectors.len()];
    let mut top = (0.0f32, 0);
    for (k, (b, e)) in near.iter_mut().zip(vectors).enumerate() {
        *b = distance_to_hull(*e, &kept, f32::INFINITY);
        if *b > top.0 {
            top = (*b, k);
        }
    }
    let mut widening = match vectors.get(top.1) {
        Some(e) => distance_to_hull(*e, &kept, 0.0),
        None => 0.0,
    };
    for (b, e) in near.iter().zip(vectors) {
        if *b > widening {
            widening = max(widening, distance_to_hull(*e, &kept, widening));
        }
    }
    Kept {
        vectors: q,
        scale,
        widening,
    }
}

/// The longest of `vectors`' lengths, rounded up (a bound of the root of the largest square,
/// the squares' few roundings covered).
pub(crate) fn longest_of(vectors: &[Vec3]) -> f32 {
    let mut big = 0.0f32;
    for v in vectors {
        big = max(big, v.dot(*v));
    }
    crate::math::sqrt_above(big) * (1.0 + 4.0 * crate::deviation::EPS)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn few_vectors_are_kept_exactly_up_to_quantisation() {
        let v = [Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 2.0, 0.0)];
        let k = keep(&v, &v, |s| s);
        let d = dequantize(&k.vectors, k.scale);
        assert!(d.contains(&Vec3::new(0.0, 2.0, 0.0)));
        assert!(k.widening < 0.02, "{}", k.widening);
    }

    #[test]
    fn the_widening_covers_every_vector_left_out() {
        // 28 vectors on a bumpy dome: each must lie within the widening of the kept hull.
        let mut v = [Vec3::ZERO; 28];
        for (k, e) in v.iter_mut().enumerate() {
            let a = k as f32 * 0.7;
            *e = Vec3::new(
                libm::cosf(a),
                libm::sinf(a),
                1.0 + 0.3 * libm::sinf(3.0 * a),
            ) * (0.5 + (k % 5) as f32 * 0.1);
        }
        let k = keep(&v, &v, |s| s);
        let d = dequantize(&k.vectors, k.scale);
        let n = d.iter().filter(|x| **x != Vec3::ZERO).count();
        assert_eq!(n, KEPT);
        for e in v {
            // A lower bound of e's distance to the hull, from the plane through the hull's
            // farthest point along a direction from one of its vertices to e: the widening
            // must be above it.
            let mut lower = 0.0f32;
            for a in d.iter().chain([Vec3::ZERO].iter()) {
                let dir = e - *a;
                if length(dir) == 0.0 {
                    continue;
                }
                let dir = dir / length(dir);
                let reach = d.iter().map(|h| h.dot(dir)).fold(0.0f32, f32::max);
                lower = lower.max(e.dot(dir) - reach);
            }
            assert!(lower <= k.widening, "{lower} > {}", k.widening);
        }
        assert!(k.widening < 0.5, "{}", k.widening);
    }
}

#[cfg(test)]
mod distance_tests {
    use super::*;
    use crate::test_rng::TestRng;

    /// The distance from `e` to `conv{0, hull}` in `f64`, by another method: pairwise
    /// Frank-Wolfe steps with exact line search, with the duality gap's certificate. Returns
    /// a lower and an upper bound of the distance.
    fn reference(e: Vec3, hull: &[Vec3]) -> (f64, f64) {
        let mut all = [[0.0f64; 3]; KEPT + 1];
        for (a, h) in all[1..].iter_mut().zip(hull) {
            *a = [h.x as f64, h.y as f64, h.z as f64];
        }
        let v = &all[..hull.len() + 1];
        let e = [e.x as f64, e.y as f64, e.z as f64];
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
        let mut w = [0.0f64; KEPT + 1];
        w[0] = 1.0;
        let point = |w: &[f64]| {
            let mut x = [0.0; 3];
            for (wi, vi) in w.iter().zip(v) {
                for k in 0..3 {
                    x[k] += wi * vi[k];
                }
            }
            x
        };
        let mut lower = 0.0f64;
        for _ in 0..4000 {
            let x = point(&w);
            let g = sub(x, e);
            let f = dot(g, g);
            let mut along = [0.0f64; KEPT + 1];
            for (a, &vi) in along.iter_mut().zip(v) {
                *a = dot(g, vi);
            }
            let to = (0..v.len())
                .min_by(|&a, &b| along[a].total_cmp(&along[b]))
                .unwrap();
            // The duality gap: f - f* <= 2 <g, x - v_to>.
            let gap = 2.0 * (dot(g, x) - along[to]);
            lower = lower.max(f - gap);
            let away = (0..v.len())
                .filter(|&k| w[k] > 0.0)
                .max_by(|&a, &b| along[a].total_cmp(&along[b]))
                .unwrap();
            let d = sub(v[to], v[away]);
            let dd = dot(d, d);
            if dd == 0.0 || gap <= 0.0 {
                break;
            }
            let step = ((along[away] - along[to]) / dd).clamp(0.0, w[away]);
            w[to] += step;
            w[away] -= step;
        }
        let x = point(&w);
        let g = sub(x, e);
        (lower.max(0.0).sqrt(), dot(g, g).sqrt())
    }

    /// Random hulls (flat, thin, with repeated and zero vectors among them) and points
    /// inside, near and far from them (up to a hundred times their size): every bound is at
    /// least the reference's lower bound, and within `1e-4` of the hull's size (and a
    /// millionth) of its upper one (a candidate inside a thin simplex has weights no better
    /// than the simplex's shape allows).
    #[test]
    fn the_distance_bound_covers_the_distance_and_is_tight() {
        let mut rng = TestRng::new(0xd157_a4ce_2026);
        let unit = |rng: &mut TestRng| rng.signed(1 << 20) as f32 / (1 << 20) as f32;
        let mut cases = 0;
        for case in 0..3000 {
            let n = 1 + case % KEPT;
            let scale = [1e-4, 0.03, 1.0, 250.0][case % 4];
            let mut hull = [Vec3::ZERO; KEPT];
            for h in &mut hull[..n] {
                *h = Vec3::new(unit(&mut rng), unit(&mut rng), unit(&mut rng)) * scale;
            }
            match case % 7 {
                // Flat: every vector in one plane, or along one line.
                0 => hull[..n].iter_mut().for_each(|h| h.z = 0.0),
                1 => hull[..n].iter_mut().for_each(|h| *h = Vec3::X * h.x),
                // Repeated vectors.
                2 if n > 1 => hull[1] = hull[0],
                _ => {}
            }
            let h = Hull::new(&hull[..n]);
            for k in 0..10 {
                // A point of the hull moved off it by up to its size times a factor.
                let mut w = [0.0f32; KEPT];
                for x in &mut w[..n] {
                    *x = unit(&mut rng).abs() / n as f32;
                }
                let inside = hull[..n]
                    .iter()
                    .zip(&w)
                    .fold(Vec3::ZERO, |p, (v, x)| p + *v * *x);
                let off = [0.0, 0.01, 0.3, 2.0, 100.0][k % 5] * scale;
                let e = inside + Vec3::new(unit(&mut rng), unit(&mut rng), unit(&mut rng)) * off;
                let got = distance_to_hull(e, &h, 0.0) as f64;
                let (low, high) = reference(e, &hull[..n]);
                assert!(got >= low, "case {case}: {got} < {low}");
                // (A candidate's weights are as good as its simplex is well shaped: in a thin
                // one, the point they rebuild is off the projection by more than the drift,
                // though still a point of the hull up to it.)
                let within = high * (1.0 + 1e-6) + 1e-4 * scale as f64;
                assert!(
                    got <= within,
                    "case {case}.{k}: {got} > {high} (+{})",
                    h.drift
                );
                cases += 1;
            }
        }
        assert_eq!(cases, 30_000);
    }
}

#[cfg(test)]
mod longest_tests {
    use crate::tessellator::HierarchyNode;
    use crate::test_rng::TestRng;

    /// The length bound from the quantised vectors covers every kept vector, as the bake's
    /// does, and is as tight (within a few roundings of it).
    #[test]
    fn the_quantised_length_bound_covers_the_kept_vectors() {
        let mut rng = TestRng::new(0x0b16_1e55);
        for k in 0..20_000 {
            let mut node = HierarchyNode {
                scale: [1e-7, 3.3e-4, 0.71, 12.5][k % 4] * (1.0 + rng.signed(1000) as f32 / 1e4),
                ..HierarchyNode::default()
            };
            for v in &mut node.vectors {
                *v = [0; 3].map(|_| rng.signed(127) as i8);
            }
            let quick = node.longest_quantised();
            let exact = node
                .kept()
                .iter()
                .map(|v| (v.x as f64).hypot(v.y as f64).hypot(v.z as f64))
                .fold(0.0, f64::max);
            assert!(quick as f64 >= exact, "{k}: {quick} < {exact}");
            let bake = node.longest();
            assert!(
                (quick - bake).abs() <= 8.0 * f32::EPSILON * bake,
                "{k}: {quick} {bake}"
            );
        }
    }
}
