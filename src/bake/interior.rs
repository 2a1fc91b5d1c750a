//! Greedy sampling of one patch: its interior and how far into each boundary curve it reaches.
//!
//! The patch's domain triangulation starts from its four corners. Each step takes the triangle
//! with the largest deviation *bound* (see [`PatchBounds`]) and does one of two things:
//!
//! - when one of the triangle's edges lies on a boundary curve and that edge's own chord bound
//!   is at least half the triangle's, it *requests* the curve's next sample: the curve's
//!   samples, chosen once for every patch that shares it (see
//!   [`sample_curve`](super::sample_curve)), enter in their own order;
//! - otherwise it inserts the (u,v) where the triangle's sampled deviation is largest.
//!
//! Each step is recorded with the largest bound of the whole triangulation after it; the list
//! is then made non-increasing by a running minimum. At run time a patch takes the shortest
//! prefix whose last value is at or below its threshold (the bound can rise after a step, so
//! the value of a prefix is its own bound only for that shortest one), and each curve carries the samples the patches that
//! share it request in their prefixes (the larger request wins). So the run time's
//! triangulation of a patch holds its baked prefix's points, plus, on a curve whose neighbour
//! asked for more, some more boundary points: where it holds exactly the prefix's points, every
//! triangle's bound is at most the recorded value, a computed bound, not an estimate.
//!
//! A request is recorded as the boundary point it inserts (interior samples never lie on the
//! boundary, see below).
//!
//! # The boundary margin
//!
//! An interior sample is never closer than [`BOUNDARY_MARGIN`] grid steps (1/4096 of the
//! parameter range) to the square's boundary: a candidate inside that strip is moved onto its
//! inner edge. The reasons:
//!
//! - The boundary belongs to the curves. Along it the surface *is* the boundary curve, whose
//!   samples are chosen once for every patch sharing it; a sample on the edge, or rounding onto
//!   it, would be a vertex the neighbour does not have: a crack.
//! - At run time a curve's active samples follow the finer of its two patches, so the vertices
//!   on the boundary change with the neighbour. Keeping interior samples a few steps away keeps
//!   the triangles between the two from collapsing onto the edge.
//!
//! The strip is deliberately thin. A wider one (1/256 was tried) stalls the bake where the
//! surface changes fast across an edge: at a pole (a collapsed edge has no curve samples, so
//! the triangles touching it are only as good as the samples nearest to it) and along a
//! straight edge of a strongly bent surface (the three.js NURBS example), where the deviation
//! inside the strip grows in proportion to its width.
//!
//! If the moved candidate (and, as a fallback, the triangle's centroid) is already a vertex, the
//! triangle cannot take a sample; when it is the worst one, sampling stops with
//! [`StopReason::Resolution`].

use core::fmt;

use super::curve::{CurveSample, StopReason};
use super::model::boundary_point;
use super::quantize::{decode_offset, encode_offset, PointBox};
use crate::deviation::{chord_bound, triangle_bound};
use crate::domain::orient;
use crate::domain::{DomainMesh, GridPoint, InsertError, Metric};
use crate::math::length;
use crate::patch::{BezierPatch, Side};
use crate::tessellator::{along, common_side};

/// Grid steps between an interior sample and the square's boundary, at least.
pub const BOUNDARY_MARGIN: u16 = 16;

/// One recorded step of a patch: an interior sample, or a request for a boundary curve's next
/// sample (then `point` is that sample's point on the boundary).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct InteriorSample {
    /// The sample's (u,v) on the grid; on the boundary for a curve request.
    pub point: GridPoint,
    /// Largest deviation bound of the patch's triangulation once this step and all before it
    /// are in.
    pub deviation: f32,
    /// The surface at `point`, as stored (in the patch's [`PointBox`]).
    pub surface: [f32; 3],
    /// The surface at `point` minus the linear interpolant there of the triangle that held it
    /// before this step, as stored: how far the step moves the triangulation at its own point
    /// (three 15-bit mantissas and a shared exponent). Not a bound: the run time uses it to
    /// choose steps.
    pub offset: [f32; 3],
}

impl InteriorSample {
    /// The side whose curve this step requests a sample of, or `None` for an interior sample.
    pub fn requested_side(&self) -> Option<Side> {
        let (p, m) = (self.point, GridPoint::MAX);
        if p.v == 0 {
            Some(Side::V0)
        } else if p.u == m {
            Some(Side::U1)
        } else if p.v == m {
            Some(Side::V1)
        } else if p.u == 0 {
            Some(Side::U0)
        } else {
            None
        }
    }
}

/// The deviation bound of one domain triangle, and where to split it.
///
/// Also the scratch entry [`sample_patch`] keeps per triangle slot.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct TriangleDeviation {
    deviation: f32,
    at: GridPoint,
    stuck: bool,
}

impl TriangleDeviation {
    /// Upper bound of the distance between the surface and the triangle's linear interpolant.
    pub fn deviation(&self) -> f32 {
        self.deviation
    }

    /// Where the sampled deviation is largest, on the grid and outside the boundary margin.
    pub fn at(&self) -> GridPoint {
        self.at
    }
}

/// The outcome of [`sample_patch`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct InteriorSampling {
    /// Steps written, in order (interior samples and curve requests).
    pub samples: usize,
    /// Interior samples among them.
    pub interior: usize,
    /// Deviation bound of the starting triangulation (the corners).
    pub initial_deviation: f32,
    /// Why it stopped.
    pub stop: StopReason,
}

/// Why a patch interior could not be sampled. The sample buffer is untouched.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum InteriorSampleError {
    /// The tolerance is negative or not finite.
    BadTolerance,
    /// The per-triangle scratch needs one entry per triangle slot of the mesh.
    ScratchTooSmall {
        /// Entries needed.
        needed: usize,
    },
    /// The mesh cannot take one vertex per sample of the buffer.
    MeshTooSmall {
        /// Vertex slots needed.
        vertices: usize,
        /// Triangle slots needed.
        triangles: usize,
    },
}

impl fmt::Display for InteriorSampleError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            InteriorSampleError::BadTolerance => f.write_str("tolerance must be finite and >= 0"),
            InteriorSampleError::ScratchTooSmall { needed } => {
                write!(f, "triangle scratch needs {needed} entries")
            }
            InteriorSampleError::MeshTooSmall {
                vertices,
                triangles,
            } => write!(
                f,
                "mesh needs {vertices} vertex and {triangles} triangle slots"
            ),
        }
    }
}

impl core::error::Error for InteriorSampleError {}

/// The Delaunay metric that suits `patch`: circles are stretched so that triangles are longer
/// along the parameter in which the surface bends less.
///
/// Linear interpolation over a triangle with extents `h_u`, `h_v` deviates by about
/// `(h_u^2 A_u + 2 h_u h_v A_uv + h_v^2 A_v) / 8`, where the `A` bound the second derivatives
/// (from the control net's second differences). Balancing the two end terms asks for
/// `h_u / h_v = sqrt(A_v / A_u)`, which the metric `u : v = sqrt(A_u : A_v)` produces from
/// triangles that are round in its coordinates. The twist `A_uv` is added to both, so a ruled
/// surface is not stretched without bound, and the factors are rounded to whole numbers up to
/// [`Metric::MAX`].
///
/// ```
/// use spline_tess::bake::patch_metric;
/// use spline_tess::{BezierPatch, Metric};
///
/// // A parabolic cylinder z = (2u - 1)^2: bent along u, straight along v.
/// let net = [
///     [0.0, 0.0, 1.0], [0.0, 1.0, 1.0],
///     [1.0, 0.0, -1.0], [1.0, 1.0, -1.0],
///     [2.0, 0.0, 1.0], [2.0, 1.0, 1.0],
/// ];
/// let patch = BezierPatch::new(2, 1, &net).unwrap();
/// assert_eq!(patch_metric(&patch), Metric::new(Metric::MAX, 1));
/// ```
pub fn patch_metric(patch: &BezierPatch<'_>) -> Metric {
    let (p, q) = (patch.degree_u(), patch.degree_v());
    let mut a = [0.0f32; 3]; // A_u, A_v, A_uv
    for i in 0..=p {
        for j in 0..=q {
            let at = |i: usize, j: usize| patch.control_point(i, j);
            if i >= 1 && i < p {
                let d = at(i + 1, j) - at(i, j) * 2.0 + at(i - 1, j);
                a[0] = a[0].max(length(d) * (p * (p - 1)) as f32);
            }
            if j >= 1 && j < q {
                let d = at(i, j + 1) - at(i, j) * 2.0 + at(i, j - 1);
                a[1] = a[1].max(length(d) * (q * (q - 1)) as f32);
            }
            if i < p && j < q {
                let d = at(i + 1, j + 1) - at(i + 1, j) - at(i, j + 1) + at(i, j);
                a[2] = a[2].max(length(d) * (p * q) as f32);
            }
        }
    }
    let (au, av) = (a[0] + a[2], a[1] + a[2]);
    if !(au.is_finite() && av.is_finite()) || au <= 0.0 || av <= 0.0 {
        return if au > 0.0 && av <= 0.0 {
            Metric::new(Metric::MAX, 1)
        } else if av > 0.0 && au <= 0.0 {
            Metric::new(1, Metric::MAX)
        } else {
            Metric::ISOTROPIC
        };
    }
    let factor = |r: f32| {
        let r = crate::math::sqrt(r);
        if r >= Metric::MAX as f32 {
            Metric::MAX
        } else {
            libm::floorf(r + 0.5) as u8
        }
    };
    if au >= av {
        Metric::new(factor(au / av), 1)
    } else {
        Metric::new(1, factor(av / au))
    }
}

/// A boundary edge whose chord bound is at least this share of its triangle's bound asks for
/// its curve's next sample instead of an interior sample. (Measured on the teapot at 0.02:
/// 0.5 gives 25% more triangles, 0.6 16%, 0.75 none, 0.8 8% more; Gumbo and the teacup agree
/// within a few percent; `host-tests/examples/error_figures.rs`.)
const REQUEST_SHARE: f32 = 0.75;

/// `p` moved inside the boundary margin.
fn inside_margin(p: GridPoint) -> GridPoint {
    let c = |x: u16| x.clamp(BOUNDARY_MARGIN, GridPoint::MAX - BOUNDARY_MARGIN);
    GridPoint::new(c(p.u), c(p.v))
}

/// The bound of the counter-clockwise domain triangle `corners` of `patch` and where to split
/// it: the largest sampled deviation's point, moved out of the boundary margin.
///
/// ```
/// use spline_tess::bake::triangle_deviation;
/// use spline_tess::{BezierPatch, GridPoint};
///
/// // A bilinear patch is exactly linear along u and along v; on the diagonal it bends.
/// let saddle = [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 1.0]];
/// let patch = BezierPatch::new(1, 1, &saddle).unwrap();
/// let m = GridPoint::MAX;
/// let d = triangle_deviation(&patch, [GridPoint::new(0, 0), GridPoint::new(m, 0), GridPoint::new(m, m)]);
/// // z = uv against the plane z = v: v (1 - u), largest (1/4) in the middle of the diagonal.
/// assert!(d.deviation() >= 0.25 && d.deviation() < 0.26);
/// let (u, v) = d.at().to_unit();
/// assert!((u - 0.5).abs() < 1e-4 && (v - 0.5).abs() < 1e-4);
/// ```
pub fn triangle_deviation(patch: &BezierPatch<'_>, corners: [GridPoint; 3]) -> TriangleDeviation {
    let b = triangle_bound(patch, corners);
    TriangleDeviation {
        deviation: b.bound(),
        at: inside_margin(b.at),
        stuck: false,
    }
}

fn analyse(patch: &BezierPatch<'_>, mesh: &DomainMesh<'_>, slot: u16) -> TriangleDeviation {
    let corners = mesh
        .triangle(slot)
        .map(|t| t.map(|v| mesh.point(v).unwrap_or_default()))
        .unwrap_or_default();
    triangle_deviation(patch, corners)
}

/// The live triangle with the largest bound (ties: the lowest slot).
fn worst(mesh: &DomainMesh<'_>, scratch: &[TriangleDeviation]) -> (u16, TriangleDeviation) {
    let mut best = (0u16, TriangleDeviation::default());
    let mut found = false;
    for slot in 0..mesh.triangle_capacity() as u16 {
        if mesh.triangle(slot).is_some() {
            let d = scratch[slot as usize];
            if !found || d.deviation > best.1.deviation {
                best = (slot, d);
                found = true;
            }
        }
    }
    best
}

/// The surface at `point` and its offset from the linear interpolant of the domain triangle
/// `held` (which holds it), both rounded as the format stores them (in `frame`).
fn step_offset(
    patch: &BezierPatch<'_>,
    frame: &PointBox,
    held: [GridPoint; 3],
    point: GridPoint,
) -> ([f32; 3], [f32; 3]) {
    let at = |g: GridPoint| {
        let (u, v) = g.to_unit();
        patch.position(u, v)
    };
    let [a, b, c] = held;
    // Barycentric weights from the exact integer areas.
    let area = orient(a, b, c) as f32;
    let weights = if area > 0.0 {
        [
            orient(point, b, c) as f32 / area,
            orient(a, point, c) as f32 / area,
            orient(a, b, point) as f32 / area,
        ]
    } else {
        [1.0 / 3.0; 3]
    };
    let linear = at(a) * weights[0] + at(b) * weights[1] + at(c) * weights[2];
    let surface = at(point);
    let (m, e) = encode_offset((surface - linear).to_array());
    (
        frame.decode(frame.encode(surface.to_array())),
        decode_offset(m, e),
    )
}

/// One side's boundary curve as [`sample_patch`] reads it: the curve's samples in their order,
/// and whether the side runs against the curve.
#[derive(Clone, Copy, Debug)]
pub struct SideCurve<'a> {
    /// The curve's samples.
    pub samples: &'a [CurveSample],
    /// True when the side runs against the curve's parameter.
    pub reversed: bool,
}

/// Samples `patch` greedily (see the module docs) until the triangulation's bound is at most
/// `tolerance`, `max_interior` interior samples are in, `out` is full, or the worst triangle
/// cannot take a sample.
///
/// `mesh` holds the patch's four corners and receives the samples; it needs a free vertex
/// slot per entry of `out` and triangle slots for them ([`DomainMesh::triangles_for`]).
/// `scratch` needs one entry per triangle slot of `mesh`. `curves[s]` is the curve of side
/// `s` (`None` for a collapsed side).
///
/// ```
/// use spline_tess::bake::{sample_patch, InteriorSample, StopReason, TriangleDeviation};
/// use spline_tess::{BezierPatch, DomainMesh, MeshTriangle, MeshVertex};
///
/// // A biquadratic bump whose sides are straight: no curve sample is needed.
/// let mut net = [[0.0f32; 3]; 9];
/// for i in 0..3 {
///     for j in 0..3 {
///         net[i * 3 + j] = [i as f32, j as f32, if i == 1 && j == 1 { 2.0 } else { 0.0 }];
///     }
/// }
/// let patch = BezierPatch::new(2, 2, &net).unwrap();
/// let mut vertices = [MeshVertex::default(); 36];
/// let mut triangles = [MeshTriangle::default(); DomainMesh::triangles_for(36)];
/// let mut mesh = DomainMesh::new(&mut vertices, &mut triangles).unwrap();
/// let mut scratch = [TriangleDeviation::default(); DomainMesh::triangles_for(36)];
/// let mut out = [InteriorSample::default(); 32];
/// let s = sample_patch(&patch, [None; 4], &mut mesh, 0.05, &mut scratch, &mut out, 32).unwrap();
/// assert_eq!(s.stop, StopReason::Tolerance);
/// assert!(s.initial_deviation > 0.4 && out[s.samples - 1].deviation <= 0.05);
/// // Each recorded bound bounds the ones after it.
/// assert!(out[..s.samples].windows(2).all(|w| w[0].deviation >= w[1].deviation));
/// ```
pub fn sample_patch(
    patch: &BezierPatch<'_>,
    curves: [Option<SideCurve<'_>>; 4],
    mesh: &mut DomainMesh<'_>,
    tolerance: f32,
    scratch: &mut [TriangleDeviation],
    out: &mut [InteriorSample],
    max_interior: usize,
) -> Result<InteriorSampling, InteriorSampleError> {
    if !(tolerance.is_finite() && tolerance >= 0.0) {
        return Err(InteriorSampleError::BadTolerance);
    }
    if scratch.len() < mesh.triangle_capacity() {
        return Err(InteriorSampleError::ScratchTooSmall {
            needed: mesh.triangle_capacity(),
        });
    }
    let vertices = mesh.vertex_count() + out.len();
    let triangles = DomainMesh::triangles_for(vertices);
    if mesh.vertex_capacity() < vertices || mesh.triangle_capacity() < triangles {
        return Err(InteriorSampleError::MeshTooSmall {
            vertices,
            triangles,
        });
    }
    for slot in 0..mesh.triangle_capacity() as u16 {
        if mesh.triangle(slot).is_some() {
            scratch[slot as usize] = analyse(patch, mesh, slot);
        }
    }
    let initial_deviation = worst(mesh, scratch).1.deviation;
    let frame = PointBox::of_points(patch.points());
    let mut cursor = [0usize; 4];
    let (mut count, mut interior) = (0usize, 0usize);
    let stop = loop {
        let (slot, w) = worst(mesh, scratch);
        if w.deviation <= tolerance {
            break StopReason::Tolerance;
        }
        if count == out.len() || interior == max_interior {
            break StopReason::SampleCap;
        }
        let Some(corners) = mesh
            .triangle(slot)
            .map(|t| t.map(|v| mesh.point(v).unwrap_or_default()))
        else {
            break StopReason::Resolution;
        };
        // A boundary edge that carries much of the bound asks for its curve's next sample.
        let mut request = None;
        for i in 0..3 {
            let (a, b) = (corners[(i + 1) % 3], corners[(i + 2) % 3]);
            let Some(side) = common_side(a, b) else {
                continue;
            };
            let Some(curve) = curves[side.index()] else {
                continue;
            };
            let Some(next) = curve.samples.get(cursor[side.index()]) else {
                continue;
            };
            let (ta, tb) = (along(side, a), along(side, b));
            let unit = |t: u16| t as f32 / GridPoint::MAX as f32;
            let chord = chord_bound(patch, side, unit(ta.min(tb)), unit(ta.max(tb)));
            if chord.bound >= REQUEST_SHARE * w.deviation
                && request.is_none_or(|(_, _, c): (Side, GridPoint, f32)| chord.bound > c)
            {
                request = Some((
                    side,
                    boundary_point(side, next.t, curve.reversed),
                    chord.bound,
                ));
            }
        }
        // The triangle that holds a point before it goes in.
        let mut held = [GridPoint::default(); 3];
        let mut insert = |mesh: &mut DomainMesh<'_>, point: GridPoint| {
            held = mesh.holding(point);
            mesh.insert(point).map(|id| (id, point))
        };
        let inserted = match request {
            Some((side, point, _)) => {
                cursor[side.index()] += 1;
                insert(mesh, point)
            }
            None => {
                let centroid = {
                    let mean = |f: fn(GridPoint) -> u16| {
                        ((f(corners[0]) as u32 + f(corners[1]) as u32 + f(corners[2]) as u32) / 3)
                            as u16
                    };
                    inside_margin(GridPoint::new(mean(|p| p.u), mean(|p| p.v)))
                };
                match insert(mesh, w.at) {
                    Err(InsertError::Duplicate { .. }) => insert(mesh, centroid),
                    other => other,
                }
                .inspect(|_| interior += 1)
            }
        };
        match inserted {
            Ok((id, point)) => {
                for t in mesh.star(id) {
                    scratch[t as usize] = analyse(patch, mesh, t);
                }
                let (surface, offset) = step_offset(patch, &frame, held, point);
                out[count] = InteriorSample {
                    point,
                    deviation: worst(mesh, scratch).1.deviation,
                    surface,
                    offset,
                };
                count += 1;
            }
            // The capacities were checked above, so only these can happen: the triangle
            // cannot take a sample (a requested curve point is never a duplicate: curve
            // samples are distinct and never corners).
            Err(_) => scratch[slot as usize].stuck = true,
        }
        if w.stuck && request.is_none() {
            break StopReason::Resolution;
        }
    };
    // A running minimum: the first prefix whose bound is at most a threshold is still the
    // first whose recorded value is, and the list becomes non-increasing (a binary search finds
    // that prefix). A suffix maximum would do the same but drags a late rise back over every
    // earlier step.
    for k in 1..count {
        out[k].deviation = out[k].deviation.min(out[k - 1].deviation);
    }
    Ok(InteriorSampling {
        samples: count,
        interior,
        initial_deviation,
        stop,
    })
}
