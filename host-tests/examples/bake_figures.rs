//! Bake figures for every model: samples, bytes and bake time at relative tolerances 1e-3 and
//! 1e-4, and the triangles of the baked triangulation beside a uniform grid per patch reaching
//! the same verified deviation. One run, one machine; prints a Markdown table.
//!
//! ```text
//! cargo run --release -p host-tests --example bake_figures          # 1e-3 and 1e-4
//! cargo run --release -p host-tests --example bake_figures -- 1e-3  # the tolerances given
//! ```
//!
//! "Verified deviation" is the largest distance, over every triangle, between the surface and
//! the triangle's linear interpolant at the same (u,v), sampled at 24 x 24 barycentric points
//! per triangle with the f64 reference evaluator. The baked triangulation of a patch is its
//! corners, all its curves' samples and all its interior samples. For the uniform grid, each
//! patch gets its own smallest n such that the n x n vertex grid (2 (n-1)^2 triangles) has a
//! verified deviation at most the baked model's.

use std::time::Instant;

use host_tests::baked::{boundary_points, triangle_max, unit};
use host_tests::model_file::{bake_to_vec, ModelFile};
use host_tests::reference::RefPatch;
use host_tests::{bpt_models, name, nurbs_fixtures};
use spline_tess::bake::{BakeSettings, BakedModel, Tolerance};
use spline_tess::{DomainMesh, MeshTriangle, MeshVertex};

const DENSE: usize = 24;

fn tri_max(r: &RefPatch, uv: [(f64, f64); 3]) -> f64 {
    triangle_max(r, uv, DENSE)
}

/// Verified deviation of the uniform n x n vertex grid (cells split along one diagonal).
fn grid_max(r: &RefPatch, n: usize) -> f64 {
    let s = |k: usize| k as f64 / (n - 1) as f64;
    let mut best = 0.0f64;
    for i in 0..n - 1 {
        for j in 0..n - 1 {
            let (a, b, c, d) = (
                (s(i), s(j)),
                (s(i + 1), s(j)),
                (s(i + 1), s(j + 1)),
                (s(i), s(j + 1)),
            );
            best = best.max(tri_max(r, [a, b, c])).max(tri_max(r, [a, c, d]));
        }
    }
    best
}

/// Largest grid tried; a patch that needs more counts as this (a lower bound, marked `>`).
const GRID_LIMIT: usize = 512;

/// Smallest n whose grid reaches `target`, by bisection (the deviation falls as n grows), or
/// `None` past [`GRID_LIMIT`].
fn grid_n(r: &RefPatch, target: f64) -> Option<usize> {
    let (mut lo, mut hi) = (1usize, 2usize); // grid_max(lo) > target (lo = 1: no grid)
    while grid_max(r, hi) > target {
        lo = hi;
        hi *= 2;
        if hi > GRID_LIMIT {
            return None;
        }
    }
    while hi - lo > 1 {
        let mid = (lo + hi) / 2;
        if grid_max(r, mid) > target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(hi)
}

fn main() {
    // FIGURES_ONLY=teapot limits the run to models whose file name contains it.
    let only = std::env::var("FIGURES_ONLY").unwrap_or_default();
    let models: Vec<_> = bpt_models()
        .into_iter()
        .chain(nurbs_fixtures())
        .filter(|p| name(p).contains(&only))
        .collect();
    let tolerances: Vec<f32> = std::env::args()
        .skip(1)
        .map(|a| a.parse().expect("a relative tolerance"))
        .collect();
    let tolerances = if tolerances.is_empty() {
        vec![1e-3, 1e-4]
    } else {
        tolerances
    };
    println!("| model | rel. tol. | patches | curve samples | interior samples | bytes | bake s | stops tol/cap/res | baked triangles | verified deviation | grid triangles | baked / grid |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    for path in &models {
        let file = ModelFile::read(path.to_str().unwrap()).unwrap();
        let patches = file.patches();
        let refs: Vec<RefPatch> = patches.iter().map(|p| RefPatch::from_kernel(&p)).collect();
        for &rel in &tolerances {
            let settings = BakeSettings {
                tolerance: Tolerance::Relative(rel),
                max_curve_samples: 256,
                max_interior_samples: 4096,
            };
            let start = Instant::now();
            let bytes = file
                .with_model(|m| bake_to_vec(m, &settings))
                .unwrap()
                .unwrap();
            let seconds = start.elapsed().as_secs_f64();
            let baked = BakedModel::from_bytes(&bytes).unwrap();
            let mut stops = [0usize; 3];
            for c in (0..baked.curve_count()).filter_map(|k| baked.curve(k)) {
                stops[c.stop as usize] += 1;
            }
            let (mut triangles, mut verified) = (0usize, 0.0f64);
            for (k, r) in refs.iter().enumerate() {
                let bp = baked.patch(k).unwrap();
                stops[bp.stop as usize] += 1;
                let n = 4 + 4 * 256 + bp.samples.len();
                let mut vs = vec![MeshVertex::default(); n];
                let mut ts = vec![MeshTriangle::default(); DomainMesh::triangles_for(n)];
                let mut mesh = DomainMesh::with_metric(&mut vs, &mut ts, bp.metric).unwrap();
                for p in boundary_points(&baked, &bp) {
                    mesh.insert(p).unwrap();
                }
                // Curve requests are already in, as the curves' samples.
                for s in bp.samples.iter().filter(|s| s.requested_side().is_none()) {
                    mesh.insert(s.point).unwrap();
                }
                triangles += mesh.triangle_count();
                let worst = mesh
                    .triangles()
                    .map(|t| tri_max(r, t.map(|v| unit(mesh.point(v).unwrap()))))
                    .fold(0.0, f64::max);
                verified = verified.max(worst);
            }
            let mut capped = false;
            let grid: usize = refs
                .iter()
                .map(|r| {
                    let n = grid_n(r, verified).unwrap_or_else(|| {
                        capped = true;
                        GRID_LIMIT
                    });
                    2 * (n - 1) * (n - 1)
                })
                .sum();
            let (more, less) = if capped { ("> ", "< ") } else { ("", "") };
            println!(
                "| {} | {rel:e} | {} | {} | {} | {} | {seconds:.3} | {}/{}/{} | {triangles} | {verified:.3e} | {more}{grid} | {less}{:.2} |",
                name(path),
                baked.patch_count(),
                baked.curve_sample_count(),
                baked.interior_sample_count(),
                bytes.len(),
                stops[0],
                stops[1],
                stops[2],
                triangles as f64 / grid as f64,
            );
        }
    }
}
