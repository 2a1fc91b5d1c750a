//! Computed upper bounds on how far a patch strays from a flat triangle or a chord.
//!
//! The deviation of a domain triangle `T` (corners `p0, p1, p2` in the unit square) is
//! `sup |S(x) - L(x)|` over `x` in `T`, where `L` is the linear interpolant of the surface
//! points `S(p0), S(p1), S(p2)` at the same barycentric coordinates. Everything that decides
//! how finely to tessellate, in the bake and at run time, uses the bound of this module, so a
//! recorded or cached value is never an estimate.
//!
//! # The bound
//!
//! **Sampled part.** Let `x_k` be the points of the barycentric lattice of step `1/6` on `T`
//! (28 points, the corners included), and `e_k = S(x_k) - L(x_k)`. The lattice cuts `T` into
//! 36 triangles `T_s` similar to `T` at scale `1/6` (and their point reflections). On one of
//! them, `L_s` interpolates `S` at its corners, and `L_s - L` is linear, so it is the linear
//! interpolant of the `e_k` at those corners. For `x` in `T_s`:
//!
//! `|S(x) - L(x)| <= |S(x) - L_s(x)| + |L_s(x) - L(x)| <= R_s + max_k |e_k|`.
//!
//! **Remainder.** `R_s` bounds linear interpolation on `T_s`. With the second-derivative
//! bounds `a >= |S_uu|`, `b >= |S_uv|`, `c >= |S_vv|` over the patch ([`PatchBounds`]), for any
//! direction `h`, `|D²S[h, h]| <= a h_u² + 2 b |h_u h_v| + c h_v² <= α h_u² + β h_v²` with
//! `α = a + b t`, `β = c + b / t` for any `t > 0` (`2|h_u h_v| <= t h_u² + h_v² / t`). Taylor's
//! theorem with integral remainder at `x`, `S(p_i) = S(x) + DS(x)(p_i - x) + r_i` with
//! `|r_i| <= ½ (α d_u² + β d_v²)`, `d = p_i - x`, and `Σ λ_i (p_i - x) = 0` give
//! `|S(x) - L(x)| <= ½ Σ λ_i (α d_iu² + β d_iv²)`. In the coordinates `(√α u, √β v)` that sum
//! is `Σ λ_i |p_i - x|²`, at most `ρ²`, the squared radius of the triangle's smallest
//! enclosing circle there (for `x = Σ λ_i p_i`, `Σ λ_i |p_i - x|² = r² - |x - o|²` for the
//! centre `o` and radius `r` of any circle through the corners; take the smallest enclosing
//! circle, or the circumcircle for an acute triangle). So `R_s = ½ ρ(T)² / 36`. The smallest
//! of a few choices of `t` is taken.
//!
//! The same argument with the lattice of step `1/3` (its 10 points are among the 28) gives
//! `max |e_k| + ½ ρ(T)² / 9`, and any second-derivative bounds over a region containing `T`
//! (the whole patch's) may stand in for the triangle's own: the run time tries these cheaper
//! forms first and keeps one where it already settles the triangle (see
//! `tessellator::refine`).
//!
//! **Refinement.** The same 28 samples bound the pieces of `T` cut uniformly by 2, 3 and 6:
//! a piece's own interpolant is sampled on the sub-lattice it contains, with the same
//! remainder `R_s`. Past 6, or for a piece of another shape, the remainder alone on the piece,
//! `½ ρ(piece)²`, is the bound (see [`PatchBounds::curvature_term`]).
//!
//! **Chords.** A boundary curve segment is bounded the same way in one dimension: six
//! samples, and `⅛ M (h/6)²` for linear interpolation over a sixth of its length `h`, with
//! `M = a` along `u` and `c` along `v`.
//!
//! **Second derivatives of a rational patch.** With `A = w (S - o)` (the homogeneous patch
//! after moving the origin to the net's centre `o`), `A_u = w_u (S - o) + w S_u` and so on,
//! so `|S_u| <= (|A_u| + |w_u| r) / w_min` and
//! `|S_uu| <= (|A_uu| + 2 |w_u| |S_u| + |w_uu| r) / w_min` (likewise `S_uv`, `S_vv`), where
//! `r` is the net's radius about `o`, `w_min` its smallest weight (`w` is a convex
//! combination of the weights), and each `|A_..|`, `|w_..|` is the largest control point of
//! the derivative's Bezier net (the convex hull property). A polynomial patch has `w = 1`:
//! the bounds are its second-difference nets' largest points.
//!
//! **Rounding.** Samples are computed in `f32`. [`PatchBounds::slack`] covers the error of a
//! computed `|e_k|`: each position is off by at most `γ M / w_min` per coordinate (de
//! Casteljau's algorithm is a chain of convex combinations; `γ = n ε / (1 - n ε)`,
//! `n = 3 (p + q) + 8` operations, `M` the largest `|w P| + |P| w`), the interpolant and the
//! lattice parameters by a few `ε` of the net's size. The remainder is computed in `f32` and
//! enlarged by `2^-10` (its inputs are exact grid coordinates; its roundings are relative and
//! few).
//!
//! `host-tests/tests/deviation.rs` checks the bound against dense `f64` sampling on every
//! triangle of every model's bake and reports how tight it is.

use crate::domain::GridPoint;
use crate::math::{length, max, sqrt};
use crate::patch::{BezierPatch, Side};
use crate::view::Camera;

mod patch_bounds;
mod screen;

pub use patch_bounds::PatchBounds;
pub(crate) use patch_bounds::PreparedBounds;
pub(crate) use screen::{bound_on_screen, isotropic_bound_on_screen, view_extent};

/// Lattice steps per side of a bounded triangle or chord.
pub const LATTICE: u32 = 6;

/// Refinement factors whose pieces the lattice samples bound (the divisors of [`LATTICE`]).
pub const SAMPLED_FACTORS: [u8; 4] = [1, 2, 3, 6];

/// Unit roundoff of `f32`.
pub(crate) const EPS: f32 = f32::EPSILON * 0.5;

/// Relative enlargement of the computed remainder, for its own rounding.
pub(crate) const REMAINDER_SLACK: f32 = 1.0 + 1.0 / 1024.0;

/// The bound of one domain triangle, for the triangle itself and its uniform refinements.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct TriangleBound {
    /// Bounds of the deviation of every piece of the triangle cut uniformly by the factors of
    /// [`SAMPLED_FACTORS`] (1: the triangle itself).
    pub refined: [f32; 4],
    /// `½ ρ²` of the triangle itself (see [`PatchBounds::curvature_term`]): the bound of a
    /// uniform refinement by `n` is at most `curvature / n² + slack`.
    pub curvature: f32,
    /// The rounding slack of one sampled deviation (part of every bound above).
    pub slack: f32,
    /// Where the sampled deviation of the whole triangle is largest.
    pub at: GridPoint,
    /// The surface points at the triangle's corners: the surface piece lies within
    /// [`bound`](Self::bound) of their flat triangle.
    pub points: [[f32; 3]; 3],
}

impl TriangleBound {
    /// The bound of the triangle itself.
    pub fn bound(&self) -> f32 {
        self.refined[0]
    }
}

/// The bound of one chord of a boundary curve.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ChordBound {
    /// Upper bound of the distance between the curve and the chord over the segment.
    pub bound: f32,
    /// Curve parameter (unit) of the largest sampled deviation.
    pub at: f32,
}

/// The bound of the domain triangle `corners` of `patch`, and of its uniform refinements by 2,
/// 3 and 6 (see the module docs).
pub fn triangle_bound(patch: &BezierPatch<'_>, corners: [GridPoint; 3]) -> TriangleBound {
    let mut lattice = Lattice::coarse(patch, corners);
    lattice.complete(patch);
    lattice.pieces();
    let uv = corners.map(GridPoint::to_unit);
    let local = PatchBounds::around(patch, uv);
    lattice.bound(local.curvature_term(uv), local.slack, true)
}

/// The bound, in pixels, of the deviation on `camera`'s screen of the domain triangle
/// `corners` of `patch`: its lattice's deviation vectors projected one by one at the view rays
/// of the part of the triangle that can show, with the remainder of [`triangle_bound`] (see
/// the derivation in `deviation/screen.rs`). At most [`triangle_bound`]'s bound times the
/// projection's largest scale over the triangle, and far below it where the deviation runs
/// along the line of sight.
pub fn triangle_screen_bound(
    patch: &BezierPatch<'_>,
    corners: [GridPoint; 3],
    camera: &Camera,
) -> f32 {
    let mut lattice = Lattice::coarse(patch, corners);
    lattice.complete(patch);
    let uv = corners.map(GridPoint::to_unit);
    let local = PatchBounds::around(patch, uv);
    lattice.screen_bound(camera, local.curvature_term(uv), local.slack)
}

/// The surface on a triangle's lattice: its samples, and the largest sampled deviations of
/// the triangle and of its uniform pieces, before any remainder.
pub(crate) struct Lattice {
    /// Samples, indexed by (i, j): weight i on corner 1, j on corner 2 (in sixths).
    s: [[Sample; LATTICE as usize + 1]; LATTICE as usize + 1],
    /// Largest sampled deviation of the pieces of [`SAMPLED_FACTORS`] (the last unused).
    worst: [f32; 4],
    /// Lattice point of the triangle's own largest sampled deviation.
    at: (usize, usize),
    /// The triangle's corners.
    corners: [GridPoint; 3],
    /// Whether every point is sampled (not only the coarse ones).
    complete: bool,
}

/// A lattice sample: a [`glam::Vec3A`] where it has SIMD lanes (each lane's arithmetic is
/// [`glam::Vec3`]'s, and its `dot` adds `x² + y²` then `z²` as `Vec3`'s does: the same bits), three
/// scalars elsewhere (12 bytes, not 16, on the stack of a microcontroller).
#[cfg(any(
    target_feature = "sse2",
    target_feature = "simd128",
    all(target_arch = "aarch64", target_feature = "neon")
))]
type Sample = glam::Vec3A;
#[cfg(not(any(
    target_feature = "sse2",
    target_feature = "simd128",
    all(target_arch = "aarch64", target_feature = "neon")
)))]
type Sample = glam::Vec3;

/// The surface at the corners of `corners`, computed as every bound computes them.
pub(crate) fn corner_points(patch: &BezierPatch<'_>, corners: [GridPoint; 3]) -> [[f32; 3]; 3] {
    let n = LATTICE as usize;
    let uv = [(0, 0), (n, 0), (0, n)].map(|(i, j)| lattice_point(corners, i, j));
    patch.positions_direct(uv).map(|p| p.to_array())
}

/// The lattice points with even indices besides the corners (the lattice of step 1/3).
const COARSE: [(usize, usize); 7] = [(0, 2), (0, 4), (2, 0), (2, 2), (2, 4), (4, 0), (4, 2)];

/// The lattice points with an odd index (the rest of the lattice of step 1/6).
const FINE: [(usize, usize); 18] = [
    (0, 1),
    (0, 3),
    (0, 5),
    (1, 0),
    (1, 1),
    (1, 2),
    (1, 3),
    (1, 4),
    (1, 5),
    (2, 1),
    (2, 3),
    (3, 0),
    (3, 1),
    (3, 2),
    (3, 3),
    (4, 1),
    (5, 0),
    (5, 1),
];

/// A point of a piece of a triangle cut uniformly, where [`Lattice::pieces`] samples the
/// piece's deviation: a lattice point (not a corner of the piece), the piece's corners as
/// lattice points, and its weights on them in steps of the piece's own lattice.
#[derive(Clone, Copy)]
struct PiecePoint {
    at: (u8, u8),
    corners: [(u8, u8); 3],
    weights: [u8; 3],
}

/// The points of [`Lattice::pieces`] for the cut by `factor` (a divisor of [`LATTICE`]): per
/// piece, upright `(a, b)` then inverted, the points of its own lattice besides its corners.
/// `K` must be their number (a wrong one does not compile).
const fn piece_points<const K: usize>(factor: usize) -> [PiecePoint; K] {
    let m = LATTICE as usize / factor;
    let mut out = [PiecePoint {
        at: (0, 0),
        corners: [(0, 0); 3],
        weights: [0; 3],
    }; K];
    let mut k = 0;
    let mut pb = 0;
    while pb < factor {
        let mut pa = 0;
        while pa < factor - pb {
            let mut inverted = 0;
            while inverted < 2 {
                if inverted == 0 || pa + pb + 2 <= factor {
                    let c = if inverted == 1 {
                        [(pa + 1, pb), (pa + 1, pb + 1), (pa, pb + 1)]
                    } else {
                        [(pa, pb), (pa + 1, pb), (pa, pb + 1)]
                    };
                    let mut x = 0;
                    while x <= m {
                        let mut y = 0;
                        while y <= m - x {
                            let z = m - x - y;
                            if x != m && y != m && z != m {
                                let gi = c[0].0 * z + c[1].0 * x + c[2].0 * y;
                                let gj = c[0].1 * z + c[1].1 * x + c[2].1 * y;
                                out[k] = PiecePoint {
                                    at: (gi as u8, gj as u8),
                                    corners: [
                                        ((c[0].0 * m) as u8, (c[0].1 * m) as u8),
                                        ((c[1].0 * m) as u8, (c[1].1 * m) as u8),
                                        ((c[2].0 * m) as u8, (c[2].1 * m) as u8),
                                    ],
                                    weights: [z as u8, x as u8, y as u8],
                                };
                                k += 1;
                            }
                            y += 1;
                        }
                        x += 1;
                    }
                }
                inverted += 1;
            }
            pa += 1;
        }
        pb += 1;
    }
    assert!(k == K, "K is the number of points");
    out
}

/// [`piece_points`] of the cut by 2: 4 pieces of 7 points.
const PIECES_BY_2: [PiecePoint; 28] = piece_points(2);

/// [`piece_points`] of the cut by 3: 9 pieces of 3 points.
const PIECES_BY_3: [PiecePoint; 27] = piece_points(3);

/// Unit parameters of lattice point (i, j) of `corners`.
fn lattice_point(corners: [GridPoint; 3], i: usize, j: usize) -> (f32, f32) {
    let n = LATTICE as usize;
    let scale = 1.0 / (LATTICE as f32 * GridPoint::MAX as f32);
    let k = n - i - j;
    let g = |f: fn(GridPoint) -> u16| {
        (k as u32 * f(corners[0]) as u32
            + i as u32 * f(corners[1]) as u32
            + j as u32 * f(corners[2]) as u32) as f32
            * scale
    };
    (g(|p| p.u), g(|p| p.v))
}

impl Lattice {
    /// The points with even indices only (the lattice of step 1/3).
    pub(crate) fn coarse(patch: &BezierPatch<'_>, corners: [GridPoint; 3]) -> Lattice {
        Self::coarse_with(patch, corners, corner_points(patch, corners))
    }

    /// [`coarse`](Self::coarse) with the corners' surface points already at hand (as
    /// [`corner_points`] computes them).
    pub(crate) fn coarse_with(
        patch: &BezierPatch<'_>,
        corners: [GridPoint; 3],
        points: [[f32; 3]; 3],
    ) -> Lattice {
        let mut lattice = Lattice::UNSAMPLED;
        lattice.sample_coarse(patch, corners, points);
        lattice
    }

    /// A lattice with no samples, to [sample](Self::sample_coarse) in place (one lattice on
    /// the stack where a caller may need it several ways). All zeros, so that it is cleared
    /// in place rather than copied from flash.
    pub(crate) const UNSAMPLED: Lattice = Lattice {
        s: [[Sample::ZERO; LATTICE as usize + 1]; LATTICE as usize + 1],
        worst: [0.0; 4],
        at: (0, 0),
        corners: [GridPoint { u: 0, v: 0 }; 3],
        complete: false,
    };

    /// Makes this the [`coarse_with`](Self::coarse_with) lattice of `corners`, in place.
    pub(crate) fn sample_coarse(
        &mut self,
        patch: &BezierPatch<'_>,
        corners: [GridPoint; 3],
        points: [[f32; 3]; 3],
    ) {
        let n = LATTICE as usize;
        let s = &mut self.s;
        s[0][0] = Sample::from_array(points[0]);
        s[n][0] = Sample::from_array(points[1]);
        s[0][n] = Sample::from_array(points[2]);
        let sampled = patch.positions_direct(COARSE.map(|(i, j)| lattice_point(corners, i, j)));
        for ((i, j), point) in COARSE.into_iter().zip(sampled) {
            s[i][j] = Sample::from_array(point.to_array());
        }
        self.worst = [0.0; 4];
        self.at = (1, 1);
        self.corners = corners;
        self.complete = false;
    }

    /// Forgets which triangle the samples are of (where the next triangle may be of another
    /// patch): the next [`sample_coarse_once`](Self::sample_coarse_once) samples.
    pub(crate) fn forget(&mut self) {
        self.corners = Self::UNSAMPLED.corners;
    }

    /// [`sample_coarse`](Self::sample_coarse), unless this lattice holds the samples of
    /// `corners` already. (A triangle's corners are distinct, so
    /// [`UNSAMPLED`](Self::UNSAMPLED), whose corners are equal, holds none.)
    pub(crate) fn sample_coarse_once(
        &mut self,
        patch: &BezierPatch<'_>,
        corners: [GridPoint; 3],
        points: [[f32; 3]; 3],
    ) {
        if self.corners != corners {
            self.sample_coarse(patch, corners, points);
        }
    }

    /// The bound from the coarse points: the largest deviation at them and `½ ρ² / 9`, with
    /// the curvature term `curvature` and rounding slack `slack` of bounds over a region
    /// containing the triangle.
    pub(crate) fn coarse_bound(&self, curvature: f32, slack: f32) -> TriangleBound {
        let n = LATTICE as usize;
        let s = &self.s;
        let (q0, q1, q2) = (s[0][0], s[n][0], s[0][n]);
        let (mut worst, mut at) = (0.0f32, (2, 2));
        for i in (0..=n).step_by(2) {
            for j in (0..=n - i).step_by(2) {
                let e = self.deviation(i, j);
                let d = e.dot(e);
                if d > worst {
                    (worst, at) = (d, (i, j));
                }
            }
        }
        let remainder = curvature * (1.0 / 9.0) + slack;
        let (bu, bv) = lattice_point(self.corners, at.0, at.1);
        TriangleBound {
            refined: [
                sqrt(worst) + remainder,
                f32::INFINITY,
                f32::INFINITY,
                f32::INFINITY,
            ],
            curvature,
            slack,
            at: GridPoint::from_unit(bu, bv),
            points: [q0, q1, q2].map(|p| p.to_array()),
        }
    }

    /// Every point, and the largest deviation of the triangle itself (once; later calls do
    /// nothing).
    pub(crate) fn complete(&mut self, patch: &BezierPatch<'_>) {
        if self.complete {
            return;
        }
        self.complete = true;
        let n = LATTICE as usize;
        let corners = self.corners;
        let sampled = patch.positions_direct(FINE.map(|(i, j)| lattice_point(corners, i, j)));
        for ((i, j), point) in FINE.into_iter().zip(sampled) {
            self.s[i][j] = Sample::from_array(point.to_array());
        }
        // The first point of the largest deviation `length` gives (as rounded): a root is
        // taken only for a squared length above the best one's (the root is monotone, so no
        // other can be larger).
        let mut best = (-1.0f32, (1usize, 1usize));
        let mut best_squared = -1.0f32;
        for i in 0..=n {
            for j in 0..=n - i {
                if i == n || j == n || i + j == 0 {
                    continue;
                }
                let e = self.deviation(i, j);
                let squared = e.dot(e);
                if squared > best_squared {
                    let d = sqrt(squared);
                    if d > best.0 {
                        best = (d, (i, j));
                        best_squared = squared;
                    }
                }
            }
        }
        self.worst[0] = max(best.0, 0.0);
        self.at = best.1;
    }

    /// `e_k` at lattice point `(i, j)`: its sample less the corners' interpolant there.
    #[inline(always)]
    fn deviation(&self, i: usize, j: usize) -> Sample {
        let n = LATTICE as usize;
        let s = &self.s;
        let (q0, q1, q2) = (s[0][0], s[n][0], s[0][n]);
        let linear = (q0 * (n - i - j) as f32 + q1 * i as f32 + q2 * j as f32) * (1.0 / n as f32);
        s[i][j] - linear
    }

    /// The largest deviations of the pieces of a uniform refinement by 2 and 3, each against
    /// its own interpolant (at the points of [`PIECES_BY_2`] and [`PIECES_BY_3`]).
    pub(crate) fn pieces(&mut self) {
        let s = &self.s;
        let at = |(i, j): (u8, u8)| s[i as usize][j as usize];
        for (f, table) in [(1, &PIECES_BY_2[..]), (2, &PIECES_BY_3[..])] {
            // Lattice steps per piece side.
            let m = LATTICE as usize / SAMPLED_FACTORS[f] as usize;
            let inv = 1.0 / m as f32;
            let mut w = 0.0f32;
            for point in table {
                let [z, x, y] = point.weights.map(f32::from);
                let [q0, q1, q2] = point.corners.map(at);
                let linear = (q0 * z + q1 * x + q2 * y) * inv;
                let e = at(point.at) - linear;
                // Squared, one root at the end (the same value).
                w = max(w, e.dot(e));
            }
            self.worst[f] = sqrt(w);
        }
    }

    /// The largest sampled deviation of a piece of the triangle whose corners are lattice
    /// points at halves of its sides, `h[k] = (i, j)` in halves (weight `i / 2` on corner 1,
    /// `j / 2` on corner 2), against the piece's own interpolant, at the 7 points of the
    /// piece's lattice of step 1/3 besides its corners: those are points of this lattice (a
    /// third of a half is a sixth), so no surface point is computed. Needs
    /// [`complete`](Self::complete).
    pub(crate) fn half_piece_worst(&self, h: [(usize, usize); 3]) -> f32 {
        let s = &self.s;
        let q = h.map(|(i, j)| s[3 * i][3 * j]);
        let mut w = 0.0f32;
        for (x, y) in [(1, 0), (2, 0), (0, 1), (0, 2), (1, 1), (2, 1), (1, 2)] {
            let z = 3 - x - y;
            // Weights z, x, y thirds on the piece's corners: in sixths of the triangle's.
            let gi = h[0].0 * z + h[1].0 * x + h[2].0 * y;
            let gj = h[0].1 * z + h[1].1 * x + h[2].1 * y;
            let linear = (q[0] * z as f32 + q[1] * x as f32 + q[2] * y as f32) * (1.0 / 3.0);
            let e = s[gi][gj] - linear;
            w = max(w, e.dot(e));
        }
        sqrt(w)
    }

    /// The bounds, with the remainder from the curvature term `curvature` and rounding slack
    /// `slack` of bounds over a region containing the triangle.
    /// Without `with_pieces` (no [`pieces`](Self::pieces) taken), only the triangle's own
    /// bound is sampled; its pieces are left to the curvature term.
    pub(crate) fn bound(&self, curvature: f32, slack: f32, with_pieces: bool) -> TriangleBound {
        let n = LATTICE as usize;
        let remainder = curvature * (1.0 / (n * n) as f32) + slack;
        let mut refined = [remainder; 4];
        for (r, w) in refined.iter_mut().zip(self.worst).take(3) {
            *r = w + remainder;
        }
        if !with_pieces {
            refined[1..].fill(f32::INFINITY);
        }
        let (bu, bv) = lattice_point(self.corners, self.at.0, self.at.1);
        TriangleBound {
            refined,
            curvature,
            slack,
            at: GridPoint::from_unit(bu, bv),
            points: [self.s[0][0], self.s[n][0], self.s[0][n]].map(|p| p.to_array()),
        }
    }
}

/// The bound of the chord of edge `side` of `patch` between unit parameters `t0 < t1`.
pub fn chord_bound(patch: &BezierPatch<'_>, side: Side, t0: f32, t1: f32) -> ChordBound {
    let point = |t: f32| match side {
        Side::V0 => patch.position_direct(t, 0.0),
        Side::U1 => patch.position_direct(1.0, t),
        Side::V1 => patch.position_direct(t, 1.0),
        Side::U0 => patch.position_direct(0.0, t),
    };
    let n = LATTICE as usize;
    let (a, b) = (point(t0), point(t1));
    let h = t1 - t0;
    let mut best = (0.0f32, 0.5 * (t0 + t1));
    for k in 1..n {
        let f = k as f32 / n as f32;
        let t = t0 + h * f;
        let d = length(point(t) - (a + (b - a) * f));
        if d > best.0 {
            best = (d, t);
        }
    }
    let local = {
        let area = match side {
            Side::V0 => [t0, t1, 0.0, 0.0],
            Side::U1 => [1.0, 1.0, t0, t1],
            Side::V1 => [t0, t1, 1.0, 1.0],
            Side::U0 => [0.0, 0.0, t0, t1],
        };
        PatchBounds::over(patch, area)
    };
    let m = match side {
        Side::V0 | Side::V1 => local.second[0],
        Side::U0 | Side::U1 => local.second[2],
    };
    let step = h / n as f32;
    let remainder = 0.125 * m * step * step * REMAINDER_SLACK;
    ChordBound {
        bound: best.0 + remainder + local.slack,
        at: best.1,
    }
}

/// Squared radius of the smallest circle around the triangle `uv` in the coordinates
/// `(√alpha u, √beta v)`, rounded up, with `sqrt(alpha beta)` from `root` (called only for
/// an acute triangle).
#[inline]
pub(crate) fn enclosing_radius_sq(
    uv: [(f32, f32); 3],
    alpha: f32,
    beta: f32,
    root: impl FnOnce() -> f32,
) -> f32 {
    let d = |i: usize, j: usize| {
        let (du, dv) = (uv[j].0 - uv[i].0, uv[j].1 - uv[i].1);
        (du, dv, alpha * du * du + beta * dv * dv)
    };
    let (e01, e12, e20) = (d(0, 1), d(1, 2), d(2, 0));
    let (x, y, z) = (e01.2, e12.2, e20.2);
    let longest = max(max(x, y), z);
    if longest + longest >= x + y + z {
        // Right or obtuse: the longest side is a diameter.
        return longest * 0.25;
    }
    // Acute: the circumcircle, R² = x y z / (4 cross²) with the scaled cross product, which
    // lies between longest/4 and longest/3 (the largest angle is 60 to 90 degrees).
    let cross = (e01.0 * (-e20.1) - e01.1 * (-e20.0)) * root();
    let r2 = x * y * z / (4.0 * cross * cross);
    if r2.is_finite() {
        r2.clamp(longest * 0.25, longest * (1.0 / 3.0))
    } else {
        longest * (1.0 / 3.0)
    }
}
