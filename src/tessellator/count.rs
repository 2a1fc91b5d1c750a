//! A frame's figures: the triangles written out and the hidden leaves, counted as the search
//! judges them, and the vertices the mesh uses, counted by a walk on demand.

use super::bits::{bit, set};
use super::hierarchy::{walk, Pending};
use super::select::Tessellator;

impl Tessellator<'_, '_> {
    /// Counts leaf `h`, judged and kept whole, as a triangle written out (if it is).
    ///
    /// The frame's triangles and hidden leaves are counted as the search judges them, so that
    /// a frame needs no walk to count them (a walk costs a good part of an update): a
    /// leaf halved later is taken off again ([`uncount_leaf`](Self::uncount_leaf)). A frame
    /// with leaves below the bake, which have no bit to say they were judged, is counted by a
    /// walk instead (see [`update`](Self::update)); a test checks both ways agree. The
    /// vertices, which a frame that is only drawn does not need, are counted by a walk on
    /// demand ([`mesh_size`](Self::mesh_size), [`write_mesh`](Self::write_mesh)).
    pub(super) fn count_leaf(&mut self, h: &Pending) {
        self.stats.triangles += usize::from(self.is_written(h));
    }

    /// Takes leaf `x`, about to be halved, off the frame's figures where
    /// [`count_leaf`](Self::count_leaf) or a judgement of hidden counted it.
    pub(super) fn uncount_leaf(&mut self, x: &Pending) {
        if !self.is_judged(x) {
            return;
        }
        if bit(&self.bits[self.layout.hidden..], x.node) {
            self.stats.hidden = self.stats.hidden.saturating_sub(1);
        } else if self.is_written(x) {
            self.stats.triangles = self.stats.triangles.saturating_sub(1);
        }
    }

    /// Counts the frame's written triangles, the vertices they use and the hidden leaves, by
    /// a walk of the mesh (the frame's `seen` bits mark the vertices).
    pub(super) fn count(&mut self) {
        let layout = self.layout();
        let tree = self.tree;
        let (mut triangles, mut vertices, mut hidden) = (0, 0, 0);
        self.bits[layout.seen..layout.culled].fill(0);
        for e in self.pool.entries.iter_mut() {
            e.seen = false;
        }
        let baked = tree.vertex_count() as u32;
        let mut bounds = None;
        walk(tree, |h| {
            if let Some(v) = self.split_vertex(h) {
                return Some(v);
            }
            if self.is_hidden(h, &mut bounds) {
                hidden += 1;
                return None;
            }
            if let Some(corners) = self.written(h) {
                triangles += 1;
                for v in corners {
                    let new = if v < baked {
                        let words = &mut self.bits[layout.seen..layout.culled];
                        let fresh = !bit(words, v);
                        set(words, v);
                        fresh
                    } else {
                        let e = &mut self.pool.entries[(v - baked) as usize];
                        !core::mem::replace(&mut e.seen, true)
                    };
                    vertices += usize::from(new);
                }
            }
            None
        });
        self.stats.triangles = triangles;
        self.stats.hidden = hidden;
        self.vertices = Some(vertices);
    }
}

#[cfg(test)]
mod tests {
    use super::super::select::tests::with_bump;
    use super::*;
    use crate::view::View;
    use glam::Vec3;

    /// The triangles and hidden leaves the search counts as it goes are those a walk of the
    /// resulting mesh counts: over views from near and far, some with the bump across the
    /// near plane or the screen's sides (hidden leaves, and leaves judged whole before a
    /// neighbour halved them), with a stack long enough and one so short that walks find
    /// what it had no room for.
    #[test]
    fn the_counts_kept_during_the_search_are_the_mesh_walked() {
        with_bump::<8192>(2e-3, |_, tree, _| {
            let mut rng = crate::test_rng::TestRng::new(0xc0_4e7);
            let mut unit = |scale: f32| rng.signed(1 << 20) as f32 / (1 << 20) as f32 * scale;
            let (mut hidden_frames, mut halved_after, mut sweeps) = (0, 0, 0);
            for length in [Tessellator::MIN_STACK, 64] {
                let mut bits = [0u32; 1024];
                let mut stack = [crate::tessellator::StackSlot::default(); 64];
                let mut selection =
                    Tessellator::from_slices(tree, &mut bits, &mut stack[..length], &mut [])
                        .unwrap();
                for k in 0..60 {
                    let distance = [0.4, 1.5, 6.0][k % 3];
                    let target = Vec3::new(1.5 + unit(1.5), 1.5 + unit(1.5), 0.5);
                    let eye = target
                        + Vec3::new(unit(1.0), unit(1.0), 0.3 + unit(0.25).abs())
                            .normalize_or_zero()
                            * distance;
                    let Ok(camera) = crate::Camera::new(
                        eye,
                        target,
                        Vec3::Z,
                        crate::Projection::Perspective {
                            fov_y_degrees: 40.0,
                        },
                        0.05,
                        [240, 240],
                    ) else {
                        continue;
                    };
                    let view = View::Screen {
                        camera,
                        tolerance_px: [0.5, 1.0, 3.0][k % 3],
                    };
                    let stats = selection.update(&view).unwrap();
                    selection.count();
                    let walked = selection.stats();
                    assert_eq!(
                        (stats.triangles, stats.hidden),
                        (walked.triangles, walked.hidden),
                        "view {k}, stack {length}"
                    );
                    hidden_frames += usize::from(stats.hidden > 0);
                    // Leaves judged and then halved by a neighbour: more judged than a
                    // top-down split of the final mesh needs.
                    halved_after += usize::from(stats.judged > 2 * stats.triangles);
                    sweeps += stats.sweeps;
                }
            }
            assert!(
                hidden_frames > 10,
                "{hidden_frames} frames with hidden leaves"
            );
            assert!(halved_after > 0 && sweeps > 0, "{halved_after} {sweeps}");
        });
    }
}
