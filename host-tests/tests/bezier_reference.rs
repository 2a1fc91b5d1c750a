//! Every patch of every BPT model: kernel f32 evaluation against the f64 Bernstein reference.

use host_tests::reference::{self, dist, read_bpt, RefFrame};
use host_tests::{
    angle, bpt_models, name, near_pole, widen, KernelBpt, Rng, NORMAL_TOL, POSITION_TOL,
};
use spline_tess::BezierPatch;

struct Stats {
    points: usize,
    normals: usize,
    worst_position: f64,
    worst_normal: f64,
}

/// Samples on a 17 x 17 grid (borders included) and 200 random points.
fn samples(rng: &mut Rng) -> Vec<(f64, f64)> {
    let mut s: Vec<(f64, f64)> = (0..17)
        .flat_map(|i| (0..17).map(move |j| (i as f64 / 16.0, j as f64 / 16.0)))
        .collect();
    s.extend((0..200).map(|_| (rng.unit(), rng.unit())));
    s
}

/// Checks one patch; `collapsed` is `[v=0, u=1, v=1, u=0]`.
fn check_patch(
    label: &str,
    kernel: &BezierPatch<'_>,
    r: &reference::RefPatch,
    diag: f64,
    rng: &mut Rng,
    stats: &mut Stats,
) {
    let collapsed = r.collapsed();
    for (u, v) in samples(rng) {
        // The kernel sees the f32 parameter; the reference evaluates at the same value.
        let (uf, vf) = (u as f32, v as f32);
        let (u, v) = (uf as f64, vf as f64);
        let k = kernel.evaluate(uf, vf);
        let f: RefFrame = r.eval(u, v);
        let e = dist(widen(k.position), f.p) / diag;
        assert!(
            e <= POSITION_TOL,
            "{label} at ({u}, {v}): position error {e:e} x diagonal"
        );
        assert!(
            (widen(kernel.position(uf, vf)) == widen(k.position)),
            "{label}: position() and evaluate() disagree at ({u}, {v})"
        );
        stats.worst_position = stats.worst_position.max(e);
        stats.points += 1;
        let n = widen(k.normal);
        assert!(
            (reference::norm(n) - 1.0).abs() < 1e-6,
            "{label}: normal not unit at ({u}, {v})"
        );
        let near_pole = near_pole(collapsed, u, v);
        let on_pole = (collapsed[0] && v == 0.0)
            || (collapsed[2] && v == 1.0)
            || (collapsed[3] && u == 0.0)
            || (collapsed[1] && u == 1.0);
        if on_pole {
            let limit = if (collapsed[0] && v == 0.0) || (collapsed[2] && v == 1.0) {
                f.limit_normal_su_vanishes(if v == 0.0 { 1.0 } else { -1.0 })
            } else {
                f.limit_normal_sv_vanishes(if u == 0.0 { 1.0 } else { -1.0 })
            };
            let a = angle(n, limit);
            assert!(
                a <= NORMAL_TOL,
                "{label} at pole ({u}, {v}): normal {n:?} is {a} rad from the limit {limit:?}"
            );
        } else if !near_pole {
            if let Some(rn) = f.normal() {
                let a = angle(n, rn);
                assert!(
                    a <= NORMAL_TOL,
                    "{label} at ({u}, {v}): normal {n:?} is {a} rad from {rn:?}"
                );
                stats.worst_normal = stats.worst_normal.max(a);
                stats.normals += 1;
            }
        }
    }
}

#[test]
fn every_bpt_patch_matches_the_f64_reference() {
    let mut rng = Rng::for_test(2);
    for path in bpt_models() {
        let text = std::fs::read_to_string(&path).unwrap();
        let reference = read_bpt(&text);
        let kernel = KernelBpt::parse(&text);
        let set = kernel.set();
        assert_eq!(set.len(), reference.len());
        let diag = reference::diagonal(reference.iter().flat_map(|p| p.pts.iter()));
        let mut stats = Stats {
            points: 0,
            normals: 0,
            worst_position: 0.0,
            worst_normal: 0.0,
        };
        for (i, (k, r)) in set.iter().zip(&reference).enumerate() {
            let label = format!("{} patch {i}", name(&path));
            check_patch(&label, &k, r, diag, &mut rng, &mut stats);
        }
        println!(
            "{}: {} points, worst position {:.2e} x diagonal; {} normals, worst {:.2e} rad",
            name(&path),
            stats.points,
            stats.worst_position,
            stats.normals,
            stats.worst_normal
        );
        assert!(stats.normals > stats.points / 2, "too few normals compared");
    }
}

/// The teapot's lid and bottom poles lie on the z axis of a surface of revolution: the limit
/// normal there must be +z or -z exactly, and agree with the normals just beside the pole.
#[test]
fn teapot_pole_normals_are_the_axis() {
    let text = std::fs::read_to_string(host_tests::models_dir().join("teapot.bpt")).unwrap();
    let kernel = KernelBpt::parse(&text);
    let mut poles = 0;
    for (i, patch) in kernel.set().iter().enumerate() {
        for side in spline_tess::Side::ALL {
            if !patch.is_collapsed(side) {
                continue;
            }
            poles += 1;
            for k in 0..=8 {
                let t = k as f32 / 8.0;
                let (u, v, u_in, v_in) = match side {
                    spline_tess::Side::V0 => (t, 0.0, t, 0.02),
                    spline_tess::Side::V1 => (t, 1.0, t, 0.98),
                    spline_tess::Side::U0 => (0.0, t, 0.02, t),
                    spline_tess::Side::U1 => (1.0, t, 0.98, t),
                };
                let n = patch.evaluate(u, v).normal;
                assert!(
                    n.z.abs() > 1.0 - 1e-6 && n.x.abs() < 1e-3 && n.y.abs() < 1e-3,
                    "patch {i} {side:?} at t = {t}: pole normal {n:?}"
                );
                let beside = patch.evaluate(u_in, v_in).normal;
                assert!(
                    n.dot(beside) > 0.9,
                    "patch {i} {side:?}: pole normal {n:?} flips against {beside:?} beside it"
                );
            }
        }
    }
    assert_eq!(poles, 8, "the teapot has 8 collapsed edges");
}

/// Bounds contain every evaluated point.
#[test]
fn bounds_contain_the_surface() {
    let mut rng = Rng::for_test(3);
    for path in bpt_models() {
        let kernel = KernelBpt::parse(&std::fs::read_to_string(&path).unwrap());
        for patch in kernel.set().iter() {
            let b = patch.aabb();
            let s = patch.bounding_sphere();
            for (u, v) in samples(&mut rng) {
                let p = patch.position(u as f32, v as f32);
                assert!(
                    p.cmpge(b.min).all() && p.cmple(b.max).all(),
                    "{p:?} outside {b:?}"
                );
                assert!((p - s.center).length() <= s.radius, "{p:?} outside {s:?}");
            }
        }
    }
}

/// The same patches through curvo and truck-geometry (as B-splines with Bezier knots): the
/// kernel agrees with both third-party references too.
#[test]
fn every_bpt_patch_matches_curvo_and_truck() {
    use host_tests::peers::{bezier_knots, Net};
    use truck_geometry::prelude::ParametricSurface3D;

    let mut rng = Rng::for_test(5);
    for path in bpt_models() {
        let text = std::fs::read_to_string(&path).unwrap();
        let reference = read_bpt(&text);
        let kernel = KernelBpt::parse(&text);
        let diag = reference::diagonal(reference.iter().flat_map(|p| p.pts.iter()));
        let (mut worst_p, mut worst_n) = (0.0f64, 0.0f64);
        for (i, (k, r)) in kernel.set().iter().zip(&reference).enumerate() {
            let homogeneous = |i: usize, j: usize| {
                let (p, w) = (r.at(i, j), r.w[i * (r.dv + 1) + j]);
                [p[0] * w, p[1] * w, p[2] * w, w]
            };
            let (ku, kv) = (bezier_knots(r.du), bezier_knots(r.dv));
            let net = Net {
                du: r.du,
                dv: r.dv,
                ku: &ku,
                kv: &kv,
                at: &homogeneous,
            };
            let (curvo, truck) = (net.curvo(), net.truck());
            let collapsed = r.collapsed();
            for (u, v) in samples(&mut rng) {
                let (uf, vf) = (u as f32, v as f32);
                let (u, v) = (uf as f64, vf as f64);
                let e = k.evaluate(uf, vf);
                let kp = widen(e.position);
                let cp = curvo.point_at(u, v);
                let tp = truck.subs(u, v);
                for (who, p) in [("curvo", [cp.x, cp.y, cp.z]), ("truck", [tp.x, tp.y, tp.z])] {
                    let err = dist(kp, p) / diag;
                    assert!(
                        err <= POSITION_TOL,
                        "{} patch {i} at ({u}, {v}): {err:e} x diagonal from {who}",
                        name(&path)
                    );
                    worst_p = worst_p.max(err);
                }
                let near_pole = near_pole(collapsed, u, v);
                // Compare normals where the f64 reference says they are well defined.
                if near_pole || r.eval(u, v).normal().is_none() {
                    continue;
                }
                let cn = curvo.normal_at(u, v);
                let tn = truck.normal(u, v);
                let cn = reference::scale([cn.x, cn.y, cn.z], 1.0 / cn.norm());
                for (who, m) in [("curvo", cn), ("truck", [tn.x, tn.y, tn.z])] {
                    let a = angle(widen(e.normal), m);
                    assert!(
                        a <= NORMAL_TOL,
                        "{} patch {i} at ({u}, {v}): normal {a} rad from {who}",
                        name(&path)
                    );
                    worst_n = worst_n.max(a);
                }
            }
        }
        println!(
            "{} vs curvo and truck: worst position {worst_p:.2e} x diagonal, worst normal {worst_n:.2e} rad",
            name(&path)
        );
    }
}
