//! Which side of the surface is out, decided once at bake time.
//!
//! A patch's own normal is `S_u × S_v`, and its own winding is counter-clockwise in `(u, v)`;
//! models are drawn by many hands, and half of them point that normal inward (the Utah
//! teapot does). The bake decides per patch, by this rule, and records it
//! ([`HierarchyPatch::flip`]):
//!
//! 1. **Parts.** Patches joined by shared curves form a part. Along a shared curve two
//!    patches *agree* when they run it in opposite directions going around their squares
//!    counter-clockwise (`V0` along +u, `U1` along +v, `V1` along -u, `U0` along -v): then
//!    `S_u × S_v` points to the same side of the surface on both. A part is oriented by a
//!    walk over its shared curves from its first patch (in patch order), each patch taking
//!    the orientation that agrees with the patch it is reached from. A patch reached again
//!    with the other orientation (a non-orientable part, or a model whose patches disagree
//!    around a loop) keeps the first, and its part is *inconsistent*.
//! 2. **Outside.** A part's outside is the side its enclosed volume is positive on: the sum
//!    over its patches of `∫∫ (S - c) · n` (`n` the oriented `S_u × S_v`, `c` the centre of
//!    the model's control points, 5 x 5 Gauss-Legendre points a patch), three times the
//!    enclosed volume of a closed part and the volume of the cone from `c` over an open one.
//!    Where the sum is below 1% of the same integral of its absolute value, the side is
//!    *unknown* and the part keeps its first patch's own orientation.
//! 3. **Output.** A patch oriented against its own `S_u × S_v` is flipped: its triangles are
//!    written clockwise in `(u, v)` (counter-clockwise seen from outside) and its vertices'
//!    normals are negated, so that normals and winding agree and point out.
//! 4. **Culling.** Where every curve of the model is shared by exactly two patch edges (a
//!    closed surface) and a part is consistent with a known side, each of its patches records
//!    the cone of its outward normals ([`HierarchyPatch::cone`], `facing`'s `NormalCone`,
//!    where it is narrower than a half-space): a tessellator leaves out a patch whose cone
//!    faces away from the eye (see its `cull` module).
//!
//! `host-tests/tests/orientation.rs` checks the shipped models: a positive signed volume of
//! the written mesh, and normals that agree with the winding.

use super::hierarchy::BakeScratch;
use crate::bound::BoundingSphere;
use crate::facing::{signed_volume, NormalCone};
use crate::model::Model;
use crate::patch::Side;
use crate::tessellator::{HierarchyPatch, HierarchyVertex};

/// Whether `side` runs forward along its parameter going around the square counter-clockwise.
fn forward(side: Side) -> bool {
    matches!(side, Side::V0 | Side::U1)
}

/// No orientation yet (a scratch entry's value).
const UNSET: u32 = u32::MAX;

/// Orients every patch of `model` (rule 1 to 3 of the module docs, in `patches[p].flip`),
/// records the outward cones where rule 4 allows, and negates the normals of the vertices
/// that flipped patches evaluated. `scratch` holds at least one entry per patch (the bake's
/// is spent by now).
pub(super) fn orient(
    model: &Model<'_>,
    patches: &mut [HierarchyPatch],
    vertices: &mut [HierarchyVertex],
    scratch: &mut [BakeScratch],
) {
    let count = patches.len();
    let Some(scratch) = scratch.get_mut(..count) else {
        return;
    };
    // Per patch: its part (the first patch of it), its orientation (1: against its own
    // normal) and, for a part's first patch, whether the part is consistent (1).
    for s in scratch.iter_mut() {
        s.corners = [UNSET, UNSET, 0];
    }
    for first in 0..count {
        if scratch[first].corners[0] != UNSET {
            continue;
        }
        scratch[first].corners = [first as u32, 0, 1];
        // A walk by sweeps: every patch of the part reached from one already oriented.
        let mut changed = true;
        while changed {
            changed = false;
            for p in first..count {
                if scratch[p].corners[0] != first as u32 {
                    continue;
                }
                let flipped = scratch[p].corners[1];
                for side in Side::ALL {
                    let Some(link) = patches[p].links[side.index()] else {
                        continue;
                    };
                    let q = link.patch as usize;
                    let agree = forward(side) ^ forward(link.side) ^ link.flip;
                    let want = flipped ^ u32::from(!agree);
                    let Some(other) = scratch.get_mut(q) else {
                        continue;
                    };
                    if other.corners[0] == UNSET {
                        other.corners = [first as u32, want, 1];
                        changed = true;
                    } else if other.corners[1] != want {
                        // Inconsistent: the part's first patch carries the mark.
                        scratch[first].corners[2] = 0;
                    }
                }
            }
        }
    }
    let closed = model.topology.curves().iter().all(|c| c.uses == 2);
    let center = BoundingSphere::of_points(model.patches.points()).map(|s| s.center);
    for first in 0..count {
        if scratch[first].corners[0] != first as u32 {
            continue;
        }
        // The part's signed volume with the orientations found.
        let (mut volume, mut scale) = (0.0f32, 0.0f32);
        for (p, entry) in scratch.iter().enumerate().skip(first) {
            if entry.corners[0] != first as u32 {
                continue;
            }
            let (Some(patch), Some(c)) = (model.patches.patch(p), center) else {
                continue;
            };
            let (v, s) = signed_volume(&patch, c);
            volume += if entry.corners[1] == 1 { -v } else { v };
            scale += s;
        }
        let known = volume.abs() >= 0.01 * scale && volume.is_finite();
        let outward = if known && volume < 0.0 { 1 } else { 0 };
        let cull = closed && known && scratch[first].corners[2] == 1;
        for p in first..count {
            if scratch[p].corners[0] != first as u32 {
                continue;
            }
            let flip = (scratch[p].corners[1] ^ outward) == 1;
            patches[p].flip = flip;
            let cone = model
                .patches
                .patch(p)
                .filter(|_| cull)
                .and_then(|patch| NormalCone::of(&patch))
                .map(|c| if flip { c.flipped() } else { c });
            patches[p].cone = match cone {
                Some(c) => {
                    let a = c.axis();
                    [a.x, a.y, a.z, c.sin_half_angle()]
                }
                None => crate::tessellator::NO_CONE,
            };
        }
    }
    for v in vertices.iter_mut() {
        if patches.get(v.patch as usize).is_some_and(|p| p.flip) {
            v.normal = v.normal.map(|x| -x);
        }
    }
}
