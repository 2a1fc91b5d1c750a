//! Baking a whole model: every boundary curve once, then every patch's interior, written
//! straight into the compact format.

use core::fmt;

use super::curve::{sample_curve, CurveSample, CurveSampleError, CurveSegment};
use super::format::{
    baked_len, checksum, link_code, metric_code, model_fingerprint, put_step, stop_code, BOX_AT,
    CURVE_RECORD, CURVE_SAMPLE, HEADER_LEN, INTERIOR_SAMPLE, MAGIC, PATCH_RECORD, VERSION,
};
use super::interior::{
    patch_metric, sample_patch, InteriorSample, InteriorSampleError, SideCurve, TriangleDeviation,
};
use super::quantize::PointBox;
use crate::domain::{DomainMesh, GridPoint, InsertError, MeshTriangle, MeshVertex};
use crate::model::{EdgeLink, Model};
use crate::patch::Side;

/// The bake tolerance: the deviation at which sampling stops.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Tolerance {
    /// In object-space units.
    Absolute(f32),
    /// As a fraction of the diagonal of the model's control-point bounding box.
    Relative(f32),
}

impl Tolerance {
    /// The tolerance in model units, for a model whose control-point bounding box has
    /// diagonal `diagonal`.
    pub(crate) fn in_model_units(self, diagonal: f32) -> f32 {
        match self {
            Tolerance::Absolute(t) => t,
            Tolerance::Relative(r) => r * diagonal,
        }
    }
}

/// What to bake.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BakeSettings {
    /// Where sampling stops.
    pub tolerance: Tolerance,
    /// Most samples per boundary curve.
    pub max_curve_samples: u16,
    /// Most interior samples per patch (its curve requests come on top).
    pub max_interior_samples: u16,
}

/// Scratch sizes [`bake_model`] needs for some [`BakeSettings`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BakeScratchSize {
    /// Entries of [`BakeScratch::vertices`].
    pub vertices: usize,
    /// Entries of [`BakeScratch::triangles`] and of [`BakeScratch::deviations`].
    pub triangles: usize,
    /// Entries of [`BakeScratch::segments`].
    pub segments: usize,
    /// Entries of [`BakeScratch::curve_samples`]: four curves' samples.
    pub curve_samples: usize,
    /// Entries of [`BakeScratch::interior_samples`]: one patch's steps.
    pub interior_samples: usize,
}

impl BakeSettings {
    /// The scratch [`bake_model`] needs: a domain mesh for four curves' samples and the
    /// interior samples of one patch, and the sample buffers.
    pub const fn scratch_size(&self) -> BakeScratchSize {
        let c = self.max_curve_samples as usize;
        let i = self.max_interior_samples as usize;
        let vertices = 4 + 4 * c + i;
        BakeScratchSize {
            vertices,
            triangles: DomainMesh::triangles_for(vertices),
            segments: c + 1,
            curve_samples: 4 * c,
            interior_samples: i + 4 * c,
        }
    }
}

/// Caller-provided working memory for [`bake_model`], reused patch after patch.
#[derive(Debug)]
pub struct BakeScratch<'a> {
    /// Vertex slots of the domain mesh.
    pub vertices: &'a mut [MeshVertex],
    /// Triangle slots of the domain mesh.
    pub triangles: &'a mut [MeshTriangle],
    /// One entry per triangle slot.
    pub deviations: &'a mut [TriangleDeviation],
    /// Curve-sampling scratch.
    pub segments: &'a mut [CurveSegment],
    /// Four curves' samples.
    pub curve_samples: &'a mut [CurveSample],
    /// One patch's steps (interior samples and curve requests).
    pub interior_samples: &'a mut [InteriorSample],
}

/// Why a model could not be baked.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum BakeError {
    /// The tolerance is negative or not finite (or the model's diagonal is not finite).
    BadTolerance,
    /// The per-patch mesh would need more than 65535 vertex or triangle slots.
    CapsTooLarge,
    /// A scratch buffer is too small; these are the sizes needed.
    ScratchTooSmall(BakeScratchSize),
    /// The output buffer is too small; it needs this many bytes (and holds no loadable bake).
    OutputTooSmall {
        /// Bytes needed.
        needed: usize,
    },
    /// A boundary sample could not enter a patch's domain mesh.
    Mesh {
        /// The patch.
        patch: usize,
        /// What the mesh said.
        error: InsertError,
    },
}

impl fmt::Display for BakeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BakeError::BadTolerance => f.write_str("tolerance must be finite and >= 0"),
            BakeError::CapsTooLarge => {
                f.write_str("sample caps need more than 65535 mesh slots per patch")
            }
            BakeError::ScratchTooSmall(s) => write!(
                f,
                "bake scratch too small: needs {} vertices, {} triangles and deviations, \
                 {} segments, {} curve and {} interior samples",
                s.vertices, s.triangles, s.segments, s.curve_samples, s.interior_samples
            ),
            BakeError::OutputTooSmall { needed } => {
                write!(f, "output buffer too small: needs {needed} bytes")
            }
            BakeError::Mesh { patch, error } => write!(f, "patch {patch}: {error}"),
        }
    }
}

impl core::error::Error for BakeError {}

impl From<CurveSampleError> for BakeError {
    fn from(e: CurveSampleError) -> Self {
        match e {
            CurveSampleError::BadTolerance => BakeError::BadTolerance,
            CurveSampleError::ScratchTooSmall { .. } => BakeError::CapsTooLarge,
        }
    }
}

/// Numbers of a finished bake.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BakeSummary {
    /// Patches.
    pub patches: usize,
    /// Distinct boundary curves.
    pub curves: usize,
    /// Samples on all curves.
    pub curve_samples: usize,
    /// Interior samples of all patches.
    pub interior_samples: usize,
    /// Bytes written.
    pub bytes: usize,
    /// The object-space tolerance used.
    pub tolerance: f32,
    /// The largest deviation left on any curve or patch once all its samples are in.
    pub max_deviation: f32,
    /// Curves and patches that stopped at the tolerance, at their cap, and at the grid's
    /// resolution (or the boundary margin), in that order.
    pub stops: [usize; 3],
}

/// Writes into `out` only while it fits, counting every byte.
struct Writer<'o> {
    out: &'o mut [u8],
}

impl Writer<'_> {
    fn put(&mut self, at: usize, bytes: &[u8]) {
        if let Some(dst) = self.out.get_mut(at..at + bytes.len()) {
            dst.copy_from_slice(bytes);
        }
    }
}

/// The edge parameter `t` of curve parameter `t` on an edge running `reversed`, as a grid
/// point on `side`.
/// The domain point of curve parameter `t` on `side` (`reversed`: the side runs against the
/// curve). Shared with the run time.
pub(crate) fn boundary_point(side: Side, t: u16, reversed: bool) -> GridPoint {
    let e = if reversed { GridPoint::MAX - t } else { t };
    let m = GridPoint::MAX;
    match side {
        Side::V0 => GridPoint::new(e, 0),
        Side::U1 => GridPoint::new(m, e),
        Side::V1 => GridPoint::new(e, m),
        Side::U0 => GridPoint::new(0, e),
    }
}

fn last_deviation(initial: f32, samples: impl Iterator<Item = f32>) -> f32 {
    samples.last().unwrap_or(initial)
}

/// Bakes `model` into `out` in the [compact format](super::BakedModel): every boundary curve is
/// sampled once, then every patch from its corners, requesting its curves' samples as it goes
/// (see [`sample_patch`](super::sample_patch)). Returns the numbers of the bake; `out[..summary.bytes]` is the baked model.
///
/// Everything runs in the caller's memory: `scratch` sized by
/// [`BakeSettings::scratch_size`]. Curves are sampled again for each patch that uses them
/// (the same bits every time), which keeps the scratch independent of the model's size.
///
/// ```
/// use spline_tess::bake::{bake_model, BakeScratch, BakeSettings, BakedModel, Tolerance};
/// use spline_tess::bake::{CurveSample, CurveSegment, InteriorSample, TriangleDeviation};
/// use spline_tess::{BoundaryCurve, EdgeLink, MeshTriangle, MeshVertex, Model};
/// use spline_tess::{PatchHeader, PatchSet};
///
/// // One biquadratic bump.
/// let mut points = [[0.0f32; 3]; 9];
/// for i in 0..3 {
///     for j in 0..3 {
///         points[i * 3 + j] = [i as f32, j as f32, if i == 1 && j == 1 { 2.0 } else { 0.0 }];
///     }
/// }
/// let headers = [PatchHeader { degree_u: 2, degree_v: 2, first_point: 0 }];
/// let patches = PatchSet::new(&headers, &points, None)?;
/// let (mut edges, mut curves) = ([[EdgeLink::Collapsed; 4]; 1], [BoundaryCurve::default(); 4]);
/// let model = Model::build(patches, &mut edges, &mut curves).unwrap();
///
/// let settings = BakeSettings {
///     tolerance: Tolerance::Relative(1e-2),
///     max_curve_samples: 16,
///     max_interior_samples: 32,
/// };
/// const V: usize = 4 + 4 * 16 + 32;
/// const T: usize = 2 * V - 6;
/// assert_eq!(settings.scratch_size().triangles, T);
/// let mut vertices = [MeshVertex::default(); V];
/// let mut triangles = [MeshTriangle::default(); T];
/// let mut deviations = [TriangleDeviation::default(); T];
/// let mut segments = [CurveSegment::default(); 17];
/// let mut curve_samples = [CurveSample::default(); 4 * 16];
/// let mut interior_samples = [InteriorSample::default(); 32 + 4 * 16];
/// let scratch = BakeScratch {
///     vertices: &mut vertices,
///     triangles: &mut triangles,
///     deviations: &mut deviations,
///     segments: &mut segments,
///     curve_samples: &mut curve_samples,
///     interior_samples: &mut interior_samples,
/// };
/// let mut out = [0u8; 1024];
/// let summary = bake_model(&model, &settings, scratch, &mut out).unwrap();
/// assert!(summary.max_deviation <= summary.tolerance);
///
/// let baked = BakedModel::from_bytes(&out[..summary.bytes]).unwrap();
/// assert!(baked.matches(&model.patches));
/// assert_eq!(baked.patch(0).unwrap().samples.len(), summary.interior_samples);
/// # Ok::<(), spline_tess::PatchSetError>(())
/// ```
pub fn bake_model(
    model: &Model<'_>,
    settings: &BakeSettings,
    scratch: BakeScratch<'_>,
    out: &mut [u8],
) -> Result<BakeSummary, BakeError> {
    let patches = &model.patches;
    let curves = model.topology.curves();
    let diagonal = patches.aabb().map_or(0.0, |b| b.diagonal());
    let tolerance = settings.tolerance.in_model_units(diagonal);
    if !(tolerance.is_finite() && tolerance >= 0.0) {
        return Err(BakeError::BadTolerance);
    }
    let need = settings.scratch_size();
    if need.vertices > u16::MAX as usize || need.triangles > u16::MAX as usize {
        return Err(BakeError::CapsTooLarge);
    }
    let BakeScratch {
        vertices,
        triangles,
        deviations,
        segments,
        curve_samples,
        interior_samples,
    } = scratch;
    if vertices.len() < need.vertices
        || triangles.len() < need.triangles
        || deviations.len() < need.triangles
        || segments.len() < need.segments
        || curve_samples.len() < need.curve_samples
        || interior_samples.len() < need.interior_samples
    {
        return Err(BakeError::ScratchTooSmall(need));
    }
    let curve_samples = &mut curve_samples[..need.curve_samples];
    let interior_samples = &mut interior_samples[..need.interior_samples];
    let segments = &mut segments[..need.segments];
    // The mesh is sized exactly, so its slot numbers (and the bake) do not depend on how much
    // larger the caller's storage is.
    let vertices = &mut vertices[..need.vertices];
    let triangles = &mut triangles[..need.triangles];
    let deviations = &mut deviations[..need.triangles];

    // Invalidate any bake the buffer held; the header is written last.
    if let Some(magic) = out.get_mut(..4) {
        magic.fill(0);
    }
    let mut w = Writer { out };
    let mut summary = BakeSummary {
        patches: patches.len(),
        curves: curves.len(),
        tolerance,
        ..BakeSummary::default()
    };
    let records_end = HEADER_LEN + curves.len() * CURVE_RECORD + patches.len() * PATCH_RECORD;

    // Curves: samples from `records_end` on.
    for (k, curve) in curves.iter().enumerate() {
        let Some(patch) = patches.patch(curve.patch as usize) else {
            continue;
        };
        let one = &mut curve_samples[..need.curve_samples / 4];
        let s = sample_curve(&patch, curve.side, tolerance, one, segments)?;
        let at = HEADER_LEN + k * CURVE_RECORD;
        w.put(at, &curve.patch.to_le_bytes());
        w.put(at + 4, &[curve.side.index() as u8, stop_code(s.stop)]);
        w.put(at + 6, &(s.samples as u16).to_le_bytes());
        w.put(at + 8, &(summary.curve_samples as u32).to_le_bytes());
        w.put(at + 12, &s.initial_deviation.to_le_bytes());
        for (j, sample) in one[..s.samples].iter().enumerate() {
            let at = records_end + (summary.curve_samples + j) * CURVE_SAMPLE;
            w.put(at, &sample.t.to_le_bytes());
            w.put(at + 2, &sample.deviation.to_le_bytes());
        }
        summary.curve_samples += s.samples;
        summary.stops[stop_code(s.stop) as usize] += 1;
        let left = last_deviation(
            s.initial_deviation,
            one[..s.samples].iter().map(|x| x.deviation),
        );
        summary.max_deviation = summary.max_deviation.max(left);
    }

    // Patches: interior samples after all curve samples.
    let interior_start = records_end + summary.curve_samples * CURVE_SAMPLE;
    let per_curve = need.curve_samples / 4;
    for (k, patch) in patches.iter().enumerate() {
        let metric = patch_metric(&patch);
        let mut mesh = DomainMesh::with_metric(&mut *vertices, &mut *triangles, metric)
            .map_err(|_| BakeError::CapsTooLarge)?;
        let edges = model.topology.edges()[k];
        // Each side's curve, sampled again from its owner (the same bits every time).
        let mut counts = [0usize; 4];
        let mut reversed_sides = [false; 4];
        for (s, link) in edges.into_iter().enumerate() {
            let EdgeLink::Curve { curve, reversed } = link else {
                continue;
            };
            let Some(owner) = curves
                .get(curve as usize)
                .and_then(|c| Some((patches.patch(c.patch as usize)?, c.side)))
            else {
                continue;
            };
            let buffer = &mut curve_samples[s * per_curve..(s + 1) * per_curve];
            counts[s] = sample_curve(&owner.0, owner.1, tolerance, buffer, segments)?.samples;
            reversed_sides[s] = reversed;
        }
        let lists: [&[CurveSample]; 4] = {
            let (a, rest) = curve_samples.split_at(per_curve);
            let (b, rest) = rest.split_at(per_curve);
            let (c, d) = rest.split_at(per_curve);
            [
                &a[..counts[0]],
                &b[..counts[1]],
                &c[..counts[2]],
                &d[..counts[3]],
            ]
        };
        let sides = core::array::from_fn(|s| match edges[s] {
            EdgeLink::Curve { .. } => Some(SideCurve {
                samples: lists[s],
                reversed: reversed_sides[s],
            }),
            EdgeLink::Collapsed => None,
        });
        let s = sample_patch(
            &patch,
            sides,
            &mut mesh,
            tolerance,
            deviations,
            interior_samples,
            settings.max_interior_samples as usize,
        )
        .map_err(|e| match e {
            InteriorSampleError::BadTolerance => BakeError::BadTolerance,
            _ => BakeError::CapsTooLarge,
        })?;
        let at = HEADER_LEN + curves.len() * CURVE_RECORD + k * PATCH_RECORD;
        for (j, link) in edges.into_iter().enumerate() {
            w.put(at + 4 * j, &link_code(link).to_le_bytes());
        }
        w.put(at + 16, &(summary.interior_samples as u32).to_le_bytes());
        w.put(at + 20, &(s.samples as u16).to_le_bytes());
        w.put(at + 22, &[stop_code(s.stop), metric_code(metric)]);
        w.put(at + 24, &s.initial_deviation.to_le_bytes());
        let frame = PointBox::of_points(patch.points());
        for (i, x) in frame.min.into_iter().chain(frame.extent).enumerate() {
            w.put(at + BOX_AT + 4 * i, &x.to_le_bytes());
        }
        for (j, sample) in interior_samples[..s.samples].iter().enumerate() {
            let at = interior_start + (summary.interior_samples + j) * INTERIOR_SAMPLE;
            let mut record = [0u8; INTERIOR_SAMPLE];
            put_step(&mut record, sample, &frame);
            w.put(at, &record);
        }
        summary.interior_samples += s.samples;
        summary.stops[stop_code(s.stop) as usize] += 1;
        let left = last_deviation(
            s.initial_deviation,
            interior_samples[..s.samples].iter().map(|x| x.deviation),
        );
        summary.max_deviation = summary.max_deviation.max(left);
    }

    let len = baked_len(
        patches.len(),
        curves.len(),
        summary.curve_samples,
        summary.interior_samples,
    )
    .unwrap_or(usize::MAX);
    if w.out.len() < len {
        return Err(BakeError::OutputTooSmall { needed: len });
    }
    let mut header = [0u8; HEADER_LEN];
    header[..4].copy_from_slice(&MAGIC);
    header[4..6].copy_from_slice(&VERSION.to_le_bytes());
    header[6..8].copy_from_slice(&(HEADER_LEN as u16).to_le_bytes());
    for (at, n) in [
        (8, patches.len()),
        (12, curves.len()),
        (16, summary.curve_samples),
        (20, summary.interior_samples),
    ] {
        header[at..at + 4].copy_from_slice(&(n as u32).to_le_bytes());
    }
    header[24..28].copy_from_slice(&tolerance.to_le_bytes());
    header[28..32].copy_from_slice(&model_fingerprint(patches).to_le_bytes());
    w.put(0, &header);
    let sum = checksum(&w.out[..len]);
    w.put(36, &sum.to_le_bytes());
    summary.bytes = len;
    Ok(summary)
}
