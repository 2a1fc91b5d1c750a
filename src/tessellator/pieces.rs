//! Bounds of the pieces of a cut triangle, each a bound on its own: of the n x n pieces of a
//! uniform cut (from a triangle's own bound), of the pieces of a halving (one or two inner
//! edges halved, from the triangle's lattice of step 1/6), and of any piece from its own
//! lattice of step 1/3 (see `refine` for where each is used).

use crate::deviation::{Lattice, PatchBounds, PreparedBounds, TriangleBound};
use crate::domain::GridPoint;
use crate::math::{self, length};
use crate::patch::BezierPatch;

/// The bound of the pieces of a uniform refinement by `n`.
pub(super) fn refined_bound(b: &TriangleBound, n: u8) -> f32 {
    let general = b.curvature / (n as f32 * n as f32) + b.slack;
    let sampled = match n {
        1 => b.refined[0],
        2 => b.refined[1],
        3 => b.refined[2],
        6 => b.refined[3],
        _ => f32::INFINITY,
    };
    math::min(sampled, general)
}

/// The smallest factor up to `max` whose pieces are within `c` (or `max`).
pub(super) fn factor_for(b: &TriangleBound, c: f32, max: u8) -> u8 {
    (1..=max).find(|&n| refined_bound(b, n) <= c).unwrap_or(max)
}

/// A cheaper cut than four for a triangle with corners `corners` (surface points `points`)
/// whose own bound asks for a factor of 2, as split requests per edge: one inner edge halved
/// (the one whose halves bound smallest), or else two (the corner between them cut off, the
/// rest along one of two diagonals: the larger bound of both is taken, the pattern chooses
/// one), where the pieces are within `c`. `inner[i]` says whether edge `i` (opposite corner
/// `i`) has a neighbour. `local` bounds the triangle's box.
///
/// Every piece has its corners at halves of the triangle's sides, so the samples of a piece's
/// bound (as [`piece_bound`] takes it: at thirds of the piece's sides) are points of the
/// triangle's own lattice of step 1/6: `lattice` is completed once, where a piece needs
/// samples, and no other surface point is computed.
#[allow(clippy::too_many_arguments)]
pub(super) fn halving(
    patch: &BezierPatch<'_>,
    lattice: &mut Lattice,
    corners: [GridPoint; 3],
    points: [[f32; 3]; 3],
    local: &PreparedBounds,
    inner: [bool; 3],
    c: f32,
) -> Option<[u8; 3]> {
    let uv = corners.map(GridPoint::to_unit);
    // Corner `i` in halves of the sides (weight on corners 1 and 2), and its parameters.
    let at = |i: usize| [(0, 0), (2, 0), (0, 2)][i];
    let mid = |a: usize, b: usize| {
        let (p, q) = (at(a), at(b));
        ((p.0 + q.0) / 2, (p.1 + q.1) / 2)
    };
    let unit = |(i, j): (usize, usize)| {
        let k = 2 - i - j;
        let f = |c: fn((f32, f32)) -> f32| {
            (k as f32 * c(uv[0]) + i as f32 * c(uv[1]) + j as f32 * c(uv[2])) * 0.5
        };
        (f(|p| p.0), f(|p| p.1))
    };
    let mut piece = |h: [(usize, usize); 3]| {
        let curvature = local.curvature_term(h.map(unit));
        let general = curvature + local.slack;
        if general <= c {
            return general;
        }
        lattice.sample_coarse_once(patch, corners, points);
        lattice.complete(patch);
        let sampled = lattice.half_piece_worst(h) + curvature * (1.0 / 9.0) + local.slack;
        math::min(sampled, general)
    };
    let mut one = None;
    for i in (0..3).filter(|&i| inner[i]) {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        let m = mid(j, k);
        let h = math::max(piece([at(i), at(j), m]), piece([at(i), m, at(k)]));
        if one.is_none_or(|(_, best): (usize, f32)| h.total_cmp(&best).is_lt()) {
            one = Some((i, h));
        }
    }
    if let Some((i, h)) = one {
        if h <= c {
            let mut split = [0; 3];
            split[i] = 2;
            return Some(split);
        }
    }
    let mut two = None;
    for (i, j) in [(0, 1), (0, 2), (1, 2)] {
        if !(inner[i] && inner[j]) {
            continue;
        }
        let k = 3 - i - j;
        let (mi, mj) = (mid(j, k), mid(i, k));
        let (ai, aj, ak) = (at(i), at(j), at(k));
        let h = math::max(
            math::max(
                piece([mi, ak, mj]),
                math::max(piece([ai, aj, mi]), piece([ai, mi, mj])),
            ),
            math::max(piece([ai, aj, mj]), piece([aj, mi, mj])),
        );
        if two.is_none_or(|(_, _, best): (usize, usize, f32)| h.total_cmp(&best).is_lt()) {
            two = Some((i, j, h));
        }
    }
    two.filter(|&(_, _, h)| h <= c).map(|(i, j, _)| {
        let mut split = [0; 3];
        split[i] = 2;
        split[j] = 2;
        split
    })
}

/// Bound of the piece `uv` of a triangle whose second derivatives `whole` bounds (the whole
/// patch's, or any region's containing the piece), or where that is over `c`, `local` (the
/// triangle's box, cut by [`PatchBounds::around`] from the triangle `tri` when first needed):
/// the curvature term alone where that is within `c` (no surface point needed), otherwise the
/// lattice of step 1/3 on the piece sampled (its 7 points besides the corners, once for both)
/// and a ninth of the curvature term (the bound's argument, see [`crate::deviation`]). Each
/// value taken is a bound of the piece on its own, so the smallest is.
pub(super) fn piece_bound(
    patch: &BezierPatch<'_>,
    whole: &PreparedBounds,
    local: &mut Option<PreparedBounds>,
    tri: [(f32, f32); 3],
    uv: [(f32, f32); 3],
    c: f32,
) -> f32 {
    let curvature = whole.curvature_term(uv);
    let general = curvature + whole.slack;
    if general <= c {
        return general;
    }
    let worst = piece_worst(patch, uv);
    let bound = math::min(worst + curvature * (1.0 / 9.0) + whole.slack, general);
    if bound <= c {
        return bound;
    }
    let local = local.get_or_insert_with(|| PatchBounds::around(patch, tri).prepared());
    let curvature = local.curvature_term(uv);
    let general = curvature + local.slack;
    let sampled = worst + curvature * (1.0 / 9.0) + local.slack;
    math::min(bound, math::min(sampled, general))
}

/// The largest deviation of the piece `uv` from its flat triangle at the 7 points of its
/// lattice of step 1/3 besides its corners.
pub(super) fn piece_worst(patch: &BezierPatch<'_>, uv: [(f32, f32); 3]) -> f32 {
    const INNER: [(usize, usize); 7] = [(1, 0), (2, 0), (0, 1), (0, 2), (1, 1), (2, 1), (1, 2)];
    let weights = |(i, j): (usize, usize)| {
        let k = 3 - i - j;
        (k as f32 / 3.0, i as f32 / 3.0, j as f32 / 3.0)
    };
    // The corners and the 7 points, evaluated together.
    let mut at = [(0.0, 0.0); 10];
    at[..3].copy_from_slice(&uv);
    for (slot, ij) in at[3..].iter_mut().zip(INNER) {
        let (a, b, c) = weights(ij);
        let u = a * uv[0].0 + b * uv[1].0 + c * uv[2].0;
        let v = a * uv[0].1 + b * uv[1].1 + c * uv[2].1;
        *slot = (u, v);
    }
    let s = patch.positions_direct(at);
    let mut worst = 0.0f32;
    for (k, ij) in INNER.into_iter().enumerate() {
        let (a, b, c) = weights(ij);
        let linear = s[0] * a + s[1] * b + s[2] * c;
        worst = math::max(worst, length(s[3 + k] - linear));
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every half-side piece a halving tries gets the deviation from the triangle's lattice
    /// that its own samples give: the same points (to within the rounding of their
    /// parameters), so the same value to a few units of rounding. A wrong lattice index
    /// would pick another surface point, far off on this strongly curved rational patch.
    #[test]
    fn half_pieces_read_their_samples_from_the_lattice() {
        let mut points = [[0.0f32; 3]; 16];
        let mut weights = [1.0f32; 16];
        for i in 0..4 {
            for j in 0..4 {
                let (x, y) = (i as f32 / 3.0, j as f32 / 3.0);
                let k = i * 4 + j;
                points[k] = [x, y, (3.0 * x).sin() * (2.0 * y + 0.5).cos()];
                weights[k] = 1.0 + 0.3 * ((i + 2 * j) % 3) as f32;
            }
        }
        let patch = BezierPatch::new_rational(3, 3, &points, &weights).unwrap();
        let m = GridPoint::MAX;
        let triangles = [
            [(0, 0), (m, 0), (0, m)],
            [(m / 7, m / 5), (m - m / 3, m / 9), (m / 4, m - m / 6)],
            [(m / 2, m / 2), (m, m / 3), (m - m / 5, m)],
        ];
        let at = [(0, 0), (2, 0), (0, 2)];
        let mid = |a: usize, b: usize| ((at[a].0 + at[b].0) / 2, (at[a].1 + at[b].1) / 2);
        let (mut compared, mut largest) = (0, 0.0f32);
        for corners in triangles {
            let corners = corners.map(|(u, v)| GridPoint { u, v });
            let uv = corners.map(GridPoint::to_unit);
            let unit = |(i, j): (usize, usize)| {
                let k = 2 - i - j;
                let f = |c: fn((f32, f32)) -> f32| {
                    (k as f32 * c(uv[0]) + i as f32 * c(uv[1]) + j as f32 * c(uv[2])) * 0.5
                };
                (f(|p| p.0), f(|p| p.1))
            };
            let mut lattice = Lattice::coarse(&patch, corners);
            lattice.complete(&patch);
            for (i, j, k) in [(0, 1, 2), (1, 2, 0), (2, 0, 1)] {
                let (mi, mj, mk) = (mid(j, k), mid(i, k), mid(i, j));
                for h in [
                    [at[i], at[j], mi],
                    [at[i], mi, at[k]],
                    [mi, at[k], mj],
                    [at[i], mi, mj],
                    [mi, mj, mk],
                ] {
                    let from_lattice = lattice.half_piece_worst(h);
                    let direct = piece_worst(&patch, h.map(unit));
                    assert!(direct > 1e-4, "{h:?}: a curved piece deviates");
                    let diff = (from_lattice - direct).abs();
                    assert!(diff <= 1e-5, "{h:?}: {from_lattice} against {direct}");
                    largest = largest.max(diff);
                    compared += 1;
                }
            }
        }
        assert_eq!(compared, 45);
        assert!(largest < 1e-5);
    }
}
