//! The third-party references, built from the same homogeneous control net.

use curvo::prelude::NurbsSurface3D;
use nalgebra::Point4;
use truck_geometry::prelude::{BSplineSurface, KnotVec, NurbsSurface, Vector4};

/// A B-spline surface given by degrees, knots and its homogeneous control point `(i, j)` =
/// `(w x, w y, w z, w)` (`i` along u).
pub struct Net<'a> {
    /// Degree in u.
    pub du: usize,
    /// Degree in v.
    pub dv: usize,
    /// u knots.
    pub ku: &'a [f64],
    /// v knots.
    pub kv: &'a [f64],
    /// Homogeneous control point `(i, j)`.
    pub at: &'a dyn Fn(usize, usize) -> [f64; 4],
}

impl Net<'_> {
    fn rows<T>(&self, make: impl Fn([f64; 4]) -> T) -> Vec<Vec<T>> {
        let nu = self.ku.len() - self.du - 1;
        let nv = self.kv.len() - self.dv - 1;
        (0..nu)
            .map(|i| (0..nv).map(|j| make((self.at)(i, j))).collect())
            .collect()
    }

    /// The surface as curvo sees it.
    pub fn curvo(&self) -> NurbsSurface3D<f64> {
        let net = self.rows(|h| Point4::new(h[0], h[1], h[2], h[3]));
        NurbsSurface3D::new(self.du, self.dv, self.ku.to_vec(), self.kv.to_vec(), net)
    }

    /// The surface as truck-geometry sees it.
    pub fn truck(&self) -> NurbsSurface<Vector4> {
        let net = self.rows(|h| Vector4::new(h[0], h[1], h[2], h[3]));
        NurbsSurface::new(BSplineSurface::new(
            (
                KnotVec::from(self.ku.to_vec()),
                KnotVec::from(self.kv.to_vec()),
            ),
            net,
        ))
    }
}

/// Clamped knots of a single Bezier span of degree `d`.
pub fn bezier_knots(d: usize) -> Vec<f64> {
    [vec![0.0; d + 1], vec![1.0; d + 1]].concat()
}
