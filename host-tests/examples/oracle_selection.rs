//! How few triangles a selection of this kind could reach, with a perfect error measure:
//! two oracle tessellators beside the verified uniform grid, on the views of the
//! error-control table. Prints a Markdown table.
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

use std::collections::HashMap;

use host_tests::model_file::ModelFile;
use host_tests::reference::{dist, RefPatch, V3};
use host_tests::screen::{grid_size, Measure, Meter, ERROR_VIEWS};
use spline_tess::{DomainMesh, GridPoint, MeshTriangle, MeshVertex};

/// Barycentric steps per side of a measured triangle (as `error_figures`).
const DENSE: usize = 12;
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

/// Triangles of one oracle on patch `r` (`nested`: the prefix of the object-space order).
fn oracle(r: &RefPatch, meter: &Meter, tol: f64, nested: bool) -> usize {
    let mut vertices = vec![MeshVertex::default(); VERTICES];
    let mut triangles = vec![MeshTriangle::default(); DomainMesh::triangles_for(VERTICES)];
    let mut mesh = DomainMesh::new(&mut vertices, &mut triangles).expect("room for the square");
    let mut measured: HashMap<[GridPoint; 3], (Worst, Worst)> = HashMap::new();
    let unit = |p: GridPoint| [p.u, p.v].map(|c| c as f64 / GridPoint::MAX as f64);
    loop {
        let (mut on_screen, mut next): (f64, Option<Worst>) = (0.0, None);
        for ids in mesh.triangles() {
            let mut key = ids.map(|id| mesh.point(id).expect("a vertex of the mesh"));
            key.sort_by_key(|p| (p.u, p.v));
            let (screen, object) = *measured
                .entry(key)
                .or_insert_with(|| measure(r, key.map(unit), meter));
            on_screen = on_screen.max(screen.error);
            let order = if nested { object } else { screen };
            if next.is_none_or(|n| order.error > n.error) {
                next = Some(order);
            }
        }
        let Some(next) = next.filter(|_| on_screen > tol) else {
            return mesh.triangle_count();
        };
        let [u, v] = next.at.map(|c| (c * GridPoint::MAX as f64).round() as u16);
        if mesh.insert(GridPoint { u, v }).is_err() {
            eprintln!("a patch stopped at {on_screen:.3} px: its worst point is a vertex");
            return mesh.triangle_count();
        }
    }
}

fn main() {
    println!("| case | grid | adaptive oracle | adaptive / grid | nested oracle | nested / grid |");
    println!("|---|---|---|---|---|---|");
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
        let (mut grid, mut adaptive, mut nested) = (0, 0, 0);
        for r in &refs {
            grid += grid_size(r, tol, GRID_DENSE, 512, Measure::Screen(&meter))
                .map_or(2 * 511 * 511, |n| 2 * (n - 1) * (n - 1));
            adaptive += oracle(r, &meter, tol, false);
            nested += oracle(r, &meter, tol, true);
        }
        println!(
            "| {name} | {grid} | {adaptive} | {:.2} | {nested} | {:.2} |",
            adaptive as f64 / grid as f64,
            nested as f64 / grid as f64
        );
    }
}
