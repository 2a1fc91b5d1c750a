//! Patch sampling on every model (BPT models and NURBS fixtures) at a relative tolerance of
//! 1e-3, rebuilt step by step with the patch's own triangulation (its corners, the curve
//! samples it requests, its interior samples): wherever a recorded value is a new minimum (the
//! prefixes the run time selects), it is at least the true largest deviation of the
//! triangulation after that step (dense f64 sampling, 64x64 barycentric points per triangle,
//! with the reference evaluator), and within 10% of it on the median over all models; the lists are
//! non-increasing; a curve request inserts its side's next curve sample; interior samples keep
//! the boundary margin; the stop reason is honest; each step's stored surface point and offset
//! (the surface against the triangle that held the point before it) match the reference's
//! within what their encoding allows.

use std::collections::HashMap;

use host_tests::baked::{on_side, triangle_max, unit};
use host_tests::model_file::{bake_to_vec, ModelFile};
use host_tests::reference::RefPatch;
use host_tests::{bpt_models, name, nurbs_fixtures};
use spline_tess::bake::{
    BakeSettings, BakedModel, InteriorSample, PointBox, StopReason, Tolerance, BOUNDARY_MARGIN,
};
use spline_tess::{DomainMesh, EdgeLink, GridPoint, MeshTriangle, MeshVertex, Side};

const DENSE: usize = 64;
const RELATIVE: f32 = 1e-3;
const SETTINGS: BakeSettings = BakeSettings {
    tolerance: Tolerance::Relative(RELATIVE),
    max_curve_samples: 256,
    max_interior_samples: 1024,
};

struct Report {
    samples: usize,
    ratios: Vec<f64>,
    /// Largest error of a stored surface point or offset over what its encoding allows.
    stored: f64,
}

/// How far step `s`'s stored surface point and offset are from the reference's (the surface
/// at its point, and that minus the linear interpolant of the triangle of `mesh` holding it),
/// as a share of what their encodings allow: the point within `extent / 131070` per axis of
/// its box, the offset within `1 / 32768` of its largest component; both plus `f32`
/// evaluation (`1e-6` of the box's size).
fn stored_error(r: &RefPatch, mesh: &DomainMesh<'_>, s: InteriorSample, frame: PointBox) -> f64 {
    let orient = |a: GridPoint, b: GridPoint, c: GridPoint| {
        let (ax, ay, bx, by, cx, cy) = [a.u, a.v, b.u, b.v, c.u, c.v].map(|x| x as i64).into();
        (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
    };
    let q = s.point;
    let held = mesh
        .triangles()
        .map(|t| t.map(|v| mesh.point(v).unwrap()))
        .find(|&[a, b, c]| orient(b, c, q) >= 0 && orient(c, a, q) >= 0 && orient(a, b, q) >= 0)
        .expect("a triangle holds every step");
    let [a, b, c] = held;
    let area = orient(a, b, c) as f64;
    let weights = [orient(q, b, c), orient(a, q, c), orient(a, b, q)].map(|w| w as f64 / area);
    let at = |g: GridPoint| {
        let (u, v) = unit(g);
        r.point(u, v)
    };
    let corners = held.map(at);
    let surface = at(q);
    let linear: [f64; 3] =
        std::array::from_fn(|i| (0..3).map(|k| weights[k] * corners[k][i]).sum());
    let offset: [f64; 3] = std::array::from_fn(|i| surface[i] - linear[i]);
    let size = (0..3)
        .map(|i| {
            frame.min[i]
                .abs()
                .max((frame.min[i] + frame.extent[i]).abs()) as f64
        })
        .fold(0.0, f64::max);
    let slack = 1e-6 * size;
    let largest = offset.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    (0..3)
        .map(|i| {
            let point = (s.surface[i] as f64 - surface[i]).abs()
                / (frame.extent[i] as f64 / 131070.0 + slack);
            let off = (s.offset[i] as f64 - offset[i]).abs() / (largest / 32768.0 + slack);
            point.max(off)
        })
        .fold(0.0, f64::max)
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
        ratios: Vec::new(),
        stored: 0.0,
    };
    let inside = BOUNDARY_MARGIN..=GridPoint::MAX - BOUNDARY_MARGIN;
    for k in 0..baked.patch_count() {
        let bp = baked.patch(k).unwrap();
        let r = RefPatch::from_kernel(&patches.patch(k).unwrap());
        let n = 4 + 4 * 256 + bp.samples.len();
        let mut vs = vec![MeshVertex::default(); n];
        let mut ts = vec![MeshTriangle::default(); DomainMesh::triangles_for(n)];
        let mut mesh = DomainMesh::with_metric(&mut vs, &mut ts, bp.metric).unwrap();
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
        assert!(
            bp.initial_deviation as f64 >= truth,
            "{label} patch {k}: initial bound {} < true {truth}",
            bp.initial_deviation
        );
        // The curve samples each side's requests must insert, in order.
        let sides: Vec<Vec<GridPoint>> = Side::ALL
            .into_iter()
            .zip(bp.edges)
            .map(|(side, link)| match link {
                EdgeLink::Curve { curve, reversed } => baked
                    .curve(curve as usize)
                    .unwrap()
                    .samples
                    .iter()
                    .map(|c| on_side(side, c.t, reversed))
                    .collect(),
                EdgeLink::Collapsed => Vec::new(),
            })
            .collect();
        let mut requested = [0usize; 4];
        let mut last = bp.initial_deviation;
        for (j, s) in bp.samples.iter().enumerate() {
            match s.requested_side() {
                None => assert!(
                    inside.contains(&s.point.u) && inside.contains(&s.point.v),
                    "{label} patch {k} sample {j} inside the margin"
                ),
                Some(side) => {
                    let r = &mut requested[side.index()];
                    assert_eq!(
                        sides[side.index()].get(*r),
                        Some(&s.point),
                        "{label} patch {k} step {j}: not the side's next curve sample"
                    );
                    *r += 1;
                }
            }
            assert!(
                s.deviation <= last || j == 0,
                "{label} patch {k} sample {j}: list increases"
            );
            let new_minimum = j == 0 || s.deviation < last;
            last = s.deviation;
            report.stored = report
                .stored
                .max(stored_error(&r, &mesh, s, bp.samples.point_box()));
            mesh.insert(s.point).unwrap();
            if new_minimum {
                let truth = current(&mesh);
                assert!(
                    s.deviation as f64 >= truth,
                    "{label} patch {k} sample {j}: recorded {} < true {truth}",
                    s.deviation
                );
                if truth > 1e-6 * tolerance {
                    report.ratios.push(s.deviation as f64 / truth);
                }
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
            StopReason::SampleCap => assert_eq!(
                bp.samples
                    .iter()
                    .filter(|s| s.requested_side().is_none())
                    .count(),
                1024,
                "{label} patch {k}"
            ),
            StopReason::Resolution => assert!(left > tolerance, "{label} patch {k}"),
        }
    }
    report.ratios.sort_by(f64::total_cmp);
    let median = report
        .ratios
        .get(report.ratios.len() / 2)
        .copied()
        .unwrap_or(1.0);
    eprintln!(
        "{label}: {} patches, {} steps, recorded / true: min {:.3}, median {median:.3}; \
         stored point and offset error / allowed {:.3}",
        baked.patch_count(),
        report.samples,
        report.ratios.first().copied().unwrap_or(1.0),
        report.stored,
    );
    assert!(
        report.stored <= 1.0,
        "{label}: a stored point or offset is {:.3} times what its encoding allows",
        report.stored
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
    // Tight where it matters: the typical selectable prefix is within 10% of the truth.
    let mut all: Vec<f64> = reports
        .iter()
        .flat_map(|r| r.ratios.iter().copied())
        .collect();
    all.sort_by(f64::total_cmp);
    let median = all[all.len() / 2];
    eprintln!("all models: median recorded / true {median:.3}");
    assert!(median < 1.1, "median recorded / true {median}");
}
