//! Whether a bisection tessellator could select its mesh top-down, with no memory of
//! neighbours, and still meet the error-control issue's triangle ratios: an oracle on the
//! views of the error-control table. Prints a Markdown table.
//!
//! ```text
//! cargo run --release -p host-tests --example oracle_saturated
//! ```
//!
//! `oracle_selection`'s shared-curve bintree splits a triangle when its own bound on screen
//! is over the tolerance, and then splits the triangle across its hypotenuse too, and those
//! that one needs first: a frame that does so must find neighbours, so it keeps its mesh in
//! memory. Lindstrom and Pascucci's terrain meshes need none. They give each bisection
//! *vertex* (the midpoint of a hypotenuse, shared by the one or two triangles on it) a test
//! that passes wherever the test of a vertex below it passes. Then a frame walks each
//! patch's two triangles down, splitting a triangle exactly when its hypotenuse's vertex
//! passes: the triangles on both sides of a hypotenuse see one vertex and decide alike, and
//! no split is ever needed under a triangle that stays whole, so the mesh is conforming.
//!
//! Here the test is `host_tests::screen_bound::region_bound` (sound and monotone; derived
//! there), and each vertex holds, as a bake would store it:
//!
//! - a box in model space holding its triangles' flat triangles and surface pieces (their
//!   corners' box widened by their bound in model units), and its children vertices' boxes;
//! - at most `K` deviation vectors and a remainder covering its triangles' deviations on the
//!   6-step lattice and its children vertices' vectors (`keep_vectors`, sound).
//!
//! The bake is the shared-curve bintree split in model space to `BAKE_REL` of the diagonal
//! (default 2.5e-4): a vertex below it has no record, so a triangle of its last level stays
//! whole (*left over* counts those whose own bound is over the tolerance; a run time would
//! refine them uniformly). For each `K` in 4 and 8, and for the rays of the box and their
//! rectangle (the cheaper form), the table gives the triangles against the verified uniform
//! grid, the vertices a frame tests per triangle, and, for the cheaper form with 8 vectors,
//! the median error on screen over the tolerance of the triangles that show. Each selection
//! is checked against `host_tests::bintree::bintree` with the same test, which finds
//! neighbours: the two meshes must be the same, but for triangles with a corner on a patch
//! side that collapses to a pole (the last column counts them). There, edges from one point
//! to the pole through different parameters are one segment in model space, and the mesh
//! that finds neighbours by model-space spots takes their triangles for neighbours, which
//! they are not in the domain: the top-down mesh is the one that conforms in the domain.
//!
//! The last columns judge each triangle by its own box and vectors (not saturated), splitting
//! the bake's triangles whose own test fails and, to keep the mesh conforming, those that
//! needs: what saturation costs. That mesh is found with one bit of state per baked vertex
//! (`select_with_bits`: rounds of the top-down walk, each setting the bits of the triangles
//! it keeps that fail and of the vertices above them, until a round sets none) and checked
//! to have no crack; the columns give its triangles, its rounds and the vertices it tested
//! per triangle, all rounds together (a cold frame).

use std::collections::{HashMap, HashSet};

use host_tests::bintree::{
    bintree, children, edge_key, model_spot, roots, unit, Bin, Spot, BINTREE_BITS,
};
use host_tests::model_file::ModelFile;
use host_tests::reference::{RefPatch, V3};
use host_tests::screen::{grid_size, triangle_deviation, Measure, Meter, ERROR_VIEWS};
use host_tests::screen_bound::{keep_vectors, lattice_deviations, region_bound, LATTICE};

/// Steps per side of a grid triangle (as `error_figures`).
const GRID_DENSE: usize = 8;
/// Barycentric steps per side of a measured triangle (as `error_figures`).
const DENSE: usize = 12;
/// Vectors a vertex keeps.
const KEEP: [usize; 2] = [4, 8];

/// A hypotenuse: the spots of its ends, in order, and of its midpoint (see
/// `host_tests::bintree::edge_key`).
type Key = (Spot, Spot, Spot);

/// What a vertex holds: a box, deviation vectors, a remainder.
#[derive(Clone, Debug)]
struct Region {
    lo: V3,
    hi: V3,
    vectors: Vec<V3>,
    remainder: f64,
}

impl Region {
    fn empty() -> Region {
        Region {
            lo: [f64::INFINITY; 3],
            hi: [f64::NEG_INFINITY; 3],
            vectors: Vec::new(),
            remainder: 0.0,
        }
    }

    /// Widens `self` to hold `other`.
    fn take(&mut self, other: &Region) {
        for k in 0..3 {
            self.lo[k] = self.lo[k].min(other.lo[k]);
            self.hi[k] = self.hi[k].max(other.hi[k]);
        }
        self.vectors.extend_from_slice(&other.vectors);
        self.remainder = self.remainder.max(other.remainder);
    }

    /// At most `keep` vectors, the rest covered by the remainder.
    fn kept(self, keep: usize) -> Region {
        let (vectors, remainder) = keep_vectors(self.vectors, keep, self.remainder);
        Region {
            vectors,
            remainder,
            ..self
        }
    }

    fn bound(&self, meter: &Meter, rect: bool) -> f64 {
        region_bound(
            meter,
            [self.lo, self.hi],
            &self.vectors,
            self.remainder,
            rect,
        )
    }
}

/// A model's bake: the vertices of its bisection mesh in model space, saturated.
struct Bake {
    /// The hypotenuse of every triangle that is split in the bake.
    split: HashMap<Bin, Key>,
    /// What each vertex holds, with at most `K` vectors, per `K` of [`KEEP`].
    vertices: Vec<HashMap<Key, Region>>,
    /// The bake's last triangles, each with its own region (8 vectors).
    leaves: HashMap<Bin, Region>,
    /// Every triangle of the bake below the patches' squares, with the one it was cut from.
    parent: HashMap<Bin, Bin>,
    /// The triangles split at each vertex (one, or two on a shared hypotenuse).
    on: HashMap<Key, Vec<Bin>>,
}

fn own_region(r: &RefPatch, uv: [[f64; 2]; 3]) -> Region {
    let d = lattice_deviations(r, uv, LATTICE).expect("a polynomial patch");
    let mut region = Region {
        vectors: d.vectors,
        remainder: d.remainder,
        ..Region::empty()
    };
    let m = d.object;
    for c in d.corners {
        region.take(&Region {
            lo: c.map(|x| x - m),
            hi: c.map(|x| x + m),
            ..Region::empty()
        });
    }
    region
}

fn bake(refs: &[RefPatch], tol: f64, spot: &dyn Fn(usize, [u32; 2]) -> Spot) -> Bake {
    let object = |(p, t): Bin| {
        lattice_deviations(&refs[p], t.map(unit), LATTICE).map_or(f64::INFINITY, |d| d.object)
    };
    let last: HashSet<Bin> = bintree(refs.len(), tol, spot, object).into_iter().collect();
    // A hypotenuse on a collapsed side has nothing across: a key of its own, in the domain.
    let hypotenuse = |(p, [_, b, c]): Bin| {
        edge_key(spot, p, b, c).unwrap_or_else(|| {
            let at = |g: [u32; 2]| [i64::MIN, p as i64, ((g[0] as i64) << 32) | g[1] as i64];
            (at(b), at(c), at(b))
        })
    };
    // Every triangle of the bake, level by level from the patches' squares.
    let mut levels: Vec<Vec<Bin>> = vec![roots(refs.len())];
    while let Some(level) = levels.last() {
        let next: Vec<Bin> = level
            .iter()
            .filter(|t| !last.contains(t))
            .flat_map(|&t| children(t))
            .collect();
        if next.is_empty() {
            break;
        }
        levels.push(next);
    }
    let split: HashMap<Bin, Key> = levels
        .iter()
        .flatten()
        .filter(|t| !last.contains(t))
        .map(|&t| (t, hypotenuse(t)))
        .collect();
    let vertices = KEEP
        .iter()
        .map(|&keep| {
            let mut done: HashMap<Key, Region> = HashMap::new();
            for level in levels.iter().rev() {
                let mut open: HashMap<Key, Region> = HashMap::new();
                for &t in level.iter().filter(|t| split.contains_key(t)) {
                    let region = open.entry(split[&t]).or_insert_with(Region::empty);
                    region.take(&own_region(&refs[t.0], t.1.map(unit)));
                    for c in children(t) {
                        if let Some(k) = split.get(&c) {
                            region.take(&done[k]);
                        }
                    }
                }
                done.extend(open.into_iter().map(|(k, r)| (k, r.kept(keep))));
            }
            done
        })
        .collect();
    let leaves = last
        .iter()
        .map(|&t| (t, own_region(&refs[t.0], t.1.map(unit)).kept(8)))
        .collect();
    let parent = split
        .keys()
        .flat_map(|&t| children(t).map(|c| (c, t)))
        .collect();
    let mut on: HashMap<Key, Vec<Bin>> = HashMap::new();
    for (&t, &k) in &split {
        on.entry(k).or_default().push(t);
    }
    Bake {
        split,
        vertices,
        leaves,
        parent,
        on,
    }
}

/// The selection that finds neighbours with one bit of state per baked vertex and nothing
/// else: rounds of a top-down walk that splits a triangle where its vertex's bit is set, and
/// sets the bit of every triangle it keeps whose own test `over` fails, with the bits of the
/// vertices above it (the two triangles split at a vertex must both be there, so their
/// parents must be split), until a round sets none. Its triangles, the rounds, and the
/// tests it made.
fn select_with_bits(
    bake: &Bake,
    over: &dyn Fn(Bin) -> bool,
    patches: usize,
) -> (Vec<Bin>, usize, usize) {
    let mut bits: HashSet<Key> = HashSet::new();
    let (mut rounds, mut tests) = (0, 0);
    loop {
        rounds += 1;
        let mut leaves = Vec::new();
        let mut set = Vec::new();
        let mut stack = roots(patches);
        while let Some(t) = stack.pop() {
            match bake.split.get(&t) {
                Some(k) if bits.contains(k) => stack.extend(children(t)),
                Some(k) => {
                    tests += 1;
                    if over(t) {
                        set.push(*k);
                    }
                    leaves.push(t);
                }
                None => leaves.push(t),
            }
        }
        if set.is_empty() {
            leaves.sort_unstable();
            return (leaves, rounds, tests);
        }
        while let Some(k) = set.pop() {
            if bits.insert(k) {
                for t in &bake.on[&k] {
                    if let Some(p) = bake.parent.get(t) {
                        set.push(bake.split[p]);
                    }
                }
            }
        }
    }
}

/// One top-down selection: its triangles, the vertices it tested, and the bake's last
/// triangles it keeps whose own bound is over `tol`.
struct Selected {
    leaves: Vec<Bin>,
    tested: usize,
    left_over: usize,
}

fn select(bake: &Bake, k: usize, meter: &Meter, tol: f64, rect: bool, patches: usize) -> Selected {
    let mut out = Selected {
        leaves: Vec::new(),
        tested: 0,
        left_over: 0,
    };
    let mut stack = roots(patches);
    while let Some(t) = stack.pop() {
        match bake.split.get(&t) {
            Some(key) => {
                out.tested += 1;
                if bake.vertices[k][key].bound(meter, rect) > tol {
                    stack.extend(children(t));
                } else {
                    out.leaves.push(t);
                }
            }
            None => {
                if bake.leaves[&t].bound(meter, rect) > tol {
                    out.left_over += 1;
                }
                out.leaves.push(t);
            }
        }
    }
    out.leaves.sort_unstable();
    out
}

/// Whether the mesh of bintree triangles `leaves` has no crack: no edge (between two spots)
/// whose midpoint is a corner of a triangle, in the domain or across a shared curve.
fn conforming(leaves: &[Bin], spot: &dyn Fn(usize, [u32; 2]) -> Spot) -> bool {
    let corners: HashSet<Spot> = leaves
        .iter()
        .flat_map(|&(p, t)| t.map(|g| spot(p, g)))
        .collect();
    leaves.iter().all(|&(p, t)| {
        [(0, 1), (1, 2), (2, 0)].iter().all(|&(i, j)| {
            let (a, b) = (t[i], t[j]);
            let mid = [(a[0] + b[0]) / 2, (a[1] + b[1]) / 2];
            spot(p, a) == spot(p, b) || !corners.contains(&spot(p, mid))
        })
    })
}

/// Whether grid point `g` of patch `p` lies on a side of its square whose ends are one spot.
fn on_collapsed_side(p: usize, [u, v]: [u32; 2], spot: &dyn Fn(usize, [u32; 2]) -> Spot) -> bool {
    let m = 1u32 << BINTREE_BITS;
    let sides = [
        (v == 0, [0, 0], [m, 0]),
        (u == m, [m, 0], [m, m]),
        (v == m, [0, m], [m, m]),
        (u == 0, [0, 0], [0, m]),
    ];
    sides
        .iter()
        .any(|&(on, a, b)| on && spot(p, a) == spot(p, b))
}

fn main() {
    let bake_rel: f64 = std::env::var("BAKE_REL")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(2.5e-4);
    println!(
        "Bake: the shared-curve bintree split in model space to {bake_rel:e} of the diagonal."
    );
    println!();
    println!(
        "| case | grid | saturated, 4 vectors, rays / grid | 8 vectors, rays / grid \
         | 4 vectors, rectangle / grid | 8 vectors, rectangle / grid \
         | 8 vectors, rectangle, unsaturated, one bit per vertex / grid \
         | its rounds, vertices tested per triangle \
         | vertices tested per triangle (8, rectangle) | left over (8, rectangle) \
         | median error / tol (8, rectangle) | differences at poles |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    let mut bakes: Vec<(&str, ModelFile, Vec<RefPatch>, Bake, usize)> = Vec::new();
    for view in ERROR_VIEWS {
        let model = view.model;
        if !bakes.iter().any(|(m, ..)| *m == model) {
            let path = host_tests::models_dir().join(model);
            let file = ModelFile::read(path.to_str().expect("a UTF-8 path")).expect("a model");
            let patches = file.patches();
            let refs: Vec<RefPatch> = patches.iter().map(|p| RefPatch::from_kernel(&p)).collect();
            let diag = patches.aabb().expect("patches").diagonal() as f64;
            let b = bake(&refs, bake_rel * diag, &|p, g| {
                model_spot(&refs, diag, p, g)
            });
            let vertices = b.vertices[0].len();
            bakes.push((model, file, refs, b, vertices));
        }
        let (_, file, refs, b, _) = bakes.iter().find(|(m, ..)| *m == model).expect("baked");
        let patches = file.patches();
        let diag = patches.aabb().expect("patches").diagonal() as f64;
        let [eye, target] = [view.eye, view.target].map(|p| p.map(|c| c as f64));
        let meter = Meter::new(
            eye,
            target,
            [0.0, 0.0, 1.0],
            40.0,
            0.01 * diag,
            view.viewport,
        );
        let tol = view.tol as f64;
        let grid: usize = refs
            .iter()
            .map(|r| {
                grid_size(r, tol, GRID_DENSE, 512, Measure::Screen(&meter))
                    .map_or(2 * 511 * 511, |n| 2 * (n - 1) * (n - 1))
            })
            .sum();
        let spot = |p: usize, g: [u32; 2]| model_spot(refs, diag, p, g);
        let at_pole = |&(p, t): &Bin| t.iter().any(|&g| on_collapsed_side(p, g, &spot));
        let mut cells = Vec::new();
        let mut cheap = None;
        let mut poles = 0;
        for rect in [false, true] {
            for k in 0..KEEP.len() {
                let s = select(b, k, &meter, tol, rect, refs.len());
                // The same test through a mesh that finds its neighbours: the same mesh.
                let test = |t: Bin| match b.split.get(&t) {
                    Some(key) => b.vertices[k][key].bound(&meter, rect),
                    None => 0.0,
                };
                let check = bintree(refs.len(), tol, spot, test);
                // (Where a patch side collapses to a pole, edges from one point to the pole
                // through different parameters are one segment in model space: the mesh that
                // finds neighbours by model-space spots takes them for neighbours, which they
                // are not in the domain. Only triangles at a pole may differ.)
                let check: HashSet<Bin> = check.into_iter().collect();
                let top_down: HashSet<Bin> = s.leaves.iter().copied().collect();
                let differ: Vec<&Bin> = check.symmetric_difference(&top_down).collect();
                assert!(
                    differ.iter().all(|t| at_pole(t)),
                    "{}: a top-down selection that does not conform: {differ:?}",
                    view.name
                );
                poles += differ.len();
                cells.push(format!("{:.2}", s.leaves.len() as f64 / grid as f64));
                if rect && k + 1 == KEEP.len() {
                    cheap = Some(s);
                }
            }
        }
        let s = cheap.expect("the cheaper form with 8 vectors");
        // The same regions without saturation, each triangle judged by its own, its mesh
        // kept conforming with one bit per baked vertex.
        let own = |(p, t): Bin| {
            own_region(&refs[p], t.map(unit))
                .kept(KEEP[KEEP.len() - 1])
                .bound(&meter, true)
        };
        let judged = std::cell::RefCell::new(HashMap::new());
        let over = |t: Bin| *judged.borrow_mut().entry(t).or_insert_with(|| own(t) > tol);
        let (with_bits, rounds, tests) = select_with_bits(b, &over, refs.len());
        assert!(
            conforming(&with_bits, &spot),
            "{}: one bit per vertex leaves a crack",
            view.name
        );
        let (unsaturated, tests) = (
            with_bits.len() as f64 / grid as f64,
            tests as f64 / with_bits.len() as f64,
        );
        let mut errors: Vec<f64> = s
            .leaves
            .iter()
            .map(|&(p, t)| {
                let uv = t.map(unit);
                let corners = uv.map(|[u, v]| refs[p].point(u, v));
                triangle_deviation(&refs[p], uv, corners, DENSE, Measure::Screen(&meter)).worst
                    / tol
            })
            .filter(|&e| e > 0.0)
            .collect();
        errors.sort_by(f64::total_cmp);
        println!(
            "| {} | {grid} | {} | {unsaturated:.2} | {rounds}, {tests:.2} | {:.2} | {} | {:.2} | {poles} |",
            view.name,
            cells.join(" | "),
            s.tested as f64 / s.leaves.len() as f64,
            s.left_over,
            errors.get(errors.len() / 2).copied().unwrap_or(f64::NAN),
        );
    }
    println!();
    println!("| model | bake's vertices | bake's last triangles |");
    println!("|---|---|---|");
    for (model, _, _, b, vertices) in &bakes {
        println!("| {model} | {vertices} | {} |", b.leaves.len());
    }
}
