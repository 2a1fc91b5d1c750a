//! Any control net, weights and parameters: construction is a typed error or evaluation gives
//! a finite unit normal (positions may overflow to infinity only for huge inputs).
#![no_main]

use libfuzzer_sys::fuzz_target;
use spline_tess::BezierPatch;

fuzz_target!(|data: &[u8]| {
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
});
