//! The BPT text format of Bezier patch models (the Utah teapot's classic form).
//!
//! Line 1 holds the number of patches. Each patch is a line `du dv` (its degrees) followed by
//! `(du + 1) * (dv + 1)` lines `x y z`, which this crate reads as the u-major control net:
//! `du + 1` rows (along u) of `dv + 1` points (along v). Blank lines are ignored.

use core::fmt;

use crate::model::{PatchHeader, PatchSet};
use crate::MAX_DEGREE;

/// What a BPT text holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BptSize {
    /// Number of patches.
    pub patches: usize,
    /// Number of control points over all patches.
    pub points: usize,
}

/// A BPT parse error, with the 1-based line where it was found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BptError {
    /// 1-based line number (one past the last line for a truncated file).
    pub line: usize,
    /// What went wrong.
    pub kind: BptErrorKind,
}

/// The problems a BPT text can have.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum BptErrorKind {
    /// The first line is not a single non-negative integer.
    BadPatchCount,
    /// A patch header is not two integers `du dv`.
    BadDegrees,
    /// A degree is 0 or above [`MAX_DEGREE`].
    DegreeOutOfRange {
        /// The degree read.
        degree: usize,
    },
    /// A control point line does not hold exactly three numbers.
    BadPoint {
        /// How many values the line holds.
        values: usize,
    },
    /// A value is not a number.
    BadNumber,
    /// A coordinate is NaN or infinite.
    NonFinite,
    /// The text ends before the patches it announced.
    Truncated {
        /// Patches announced.
        expected: usize,
        /// Patches complete before the end.
        complete: usize,
    },
    /// Non-blank lines follow the last patch.
    TrailingData,
    /// The model is too large: its bounding box's diagonal overflows `f32`.
    ExtentOverflow,
    /// The header or point buffer is too small.
    BufferTooSmall {
        /// Headers needed.
        patches: usize,
        /// Points needed.
        points: usize,
    },
}

impl fmt::Display for BptError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "line {}: ", self.line)?;
        match self.kind {
            BptErrorKind::BadPatchCount => f.write_str("expected the number of patches"),
            BptErrorKind::BadDegrees => f.write_str("expected two degrees `du dv`"),
            BptErrorKind::DegreeOutOfRange { degree } => {
                write!(f, "degree {degree} is outside 1..={MAX_DEGREE}")
            }
            BptErrorKind::BadPoint { values } => {
                write!(f, "expected a point `x y z`, found {values} values")
            }
            BptErrorKind::BadNumber => f.write_str("not a number"),
            BptErrorKind::NonFinite => f.write_str("coordinate is not finite"),
            BptErrorKind::ExtentOverflow => {
                f.write_str("the model is too large: its bounding box's diagonal overflows f32")
            }
            BptErrorKind::Truncated { expected, complete } => {
                write!(f, "file ends after {complete} of {expected} patches")
            }
            BptErrorKind::TrailingData => f.write_str("unexpected data after the last patch"),
            BptErrorKind::BufferTooSmall { patches, points } => write!(
                f,
                "buffers too small: need {patches} patch headers and {points} points"
            ),
        }
    }
}

impl core::error::Error for BptError {}

/// Non-blank lines with their 1-based numbers.
struct Lines<'t> {
    inner: core::iter::Enumerate<core::str::Lines<'t>>,
    last: usize,
}

impl<'t> Lines<'t> {
    fn new(text: &'t str) -> Self {
        Lines {
            inner: text.lines().enumerate(),
            last: 0,
        }
    }

    /// Next non-blank line, or the error `kind` at the line after the last.
    fn next(&mut self, kind: BptErrorKind) -> Result<(usize, &'t str), BptError> {
        for (i, line) in self.inner.by_ref() {
            self.last = i + 1;
            if !line.trim().is_empty() {
                return Ok((i + 1, line));
            }
        }
        Err(BptError {
            line: self.last + 1,
            kind,
        })
    }
}

/// Reads up to `N` whitespace-separated values of a line; returns how many it holds.
fn values<'t, const N: usize>(line: &'t str, out: &mut [&'t str; N]) -> usize {
    let mut n = 0;
    for word in line.split_whitespace() {
        if n < N {
            out[n] = word;
        }
        n += 1;
    }
    n
}

fn walk(
    text: &str,
    mut store: Option<(&mut [PatchHeader], &mut [[f32; 3]])>,
) -> Result<BptSize, BptError> {
    let mut lines = Lines::new(text);
    let err = |line, kind| BptError { line, kind };
    let (n, first) = lines.next(BptErrorKind::BadPatchCount)?;
    let mut words = [""; 1];
    if values(first, &mut words) != 1 {
        return Err(err(n, BptErrorKind::BadPatchCount));
    }
    let patches: usize = words[0]
        .parse()
        .map_err(|_| err(n, BptErrorKind::BadPatchCount))?;
    let mut points = 0usize;
    for patch in 0..patches {
        let truncated = BptErrorKind::Truncated {
            expected: patches,
            complete: patch,
        };
        let (n, line) = lines.next(truncated)?;
        let mut words = [""; 2];
        if values(line, &mut words) != 2 {
            return Err(err(n, BptErrorKind::BadDegrees));
        }
        let mut degrees = [0usize; 2];
        for (d, w) in degrees.iter_mut().zip(words) {
            *d = w.parse().map_err(|_| err(n, BptErrorKind::BadDegrees))?;
            if !(1..=MAX_DEGREE).contains(d) {
                return Err(err(n, BptErrorKind::DegreeOutOfRange { degree: *d }));
            }
        }
        let header = PatchHeader {
            degree_u: degrees[0] as u8,
            degree_v: degrees[1] as u8,
            first_point: points as u32,
        };
        for k in 0..header.point_count() {
            let (n, line) = lines.next(truncated)?;
            let mut words = [""; 3];
            let count = values(line, &mut words);
            if count != 3 {
                return Err(err(n, BptErrorKind::BadPoint { values: count }));
            }
            let mut p = [0.0f32; 3];
            for (c, w) in p.iter_mut().zip(words) {
                *c = w.parse().map_err(|_| err(n, BptErrorKind::BadNumber))?;
                if !c.is_finite() {
                    return Err(err(n, BptErrorKind::NonFinite));
                }
            }
            if let Some((_, pts)) = store.as_mut() {
                pts[points + k] = p;
            }
        }
        if let Some((hs, _)) = store.as_mut() {
            hs[patch] = header;
        }
        points += header.point_count();
    }
    if let Ok((n, _)) = lines.next(BptErrorKind::TrailingData) {
        return Err(err(n, BptErrorKind::TrailingData));
    }
    Ok(BptSize { patches, points })
}

/// Validates a BPT text and counts its patches and points, storing nothing.
pub fn bpt_size(text: &str) -> Result<BptSize, BptError> {
    walk(text, None)
}

/// Parses a BPT text into the caller's buffers and returns the patches as a [`PatchSet`]
/// (all weights 1). On error the buffers are untouched.
///
/// ```
/// use spline_tess::parse::parse_bpt;
/// use spline_tess::PatchHeader;
///
/// let text = "1\n1 1\n0 0 0\n0 1 0\n1 0 0\n1 1 0\n";
/// let mut headers = [PatchHeader::default(); 4];
/// let mut points = [[0.0; 3]; 16];
/// let set = parse_bpt(text, &mut headers, &mut points).unwrap();
/// assert_eq!(set.len(), 1);
/// assert_eq!(set.patch(0).unwrap().position(1.0, 0.0).to_array(), [1.0, 0.0, 0.0]);
///
/// let err = parse_bpt("1\n1 1\n0 0 0\n", &mut headers, &mut points).unwrap_err();
/// assert_eq!(err.to_string(), "line 4: file ends after 0 of 1 patches");
/// ```
pub fn parse_bpt<'a>(
    text: &str,
    headers: &'a mut [PatchHeader],
    points: &'a mut [[f32; 3]],
) -> Result<PatchSet<'a>, BptError> {
    let size = walk(text, None)?;
    if headers.len() < size.patches || points.len() < size.points {
        return Err(BptError {
            line: 1,
            kind: BptErrorKind::BufferTooSmall {
                patches: size.patches,
                points: size.points,
            },
        });
    }
    walk(
        text,
        Some((&mut headers[..size.patches], &mut points[..size.points])),
    )?;
    if crate::bound::extent_overflows(&points[..size.points]) {
        return Err(BptError {
            line: 1,
            kind: BptErrorKind::ExtentOverflow,
        });
    }
    Ok(PatchSet::trusted(
        &headers[..size.patches],
        &points[..size.points],
        None,
    ))
}
