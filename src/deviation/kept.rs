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
//! at least its distance to `H`. Frank-Wolfe steps from the nearest kept vector find a good
//! point; each step is a convex combination of the last point and a vertex of `H`, computed
//! in `f32`, so the point is within `3 ε` of `H` per step times the vertices' largest length
//! (the three roundings of `x + γ (s - x)`), which is added.
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

/// Frank-Wolfe steps per distance: while choosing the vectors to keep, and for the widening.
const CHOOSING_STEPS: usize = 16;
const FIRST_STEPS: usize = 4;
const STEPS: usize = 64;

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

/// An upper bound of the distance from `e` to `conv{0, hull}`: the distance to a point of
/// it that `steps` pairwise Frank-Wolfe steps reach from the nearest vertex (each moves
/// weight from the vertex farthest along the gradient to the one farthest against it, which
/// converges on a polytope where plain steps crawl). Stops early once the bound is at most
/// `enough`.
fn distance_to_hull(e: Vec3, hull: &[Vec3], steps: usize, enough: f32) -> f32 {
    let mut vertices = [Vec3::ZERO; KEPT + 1];
    let n = hull.len().min(KEPT) + 1;
    vertices[1..n].copy_from_slice(&hull[..n - 1]);
    let vertices = &vertices[..n];
    let mut weights = [0.0f32; KEPT + 1];
    let (mut near, mut best) = (0, f32::INFINITY);
    let mut big = 0.0f32;
    for (k, &v) in vertices.iter().enumerate() {
        let d = length(e - v);
        if d < best {
            (near, best) = (k, d);
        }
        big = max(big, length(v));
    }
    weights[near] = 1.0;
    let mut x = vertices[near];
    let drift = (n as f32 + 4.0) * EPS * big;
    for _ in 0..steps {
        let g = x - e;
        if (length(g) + 2.0 * drift) * (1.0 + 4.0 * EPS) <= enough {
            break;
        }
        let (mut to, mut away) = (0, None::<usize>);
        let (mut low, mut high) = (f32::INFINITY, f32::NEG_INFINITY);
        for (k, &v) in vertices.iter().enumerate() {
            let d = g.dot(v);
            if d < low {
                (low, to) = (d, k);
            }
            if weights[k] > 0.0 && d > high {
                (high, away) = (d, Some(k));
            }
        }
        let Some(away) = away else { break };
        let d = vertices[to] - vertices[away];
        let (dd, gain) = (d.dot(d), high - low);
        if to == away || dd <= 0.0 || gain <= 0.0 {
            break;
        }
        let step = (gain / dd).clamp(0.0, weights[away]);
        weights[to] += step;
        weights[away] = max(weights[away] - step, 0.0);
        x += d * step;
    }
    // The point of the weights, normalised: a point of the hull up to the roundings of its
    // sum (at most `n + 2` of `ε` times the longest vertex).
    let total: f32 = weights[..n].iter().sum();
    let mut point = Vec3::ZERO;
    for (w, v) in weights.iter().zip(vertices) {
        point += *v * (*w / total);
    }
    (length(e - point) + drift) * (1.0 + 4.0 * EPS)
}

/// Lazy search for the vector farthest from a hull that only grows (or, between searches,
/// moves by a known amount): each vector keeps an upper bound of its distance, and of the
/// vectors whose bound is largest only the first is measured against the current hull, until
/// the largest bound is a measured one.
struct Farthest {
    /// Upper bound of each vector's distance to the hull.
    bound: [f32; MAX_VECTORS],
    /// Whether the bound was measured against the current hull.
    measured: [bool; MAX_VECTORS],
}

impl Farthest {
    /// The vector farthest from `conv{0, hull}` as `steps` steps measure it, and that bound,
    /// or `None` when every bound is 0.
    fn next(&mut self, vectors: &[Vec3], hull: &[Vec3], steps: usize) -> Option<(usize, f32)> {
        let bounds = &mut self.bound[..vectors.len()];
        let mut best = (0.0f32, None);
        for (k, &b) in bounds.iter().enumerate() {
            if self.measured[k] && b > best.0 {
                best = (b, Some(k));
            }
        }
        loop {
            // The unmeasured vector with the largest bound above the best measured one.
            let mut top = (best.0, None);
            for (k, &b) in bounds.iter().enumerate() {
                if !self.measured[k] && b > top.0 {
                    top = (b, Some(k));
                }
            }
            let Some(k) = top.1 else {
                return best.1.map(|k| (k, best.0));
            };
            // Measured only as far as it matters: a bound at most the best one's is enough.
            let d = distance_to_hull(vectors[k], hull, steps, best.0);
            bounds[k] = bounds[k].min(d);
            self.measured[k] = true;
            if bounds[k] > best.0 {
                best = (bounds[k], Some(k));
            }
        }
    }

    /// The hull changed: no bound is a measured one any more.
    fn forget(&mut self) {
        self.measured = [false; MAX_VECTORS];
    }
}

/// Most vectors [`keep`] looks at.
const MAX_VECTORS: usize = 192;

/// Keeps at most [`KEPT`] of `candidates` in place of `vectors` (at most 192 of each are
/// looked at: two lattices of the bake; see the module docs): the candidates are chosen from, the widening covers
/// every one of `vectors`. All must be finite. The scale is `round_scale` of the smallest
/// that fits (at least that: a coarser one only widens the remainder; one that is not gives no
/// vectors).
pub(crate) fn keep(
    vectors: &[Vec3],
    candidates: &[Vec3],
    round_scale: impl Fn(f32) -> f32,
) -> Kept {
    let vectors = &vectors[..vectors.len().min(MAX_VECTORS)];
    let candidates = &candidates[..candidates.len().min(MAX_VECTORS)];
    let mut far = Farthest {
        bound: [0.0; MAX_VECTORS],
        measured: [false; MAX_VECTORS],
    };
    for (b, e) in far.bound.iter_mut().zip(candidates) {
        *b = length(*e);
    }
    let mut chosen = [Vec3::ZERO; KEPT];
    let mut n = 0;
    while n < KEPT {
        match far.next(candidates, &chosen[..n], CHOOSING_STEPS) {
            Some((k, _)) => {
                chosen[n] = candidates[k];
                far.bound[k] = 0.0;
                n += 1;
                far.forget();
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
    // A first bound of every vector's distance (a few steps), then the largest ones
    // measured closely.
    for (b, e) in far.bound.iter_mut().zip(vectors) {
        *b = distance_to_hull(*e, &hull[..n], FIRST_STEPS, 0.0);
    }
    far.forget();
    let widening = far.next(vectors, &hull[..n], STEPS).map_or(0.0, |(_, d)| d);
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
