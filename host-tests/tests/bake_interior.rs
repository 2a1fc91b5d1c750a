//! Interior sampling on every model (BPT models and NURBS fixtures) at a relative tolerance of
//! 1e-3: each recorded deviation is at least 95% of the true largest deviation of the patch's
//! triangulation after that insertion (dense f64 sampling, 64x64 barycentric points per
//! triangle, with the reference evaluator), the lists are non-increasing, the stop reason is
//! honest, and samples keep the boundary margin.

use std::collections::HashMap;

use host_tests::model_file::{bake_to_vec, ModelFile};
use host_tests::reference::{add, dist, scale, sub, RefPatch, V3};
use host_tests::{bpt_models, name, nurbs_fixtures};
use spline_tess::bake::{BakeSettings, BakedModel, StopReason, Tolerance, BOUNDARY_MARGIN};
use spline_tess::{DomainMesh, EdgeLink, GridPoint, MeshTriangle, MeshVertex, Side};

const DENSE: usize = 64;
const RELATIVE: f32 = 1e-3;
const SETTINGS: BakeSettings = BakeSettings {
    tolerance: Tolerance::Relative(RELATIVE),
    max_curve_samples: 256,
    max_interior_samples: 1024,
};

/// The largest distance between the patch and the triangle's interpolant, densely sampled.
fn true_max(r: &RefPatch, tri: [GridPoint; 3]) -> f64 {
    let m = GridPoint::MAX as f64;
    let uv = tri.map(|p| (p.u as f64 / m, p.v as f64 / m));
    let pos = uv.map(|(u, v)| r.point(u, v));
    let (d1, d2) = (sub(pos[1], pos[0]), sub(pos[2], pos[0]));
    let mut best = 0.0f64;
    for i in 0..=DENSE {
        for j in 0..=DENSE - i {
            let (s, t) = (i as f64 / DENSE as f64, j as f64 / DENSE as f64);
            let u = uv[0].0 + s * (uv[1].0 - uv[0].0) + t * (uv[2].0 - uv[0].0);
            let v = uv[0].1 + s * (uv[1].1 - uv[0].1) + t * (uv[2].1 - uv[0].1);
            let linear: V3 = add(pos[0], add(scale(d1, s), scale(d2, t)));
            best = best.max(dist(r.point(u.clamp(0.0, 1.0), v.clamp(0.0, 1.0)), linear));
        }
    }
    best
}

/// Where curve parameter `t` lands on `side`, for an edge running `reversed`.
fn on_side(side: Side, t: u16, reversed: bool) -> GridPoint {
    let e = if reversed { GridPoint::MAX - t } else { t };
    match side {
        Side::V0 => GridPoint::new(e, 0),
        Side::U1 => GridPoint::new(GridPoint::MAX, e),
        Side::V1 => GridPoint::new(e, GridPoint::MAX),
        Side::U0 => GridPoint::new(0, e),
    }
}

struct Report {
    samples: usize,
    worst_ratio: f64,
}

fn check_model(path: &std::path::Path) -> Report {
    let label = name(path);
    let file = ModelFile::read(path.to_str().unwrap()).unwrap();
    let bytes = file
        .with_model(|m| bake_to_vec(m, &SETTINGS))
        .unwrap()
        .unwrap();
    let baked = BakedModel::from_bytes(&bytes).unwrap();
    let tolerance = baked.tolerance() as f64;
    let patches = file.patches();
    let mut report = Report {
        samples: 0,
        worst_ratio: f64::INFINITY,
    };
    let inside = BOUNDARY_MARGIN..=GridPoint::MAX - BOUNDARY_MARGIN;
    for k in 0..baked.patch_count() {
        let bp = baked.patch(k).unwrap();
        let r = RefPatch::from_kernel(&patches.patch(k).unwrap());
        let n = 4 + 4 * 256 + bp.samples.len();
        let mut vs = vec![MeshVertex::default(); n];
        let mut ts = vec![MeshTriangle::default(); DomainMesh::triangles_for(n)];
        let mut mesh = DomainMesh::with_metric(&mut vs, &mut ts, bp.metric).unwrap();
        for (side, link) in Side::ALL.into_iter().zip(bp.edges) {
            if let EdgeLink::Curve { curve, reversed } = link {
                for s in baked.curve(curve as usize).unwrap().samples.iter() {
                    mesh.insert(on_side(side, s.t, reversed)).unwrap();
                }
            }
        }
        let mut cache: HashMap<[GridPoint; 3], f64> = HashMap::new();
        let mut current = |mesh: &DomainMesh<'_>| -> f64 {
            mesh.triangles()
                .map(|t| {
                    let c = t.map(|v| mesh.point(v).unwrap());
                    *cache.entry(c).or_insert_with(|| true_max(&r, c))
                })
                .fold(0.0, f64::max)
        };
        let truth = current(&mesh);
        let ratio = bp.initial_deviation as f64 / truth.max(1e-30);
        assert!(
            ratio >= 0.95 || truth < 1e-6 * tolerance,
            "{label} patch {k}: initial deviation {} < 95% of {truth}",
            bp.initial_deviation
        );
        let mut last = f32::INFINITY;
        for (j, s) in bp.samples.iter().enumerate() {
            assert!(
                inside.contains(&s.point.u) && inside.contains(&s.point.v),
                "{label} patch {k} sample {j} inside the margin"
            );
            assert!(
                s.deviation <= last,
                "{label} patch {k} sample {j}: list increases"
            );
            last = s.deviation;
            mesh.insert(s.point).unwrap();
            let truth = current(&mesh);
            if truth > 1e-6 * tolerance {
                let ratio = s.deviation as f64 / truth;
                report.worst_ratio = report.worst_ratio.min(ratio);
                assert!(
                    ratio >= 0.95,
                    "{label} patch {k} sample {j}: recorded {} < 95% of true {truth}",
                    s.deviation
                );
            }
        }
        report.samples += bp.samples.len();
        let left = bp
            .samples
            .iter()
            .last()
            .map_or(bp.initial_deviation, |s| s.deviation) as f64;
        match bp.stop {
            StopReason::Tolerance => assert!(left <= tolerance, "{label} patch {k}"),
            StopReason::SampleCap => assert_eq!(bp.samples.len(), 1024, "{label} patch {k}"),
            StopReason::Resolution => assert!(left > tolerance, "{label} patch {k}"),
        }
    }
    eprintln!(
        "{label}: {} patches, {} interior samples, worst recorded/true {:.4}",
        baked.patch_count(),
        report.samples,
        report.worst_ratio
    );
    report
}

#[test]
fn interior_deviations_are_truthful_on_every_model() {
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
    assert_eq!(reports.len(), models.len());
    assert!(reports.iter().map(|r| r.samples).sum::<usize>() > 1000);
}
