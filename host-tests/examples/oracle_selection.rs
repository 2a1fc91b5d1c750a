//! How few triangles a selection of this kind could reach: oracle tessellators beside the
//! verified uniform grid, on the views of the error-control table, two with a perfect error
//! measure and two with a sound bound. Prints a Markdown table.
//!
//! ```text
//! cargo run --release -p host-tests --example oracle_selection
//! ```
//!
//! Both oracles triangulate each patch on its own (as the grid does: no shared boundaries, so
//! cracks), by Delaunay insertion in (u,v) with the kernel's `DomainMesh`, starting from the
//! square's two triangles, and both measure a triangle's error exactly as `error_figures`
//! does: the surface against the triangle's linear interpolant at the same (u,v), 12 steps
//! per side with the `f64` reference, projected, only samples on screen counting. Neither is
//! sound (sampled, not bounded) nor crack-free, and greedy insertion is not optimal: they show
//! what a tessellator that is both, selecting the same way, can hope for before a bound's
//! margin and shared boundaries.
//!
//! - *Adaptive*: inserts the worst point of the triangle with the largest projected error
//!   until every triangle is within the tolerance. Each triangle is judged by its own
//!   projection: the selection is not a prefix of any fixed order.
//! - *Nested*: inserts in the order of largest *object-space* error (the view-independent
//!   order a bake records) and stops at the shortest prefix whose every triangle is within
//!   the tolerance on screen: Chhugani & Kumar's per-patch prefix, with an exact measure in
//!   place of a bound and no curve sampled apart.
//!
//! The other two select as *adaptive* does, but judge each triangle by a computed bound of its
//! deviation on screen (`host_tests::screen_bound`, where both are derived) instead of the
//! sampled error, and stop when every bound is within the tolerance: a selection that is
//! sound, still without shared boundaries.
//!
//! - *Isotropic bound*: the triangle's bound in model units times the largest scale of the
//!   projection over the triangle, the form the kernel's run time uses.
//! - *Directional bound*: the deviation vectors of the triangle's lattice projected one by one
//!   at the corners' view rays, plus the remainder: a deviation along the line of sight moves
//!   no pixel, and this bound sees it. Its last column checks it: the bound over the triangle's
//!   deviation on screen sampled at 24 steps per side (a sound bound is at least 1).

use std::collections::HashMap;

use host_tests::model_file::ModelFile;
use host_tests::reference::{dist, RefPatch, V3};
use host_tests::screen::{grid_size, triangle_deviation, Measure, Meter, ERROR_VIEWS};
use host_tests::screen_bound::screen_bound;
use spline_tess::{DomainMesh, GridPoint, MeshTriangle, MeshVertex};

/// Barycentric steps per side of a measured triangle (as `error_figures`).
const DENSE: usize = 12;
/// Barycentric steps per side when a bound is checked.
const CHECK_DENSE: usize = 24;
/// Steps per side of a grid triangle (as `error_figures`).
const GRID_DENSE: usize = 8;
/// Vertex slots per patch; no case comes near.
const VERTICES: usize = 1 << 14;

/// A triangle's largest error and where it is, in (u,v).
#[derive(Clone, Copy)]
struct Worst {
    error: f64,
    at: [f64; 2],
}

/// How an oracle judges a triangle and picks the next point.
#[derive(Clone, Copy, PartialEq)]
enum Selection {
    /// The sampled error on screen.
    Adaptive,
    /// The prefix of the order of the sampled error in model units.
    Nested,
    /// The isotropic bound on screen.
    Isotropic,
    /// The directional bound on screen.
    Directional,
}

/// The largest projected and object-space errors of the triangle with corner parameters
/// `uv` on patch `r`.
fn measure(r: &RefPatch, uv: [[f64; 2]; 3], meter: &Meter) -> (Worst, Worst) {
    let corners: [V3; 3] = uv.map(|[u, v]| r.point(u, v));
    let none = Worst {
        error: 0.0,
        at: [0.0; 2],
    };
    let (mut screen, mut object) = (none, none);
    for i in 0..=DENSE {
        for j in 0..=DENSE - i {
            let (a, b) = (i as f64 / DENSE as f64, j as f64 / DENSE as f64);
            let c = 1.0 - a - b;
            let at = [0, 1].map(|k| uv[0][k] * c + uv[1][k] * a + uv[2][k] * b);
            let s = r.point(at[0], at[1]);
            let l = [0, 1, 2].map(|k| corners[0][k] * c + corners[1][k] * a + corners[2][k] * b);
            if let Some(d) = meter.deviation(s, l) {
                if d > screen.error {
                    screen = Worst { error: d, at };
                }
            }
            let d = dist(s, l);
            if d > object.error {
                object = Worst { error: d, at };
            }
        }
    }
    (screen, object)
}

/// How one triangle is judged: the value held against the tolerance, and the value and
/// point that order the insertions.
fn judge(r: &RefPatch, uv: [[f64; 2]; 3], meter: &Meter, selection: Selection) -> (f64, Worst) {
    match selection {
        Selection::Adaptive | Selection::Nested => {
            let (screen, object) = measure(r, uv, meter);
            let order = if selection == Selection::Nested {
                object
            } else {
                screen
            };
            (screen.error, order)
        }
        Selection::Isotropic | Selection::Directional => {
            let b = screen_bound(r, uv, meter).expect("a polynomial patch");
            let error = if selection == Selection::Isotropic {
                b.isotropic
            } else {
                b.hull
            };
            (error, Worst { error, at: b.at })
        }
    }
}

/// The final triangles of one oracle on patch `r`: corner parameters, and the value each was
/// held to (its bound, for the bounded selections).
fn oracle(r: &RefPatch, meter: &Meter, tol: f64, selection: Selection) -> Vec<Judged> {
    let mut vertices = vec![MeshVertex::default(); VERTICES];
    let mut triangles = vec![MeshTriangle::default(); DomainMesh::triangles_for(VERTICES)];
    let mut mesh = DomainMesh::new(&mut vertices, &mut triangles).expect("room for the square");
    let mut judged: HashMap<[GridPoint; 3], (f64, Worst)> = HashMap::new();
    let unit = |p: GridPoint| [p.u, p.v].map(|c| c as f64 / GridPoint::MAX as f64);
    let keys = |mesh: &DomainMesh<'_>| -> Vec<[GridPoint; 3]> {
        mesh.triangles()
            .map(|ids| {
                let mut key = ids.map(|id| mesh.point(id).expect("a vertex of the mesh"));
                key.sort_by_key(|p| (p.u, p.v));
                key
            })
            .collect()
    };
    loop {
        let (mut worst, mut next): (f64, Option<(Worst, [GridPoint; 3])>) = (0.0, None);
        for key in keys(&mesh) {
            let (held, order) = *judged
                .entry(key)
                .or_insert_with(|| judge(r, key.map(unit), meter, selection));
            worst = worst.max(held);
            // The nested order runs over every triangle; the others refine one over.
            let candidate = selection == Selection::Nested || held > tol;
            if candidate && next.is_none_or(|(n, _)| order.error > n.error) {
                next = Some((order, key));
            }
        }
        let done = |mesh: &DomainMesh<'_>| {
            let held = |k: &[GridPoint; 3]| judged[k].0;
            keys(mesh).iter().map(|k| (k.map(unit), held(k))).collect()
        };
        let Some((next, key)) = next.filter(|_| worst > tol) else {
            return done(&mesh);
        };
        let [u, v] = next.at.map(|c| (c * GridPoint::MAX as f64).round() as u16);
        let midpoint = |(a, b): (GridPoint, GridPoint)| GridPoint {
            u: ((a.u as u32 + b.u as u32) / 2) as u16,
            v: ((a.v as u32 + b.v as u32) / 2) as u16,
        };
        let edges = [(0, 1), (1, 2), (2, 0)].map(|(i, j)| (key[i], key[j]));
        // Where the worst point rounds to a vertex (a sliver), the longest edge's midpoint.
        let longest = edges
            .into_iter()
            .max_by_key(|(a, b)| {
                (a.u.abs_diff(b.u) as u32).pow(2) + (a.v.abs_diff(b.v) as u32).pow(2)
            })
            .map(midpoint)
            .expect("three edges");
        if mesh.insert(GridPoint { u, v }).is_err() && mesh.insert(longest).is_err() {
            eprintln!("a patch stopped at {worst:.3} px: no point left to insert");
            return done(&mesh);
        }
    }
}

/// A final triangle's corner parameters and the value it was held to.
type Judged = ([[f64; 2]; 3], f64);

/// Bound over sampled deviation, on screen, of every triangle (held to its bound) with
/// something on screen.
fn bound_over_true(r: &RefPatch, triangles: &[Judged], meter: &Meter) -> Vec<f64> {
    triangles
        .iter()
        .filter_map(|&(uv, bound)| {
            let corners = uv.map(|[u, v]| r.point(u, v));
            let sampled = triangle_deviation(r, uv, corners, CHECK_DENSE, Measure::Screen(meter));
            (sampled.worst > 0.0).then(|| bound / sampled.worst)
        })
        .collect()
}

fn main() {
    println!(
        "| case | grid | adaptive oracle | adaptive / grid | nested oracle | nested / grid \
         | isotropic bound | isotropic / grid | directional bound | directional / grid \
         | directional bound / sampled: min, median |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    let mut loaded: Vec<(&str, ModelFile)> = Vec::new();
    for view in ERROR_VIEWS {
        let (model, name, viewport) = (view.model, view.name, view.viewport);
        let [eye, target] = [view.eye, view.target].map(|p| p.map(|c| c as f64));
        let tol = view.tol as f64;
        if !loaded.iter().any(|(m, _)| *m == model) {
            let path = host_tests::models_dir().join(model);
            let file = ModelFile::read(path.to_str().expect("a UTF-8 path")).expect("a model");
            loaded.push((model, file));
        }
        let (_, file) = loaded.iter().find(|(m, _)| *m == model).expect("loaded");
        let patches = file.patches();
        let diag = patches.aabb().expect("patches").diagonal();
        // The near plane of `error_figures`, rounded to f32 as its camera's is.
        let near = (0.01 * diag) as f64;
        let meter = Meter::new(eye, target, [0.0, 0.0, 1.0], 40.0, near, viewport);
        let refs: Vec<RefPatch> = patches.iter().map(|p| RefPatch::from_kernel(&p)).collect();
        let mut grid = 0;
        let mut counts = [0usize; 4];
        let mut ratios: Vec<f64> = Vec::new();
        let selections = [
            Selection::Adaptive,
            Selection::Nested,
            Selection::Isotropic,
            Selection::Directional,
        ];
        for r in &refs {
            grid += grid_size(r, tol, GRID_DENSE, 512, Measure::Screen(&meter))
                .map_or(2 * 511 * 511, |n| 2 * (n - 1) * (n - 1));
            for (count, &selection) in counts.iter_mut().zip(&selections) {
                let triangles = oracle(r, &meter, tol, selection);
                *count += triangles.len();
                if selection == Selection::Directional {
                    ratios.extend(bound_over_true(r, &triangles, &meter));
                }
            }
        }
        ratios.sort_by(f64::total_cmp);
        let cells: Vec<String> = counts
            .iter()
            .map(|&c| format!("{c} | {:.2}", c as f64 / grid as f64))
            .collect();
        println!(
            "| {name} | {grid} | {} | {:.3}, {:.3} |",
            cells.join(" | "),
            ratios.first().copied().unwrap_or(f64::NAN),
            ratios.get(ratios.len() / 2).copied().unwrap_or(f64::NAN),
        );
    }
}
