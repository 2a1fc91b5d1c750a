//! Where the triangles of the bisection hierarchy are: corners on a grid of `2^15` steps per
//! side, halves, and the triangle across a hypotenuse, in the same patch or across a shared
//! curve.
//!
//! # Cells
//!
//! A patch's square is cut into `2^a x 2^b` cells ([`Cells`], `a, b <= 3`), each cut along
//! its diagonal into the two roots of its hierarchy: a patch twice as long on screen in `u`
//! as in `v` takes `2 x 1` cells, and its triangles are then as long as wide on screen. A
//! cell is a square in its own coordinates, where halving is the longest-edge bisection of a
//! square; in the patch's parameters that is an affine image, so midpoints, halves and
//! mirror images stay the same computations. The tests of where a point lies (which half,
//! which root) take the *cell units*: grid steps divided by `2^(3 - a)` along `u` and by
//! `2^(3 - b)` along `v`, where every cell is `2^12` units square and every triangle right and
//! isosceles. A triangle is halved only where the midpoint is a point of that lattice (`2^12`
//! steps a cell side, 24 halvings a cell), so a triangle and its mirror across a shared curve
//! are both on it whatever the two patches' cells.

use crate::patch::Side;

/// The grid value of parameter 1 (a power of two, so that every midpoint of the hierarchy
/// down to one grid step is a grid point and every grid point a float).
pub(crate) const ONE: u16 = 1 << 15;

/// A point of the grid, `[u, v]`.
pub(crate) type Point = [u16; 2];

/// How a patch's square is cut into cells: `2^cells[0]` along `u` by `2^cells[1]` along `v`
/// (see the module docs).
pub type Cells = [u8; 2];

/// The most cell levels in one direction: eight cells.
pub const MAX_CELL_LEVEL: u8 = 3;

/// Cell units per cell side: `2^12`.
const CELL: i32 = 1 << (15 - MAX_CELL_LEVEL);

/// Grid steps per cell unit along `u` and along `v`, as shifts.
fn unit_shift(cells: Cells) -> [u32; 2] {
    [0, 1].map(|k| (MAX_CELL_LEVEL - cells[k].min(MAX_CELL_LEVEL)) as u32)
}

/// `p` (grid steps, or a sum of grid points) in cell units: exact for points of the lattice.
fn in_cell_units(p: [i32; 2], cells: Cells) -> [i32; 2] {
    let s = unit_shift(cells);
    [p[0] >> s[0], p[1] >> s[1]]
}

/// The number of roots of a patch with `cells`: two per cell.
pub(crate) fn root_count(cells: Cells) -> usize {
    2 << (cells[0] + cells[1])
}

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
    /// Root `k` of patch `patch` ([`root_count`] of them): cell `k / 2`, counted along `v`
    /// first (cell `(i, j)` is `i 2^b + j`), cut along its diagonal from `(u1, v0)` to
    /// `(u0, v1)`; `k` even takes the triangle below it, odd the one above.
    pub(crate) fn root(patch: u32, cells: Cells, k: usize) -> Tri {
        let rows = 1usize << cells[1];
        let (i, j) = ((k / 2) / rows, (k / 2) % rows);
        let (w, h) = (ONE as usize >> cells[0], ONE as usize >> cells[1]);
        let (u0, v0) = ((i * w) as u16, (j * h) as u16);
        let (u1, v1) = (((i + 1) * w) as u16, ((j + 1) * h) as u16);
        Tri {
            patch,
            corners: if k.is_multiple_of(2) {
                [[u0, v0], [u1, v0], [u0, v1]]
            } else {
                [[u1, v1], [u0, v1], [u1, v0]]
            },
        }
    }

    /// The hypotenuse's midpoint.
    pub(crate) fn midpoint(&self) -> Point {
        let [_, b, c] = self.corners;
        [
            ((b[0] as u32 + c[0] as u32) / 2) as u16,
            ((b[1] as u32 + c[1] as u32) / 2) as u16,
        ]
    }

    /// Whether the hypotenuse's midpoint is a point of the lattice of cell units (the
    /// triangle can be halved), in a patch with `cells`.
    pub(crate) fn can_split(&self, cells: Cells) -> bool {
        let [_, b, c] = self.corners;
        let s = unit_shift(cells);
        b != c
            && (b[0] as u32 + c[0] as u32).is_multiple_of(2 << s[0])
            && (b[1] as u32 + c[1] as u32).is_multiple_of(2 << s[1])
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
    /// point, strictly inside one half), in a patch with `cells`.
    ///
    /// The halves meet on the line from the hypotenuse's midpoint `m` to the right angle `a`.
    /// In cell units a triangle of the hierarchy is right and isosceles, its legs along the
    /// axes or the diagonals, so `a - m` is `L (u_x, u_y)` with `u` in `{-1, 0, 1}²` and
    /// `L > 0`: the side of that line a point lies on is the sign of
    /// `u_x (q_y - m_y) - u_y (q_x - m_x)`, exact in `i32` (coordinates below `2^17`), where
    /// the cross product with `a - m` itself would take 64 bits. The corners, the midpoint and
    /// `p3` are points (or sums of points) of the lattice, so in cell units they are exact.
    pub(crate) fn half_toward(&self, p3: [i32; 2], cells: Cells) -> usize {
        let to = |p: Point| in_cell_units([p[0] as i32, p[1] as i32], cells);
        let [a, b, _] = self.corners.map(to);
        let m = to(self.midpoint());
        let p3 = in_cell_units(p3, cells);
        let u = [(a[0] - m[0]).signum(), (a[1] - m[1]).signum()];
        let side = |q: [i32; 2]| u[0] * q[1] - u[1] * q[0];
        let p = side([p3[0] - 3 * m[0], p3[1] - 3 * m[1]]);
        if (p > 0) == (side([b[0] - m[0], b[1] - m[1]]) > 0) {
            0
        } else {
            1
        }
    }

    /// Which root of its patch ([`root`](Self::root)) holds this triangle, in a patch with
    /// `cells`: the cell of its centroid, then the side of the cell's diagonal (in cell units,
    /// where the centroid is exact and strictly inside one root).
    pub(crate) fn root_index(&self, cells: Cells) -> usize {
        let c = in_cell_units(self.centroid3(), cells);
        let (i, j) = (c[0] / (3 * CELL), c[1] / (3 * CELL));
        let rows = 1usize << cells[1];
        let cell = (i.max(0) as usize * rows + j.max(0) as usize).min(root_count(cells) / 2 - 1);
        let inside = [c[0] - 3 * CELL * i, c[1] - 3 * CELL * j];
        2 * cell + usize::from(inside[0] + inside[1] > 3 * CELL)
    }

    /// Halvings from its cell's diagonal to this triangle, in a patch with `cells` (a root
    /// is level 0; two halvings halve a side).
    pub(crate) fn level(&self, cells: Cells) -> u8 {
        let [_, b, c] = self.corners;
        let d = in_cell_units(
            [b[0] as i32 - c[0] as i32, b[1] as i32 - c[1] as i32],
            cells,
        );
        let span = d[0].unsigned_abs().max(d[1].unsigned_abs());
        // Even levels have a diagonal hypotenuse, odd ones one along an axis; two levels
        // halve its span (level 0: the cell's diagonal, span `CELL`).
        let diagonal = d[0] != 0 && d[1] != 0;
        let halvings = (CELL as u32 / span.max(1)).trailing_zeros() as u8;
        2 * halvings + u8::from(!diagonal)
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
    /// gives what a patch's side joins, `cells` a patch's cells). `None` on an open or
    /// collapsed side.
    ///
    /// Across a curve the two triangles are mirror images in cell units: the two patches cut
    /// the curve into the same number of cells (the bake chooses cells so, and a hierarchy
    /// is checked for it), so the hypotenuse is as long in either's cell units, and the
    /// apex is half of it inside the other patch, scaled to its grid along its inward
    /// direction.
    pub(crate) fn across(
        &self,
        link: impl Fn(u32, Side) -> Option<SideLink>,
        cells: impl Fn(u32) -> Cells,
    ) -> Option<Tri> {
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
        let along = |s: Side| match s {
            Side::V0 | Side::V1 => 0,
            Side::U1 | Side::U0 => 1,
        };
        let (ours, theirs) = (cells(self.patch), cells(link.patch));
        // Half the hypotenuse in cell units, then in the other patch's grid steps inward.
        let half_cells = (side_parameter(side, b).abs_diff(side_parameter(side, c)) / 2)
            >> unit_shift(ours)[along(side)];
        let half = half_cells << unit_shift(theirs)[1 - along(link.side)];
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

/// Whether grid point `p` lies on side `side` of the square.
pub(crate) fn on_side(side: Side, p: Point) -> bool {
    match side {
        Side::V0 => p[1] == 0,
        Side::U1 => p[0] == ONE,
        Side::V1 => p[1] == ONE,
        Side::U0 => p[0] == 0,
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

    /// Every cut of a square the bake may choose.
    fn every_cells() -> impl Iterator<Item = Cells> {
        (0..=MAX_CELL_LEVEL).flat_map(|a| (0..=MAX_CELL_LEVEL).map(move |b| [a, b]))
    }

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
    fn roots_tile_the_square() {
        for cells in every_cells() {
            let n = root_count(cells);
            let area: i64 = (0..n).map(|k| cross(&Tri::root(0, cells, k))).sum();
            assert_eq!(area, 2 * (ONE as i64) * (ONE as i64), "{cells:?}");
            for k in 0..n {
                let t = Tri::root(0, cells, k);
                assert!(cross(&t) > 0);
                assert_eq!(t.root_index(cells), k, "{cells:?} {k}");
                assert_eq!(t.level(cells), 0);
            }
        }
    }

    #[test]
    fn halves_are_right_triangles_in_cell_units_and_found_from_inside() {
        for cells in every_cells() {
            for k in 0..root_count(cells) {
                each(Tri::root(0, cells, k), 7, &mut |t| {
                    assert!(cross(t) > 0, "{t:?}");
                    let [a, b, c] = t.corners.map(|p| {
                        let q = in_cell_units([p[0] as i32, p[1] as i32], cells);
                        [q[0] as i64, q[1] as i64]
                    });
                    let dot = (b[0] - a[0]) * (c[0] - a[0]) + (b[1] - a[1]) * (c[1] - a[1]);
                    assert_eq!(dot, 0, "right angle at the first corner in cell units");
                    assert!(t.can_split(cells));
                    for (i, h) in t.children().iter().enumerate() {
                        assert_eq!(t.half_toward(h.centroid3(), cells), i);
                        assert_eq!(h.level(cells), t.level(cells) + 1);
                    }
                    let mut x = Tri::root(0, cells, t.root_index(cells));
                    while x != *t {
                        x = x.children()[x.half_toward(t.centroid3(), cells)];
                    }
                });
            }
        }
    }

    #[test]
    fn halving_stops_at_the_lattice() {
        for cells in every_cells() {
            let mut t = Tri::root(0, cells, 0);
            let mut levels = 0;
            while t.can_split(cells) {
                t = t.children()[0];
                levels += 1;
            }
            assert_eq!(levels, 24, "{cells:?}");
        }
    }

    #[test]
    fn the_triangle_across_is_across() {
        let links = |_, _| None;
        for cells in every_cells() {
            let shape = |_| cells;
            for k in 0..root_count(cells) {
                each(
                    Tri::root(0, cells, k),
                    6,
                    &mut |t| match t.across(links, shape) {
                        Some(n) => {
                            assert_eq!(n.corners[1], t.corners[2]);
                            assert_eq!(n.corners[2], t.corners[1]);
                            assert_eq!(n.across(links, shape), Some(*t));
                        }
                        None => assert!(t.hypotenuse_side().is_some()),
                    },
                );
            }
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
        let square = |_| [0, 0];
        let n = t.across(link, square).unwrap();
        assert_eq!(n.patch, 1);
        assert_eq!(n.corners[0], [m / 4, m / 4 * 3]);
        assert!(cross(&n) > 0);
        assert_eq!(n.across(link, square), Some(t));
        // Both cut into two along v (the curve), patch 1 into four along u (its inward
        // direction): the lower cell of patch 0 (its right triangle on the side reaches
        // half way in, as the cell is half as high), and across it a triangle a quarter as
        // deep (a cell of patch 1 is a quarter of its width).
        let cells = |p: u32| if p == 0 { [0, 1] } else { [2, 1] };
        let t = Tri {
            patch: 0,
            corners: [[m / 2, m / 4], [m, 0], [m, m / 2]],
        };
        assert_eq!(t.level(cells(0)), 1);
        let n = t.across(link, cells).unwrap();
        assert_eq!(n.corners[0], [m / 8, m / 4 * 3]);
        assert_eq!(n.level(cells(1)), 1);
        assert!(cross(&n) > 0);
        assert_eq!(n.across(link, cells), Some(t));
    }

    #[test]
    fn across_every_side_and_cells() {
        // Patch 0's side `s` is patch 1's side `o`, either way round; each cut so that the
        // curve has as many cells on both: every triangle on the curve finds its mirror,
        // which finds it.
        for s in Side::ALL {
            for o in Side::ALL {
                for flip in [false, true] {
                    for ours in every_cells() {
                        for theirs in every_cells() {
                            let along = |x: Side, c: Cells| match x {
                                Side::V0 | Side::V1 => c[0],
                                _ => c[1],
                            };
                            if along(s, ours) != along(o, theirs) {
                                continue;
                            }
                            let link = |p: u32, side: Side| match (p, side) {
                                (0, x) if x == s => Some(SideLink {
                                    patch: 1,
                                    side: o,
                                    flip,
                                }),
                                (1, x) if x == o => Some(SideLink {
                                    patch: 0,
                                    side: s,
                                    flip,
                                }),
                                _ => None,
                            };
                            let cells = |p: u32| if p == 0 { ours } else { theirs };
                            for k in 0..root_count(ours) {
                                each(Tri::root(0, ours, k), 5, &mut |t| {
                                    if t.hypotenuse_side() != Some(s) {
                                        return;
                                    }
                                    let n = t.across(link, cells).unwrap();
                                    assert_eq!(n.patch, 1);
                                    assert!(cross(&n) > 0);
                                    assert_eq!(n.level(theirs), t.level(ours));
                                    assert_eq!(n.across(link, cells), Some(*t));
                                    // The mirror is a triangle of patch 1's hierarchy.
                                    let mut x = Tri::root(1, theirs, n.root_index(theirs));
                                    while x != n {
                                        assert!(x.level(theirs) < n.level(theirs));
                                        x = x.children()[x.half_toward(n.centroid3(), theirs)];
                                    }
                                });
                            }
                        }
                    }
                }
            }
        }
    }
}
