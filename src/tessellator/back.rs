//! Back-patch culling: which patches of a closed model show the eye only their back.
//!
//! A patch is left out of a frame when every normal it has points away from the eye at every
//! one of its points (see [`crate::facing`] for the normal cone and the test). That hides
//! nothing only where every ray from the eye that meets such a patch has met the front of the
//! surface before, which holds when:
//!
//! 1. **The surface is closed**: every boundary curve is shared by exactly two patch edges
//!    (collapsed edges are points and need nothing). A ray that leaves the solid through a
//!    back-facing point entered it earlier through the front.
//! 2. **Its normals agree**: the two patches along every curve run it in opposite directions
//!    around their domains, so `S_u × S_v` points to the same side of the surface on both.
//! 3. **We know which side is out**: per connected part, the sign of the enclosed volume
//!    `⅓ ∮ (S - c) · (S_u × S_v)` (5 x 5 Gauss-Legendre points per patch, `c` the model's
//!    centre). The sign is taken only when the volume is at least 1% of the integral of the
//!    absolute value; otherwise the part is not culled.
//! 4. **The eye sees the surface from outside, and no plane cuts it open**: the model's
//!    bounding sphere (its control points') lies wholly beyond the near plane. Otherwise a
//!    frame culls nothing by facing (an eye inside the solid sees only backs; a near plane
//!    through it opens a window onto them).
//!
//! 1 to 3 are checked once, when the tessellator is made ([`Settings::back_patches`]
//! chooses), 4 in every frame. A culled patch is like one off the view: its curves follow the
//! patches that are drawn, so what is drawn stays crack-free.
//!
//! [`Settings::back_patches`]: super::Settings::back_patches

use super::Tessellator;
use crate::bound::BoundingSphere;
use crate::domain::DomainIndex;
use crate::facing::{signed_volume, NormalCone};
use crate::model::EdgeLink;
use crate::patch::Side;
use crate::view::{Projection, View};

/// Which of the two directions of a curve a side runs along, going around its domain
/// counter-clockwise (`V0` along +u, `U1` along +v, `V1` along -u, `U0` along -v).
fn loop_sign(side: Side, reversed: bool) -> bool {
    let forward = matches!(side, Side::V0 | Side::U1);
    forward != reversed
}

impl<'m, 's, Ix: DomainIndex> Tessellator<'m, 's, Ix> {
    /// Finds each patch's outward normal cone when the model is closed, its normals agree and
    /// their side is known (conditions 1 to 3); returns the model's bounding sphere then.
    pub(super) fn orient_patches(&mut self) -> Option<BoundingSphere> {
        let baked = self.baked;
        let (np, nc) = (baked.patch_count(), baked.curve_count());
        // 1 and 2: every curve used twice, in opposite directions around the two domains.
        // `predict` counts the uses and `used` keeps the first one's direction; both are
        // scratch until the first frame.
        for c in self.storage.curves[..nc].iter_mut() {
            c.predict = 0;
        }
        let mut agree = true;
        for p in 0..np {
            for (side, link) in Side::ALL.into_iter().zip(baked.patch_edges(p)?) {
                if let EdgeLink::Curve { curve, reversed } = link {
                    let c = self.storage.curves.get_mut(curve as usize)?;
                    let sign = loop_sign(side, reversed);
                    match c.predict {
                        0 => c.used = sign,
                        1 => agree &= c.used != sign,
                        _ => agree = false,
                    }
                    c.predict = c.predict.saturating_add(1);
                }
            }
        }
        let closed = self.storage.curves[..nc].iter().all(|c| c.predict == 2);
        for c in self.storage.curves[..nc].iter_mut() {
            c.predict = 0;
            c.used = false;
        }
        if !(agree && closed) || np == 0 {
            return None;
        }
        // 3: connected parts (a label per patch), then each part's volume, in the output
        // scratch: labels, volumes, scales.
        let scratch = self.storage.scratch.get_mut(..3 * np)?;
        let (labels, rest) = scratch.split_at_mut(np);
        let (volumes, scales) = rest.split_at_mut(np);
        for (p, l) in labels.iter_mut().enumerate() {
            *l = p as u32;
        }
        let mut changed = true;
        while changed {
            changed = false;
            for p in 0..np {
                for link in baked.patch_edges(p)? {
                    if let EdgeLink::Curve { curve, .. } = link {
                        let q = self.storage.curves[curve as usize].owner as usize;
                        let l = labels[p].min(*labels.get(q)?);
                        if labels[p] != l || labels[q] != l {
                            labels[p] = l;
                            labels[q] = l;
                            changed = true;
                        }
                    }
                }
            }
        }
        let sphere = BoundingSphere::of_points(self.patches.points())?;
        volumes.fill(0f32.to_bits());
        scales.fill(0f32.to_bits());
        for (p, &l) in labels.iter().enumerate() {
            let patch = self.patches.patch(p)?;
            let (v, s) = signed_volume(&patch, sphere.center);
            let l = l as usize;
            volumes[l] = (f32::from_bits(volumes[l]) + v).to_bits();
            scales[l] = (f32::from_bits(scales[l]) + s).to_bits();
        }
        let mut any = false;
        for (p, &l) in labels.iter().enumerate() {
            let l = l as usize;
            let (v, s) = (f32::from_bits(volumes[l]), f32::from_bits(scales[l]));
            let patch = self.patches.patch(p)?;
            let cone = if v.abs() >= 0.01 * s && v.is_finite() {
                NormalCone::of(&patch).map(|c| if v > 0.0 { c } else { c.flipped() })
            } else {
                None
            };
            any |= cone.is_some();
            self.storage.patches[p].cone = cone;
        }
        any.then_some(sphere)
    }

    /// Whether patch `p` shows only its back to `view` (condition 4, then the cone test).
    pub(super) fn faces_away(&self, p: usize, view: &View) -> bool {
        let (Some(model), View::Screen { camera, .. }) = (self.closed, view) else {
            return false;
        };
        let Some(cone) = self.storage.patches[p].cone else {
            return false;
        };
        let depth = (model.center - camera.eye()).dot(camera.forward());
        // Beyond the near plane, NaN counting as not.
        if depth - model.radius <= camera.near() || depth.is_nan() {
            return false;
        }
        let Some(patch) = self.patches.patch(p) else {
            return false;
        };
        match camera.projection() {
            Projection::Perspective { .. } => cone.faces_away_from(patch.points(), camera.eye()),
            Projection::Orthographic { .. } => cone.faces_away_along(camera.forward()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::loop_sign;
    use crate::patch::Side;

    #[test]
    fn neighbours_in_a_plane_run_their_shared_side_opposite_ways() {
        // Two unit squares side by side in (u, v), both with normal +z: the first one's U1
        // is the second one's U0, in the same direction (not reversed).
        assert_ne!(loop_sign(Side::U1, false), loop_sign(Side::U0, false));
        // One above the other: V1 of the lower is V0 of the upper.
        assert_ne!(loop_sign(Side::V1, false), loop_sign(Side::V0, false));
        // A neighbour mirrored in u meets U1 with its own U1. With its v reversed as well its
        // normal is +z again (the curve runs against it): they agree. With v kept, its normal
        // is -z: they do not.
        assert_ne!(loop_sign(Side::U1, false), loop_sign(Side::U1, true));
        assert_eq!(loop_sign(Side::U1, false), loop_sign(Side::U1, false));
    }
}
