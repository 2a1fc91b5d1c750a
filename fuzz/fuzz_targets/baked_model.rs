//! Any bytes: loading a baked model returns a typed error, or a model whose every record and
//! sample can be read.
#![no_main]

use libfuzzer_sys::fuzz_target;
use spline_tess::bake::BakedModel;

fuzz_target!(|data: &[u8]| {
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
});
