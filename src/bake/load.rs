//! Loading a baked model: [`BakedModel::from_bytes`] checks the length, magic, version and
//! checksum, then the structure (indices in range, sample ranges contiguous, deviations finite
//! and non-increasing, parameters on the curve or inside the boundary margin, each curve
//! request the side's next curve sample, point boxes and offsets that decode to finite
//! numbers), so every read afterwards is in bounds and no input makes it panic. The layout is
//! in [`format`](super::format).

use core::fmt;

use super::format::{
    baked_len, checksum, f32_at, link_from, point_box_at, stop_from, u16_at, u32_at, BakedModel,
    BOX_AT, CHECKSUM_AT, CURVE_RECORD, HEADER_LEN, INTERIOR_SAMPLE, MAGIC, VERSION,
};
use super::interior::BOUNDARY_MARGIN;
use super::quantize::MAX_OFFSET_EXPONENT;
use crate::domain::GridPoint;
use crate::model::EdgeLink;

/// The part of a baked model a [`LoadError::Malformed`] is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Part {
    /// The header.
    Header,
    /// The curve record with this index.
    Curve(usize),
    /// The patch record with this index.
    Patch(usize),
}

/// Why bytes are not a baked model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LoadError {
    /// Fewer bytes than the header, or than the header says the model has.
    Truncated {
        /// Bytes needed.
        needed: usize,
        /// Bytes given.
        found: usize,
    },
    /// More bytes than the header says the model has.
    TrailingBytes {
        /// Bytes the model has.
        expected: usize,
        /// Bytes given.
        found: usize,
    },
    /// The bytes do not start with [`MAGIC`].
    BadMagic,
    /// A format version this crate does not read.
    UnsupportedVersion {
        /// The version in the bytes.
        found: u16,
    },
    /// The checksum does not match: the bytes were changed.
    ChecksumMismatch {
        /// Checksum in the header.
        stored: u32,
        /// Checksum of the bytes.
        computed: u32,
    },
    /// The checksum matches but a record breaks the format's rules.
    Malformed(Part),
}

impl fmt::Display for LoadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LoadError::Truncated { needed, found } => {
                write!(f, "baked model truncated: {found} of {needed} bytes")
            }
            LoadError::TrailingBytes { expected, found } => {
                write!(f, "baked model has {found} bytes, expected {expected}")
            }
            LoadError::BadMagic => f.write_str("not a baked model (bad magic)"),
            LoadError::UnsupportedVersion { found } => {
                write!(
                    f,
                    "baked format version {found}, this crate reads {VERSION}"
                )
            }
            LoadError::ChecksumMismatch { stored, computed } => write!(
                f,
                "baked model corrupted: checksum {computed:#010x}, header says {stored:#010x}"
            ),
            LoadError::Malformed(part) => write!(f, "baked model malformed at {part:?}"),
        }
    }
}

impl core::error::Error for LoadError {}

/// True when `d` is a usable deviation.
fn good_deviation(d: f32) -> bool {
    d.is_finite() && d >= 0.0
}

fn non_increasing(mut deviations: impl Iterator<Item = f32>) -> bool {
    let Some(mut last) = deviations.next() else {
        return true;
    };
    if !good_deviation(last) {
        return false;
    }
    deviations.all(|d| {
        let ok = good_deviation(d) && d <= last;
        last = d;
        ok
    })
}

impl<'a> BakedModel<'a> {
    /// Reads and validates a baked model.
    pub fn from_bytes(bytes: &'a [u8]) -> Result<Self, LoadError> {
        if bytes.len() < HEADER_LEN {
            if bytes.len() >= 4 && bytes[..4] != MAGIC {
                return Err(LoadError::BadMagic);
            }
            return Err(LoadError::Truncated {
                needed: HEADER_LEN,
                found: bytes.len(),
            });
        }
        if bytes[..4] != MAGIC {
            return Err(LoadError::BadMagic);
        }
        let version = u16_at(bytes, 4);
        if version != VERSION {
            return Err(LoadError::UnsupportedVersion { found: version });
        }
        if u16_at(bytes, 6) as usize != HEADER_LEN {
            return Err(LoadError::Malformed(Part::Header));
        }
        let count = |at| u32_at(bytes, at) as usize;
        let (patches, curves, curve_samples, interior_samples) =
            (count(8), count(12), count(16), count(20));
        let expected = baked_len(patches, curves, curve_samples, interior_samples)
            .ok_or(LoadError::Malformed(Part::Header))?;
        if bytes.len() < expected {
            return Err(LoadError::Truncated {
                needed: expected,
                found: bytes.len(),
            });
        }
        if bytes.len() > expected {
            return Err(LoadError::TrailingBytes {
                expected,
                found: bytes.len(),
            });
        }
        let stored = u32_at(bytes, CHECKSUM_AT);
        let computed = checksum(bytes);
        if stored != computed {
            return Err(LoadError::ChecksumMismatch { stored, computed });
        }
        if !good_deviation(f32_at(bytes, 24)) || u32_at(bytes, 32) != 0 {
            return Err(LoadError::Malformed(Part::Header));
        }
        let model = BakedModel {
            bytes,
            patches,
            curves,
            curve_samples,
        };
        model.check_curves()?;
        model.check_patches(interior_samples)?;
        Ok(model)
    }

    fn check_curves(&self) -> Result<(), LoadError> {
        let mut next = 0usize;
        for k in 0..self.curves {
            let bad = Err(LoadError::Malformed(Part::Curve(k)));
            let r = HEADER_LEN + k * CURVE_RECORD;
            let b = self.bytes;
            let (owner, side, stop) = (u32_at(b, r) as usize, b[r + 4], b[r + 5]);
            let (count, first) = (u16_at(b, r + 6) as usize, u32_at(b, r + 8) as usize);
            if owner >= self.patches
                || side > 3
                || stop_from(stop).is_none()
                || first != next
                || !good_deviation(f32_at(b, r + 12))
            {
                return bad;
            }
            next += count;
            if next > self.curve_samples {
                return bad;
            }
            // The owner's edge on that side is this curve, forwards.
            let edge = self.patch_record(owner) + 4 * side as usize;
            if u32_at(b, edge) != k as u32 {
                return bad;
            }
            let samples = self.curve_samples_of(first, count);
            let on_curve = samples.iter().all(|s| s.t > 0 && s.t < GridPoint::MAX);
            if !on_curve || !non_increasing(samples.iter().map(|s| s.deviation)) {
                return bad;
            }
        }
        if next != self.curve_samples {
            return Err(LoadError::Malformed(Part::Header));
        }
        Ok(())
    }

    fn check_patches(&self, interior_samples: usize) -> Result<(), LoadError> {
        let mut next = 0usize;
        let inside = BOUNDARY_MARGIN..=GridPoint::MAX - BOUNDARY_MARGIN;
        for k in 0..self.patches {
            let bad = Err(LoadError::Malformed(Part::Patch(k)));
            let r = self.patch_record(k);
            let b = self.bytes;
            for side in 0..4 {
                let code = u32_at(b, r + 4 * side);
                if let EdgeLink::Curve { curve, .. } = link_from(code) {
                    if curve as usize >= self.curves {
                        return bad;
                    }
                }
            }
            let (first, count) = (u32_at(b, r + 16) as usize, u16_at(b, r + 20) as usize);
            if first != next || stop_from(b[r + 22]).is_none() || !good_deviation(f32_at(b, r + 24))
            {
                return bad;
            }
            next += count;
            if next > interior_samples {
                return bad;
            }
            let frame = point_box_at(b, r + BOX_AT);
            if !frame.is_valid() {
                return bad;
            }
            let samples = self.interior_samples_of(first, count, frame);
            if !non_increasing(samples.iter().map(|s| s.deviation)) {
                return bad;
            }
            // Every offset decodes to finite numbers.
            let step_bytes = self.interior_step_bytes(first, count);
            if step_bytes
                .chunks_exact(INTERIOR_SAMPLE)
                .any(|s| s[INTERIOR_SAMPLE - 1] as i8 > MAX_OFFSET_EXPONENT)
            {
                return bad;
            }
            // Interior samples keep the margin; a boundary step is its side's next curve sample.
            let mut requested = [0usize; 4];
            for s in samples.iter() {
                match s.requested_side() {
                    None => {
                        if !(inside.contains(&s.point.u) && inside.contains(&s.point.v)) {
                            return bad;
                        }
                    }
                    Some(side) => {
                        let EdgeLink::Curve { curve, reversed } =
                            link_from(u32_at(b, r + 4 * side.index()))
                        else {
                            return bad;
                        };
                        let c = HEADER_LEN + curve as usize * CURVE_RECORD;
                        let curve_first = u32_at(b, c + 8) as usize;
                        let curve_count = u16_at(b, c + 6) as usize;
                        let j = requested[side.index()];
                        if j >= curve_count {
                            return bad;
                        }
                        let t = self.curve_samples_of(curve_first, curve_count).get(j);
                        let expected = t.map(|t| super::model::boundary_point(side, t.t, reversed));
                        if expected != Some(s.point) {
                            return bad;
                        }
                        requested[side.index()] += 1;
                    }
                }
            }
        }
        if next != interior_samples {
            return Err(LoadError::Malformed(Part::Header));
        }
        Ok(())
    }
}
