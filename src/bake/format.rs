//! The compact baked format: bytes that can live in flash and are read in place.
//!
//! Everything is little-endian and read byte by byte, so a `static [u8; N]` needs no alignment.
//! Version 3 (version 1 recorded sampled deviations instead of bounds, and a patch's steps were
//! interior samples only; version 2 stored no surface point or offset per step):
//!
//! | bytes | content |
//! |---|---|
//! | 40 | header: magic `STBK`, version `u16`, header length `u16` (40), patches `u32`, curves `u32`, curve samples `u32`, interior samples `u32`, tolerance `f32`, model fingerprint `u32`, reserved `u32` (0), checksum `u32` |
//! | 16 per curve | owner patch `u32`, owner side `u8`, stop reason `u8`, samples `u16`, first sample `u32`, initial deviation `f32` |
//! | 52 per patch | four edge links `u32` (curve index, bit 31 set when reversed, `u32::MAX` when collapsed), first sample `u32`, samples `u16`, stop reason `u8`, Delaunay metric `u8` (u factor - 1 in the high nibble, v factor - 1 in the low one), initial deviation `f32`, the [`PointBox`] of its steps' points: minimum `3 × f32`, extent `3 × f32` |
//! | 6 per curve sample | `t` `u16`, deviation `f32` |
//! | 21 per patch step | `u` `u16`, `v` `u16`, deviation bound `f32`, surface point `3 × u16` (in the patch's box), offset mantissas `3 × i16` and exponent `i8` (see [`quantize`](super::quantize)); a point on the boundary requests the next sample of that side's curve (and is that sample's point) |
//!
//! The checksum is 32-bit FNV-1a over every byte except its own four, so any change to a
//! single byte is detected. [`BakedModel::from_bytes`] (in `load`) checks every byte's place
//! before any read, so every read here is in bounds and no input makes it panic.

use core::fmt;

use super::curve::{CurveSample, StopReason};
use super::interior::InteriorSample;
use super::quantize::{decode_offset, PointBox};
use crate::domain::{GridPoint, Metric};
use crate::model::{EdgeLink, PatchSet};
use crate::patch::Side;

/// The four bytes every baked model starts with.
pub const MAGIC: [u8; 4] = *b"STBK";
/// The format version this crate writes and reads.
pub const VERSION: u16 = 3;

pub(crate) const HEADER_LEN: usize = 40;
pub(crate) const CURVE_RECORD: usize = 16;
pub(crate) const PATCH_RECORD: usize = 52;
pub(crate) const CURVE_SAMPLE: usize = 6;
pub(crate) const INTERIOR_SAMPLE: usize = 21;
pub(super) const CHECKSUM_AT: usize = 36;
const COLLAPSED: u32 = u32::MAX;
const REVERSED: u32 = 1 << 31;

/// 32-bit FNV-1a, continuing from `hash`.
pub(crate) fn fnv1a(mut hash: u32, bytes: &[u8]) -> u32 {
    for &b in bytes {
        hash = (hash ^ b as u32).wrapping_mul(0x0100_0193);
    }
    hash
}

pub(crate) const FNV_OFFSET: u32 = 0x811c_9dc5;

/// The checksum of a baked model's bytes (all but the checksum field).
pub(crate) fn checksum(bytes: &[u8]) -> u32 {
    let h = fnv1a(FNV_OFFSET, &bytes[..CHECKSUM_AT]);
    fnv1a(h, &bytes[CHECKSUM_AT + 4..])
}

/// A fingerprint of a patch set's degrees, control points and weights (FNV-1a of their bits),
/// stored in the baked model so it can be checked against the model it is used with.
pub fn model_fingerprint(patches: &PatchSet<'_>) -> u32 {
    let mut h = fnv1a(FNV_OFFSET, &(patches.len() as u32).to_le_bytes());
    for patch in patches.iter() {
        h = fnv1a(h, &[patch.degree_u() as u8, patch.degree_v() as u8]);
        for p in patch.points() {
            for c in p {
                h = fnv1a(h, &c.to_bits().to_le_bytes());
            }
        }
        match patch.weights() {
            Some(w) => {
                for x in w {
                    h = fnv1a(h, &x.to_bits().to_le_bytes());
                }
            }
            None => h = fnv1a(h, &[0xff]),
        }
    }
    h
}

pub(crate) fn u16_at(b: &[u8], at: usize) -> u16 {
    match b.get(at..at + 2) {
        Some(&[x, y]) => u16::from_le_bytes([x, y]),
        _ => 0,
    }
}

pub(crate) fn u32_at(b: &[u8], at: usize) -> u32 {
    match b.get(at..at + 4) {
        Some(&[x, y, z, w]) => u32::from_le_bytes([x, y, z, w]),
        _ => 0,
    }
}

pub(crate) fn f32_at(b: &[u8], at: usize) -> f32 {
    f32::from_bits(u32_at(b, at))
}

/// Offset of a patch record's [`PointBox`]: minimum, then extent.
pub(crate) const BOX_AT: usize = 28;

/// The [`PointBox`] stored at `at`.
pub(crate) fn point_box_at(b: &[u8], at: usize) -> PointBox {
    PointBox {
        min: [0, 1, 2].map(|i| f32_at(b, at + 4 * i)),
        extent: [0, 1, 2].map(|i| f32_at(b, at + 12 + 4 * i)),
    }
}

/// Writes `sample`'s record into `out` (`INTERIOR_SAMPLE` bytes), its point in `frame`.
pub(crate) fn put_step(out: &mut [u8], sample: &InteriorSample, frame: &PointBox) {
    let (m, e) = super::quantize::encode_offset(sample.offset);
    let q = frame.encode(sample.surface);
    let mut at = 0;
    let mut put = |bytes: &[u8]| {
        if let Some(dst) = out.get_mut(at..at + bytes.len()) {
            dst.copy_from_slice(bytes);
        }
        at += bytes.len();
    };
    put(&sample.point.u.to_le_bytes());
    put(&sample.point.v.to_le_bytes());
    put(&sample.deviation.to_le_bytes());
    for x in q {
        put(&x.to_le_bytes());
    }
    for x in m {
        put(&x.to_le_bytes());
    }
    put(&[e as u8]);
}

pub(crate) fn stop_code(stop: StopReason) -> u8 {
    match stop {
        StopReason::Tolerance => 0,
        StopReason::SampleCap => 1,
        StopReason::Resolution => 2,
    }
}

pub(super) fn stop_from(code: u8) -> Option<StopReason> {
    match code {
        0 => Some(StopReason::Tolerance),
        1 => Some(StopReason::SampleCap),
        2 => Some(StopReason::Resolution),
        _ => None,
    }
}

pub(crate) fn metric_code(m: Metric) -> u8 {
    ((m.u() - 1) << 4) | (m.v() - 1)
}

fn metric_from(code: u8) -> Metric {
    Metric::new((code >> 4) + 1, (code & 15) + 1)
}

pub(crate) fn link_code(link: EdgeLink) -> u32 {
    match link {
        EdgeLink::Collapsed => COLLAPSED,
        EdgeLink::Curve { curve, reversed } => curve | if reversed { REVERSED } else { 0 },
    }
}

pub(super) fn link_from(code: u32) -> EdgeLink {
    if code == COLLAPSED {
        EdgeLink::Collapsed
    } else {
        EdgeLink::Curve {
            curve: code & !REVERSED,
            reversed: code & REVERSED != 0,
        }
    }
}

/// The byte length of a model with these counts, or `None` if it does not fit in `usize`
/// ([`baked_size`] saturated: no buffer is `usize::MAX` bytes long).
pub(crate) fn baked_len(
    patches: usize,
    curves: usize,
    curve_samples: usize,
    interior_samples: usize,
) -> Option<usize> {
    let len = baked_size(patches, curves, curve_samples, interior_samples);
    (len != usize::MAX).then_some(len)
}

/// The byte length of a baked model with these counts (saturating at `usize::MAX`): room to
/// give [`bake_model`](super::bake_model), e.g. for the largest bake a set of caps allows.
///
/// ```
/// use spline_tess::bake::baked_size;
///
/// // One patch, four curves of at most 32 samples, at most 128 interior samples (the patch's
/// // steps also request each curve sample).
/// const OUT: usize = baked_size(1, 4, 4 * 32, 128 + 4 * 32);
/// let out = [0u8; OUT];
/// assert_eq!(out.len(), 40 + 4 * 16 + 52 + 4 * 32 * 6 + 256 * 21);
/// ```
pub const fn baked_size(
    patches: usize,
    curves: usize,
    curve_samples: usize,
    steps: usize,
) -> usize {
    HEADER_LEN
        .saturating_add(curves.saturating_mul(CURVE_RECORD))
        .saturating_add(patches.saturating_mul(PATCH_RECORD))
        .saturating_add(curve_samples.saturating_mul(CURVE_SAMPLE))
        .saturating_add(steps.saturating_mul(INTERIOR_SAMPLE))
}

/// A baked model, read in place from its bytes (e.g. a `static` in flash).
///
/// ```
/// use spline_tess::bake::{BakedModel, LoadError};
///
/// assert_eq!(BakedModel::from_bytes(b"STBK"), Err(LoadError::Truncated { needed: 40, found: 4 }));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BakedModel<'a> {
    pub(super) bytes: &'a [u8],
    pub(super) patches: usize,
    pub(super) curves: usize,
    pub(super) curve_samples: usize,
}

/// One baked boundary curve.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BakedCurve<'a> {
    /// The patch whose edge defines the curve and its direction.
    pub patch: u32,
    /// That patch's side.
    pub side: Side,
    /// Why sampling stopped.
    pub stop: StopReason,
    /// Deviation of the chord alone.
    pub initial_deviation: f32,
    /// The samples, in insertion order.
    pub samples: CurveSamples<'a>,
}

/// One baked patch.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BakedPatch<'a> {
    /// Which curve each side is, in [`Side::ALL`] order.
    pub edges: [EdgeLink; 4],
    /// Why interior sampling stopped.
    pub stop: StopReason,
    /// Deviation with the corners and every curve sample, before any interior sample.
    pub initial_deviation: f32,
    /// The Delaunay metric of the patch's domain mesh (the bake's and the run time's).
    pub metric: Metric,
    /// The interior samples, in insertion order.
    pub samples: InteriorSamples<'a>,
}

/// A curve's samples, decoded on access.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CurveSamples<'a> {
    bytes: &'a [u8],
}

/// A patch's interior samples, decoded on access.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct InteriorSamples<'a> {
    bytes: &'a [u8],
    frame: PointBox,
}

impl<'a> CurveSamples<'a> {
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.bytes.len() / CURVE_SAMPLE
    }

    /// True when there are none.
    pub fn is_empty(&self) -> bool {
        self.bytes.is_empty()
    }

    /// Sample `k`.
    pub fn get(&self, k: usize) -> Option<CurveSample> {
        let at = k.checked_mul(CURVE_SAMPLE)?;
        self.bytes.get(at..at + CURVE_SAMPLE).map(|b| CurveSample {
            t: u16_at(b, 0),
            deviation: f32_at(b, 2),
        })
    }

    /// The samples in order.
    pub fn iter(&self) -> impl Iterator<Item = CurveSample> + 'a {
        let s = *self;
        (0..s.len()).filter_map(move |k| s.get(k))
    }
}

impl<'a> InteriorSamples<'a> {
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.bytes.len() / INTERIOR_SAMPLE
    }

    /// True when there are none.
    pub fn is_empty(&self) -> bool {
        self.bytes.is_empty()
    }

    /// Sample `k`.
    pub fn get(&self, k: usize) -> Option<InteriorSample> {
        let at = k.checked_mul(INTERIOR_SAMPLE)?;
        self.bytes
            .get(at..at + INTERIOR_SAMPLE)
            .map(|b| InteriorSample {
                point: GridPoint::new(u16_at(b, 0), u16_at(b, 2)),
                deviation: f32_at(b, 4),
                surface: self.frame.decode([0, 1, 2].map(|i| u16_at(b, 8 + 2 * i))),
                offset: decode_offset([0, 1, 2].map(|i| u16_at(b, 14 + 2 * i) as i16), b[20] as i8),
            })
    }

    /// Sample `k`'s recorded bound ([`InteriorSample::deviation`]) alone, without decoding
    /// the rest (what the prefix search reads).
    pub fn bound(&self, k: usize) -> Option<f32> {
        let at = k.checked_mul(INTERIOR_SAMPLE)?;
        self.bytes
            .get(at..at + INTERIOR_SAMPLE)
            .map(|b| f32_at(b, 4))
    }

    /// The box the samples' surface points are stored in.
    pub fn point_box(&self) -> PointBox {
        self.frame
    }

    /// The samples in order.
    pub fn iter(&self) -> impl Iterator<Item = InteriorSample> + 'a {
        let s = *self;
        (0..s.len()).filter_map(move |k| s.get(k))
    }
}

impl<'a> BakedModel<'a> {
    pub(super) fn patch_record(&self, k: usize) -> usize {
        HEADER_LEN + self.curves * CURVE_RECORD + k * PATCH_RECORD
    }

    pub(super) fn curve_samples_of(&self, first: usize, count: usize) -> CurveSamples<'a> {
        let start = self.patch_record(self.patches) + first * CURVE_SAMPLE;
        CurveSamples {
            bytes: self
                .bytes
                .get(start..start + count * CURVE_SAMPLE)
                .unwrap_or_default(),
        }
    }

    pub(super) fn interior_samples_of(
        &self,
        first: usize,
        count: usize,
        frame: PointBox,
    ) -> InteriorSamples<'a> {
        let start = self.patch_record(self.patches)
            + self.curve_samples * CURVE_SAMPLE
            + first * INTERIOR_SAMPLE;
        InteriorSamples {
            bytes: self
                .bytes
                .get(start..start + count * INTERIOR_SAMPLE)
                .unwrap_or_default(),
            frame,
        }
    }

    /// The raw step records `first..first + count` (empty when out of range).
    pub(super) fn interior_step_bytes(&self, first: usize, count: usize) -> &'a [u8] {
        self.interior_samples_of(first, count, PointBox::default())
            .bytes
    }

    /// The bytes, as given to [`BakedModel::from_bytes`].
    pub fn as_bytes(&self) -> &'a [u8] {
        self.bytes
    }

    /// Number of patches.
    pub fn patch_count(&self) -> usize {
        self.patches
    }

    /// Number of boundary curves.
    pub fn curve_count(&self) -> usize {
        self.curves
    }

    /// Total curve samples.
    pub fn curve_sample_count(&self) -> usize {
        self.curve_samples
    }

    /// Total interior samples.
    pub fn interior_sample_count(&self) -> usize {
        u32_at(self.bytes, 20) as usize
    }

    /// The object-space tolerance the model was baked to.
    pub fn tolerance(&self) -> f32 {
        f32_at(self.bytes, 24)
    }

    /// The [`model_fingerprint`] of the patches it was baked from.
    pub fn fingerprint(&self) -> u32 {
        u32_at(self.bytes, 28)
    }

    /// True when `patches` are the patches this model was baked from (same count and
    /// fingerprint).
    pub fn matches(&self, patches: &PatchSet<'_>) -> bool {
        patches.len() == self.patches && model_fingerprint(patches) == self.fingerprint()
    }

    /// Curve `k`.
    pub fn curve(&self, k: usize) -> Option<BakedCurve<'a>> {
        if k >= self.curves {
            return None;
        }
        let r = HEADER_LEN + k * CURVE_RECORD;
        let b = self.bytes;
        Some(BakedCurve {
            patch: u32_at(b, r),
            side: Side::ALL[(b[r + 4] & 3) as usize],
            stop: stop_from(b[r + 5]).unwrap_or(StopReason::Tolerance),
            initial_deviation: f32_at(b, r + 12),
            samples: self.curve_samples_of(u32_at(b, r + 8) as usize, u16_at(b, r + 6) as usize),
        })
    }

    /// Patch `k`.
    pub fn patch(&self, k: usize) -> Option<BakedPatch<'a>> {
        let edges = self.patch_edges(k)?;
        let r = self.patch_record(k);
        let b = self.bytes;
        Some(BakedPatch {
            edges,
            stop: stop_from(b[r + 22]).unwrap_or(StopReason::Tolerance),
            initial_deviation: f32_at(b, r + 24),
            metric: metric_from(b[r + 23]),
            samples: self.interior_samples_of(
                u32_at(b, r + 16) as usize,
                u16_at(b, r + 20) as usize,
                point_box_at(b, r + BOX_AT),
            ),
        })
    }

    /// Patch `k`'s sides ([`BakedPatch::edges`]) alone: what the run time's frequent walks
    /// over the patches read, without the rest of its record.
    pub fn patch_edges(&self, k: usize) -> Option<[EdgeLink; 4]> {
        if k >= self.patches {
            return None;
        }
        let r = self.patch_record(k);
        Some([0, 1, 2, 3].map(|s| link_from(u32_at(self.bytes, r + 4 * s))))
    }
}

/// Writes `bytes` as Rust source: a `pub static NAME: [u8; N]` that
/// [`BakedModel::from_bytes`] reads from flash.
///
/// ```
/// let mut src = String::new();
/// spline_tess::bake::write_rust_source(&mut src, "BAKED", &[1, 2, 3]).unwrap();
/// assert!(src.contains("pub static BAKED: [u8; 3] = [\n    0x01, 0x02, 0x03,\n];"));
/// ```
pub fn write_rust_source(w: &mut impl fmt::Write, name: &str, bytes: &[u8]) -> fmt::Result {
    writeln!(
        w,
        "// A baked model in the spline-tess format, version {VERSION}: load it with\n\
         // `spline_tess::bake::BakedModel::from_bytes(&{name})`."
    )?;
    writeln!(w, "pub static {name}: [u8; {}] = [", bytes.len())?;
    for row in bytes.chunks(16) {
        w.write_str("   ")?;
        for b in row {
            write!(w, " {b:#04x},")?;
        }
        w.write_str("\n")?;
    }
    w.write_str("];\n")
}
