//! The kernel's inputs: the parsers and patch evaluation.

use spline_tess::parse::{self, NurbsJsonBuffers};
use spline_tess::{BezierPatch, BoundaryCurve, EdgeLink, ParamRect, PatchHeader, Topology};

/// Any text: the BPT parser returns a typed error or patches whose topology builds and whose
/// evaluation is finite.
pub fn parse_bpt(data: &[u8]) {
    let Ok(text) = core::str::from_utf8(data) else {
        return;
    };
    let mut headers = [PatchHeader::default(); 8];
    let mut points = [[0.0f32; 3]; 512];
    let Ok(set) = parse::parse_bpt(text, &mut headers, &mut points) else {
        return;
    };
    let mut edges = [[EdgeLink::Collapsed; 4]; 8];
    let mut curves = [BoundaryCurve::default(); 32];
    let _ = Topology::build(&set, &mut edges, &mut curves);
    for patch in set.iter() {
        for (u, v) in [(0.0, 0.0), (0.5, 0.25), (1.0, 1.0), (0.0, 1.0)] {
            let e = patch.evaluate(u, v);
            assert!(e.normal.is_finite());
            assert!((e.normal.length() - 1.0).abs() < 1e-3);
        }
    }
}

/// Any text: the NURBS JSON reader returns a typed error or a surface that evaluates and
/// decomposes without panicking.
pub fn parse_nurbs_json(data: &[u8]) {
    let Ok(text) = core::str::from_utf8(data) else {
        return;
    };
    let (mut ku, mut kv, mut pts, mut w) = ([0.0; 32], [0.0; 32], [[0.0; 3]; 128], [0.0; 128]);
    let b = NurbsJsonBuffers {
        knots_u: &mut ku,
        knots_v: &mut kv,
        points: &mut pts,
        weights: &mut w,
    };
    let Ok(s) = parse::parse_nurbs_json(text, b) else {
        return;
    };
    let d = s.domain();
    for (a, c) in [(0.0, 0.0), (0.3, 0.7), (1.0, 1.0)] {
        let _ = s.evaluate(d.u0 + a * (d.u1 - d.u0), d.v0 + c * (d.v1 - d.v0));
    }
    let mut headers = [PatchHeader::default(); 64];
    let mut bez = [[0.0; 3]; 1024];
    let mut bw = [0.0; 1024];
    let mut domains = [ParamRect::default(); 64];
    if let Ok(set) = s.decompose(&mut headers, &mut bez, &mut bw, &mut domains) {
        for p in set.iter() {
            let _ = p.evaluate(0.5, 0.5);
        }
    }
}

/// Any control net, weights and parameters: construction is a typed error or evaluation gives
/// a finite unit normal (positions may overflow to infinity only for huge inputs).
pub fn evaluate(data: &[u8]) {
    if data.len() < 4 {
        return;
    }
    let (du, dv) = ((data[0] % 9) as usize, (data[1] % 9) as usize);
    let floats: Vec<f32> = data[2..]
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    let n = (du + 1) * (dv + 1);
    if floats.len() < 4 * n + 2 {
        return;
    }
    let points: Vec<[f32; 3]> = (0..n)
        .map(|k| [floats[3 * k], floats[3 * k + 1], floats[3 * k + 2]])
        .collect();
    let weights = &floats[3 * n..4 * n];
    let (u, v) = (floats[4 * n], floats[4 * n + 1]);
    if let Ok(p) = BezierPatch::new_rational(du, dv, &points, weights) {
        let e = p.evaluate(u, v);
        assert!(e.normal.is_finite(), "normal {:?}", e.normal);
        let _ = p.position(u, v);
        let _ = p.aabb();
    }
}
