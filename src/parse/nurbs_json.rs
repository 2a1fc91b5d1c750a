//! The JSON form of a single NURBS surface used by the test fixtures.
//!
//! An object with `degree_u`, `degree_v` (integers), `knots_u`, `knots_v` (arrays of numbers),
//! `control_points` (`[i][j] = [x, y, z]`, `i` along u) and optionally `weights` (`[i][j]`, all 1
//! when absent). Other fields (`source`, `expected`, ...) are skipped. This is a small JSON
//! reader for exactly that shape, not a general JSON library.

use core::fmt;

use crate::nurbs::{Direction, NurbsError, NurbsSurface};

/// What a NURBS JSON text holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct NurbsJsonSize {
    /// Knots in u.
    pub knots_u: usize,
    /// Knots in v.
    pub knots_v: usize,
    /// Control points (and weights).
    pub points: usize,
}

/// Caller storage for [`parse_nurbs_json`].
#[derive(Debug)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct NurbsJsonBuffers<'a> {
    /// Receives the u knots.
    pub knots_u: &'a mut [f32],
    /// Receives the v knots.
    pub knots_v: &'a mut [f32],
    /// Receives the control points, u-major.
    pub points: &'a mut [[f32; 3]],
    /// Receives the weights, u-major.
    pub weights: &'a mut [f32],
}

/// A NURBS JSON error, with the 1-based line where it was found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct NurbsJsonError {
    /// 1-based line number.
    pub line: usize,
    /// What went wrong.
    pub kind: NurbsJsonErrorKind,
}

/// The problems a NURBS JSON text can have.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum NurbsJsonErrorKind {
    /// The text is not JSON of the expected shape; `expected` says what should have come.
    Syntax {
        /// What the reader expected here.
        expected: &'static str,
    },
    /// A required field is absent.
    MissingField {
        /// Its name.
        field: &'static str,
    },
    /// A field appears twice.
    DuplicateField {
        /// Its name.
        field: &'static str,
    },
    /// A number does not fit its field (not a number, not finite, or not an integer degree).
    BadNumber,
    /// Rows of `control_points` or `weights` differ in length, or `weights` has another shape.
    Ragged {
        /// The field.
        field: &'static str,
    },
    /// Arrays or objects are nested too deeply to skip.
    TooDeep,
    /// A buffer is too small.
    BufferTooSmall {
        /// What the text needs.
        needed: NurbsJsonSize,
    },
    /// The fields do not form a valid surface.
    Surface(NurbsError),
}

impl fmt::Display for NurbsJsonError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "line {}: ", self.line)?;
        match self.kind {
            NurbsJsonErrorKind::Syntax { expected } => write!(f, "expected {expected}"),
            NurbsJsonErrorKind::MissingField { field } => write!(f, "missing field `{field}`"),
            NurbsJsonErrorKind::DuplicateField { field } => {
                write!(f, "field `{field}` appears twice")
            }
            NurbsJsonErrorKind::BadNumber => f.write_str("number out of range for its field"),
            NurbsJsonErrorKind::Ragged { field } => {
                write!(f, "rows of `{field}` do not match the control net")
            }
            NurbsJsonErrorKind::TooDeep => f.write_str("nesting too deep"),
            NurbsJsonErrorKind::BufferTooSmall { needed } => write!(
                f,
                "buffers too small: need {} + {} knots and {} points and weights",
                needed.knots_u, needed.knots_v, needed.points
            ),
            NurbsJsonErrorKind::Surface(e) => write!(f, "{e}"),
        }
    }
}

impl core::error::Error for NurbsJsonError {}

/// Deepest nesting `skip_value` accepts.
const MAX_DEPTH: usize = 64;

struct Cursor<'t> {
    text: &'t str,
    pos: usize,
    line: usize,
}

type Result<T> = core::result::Result<T, NurbsJsonError>;

impl<'t> Cursor<'t> {
    fn err(&self, kind: NurbsJsonErrorKind) -> NurbsJsonError {
        NurbsJsonError {
            line: self.line,
            kind,
        }
    }

    fn syntax(&self, expected: &'static str) -> NurbsJsonError {
        self.err(NurbsJsonErrorKind::Syntax { expected })
    }

    fn peek(&self) -> Option<u8> {
        self.text.as_bytes().get(self.pos).copied()
    }

    fn skip_ws(&mut self) {
        while let Some(b) = self.peek() {
            match b {
                b'\n' => self.line += 1,
                b' ' | b'\t' | b'\r' => {}
                _ => break,
            }
            self.pos += 1;
        }
    }

    /// Consumes `b` after white space, or fails saying `what` was expected.
    fn expect(&mut self, b: u8, what: &'static str) -> Result<()> {
        self.skip_ws();
        if self.peek() == Some(b) {
            self.pos += 1;
            Ok(())
        } else {
            Err(self.syntax(what))
        }
    }

    /// After white space, consumes `b` if it is next.
    fn eat(&mut self, b: u8) -> bool {
        self.skip_ws();
        if self.peek() == Some(b) {
            self.pos += 1;
            true
        } else {
            false
        }
    }

    /// A string's raw contents (escapes are kept as written).
    fn string(&mut self) -> Result<&'t str> {
        self.expect(b'"', "a string")?;
        let start = self.pos;
        loop {
            match self.peek() {
                None | Some(b'\n') => return Err(self.syntax("a closing quote")),
                Some(b'"') => break,
                Some(b'\\') => self.pos += 2,
                Some(_) => self.pos += 1,
            }
        }
        let s = self
            .text
            .get(start..self.pos)
            .ok_or(self.syntax("a string"))?;
        self.pos += 1;
        Ok(s)
    }

    /// The text of a number token.
    fn number_token(&mut self) -> Result<&'t str> {
        self.skip_ws();
        let start = self.pos;
        while let Some(b'0'..=b'9' | b'-' | b'+' | b'.' | b'e' | b'E') = self.peek() {
            self.pos += 1;
        }
        if self.pos == start {
            return Err(self.syntax("a number"));
        }
        Ok(&self.text[start..self.pos])
    }

    fn float(&mut self) -> Result<f32> {
        let token = self.number_token()?;
        match token.parse::<f32>() {
            Ok(x) if x.is_finite() => Ok(x),
            _ => Err(self.err(NurbsJsonErrorKind::BadNumber)),
        }
    }

    fn integer(&mut self) -> Result<usize> {
        let token = self.number_token()?;
        token
            .parse::<usize>()
            .map_err(|_| self.err(NurbsJsonErrorKind::BadNumber))
    }

    /// Reads `[n, n, ...]`, storing into `out` when given; returns the count.
    fn numbers(&mut self, mut out: Option<&mut [f32]>) -> Result<usize> {
        self.expect(b'[', "`[`")?;
        let mut n = 0;
        if self.eat(b']') {
            return Ok(0);
        }
        loop {
            let x = self.float()?;
            if let Some(slot) = out.as_deref_mut().and_then(|o| o.get_mut(n)) {
                *slot = x;
            }
            n += 1;
            if self.eat(b']') {
                return Ok(n);
            }
            self.expect(b',', "`,` or `]`")?;
        }
    }

    /// Reads `[[...], [...]]` where each row is read by `row`; checks rows have equal length.
    /// Returns (rows, row length).
    fn grid(
        &mut self,
        field: &'static str,
        mut row: impl FnMut(&mut Self, usize) -> Result<usize>,
    ) -> Result<(usize, usize)> {
        self.expect(b'[', "`[`")?;
        let mut rows = 0;
        let mut width = 0;
        if self.eat(b']') {
            return Ok((0, 0));
        }
        loop {
            self.skip_ws();
            let line = self.line;
            let w = row(self, rows)?;
            if rows == 0 {
                width = w;
            } else if w != width {
                return Err(NurbsJsonError {
                    line,
                    kind: NurbsJsonErrorKind::Ragged { field },
                });
            }
            rows += 1;
            if self.eat(b']') {
                return Ok((rows, width));
            }
            self.expect(b',', "`,` or `]`")?;
        }
    }

    /// Skips any JSON value.
    fn skip_value(&mut self) -> Result<()> {
        let mut depth = 0usize;
        loop {
            self.skip_ws();
            match self.peek() {
                None => return Err(self.syntax("a value")),
                Some(b'"') => {
                    self.string()?;
                }
                Some(b'[' | b'{') => {
                    depth += 1;
                    if depth > MAX_DEPTH {
                        return Err(self.err(NurbsJsonErrorKind::TooDeep));
                    }
                    self.pos += 1;
                    continue;
                }
                Some(b']' | b'}') => {
                    if depth == 0 {
                        return Err(self.syntax("a value"));
                    }
                    depth -= 1;
                    self.pos += 1;
                }
                Some(b',' | b':') if depth > 0 => {
                    self.pos += 1;
                    continue;
                }
                Some(b't' | b'f' | b'n') => {
                    let rest = &self.text[self.pos..];
                    let len = ["true", "false", "null"]
                        .iter()
                        .find(|w| rest.starts_with(*w))
                        .map(|w| w.len())
                        .ok_or(self.syntax("a value"))?;
                    self.pos += len;
                }
                Some(_) => {
                    self.number_token()?;
                }
            }
            if depth == 0 {
                return Ok(());
            }
        }
    }
}

const FIELDS: [&str; 6] = [
    "degree_u",
    "degree_v",
    "knots_u",
    "knots_v",
    "control_points",
    "weights",
];

/// What one pass found: values and the line each field started on.
#[derive(Default)]
struct Found {
    degree: [usize; 2],
    knots: [usize; 2],
    rows: usize,
    cols: usize,
    weight_shape: Option<(usize, usize)>,
    line: [Option<usize>; 6],
}

fn walk(text: &str, mut store: Option<&mut NurbsJsonBuffers<'_>>) -> Result<Found> {
    let mut c = Cursor {
        text,
        pos: 0,
        line: 1,
    };
    let mut found = Found::default();
    c.expect(b'{', "`{`")?;
    if !c.eat(b'}') {
        loop {
            c.skip_ws();
            let key_line = c.line;
            let key = c.string()?;
            c.expect(b':', "`:`")?;
            let field = FIELDS.iter().position(|f| *f == key);
            if let Some(k) = field {
                if found.line[k].is_some() {
                    return Err(c.err(NurbsJsonErrorKind::DuplicateField { field: FIELDS[k] }));
                }
                found.line[k] = Some(key_line);
            }
            match field {
                Some(k @ (0 | 1)) => found.degree[k] = c.integer()?,
                Some(k @ (2 | 3)) => {
                    let out = store.as_deref_mut().map(|s| {
                        if k == 2 {
                            &mut *s.knots_u
                        } else {
                            &mut *s.knots_v
                        }
                    });
                    found.knots[k - 2] = c.numbers(out)?;
                }
                Some(4) => {
                    let mut points = store.as_deref_mut().map(|s| &mut *s.points);
                    let mut cols_seen = 0;
                    let (rows, cols) = c.grid("control_points", |c, i| {
                        let (n, _) = c.grid("control_points", |c, j| {
                            let mut xyz = [0.0f32; 3];
                            if c.numbers(Some(&mut xyz))? != 3 {
                                return Err(c.syntax("points of three coordinates"));
                            }
                            let k = i * cols_seen.max(1) + j;
                            if let Some(slot) = points.as_deref_mut().and_then(|p| p.get_mut(k)) {
                                *slot = xyz;
                            }
                            Ok(3)
                        })?;
                        if i == 0 {
                            cols_seen = n;
                        }
                        Ok(n)
                    })?;
                    found.rows = rows;
                    found.cols = cols;
                }
                Some(_) => {
                    let mut weights = store.as_deref_mut().map(|s| &mut *s.weights);
                    let mut cols_seen = 0;
                    let shape = c.grid("weights", |c, i| {
                        // Each row is stored straight into its place when the width is known.
                        let offset = i * cols_seen;
                        let out = weights.as_deref_mut().and_then(|w| w.get_mut(offset..));
                        let n = c.numbers(out)?;
                        if i == 0 {
                            cols_seen = n;
                        }
                        Ok(n)
                    })?;
                    found.weight_shape = Some(shape);
                }
                None => c.skip_value()?,
            }
            if c.eat(b'}') {
                break;
            }
            c.expect(b',', "`,` or `}`")?;
        }
    }
    c.skip_ws();
    if c.peek().is_some() {
        return Err(c.syntax("the end of the text"));
    }
    for (k, line) in found.line.iter().enumerate().take(5) {
        if line.is_none() {
            return Err(c.err(NurbsJsonErrorKind::MissingField { field: FIELDS[k] }));
        }
    }
    if let Some(shape) = found.weight_shape {
        if shape != (found.rows, found.cols) {
            return Err(NurbsJsonError {
                line: found.line[5].unwrap_or(1),
                kind: NurbsJsonErrorKind::Ragged { field: "weights" },
            });
        }
    }
    Ok(found)
}

impl Found {
    fn size(&self) -> NurbsJsonSize {
        NurbsJsonSize {
            knots_u: self.knots[0],
            knots_v: self.knots[1],
            points: self.rows * self.cols,
        }
    }

    /// The line of the field a surface error is about.
    fn line_of(&self, e: &NurbsError) -> usize {
        let dir = |d: &Direction| match d {
            Direction::U => 0,
            Direction::V => 1,
        };
        let field = match e {
            NurbsError::DegreeOutOfRange { direction, .. } => dir(direction),
            NurbsError::TooFewKnots { direction, .. }
            | NurbsError::NonFiniteKnot { direction, .. }
            | NurbsError::DecreasingKnots { direction, .. }
            | NurbsError::NotClamped { direction }
            | NurbsError::KnotMultiplicity { direction, .. } => 2 + dir(direction),
            NurbsError::PointCount { .. }
            | NurbsError::NonFinitePoint { .. }
            | NurbsError::ExtentOverflow => 4,
            NurbsError::WeightCount { .. } | NurbsError::InvalidWeight { .. } => 5,
        };
        self.line[field].or(self.line[4]).unwrap_or(1)
    }
}

/// Validates a NURBS JSON text and counts what it holds, storing nothing.
pub fn nurbs_json_size(text: &str) -> Result<NurbsJsonSize> {
    walk(text, None).map(|f| f.size())
}

/// Parses a NURBS JSON text into the caller's buffers and validates the surface.
///
/// ```
/// use spline_tess::parse::{parse_nurbs_json, NurbsJsonBuffers};
///
/// let text = r#"{
///   "degree_u": 1, "degree_v": 1,
///   "knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1],
///   "control_points": [[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 1]]],
///   "expected": [{"u": 1, "v": 1, "p": [1, 1, 1]}]
/// }"#;
/// let (mut ku, mut kv, mut pts, mut w) = ([0.0; 8], [0.0; 8], [[0.0; 3]; 8], [0.0; 8]);
/// let buffers = NurbsJsonBuffers { knots_u: &mut ku, knots_v: &mut kv, points: &mut pts, weights: &mut w };
/// let surface = parse_nurbs_json(text, buffers).unwrap();
/// assert_eq!(surface.position(1.0, 1.0).to_array(), [1.0, 1.0, 1.0]);
/// ```
pub fn parse_nurbs_json<'a>(text: &str, buffers: NurbsJsonBuffers<'a>) -> Result<NurbsSurface<'a>> {
    let found = walk(text, None)?;
    let size = found.size();
    if buffers.knots_u.len() < size.knots_u
        || buffers.knots_v.len() < size.knots_v
        || buffers.points.len() < size.points
        || buffers.weights.len() < size.points
    {
        return Err(NurbsJsonError {
            line: 1,
            kind: NurbsJsonErrorKind::BufferTooSmall { needed: size },
        });
    }
    let mut buffers = buffers;
    walk(text, Some(&mut buffers))?;
    let NurbsJsonBuffers {
        knots_u,
        knots_v,
        points,
        weights,
    } = buffers;
    let weights: Option<&'a [f32]> = match found.weight_shape {
        Some(_) => Some(&weights[..size.points]),
        None => None,
    };
    NurbsSurface::new(
        found.degree[0],
        found.degree[1],
        &knots_u[..size.knots_u],
        &knots_v[..size.knots_v],
        &points[..size.points],
        weights,
    )
    .map_err(|e| NurbsJsonError {
        line: found.line_of(&e),
        kind: NurbsJsonErrorKind::Surface(e),
    })
}
