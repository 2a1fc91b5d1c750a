//! How a triangle of the hierarchy is judged in a view: its bound, and whether nothing of it
//! can show.
//!
//! The bound is the node's kept vectors and remainder (see `kept`) put through the bounds of
//! the `deviation` module: in model units, the longest vector plus the remainder; on screen,
//! the vectors projected one by one at the view rays of the flat triangle's part that can
//! show (`deviation/screen.rs`, which derives it for any vectors whose hull, widened by the
//! remainder, holds the deviation). Its corners' recorded points are the flat triangle that is
//! written out, and the points the bake measured the vectors against.
//!
//! A triangle is hidden when its three corners lie beyond one plane of the view (the near
//! plane, or a side plane) by more than its longest vector plus the remainder plus the
//! rounding of the move into view coordinates: the surface piece is within that of the flat
//! triangle, so all of it lies beyond that plane. It is not written out, and its bound on
//! screen is 0 (nothing of it counts). Its sides that other triangles share lie beyond the same
//! plane: a gap there is out of sight.

use glam::Vec3;

use super::tree::{Bintree, Pending};
use crate::deviation::{bound_on_screen, EPS};
use crate::math::max;
use crate::view::{Camera, Projection, View};

/// A triangle's bound in a view's units (pixels or model units), and whether it is hidden.
#[derive(Clone, Copy, Debug)]
pub(super) struct Judged {
    pub bound: f32,
    pub hidden: bool,
}

/// Judges `h` in `view`.
pub(super) fn judge(tree: &Bintree<'_>, view: &View, h: &Pending) -> Judged {
    let node = tree.node(h);
    match view {
        View::Object { .. } => Judged {
            bound: node.object_bound(),
            hidden: false,
        },
        View::Screen { camera, .. } => {
            let mut e = [Vec3::ZERO; super::KEPT];
            for (out, v) in e.iter_mut().zip(node.kept()) {
                *out = camera.rotate_to_view(v);
            }
            let big = node.longest();
            let corners = h
                .corners
                .map(|v| Vec3::from_array(tree.vertices[v as usize].position));
            if beyond_one_plane(camera, corners, big + node.remainder) {
                return Judged {
                    bound: 0.0,
                    hidden: true,
                };
            }
            Judged {
                bound: bound_on_screen(camera, corners, &e, big, node.remainder, node.remainder),
                hidden: false,
            }
        }
    }
}

/// Whether the three points `corners` lie beyond one plane of `camera`'s view by more than
/// `margin` (and the rounding of moving them into view coordinates). Never for an
/// orthographic camera (it has no side planes here).
fn beyond_one_plane(camera: &Camera, corners: [Vec3; 3], margin: f32) -> bool {
    if let Projection::Orthographic { .. } = camera.projection() {
        return false;
    }
    let view = corners.map(|p| camera.to_view(p));
    let size = view
        .iter()
        .map(|v| v.x.abs() + v.y.abs() + v.z.abs())
        .fold(0.0f32, max);
    let w = margin + 16.0 * EPS * size;
    if !w.is_finite() {
        return false;
    }
    let ([sx, sy], [nx, ny]) = camera.side_planes();
    let near = camera.near();
    // Each plane's signed distance, positive inside (as `deviation/screen.rs` clips).
    let planes: [&dyn Fn(Vec3) -> f32; 5] = [
        &|p| p.z - near,
        &|p| (-(-p.x - sx * p.z)) / nx,
        &|p| (-(p.x - sx * p.z)) / nx,
        &|p| (-(-p.y - sy * p.z)) / ny,
        &|p| (-(p.y - sy * p.z)) / ny,
    ];
    planes
        .iter()
        .any(|inside| view.iter().all(|&p| inside(p) < -w))
}
