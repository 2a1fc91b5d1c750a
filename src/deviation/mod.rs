//! Computed upper bounds on how far a patch strays from a flat triangle, in model units and
//! on screen.
//!
//! The deviation of a domain triangle `T` (corners `p0, p1, p2` in the unit square) is
//! `sup |S(x) - L(x)|` over `x` in `T`, where `L` is the linear interpolant of the surface
//! points `S(p0), S(p1), S(p2)` at the same barycentric coordinates. Everything that decides
//! how finely to tessellate, in the bake and at run time, uses the bound of this module, so a
//! recorded value is never an estimate.
//!
//! # The bound
//!
//! **Sampled part.** Let `x_k` be the points of the barycentric lattice of step `1/n` on `T`
//! (`(n + 1)(n + 2) / 2` points, the corners included), and `e_k = S(x_k) - L(x_k)`. The
//! lattice cuts `T` into `n²` triangles `T_s` similar to `T` at scale `1/n` (and their point
//! reflections). On one of them, `L_s` interpolates `S` at its corners, and `L_s - L` is
//! linear, so it is the linear interpolant of the `e_k` at those corners. For `x` in `T_s`:
//!
//! `S(x) - L(x) = (S(x) - L_s(x)) + (L_s(x) - L(x))`, with `|S(x) - L_s(x)| <= R_s` and
//! `L_s(x) - L(x)` in the convex hull of the `e_k`.
//!
//! So the deviation lies in `conv{e_k} + B(R)`, and `|S(x) - L(x)| <= max_k |e_k| + R`.
//!
//! **Remainder.** `R_s` bounds linear interpolation on `T_s`. With the second-derivative
//! bounds `a >= |S_uu|`, `b >= |S_uv|`, `c >= |S_vv|` over a region holding `T`
//! ([`PatchBounds`]), for any direction `h`, `|D²S[h, h]| <= a h_u² + 2 b |h_u h_v| + c h_v²
//! <= α h_u² + β h_v²` with `α = a + b t`, `β = c + b / t` for any `t > 0`
//! (`2|h_u h_v| <= t h_u² + h_v² / t`). Taylor's theorem with integral remainder at `x`,
//! `S(p_i) = S(x) + DS(x)(p_i - x) + r_i` with `|r_i| <= ½ (α d_u² + β d_v²)`, `d = p_i - x`,
//! and `Σ λ_i (p_i - x) = 0` give `|S(x) - L(x)| <= ½ Σ λ_i (α d_iu² + β d_iv²)`. In the
//! coordinates `(√α u, √β v)` that sum is `Σ λ_i |p_i - x|²`, at most `ρ²`, the squared
//! radius of the triangle's smallest enclosing circle there (for `x = Σ λ_i p_i`,
//! `Σ λ_i |p_i - x|² = r² - |x - o|²` for the centre `o` and radius `r` of any circle through
//! the corners; take the smallest enclosing circle, or the circumcircle for an acute
//! triangle). So `R = ½ ρ(T)² / n²` ([`PatchBounds::curvature_term`]). The smallest of a few
//! choices of `t` is taken.
//!
//! The bake takes `n = 12` and keeps a few of the vectors (`lattice` and `kept` in the run
//! time); a triangle below the bake is bounded at run time with `n = 6`.
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
//! On screen, the vectors are projected one by one at the view rays of the flat triangle
//! (`screen`, which derives it).
//!
//! `host-tests/tests/bisection.rs` checks every frame's triangles against dense `f64`
//! sampling, on screen and in model units, and `host-tests/tests/screen_bound.rs` the bound on
//! screen against its own `f64` derivation.

use crate::math::max;

pub(crate) mod certificate;
pub(crate) mod kept;
pub(crate) mod lattice;
mod patch_bounds;
mod screen;
pub(crate) mod vectors;

pub use patch_bounds::PatchBounds;
pub(crate) use screen::{bound_on_screen, isotropic_bound_on_screen, view_extent, SCREEN_SLACK};

/// Unit roundoff of `f32`.
pub(crate) const EPS: f32 = f32::EPSILON * 0.5;

/// Relative enlargement of the computed remainder, for its own rounding.
pub(crate) const REMAINDER_SLACK: f32 = 1.0 + 1.0 / 1024.0;

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
