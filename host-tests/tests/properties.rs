//! Property tests over random rational patches and NURBS surfaces.

use host_tests::reference::{self, dist, RefNurbs, RefPatch};
use host_tests::{angle, widen};
use proptest::prelude::*;
use spline_tess::{BezierPatch, NurbsSurface, ParamRect, PatchHeader};

/// A random rational patch: degrees 1..=7, points in a box of side 200, weights 10^[-3, 3].
fn patch() -> impl Strategy<Value = (usize, usize, Vec<[f32; 3]>, Vec<f32>)> {
    (1usize..=7, 1usize..=7).prop_flat_map(|(du, dv)| {
        let n = (du + 1) * (dv + 1);
        (
            Just(du),
            Just(dv),
            prop::collection::vec(prop::array::uniform3(-100.0f32..100.0), n),
            prop::collection::vec((-3.0f32..3.0).prop_map(|e| 10f32.powf(e)), n),
        )
    })
}

fn reference_of(du: usize, dv: usize, pts: &[[f32; 3]], w: &[f32]) -> RefPatch {
    RefPatch {
        du,
        dv,
        pts: pts
            .iter()
            .map(|p| [p[0] as f64, p[1] as f64, p[2] as f64])
            .collect(),
        w: w.iter().map(|&x| x as f64).collect(),
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn rational_patches_match_the_reference(
        (du, dv, pts, w) in patch(),
        params in prop::collection::vec((0.0f32..=1.0, 0.0f32..=1.0), 16),
    ) {
        let k = BezierPatch::new_rational(du, dv, &pts, &w).unwrap();
        let r = reference_of(du, dv, &pts, &w);
        let diag = reference::diagonal(r.pts.iter());
        for (u, v) in params {
            let e = k.evaluate(u, v);
            let f = r.eval(u as f64, v as f64);
            let err = dist(widen(e.position), f.p) / diag;
            prop_assert!(err <= 1e-5, "({}, {}): position error {:e} x diagonal", u, v, err);
            prop_assert!(e.normal.is_finite() && (e.normal.length() - 1.0).abs() < 1e-5);
            // Compare normals only where the f64 normal is well conditioned for f32 input:
            // partials not tiny against the net, and not nearly parallel.
            let (lu, lv) = (reference::norm(f.su), reference::norm(f.sv));
            let sin = reference::norm(reference::cross(f.su, f.sv)) / (lu * lv);
            if lu > 1e-2 * diag && lv > 1e-2 * diag && sin > 1e-2 {
                let a = angle(widen(e.normal), f.normal().unwrap());
                prop_assert!(a <= 1e-3, "({}, {}): normal {} rad off", u, v, a);
            }
        }
    }

    #[test]
    fn nurbs_decomposition_reproduces_the_surface(
        du in 1usize..=4,
        dv in 1usize..=4,
        extra_u in 0usize..4,
        extra_v in 0usize..4,
        seed in prop::collection::vec(-50.0f32..50.0, 3 * 64),
        wexp in prop::collection::vec(-2.0f32..2.0, 64),
        params in prop::collection::vec((0.0f32..=1.0, 0.0f32..=1.0), 8),
    ) {
        // Clamped knots with `extra` interior knots, one repeated where the degree allows.
        let knots = |p: usize, extra: usize| {
            let mut k = vec![0.0f32; p + 1];
            let interior = if p >= 2 { [0.25f32, 0.5, 0.5, 0.8] } else { [0.25, 0.5, 0.65, 0.8] };
            k.extend_from_slice(&interior[..extra]);
            k.extend(std::iter::repeat_n(1.0, p + 1));
            k
        };
        let (ku, kv) = (knots(du, extra_u), knots(dv, extra_v));
        let (nu, nv) = (ku.len() - du - 1, kv.len() - dv - 1);
        let pts: Vec<[f32; 3]> = (0..nu * nv).map(|k| [seed[3 * k], seed[3 * k + 1], seed[3 * k + 2]]).collect();
        let w: Vec<f32> = wexp[..nu * nv].iter().map(|e| 10f32.powf(*e)).collect();
        let s = NurbsSurface::new(du, dv, &ku, &kv, &pts, Some(&w)).unwrap();
        let r = RefNurbs {
            du, dv,
            ku: ku.iter().map(|&x| x as f64).collect(),
            kv: kv.iter().map(|&x| x as f64).collect(),
            pts: pts.iter().map(|p| [p[0] as f64, p[1] as f64, p[2] as f64]).collect(),
            w: w.iter().map(|&x| x as f64).collect(),
            nv,
            json: serde_json::Value::Null,
        };
        let diag = reference::diagonal(r.pts.iter());
        let size = s.decomposition_size();
        let mut headers = vec![PatchHeader::default(); size.patches];
        let mut bez = vec![[0.0f32; 3]; size.points];
        let mut bw = vec![0.0f32; size.points];
        let mut domains = vec![ParamRect::default(); size.patches];
        let set = s.decompose(&mut headers, &mut bez, &mut bw, &mut domains).unwrap();
        for (u, v) in params {
            let direct = widen(s.position(u, v));
            let f = r.eval(u as f64, v as f64).p;
            prop_assert!(dist(direct, f) / diag <= 1e-5);
            // The piece whose domain holds (u, v), at its local parameters.
            let k = domains.iter().position(|d| u >= d.u0 && u <= d.u1 && v >= d.v0 && v <= d.v1).unwrap();
            let d = domains[k];
            let (a, b) = ((u - d.u0) / (d.u1 - d.u0), (v - d.v0) / (d.v1 - d.v0));
            let piece = widen(set.patch(k).unwrap().position(a, b));
            prop_assert!(dist(piece, f) / diag <= 1e-5, "piece {} off by {:e}", k, dist(piece, f) / diag);
        }
    }
}
