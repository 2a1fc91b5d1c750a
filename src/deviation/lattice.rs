//! A bisection triangle's deviation vectors, on a lattice of step `1/12`.
//!
//! The derivation is the `deviation` module's with `n = 12` in place of 6: the lattice cuts
//! the triangle `T` into `n²` triangles similar to `T` at scale `1/n`; on each, the deviation
//! `e = S - L` is the linear interpolant of the three lattice vectors at its corners plus at
//! most `½ ρ(T)² / n²` (`ρ` the smallest enclosing radius in the coordinates the second
//! derivative bounds scale), so `e(x) ∈ conv{e_k} + B(R)` with `R = ½ ρ² / n² + slack`. The
//! bake computes this once per triangle, so the finer lattice costs no run time: it makes the
//! remainder a quarter of the 6-step lattice's, which is most of what a kept bound carries
//! above the true deviation.
//!
//! `L` interpolates the corners' recorded points, and the corners' own vectors are the patch's
//! points there less the recorded ones (a shared curve's point recorded from the other patch
//! may differ in its last bits): every vector is what the run time's flat triangle misses.

use glam::Vec3;

use crate::deviation::PatchBounds;
use crate::patch::BezierPatch;

/// Lattice steps per side of the bake's lattice.
pub(crate) const STEPS: usize = 12;

/// Lattice points of the bake's lattice, the corners included.
pub(crate) const POINTS: usize = (STEPS + 1) * (STEPS + 2) / 2;

/// Lattice steps per side where the run time bounds a triangle below the bake (fewer
/// evaluations, four times the remainder).
pub(crate) const RUN_TIME_STEPS: usize = 6;

/// Lattice points of the run time's lattice.
pub(crate) const RUN_TIME_POINTS: usize = (RUN_TIME_STEPS + 1) * (RUN_TIME_STEPS + 2) / 2;

/// The deviation vectors at the lattice points (`N` steps per side, `P` points) of the
/// triangle with grid corners `grid` (parameter 1 at `one`) of `patch`, against the flat
/// triangle through `points`, and the remainder `R` with its rounding slack.
pub(crate) fn deviation_vectors<const N: usize, const P: usize>(
    patch: &BezierPatch<'_>,
    grid: [[u32; 2]; 3],
    one: u32,
    points: [[f32; 3]; 3],
) -> ([Vec3; P], f32) {
    const { assert!(P == (N + 1) * (N + 2) / 2) };
    let n = N as u32;
    let scale = 1.0 / (n as f32 * one as f32);
    let mut uv = [(0.0f32, 0.0f32); P];
    let mut weights = [(0u32, 0u32, 0u32); P];
    let mut k = 0;
    for i in 0..=n {
        for j in 0..=n - i {
            let c = n - i - j;
            let g = |x: usize| (c * grid[0][x] + i * grid[1][x] + j * grid[2][x]) as f32 * scale;
            uv[k] = (g(0), g(1));
            weights[k] = (c, i, j);
            k += 1;
        }
    }
    let mut samples = [Vec3::ZERO; P];
    patch.positions_direct_into(&uv, &mut samples);
    let [q0, q1, q2] = points.map(Vec3::from_array);
    let mut out = [Vec3::ZERO; P];
    for ((o, s), (c, i, j)) in out.iter_mut().zip(samples).zip(weights) {
        let linear = (q0 * c as f32 + q1 * i as f32 + q2 * j as f32) * (1.0 / n as f32);
        *o = s - linear;
    }
    let corners = [uv[0], uv[P - 1], uv[N]];
    let local = PatchBounds::around(patch, corners);
    let remainder = local.curvature_term(corners) * (1.0 / (n * n) as f32) + local.slack;
    (out, remainder)
}

/// The vectors of the lattice of step `2 / STEPS` among `vectors` (even indices), the
/// candidates a bake keeps a few of.
pub(crate) fn coarse(vectors: &[Vec3; POINTS]) -> [Vec3; (STEPS / 2 + 1) * (STEPS / 2 + 2) / 2] {
    let mut out = [Vec3::ZERO; (STEPS / 2 + 1) * (STEPS / 2 + 2) / 2];
    let (mut k, mut o) = (0, 0);
    for i in 0..=STEPS {
        for j in 0..=STEPS - i {
            if i % 2 == 0 && j % 2 == 0 {
                out[o] = vectors[k];
                o += 1;
            }
            k += 1;
        }
    }
    out
}
