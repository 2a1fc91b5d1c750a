//! Back-patch culling: in a closed model, a patch that shows the eye only its back is left
//! out of a frame, as a triangle beyond a plane of the view is.
//!
//! The bake records each patch's outward normal cone where the model is closed and its side
//! is known (see `bake`'s orientation rule). A patch faces away when every normal in its cone
//! points away from the eye at every point of its control points' convex hull (which holds
//! the patch), or, for a parallel projection, along the view direction (`facing`'s
//! `NormalCone`). That hides nothing only where every ray from the eye that meets such a
//! patch met the front of the surface before: the surface is closed, and the eye sees it from
//! outside with no plane cutting it open. So a frame culls only when the model's bounding
//! sphere lies wholly beyond the near plane (an eye inside the solid sees only backs; a near
//! plane through it opens a window onto them).
//!
//! A culled patch's triangles are judged hidden, with a bound of 0: they are halved only where
//! a visible neighbour needs them halved to stay conforming, and none is written out, so what
//! is drawn stays crack-free.

use super::bits::set;
use super::select::Tessellator;
use crate::bound::BoundingSphere;
use crate::facing::NormalCone;
use crate::tessellator::Hierarchy;
use crate::view::{Camera, Projection, View};

impl Hierarchy<'_> {
    /// Patch `p`'s outward normal cone, if the bake recorded one.
    pub(super) fn cone(&self, p: usize) -> Option<NormalCone> {
        let [x, y, z, sin] = self.patch(p)?.cone;
        (sin < 1.0).then(|| NormalCone::from_parts([x, y, z], sin))
    }

    /// The sphere around the model's control points, where some patch has a cone (culling
    /// needs it every frame).
    pub(super) fn culling_sphere(&self) -> Option<BoundingSphere> {
        let any = (0..self.patch_count()).any(|p| self.cone(p).is_some());
        any.then(|| BoundingSphere::of_points(self.model.points()))
            .flatten()
    }
}

impl Tessellator<'_, '_> {
    /// Sets the culled bit of every patch that faces away in `view`.
    pub(super) fn cull(&mut self, view: &View) {
        let View::Screen { camera, .. } = view else {
            return;
        };
        if !self.seen_from_outside(camera) {
            return;
        }
        let culled = self.layout().culled;
        for p in 0..self.tree.patch_count() as u32 {
            if self.faces_away(camera, p) {
                set(&mut self.bits[culled..], p);
            }
        }
    }

    /// Whether `camera` culls the patches the current frame culls (see
    /// [`cull`](Self::cull)), and no other.
    #[cfg_attr(not(feature = "reuse"), allow(dead_code))]
    pub(super) fn culls_alike(&self, camera: &Camera) -> bool {
        if self.sphere.is_none() {
            return true;
        }
        let outside = self.seen_from_outside(camera);
        (0..self.tree.patch_count() as u32)
            .all(|p| self.is_culled(p) == (outside && self.faces_away(camera, p)))
    }

    /// Whether patch `p`, one of this search's, faces away from `camera`, seen from outside.
    fn faces_away(&self, camera: &Camera, p: u32) -> bool {
        // (A part of a frame culls its own patches: see `parallel`.)
        if !self.in_group(p) {
            return false;
        }
        let (Some(cone), Some(patch)) = (self.tree.cone(p as usize), self.tree.patch_of(p)) else {
            return false;
        };
        match camera.projection() {
            Projection::Perspective { .. } => cone.faces_away_from(patch.points(), camera.eye()),
            Projection::Orthographic { .. } => cone.faces_away_along(camera.forward()),
        }
    }

    /// Whether `camera` sees the model's closed parts from outside, with no plane cutting
    /// them open: the model has a cone somewhere, and its sphere lies wholly beyond the near
    /// plane (see the module docs).
    fn seen_from_outside(&self, camera: &Camera) -> bool {
        let Some(model) = self.sphere else {
            return false;
        };
        let depth = (model.center - camera.eye()).dot(camera.forward());
        // Beyond the near plane, NaN counting as not.
        depth - model.radius > camera.near()
    }

    /// Whether patch `p`'s triangles show `camera` their outside only where they face it:
    /// `p` is part of a closed model, seen from outside (see the module docs). Then a
    /// triangle that faces away is behind one that faces the eye, and a renderer may leave
    /// it out (the renderer's `TriangleSource::one_sided`).
    pub fn one_sided(&self, camera: &Camera, p: u32) -> bool {
        self.seen_from_outside(camera) && self.tree.cone(p as usize).is_some()
    }

    /// Whether patch `p` is culled in the current frame for facing away from the eye (see
    /// the module docs; its triangles are left out as hidden).
    pub fn is_culled(&self, p: u32) -> bool {
        // (No bit to read where the model culls nothing.)
        self.sphere.is_some() && super::bits::bit(&self.bits[self.layout().culled..], p)
    }
}
