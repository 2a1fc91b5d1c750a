//! Greedy sampling of one boundary curve.
//!
//! The curve is a patch edge in its own parameter `t` (see [`Side`]). Starting from the chord
//! between its ends, each step splits the polyline segment with the largest deviation bound
//! (see [`chord_bound`]) at the parameter where it deviates most, and records the largest bound
//! of the whole polyline *after* the insertion. Deviation is the distance between `C(t)` and the
//! segment's linear interpolant at the same `t`.
//!
//! Parameters are on the 16-bit grid of [`GridPoint`](crate::GridPoint), so a sample is the same
//! grid value for both patches that share the curve (a reversed edge reads `MAX - t`).
//!
//! Where to split a segment is found by sampling it at [`SCAN`] points and refining the best
//! one by golden-section search. The recorded list is then made non-increasing by a suffix
//! maximum, so each recorded value bounds the deviation of its prefix.

use core::fmt;

use glam::Vec3;

use crate::deviation::chord_bound;
use crate::domain::GridPoint;
use crate::math::length;
use crate::patch::{BezierPatch, Side};

/// Samples per segment when looking for its largest deviation.
const SCAN: usize = 24;
/// Golden-section steps refining the best sample.
const REFINE: usize = 24;

/// One recorded curve sample.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CurveSample {
    /// Parameter on the 16-bit grid.
    pub t: u16,
    /// Deviation bound of the polyline once this sample and all before it are in.
    pub deviation: f32,
}

/// Why sampling stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum StopReason {
    /// The deviation reached the tolerance.
    Tolerance,
    /// The sample buffer is full.
    SampleCap,
    /// The worst piece cannot be split: a curve segment spans adjacent grid values, or a patch
    /// triangle has no free grid point outside the boundary margin
    /// ([`BOUNDARY_MARGIN`](super::BOUNDARY_MARGIN)).
    Resolution,
}

/// The outcome of [`sample_curve`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CurveSampling {
    /// Samples written, in insertion order.
    pub samples: usize,
    /// Deviation of the chord alone (before any sample).
    pub initial_deviation: f32,
    /// Why it stopped.
    pub stop: StopReason,
}

/// Why a curve could not be sampled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum CurveSampleError {
    /// The tolerance is negative or not finite.
    BadTolerance,
    /// The segment scratch needs one more entry than the sample buffer.
    ScratchTooSmall {
        /// Entries needed.
        needed: usize,
    },
}

impl fmt::Display for CurveSampleError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CurveSampleError::BadTolerance => f.write_str("tolerance must be finite and >= 0"),
            CurveSampleError::ScratchTooSmall { needed } => {
                write!(f, "segment scratch needs {needed} entries")
            }
        }
    }
}

impl core::error::Error for CurveSampleError {}

/// Scratch for [`sample_curve`]: one polyline segment and its largest deviation.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CurveSegment {
    t0: u16,
    t1: u16,
    deviation: f32,
    /// Where to split (grid value strictly inside), or `None` for adjacent grid values.
    split: Option<u16>,
}

fn grid_to_unit(t: u16) -> f32 {
    t as f32 * (1.0 / GridPoint::MAX as f32)
}

/// The point of edge `side` at curve parameter `t` in `[0, 1]`.
fn point_on_edge(patch: &BezierPatch<'_>, side: Side, t: f32) -> Vec3 {
    match side {
        Side::V0 => patch.position(t, 0.0),
        Side::U1 => patch.position(1.0, t),
        Side::V1 => patch.position(t, 1.0),
        Side::U0 => patch.position(0.0, t),
    }
}

fn analyse(patch: &BezierPatch<'_>, side: Side, t0: u16, t1: u16) -> CurveSegment {
    let (a, b) = (grid_to_unit(t0), grid_to_unit(t1));
    let (pa, pb) = (point_on_edge(patch, side, a), point_on_edge(patch, side, b));
    let deviation = |t: f32| {
        let chord = pa + (pb - pa) * ((t - a) / (b - a));
        length(point_on_edge(patch, side, t) - chord)
    };
    let step = (b - a) / (SCAN + 1) as f32;
    let (mut best_t, mut best) = (a, 0.0f32);
    for k in 1..=SCAN {
        let t = a + step * k as f32;
        let d = deviation(t);
        if d > best {
            best = d;
            best_t = t;
        }
    }
    // Golden-section search around the best sample.
    let (mut lo, mut hi) = ((best_t - step).max(a), (best_t + step).min(b));
    const G: f32 = 0.618_034;
    let (mut x1, mut x2) = (hi - G * (hi - lo), lo + G * (hi - lo));
    let (mut d1, mut d2) = (deviation(x1), deviation(x2));
    for _ in 0..REFINE {
        if d1 > d2 {
            hi = x2;
            x2 = x1;
            d2 = d1;
            x1 = hi - G * (hi - lo);
            d1 = deviation(x1);
        } else {
            lo = x1;
            x1 = x2;
            d1 = d2;
            x2 = lo + G * (hi - lo);
            d2 = deviation(x2);
        }
    }
    let refined_t = if d1 > d2 { x1 } else { x2 };
    let best_t = if d1.max(d2) > best { refined_t } else { best_t };

    let split = (t1 - t0 >= 2).then(|| {
        let q = libm::floorf(best_t * GridPoint::MAX as f32 + 0.5) as u16;
        q.clamp(t0 + 1, t1 - 1)
    });
    CurveSegment {
        t0,
        t1,
        deviation: chord_bound(patch, side, a, b).bound,
        split,
    }
}

/// Samples edge `side` of `patch` greedily until the polyline's deviation is at most
/// `tolerance`, `out` is full, or the grid cannot split further.
///
/// `segments` is scratch with at least `out.len() + 1` entries.
///
/// ```
/// use spline_tess::bake::{sample_curve, CurveSample, CurveSegment, StopReason};
/// use spline_tess::{BezierPatch, Side};
///
/// // A bilinear patch whose v = 0 edge is straight: no sample is needed.
/// let flat = [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]];
/// let patch = BezierPatch::new(1, 1, &flat).unwrap();
/// let mut out = [CurveSample::default(); 8];
/// let mut scratch = [CurveSegment::default(); 9];
/// let s = sample_curve(&patch, Side::V0, 1e-3, &mut out, &mut scratch).unwrap();
/// assert_eq!((s.samples, s.stop), (0, StopReason::Tolerance));
/// ```
pub fn sample_curve(
    patch: &BezierPatch<'_>,
    side: Side,
    tolerance: f32,
    out: &mut [CurveSample],
    segments: &mut [CurveSegment],
) -> Result<CurveSampling, CurveSampleError> {
    if !(tolerance.is_finite() && tolerance >= 0.0) {
        return Err(CurveSampleError::BadTolerance);
    }
    if segments.len() < out.len() + 1 {
        return Err(CurveSampleError::ScratchTooSmall {
            needed: out.len() + 1,
        });
    }
    segments[0] = analyse(patch, side, 0, GridPoint::MAX);
    let initial_deviation = segments[0].deviation;
    let mut live = 1;
    let mut count = 0;
    let stop = loop {
        // The worst segment; ties go to the first, so the order is deterministic.
        let mut worst = 0;
        for k in 1..live {
            if segments[k].deviation > segments[worst].deviation {
                worst = k;
            }
        }
        let w = segments[worst];
        if w.deviation <= tolerance {
            break StopReason::Tolerance;
        }
        if count == out.len() {
            break StopReason::SampleCap;
        }
        let Some(t) = w.split else {
            break StopReason::Resolution;
        };
        segments[worst] = analyse(patch, side, w.t0, t);
        segments[live] = analyse(patch, side, t, w.t1);
        live += 1;
        let deviation = segments[..live]
            .iter()
            .fold(0.0f32, |m, s| m.max(s.deviation));
        out[count] = CurveSample { t, deviation };
        count += 1;
    };
    // Suffix maximum: every recorded value bounds all later polylines, so the list is
    // non-increasing and a prefix's value is an upper bound of its deviation.
    for k in (0..count.saturating_sub(1)).rev() {
        out[k].deviation = out[k].deviation.max(out[k + 1].deviation);
    }
    Ok(CurveSampling {
        samples: count,
        initial_deviation,
        stop,
    })
}
