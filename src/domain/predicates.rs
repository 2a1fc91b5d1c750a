//! The exact predicates every decision of the triangulation rests on: orientation, and the
//! in-circle test in the metric's coordinates with ties broken by simulation of simplicity.

use super::GridPoint;

/// Twice the signed area of `abc`: positive when counter-clockwise.
#[inline]
pub(crate) fn orient(a: GridPoint, b: GridPoint, c: GridPoint) -> i64 {
    let (ax, ay) = (a.u as i64, a.v as i64);
    (b.u as i64 - ax) * (c.v as i64 - ay) - (b.v as i64 - ay) * (c.u as i64 - ax)
}

/// How the Delaunay test weighs u against v: circles are taken in the coordinates
/// `(u * metric.u, v * metric.v)`, so a patch whose surface bends faster along one parameter gets
/// triangles stretched along the other.
///
/// Orientation does not depend on it, so a mesh's validity does not either; only which of the
/// valid triangulations is chosen. Factors are whole numbers from 1 to [`Metric::MAX`], which
/// keeps the predicates exact.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Metric {
    u: u8,
    v: u8,
}

impl Default for Metric {
    fn default() -> Self {
        Metric::ISOTROPIC
    }
}

impl Metric {
    /// The largest factor.
    pub const MAX: u8 = 16;
    /// Plain Delaunay in `(u, v)`.
    pub const ISOTROPIC: Metric = Metric { u: 1, v: 1 };

    /// Factors for u and v, each clamped into `1..=MAX`.
    pub const fn new(u: u8, v: u8) -> Self {
        Metric {
            u: clamp_factor(u),
            v: clamp_factor(v),
        }
    }

    /// The factor of u.
    pub const fn u(self) -> u8 {
        self.u
    }

    /// The factor of v.
    pub const fn v(self) -> u8 {
        self.v
    }
}

const fn clamp_factor(x: u8) -> u8 {
    if x < 1 {
        1
    } else if x > Metric::MAX {
        Metric::MAX
    } else {
        x
    }
}

/// True when `d` lies inside the circumcircle of the counter-clockwise triangle `abc` (in the
/// coordinates `metric` scales), with ties broken by simulation of simplicity (the largest point
/// in `(u, v)` order is perturbed most).
pub(super) fn in_circle(
    metric: Metric,
    a: GridPoint,
    b: GridPoint,
    c: GridPoint,
    d: GridPoint,
) -> bool {
    // Differences up to 2^20 (in i32, and exact in f32, so the filter's are computed in f32
    // directly): the lifts are below 2^41, the determinant below 2^85.
    let (mu, mv) = (metric.u as f32, metric.v as f32);
    let fx = |p: GridPoint| (p.u as f32 - d.u as f32) * mu;
    let fy = |p: GridPoint| (p.v as f32 - d.v as f32) * mv;
    if let Some(inside) = in_circle_filter([fx(a), fy(a), fx(b), fy(b), fx(c), fy(c)]) {
        return inside;
    }
    let dx = |p: GridPoint| (p.u as i32 - d.u as i32) * metric.u as i32;
    let dy = |p: GridPoint| (p.v as i32 - d.v as i32) * metric.v as i32;
    let differences = [dx(a), dy(a), dx(b), dy(b), dx(c), dy(c)];
    let [adx, ady, bdx, bdy, cdx, cdy] = differences.map(i64::from);
    let lift = |x: i64, y: i64| (x * x + y * y) as i128;
    let det = lift(adx, ady) * (bdx * cdy - bdy * cdx) as i128
        + lift(bdx, bdy) * (cdx * ady - cdy * adx) as i128
        + lift(cdx, cdy) * (adx * bdy - ady * bdx) as i128;
    if det != 0 {
        return det > 0;
    }
    // Raising p's lift by eps_p adds eps_p times p's cofactor; the largest point's term wins.
    // Its cofactor is the orientation of the other three, which are distinct points on one
    // circle and so never collinear.
    let top = a.max(b).max(c).max(d);
    let term = if top == a {
        orient(d, b, c)
    } else if top == b {
        orient(d, c, a)
    } else if top == c {
        orient(d, a, b)
    } else {
        -orient(a, b, c)
    };
    term > 0
}

/// Shewchuk's first in-circle error bound ("Adaptive precision floating-point arithmetic and
/// fast robust geometric predicates", 1997, `iccerrboundA`), for `f32`: its unit roundoff is
/// 2^-24.
const IN_CIRCLE_ERROR: f32 = (10.0 + 96.0 * F32_ROUNDOFF) * F32_ROUNDOFF;
const F32_ROUNDOFF: f32 = 1.0 / 16_777_216.0;

/// The in-circle sign in `f32` when it is certain, else `None`.
///
/// The differences (`[adx, ady, bdx, bdy, cdx, cdy]`, below 2^20 in magnitude) are exact in
/// `f32`, which is what Shewchuk's bound assumes: the rounded determinant is within
/// `IN_CIRCLE_ERROR` times the permanent (the same sum over absolute values, also rounded) of
/// the exact one, so a larger magnitude has the exact sign. Nothing can overflow (the
/// determinant is below 2^85); a NaN would fail the comparison and fall through. The exact
/// `i128` test decides the rest, so the answer never depends on the filter.
#[inline]
fn in_circle_filter([adx, ady, bdx, bdy, cdx, cdy]: [f32; 6]) -> Option<bool> {
    let (bc, cb) = (bdx * cdy, cdx * bdy);
    let (ca, ac) = (cdx * ady, adx * cdy);
    let (ab, ba) = (adx * bdy, bdx * ady);
    let (la, lb, lc) = (
        adx * adx + ady * ady,
        bdx * bdx + bdy * bdy,
        cdx * cdx + cdy * cdy,
    );
    let det = la * (bc - cb) + lb * (ca - ac) + lc * (ab - ba);
    let permanent =
        la * (bc.abs() + cb.abs()) + lb * (ca.abs() + ac.abs()) + lc * (ab.abs() + ba.abs());
    let error = IN_CIRCLE_ERROR * permanent;
    if det > error {
        Some(true)
    } else if -det > error {
        Some(false)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::in_circle_filter;

    /// The exact determinant's sign, as `in_circle` computes it.
    fn exact(d: [i64; 6]) -> i128 {
        let [adx, ady, bdx, bdy, cdx, cdy] = d;
        let lift = |x: i64, y: i64| (x * x + y * y) as i128;
        lift(adx, ady) * (bdx * cdy - bdy * cdx) as i128
            + lift(bdx, bdy) * (cdx * ady - cdy * adx) as i128
            + lift(cdx, cdy) * (adx * bdy - ady * bdx) as i128
    }

    fn check(d: [i64; 6]) -> bool {
        let det = exact(d);
        match in_circle_filter(d.map(|x| x as f32)) {
            Some(inside) => {
                assert!(det != 0 && inside == (det > 0), "{d:?}: filter wrong");
                true
            }
            None => false,
        }
    }

    #[test]
    fn the_filter_never_contradicts_the_exact_test() {
        let mut rng = crate::test_rng::TestRng::new(0x2545_f491_4f6c_dd1d);
        let mut next = |range: i64| rng.signed(range);
        let (mut decided, mut total) = (0, 0);
        // Random differences at every scale up to the grid's 2^20.
        for scale in [3i64, 100, 65_535, (1 << 20) - 1] {
            for _ in 0..20_000 {
                let d = core::array::from_fn(|_| next(scale));
                decided += check(d) as usize;
                total += 1;
            }
        }
        // Cocircular points at every scale, and nearly cocircular ones: the hard cases.
        let ring = [
            (5, 0),
            (4, 3),
            (3, 4),
            (0, 5),
            (-3, 4),
            (-4, -3),
            (0, -5),
            (3, -4),
        ];
        for _ in 0..20_000 {
            let k = next(40_000).abs() + 1;
            let pick = |i: i64| ring[(i.unsigned_abs() % 8) as usize];
            let [a, b, c, d] = [pick(next(8)), pick(next(8)), pick(next(8)), pick(next(8))];
            let nudge = next(1);
            let d = [
                (a.0 - d.0) * k + nudge,
                (a.1 - d.1) * k,
                (b.0 - d.0) * k,
                (b.1 - d.1) * k,
                (c.0 - d.0) * k,
                (c.1 - d.1) * k,
            ];
            if d.iter().all(|x| x.abs() < 1 << 20) {
                decided += check(d) as usize;
                total += 1;
            }
        }
        // The filter decides the bulk of the random cases.
        assert!(decided * 2 > total, "{decided} of {total}");
    }
}
