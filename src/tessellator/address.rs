//! Where the triangles of the bisection hierarchy are: corners on a grid of `2^15` steps per
//! side, halves, and the triangle across a hypotenuse, in the same patch or across a shared
//! curve.

use crate::patch::Side;

/// The grid value of parameter 1 (a power of two, so that every midpoint of the hierarchy
/// down to one grid step is a grid point and every grid point a float).
pub(crate) const ONE: u16 = 1 << 15;

/// A point of the grid, `[u, v]`.
pub(crate) type Point = [u16; 2];

/// A triangle of one patch's hierarchy: its right-angle corner, then the ends of its
/// hypotenuse, counter-clockwise in the `(u, v)` square.
#[derive(Clone, Copy, Debug, Default, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Tri {
    /// The patch.
    pub patch: u32,
    /// Right-angle corner, then the hypotenuse's ends.
    pub corners: [Point; 3],
}

/// What a patch side joins: the same curve as side `side` of patch `patch`, whose parameter
/// runs the other way when `flip`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SideLink {
    /// The other patch.
    pub patch: u32,
    /// Its side.
    pub side: Side,
    /// Whether the side parameter of one is `1 - t` of the other's.
    pub flip: bool,
}

/// Field by field: a derived comparison of the corner arrays is a call to `memcmp` on a
/// Cortex-M, where the run time compares triangles at every step of a descent.
impl PartialEq for Tri {
    #[inline]
    fn eq(&self, other: &Tri) -> bool {
        let [a, b, c] = self.corners;
        let [x, y, z] = other.corners;
        self.patch == other.patch && a == x && b == y && c == z
    }
}

impl Tri {
    /// The two triangles of patch `patch`'s square: below the diagonal from `(1, 0)` to
    /// `(0, 1)`, then above it.
    pub(crate) fn roots(patch: u32) -> [Tri; 2] {
        let m = ONE;
        [
            Tri {
                patch,
                corners: [[0, 0], [m, 0], [0, m]],
            },
            Tri {
                patch,
                corners: [[m, m], [0, m], [m, 0]],
            },
        ]
    }

    /// The hypotenuse's midpoint.
    pub(crate) fn midpoint(&self) -> Point {
        let [_, b, c] = self.corners;
        [
            ((b[0] as u32 + c[0] as u32) / 2) as u16,
            ((b[1] as u32 + c[1] as u32) / 2) as u16,
        ]
    }

    /// Whether the hypotenuse's midpoint is a grid point (the triangle can be halved).
    pub(crate) fn can_split(&self) -> bool {
        let [_, b, c] = self.corners;
        b != c
            && (b[0] as u32 + c[0] as u32).is_multiple_of(2)
            && (b[1] as u32 + c[1] as u32).is_multiple_of(2)
    }

    /// The two halves, cut from the right-angle corner to the hypotenuse's midpoint: each has
    /// the midpoint as its right-angle corner; the first holds the hypotenuse's first end.
    pub(crate) fn children(&self) -> [Tri; 2] {
        let [a, b, c] = self.corners;
        let m = self.midpoint();
        [
            Tri {
                patch: self.patch,
                corners: [m, a, b],
            },
            Tri {
                patch: self.patch,
                corners: [m, c, a],
            },
        ]
    }

    /// Three times the centroid (exact in integers).
    pub(crate) fn centroid3(&self) -> [i32; 2] {
        let c = self.corners;
        [0, 1].map(|k| c[0][k] as i32 + c[1][k] as i32 + c[2][k] as i32)
    }

    /// Which half ([`children`](Self::children)) holds the point `p3` (three times a grid
    /// point, strictly inside one half).
    ///
    /// The halves meet on the line from the hypotenuse's midpoint `m` to the right angle `a`.
    /// A triangle of the hierarchy is right and isosceles, its legs along the grid or its
    /// diagonals, so `a - m` is `L (u_x, u_y)` with `u` in `{-1, 0, 1}²` and `L > 0`: the side
    /// of that line a point lies on is the sign of `u_x (q_y - m_y) - u_y (q_x - m_x)`, exact
    /// in `i32` (coordinates below `2^17`), where the cross product with `a - m` itself would
    /// take 64 bits.
    pub(crate) fn half_toward(&self, p3: [i32; 2]) -> usize {
        let [a, b, _] = self.corners.map(|p| [p[0] as i32, p[1] as i32]);
        let m = self.midpoint().map(|x| x as i32);
        let u = [(a[0] - m[0]).signum(), (a[1] - m[1]).signum()];
        let side = |q: [i32; 2]| u[0] * q[1] - u[1] * q[0];
        let p = side([p3[0] - 3 * m[0], p3[1] - 3 * m[1]]);
        if (p > 0) == (side([b[0] - m[0], b[1] - m[1]]) > 0) {
            0
        } else {
            1
        }
    }

    /// Which root of its patch ([`roots`](Self::roots)) holds this triangle.
    pub(crate) fn root_index(&self) -> usize {
        let c = self.centroid3();
        usize::from(c[0] + c[1] > 3 * ONE as i32)
    }

    /// The side of the square the hypotenuse lies on, if any.
    pub(crate) fn hypotenuse_side(&self) -> Option<Side> {
        let [_, b, c] = self.corners;
        if b[1] == 0 && c[1] == 0 {
            Some(Side::V0)
        } else if b[0] == ONE && c[0] == ONE {
            Some(Side::U1)
        } else if b[1] == ONE && c[1] == ONE {
            Some(Side::V1)
        } else if b[0] == 0 && c[0] == 0 {
            Some(Side::U0)
        } else {
            None
        }
    }

    /// The triangle across the hypotenuse: the mirror image in the same patch, or across a
    /// shared curve the triangle of the other patch on the same piece of the curve (`link`
    /// gives what a patch's side joins). `None` on an open or collapsed side.
    pub(crate) fn across(&self, link: impl Fn(u32, Side) -> Option<SideLink>) -> Option<Tri> {
        let [a, b, c] = self.corners;
        let mirror = [0, 1].map(|k| b[k] as i32 + c[k] as i32 - a[k] as i32);
        if mirror.iter().all(|&x| (0..=ONE as i32).contains(&x)) {
            return Some(Tri {
                patch: self.patch,
                corners: [mirror.map(|x| x as u16), c, b],
            });
        }
        let side = self.hypotenuse_side()?;
        let link = link(self.patch, side)?;
        let map = |p: Point| {
            let t = side_parameter(side, p);
            point_on(link.side, if link.flip { ONE - t } else { t })
        };
        let (b2, c2) = (map(b), map(c));
        let half = side_parameter(side, b).abs_diff(side_parameter(side, c)) / 2;
        let mid = [0, 1].map(|k| ((b2[k] as u32 + c2[k] as u32) / 2) as i32);
        let inward = match link.side {
            Side::V0 => [0, 1],
            Side::U1 => [-1, 0],
            Side::V1 => [0, -1],
            Side::U0 => [1, 0],
        };
        let apex = [0, 1].map(|k| (mid[k] + inward[k] * half as i32) as u16);
        let cross = |p: Point, q: Point| {
            let d = |x: Point| [x[0] as i64 - apex[0] as i64, x[1] as i64 - apex[1] as i64];
            let (p, q) = (d(p), d(q));
            p[0] * q[1] - p[1] * q[0]
        };
        let corners = if cross(b2, c2) > 0 {
            [apex, b2, c2]
        } else {
            [apex, c2, b2]
        };
        Some(Tri {
            patch: link.patch,
            corners,
        })
    }
}

/// The parameter along `side` of a point on it, in the side's own direction (`u` along
/// `V0` and `V1`, `v` along `U0` and `U1`, as [`Side`]'s edge points run).
pub(crate) fn side_parameter(side: Side, p: Point) -> u16 {
    match side {
        Side::V0 | Side::V1 => p[0],
        Side::U0 | Side::U1 => p[1],
    }
}

/// The point of `side` at side parameter `t`.
pub(crate) fn point_on(side: Side, t: u16) -> Point {
    match side {
        Side::V0 => [t, 0],
        Side::U1 => [ONE, t],
        Side::V1 => [t, ONE],
        Side::U0 => [0, t],
    }
}

/// Unit parameters of a grid point.
pub(crate) fn unit(p: Point) -> (f32, f32) {
    let s = 1.0 / ONE as f32;
    (p[0] as f32 * s, p[1] as f32 * s)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cross(t: &Tri) -> i64 {
        let [a, b, c] = t.corners.map(|p| [p[0] as i64, p[1] as i64]);
        (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    }

    /// Calls `f` on every triangle of patch 0's hierarchy down to `depth` levels.
    fn each(t: Tri, depth: u32, f: &mut impl FnMut(&Tri)) {
        f(&t);
        if depth > 0 {
            for h in t.children() {
                each(h, depth - 1, f);
            }
        }
    }

    #[test]
    fn halves_are_counter_clockwise_right_triangles_and_found_from_inside() {
        for r in Tri::roots(0) {
            each(r, 8, &mut |t| {
                assert!(cross(t) > 0, "{t:?}");
                let [a, b, c] = t.corners.map(|p| [p[0] as i64, p[1] as i64]);
                let dot = (b[0] - a[0]) * (c[0] - a[0]) + (b[1] - a[1]) * (c[1] - a[1]);
                assert_eq!(dot, 0, "right angle at the first corner");
                for (k, h) in t.children().iter().enumerate() {
                    assert_eq!(t.half_toward(h.centroid3()), k);
                }
                let mut x = Tri::roots(0)[t.root_index()];
                while x != *t {
                    x = x.children()[x.half_toward(t.centroid3())];
                }
            });
        }
    }

    #[test]
    fn the_triangle_across_is_across() {
        let links = |_, _| None;
        for r in Tri::roots(0) {
            each(r, 6, &mut |t| match t.across(links) {
                Some(n) => {
                    assert_eq!(n.corners[1], t.corners[2]);
                    assert_eq!(n.corners[2], t.corners[1]);
                    assert_eq!(n.across(links), Some(*t));
                }
                None => assert!(t.hypotenuse_side().is_some()),
            });
        }
    }

    #[test]
    fn across_a_shared_side_with_a_flip() {
        // Side U1 of patch 0 is side U0 of patch 1 running the other way.
        let mut links = [[None; 4]; 2];
        links[0][Side::U1.index()] = Some(SideLink {
            patch: 1,
            side: Side::U0,
            flip: true,
        });
        links[1][Side::U0.index()] = Some(SideLink {
            patch: 0,
            side: Side::U1,
            flip: true,
        });
        let m = ONE;
        let t = Tri {
            patch: 0,
            corners: [[m / 4 * 3, m / 4], [m, 0], [m, m / 2]],
        };
        let link = |p: u32, s: Side| links[p as usize][s.index()];
        let n = t.across(link).unwrap();
        assert_eq!(n.patch, 1);
        assert_eq!(n.corners[0], [m / 4, m / 4 * 3]);
        assert!(cross(&n) > 0);
        assert_eq!(n.across(link), Some(t));
    }
}
