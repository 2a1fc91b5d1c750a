//! Exact decomposition of a NURBS surface into rational Bezier patches, one per non-empty knot
//! span rectangle, written into caller buffers.

use core::fmt;

use glam::Vec4;

use super::{NurbsSurface, ParamRect};
use crate::basis::blossom;
use crate::model::{PatchHeader, PatchSet};
use crate::MAX_DEGREE;

/// How much room a decomposition needs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct DecompositionSize {
    /// Bezier patches (and headers, and domains).
    pub patches: usize,
    /// Control points (and weights).
    pub points: usize,
}

/// Why a decomposition could not be written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum DecomposeError {
    /// A buffer is smaller than needed; nothing was written.
    BufferTooSmall {
        /// What the decomposition needs.
        needed: DecompositionSize,
    },
}

impl fmt::Display for DecomposeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DecomposeError::BufferTooSmall { needed } => write!(
                f,
                "buffers too small: need {} patches and {} control points and weights",
                needed.patches, needed.points
            ),
        }
    }
}

impl core::error::Error for DecomposeError {}

impl<'a> NurbsSurface<'a> {
    /// The room [`decompose`](Self::decompose) needs.
    pub fn decomposition_size(&self) -> DecompositionSize {
        let spans_u = spans(self.knots_u, self.degree_u(), self.count_u()).count();
        let spans_v = spans(self.knots_v, self.degree_v(), self.count_v()).count();
        let patches = spans_u * spans_v;
        DecompositionSize {
            patches,
            points: patches * (self.degree_u() + 1) * (self.degree_v() + 1),
        }
    }

    /// Writes the exact rational Bezier pieces of the surface, one per non-empty knot span
    /// rectangle, u-span major, and returns them as a [`PatchSet`]. `domains[k]` receives the
    /// parameter rectangle of piece `k`.
    ///
    /// Neighbouring pieces share their common boundary row bit for bit (it is computed once
    /// and copied), so [`Topology`](crate::Topology) finds them as shared curves.
    ///
    /// ```
    /// use spline_tess::{NurbsSurface, PatchHeader, ParamRect};
    ///
    /// let knots = [0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0]; // quadratic, two spans
    /// let points: [[f32; 3]; 16] =
    ///     core::array::from_fn(|k| [(k / 4) as f32, (k % 4) as f32, ((k * 7) % 5) as f32]);
    /// let s = NurbsSurface::new(2, 2, &knots, &knots, &points, None)?;
    /// let size = s.decomposition_size();
    /// assert_eq!((size.patches, size.points), (4, 36));
    ///
    /// let mut headers = [PatchHeader::default(); 4];
    /// let mut bez = [[0.0; 3]; 36];
    /// let mut weights = [0.0; 36];
    /// let mut domains = [ParamRect::default(); 4];
    /// let set = s.decompose(&mut headers, &mut bez, &mut weights, &mut domains).unwrap();
    /// // Piece 3 covers [0.5, 1] x [0.5, 1]; its middle is the surface at (0.75, 0.75).
    /// let mid = set.patch(3).unwrap().position(0.5, 0.5);
    /// assert!((mid - s.position(0.75, 0.75)).length() < 1e-5);
    /// # Ok::<(), spline_tess::NurbsError>(())
    /// ```
    pub fn decompose<'b>(
        &self,
        headers: &'b mut [PatchHeader],
        points: &'b mut [[f32; 3]],
        weights: &'b mut [f32],
        domains: &mut [ParamRect],
    ) -> Result<PatchSet<'b>, DecomposeError> {
        let needed = self.decomposition_size();
        if headers.len() < needed.patches
            || domains.len() < needed.patches
            || points.len() < needed.points
            || weights.len() < needed.points
        {
            return Err(DecomposeError::BufferTooSmall { needed });
        }
        let (p, q) = (self.degree_u(), self.degree_v());
        let per_patch = (p + 1) * (q + 1);
        let spans_v = spans(self.knots_v, q, self.count_v()).count();
        let mut index = 0;
        for ku in spans(self.knots_u, p, self.count_u()) {
            for kv in spans(self.knots_v, q, self.count_v()) {
                let first = index * per_patch;
                self.extract(
                    ku,
                    kv,
                    &mut points[first..first + per_patch],
                    &mut weights[first..first + per_patch],
                );
                // Share boundary rows with the pieces before, bit for bit.
                if index >= spans_v {
                    let prev = first - spans_v * per_patch;
                    for j in 0..=q {
                        points[first + j] = points[prev + p * (q + 1) + j];
                        weights[first + j] = weights[prev + p * (q + 1) + j];
                    }
                }
                if index % spans_v != 0 {
                    let prev = first - per_patch;
                    for i in 0..=p {
                        points[first + i * (q + 1)] = points[prev + i * (q + 1) + q];
                        weights[first + i * (q + 1)] = weights[prev + i * (q + 1) + q];
                    }
                }
                headers[index] = PatchHeader {
                    degree_u: p as u8,
                    degree_v: q as u8,
                    first_point: first as u32,
                };
                domains[index] = ParamRect {
                    u0: self.knots_u[ku],
                    u1: self.knots_u[ku + 1],
                    v0: self.knots_v[kv],
                    v1: self.knots_v[kv + 1],
                };
                index += 1;
            }
        }
        let n = needed.points;
        Ok(PatchSet::trusted(
            &headers[..index],
            &points[..n],
            Some(&weights[..n]),
        ))
    }

    /// The Bezier piece over span `(ku, kv)`, written into `points` / `weights` (u-major).
    fn extract(&self, ku: usize, kv: usize, points: &mut [[f32; 3]], weights: &mut [f32]) {
        let (p, q) = (self.degree_u(), self.degree_v());
        let local_u = &self.knots_u[ku + 1 - p..=ku + p];
        let local_v = &self.knots_v[kv + 1 - q..=kv + q];
        let (a_u, b_u) = (self.knots_u[ku], self.knots_u[ku + 1]);
        let (a_v, b_v) = (self.knots_v[kv], self.knots_v[kv + 1]);
        let mut args = [0.0f32; MAX_DEGREE];
        let mut work = [Vec4::ZERO; MAX_DEGREE + 1];
        let mut column = [Vec4::ZERO; MAX_DEGREE + 1];
        // The homogeneous intermediate (w x, w y, w z) / w is kept in the output itself:
        // first in u for every v row...
        for j in 0..=q {
            for i in 0..=p {
                for (r, a) in args[..p].iter_mut().enumerate() {
                    *a = if r < p - i { a_u } else { b_u };
                }
                for (m, w) in work[..=p].iter_mut().enumerate() {
                    *w = self.homogeneous(ku - p + m, kv - q + j);
                }
                let h = blossom(&mut work[..=p], local_u, &args[..p]);
                let k = i * (q + 1) + j;
                points[k] = [h.x, h.y, h.z];
                weights[k] = h.w;
            }
        }
        // ...then in v for every u row, finishing with the division by the weight.
        for i in 0..=p {
            for (j, c) in column[..=q].iter_mut().enumerate() {
                let k = i * (q + 1) + j;
                *c = Vec4::new(points[k][0], points[k][1], points[k][2], weights[k]);
            }
            for j in 0..=q {
                for (r, a) in args[..q].iter_mut().enumerate() {
                    *a = if r < q - j { a_v } else { b_v };
                }
                work[..=q].copy_from_slice(&column[..=q]);
                let h = blossom(&mut work[..=q], local_v, &args[..q]);
                let k = i * (q + 1) + j;
                points[k] = [h.x / h.w, h.y / h.w, h.z / h.w];
                weights[k] = h.w;
            }
        }
    }
}

/// Indices of the non-empty spans.
fn spans(knots: &[f32], degree: usize, count: usize) -> impl Iterator<Item = usize> + '_ {
    (degree..count).filter(move |&k| knots[k] < knots[k + 1])
}
