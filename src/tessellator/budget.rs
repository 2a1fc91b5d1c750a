//! Budget mode: the smallest tolerance whose mesh fits a triangle count.
//!
//! The count is predicted exactly from the prefix lengths, without touching a mesh: a
//! triangulation of the square with `n` interior and `b` boundary vertices (corners included)
//! has `2n + b - 2` triangles, and each side without samples whose two corners are one point (a
//! collapsed edge, or a closed loop) loses the one triangle that has both corners, which is
//! flat. Prefix lengths only grow as the tolerance shrinks, so the count is monotone and
//! a bisection on the tolerance (in ratio, to 0.1%) finds the smallest one that fits. Budget
//! frames are not refined: the mesh is the samples' triangulation, so the prediction is the
//! count written.
//!
//! The fit keeps its word: [`BudgetFit::bound`] is the frame's computed error bound (see
//! [`crate::deviation`]), never less than what the mesh can deviate. Where the samples reach
//! the fitted tolerance it is at most that tolerance; where they run out first (a bake that
//! stops short, a step cap, or curve samples that a neighbour asked for), it is the larger,
//! true bound, and the tolerance is not claimed.

use crate::domain::DomainIndex;
use core::fmt;

use super::select::{move_requests, prefix};
use super::{FrameStats, Tessellator, UpdateError};
use crate::model::EdgeLink;
use crate::view::View;

/// The result of fitting a budget.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BudgetFit {
    /// The smallest tolerance (within 0.1%) whose mesh fits, in the view's units.
    pub tolerance: f32,
    /// The error bound the frame honours, in the view's units: the largest computed bound of
    /// its triangles over their thresholds, times the tolerance. At most `tolerance` when the
    /// samples reach it; larger, and true, when they do not.
    pub bound: f32,
    /// Triangles of that mesh.
    pub triangles: usize,
    /// True when every sample is in and the budget still holds: no smaller tolerance
    /// changes the mesh.
    pub exhausted: bool,
}

/// Why no tolerance fits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum BudgetError {
    /// Even with no samples (two triangles per patch) the mesh exceeds the budget.
    TooSmall {
        /// The smallest possible triangle count for this view.
        minimum: usize,
    },
    /// Updating to the fitted tolerance failed.
    Update(UpdateError),
}

impl fmt::Display for BudgetError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BudgetError::TooSmall { minimum } => {
                write!(
                    f,
                    "budget too small: this view needs at least {minimum} triangles"
                )
            }
            BudgetError::Update(e) => write!(f, "update failed: {e}"),
        }
    }
}

impl core::error::Error for BudgetError {}

/// The domain corners at the ends of each side, in [`Side::ALL`](crate::Side::ALL) order.
const SIDE_CORNERS: [(usize, usize); 4] = [(0, 1), (1, 2), (3, 2), (0, 3)];

impl<Ix: DomainIndex> Tessellator<'_, '_, Ix> {
    /// Triangles of the unrefined mesh for `view`, predicted from prefix lengths alone.
    pub fn predict_triangles(&mut self, view: &View) -> usize {
        let baked = self.baked;
        let tol = view.tolerance();
        for c in self.storage.curves[..baked.curve_count()].iter_mut() {
            c.predict = 0;
        }
        // The prefix of a patch for `view` and its requests per side.
        let target = |this: &Self, p: usize| -> Option<(usize, [u16; 4])> {
            let slot = this.storage.patches[p];
            let fit = this.patch_threshold(p, view, tol);
            let c = fit.c;
            let bp = baked.patch(p)?;
            if fit.culled {
                return None;
            }
            let steps = bp.samples;
            let n = prefix(
                bp.initial_deviation,
                steps.len(),
                |i| steps.bound(i).unwrap_or(0.0),
                c,
            )
            .min(slot.step_cap as usize);
            let mut requests = [0u16; 4];
            move_requests(&bp, &mut requests, 0, n);
            Some((n, requests))
        };
        for p in 0..baked.patch_count() {
            let (Some((_, requests)), Some(bp)) = (target(self, p), baked.patch(p)) else {
                continue;
            };
            for (s, link) in bp.edges.into_iter().enumerate() {
                if let EdgeLink::Curve { curve, .. } = link {
                    let c = &mut self.storage.curves[curve as usize].predict;
                    *c = (*c).max(requests[s]);
                }
            }
        }
        let mut total = 0usize;
        for p in 0..baked.patch_count() {
            let (Some((n, requests)), Some(bp)) = (target(self, p), baked.patch(p)) else {
                continue;
            };
            let slot = self.storage.patches[p];
            let interior = n - requests.iter().map(|&r| r as usize).sum::<usize>();
            let mut b = 4usize;
            let mut dropped = 0usize;
            for (s, link) in bp.edges.into_iter().enumerate() {
                let on_side = match link {
                    EdgeLink::Curve { curve, .. } => {
                        self.storage.curves[curve as usize].predict as usize
                    }
                    EdgeLink::Collapsed => 0,
                };
                b += on_side;
                // A side without samples whose corners are one point (collapsed, or a
                // closed loop) gives one flat triangle, which is dropped.
                let (x, y) = SIDE_CORNERS[s];
                if on_side == 0 && slot.nodes[x] == slot.nodes[y] {
                    dropped += 1;
                }
            }
            total += (2 * interior + b - 2).saturating_sub(dropped);
        }
        total
    }

    /// The smallest tolerance, for `view`'s camera, whose unrefined mesh has at most
    /// `max_triangles` triangles (the view's own tolerance is ignored), with the triangle
    /// count and whether every sample is in; the bound is filled in by the update.
    fn fit_budget(&mut self, view: &View, max_triangles: usize) -> Result<BudgetFit, BudgetError> {
        let count = |t: f32, s: &mut Self| s.predict_triangles(&view.with_tolerance(t));
        let (mut lo, mut hi) = (f32::MIN_POSITIVE, f32::MAX);
        let minimum = count(hi, self);
        if minimum > max_triangles {
            return Err(BudgetError::TooSmall { minimum });
        }
        let full = count(lo, self);
        if full <= max_triangles {
            // Everything fits: the largest tolerance that still takes every sample.
            while hi > lo * 1.001 {
                let mid = geometric_mean(lo, hi);
                if count(mid, self) == full {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            return Ok(BudgetFit {
                tolerance: lo,
                bound: f32::INFINITY,
                triangles: full,
                exhausted: true,
            });
        }
        // `lo` does not fit, `hi` does.
        let mut fits = minimum;
        while hi > lo * 1.001 {
            let mid = geometric_mean(lo, hi);
            let c = count(mid, self);
            if c <= max_triangles {
                hi = mid;
                fits = c;
            } else {
                lo = mid;
            }
        }
        Ok(BudgetFit {
            tolerance: hi,
            bound: f32::INFINITY,
            triangles: fits,
            exhausted: false,
        })
    }

    /// Fits the budget for `view`'s camera (its own tolerance is ignored) and updates to the
    /// smallest tolerance whose unrefined mesh has at most `max_triangles` triangles.
    ///
    /// The returned [`BudgetFit::bound`] is what the frame honours; it equals the frame's
    /// [`FrameStats::max_predicted_error`] and exceeds [`BudgetFit::tolerance`] only where the
    /// samples run out.
    pub fn update_to_budget(
        &mut self,
        view: &View,
        max_triangles: usize,
    ) -> Result<(FrameStats, BudgetFit), BudgetError> {
        let mut fit = self.fit_budget(view, max_triangles)?;
        let stats = self
            .update_unrefined(&view.with_tolerance(fit.tolerance))
            .map_err(BudgetError::Update)?;
        fit.bound = stats.max_predicted_error;
        Ok((stats, fit))
    }
}

/// The geometric mean of two positive numbers, computed without overflow.
fn geometric_mean(a: f32, b: f32) -> f32 {
    crate::math::sqrt(a) * crate::math::sqrt(b)
}
