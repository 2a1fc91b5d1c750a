//! NURBS fixtures: kernel evaluation against the f64 reference, curvo and truck-geometry; the
//! fixtures' expected points and analytic properties; exact decomposition.

use curvo::prelude::NurbsSurface3D;
use host_tests::peers::Net;
use host_tests::reference::{self, dist, RefNurbs, V3};
use host_tests::{
    angle, name, near_pole, nurbs_fixtures, widen, KernelNurbs, Rng, NORMAL_TOL, POSITION_TOL,
};
use spline_tess::{BoundaryCurve, EdgeLink, ParamRect, PatchHeader, Topology};
use truck_geometry::prelude::{NurbsSurface as TruckNurbs, ParametricSurface3D, Vector4};

struct Fixture {
    name: String,
    r: RefNurbs,
    k: KernelNurbs,
    curvo: NurbsSurface3D<f64>,
    truck: TruckNurbs<Vector4>,
    diag: f64,
}

fn fixtures() -> Vec<Fixture> {
    nurbs_fixtures()
        .into_iter()
        .map(|path| {
            let text = std::fs::read_to_string(&path).unwrap();
            let r = RefNurbs::read(&text);
            let k = KernelNurbs::parse(&text);
            let homogeneous = |i: usize, j: usize| {
                let (p, w) = (r.pts[i * r.nv + j], r.w[i * r.nv + j]);
                [p[0] * w, p[1] * w, p[2] * w, w]
            };
            let net = Net {
                du: r.du,
                dv: r.dv,
                ku: &r.ku,
                kv: &r.kv,
                at: &homogeneous,
            };
            let (curvo, truck) = (net.curvo(), net.truck());
            let diag = reference::diagonal(r.pts.iter());
            Fixture {
                name: name(&path),
                r,
                k,
                curvo,
                truck,
                diag,
            }
        })
        .collect()
}

/// Grid (17 x 17, borders included) and random parameters over the domain, as f32 values.
fn params(r: &RefNurbs, rng: &mut Rng) -> Vec<(f32, f32)> {
    let (u0, u1, v0, v1) = r.domain();
    let mut s: Vec<(f64, f64)> = (0..17)
        .flat_map(|i| (0..17).map(move |j| (i as f64 / 16.0, j as f64 / 16.0)))
        .collect();
    s.extend((0..300).map(|_| (rng.unit(), rng.unit())));
    s.into_iter()
        .map(|(a, b)| ((u0 + a * (u1 - u0)) as f32, (v0 + b * (v1 - v0)) as f32))
        .collect()
}

/// Which domain edges are collapsed, `[v = v0, u = u1, v = v1, u = u0]`.
fn collapsed(r: &RefNurbs) -> [bool; 4] {
    let nu = r.pts.len() / r.nv;
    let at = |i: usize, j: usize| r.pts[i * r.nv + j];
    let eq = |f: &dyn Fn(usize) -> V3, n: usize| (1..n).all(|k| f(k) == f(0));
    [
        eq(&|k| at(k, 0), nu),
        eq(&|k| at(nu - 1, k), r.nv),
        eq(&|k| at(k, r.nv - 1), nu),
        eq(&|k| at(0, k), r.nv),
    ]
}

fn unit(v: V3) -> V3 {
    reference::scale(v, 1.0 / reference::norm(v))
}

#[test]
fn kernel_matches_reference_curvo_and_truck() {
    let mut rng = Rng::for_test(7);
    for f in fixtures() {
        let s = f.k.surface();
        let (u0, u1, v0, v1) = f.r.domain();
        let c = collapsed(&f.r);
        let mut normals = 0;
        let mut worst = (0.0f64, 0.0f64);
        for (uf, vf) in params(&f.r, &mut rng) {
            let (u, v) = (uf as f64, vf as f64);
            let k = s.evaluate(uf, vf);
            let kp = widen(k.position);
            let rf = f.r.eval(u, v);
            let cp = f.curvo.point_at(u, v);
            let cp = [cp.x, cp.y, cp.z];
            let tp = f.truck.subs(u, v);
            let tp = [tp.x, tp.y, tp.z];
            for (who, p) in [("f64 reference", rf.p), ("curvo", cp), ("truck", tp)] {
                let e = dist(kp, p) / f.diag;
                assert!(
                    e <= POSITION_TOL,
                    "{} at ({u}, {v}): {e:e} x diagonal from {who}",
                    f.name
                );
                worst.0 = worst.0.max(e);
            }
            assert_eq!(widen(s.position(uf, vf)), kp, "position() vs evaluate()");
            let su = (u - u0) / (u1 - u0);
            let sv = (v - v0) / (v1 - v0);
            if near_pole(c, su, sv) {
                continue;
            }
            let Some(rn) = rf.normal() else { continue };
            let cn = f.curvo.normal_at(u, v);
            let tn = f.truck.normal(u, v);
            let n = widen(k.normal);
            for (who, m) in [
                ("f64 reference", rn),
                ("curvo", unit([cn.x, cn.y, cn.z])),
                ("truck", [tn.x, tn.y, tn.z]),
            ] {
                let a = angle(n, m);
                assert!(
                    a <= NORMAL_TOL,
                    "{} at ({u}, {v}): normal {a} rad from {who}",
                    f.name
                );
                worst.1 = worst.1.max(a);
            }
            normals += 1;
        }
        assert!(normals > 100, "{}: only {normals} normals compared", f.name);
        println!(
            "{}: worst position {:.2e} x diagonal, worst normal {:.2e} rad",
            f.name, worst.0, worst.1
        );
    }
}

#[test]
fn expected_points_hold() {
    for f in fixtures() {
        let s = f.k.surface();
        let tol = f.r.json["tolerance"].as_f64();
        let expected = f.r.json["expected"].as_array().unwrap();
        for e in expected {
            let (u, v) = (e["u"].as_f64().unwrap(), e["v"].as_f64().unwrap());
            let p: Vec<f64> = e["p"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect();
            let k = widen(s.position(u as f32, v as f32));
            let r = f.r.eval(u, v).p;
            // The sources assert each coordinate within their delta (geomdl truncates to
            // 1e-3); without a stated tolerance they assert exact values.
            let limit = tol.unwrap_or(POSITION_TOL * f.diag);
            for (who, q) in [("kernel", k), ("f64 reference", r)] {
                let d = (0..3).map(|i| (q[i] - p[i]).abs()).fold(0.0, f64::max);
                assert!(
                    d <= limit,
                    "{}: {who} at ({u}, {v}): {q:?} is {d} from {p:?}",
                    f.name
                );
            }
        }
    }
}

#[test]
fn hemisphere_lies_on_the_unit_sphere_with_radial_normals() {
    let f = fixtures()
        .into_iter()
        .find(|f| f.name == "tinynurbs_hemisphere.json")
        .unwrap();
    let s = f.k.surface();
    let mut rng = Rng::for_test(11);
    for (u, v) in params(&f.r, &mut rng) {
        let k = s.evaluate(u, v);
        let p = widen(k.position);
        let r = reference::norm(p);
        assert!((r - 1.0).abs() <= 2e-6, "|P({u}, {v})| = {r}");
        // A sphere's normal is its position (up to orientation), at the poles too.
        let cos = reference::dot(widen(k.normal), p).abs() / r;
        assert!(
            cos > 1.0 - 1e-6,
            "normal at ({u}, {v}) is not radial: cos {cos}"
        );
    }
}

#[test]
fn quarter_cylinder_lies_on_the_cylinder() {
    let f = fixtures()
        .into_iter()
        .find(|f| f.name == "verb_quarter_cylinder.json")
        .unwrap();
    let s = f.k.surface();
    let mut rng = Rng::for_test(13);
    for (u, v) in params(&f.r, &mut rng) {
        let k = s.evaluate(u, v);
        let p = widen(k.position);
        let e = p[1] * p[1] + p[2] * p[2] - 1.0;
        assert!(e.abs() <= 2e-6, "y^2 + z^2 - 1 = {e} at ({u}, {v})");
        let radial = [0.0, p[1], p[2]];
        let cos = reference::dot(widen(k.normal), radial).abs() / reference::norm(radial);
        assert!(
            cos > 1.0 - 1e-6,
            "normal at ({u}, {v}) is not radial: cos {cos}"
        );
    }
}

#[test]
fn torus_lies_on_the_torus_with_tube_normals() {
    let f = fixtures()
        .into_iter()
        .find(|f| f.name == "rational_torus.json")
        .unwrap();
    let s = f.k.surface();
    let mut rng = Rng::for_test(19);
    for (u, v) in params(&f.r, &mut rng) {
        let k = s.evaluate(u, v);
        let p = widen(k.position);
        let rho = (p[0] * p[0] + p[1] * p[1]).sqrt();
        let e = (rho - 2.0).powi(2) + p[2] * p[2] - 0.25;
        assert!(
            e.abs() <= 4e-6,
            "(rho - 2)^2 + z^2 - 1/4 = {e} at ({u}, {v})"
        );
        // The normal points from the tube's centre circle to the point.
        let centre = [2.0 * p[0] / rho, 2.0 * p[1] / rho, 0.0];
        let radial = reference::sub(p, centre);
        let cos = reference::dot(widen(k.normal), radial).abs() / reference::norm(radial);
        assert!(
            cos > 1.0 - 1e-6,
            "normal at ({u}, {v}) is not radial: cos {cos}"
        );
    }
}

#[test]
fn decomposition_is_exact_and_shares_rows() {
    let mut rng = Rng::for_test(17);
    for f in fixtures() {
        let s = f.k.surface();
        let size = s.decomposition_size();
        let mut headers = vec![PatchHeader::default(); size.patches];
        let mut points = vec![[0.0f32; 3]; size.points];
        let mut weights = vec![0.0f32; size.points];
        let mut domains = vec![ParamRect::default(); size.patches];
        // One too few of anything is refused with the needed size, and nothing is written.
        let mut short = vec![[7.0f32; 3]; size.points - 1];
        let err = s
            .decompose(&mut headers, &mut short, &mut weights, &mut domains)
            .unwrap_err();
        assert_eq!(
            err,
            spline_tess::DecomposeError::BufferTooSmall { needed: size }
        );
        assert!(short.iter().all(|p| *p == [7.0; 3]));

        let set = s
            .decompose(&mut headers, &mut points, &mut weights, &mut domains)
            .unwrap();
        assert_eq!(set.len(), size.patches);
        for (k, patch) in set.iter().enumerate() {
            let d = domains[k];
            for _ in 0..60 {
                let (a, b) = (rng.unit(), rng.unit());
                let u = d.u0 as f64 + a * (d.u1 - d.u0) as f64;
                let v = d.v0 as f64 + b * (d.v1 - d.v0) as f64;
                let piece = widen(patch.position(a as f32, b as f32));
                let e = dist(piece, f.r.eval(u, v).p) / f.diag;
                assert!(
                    e <= POSITION_TOL,
                    "{} piece {k} at ({a}, {b}): {e:e}",
                    f.name
                );
            }
        }
        // Interior span boundaries are found as shared curves.
        let (mut spans_u, mut spans_v) = (0, 0);
        for w in f.r.ku.windows(2) {
            spans_u += (w[0] < w[1]) as usize;
        }
        for w in f.r.kv.windows(2) {
            spans_v += (w[0] < w[1]) as usize;
        }
        let mut edges = vec![[EdgeLink::Collapsed; 4]; set.len()];
        let mut curves = vec![BoundaryCurve::default(); 4 * set.len()];
        let topo = Topology::build(&set, &mut edges, &mut curves).unwrap();
        let counts = topo.edge_counts();
        let interior = 2 * ((spans_u - 1) * spans_v + spans_u * (spans_v - 1));
        assert!(
            counts.shared >= interior,
            "{}: {} shared edges, {interior} interior span edges",
            f.name,
            counts.shared
        );
        println!(
            "{}: {} pieces, edges shared/open/collapsed {}/{}/{}",
            f.name, size.patches, counts.shared, counts.open, counts.collapsed
        );
    }
}
