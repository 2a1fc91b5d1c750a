//! Interior sampling on every model (BPT models and NURBS fixtures) at a relative tolerance of
//! 1e-3: each recorded deviation is at least 95% of the true largest deviation of the patch's
//! triangulation after that insertion (dense f64 sampling, 64x64 barycentric points per
//! triangle, with the reference evaluator), the lists are non-increasing, the stop reason is
//! honest, and samples keep the boundary margin.

use std::collections::HashMap;

use host_tests::baked::{boundary_points, triangle_max, unit};
use host_tests::model_file::{bake_to_vec, ModelFile};
use host_tests::reference::RefPatch;
use host_tests::{bpt_models, name, nurbs_fixtures};
use spline_tess::bake::{BakeSettings, BakedModel, StopReason, Tolerance, BOUNDARY_MARGIN};
use spline_tess::{DomainMesh, GridPoint, MeshTriangle, MeshVertex};

const DENSE: usize = 64;
const RELATIVE: f32 = 1e-3;
const SETTINGS: BakeSettings = BakeSettings {
    tolerance: Tolerance::Relative(RELATIVE),
    max_curve_samples: 256,
    max_interior_samples: 1024,
};

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
        for p in boundary_points(&baked, &bp) {
            mesh.insert(p).unwrap();
        }
        let mut cache: HashMap<[GridPoint; 3], f64> = HashMap::new();
        let mut current = |mesh: &DomainMesh<'_>| -> f64 {
            mesh.triangles()
                .map(|t| {
                    let c = t.map(|v| mesh.point(v).unwrap());
                    *cache
                        .entry(c)
                        .or_insert_with(|| triangle_max(&r, c.map(unit), DENSE))
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
