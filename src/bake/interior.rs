//! Greedy sampling of one patch's interior.
//!
//! The patch's domain triangulation starts from its corners and its boundary-curve samples
//! (the caller inserts those). Each step takes the triangle whose linear interpolant deviates
//! most from the surface, inserts the (u,v) where it deviates most, and records the largest
//! deviation of the *whole* triangulation after the insertion. As for curves, the recorded list
//! is then made non-increasing by a suffix maximum, so a prefix's value bounds its deviation.
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

use glam::Vec3;

use super::curve::StopReason;
use crate::domain::{orient, DomainMesh, GridPoint, InsertError, Metric};
use crate::math::{clamp_param, length};
use crate::patch::BezierPatch;

/// Grid steps between an interior sample and the square's boundary, at least.
pub const BOUNDARY_MARGIN: u16 = 16;

/// Barycentric subdivisions of the scan that looks for a triangle's largest deviation.
const SCAN: usize = 8;
/// Steps of the pattern search that refines the best scanned point.
const REFINE: usize = 20;

/// One recorded interior sample.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct InteriorSample {
    /// The sample's (u,v) on the grid.
    pub point: GridPoint,
    /// Largest deviation of the patch's triangulation once this sample and all before it are in.
    pub deviation: f32,
}

/// The largest deviation found on one domain triangle, and where to split it.
///
/// Also the scratch entry [`sample_interior`] keeps per triangle slot.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct TriangleDeviation {
    deviation: f32,
    at: GridPoint,
    stuck: bool,
}

impl TriangleDeviation {
    /// Largest distance found between the surface and the triangle's linear interpolant.
    pub fn deviation(&self) -> f32 {
        self.deviation
    }

    /// Where it was found, on the grid and outside the boundary margin.
    pub fn at(&self) -> GridPoint {
        self.at
    }
}

/// The outcome of [`sample_interior`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct InteriorSampling {
    /// Samples written, in insertion order.
    pub samples: usize,
    /// Deviation of the starting triangulation (corners and curve samples).
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

/// `p` moved inside the boundary margin.
fn inside_margin(p: GridPoint) -> GridPoint {
    let c = |x: u16| x.clamp(BOUNDARY_MARGIN, GridPoint::MAX - BOUNDARY_MARGIN);
    GridPoint::new(c(p.u), c(p.v))
}

/// The largest deviation of `patch` from the linear interpolant over the counter-clockwise
/// domain triangle `corners`, found by a barycentric scan refined by a pattern search.
///
/// The deviation is the distance between `S(u,v)` and the interpolant of the corners' surface
/// points at the same `(u,v)`. The split point is the best point found, rounded to the grid and
/// moved out of the boundary margin.
///
/// ```
/// use spline_tess::bake::max_deviation;
/// use spline_tess::{BezierPatch, GridPoint};
///
/// // A bilinear patch is exactly linear along u and along v; on the diagonal it bends.
/// let saddle = [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 1.0]];
/// let patch = BezierPatch::new(1, 1, &saddle).unwrap();
/// let m = GridPoint::MAX;
/// let d = max_deviation(&patch, [GridPoint::new(0, 0), GridPoint::new(m, 0), GridPoint::new(m, m)]);
/// // z = uv against the plane z = v: v (1 - u), largest (1/4) in the middle of the diagonal.
/// assert!((d.deviation() - 0.25).abs() < 1e-4);
/// assert_eq!(d.at(), GridPoint::from_unit(0.5, 0.5));
/// ```
pub fn max_deviation(patch: &BezierPatch<'_>, corners: [GridPoint; 3]) -> TriangleDeviation {
    let uv = corners.map(GridPoint::to_unit);
    let pos = uv.map(|(u, v)| patch.position(u, v));
    let (e1, e2) = (
        (uv[1].0 - uv[0].0, uv[1].1 - uv[0].1),
        (uv[2].0 - uv[0].0, uv[2].1 - uv[0].1),
    );
    let (d1, d2) = (pos[1] - pos[0], pos[2] - pos[0]);
    let at_bary = |s: f32, t: f32| -> (f32, f32, f32) {
        let u = clamp_param(uv[0].0 + e1.0 * s + e2.0 * t, 0.0, 1.0);
        let v = clamp_param(uv[0].1 + e1.1 * s + e2.1 * t, 0.0, 1.0);
        let linear: Vec3 = pos[0] + d1 * s + d2 * t;
        (length(patch.position(u, v) - linear), u, v)
    };
    let step = 1.0 / SCAN as f32;
    let (mut best, mut bs, mut bt) = (0.0f32, 1.0 / 3.0, 1.0 / 3.0);
    for i in 0..=SCAN {
        for j in 0..=SCAN - i {
            if (i == 0 && j == 0) || i == SCAN || j == SCAN {
                continue; // the corners, where the deviation is zero
            }
            let (s, t) = (i as f32 * step, j as f32 * step);
            let d = at_bary(s, t).0;
            if d > best {
                (best, bs, bt) = (d, s, t);
            }
        }
    }
    // Pattern search in the six directions of the barycentric lattice.
    let mut h = step * 0.5;
    for _ in 0..REFINE {
        let mut moved = false;
        for (ds, dt) in [
            (1.0, 0.0),
            (-1.0, 0.0),
            (0.0, 1.0),
            (0.0, -1.0),
            (1.0, -1.0),
            (-1.0, 1.0),
        ] {
            let (s, t) = (bs + ds * h, bt + dt * h);
            if s < 0.0 || t < 0.0 || s + t > 1.0 {
                continue;
            }
            let d = at_bary(s, t).0;
            if d > best {
                (best, bs, bt, moved) = (d, s, t, true);
            }
        }
        if !moved {
            h *= 0.5;
        }
    }
    let (_, u, v) = at_bary(bs, bt);
    let q = GridPoint::from_unit(u, v);
    // The rounded point counts towards the maximum when it lies in the triangle.
    let [a, b, c] = corners;
    if orient(a, b, q) >= 0 && orient(b, c, q) >= 0 && orient(c, a, q) >= 0 {
        let (qu, qv) = q.to_unit();
        let det = e1.0 * e2.1 - e2.0 * e1.1;
        if det != 0.0 {
            let (du, dv) = (qu - uv[0].0, qv - uv[0].1);
            let s = (du * e2.1 - dv * e2.0) / det;
            let t = (e1.0 * dv - e1.1 * du) / det;
            let linear: Vec3 = pos[0] + d1 * s + d2 * t;
            best = best.max(length(patch.position(qu, qv) - linear));
        }
    }
    TriangleDeviation {
        deviation: best,
        at: inside_margin(q),
        stuck: false,
    }
}

fn analyse(patch: &BezierPatch<'_>, mesh: &DomainMesh<'_>, slot: u16) -> TriangleDeviation {
    let corners = mesh
        .triangle(slot)
        .map(|t| t.map(|v| mesh.point(v).unwrap_or_default()))
        .unwrap_or_default();
    max_deviation(patch, corners)
}

/// The live triangle with the largest deviation (ties: the lowest slot).
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

/// Samples the interior of `patch` greedily until the triangulation's deviation is at most
/// `tolerance`, `out` is full, or the worst triangle cannot take a sample.
///
/// `mesh` holds the starting triangulation (corners and boundary-curve samples) and receives
/// the samples; it needs a free vertex slot per entry of `out` and triangle slots for them
/// ([`DomainMesh::triangles_for`]). `scratch` needs one entry per triangle slot of `mesh`.
///
/// ```
/// use spline_tess::bake::{sample_interior, InteriorSample, StopReason, TriangleDeviation};
/// use spline_tess::{BezierPatch, DomainMesh, MeshTriangle, MeshVertex};
///
/// // A biquadratic bump.
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
/// let s = sample_interior(&patch, &mut mesh, 0.05, &mut scratch, &mut out).unwrap();
/// assert_eq!(s.stop, StopReason::Tolerance);
/// assert!(s.initial_deviation > 0.4 && out[s.samples - 1].deviation <= 0.05);
/// // Each recorded deviation bounds the ones after it.
/// assert!(out[..s.samples].windows(2).all(|w| w[0].deviation >= w[1].deviation));
/// ```
pub fn sample_interior(
    patch: &BezierPatch<'_>,
    mesh: &mut DomainMesh<'_>,
    tolerance: f32,
    scratch: &mut [TriangleDeviation],
    out: &mut [InteriorSample],
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
    let mut count = 0;
    let stop = loop {
        let (slot, w) = worst(mesh, scratch);
        if w.deviation <= tolerance {
            break StopReason::Tolerance;
        }
        if count == out.len() {
            break StopReason::SampleCap;
        }
        if w.stuck {
            break StopReason::Resolution;
        }
        let centroid = mesh.triangle(slot).map(|t| {
            let p = t.map(|v| mesh.point(v).unwrap_or_default());
            let mean = |f: fn(GridPoint) -> u16| {
                ((f(p[0]) as u32 + f(p[1]) as u32 + f(p[2]) as u32) / 3) as u16
            };
            inside_margin(GridPoint::new(mean(|p| p.u), mean(|p| p.v)))
        });
        let inserted = match mesh.insert(w.at) {
            Err(InsertError::Duplicate { .. }) => match centroid {
                Some(c) => mesh.insert(c).map(|id| (id, c)),
                None => Err(InsertError::Duplicate { vertex: 0 }),
            },
            other => other.map(|id| (id, w.at)),
        };
        match inserted {
            Ok((id, point)) => {
                for t in mesh.star(id) {
                    scratch[t as usize] = analyse(patch, mesh, t);
                }
                out[count] = InteriorSample {
                    point,
                    deviation: worst(mesh, scratch).1.deviation,
                };
                count += 1;
            }
            // The capacities were checked above, so only these can happen: the triangle
            // cannot take a sample.
            Err(_) => scratch[slot as usize].stuck = true,
        }
    };
    for k in (0..count.saturating_sub(1)).rev() {
        out[k].deviation = out[k].deviation.max(out[k + 1].deviation);
    }
    Ok(InteriorSampling {
        samples: count,
        initial_deviation,
        stop,
    })
}
