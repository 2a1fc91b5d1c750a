//! Conservative bounds of control nets.
//!
//! With positive weights a rational patch lies in the convex hull of its control points, so
//! any bound of the points bounds the surface.

use glam::Vec3;

use crate::math::{length, max};

/// Axis-aligned box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Smallest corner.
    pub min: Vec3,
    /// Largest corner.
    pub max: Vec3,
}

impl Aabb {
    /// The box of a set of points; `None` for an empty set.
    pub fn of_points(points: &[[f32; 3]]) -> Option<Self> {
        let (first, rest) = points.split_first()?;
        let mut b = Aabb {
            min: Vec3::from_array(*first),
            max: Vec3::from_array(*first),
        };
        for p in rest {
            b = b.including(Vec3::from_array(*p));
        }
        Some(b)
    }

    /// This box grown to contain `p`.
    pub fn including(self, p: Vec3) -> Self {
        Aabb {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    /// The smallest box containing both.
    pub fn union(self, other: Aabb) -> Self {
        Aabb {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    /// Length of the diagonal.
    pub fn diagonal(&self) -> f32 {
        length(self.max - self.min)
    }

    /// Centre of the box.
    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }
}

/// Sphere containing a set of points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundingSphere {
    /// Centre.
    pub center: Vec3,
    /// Radius (never smaller than the distance from the centre to any bounded point).
    pub radius: f32,
}

impl BoundingSphere {
    /// A sphere around the box's centre reaching every point; `None` for an empty set.
    pub fn of_points(points: &[[f32; 3]]) -> Option<Self> {
        let center = Aabb::of_points(points)?.center();
        let mut r2: f32 = 0.0;
        for p in points {
            let d = Vec3::from_array(*p) - center;
            r2 = max(r2, d.dot(d));
        }
        // One ulp of slack so rounding in the square root never makes it too small.
        let radius = crate::math::sqrt(r2) * (1.0 + 2.0 * f32::EPSILON);
        Some(BoundingSphere { center, radius })
    }
}

/// Whether the box of `points` has a diagonal `f32` cannot hold (each coordinate finite, their
/// spread past about `1.8e19` in some direction, or the three together past `f32::MAX`): such
/// a model's bounds, distances and tolerances would overflow, so it is refused where it is
/// loaded.
pub(crate) fn extent_overflows(points: &[[f32; 3]]) -> bool {
    Aabb::of_points(points).is_some_and(|b| !b.diagonal().is_finite())
}
