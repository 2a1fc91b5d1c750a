//! Any text: the NURBS JSON reader returns a typed error or a surface that evaluates and
//! decomposes without panicking.
#![no_main]

use libfuzzer_sys::fuzz_target;
use spline_tess::parse::{self, NurbsJsonBuffers};
use spline_tess::{ParamRect, PatchHeader};

fuzz_target!(|data: &[u8]| {
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
});
