//! Pre-sampling ("bake"): ordered samples by greedy maximum deviation, and the compact format
//! that stores them in flash.
//!
//! - [`sample_curve`] samples one boundary curve; every patch sharing it uses that one list.
//! - [`sample_patch`] samples one patch: its interior and how far into each boundary curve it
//!   reaches, starting from its corners.
//! - [`bake_model`] does both for a whole [`Model`](crate::Model), in caller scratch, straight
//!   into the bytes of the compact format, which [`BakedModel`] reads in place.
//!
//! Every recorded deviation is the largest deviation of the curve's polyline, or of the patch's
//! triangulation, once that sample and all before it are in; the lists are non-increasing, so
//! the run time takes the prefix whose last value is at or below its threshold.

mod curve;
mod format;
mod interior;
mod load;
mod model;
mod quantize;

pub use crate::deviation::{
    chord_bound, triangle_bound, triangle_screen_bound, ChordBound, PatchBounds, TriangleBound,
    LATTICE, SAMPLED_FACTORS,
};
pub use curve::{
    sample_curve, CurveSample, CurveSampleError, CurveSampling, CurveSegment, StopReason,
};
pub use format::{
    baked_size, model_fingerprint, write_rust_source, BakedCurve, BakedModel, BakedPatch,
    CurveSamples, InteriorSamples, MAGIC, VERSION,
};
pub use interior::{
    patch_metric, sample_patch, triangle_deviation, InteriorSample, InteriorSampleError,
    InteriorSampling, SideCurve, TriangleDeviation, BOUNDARY_MARGIN,
};
pub use load::{LoadError, Part};
pub(crate) use model::boundary_point;
pub use model::{
    bake_model, BakeError, BakeScratch, BakeScratchSize, BakeSettings, BakeSummary, Tolerance,
};
pub use quantize::PointBox;
