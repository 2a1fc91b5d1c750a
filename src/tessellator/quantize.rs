//! How a hierarchy's bytes hold numbers: points on a grid of the model's box, normals in
//! octahedral coordinates, bounds and scales on logarithmic grids. The bake rounds every
//! record it writes to these grids (a bound upward, so it stays a bound), so that the records
//! and the bytes hold the same values and give the same meshes.
//!
//! - **Points**: `u16` per coordinate, `min + q step` with `step = (max - min) / 65535` of the
//!   model's box (`PatchSet::aabb`). The bake measures every bound against the rounded points
//!   (`deviation/lattice.rs` counts a corner's own miss), so rounding them costs no soundness.
//! - **Normals**: two `i8`, the unit vector projected on the octahedron `|x| + |y| + |z| = 1`
//!   and its lower half folded out (a normal is off by at most about 0.01 radians, less than
//!   a level of a display's 6-bit green where it shades); the pair `(i8::MIN, i8::MIN)` is
//!   the zero vector.
//! - **Bounds**: one byte `b`, `unit 2^((b - zero) / K)` (`K` steps an octave), 0 for `b = 0`
//!   and infinity for `b = 255`, where `unit` is a power of two near a thousandth of the
//!   model's diagonal. A value is rounded up to the next grid value ([`LogGrid::up`]), exact
//!   in `f32` (a table entry times a power of two).

use crate::model::PatchSet;

/// The grid of the model's box the points are rounded to.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub(crate) struct PositionGrid {
    pub min: [f32; 3],
    pub step: [f32; 3],
}

impl PositionGrid {
    /// The grid of `model`'s box (an empty or unbounded box: every point at the origin).
    pub fn of(model: &PatchSet<'_>) -> PositionGrid {
        let Some(b) = model.aabb() else {
            return PositionGrid::default();
        };
        let (min, max) = (b.min.to_array(), b.max.to_array());
        let mut grid = PositionGrid::default();
        for k in 0..3 {
            let step = (max[k] - min[k]) / 65535.0;
            if min[k].is_finite() && step.is_finite() && step >= 0.0 {
                grid.min[k] = min[k];
                grid.step[k] = step;
            }
        }
        grid
    }

    /// The grid point nearest `p` (clamped to the box).
    pub fn encode(&self, p: [f32; 3]) -> [u16; 3] {
        [0, 1, 2].map(|k| {
            let s = self.step[k];
            if s > 0.0 {
                libm::roundf((p[k] - self.min[k]) / s).clamp(0.0, 65535.0) as u16
            } else {
                0
            }
        })
    }

    /// The point of grid point `q`.
    pub fn decode(&self, q: [u16; 3]) -> [f32; 3] {
        [0, 1, 2].map(|k| self.min[k] + q[k] as f32 * self.step[k])
    }

    /// `p` rounded to the grid.
    pub fn round(&self, p: [f32; 3]) -> [f32; 3] {
        self.decode(self.encode(p))
    }
}

/// The zero normal's code.
const NO_NORMAL: [i8; 2] = [i8::MIN, i8::MIN];

/// The octahedral codes' largest coordinate.
const OCT: f32 = 127.0;

/// `n` (a unit vector, or zero) in octahedral coordinates.
pub(crate) fn normal_code(n: [f32; 3]) -> [i8; 2] {
    let [x, y, z] = n;
    let l1 = x.abs() + y.abs() + z.abs();
    if !(l1 > 0.0 && l1.is_finite()) {
        return NO_NORMAL;
    }
    let (mut a, mut b) = (x / l1, y / l1);
    if z < 0.0 {
        (a, b) = fold(a, b);
    }
    [a, b].map(|c| libm::roundf(c.clamp(-1.0, 1.0) * OCT) as i8)
}

/// The unit normal of octahedral code `q`: the code's point on the octahedron in integers
/// (exact: `|a| + |b| + |z| = 127`, the lower half folded onto the square's corners), and
/// that over its length, one root and one quotient. (Normalised in `f32` from `q / 127`, it
/// took six quotients, a root and the fold's roundings: 1.11M of `fw_teapot` frame 0's
/// render instructions on ARMv6-M.)
pub(crate) fn normal_of(q: [i8; 2]) -> [f32; 3] {
    let Some([a, b, z]) = octahedral_point(q) else {
        return [0.0; 3];
    };
    // (The square is below `2^16`, and not 0, as the three add up to 127 in size.)
    let square = a * a + b * b + z * z;
    let inverse = 1.0 / crate::math::sqrt(square as f32);
    [a, b, z].map(|c| c as f32 * inverse)
}

/// The point on the octahedron of code `q`, in integers: `|a| + |b| + |z| = 127` for a code
/// the bake writes (the lower half folded onto the square's corners), every coordinate at
/// most 128 in size for any code. `None` for the zero normal's code.
pub(crate) fn octahedral_point(q: [i8; 2]) -> Option<[i32; 3]> {
    if q == NO_NORMAL {
        return None;
    }
    const O: i32 = OCT as i32;
    let (mut a, mut b) = (i32::from(q[0]), i32::from(q[1]));
    let z = O - a.abs() - b.abs();
    if z < 0 {
        let sign = |x: i32| if x >= 0 { 1 } else { -1 };
        (a, b) = ((O - b.abs()) * sign(a), (O - a.abs()) * sign(b));
    }
    Some([a, b, z])
}

/// `n` rounded to its octahedral code.
pub(crate) fn round_normal(n: [f32; 3]) -> [f32; 3] {
    normal_of(normal_code(n))
}

/// The octahedron's lower half folded onto the corners of the square (and back).
fn fold(a: f32, b: f32) -> (f32, f32) {
    let sign = |x: f32| if x >= 0.0 { 1.0 } else { -1.0 };
    ((1.0 - b.abs()) * sign(a), (1.0 - a.abs()) * sign(b))
}

/// `2^(j / 4)`, rounded to `f32`.
const QUARTERS: [u32; 4] = [0x3f80_0000, 0x3f98_37f0, 0x3fb5_04f3, 0x3fd7_44fd];

/// `2^(j / 8)`, rounded to `f32`.
const EIGHTHS: [u32; 8] = [
    0x3f80_0000,
    0x3f8b_95c2,
    0x3f98_37f0,
    0x3fa5_fed7,
    0x3fb5_04f3,
    0x3fc5_672a,
    0x3fd7_44fd,
    0x3fea_c0c7,
];

/// A logarithmic grid of one byte: see the [module docs](self).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub(crate) struct LogGrid {
    /// `log2` of the unit.
    unit: i32,
    /// The code of the unit.
    zero: i32,
    /// Steps an octave, as a shift: 2 (four steps) or 3 (eight).
    shift: u32,
}

/// The exponent of a power of two near a thousandth of `model`'s diagonal (`2^-10` for a
/// model without one).
pub(crate) fn unit_exponent(model: &PatchSet<'_>) -> i32 {
    let diagonal = model.aabb().map_or(f32::NAN, |b| b.diagonal());
    if !(diagonal.is_normal() && diagonal > 0.0) {
        return -10;
    }
    ((diagonal.to_bits() >> 23) as i32 - 127 - 10).clamp(-100, 100)
}

impl LogGrid {
    /// Kept vectors' scales: four steps an octave.
    pub fn scales(model: &PatchSet<'_>) -> LogGrid {
        LogGrid {
            unit: unit_exponent(model),
            zero: 218,
            shift: 2,
        }
    }

    /// Remainders and leaves' bounds: eight steps an octave.
    pub fn bounds(model: &PatchSet<'_>) -> LogGrid {
        LogGrid {
            unit: unit_exponent(model),
            zero: 152,
            shift: 3,
        }
    }

    /// The value of code `b`.
    pub fn value(&self, b: u8) -> f32 {
        match b {
            0 => 0.0,
            255 => f32::INFINITY,
            _ => {
                let k = b as i32 - self.zero;
                // (Shifts, not divisions: this is read at every judgement.)
                let (octave, step) = (k >> self.shift, (k & ((1 << self.shift) - 1)) as usize);
                let table = match self.shift {
                    2 => QUARTERS[step & 3],
                    _ => EIGHTHS[step & 7],
                };
                let e = (octave + self.unit).clamp(-126, 127);
                // `table 2^e`: the table's values lie in `[1, 2)` and the product is a normal
                // number, so it is exact: where `f32` is software, the table's bits with `e`
                // added to the exponent (no library call; an FPU's product is cheaper).
                if crate::math::HARD_FLOAT {
                    f32::from_bits(table) * f32::from_bits(((e + 127) as u32) << 23)
                } else {
                    f32::from_bits((table as i32 + (e << 23)) as u32)
                }
            }
        }
    }

    /// The code of the smallest grid value at least `x` (0 for `x <= 0`, 255, infinity, past
    /// the largest or for NaN).
    pub fn up(&self, x: f32) -> u8 {
        if x <= 0.0 {
            return 0;
        }
        if x.is_nan() || x > self.value(254) {
            return 255;
        }
        // A first guess from the logarithm, then the exact comparisons.
        let guess = (crate::math::log2(x) - self.unit as f32) * (1 << self.shift) as f32;
        let mut b = (libm::ceilf(guess) as i32 + self.zero).clamp(1, 254) as u8;
        while b < 254 && self.value(b) < x {
            b += 1;
        }
        while b > 1 && self.value(b - 1) >= x {
            b -= 1;
        }
        b
    }

    /// `x` rounded up to the grid.
    pub fn round_up(&self, x: f32) -> f32 {
        self.value(self.up(x))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every code's value is the table's step times the power of two of its octave, as the
    /// product of the two `f32` numbers gives it, for both grids and every unit a model may
    /// have (the exponent's clamps included).
    #[test]
    fn values_are_the_steps_times_their_octaves() {
        for (zero, shift) in [(152, 3), (218, 2)] {
            for unit in -100..=100 {
                let g = LogGrid { unit, zero, shift };
                for b in 1..255u8 {
                    let k = b as i32 - zero;
                    let (octave, step) = (k >> shift, (k & ((1 << shift) - 1)) as usize);
                    let table = if shift == 2 {
                        QUARTERS[step]
                    } else {
                        EIGHTHS[step]
                    };
                    let e = (octave + unit).clamp(-126, 127);
                    let product = f32::from_bits(table) * f32::from_bits(((e + 127) as u32) << 23);
                    let added = f32::from_bits((table as i32 + (e << 23)) as u32);
                    assert_eq!(added.to_bits(), product.to_bits(), "{unit} {b}");
                    assert_eq!(g.value(b).to_bits(), product.to_bits(), "{unit} {b}");
                }
            }
        }
    }

    #[test]
    fn bounds_round_up_to_the_smallest_grid_value() {
        let g = LogGrid {
            unit: -10,
            zero: 152,
            shift: 3,
        };
        for x in [1e-9f32, 1e-6, 1e-3, 0.0123, 0.5, 1.0, 3.0, 6.5] {
            let b = g.up(x);
            assert!(g.value(b) >= x, "{x}");
            assert!(b == 1 || g.value(b - 1) < x, "{x}");
            // (Below the grid's least value, everything rounds up to it.)
            assert!(b == 1 || g.value(b) <= x * 1.0906, "{x}");
            assert_eq!(g.up(g.value(b)), b);
        }
        assert_eq!(g.up(0.0), 0);
        assert_eq!(g.up(f32::NAN), 255);
        assert_eq!(g.up(1e30), 255);
        assert_eq!(g.up(7.77), 255, "past the grid's largest finite value");
        assert_eq!(g.value(255), f32::INFINITY);
    }

    #[test]
    fn normals_round_trip_within_a_hundredth() {
        for n in [
            [0.0f32, 0.0, 1.0],
            [0.0, 0.0, -1.0],
            [0.6, -0.8, 0.0],
            [0.3, 0.4, -0.866_025_4],
            [-0.577_350_3, -0.577_350_3, -0.577_350_3],
        ] {
            let r = round_normal(n);
            let d: f32 = (0..3).map(|k| (r[k] - n[k]).abs()).sum();
            assert!(d < 2e-2, "{n:?} -> {r:?}");
            assert_eq!(round_normal(r), r, "a rounded normal is its own code");
        }
        assert_eq!(round_normal([0.0; 3]), [0.0; 3]);
    }
}
