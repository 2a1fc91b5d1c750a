//! The computed deviation bounds (`spline_tess::bake::PatchBounds`) cover the true deviation.
//!
//! On every model (the BPT models and the NURBS fixtures, rational ones included), every
//! triangle of every patch's baked triangulation (corners, curve samples, interior samples) is
//! bounded by the kernel and sampled densely with the `f64` reference: the bound of the
//! triangle, and of its pieces when cut uniformly by 2, 3, 4 and 6, is at least the largest
//! sampled deviation. Every chord between neighbouring curve samples likewise. The tightness
//! (bound / true) is printed.

use host_tests::baked::{triangle_max, unit};
use host_tests::model_file::{bake_to_vec, ModelFile};
use host_tests::reference::{dist, RefPatch};
use host_tests::{bpt_models, name, nurbs_fixtures};
use spline_tess::bake::{
    chord_bound, triangle_bound, BakeSettings, BakedModel, Tolerance, SAMPLED_FACTORS,
};
use spline_tess::{DomainMesh, EdgeLink, MeshTriangle, MeshVertex, Side};

const SETTINGS: BakeSettings = BakeSettings {
    tolerance: Tolerance::Relative(1e-3),
    max_curve_samples: 256,
    max_interior_samples: 1024,
};
/// Barycentric steps of the dense check of a whole triangle (its pieces get a share of it).
const DENSE: usize = 36;

/// The pieces of the triangle `uv` cut uniformly by `n`.
fn pieces(uv: [(f64, f64); 3], n: usize) -> Vec<[(f64, f64); 3]> {
    let at = |a: usize, b: usize| {
        let (a, b) = (a as f64 / n as f64, b as f64 / n as f64);
        let c = 1.0 - a - b;
        (
            uv[0].0 * c + uv[1].0 * a + uv[2].0 * b,
            uv[0].1 * c + uv[1].1 * a + uv[2].1 * b,
        )
    };
    let mut out = Vec::new();
    for b in 0..n {
        for a in 0..n - b {
            out.push([at(a, b), at(a + 1, b), at(a, b + 1)]);
            if a + b + 2 <= n {
                out.push([at(a + 1, b), at(a + 1, b + 1), at(a, b + 1)]);
            }
        }
    }
    out
}

#[derive(Default)]
struct Report {
    triangles: usize,
    ratios: Vec<f64>,
}

fn check_model(path: &std::path::Path) -> Report {
    let label = name(path);
    let file = ModelFile::read(path.to_str().unwrap()).unwrap();
    let bytes = file
        .with_model(|m| bake_to_vec(m, &SETTINGS))
        .unwrap()
        .unwrap();
    let baked = BakedModel::from_bytes(&bytes).unwrap();
    let patches = file.patches();
    let mut report = Report::default();
    for k in 0..baked.patch_count() {
        let patch = patches.patch(k).unwrap();
        let bp = baked.patch(k).unwrap();
        let r = RefPatch::from_kernel(&patch);
        // The patch's own baked triangulation: its corners, the curve samples it requests and
        // its interior samples (every step is the point it inserts).
        let points: Vec<_> = bp.samples.iter().map(|s| s.point).collect();
        let n = points.len() + 4;
        let mut vs = vec![MeshVertex::default(); n];
        let mut ts = vec![MeshTriangle::default(); DomainMesh::triangles_for(n)];
        let mut mesh = DomainMesh::with_metric(&mut vs, &mut ts, bp.metric).unwrap();
        for p in points {
            mesh.insert(p).unwrap();
        }
        for t in mesh.triangles() {
            let corners = t.map(|v| mesh.point(v).unwrap());
            let uv = corners.map(unit);
            let b = triangle_bound(&patch, corners);
            let truth = triangle_max(&r, uv, DENSE);
            assert!(
                b.bound() as f64 >= truth,
                "{label} patch {k} {corners:?}: bound {:e} < true {truth:e}",
                b.bound()
            );
            report.triangles += 1;
            if truth > b.slack as f64 {
                report.ratios.push(b.bound() as f64 / truth);
            }
            for (f, &factor) in SAMPLED_FACTORS.iter().enumerate().skip(1) {
                let n = factor as usize;
                let worst = pieces(uv, n)
                    .into_iter()
                    .map(|p| triangle_max(&r, p, (DENSE / n).max(6)))
                    .fold(0.0f64, f64::max);
                assert!(
                    b.refined[f] as f64 >= worst,
                    "{label} patch {k}: bound of the pieces by {n} {:e} < true {worst:e}",
                    b.refined[f]
                );
            }
            // A factor the lattice does not sample: the curvature term scales as 1/n².
            let worst4 = pieces(uv, 4)
                .into_iter()
                .map(|p| triangle_max(&r, p, 9))
                .fold(0.0f64, f64::max);
            assert!((b.curvature / 16.0 + b.slack) as f64 >= worst4);
        }
        // Chords between neighbouring samples of every curve this patch owns.
        for (side, link) in Side::ALL.into_iter().zip(bp.edges) {
            let EdgeLink::Curve { curve, .. } = link else {
                continue;
            };
            let c = baked.curve(curve as usize).unwrap();
            if c.patch as usize != k || c.side != side {
                continue;
            }
            let mut ts: Vec<f64> = c.samples.iter().map(|s| s.t as f64 / 65535.0).collect();
            ts.extend([0.0, 1.0]);
            ts.sort_by(f64::total_cmp);
            for w in ts.windows(2) {
                let (t0, t1) = (w[0], w[1]);
                let bound = chord_bound(&patch, side, t0 as f32, t1 as f32).bound as f64;
                let point = |t: f64| match side {
                    Side::V0 => r.point(t, 0.0),
                    Side::U1 => r.point(1.0, t),
                    Side::V1 => r.point(t, 1.0),
                    Side::U0 => r.point(0.0, t),
                };
                let (a, b) = (point(t0), point(t1));
                let worst = (0..=64)
                    .map(|i| {
                        let f = i as f64 / 64.0;
                        let chord = [0, 1, 2].map(|m| a[m] + (b[m] - a[m]) * f);
                        dist(point(t0 + (t1 - t0) * f), chord)
                    })
                    .fold(0.0f64, f64::max);
                assert!(
                    bound >= worst,
                    "{label} curve {curve}: chord {bound:e} < {worst:e}"
                );
            }
        }
    }
    report.ratios.sort_by(f64::total_cmp);
    let q = |f: f64| {
        let n = report.ratios.len();
        if n == 0 {
            f64::NAN
        } else {
            report.ratios[((n - 1) as f64 * f) as usize]
        }
    };
    eprintln!(
        "{label}: {} triangles, bound / true: min {:.3}, median {:.3}, 90% {:.3}, max {:.3}",
        report.triangles,
        q(0.0),
        q(0.5),
        q(0.9),
        q(1.0)
    );
    report
}

#[test]
fn bounds_cover_the_true_deviation_on_every_model() {
    let models: Vec<_> = bpt_models().into_iter().chain(nurbs_fixtures()).collect();
    let reports: Vec<Report> = std::thread::scope(|scope| {
        let half = models.len().div_ceil(2);
        let handles: Vec<_> = models
            .chunks(half)
            .map(|chunk| {
                scope.spawn(move || chunk.iter().map(|p| check_model(p)).collect::<Vec<_>>())
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().expect("a model failed"))
            .collect()
    });
    let mut all: Vec<f64> = reports
        .iter()
        .flat_map(|r| r.ratios.iter().copied())
        .collect();
    all.sort_by(f64::total_cmp);
    assert!(all.len() > 10_000, "{}", all.len());
    // Tight where it matters: the typical triangle's bound is within 15% of the truth.
    let median = all[all.len() / 2];
    eprintln!("all models: median bound / true {median:.3}");
    assert!(median < 1.15, "median bound / true {median}");
}
