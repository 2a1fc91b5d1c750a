//! How a baked step's surface point and offset are stored in a few bytes.
//!
//! - The point as three `u16` in its patch's [`PointBox`]: `min + q * (extent / 65535)` per
//!   axis, so within `extent / 131070` of the point the bake evaluated.
//! - The offset as three `i16` with one shared binary exponent `e`: `m * 2^e`, so each
//!   component is within `2^(e-1)` of the evaluated one, and the largest keeps 15 bits.
//!
//! The bake rounds both through these encoders before it returns them, so what
//! [`sample_patch`](super::sample_patch) writes into its buffer equals what the bytes decode
//! to, bit for bit. Neither value enters an error bound: the run time uses them only to choose
//! which steps a view needs, and judges every triangle by its computed bound.

/// Largest stored exponent of an offset: `32767 * 2^110` is finite in `f32`.
pub(crate) const MAX_OFFSET_EXPONENT: i8 = 110;

/// The axis-aligned box a patch's step points are stored in: its control points' box, which
/// holds the patch (the weights are positive).
///
/// ```
/// use spline_tess::bake::PointBox;
///
/// let b = PointBox::of_points(&[[0.0, 1.0, 2.0], [4.0, 1.0, -2.0]]);
/// assert_eq!(b.min, [0.0, 1.0, -2.0]);
/// assert_eq!(b.extent, [4.0, 0.0, 4.0]);
/// assert_eq!(b.decode(b.encode([2.0, 1.0, 0.0])), [2.0000305, 1.0, 3.0517578e-5]);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PointBox {
    /// The smallest coordinate on each axis.
    pub min: [f32; 3],
    /// The box's size on each axis (not negative).
    pub extent: [f32; 3],
}

impl PointBox {
    /// The box of `points` (empty or non-finite input gives a box at the origin).
    pub fn of_points(points: &[[f32; 3]]) -> PointBox {
        let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
        for p in points {
            for i in 0..3 {
                lo[i] = lo[i].min(p[i]);
                hi[i] = hi[i].max(p[i]);
            }
        }
        let mut b = PointBox::default();
        for i in 0..3 {
            let extent = hi[i] - lo[i];
            if lo[i].is_finite() && extent.is_finite() {
                b.min[i] = lo[i];
                b.extent[i] = extent;
            }
        }
        b
    }

    /// True when the box's fields are finite, its extents not negative and its far corner
    /// finite: every stored point then decodes to a finite point.
    pub(crate) fn is_valid(&self) -> bool {
        (0..3).all(|i| {
            self.min[i].is_finite()
                && self.extent[i] >= 0.0
                && (self.min[i] + self.extent[i]).is_finite()
        })
    }

    /// The stored form of `p` (clamped into the box).
    pub fn encode(&self, p: [f32; 3]) -> [u16; 3] {
        core::array::from_fn(|i| {
            if self.extent[i] > 0.0 {
                let t = (p[i] - self.min[i]) / self.extent[i] * 65535.0;
                // NaN clamps to 0.
                libm::floorf(t.clamp(0.0, 65535.0) + 0.5) as u16
            } else {
                0
            }
        })
    }

    /// The point `q` stands for.
    pub fn decode(&self, q: [u16; 3]) -> [f32; 3] {
        core::array::from_fn(|i| self.min[i] + q[i] as f32 * (self.extent[i] / 65535.0))
    }
}

/// The stored form of an offset: three mantissas and their shared exponent (zero, and
/// non-finite input, give zero).
pub(crate) fn encode_offset(d: [f32; 3]) -> ([i16; 3], i8) {
    let largest = d.iter().fold(0.0f32, |m, x| m.max(x.abs()));
    if !(d.iter().all(|x| x.is_finite()) && largest > 0.0) {
        return ([0; 3], 0);
    }
    // largest < 2^x, so largest / 2^(x - 15) < 32768.
    let (_, x) = libm::frexpf(largest);
    let e = (x - 15).clamp(i8::MIN as i32, MAX_OFFSET_EXPONENT as i32);
    let m = d.map(|c| {
        let scaled = libm::ldexpf(c, -e);
        libm::floorf(scaled.clamp(-32767.0, 32767.0) + 0.5) as i16
    });
    (m, e as i8)
}

/// The offset stored as mantissas `m` and exponent `e`.
pub(crate) fn decode_offset(m: [i16; 3], e: i8) -> [f32; 3] {
    m.map(|c| libm::ldexpf(c as f32, e as i32))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offsets_keep_fifteen_bits() {
        for d in [
            [1.0, -0.5, 0.25],
            [3.0e-3, 1.0e-7, -2.9e-3],
            [-7.5e12, 0.0, 1.0],
            [1.0e-30, -1.0e-31, 0.0],
        ] {
            let (m, e) = encode_offset(d);
            let back = decode_offset(m, e);
            let largest = d.iter().fold(0.0f32, |a, x| a.max(x.abs()));
            for i in 0..3 {
                assert!(
                    (back[i] - d[i]).abs() <= largest / 32768.0,
                    "{d:?} -> {back:?}"
                );
            }
            assert_eq!(
                encode_offset(back),
                (m, e),
                "a stored offset is stored again alike"
            );
        }
        assert_eq!(encode_offset([0.0; 3]), ([0; 3], 0));
        assert_eq!(encode_offset([f32::NAN, 1.0, 0.0]), ([0; 3], 0));
    }

    #[test]
    fn points_round_into_their_box() {
        let b = PointBox::of_points(&[[-1.0, 0.0, 5.0], [3.0, 2.0, 5.0]]);
        for p in [[-1.0, 0.0, 5.0], [3.0, 2.0, 5.0], [0.123, 1.777, 5.0]] {
            let back = b.decode(b.encode(p));
            for i in 0..3 {
                assert!((back[i] - p[i]).abs() <= b.extent[i] / 131070.0 + 1e-6);
            }
            assert_eq!(b.encode(back), b.encode(p));
        }
        // Outside the box clamps to its faces.
        assert_eq!(b.encode([-9.0, 9.0, 0.0]), [0, 65535, 0]);
    }
}
