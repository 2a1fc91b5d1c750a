//! How the bake cuts each patch's square into cells (the roots of its hierarchy): more cells
//! along the direction in which the patch bends more, so that its triangles come out about as
//! long as they are wide where they are judged.
//!
//! # The choice
//!
//! A uniform grid of `n_u x n_v` points is within a tolerance `t` about where
//! `|S_uu| / (8 (n_u - 1)²)` and `|S_vv| / (8 (n_v - 1)²)` are (the error of linear
//! interpolation along each direction), so the best grid of a patch has
//! `(n_u - 1) / (n_v - 1) ≈ √(|S_uu| / |S_vv|)` whatever the tolerance and the distance. The
//! bake takes that ratio from the control net (`S_uu` at most `p (p - 1)` times the longest
//! second difference of the net along `u`, and so on; the twist `S_uv`, from the mixed
//! differences, is added to both, as it needs halving in both directions), and wants
//! `2^a / 2^b` cells near it: `a - b ≈ w = ½ log2(|S_uu| / |S_vv|)`.
//!
//! This is a choice, not a bound: any cells give a sound hierarchy (each triangle's bound is
//! its own). What cells may be chosen is constrained: a curve two patches share must be cut
//! into as many cells from both, or the triangles on it would not meet. So a *chord* (a
//! direction of a patch, joined through each shared curve along it to the direction of the
//! patch across, and so on) has one level. The levels, at most [`MAX_CELL_LEVEL`] each,
//! minimise `Σ (a - b - w)²` over the patches, by rounds of setting each chord's level to its
//! best given the others, until a round changes nothing (each change lowers the sum, so the
//! rounds end; a round costs `O(chords · patches)`).
//!
//! On the teapot at the error table's views this takes about 4-8% fewer triangles than one
//! cell per patch; BENCHMARKS.md has the figures.

use crate::model::Model;
use crate::patch::Side;
use crate::tessellator::{Cells, HierarchyPatch, MAX_CELL_LEVEL};

use super::hierarchy::BakeScratch;

/// The level `w` a patch wants for `a - b` (see the module docs), clamped to the levels there
/// are; 0 where the net is flat in both directions.
pub(super) fn wanted(model: &Model<'_>, patch: usize) -> f32 {
    let Some(bp) = model.patches.patch(patch) else {
        return 0.0;
    };
    let (du, dv) = (bp.degree_u(), bp.degree_v());
    let at = |i: usize, j: usize| bp.control_point(i, j);
    let (mut suu, mut svv, mut suv) = (0.0f32, 0.0f32, 0.0f32);
    for i in 0..=du {
        for j in 0..=dv {
            if i + 2 <= du {
                let d = at(i, j) - 2.0 * at(i + 1, j) + at(i + 2, j);
                suu = crate::math::max(suu, (du * (du - 1)) as f32 * d.length());
            }
            if j + 2 <= dv {
                let d = at(i, j) - 2.0 * at(i, j + 1) + at(i, j + 2);
                svv = crate::math::max(svv, (dv * (dv - 1)) as f32 * d.length());
            }
            if i < du && j < dv {
                let d = at(i, j) - at(i + 1, j) - at(i, j + 1) + at(i + 1, j + 1);
                suv = crate::math::max(suv, (du * dv) as f32 * d.length());
            }
        }
    }
    let twist = 0.5 * suv;
    let (a, b) = (suu + twist, svv + twist);
    if !(a > 0.0 && b > 0.0 && a.is_finite() && b.is_finite()) {
        // Flat in a direction (or in both): as many more cells in the other as there are.
        return match (a > 0.0 && a.is_finite(), b > 0.0 && b.is_finite()) {
            (true, false) => MAX_CELL_LEVEL as f32,
            (false, true) => -(MAX_CELL_LEVEL as f32),
            _ => 0.0,
        };
    }
    let m = MAX_CELL_LEVEL as f32;
    let w = 0.5 * crate::math::log2(a / b);
    crate::math::min(m, crate::math::max(-m, w))
}

/// Which of a patch's directions runs along `side`: `u` (0) along `V0` and `V1`.
pub(crate) fn along(side: Side) -> usize {
    match side {
        Side::V0 | Side::V1 => 0,
        Side::U1 | Side::U0 => 1,
    }
}

/// Sets every patch's [`HierarchyPatch::cells`] (see the module docs), at most `max_level`
/// in a direction; the records' links must be set. `scratch` is working memory, at least
/// twice as long as `patches` (the bake's, before its first triangle).
pub(super) fn choose(
    model: &Model<'_>,
    patches: &mut [HierarchyPatch],
    scratch: &mut [BakeScratch],
    max_level: u8,
) {
    let n = patches.len();
    if max_level == 0 || scratch.len() < 2 * n {
        for p in patches.iter_mut() {
            p.cells = [0, 0];
        }
        return;
    }
    // Direction `d` of patch `p` is entry `2 p + d`: `corners[0]` its parent in a union-find
    // of chords, `corners[1]` (a root's) the chord's level; `corners[2]` of entry `2 p`
    // holds patch `p`'s wanted level as bits.
    for (i, s) in scratch[..2 * n].iter_mut().enumerate() {
        s.corners = [i as u32, 0, 0];
    }
    for p in 0..n {
        scratch[2 * p].corners[2] = wanted(model, p).to_bits();
    }
    fn find(scratch: &mut [BakeScratch], mut x: usize) -> usize {
        while scratch[x].corners[0] as usize != x {
            let up = scratch[x].corners[0] as usize;
            scratch[x].corners[0] = scratch[up].corners[0];
            x = up;
        }
        x
    }
    for (p, rec) in patches.iter().enumerate() {
        for side in Side::ALL {
            if let Some(l) = rec.links[side.index()] {
                let a = find(scratch, 2 * p + along(side));
                let b = find(scratch, 2 * l.patch as usize + along(l.side));
                if a != b {
                    let (lo, hi) = (a.min(b), a.max(b));
                    scratch[hi].corners[0] = lo as u32;
                }
            }
        }
    }
    for i in 0..2 * n {
        let r = find(scratch, i);
        scratch[i].corners[0] = r as u32;
    }
    let chord =
        |scratch: &[BakeScratch], p: usize, d: usize| scratch[2 * p + d].corners[0] as usize;
    let level = |scratch: &[BakeScratch], c: usize| scratch[c].corners[1] as f32;
    // The part of the sum the chord `c` takes part in, were its level `l`.
    let cost = |scratch: &[BakeScratch], c: usize, l: f32| {
        let mut sum = 0.0f32;
        for p in 0..n {
            let (cu, cv) = (chord(scratch, p, 0), chord(scratch, p, 1));
            if cu != c && cv != c {
                continue;
            }
            let a = if cu == c { l } else { level(scratch, cu) };
            let b = if cv == c { l } else { level(scratch, cv) };
            let d = a - b - f32::from_bits(scratch[2 * p].corners[2]);
            sum += d * d;
        }
        sum
    };
    // Each change lowers the sum by more than the margin: the rounds end (and a cap guards
    // against a rounding that would not).
    for _ in 0..64 {
        let mut changed = false;
        for c in 0..2 * n {
            if chord(scratch, c / 2, c % 2) != c {
                continue;
            }
            let now = scratch[c].corners[1];
            let mut best = (cost(scratch, c, now as f32), now);
            for l in 0..=max_level as u32 {
                let x = cost(scratch, c, l as f32);
                if x < best.0 - 1e-4 {
                    best = (x, l);
                }
            }
            if best.1 != now {
                scratch[c].corners[1] = best.1;
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    for (p, rec) in patches.iter_mut().enumerate() {
        let cells: Cells = [0, 1].map(|d| scratch[chord(scratch, p, d)].corners[1] as u8);
        rec.cells = cells;
    }
}
