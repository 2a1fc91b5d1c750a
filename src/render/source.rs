//! Where the renderer's triangles come from: the run time itself (streamed, no mesh buffer)
//! or an indexed mesh in caller buffers.

use core::ops::Range;

use glam::Vec3;

use crate::bound::{Aabb, BoundingSphere};
use crate::patch::BezierPatch;
use crate::sink::{MeshIndex, TriangleSink, Vertex};
use crate::tessellator::{Hierarchy, Tessellator};
use crate::view::Camera;

/// Triangles the [`Renderer`](super::Renderer) can draw, band by band.
pub trait TriangleSource {
    /// A sphere around every triangle (it sets the depth buffer's range); `None` when there is
    /// nothing to draw.
    fn bound(&self) -> Option<BoundingSphere>;

    /// Hands `sink` every triangle that may cover pixel rows `rows` for `camera` (handing
    /// more is allowed: the rasteriser clips to the band), leaving out the patches the sink
    /// does not [want](TriangleSink::wants_patch). Called once per band, or once per frame
    /// with a triangle list, so a source should skip what it cheaply can.
    fn stream_rows(&self, camera: &Camera, rows: Range<u32>, sink: &mut impl TriangleSink);

    /// `Some(n)` when the keys of the [`keyed_triangle`](TriangleSink::keyed_triangle)s this
    /// source streams are vertex numbers below `n`: a renderer with a
    /// [vertex map](super::Renderer::with_vertex_map) of at least `n` entries then lists each
    /// vertex once, by its number. The default, `None`: keys are only names.
    fn vertex_numbers(&self) -> Option<usize> {
        None
    }

    /// The hierarchy whose vertices the keys of this source's
    /// [`keyed_triangle`](TriangleSink::keyed_triangle)s are, where they are a hierarchy's
    /// (a [`Tessellator`]'s): a key `v` below its
    /// [`vertex_count`](crate::tessellator::Hierarchy::vertex_count) is its vertex `v`. A
    /// renderer drawing in integers ([`Arithmetic::Integer`](crate::Arithmetic)) then reads
    /// such a vertex's point and normal from the hierarchy's compact bytes as integers,
    /// rather than from the [`Vertex`] in `f32`. The default, `None`: keys are only names.
    fn hierarchy(&self) -> Option<&Hierarchy<'_>> {
        None
    }

    /// Whether patch `patch`'s triangles may be left out where they face away from `camera`
    /// (the source hands a triangle's corners counter-clockwise seen from the surface's
    /// outside; one that faces away shows them clockwise on screen): true only where every
    /// pixel such a triangle covers is covered nearer by one that faces the eye, as on a
    /// closed surface seen from outside. The renderer then leaves those triangles out
    /// ([`RenderStats::culled`]), and draws the same pixels. The default, `false`: every
    /// triangle is drawn.
    ///
    /// [`RenderStats::culled`]: super::RenderStats::culled
    fn one_sided(&self, camera: &Camera, patch: u32) -> bool {
        let _ = (camera, patch);
        false
    }
}

/// The current frame of a bisection run time ([`Tessellator`]), streamed without a mesh buffer:
/// every written triangle, its corners named by their vertex numbers (equal within a frame, so
/// the renderer's sinks project each corner once), the patches that cannot reach the band's
/// rows left out as the tessellator's stream leaves them out. Nothing is evaluated: the
/// vertices are the bake's, or the pool's below it.
impl TriangleSource for Tessellator<'_, '_> {
    fn bound(&self) -> Option<BoundingSphere> {
        sphere_around(self.model_box()?)
    }

    fn stream_rows(&self, camera: &Camera, rows: Range<u32>, sink: &mut impl TriangleSink) {
        let patches = self.tree().model();
        // A patch that cannot reach the rows, or that the sink does not want, is not walked.
        self.stream_keyed(sink, |sink, patch| {
            sink.wants_patch(patch) && reaches(patches.patch(patch as usize), camera, &rows)
        });
    }

    /// The bake's vertices and the pool's ([`Tessellator::remap_len`]).
    fn vertex_numbers(&self) -> Option<usize> {
        Some(self.remap_len())
    }

    /// The hierarchy it tessellates: its vertex numbers are the keys.
    fn hierarchy(&self) -> Option<&Hierarchy<'_>> {
        Some(Tessellator::hierarchy(self))
    }

    /// The patches of a closed model, seen from outside ([`Tessellator::one_sided`]).
    fn one_sided(&self, camera: &Camera, patch: u32) -> bool {
        Tessellator::one_sided(self, camera, patch)
    }
}

/// Whether patch `patch` may reach pixel rows `rows`: whether its control points project
/// to rows at or below `rows.start - 1` and at or above `rows.end + 1`, or one is behind the
/// near plane (the patch lies in their convex hull, which projects to their projections'
/// hull in front of the eye). (Projected point by point, it stops where both are found: on
/// a pass over every row, at the first point in view, rather than at the sixteenth. That
/// was 1M of `fw_teapot` frame 0's render instructions on ARMv6-M, where each point's
/// projection is a dozen library calls.)
fn reaches(patch: Option<BezierPatch<'_>>, camera: &Camera, rows: &Range<u32>) -> bool {
    let Some(patch) = patch else {
        return true;
    };
    let (top, bottom) = (rows.start as f32 - 1.0, rows.end as f32 + 1.0);
    let (mut below_top, mut above_bottom) = (false, false);
    for q in patch.points() {
        let Some(y) = camera.project_row(Vec3::from_array(*q)) else {
            return true;
        };
        below_top |= y >= top;
        above_bottom |= y <= bottom;
        if below_top && above_bottom {
            return true;
        }
    }
    false
}

/// An indexed triangle mesh in caller buffers, as [`Tessellator::write_mesh`] writes it.
/// Triangles with an index out of range are skipped.
#[derive(Clone, Copy, Debug)]
pub struct IndexedMesh<'a, I> {
    /// Vertices.
    pub vertices: &'a [Vertex],
    /// Triangles as index triples.
    pub triangles: &'a [[I; 3]],
}

impl<I: MeshIndex> TriangleSource for IndexedMesh<'_, I> {
    fn bound(&self) -> Option<BoundingSphere> {
        let mut points = self.vertices.iter().map(|v| Vec3::from_array(v.position));
        let first = points.next()?;
        let box_ = points.fold(
            Aabb {
                min: first,
                max: first,
            },
            Aabb::including,
        );
        sphere_around(box_)
    }

    fn stream_rows(&self, _camera: &Camera, _rows: Range<u32>, sink: &mut impl TriangleSink) {
        for t in self.triangles {
            let [a, b, c] = t.map(|i| self.vertices.get(i.to_u32() as usize));
            if let (Some(a), Some(b), Some(c)) = (a, b, c) {
                if sink.wants_patch(a.patch) {
                    sink.triangle(a.patch, [a, b, c]);
                }
            }
        }
    }
}

/// A sphere through the corners of `box_` (with rounding slack).
fn sphere_around(box_: Aabb) -> Option<BoundingSphere> {
    let radius = 0.5 * box_.diagonal() * (1.0 + 4.0 * f32::EPSILON);
    radius.is_finite().then(|| BoundingSphere {
        center: box_.center(),
        radius,
    })
}
