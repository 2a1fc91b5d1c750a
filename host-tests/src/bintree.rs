//! Longest-edge bisection of patch domains, kept conforming: the bintree of ROAM and of
//! right-triangulated irregular networks, written for the oracle measurements
//! (`examples/oracle_selection.rs`, `examples/oracle_saturated.rs`). Each patch's unit square
//! is two right triangles; a triangle is halved at its hypotenuse's midpoint, and the one
//! across the hypotenuse too.

use std::collections::{BTreeSet, HashMap, HashSet};

use crate::reference::RefPatch;

/// A triangle of the bintree oracles: its patch, then its right-angle corner and the ends of
/// its hypotenuse, counter-clockwise, on a grid of `1 << BINTREE_BITS` steps per side.
pub type Bin = (usize, [[u32; 2]; 3]);

/// Steps per side of the bintree oracles' grid, as a power of two (their deepest triangles).
pub const BINTREE_BITS: u32 = 14;

/// Where a bintree corner is: a key two triangles share exactly when they share the corner.
pub type Spot = [i64; 3];

/// The two right triangles of each of `patches` patches' squares, the bintrees' roots.
pub fn roots(patches: usize) -> Vec<Bin> {
    let m = 1u32 << BINTREE_BITS;
    (0..patches)
        .flat_map(|p| [(p, [[0, 0], [m, 0], [0, m]]), (p, [[m, m], [0, m], [m, 0]])])
        .collect()
}

/// The roots of patches cut into cells as the kernel's hierarchy records them
/// (`HierarchyPatch::cells`: `2^a x 2^b` cells, counted along `v` first, each cut along its
/// diagonal from `(u1, v0)` to `(u0, v1)`, the triangle below it first), in the same order.
pub fn cell_roots(cells: &[[u8; 2]]) -> Vec<Bin> {
    let m = 1u32 << BINTREE_BITS;
    let mut out = Vec::new();
    for (p, &[a, b]) in cells.iter().enumerate() {
        let (w, h) = (m >> a, m >> b);
        for i in 0..1u32 << a {
            for j in 0..1u32 << b {
                let (u0, v0, u1, v1) = (i * w, j * h, (i + 1) * w, (j + 1) * h);
                out.push((p, [[u0, v0], [u1, v0], [u0, v1]]));
                out.push((p, [[u1, v1], [u0, v1], [u1, v0]]));
            }
        }
    }
    out
}

/// The two halves of triangle `t`, cut at its hypotenuse's midpoint: each has the midpoint
/// as its right-angle corner.
pub fn children((p, [a, b, c]): Bin) -> [Bin; 2] {
    let mid = [(b[0] + c[0]) / 2, (b[1] + c[1]) / 2];
    [(p, [mid, a, b]), (p, [mid, c, a])]
}

/// A grid point's parameters in the unit square.
pub fn unit([u, v]: [u32; 2]) -> [f64; 2] {
    let m = (1u32 << BINTREE_BITS) as f64;
    [u as f64 / m, v as f64 / m]
}

/// Where grid point `g` of patch `refs[p]` lies in model space, to 2^-30 of the model's
/// diagonal `diag`: a point of a curve two patches share lands on one spot from either.
pub fn model_spot(refs: &[RefPatch], diag: f64, p: usize, g: [u32; 2]) -> Spot {
    let q = diag / (1u64 << 30) as f64;
    let [u, v] = unit(g);
    refs[p].point(u, v).map(|x| (x / q).round() as i64)
}

/// The triangles of a bintree oracle on `patches` patches: each patch's square as two right
/// triangles, and every triangle whose `error` is over `tol` split at its hypotenuse's
/// midpoint, with the triangle across the hypotenuse split too (and those it needs first), so
/// the mesh stays conforming: the longest-edge bisection of ROAM and of right-triangulated
/// irregular networks. `spot` says where a corner is: with one spot per patch and grid point,
/// each patch is meshed on its own; with spots in model space, triangles across a curve that
/// two patches share conform too. The result is the coarsest conforming bisection mesh whose
/// triangles are all within `tol`, whatever the order of the splits.
pub fn bintree(
    patches: usize,
    tol: f64,
    spot: impl Fn(usize, [u32; 2]) -> Spot,
    error: impl Fn(Bin) -> f64,
) -> Vec<Bin> {
    bintree_from(roots(patches), tol, spot, error)
}

/// [`bintree`] from the given roots.
pub fn bintree_from(
    roots: Vec<Bin>,
    tol: f64,
    spot: impl Fn(usize, [u32; 2]) -> Spot,
    error: impl Fn(Bin) -> f64,
) -> Vec<Bin> {
    let mut mesh = Bisection {
        leaves: HashSet::new(),
        by_edge: HashMap::new(),
        spot: &spot,
    };
    for t in roots {
        mesh.add(t);
    }
    let mut judged: HashMap<Bin, bool> = HashMap::new();
    let mut over = |t: Bin| *judged.entry(t).or_insert_with(|| error(t) > tol);
    // Any order gives the same mesh: a triangle is split exactly when it or a finer
    // neighbour needs it.
    let mut queue: BTreeSet<Bin> = mesh.leaves.iter().copied().filter(|&t| over(t)).collect();
    while let Some(t) = queue.pop_first() {
        let mut made = Vec::new();
        mesh.split(t, &mut made);
        for c in made {
            if mesh.leaves.contains(&c) && over(c) {
                queue.insert(c);
            }
        }
    }
    let mut leaves: Vec<Bin> = mesh.leaves.into_iter().collect();
    leaves.sort_unstable();
    leaves
}

/// An edge of a bintree triangle: the spots of its ends, in order.
///
/// With its midpoint's spot too: where a patch side collapses to a pole, edges from one point
/// to the pole through different parameters have the same ends in model space, but not the
/// same midpoint, and they are not neighbours in the domain.
type Edge = (Spot, Spot, Spot);

/// The edge of patch `p` from grid point `a` to `b` as a key two triangles share exactly when
/// they share the edge, or `None` when its ends are one spot (a collapsed side, which has
/// nothing across).
pub fn edge_key(
    spot: &dyn Fn(usize, [u32; 2]) -> Spot,
    p: usize,
    a: [u32; 2],
    b: [u32; 2],
) -> Option<(Spot, Spot, Spot)> {
    let (x, y) = (spot(p, a), spot(p, b));
    let mid = spot(p, [(a[0] + b[0]) / 2, (a[1] + b[1]) / 2]);
    (x != y).then(|| if x < y { (x, y, mid) } else { (y, x, mid) })
}

/// The leaves of a bisection mesh, and the leaves on each edge.
struct Bisection<'a> {
    leaves: HashSet<Bin>,
    by_edge: HashMap<Edge, Vec<Bin>>,
    spot: &'a dyn Fn(usize, [u32; 2]) -> Spot,
}

impl Bisection<'_> {
    /// The edge from corner `i` to corner `j` of `t`, or `None` when its ends are one spot (a
    /// collapsed side), which has nothing across.
    fn edge(&self, t: Bin, i: usize, j: usize) -> Option<Edge> {
        edge_key(&self.spot, t.0, t.1[i], t.1[j])
    }

    fn add(&mut self, t: Bin) {
        self.leaves.insert(t);
        for (i, j) in [(0, 1), (1, 2), (2, 0)] {
            if let Some(e) = self.edge(t, i, j) {
                self.by_edge.entry(e).or_default().push(t);
            }
        }
    }

    fn remove(&mut self, t: Bin) {
        self.leaves.remove(&t);
        for (i, j) in [(0, 1), (1, 2), (2, 0)] {
            if let Some(v) = self.edge(t, i, j).and_then(|e| self.by_edge.get_mut(&e)) {
                v.retain(|&x| x != t);
            }
        }
    }

    /// The leaf other than `t` on `t`'s hypotenuse, if any.
    fn across(&self, t: Bin) -> Option<Bin> {
        let hypotenuse = self.edge(t, 1, 2)?;
        self.by_edge
            .get(&hypotenuse)
            .and_then(|v| v.iter().copied().find(|&x| x != t))
    }

    /// Halves leaf `t` at its hypotenuse's midpoint, and the leaf across it (split first where
    /// it is coarser, so that one of its halves shares the hypotenuse); pushes the new leaves
    /// on `made`. A triangle whose hypotenuse is one grid step long stays.
    fn split(&mut self, t: Bin, made: &mut Vec<Bin>) {
        let [_, b, c] = t.1;
        if !self.leaves.contains(&t) || b[0].abs_diff(c[0]) + b[1].abs_diff(c[1]) < 2 {
            return;
        }
        if let Some(n) = self.across(t) {
            if self.edge(n, 1, 2) != self.edge(t, 1, 2) {
                self.split(n, made);
            }
        }
        let pair = self.across(t);
        for x in [Some(t), pair].into_iter().flatten() {
            self.remove(x);
            for child in children(x) {
                self.add(child);
                made.push(child);
            }
        }
    }
}
