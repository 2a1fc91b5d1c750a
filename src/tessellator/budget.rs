//! A frame fitted to a triangle budget: the smallest tolerance whose mesh fits.
//!
//! A frame's mesh at a coarser tolerance is a subset of its mesh at a finer one (every
//! triangle over the coarser tolerance is over the finer one, and the coarsest conforming mesh
//! of the finer tolerance is conforming and within the coarser one), so its triangle count
//! never grows with the tolerance. The fit brackets the budget by doubling or halving the
//! view's tolerance, then halves the bracket (in ratio) until it is within 0.1%: about a dozen
//! frames. The frame it leaves is the one at the fitted tolerance, and it reports what it
//! honours: [`BudgetFit::bound`] is its [`FrameStats::worst_bound`], above the tolerance
//! only where the pool of vertices below the bake ran short.

use core::fmt;

use super::select::{FrameStats, Tessellator};
use crate::view::View;

/// What [`Tessellator::update_to_budget`] found.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BudgetFit {
    /// The smallest tolerance (within 0.1%) whose mesh fits, in the view's units.
    pub tolerance: f32,
    /// The bound the frame honours, in the view's units (see the module docs).
    pub bound: f32,
    /// The frame's figures.
    pub stats: FrameStats,
    /// True when a tolerance a millionth of the view's still fits, or a finer tolerance met a
    /// full pool below the bake: no finer one was tried.
    pub exhausted: bool,
}

/// Why no tolerance fits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum BudgetError {
    /// Even the patches' squares exceed the budget.
    TooSmall {
        /// The fewest triangles this view can have.
        minimum: usize,
    },
    /// The view's tolerance is not a positive finite number.
    BadTolerance,
}

impl fmt::Display for BudgetError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BudgetError::TooSmall { minimum } => {
                write!(f, "the budget is below the fewest triangles, {minimum}")
            }
            BudgetError::BadTolerance => write!(f, "the tolerance is not positive"),
        }
    }
}

impl core::error::Error for BudgetError {}

impl Tessellator<'_, '_> {
    /// Fits `budget` triangles for `view` (its tolerance is where the search starts): updates
    /// to the smallest tolerance, within 0.1%, whose mesh has at most `budget` triangles.
    ///
    /// ```
    /// # use spline_tess::bake::{bake_hierarchy, BakeBuffers, BakeScratch, BakeSettings};
    /// # use spline_tess::tessellator::{Hierarchy, HierarchyNode, HierarchyPatch, HierarchyVertex,
    /// #     StackSlot, PoolSlot, Tessellator};
    /// # use spline_tess::{BoundaryCurve, EdgeLink, Model, PatchHeader, PatchSet, View};
    /// // A bicubic bump, baked.
    /// let mut points = [[0.0f32; 3]; 16];
    /// for (k, p) in points.iter_mut().enumerate() {
    ///     let (i, j) = (k / 4, k % 4);
    ///     let z = if (1..3).contains(&i) && (1..3).contains(&j) { 1.0 } else { 0.0 };
    ///     *p = [i as f32, j as f32, z];
    /// }
    /// let headers = [PatchHeader { degree_u: 3, degree_v: 3, first_point: 0 }];
    /// let patches = PatchSet::new(&headers, &points, None).unwrap();
    /// let (mut edges, mut curves) = ([[EdgeLink::Collapsed; 4]], [BoundaryCurve::default(); 4]);
    /// let model = Model::build(patches, &mut edges, &mut curves).unwrap();
    /// let mut nodes = vec![HierarchyNode::default(); 4096];
    /// let mut vertices = vec![HierarchyVertex::default(); 2048];
    /// let mut records = [HierarchyPatch::default()];
    /// let mut scratch = vec![BakeScratch::default(); 4096];
    /// let buffers = BakeBuffers {
    ///     nodes: &mut nodes,
    ///     vertices: &mut vertices,
    ///     patches: &mut records,
    ///     scratch: &mut scratch,
    /// };
    /// let size = bake_hierarchy(&model, &BakeSettings::default(), buffers).unwrap();
    /// let tree = Hierarchy::new(patches, &nodes[..size.nodes], &vertices[..size.vertices], &records)
    ///     .unwrap();
    ///
    /// // At most 100 triangles, as fine as that allows.
    /// let (mut bits, mut stack) = (vec![0; tree.bit_words()], [StackSlot::default(); 64]);
    /// let mut pool = vec![PoolSlot::default(); 256];
    /// let mut selection = Tessellator::from_slices(tree, &mut bits, &mut stack, &mut pool).unwrap();
    /// let fit = selection.update_to_budget(&View::Object { tolerance: 1e-3 }, 100).unwrap();
    /// assert!(fit.stats.triangles <= 100);
    /// assert!(fit.bound <= fit.tolerance);
    /// # Ok::<(), spline_tess::tessellator::BudgetError>(())
    /// ```
    pub fn update_to_budget(
        &mut self,
        view: &View,
        budget: usize,
    ) -> Result<BudgetFit, BudgetError> {
        let start = view.tolerance();
        if !(start > 0.0 && start.is_finite()) {
            return Err(BudgetError::BadTolerance);
        }
        let count = |s: &mut Self, t: f32| s.select(&view.with_tolerance(t)).triangles;
        // A frame left over (its pool below the bake full) is as fine as finer tolerances get.
        let saturated = |s: &Self| s.stats().left_over > 0;
        let coarsest = count(self, f32::MAX);
        if coarsest > budget {
            return Err(BudgetError::TooSmall { minimum: coarsest });
        }
        // Bracket: `lo` over the budget (or the floor), `hi` within it.
        let (mut lo, mut hi) = (start, start);
        if count(self, start) <= budget {
            loop {
                lo *= 0.5;
                if lo < start * 1e-6 || saturated(self) {
                    let stats = self.select(&view.with_tolerance(hi));
                    return Ok(BudgetFit {
                        tolerance: hi,
                        bound: stats.worst_bound,
                        stats,
                        exhausted: true,
                    });
                }
                if count(self, lo) > budget {
                    break;
                }
                hi = lo;
            }
        } else {
            loop {
                hi *= 2.0;
                if !hi.is_finite() || count(self, hi) <= budget {
                    break;
                }
                lo = hi;
            }
            if !hi.is_finite() {
                hi = f32::MAX;
            }
        }
        while hi > lo * 1.001 {
            let mid = crate::math::sqrt(lo) * crate::math::sqrt(hi);
            if !(mid > lo && mid < hi) {
                break;
            }
            if count(self, mid) <= budget {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        let stats = self.select(&view.with_tolerance(hi));
        Ok(BudgetFit {
            tolerance: hi,
            bound: stats.worst_bound,
            stats,
            exhausted: false,
        })
    }
}
