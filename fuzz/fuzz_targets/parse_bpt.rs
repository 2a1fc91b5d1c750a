//! Any text: the BPT parser returns a typed error or patches whose topology builds and whose
//! evaluation is finite.
#![no_main]

use libfuzzer_sys::fuzz_target;
use spline_tess::{parse, BoundaryCurve, EdgeLink, PatchHeader, Topology};

fuzz_target!(|data: &[u8]| {
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
});
