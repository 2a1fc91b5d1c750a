//! The kernel's inputs: parsers, patch evaluation, the domain mesh and the baked format.

use spline_tess::bake::BakedModel;
use spline_tess::parse::{self, NurbsJsonBuffers};
use spline_tess::{BezierPatch, BoundaryCurve, EdgeLink, ParamRect, PatchHeader, Topology};
use spline_tess::{DomainMesh, GridPoint, MeshTriangle, MeshVertex, Metric, RemoveError};

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

/// Any sequence of insertions and removals: typed errors only, and the Euler count holds.
pub fn domain_mesh(data: &[u8]) {
    let mut vs = [MeshVertex::default(); 24];
    let mut ts = [MeshTriangle::default(); 42];
    let Ok(mut mesh) = DomainMesh::new(&mut vs, &mut ts) else {
        return;
    };
    // The same operations in one-byte slots: the same answers and the same slots.
    let mut vs8 = [MeshVertex::<u8>::default(); 24];
    let mut ts8 = [MeshTriangle::<u8>::default(); 42];
    let Ok(mut narrow) = DomainMesh::indexed(&mut vs8, &mut ts8, Metric::ISOTROPIC) else {
        return;
    };
    for op in data.chunks_exact(5) {
        if op[0] & 1 == 0 {
            // Coarse coordinates now and then, so cocircular ties are common.
            let coarse = op[0] & 2 != 0;
            let q = |a: u8, b: u8| {
                if coarse {
                    ((a % 9) as u32 * 65535 / 8) as u16
                } else {
                    u16::from_le_bytes([a, b])
                }
            };
            let p = GridPoint::new(q(op[1], op[2]), q(op[3], op[4]));
            assert_eq!(mesh.insert(p), narrow.insert(p));
        } else {
            let id = u16::from(op[1]) % 24;
            let removed = mesh.remove(id);
            assert_eq!(removed, narrow.remove(id));
            // A live vertex besides the corners always goes.
            assert!(
                !matches!(removed, Err(RemoveError::NoEar)),
                "no ear removing {id}"
            );
        }
        let boundary = mesh.vertices().filter(|(_, p)| p.on_boundary()).count();
        let interior = mesh.vertex_count() - boundary;
        assert_eq!(mesh.triangle_count(), 2 * interior + boundary - 2);
        check_neighbours(&mesh);
        assert!(mesh
            .triangles_with_neighbors()
            .eq(narrow.triangles_with_neighbors()));
    }
}

/// Every neighbour shares its edge, reversed, and points back.
fn check_neighbours(mesh: &DomainMesh<'_>) {
    for (t, v, n) in mesh.triangles_with_neighbors() {
        for i in 0..3 {
            let Some(s) = n[i] else { continue };
            let (a, b) = (v[(i + 1) % 3], v[(i + 2) % 3]);
            let w = mesh.triangle(s).expect("a neighbour is live");
            let j = (0..3)
                .find(|&j| w[(j + 1) % 3] == b && w[(j + 2) % 3] == a)
                .expect("a neighbour shares the edge, reversed");
            let back = mesh
                .triangles_with_neighbors()
                .find(|e| e.0 == s)
                .map(|e| e.2[j]);
            assert_eq!(
                back,
                Some(Some(t)),
                "triangle {s} does not point back to {t}"
            );
        }
    }
}

/// Any bytes: loading a baked model returns a typed error, or a model whose every record and
/// sample can be read.
pub fn baked_model(data: &[u8]) {
    let Ok(baked) = BakedModel::from_bytes(data) else {
        return;
    };
    for k in 0..baked.curve_count() {
        let c = baked.curve(k).expect("validated curve");
        assert!(c.samples.iter().all(|s| s.deviation.is_finite()));
    }
    for k in 0..baked.patch_count() {
        let p = baked.patch(k).expect("validated patch");
        assert!(p.samples.iter().all(|s| s.deviation.is_finite()));
    }
}
