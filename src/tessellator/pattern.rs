//! Uniform refinement of one domain triangle whose three edges may carry other factors than
//! its inside, without T-junctions: the hardware tessellator's rule.
//!
//! The triangle `v0 v1 v2` (counter-clockwise) has an inner factor `n` and one factor per side
//! (`e[0]` on `v0 -> v1`, `e[1]` on `v1 -> v2`, `e[2]` on `v2 -> v0`). Neighbours agree on a
//! side's factor, so a side's points are the same from both triangles. When every factor is
//! `n`, the triangle is cut into the `n²` triangles of the uniform barycentric lattice.
//! Otherwise the lattice points away from the sides (the inner triangle of lattice size
//! `n - 3`; the centroid when `n <= 3`) are kept, and the ring between the sides' points and
//! the inner triangle's outline is zipped, walking both outlines by a parameter in which the
//! inner corners sit level with the outer ones. Every zip triangle joins a side segment to an
//! inner point, or an inner segment to a point of the parallel side, so none is inverted or
//! flat.
//!
//! An uncut inside (`n` = 1) with one side cut is a fan from the opposite corner instead (a
//! triangle halved across one edge is two triangles, not a fan of four around its centroid);
//! with two sides halved it is three triangles (the corner between them cut off), with all
//! three halved the four of the uniform pattern of 2.
//!
//! Triangle counts: `n²` when uniform; `e[s]` for one cut side `s` of an uncut inside, 3 and
//! 4 for two and three halved sides;
//! otherwise `(n-3)² + e0 + e1 + e2 + 3 (n-3)` for `n >= 4` and `e0 + e1 + e2` for `n <= 3`.

/// A point of a refined triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Local {
    /// Corner `k` (`v0`, `v1`, `v2`).
    Corner(u8),
    /// Point `r` (`1 ..= e[s] - 1`) of side `s`, counted from the side's first corner.
    Side { side: u8, r: u8 },
    /// Lattice point with weights `n - a - b`, `a`, `b` on `v0`, `v1`, `v2`, strictly inside.
    Lattice { a: u8, b: u8 },
    /// The centroid (inner point when `n < 3` and a side differs).
    Centroid,
}

/// True when the pattern is the uniform lattice.
pub(crate) fn is_uniform(n: u8, e: [u8; 3]) -> bool {
    e == [n; 3]
}

/// The one side cut when the inside is not (`n` = 1) and no other side is: such a triangle is
/// a fan from the opposite corner to that side's points, without an inner point.
fn single_side(n: u8, e: [u8; 3]) -> Option<u8> {
    if n != 1 {
        return None;
    }
    match e.map(|x| x > 1) {
        [true, false, false] => Some(0),
        [false, true, false] => Some(1),
        [false, false, true] => Some(2),
        _ => None,
    }
}

/// The one side left whole when the inside is not cut (`n` = 1) and the other two sides are
/// halved: such a triangle is three, the corner between the halved sides cut off at their
/// midpoints, without an inner point.
fn two_halved(n: u8, e: [u8; 3]) -> Option<u8> {
    if n != 1 {
        return None;
    }
    match e {
        [1, 2, 2] => Some(0),
        [2, 1, 2] => Some(1),
        [2, 2, 1] => Some(2),
        _ => None,
    }
}

/// An uncut inside with every side halved: the uniform pattern of 2, without an inner point.
fn all_halved(n: u8, e: [u8; 3]) -> bool {
    n == 1 && e == [2; 3]
}

/// Points strictly inside (lattice and centroid) that the pattern adds.
pub(crate) fn inner_points(n: u8, e: [u8; 3]) -> u32 {
    if single_side(n, e).is_some() || two_halved(n, e).is_some() || all_halved(n, e) {
        return 0;
    }
    let n = n as u32;
    if is_uniform(n as u8, e) || n >= 3 {
        if n >= 3 {
            (n - 1) * (n - 2) / 2
        } else {
            0
        }
    } else {
        1
    }
}

/// Index of an inner point among [`inner_points`], or `None` for points on the outline.
pub(crate) fn inner_index(n: u8, p: Local) -> Option<u32> {
    match p {
        Local::Lattice { a, b } => {
            // Rows b = 1 .. n-2 hold a = 1 .. n-1-b.
            let (n, a, b) = (n as u32, a as u32, b as u32);
            let before: u32 = (1..b).map(|row| n - 1 - row).sum();
            Some(before + a - 1)
        }
        Local::Centroid => Some(0),
        _ => None,
    }
}

/// Triangles the pattern makes.
pub(crate) fn triangle_count(n: u8, e: [u8; 3]) -> u32 {
    let n32 = n as u32;
    if let Some(s) = single_side(n, e) {
        e[s as usize] as u32
    } else if two_halved(n, e).is_some() {
        3
    } else if all_halved(n, e) {
        4
    } else if is_uniform(n, e) {
        n32 * n32
    } else {
        let ring = e.iter().map(|&x| x as u32).sum::<u32>();
        if n >= 4 {
            (n32 - 3) * (n32 - 3) + ring + 3 * (n32 - 3)
        } else {
            ring
        }
    }
}

/// The lattice point `(a, b)` of an `n`-lattice as a [`Local`].
fn lattice(n: u8, a: u8, b: u8) -> Local {
    let i = n - a - b;
    match (i, a, b) {
        (_, 0, 0) => Local::Corner(0),
        (0, _, 0) => Local::Corner(1),
        (0, 0, _) => Local::Corner(2),
        (_, _, 0) => Local::Side { side: 0, r: a },
        (0, _, _) => Local::Side { side: 1, r: b },
        (_, 0, _) => Local::Side { side: 2, r: n - b },
        _ => Local::Lattice { a, b },
    }
}

/// Calls `out` with every triangle of the pattern, counter-clockwise. Factors must be at
/// least 1.
pub(crate) fn for_each_triangle(n: u8, e: [u8; 3], mut out: impl FnMut([Local; 3])) {
    if is_uniform(n, e) {
        uniform(n, 0, n, &mut out);
        return;
    }
    if let Some(s) = single_side(n, e) {
        // A fan from the opposite corner: the side's segments, each with that corner.
        let point = |r: u8| match r {
            0 => Local::Corner(s),
            r if r == e[s as usize] => Local::Corner((s + 1) % 3),
            r => Local::Side { side: s, r },
        };
        for r in 0..e[s as usize] {
            out([point(r), point(r + 1), Local::Corner((s + 2) % 3)]);
        }
        return;
    }
    if let Some(u) = two_halved(n, e) {
        // Sides a and b are halved; they meet at corner b.
        let (a, b) = ((u + 1) % 3, (u + 2) % 3);
        let (ma, mb) = (Local::Side { side: a, r: 1 }, Local::Side { side: b, r: 1 });
        out([ma, Local::Corner(b), mb]);
        out([Local::Corner(u), Local::Corner(a), ma]);
        out([Local::Corner(u), ma, mb]);
        return;
    }
    if all_halved(n, e) {
        uniform(2, 0, 2, &mut out);
        return;
    }
    if n >= 4 {
        // The inner triangle: lattice points with every weight at least 1.
        uniform(n, 1, n - 3, &mut out);
    }
    zip(n, e, &mut out);
}

/// The uniform triangulation of the sub-lattice with corner `(off, off)` and size `m`, in
/// the coordinates of the `n`-lattice.
fn uniform(n: u8, off: u8, m: u8, out: &mut impl FnMut([Local; 3])) {
    for b in 0..m {
        for a in 0..m - b {
            let (x, y) = (a + off, b + off);
            out([lattice(n, x, y), lattice(n, x + 1, y), lattice(n, x, y + 1)]);
            if a + b + 2 <= m {
                out([
                    lattice(n, x + 1, y),
                    lattice(n, x + 1, y + 1),
                    lattice(n, x, y + 1),
                ]);
            }
        }
    }
}

/// A point of an outline with its parameter `side + num / den` (`den > 0`).
#[derive(Clone, Copy)]
struct Pos {
    side: u8,
    num: u8,
    den: u8,
}

impl Pos {
    /// `self <= other`, compared exactly.
    fn le(self, other: Pos) -> bool {
        if self.side != other.side {
            return self.side < other.side;
        }
        (self.num as u32) * (other.den as u32) <= (other.num as u32) * (self.den as u32)
    }
}

/// Point `k` of the outer outline (corners and side points, from `v0`, counter-clockwise).
fn outer(e: [u8; 3], k: u32) -> (Local, Pos) {
    let mut k = k;
    for s in 0..3u8 {
        let len = e[s as usize] as u32;
        if k < len {
            let r = k as u8;
            let p = if r == 0 {
                Local::Corner(s)
            } else {
                Local::Side { side: s, r }
            };
            return (
                p,
                Pos {
                    side: s,
                    num: r,
                    den: e[s as usize],
                },
            );
        }
        k -= len;
    }
    (
        Local::Corner(0),
        Pos {
            side: 3,
            num: 0,
            den: 1,
        },
    )
}

/// Point `k` of the inner outline (`m = n - 3 >= 1` segments per side), or the wrap-around.
fn inner(n: u8, k: u32) -> (Local, Pos) {
    let m = n - 3;
    let side = (k / m as u32) as u8;
    let r = (k % m as u32) as u8;
    let (a, b) = match side {
        0 => (1 + r, 1),
        1 => (n - 2 - r, 1 + r),
        2 => (1, n - 2 - r),
        _ => (1, 1),
    };
    let pos = Pos {
        side,
        num: if side == 3 { 0 } else { r },
        den: m,
    };
    (Local::Lattice { a, b }, pos)
}

/// The ring between the outer outline and the inner one.
fn zip(n: u8, e: [u8; 3], out: &mut impl FnMut([Local; 3])) {
    let outer_len: u32 = e.iter().map(|&x| x as u32).sum();
    if n < 4 {
        // One inner point: a fan.
        let centre = if n == 3 {
            Local::Lattice { a: 1, b: 1 }
        } else {
            Local::Centroid
        };
        for k in 0..outer_len {
            out([outer(e, k).0, outer(e, k + 1).0, centre]);
        }
        return;
    }
    let inner_len = 3 * (n as u32 - 3);
    let (mut ia, mut ib) = (0u32, 0u32);
    while ia < outer_len || ib < inner_len {
        let advance_outer =
            ia < outer_len && (ib == inner_len || outer(e, ia + 1).1.le(inner(n, ib + 1).1));
        if advance_outer {
            out([outer(e, ia).0, outer(e, ia + 1).0, inner(n, ib).0]);
            ia += 1;
        } else {
            out([outer(e, ia).0, inner(n, ib + 1).0, inner(n, ib).0]);
            ib += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Barycentric position (times a common denominator) of a local point.
    fn position(n: u8, e: [u8; 3], p: Local) -> (f64, f64) {
        let corners = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)];
        match p {
            Local::Corner(k) => corners[k as usize],
            Local::Side { side, r } => {
                let (a, b) = (corners[side as usize], corners[(side as usize + 1) % 3]);
                let t = r as f64 / e[side as usize] as f64;
                (a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t)
            }
            Local::Lattice { a, b } => (a as f64 / n as f64, b as f64 / n as f64),
            Local::Centroid => (1.0 / 3.0, 1.0 / 3.0),
        }
    }

    #[test]
    fn every_pattern_tiles_the_triangle_with_positive_triangles() {
        for n in 1..=9u8 {
            for e0 in n..=n + 4 {
                for e1 in n..=n + 3 {
                    for e2 in [n, n + 1, 2 * n + 1] {
                        let e = [e0, e1, e2];
                        let mut area = 0.0;
                        let mut count = 0;
                        for_each_triangle(n, e, |t| {
                            let [a, b, c] = t.map(|p| position(n, e, p));
                            let cross = (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0);
                            assert!(cross > 1e-12, "n {n} e {e:?}: {t:?} has area {cross}");
                            area += cross * 0.5;
                            count += 1;
                            for p in t {
                                if let Local::Side { side, r } = p {
                                    assert!(r >= 1 && r < e[side as usize]);
                                }
                                if let Some(k) = inner_index(n, p) {
                                    assert!(k < inner_points(n, e), "{p:?}");
                                }
                            }
                        });
                        assert!((area - 0.5).abs() < 1e-9, "n {n} e {e:?}: area {area}");
                        assert_eq!(count, triangle_count(n, e), "n {n} e {e:?}");
                    }
                }
            }
        }
    }
}
