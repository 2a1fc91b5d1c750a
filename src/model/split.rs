//! Splitting every patch of a [`PatchSet`] into four, at the middle of its parameters.
//!
//! Smaller patches: a quarter of a patch is a model of its own, with its own square to halve
//! and its own side to share (`error_figures` measures the tessellator on split models with
//! `SPLIT`).
//!
//! Each quarter is the exact restriction of its patch (de Casteljau at `1/2` in homogeneous
//! coordinates, so a rational patch stays exact up to `f32` rounding), and boundaries stay
//! shared bit for bit: every control row of a boundary is halved by the same operations on the
//! same values whichever patch (and in whichever direction) it belongs to, and a midpoint
//! `(a + b) / 2` does not depend on the order of `a` and `b`. [`Topology`](crate::Topology)
//! therefore finds the same shared curves, and the seams between quarters besides.

use core::fmt;

use super::{PatchHeader, PatchSet, PatchSetError};
use crate::nurbs::ParamRect;
use crate::MAX_DEGREE;

/// The room [`PatchSet::split`] needs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SplitSize {
    /// Patches (and headers, and domains): four per patch.
    pub patches: usize,
    /// Control points (and weights): four per control point.
    pub points: usize,
}

/// Why a split could not be written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum SplitError {
    /// A buffer is smaller than needed; nothing was written.
    BufferTooSmall {
        /// What the split needs.
        needed: SplitSize,
    },
    /// A quarter is not a valid patch: its control points left the `f32` range (only for
    /// coordinates near `f32::MAX`).
    Patch(PatchSetError),
}

impl fmt::Display for SplitError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SplitError::BufferTooSmall { needed } => write!(
                f,
                "buffers too small: need {} patches and {} control points and weights",
                needed.patches, needed.points
            ),
            SplitError::Patch(e) => write!(f, "a quarter is not a valid patch: {e}"),
        }
    }
}

impl core::error::Error for SplitError {}

/// A control point in homogeneous coordinates: `(w x, w y, w z, w)`.
type Homogeneous = [f32; 4];

/// The middle of `a` and `b` (the same bits for `(b, a)`).
fn middle(a: Homogeneous, b: Homogeneous) -> Homogeneous {
    core::array::from_fn(|k| 0.5 * a[k] + 0.5 * b[k])
}

/// Splits the Bezier curve `c` (at most `MAX_DEGREE + 1` points) at `t = 1/2` in place: `c`
/// becomes its first half and `right` its second.
fn halve(c: &mut [Homogeneous], right: &mut [Homogeneous]) {
    let d = c.len() - 1;
    let mut work = [[0.0f32; 4]; MAX_DEGREE + 1];
    work[..=d].copy_from_slice(c);
    right[d] = work[d];
    for r in 1..=d {
        for t in 0..=d - r {
            work[t] = middle(work[t], work[t + 1]);
        }
        c[r] = work[0];
        right[d - r] = work[d - r];
    }
}

impl<'a> PatchSet<'a> {
    /// The room [`split`](Self::split) needs.
    pub fn split_size(&self) -> SplitSize {
        let points = self
            .headers
            .iter()
            .map(PatchHeader::point_count)
            .sum::<usize>();
        SplitSize {
            patches: 4 * self.headers.len(),
            points: 4 * points,
        }
    }

    /// Writes every patch as four patches, its quarters at `u = 1/2` and `v = 1/2`, and returns
    /// them as a [`PatchSet`].
    ///
    /// Each quarter is the exact restriction (de Casteljau
    /// in homogeneous coordinates, up to `f32` rounding), and shared boundaries stay equal bit
    /// for bit, so [`Topology`](crate::Topology) finds the same shared curves, and the seams
    /// between quarters besides.
    ///
    /// Quarter `4 k + 2 i + j` is patch
    /// `k` over `u` in its half `i` and `v` in its half `j`; `domains` receives that rectangle
    /// of patch `k`'s unit square. Weights are written for every point (1 for a polynomial
    /// patch); the returned set has weights only where `self` has. Its working nets (up to
    /// 8 x 8 homogeneous points, 1 KiB each) take a few KiB of stack: a step for the host or
    /// for start-up, before baking.
    ///
    /// ```
    /// use spline_tess::{ParamRect, PatchHeader, PatchSet};
    ///
    /// static HEADERS: [PatchHeader; 1] = [PatchHeader { degree_u: 1, degree_v: 1, first_point: 0 }];
    /// static POINTS: [[f32; 3]; 4] =
    ///     [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 1.0]];
    /// let set = PatchSet::new(&HEADERS, &POINTS, None)?;
    ///
    /// let size = set.split_size();
    /// assert_eq!((size.patches, size.points), (4, 16));
    /// let mut headers = [PatchHeader::default(); 4];
    /// let mut points = [[0.0; 3]; 16];
    /// let mut weights = [0.0; 16];
    /// let mut domains = [ParamRect::default(); 4];
    /// let quarters = set.split(&mut headers, &mut points, &mut weights, &mut domains)?;
    ///
    /// // Quarter 3 is u and v in [1/2, 1]: its (0, 0) is the patch's (1/2, 1/2).
    /// assert_eq!(domains[3], ParamRect { u0: 0.5, u1: 1.0, v0: 0.5, v1: 1.0 });
    /// let (whole, quarter) = (set.patch(0).unwrap(), quarters.patch(3).unwrap());
    /// assert_eq!(quarter.position(0.0, 0.0), whole.position(0.5, 0.5));
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn split<'b>(
        &self,
        headers: &'b mut [PatchHeader],
        points: &'b mut [[f32; 3]],
        weights: &'b mut [f32],
        domains: &mut [ParamRect],
    ) -> Result<PatchSet<'b>, SplitError> {
        let needed = self.split_size();
        if headers.len() < needed.patches
            || domains.len() < needed.patches
            || points.len() < needed.points
            || weights.len() < needed.points
        {
            return Err(SplitError::BufferTooSmall { needed });
        }
        let mut next = 0;
        for (k, h) in self.headers.iter().enumerate() {
            let (p, q) = (h.degree_u as usize, h.degree_v as usize);
            let first = h.first_point as usize;
            let at = |i: usize, j: usize| i * (q + 1) + j;
            // The net in homogeneous coordinates, then its halves in u.
            let mut net = [[[0.0f32; 4]; MAX_DEGREE + 1]; MAX_DEGREE + 1];
            for i in 0..=p {
                for j in 0..=q {
                    let x = self.points[first + at(i, j)];
                    let w = self.weights.map_or(1.0, |w| w[first + at(i, j)]);
                    net[i][j] = [x[0] * w, x[1] * w, x[2] * w, w];
                }
            }
            let mut upper = net;
            let mut column = [[0.0f32; 4]; MAX_DEGREE + 1];
            let mut second = [[0.0f32; 4]; MAX_DEGREE + 1];
            for j in 0..=q {
                for i in 0..=p {
                    column[i] = net[i][j];
                }
                halve(&mut column[..=p], &mut second[..=p]);
                for i in 0..=p {
                    net[i][j] = column[i];
                    upper[i][j] = second[i];
                }
            }
            for (iu, half) in [net, upper].iter().enumerate() {
                let mut lower = *half;
                let mut upper_v = *half;
                for i in 0..=p {
                    halve(&mut lower[i][..=q], &mut upper_v[i][..=q]);
                }
                for (jv, quarter) in [lower, upper_v].iter().enumerate() {
                    let index = 4 * k + 2 * iu + jv;
                    headers[index] = PatchHeader {
                        degree_u: h.degree_u,
                        degree_v: h.degree_v,
                        first_point: next as u32,
                    };
                    let (u0, v0) = (0.5 * iu as f32, 0.5 * jv as f32);
                    domains[index] = ParamRect {
                        u0,
                        u1: u0 + 0.5,
                        v0,
                        v1: v0 + 0.5,
                    };
                    for row in quarter.iter().take(p + 1) {
                        for c in row.iter().take(q + 1) {
                            points[next] = [c[0] / c[3], c[1] / c[3], c[2] / c[3]];
                            weights[next] = c[3];
                            next += 1;
                        }
                    }
                }
            }
        }
        let (headers, points, weights) = (
            &headers[..needed.patches],
            &points[..needed.points],
            &weights[..needed.points],
        );
        PatchSet::new(headers, points, self.weights.map(|_| weights)).map_err(SplitError::Patch)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A rational biquadratic and a polynomial bicubic with collapsed edge.
    fn set() -> ([PatchHeader; 2], [[f32; 3]; 25], [f32; 25]) {
        let headers = [
            PatchHeader {
                degree_u: 2,
                degree_v: 2,
                first_point: 0,
            },
            PatchHeader {
                degree_u: 3,
                degree_v: 3,
                first_point: 9,
            },
        ];
        let points = core::array::from_fn(|k| {
            let (a, b) = ((k * 7 % 5) as f32, (k * 3 % 4) as f32);
            [k as f32 * 0.25 - 1.0, a * 0.5, b * 0.3 + 0.1 * a]
        });
        let weights = core::array::from_fn(|k| 0.5 + (k % 3) as f32 * 0.4);
        (headers, points, weights)
    }

    #[test]
    fn quarters_are_the_patch_restricted() {
        let (headers, points, weights) = set();
        for rational in [true, false] {
            let set = PatchSet::new(&headers, &points, rational.then_some(&weights[..])).unwrap();
            let n = set.split_size();
            assert_eq!((n.patches, n.points), (8, 100));
            let mut h = [PatchHeader::default(); 8];
            let mut p = [[0.0; 3]; 100];
            let mut w = [0.0; 100];
            let mut d = [ParamRect::default(); 8];
            let quarters = set.split(&mut h, &mut p, &mut w, &mut d).unwrap();
            assert_eq!(quarters.weights().is_some(), rational);
            for (k, r) in d.iter().enumerate() {
                let (whole, quarter) = (set.patch(k / 4).unwrap(), quarters.patch(k).unwrap());
                for s in 0..=4 {
                    for t in 0..=4 {
                        let (s, t) = (s as f32 / 4.0, t as f32 / 4.0);
                        let a = quarter.position(s, t);
                        let b = whole.position(r.u0 + s * (r.u1 - r.u0), r.v0 + t * (r.v1 - r.v0));
                        assert!((a - b).length() < 1e-5, "{k} {s} {t}: {a} {b}");
                    }
                }
            }
        }
    }

    #[test]
    fn a_side_halves_to_the_same_bits_in_either_direction() {
        let c: [Homogeneous; 4] =
            core::array::from_fn(|k| [0.1 * k as f32 + 0.37, 1.0 / (k + 3) as f32, 2.7, 0.9]);
        let (mut a, mut a2) = (c, [[0.0; 4]; 4]);
        halve(&mut a, &mut a2);
        let mut r = c;
        r.reverse();
        let (mut b, mut b2) = (r, [[0.0; 4]; 4]);
        halve(&mut b, &mut b2);
        b.reverse();
        b2.reverse();
        assert_eq!(a, b2);
        assert_eq!(a2, b);
        // The halves meet at one point.
        assert_eq!(a[3], a2[0]);
    }

    #[test]
    fn short_buffers_are_refused() {
        let (headers, points, _) = set();
        let set = PatchSet::new(&headers, &points, None).unwrap();
        let mut h = [PatchHeader::default(); 8];
        let mut p = [[0.0; 3]; 99];
        let mut w = [0.0; 100];
        let mut d = [ParamRect::default(); 8];
        let e = set.split(&mut h, &mut p, &mut w, &mut d).unwrap_err();
        assert_eq!(
            e,
            SplitError::BufferTooSmall {
                needed: set.split_size()
            }
        );
    }
}
