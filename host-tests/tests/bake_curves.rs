//! Boundary-curve sampling on every curve of every BPT model: recorded deviations are truthful
//! (never below the true maximum by more than 5%, measured by dense f64 sampling with the
//! reference) and non-increasing, and the stop reason is honest.

use host_tests::reference::{self, dist, read_bpt, RefPatch, V3};
use host_tests::{bpt_models, name, KernelBpt};
use spline_tess::bake::{sample_curve, CurveSample, CurveSegment, StopReason};
use spline_tess::{BoundaryCurve, EdgeLink, GridPoint, Side, Topology};

/// Dense samples per polyline segment for the true maximum.
const DENSE: usize = 1024;
const CAP: usize = 24;

fn edge(r: &RefPatch, side: Side, t: f64) -> V3 {
    match side {
        Side::V0 => r.eval(t, 0.0).p,
        Side::U1 => r.eval(1.0, t).p,
        Side::V1 => r.eval(t, 1.0).p,
        Side::U0 => r.eval(0.0, t).p,
    }
}

/// True maximum deviation of one segment `[t0, t1]` (grid values), in f64.
fn segment_max(r: &RefPatch, side: Side, t0: u16, t1: u16) -> f64 {
    let (a, b) = (
        t0 as f64 / GridPoint::MAX as f64,
        t1 as f64 / GridPoint::MAX as f64,
    );
    let (pa, pb) = (edge(r, side, a), edge(r, side, b));
    (1..DENSE)
        .map(|k| {
            let s = k as f64 / DENSE as f64;
            let chord = reference::add(pa, reference::scale(reference::sub(pb, pa), s));
            dist(edge(r, side, a + (b - a) * s), chord)
        })
        .fold(0.0, f64::max)
}

#[test]
fn curve_deviations_are_truthful_and_non_increasing() {
    for path in bpt_models() {
        let text = std::fs::read_to_string(&path).unwrap();
        let kernel = KernelBpt::parse(&text);
        let set = kernel.set();
        let reference = read_bpt(&text);
        let diag = reference::diagonal(reference.iter().flat_map(|p| p.pts.iter()));
        let tolerance = (1e-4 * diag) as f32;
        let mut edges = vec![[EdgeLink::Collapsed; 4]; set.len()];
        let mut curves = vec![BoundaryCurve::default(); 4 * set.len()];
        let topo = Topology::build(&set, &mut edges, &mut curves).unwrap();
        let (mut total, mut worst_ratio) = (0usize, f64::INFINITY);
        for (c, curve) in topo.curves().iter().enumerate() {
            let patch = set.patch(curve.patch as usize).unwrap();
            let r = &reference[curve.patch as usize];
            let mut out = [CurveSample::default(); CAP];
            let mut scratch = [CurveSegment::default(); CAP + 1];
            let s = sample_curve(&patch, curve.side, tolerance, &mut out, &mut scratch).unwrap();
            let samples = &out[..s.samples];
            total += s.samples;
            let label = format!("{} curve {c}", name(&path));
            // Non-increasing.
            for w in samples.windows(2) {
                assert!(w[0].deviation >= w[1].deviation, "{label}: list increases");
            }
            // Truthful at every prefix, including the bare chord.
            let mut segments: Vec<(u16, u16, f64)> = vec![(
                0,
                GridPoint::MAX,
                segment_max(r, curve.side, 0, GridPoint::MAX),
            )];
            let truth = |segs: &[(u16, u16, f64)]| segs.iter().map(|s| s.2).fold(0.0, f64::max);
            let t0 = truth(&segments);
            assert!(
                s.initial_deviation as f64 >= 0.95 * t0,
                "{label}: chord {} < {t0}",
                s.initial_deviation
            );
            for (k, sample) in samples.iter().enumerate() {
                let i = segments
                    .iter()
                    .position(|&(a, b, _)| a < sample.t && sample.t < b)
                    .unwrap();
                let (a, b, _) = segments[i];
                segments[i] = (a, sample.t, segment_max(r, curve.side, a, sample.t));
                segments.push((sample.t, b, segment_max(r, curve.side, sample.t, b)));
                let t = truth(&segments);
                if t > 0.0 {
                    worst_ratio = worst_ratio.min(sample.deviation as f64 / t);
                }
                assert!(
                    sample.deviation as f64 >= 0.95 * t,
                    "{label} sample {k}: recorded {} < 95% of true {t}",
                    sample.deviation
                );
            }
            // The stop reason is honest.
            match s.stop {
                StopReason::Tolerance => {
                    let last = samples.last().map_or(s.initial_deviation, |x| x.deviation);
                    assert!(
                        last <= tolerance,
                        "{label}: stopped at {last} > {tolerance}"
                    );
                }
                StopReason::SampleCap => assert_eq!(s.samples, CAP, "{label}"),
                StopReason::Resolution => {}
            }
        }
        println!(
            "{}: {} curves, {total} samples at 1e-4 x diagonal, worst recorded/true {worst_ratio:.3}",
            name(&path),
            topo.curves().len()
        );
    }
}
