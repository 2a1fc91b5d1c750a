//! Points of the domain: the 16-bit parameter grid.

/// Coordinates on the 16-bit parameter grid: `0` is parameter 0, [`GridPoint::MAX`] is 1.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct GridPoint {
    /// u on the grid.
    pub u: u16,
    /// v on the grid.
    pub v: u16,
}

impl GridPoint {
    /// The grid value of parameter 1.
    pub const MAX: u16 = u16::MAX;

    /// A point from grid coordinates.
    pub const fn new(u: u16, v: u16) -> Self {
        GridPoint { u, v }
    }

    /// The nearest grid point to parameters `(u, v)`, clamped into `[0, 1]` (NaN counts as 0).
    pub fn from_unit(u: f32, v: f32) -> Self {
        let q = |t: f32| {
            let t = crate::math::clamp_param(t, 0.0, 1.0);
            // t in [0, 1], so the product is in [0, 65535.5) and the cast is exact after floor.
            libm::floorf(t * Self::MAX as f32 + 0.5) as u16
        };
        GridPoint { u: q(u), v: q(v) }
    }

    /// The parameters `(u, v)` of this grid point.
    pub fn to_unit(self) -> (f32, f32) {
        let s = 1.0 / Self::MAX as f32;
        (self.u as f32 * s, self.v as f32 * s)
    }

    /// True when the point lies on the square's boundary.
    pub fn on_boundary(self) -> bool {
        self.u == 0 || self.v == 0 || self.u == Self::MAX || self.v == Self::MAX
    }
}
