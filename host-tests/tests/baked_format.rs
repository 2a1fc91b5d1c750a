//! The compact baked format: round trip against the kernel's samplers, every truncation and
//! every single-byte corruption of a small model rejected with a typed error (never a panic),
//! wrong versions, trailing bytes, malformed records under a valid checksum, determinism, and
//! the bake's own errors.

use host_tests::model_file::{bake_to_vec, ModelFile};
use host_tests::models_dir;
use spline_tess::bake::{
    bake_model, model_fingerprint, sample_curve, BakeError, BakeScratch, BakeSettings, BakedModel,
    CurveSample, CurveSegment, InteriorSample, LoadError, Part, Tolerance, TriangleDeviation,
};
use spline_tess::{EdgeLink, MeshTriangle, MeshVertex};

const SETTINGS: BakeSettings = BakeSettings {
    tolerance: Tolerance::Relative(2e-3),
    max_curve_samples: 64,
    max_interior_samples: 256,
};

fn teaspoon() -> ModelFile {
    ModelFile::read(models_dir().join("teaspoon.bpt").to_str().unwrap()).unwrap()
}

fn baked_teaspoon() -> Vec<u8> {
    teaspoon()
        .with_model(|m| bake_to_vec(m, &SETTINGS))
        .unwrap()
        .unwrap()
}

/// FNV-1a over all bytes but the checksum field (an independent implementation).
fn reseal(bytes: &mut [u8]) {
    let mut h: u32 = 0x811c_9dc5;
    for (k, &b) in bytes.iter().enumerate() {
        if (36..40).contains(&k) {
            continue;
        }
        h = (h ^ b as u32).wrapping_mul(0x0100_0193);
    }
    bytes[36..40].copy_from_slice(&h.to_le_bytes());
}

#[test]
fn round_trip_matches_the_samplers_and_the_topology() {
    let file = teaspoon();
    let bytes = baked_teaspoon();
    let baked = BakedModel::from_bytes(&bytes).unwrap();
    file.with_model(|model| {
        assert!(baked.matches(&model.patches));
        assert_eq!(baked.fingerprint(), model_fingerprint(&model.patches));
        assert_eq!(baked.patch_count(), model.patches.len());
        assert_eq!(baked.curve_count(), model.topology.curves().len());
        let tolerance = baked.tolerance();
        for (k, curve) in model.topology.curves().iter().enumerate() {
            let c = baked.curve(k).unwrap();
            assert_eq!((c.patch, c.side), (curve.patch, curve.side));
            let patch = model.patches.patch(curve.patch as usize).unwrap();
            let mut out = [CurveSample::default(); 64];
            let mut seg = [CurveSegment::default(); 65];
            let s = sample_curve(&patch, curve.side, tolerance, &mut out, &mut seg).unwrap();
            assert_eq!(
                c.samples.iter().collect::<Vec<_>>(),
                out[..s.samples].to_vec()
            );
            assert_eq!((c.stop, c.initial_deviation), (s.stop, s.initial_deviation));
        }
        for k in 0..model.patches.len() {
            let p = baked.patch(k).unwrap();
            let edges: [EdgeLink; 4] = model.topology.edges()[k];
            assert_eq!(p.edges, edges);
        }
        assert!(baked.interior_sample_count() > 100);
    })
    .unwrap();
    // Another model's patches do not match.
    let teapot = ModelFile::read(models_dir().join("teapot.bpt").to_str().unwrap()).unwrap();
    assert!(!baked.matches(&teapot.patches()));
}

#[test]
fn every_truncation_is_rejected() {
    let bytes = baked_teaspoon();
    assert!(BakedModel::from_bytes(&bytes).is_ok());
    for len in 0..bytes.len() {
        let err = BakedModel::from_bytes(&bytes[..len]).unwrap_err();
        let needed = if len < 40 { 40 } else { bytes.len() };
        assert_eq!(
            err,
            LoadError::Truncated { needed, found: len },
            "length {len}"
        );
    }
}

#[test]
fn every_single_byte_corruption_is_rejected() {
    let bytes = baked_teaspoon();
    for k in 0..bytes.len() {
        for flip in [0x01u8, 0x80, 0xff] {
            let mut bad = bytes.clone();
            bad[k] ^= flip;
            let err = BakedModel::from_bytes(&bad).unwrap_err();
            match k {
                0..=3 => assert_eq!(err, LoadError::BadMagic, "byte {k}"),
                4..=5 => assert!(
                    matches!(err, LoadError::UnsupportedVersion { .. }),
                    "byte {k}: {err:?}"
                ),
                _ => {}
            }
        }
    }
}

#[test]
fn versions_trailing_bytes_and_malformed_records() {
    let bytes = baked_teaspoon();
    // Version 1 recorded sampled deviations, not bounds: it is refused.
    let mut v1 = bytes.clone();
    v1[4] = 1;
    assert_eq!(
        BakedModel::from_bytes(&v1),
        Err(LoadError::UnsupportedVersion { found: 1 })
    );
    // Version 2 stored no surface point or offset per step.
    let mut v2 = bytes.clone();
    v2[4] = 2;
    assert_eq!(
        BakedModel::from_bytes(&v2),
        Err(LoadError::UnsupportedVersion { found: 2 })
    );
    let mut v4 = bytes.clone();
    v4[4] = 4;
    assert_eq!(
        BakedModel::from_bytes(&v4),
        Err(LoadError::UnsupportedVersion { found: 4 })
    );
    let mut long = bytes.clone();
    long.push(0);
    assert_eq!(
        BakedModel::from_bytes(&long),
        Err(LoadError::TrailingBytes {
            expected: bytes.len(),
            found: bytes.len() + 1
        })
    );
    // A valid checksum over bad content: an increasing deviation in patch 0's samples.
    let baked = BakedModel::from_bytes(&bytes).unwrap();
    let curves = baked.curve_count();
    let patches_start = 40 + 16 * curves;
    let samples_start = patches_start + 52 * baked.patch_count();
    let interior_start = samples_start + 6 * baked.curve_sample_count();
    let mut bad = bytes.clone();
    bad[interior_start + 21 + 4..interior_start + 21 + 8].copy_from_slice(&1e9f32.to_le_bytes());
    reseal(&mut bad);
    assert_eq!(
        BakedModel::from_bytes(&bad),
        Err(LoadError::Malformed(Part::Patch(0)))
    );
    // A curve owned by a patch that does not exist.
    let mut bad = bytes.clone();
    bad[40..44].copy_from_slice(&999u32.to_le_bytes());
    reseal(&mut bad);
    assert_eq!(
        BakedModel::from_bytes(&bad),
        Err(LoadError::Malformed(Part::Curve(0)))
    );
    // A point box with a negative extent, or one whose far corner overflows.
    for (at, value) in [(40, -1.0f32), (28, f32::MAX)] {
        let mut bad = bytes.clone();
        let extent_x = patches_start + at;
        bad[extent_x..extent_x + 4].copy_from_slice(&value.to_le_bytes());
        if at == 28 {
            bad[extent_x + 12..extent_x + 16].copy_from_slice(&value.to_le_bytes());
        }
        reseal(&mut bad);
        assert_eq!(
            BakedModel::from_bytes(&bad),
            Err(LoadError::Malformed(Part::Patch(0))),
            "box field at {at}"
        );
    }
    // An offset exponent whose mantissas would decode past `f32`'s range.
    let mut bad = bytes.clone();
    bad[interior_start + 20] = 120;
    reseal(&mut bad);
    assert_eq!(
        BakedModel::from_bytes(&bad),
        Err(LoadError::Malformed(Part::Patch(0)))
    );
    // An interior sample inside the boundary margin.
    let mut bad = bytes.clone();
    bad[interior_start..interior_start + 2].copy_from_slice(&1u16.to_le_bytes());
    reseal(&mut bad);
    assert_eq!(
        BakedModel::from_bytes(&bad),
        Err(LoadError::Malformed(Part::Patch(0)))
    );
}

#[test]
fn bakes_are_deterministic_and_errors_are_typed() {
    let file = teaspoon();
    let first = baked_teaspoon();
    assert_eq!(first, baked_teaspoon());
    file.with_model(|model| {
        let n = SETTINGS.scratch_size();
        // Larger scratch than needed gives the same bytes.
        let mut vs = vec![MeshVertex::default(); n.vertices + 100];
        let mut ts = vec![MeshTriangle::default(); n.triangles + 100];
        let mut ds = vec![TriangleDeviation::default(); n.triangles + 100];
        let mut sg = vec![CurveSegment::default(); n.segments + 5];
        let mut cs = vec![CurveSample::default(); n.curve_samples + 5];
        let mut is = vec![InteriorSample::default(); n.interior_samples + 5];
        let mut out = vec![0u8; first.len()];
        macro_rules! scratch {
            () => {
                BakeScratch {
                    vertices: &mut vs,
                    triangles: &mut ts,
                    deviations: &mut ds,
                    segments: &mut sg,
                    curve_samples: &mut cs,
                    interior_samples: &mut is,
                }
            };
        }
        let summary = bake_model(model, &SETTINGS, scratch!(), &mut out).unwrap();
        assert_eq!(&out[..summary.bytes], &first[..]);
        // Too small an output: the exact size, and nothing loadable left behind.
        let mut small = vec![0u8; first.len() - 1];
        assert_eq!(
            bake_model(model, &SETTINGS, scratch!(), &mut small),
            Err(BakeError::OutputTooSmall {
                needed: first.len()
            })
        );
        assert!(BakedModel::from_bytes(&small).is_err());
        for bad in [f32::NAN, -1.0, f32::INFINITY] {
            let settings = BakeSettings {
                tolerance: Tolerance::Absolute(bad),
                ..SETTINGS
            };
            assert_eq!(
                bake_model(model, &settings, scratch!(), &mut out),
                Err(BakeError::BadTolerance)
            );
        }
    })
    .unwrap();
    file.with_model(|model| {
        let n = SETTINGS.scratch_size();
        let mut vs = vec![MeshVertex::default(); n.vertices - 1];
        let mut ts = vec![MeshTriangle::default(); n.triangles];
        let mut ds = vec![TriangleDeviation::default(); n.triangles];
        let mut sg = vec![CurveSegment::default(); n.segments];
        let mut cs = vec![CurveSample::default(); n.curve_samples];
        let mut is = vec![InteriorSample::default(); n.interior_samples];
        let scratch = BakeScratch {
            vertices: &mut vs,
            triangles: &mut ts,
            deviations: &mut ds,
            segments: &mut sg,
            curve_samples: &mut cs,
            interior_samples: &mut is,
        };
        let mut out = vec![0u8; 1 << 20];
        assert_eq!(
            bake_model(model, &SETTINGS, scratch, &mut out),
            Err(BakeError::ScratchTooSmall(n))
        );
    })
    .unwrap();
}
