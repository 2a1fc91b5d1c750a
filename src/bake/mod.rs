//! Pre-sampling ("bake"): ordered samples by greedy maximum deviation.
//!
//! This release holds the boundary-curve sampler ([`sample_curve`]); interior sampling and the
//! compact baked format build on it.

mod curve;

pub use curve::{
    sample_curve, CurveSample, CurveSampleError, CurveSampling, CurveSegment, StopReason,
};
