//! A hierarchy's compact bytes: read in place, they give the meshes the bake's records give,
//! bit for bit (positions, normals, parameters, triangles and the frames' figures), on every
//! model of the repository; and bytes that are not a hierarchy of the model are refused with
//! what is wrong, never a panic.

use host_tests::bake_relative as bake;
use host_tests::runtime::{indexed, VecStorage};
use host_tests::{bpt_models, models_dir, nurbs_fixtures};
use spline_tess::tessellator::{FormatError, FORMAT_VERSION};
use spline_tess::{Hierarchy, Vec3, View};

/// Views of a model: in model units within and below the bake, and two cameras.
fn views(tree: &Hierarchy<'_>) -> Vec<View> {
    let b = tree.model().aabb().unwrap();
    let (c, d) = (b.center(), b.diagonal());
    let mut views = vec![
        View::Object {
            tolerance: 2e-2 * d,
        },
        View::Object {
            tolerance: 2e-3 * d,
        },
    ];
    for (eye, size) in [
        (Vec3::new(1.0, -1.0, 0.6), [320, 240]),
        (Vec3::new(0.1, 0.5, 0.2), [640, 480]),
    ] {
        let camera = host_tests::screen::camera_40(c + eye * d, c, 0.01 * d, size);
        views.push(View::Screen {
            camera,
            tolerance_px: 1.0,
        });
    }
    views
}

#[test]
fn bytes_give_the_records_meshes_on_every_model() {
    let models: Vec<_> = bpt_models().into_iter().chain(nurbs_fixtures()).collect();
    assert!(models.len() >= 12, "the repository's models");
    for path in &models {
        let name = path.display();
        let baked = bake(path, 1e-2);
        let records = baked.tree();
        let bytes = baked.encoded();
        assert_eq!(bytes, baked.encoded(), "{name}: encoding is deterministic");
        let read = baked.tree_from(&bytes);
        assert_eq!(read.node_count(), records.node_count(), "{name}");
        assert!(read.vertex_count() <= records.vertex_count(), "{name}");
        let mut a = VecStorage::new(&records, 256, 4096);
        let mut b = VecStorage::new(&read, 256, 4096);
        let (mut x, mut y) = (a.tessellator(records), b.tessellator(read));
        for view in views(&records) {
            let (sx, sy) = (x.update(&view).unwrap(), y.update(&view).unwrap());
            assert_eq!(sx, sy, "{name}: frame figures");
            let (mx, my) = (indexed(&mut x), indexed(&mut y));
            assert!(!mx.triangles.is_empty(), "{name}");
            assert_eq!(mx, my, "{name}: meshes from records and from bytes");
        }
    }
}

/// A hierarchy of more than 65,535 vertices keeps its numbers in `u32` (the vertex numbers and
/// the patch records' numbers), and still gives the records' meshes.
#[test]
fn a_hierarchy_of_wide_numbers_gives_the_records_meshes() {
    let baked = bake(&models_dir().join("teapot.bpt"), 5e-5);
    let records = baked.tree();
    assert!(
        records.vertex_count() > 65_535,
        "{}",
        records.vertex_count()
    );
    let bytes = baked.encoded();
    // Flag bit 0: wide numbers.
    assert_eq!(bytes[6] & 1, 1);
    let read = baked.tree_from(&bytes);
    let mut a = VecStorage::new(&records, 256, 4096);
    let mut b = VecStorage::new(&read, 256, 4096);
    let (mut x, mut y) = (a.tessellator(records), b.tessellator(read));
    for view in views(&records).into_iter().skip(1) {
        assert_eq!(x.update(&view).unwrap(), y.update(&view).unwrap());
        let (mx, my) = (indexed(&mut x), indexed(&mut y));
        assert!(!mx.triangles.is_empty());
        assert_eq!(mx, my, "meshes from records and from bytes");
    }
}

#[test]
fn bad_bytes_are_refused_with_what_is_wrong() {
    let baked = bake(&models_dir().join("teapot.bpt"), 2e-2);
    let patches = baked.file.patches();
    let bytes = baked.encoded();
    assert!(Hierarchy::from_bytes(patches, &bytes).is_ok());
    // Every cut: too short (or, past the magic, not a hierarchy at all).
    for len in (0..bytes.len()).filter(|l| *l < 256 || l % 97 == 0) {
        match Hierarchy::from_bytes(patches, &bytes[..len]) {
            Err(FormatError::Truncated { needed, found }) => {
                assert!(found == len && needed > len)
            }
            other => panic!("cut to {len}: {other:?}"),
        }
    }
    let mut longer = bytes.clone();
    longer.push(0);
    assert!(matches!(
        Hierarchy::from_bytes(patches, &longer),
        Err(FormatError::TrailingBytes { .. })
    ));
    // Every changed byte past the checksum, at a stride: a count of the header gives the
    // bytes another length (or counts no hierarchy has), any other byte another checksum.
    for at in (12..bytes.len()).step_by(7) {
        let mut b = bytes.clone();
        b[at] ^= 0x5a;
        let result = Hierarchy::from_bytes(patches, &b);
        if (16..56).contains(&at) {
            assert!(result.is_err(), "byte {at}");
        } else {
            assert!(
                matches!(result, Err(FormatError::ChecksumMismatch { .. })),
                "byte {at}: {:?}",
                result.err()
            );
        }
    }
    let mut b = bytes.clone();
    b[0] = b'X';
    assert_eq!(
        Hierarchy::from_bytes(patches, &b).err(),
        Some(FormatError::BadMagic)
    );
    let mut b = bytes.clone();
    b[4..6].copy_from_slice(&(FORMAT_VERSION + 1).to_le_bytes());
    assert_eq!(
        Hierarchy::from_bytes(patches, &b).err(),
        Some(FormatError::UnsupportedVersion {
            found: FORMAT_VERSION + 1
        })
    );
    // The bytes of another model.
    let other = bake(&models_dir().join("teaspoon.bpt"), 2e-2);
    assert!(matches!(
        Hierarchy::from_bytes(other.file.patches(), &bytes),
        Err(FormatError::ModelMismatch { .. })
    ));
    // Unaligned: the same bytes one byte into a buffer read the same.
    let mut shifted = vec![0u8; bytes.len() + 1];
    shifted[1..].copy_from_slice(&bytes);
    let tree = Hierarchy::from_bytes(patches, &shifted[1..]).unwrap();
    assert_eq!(tree.node_count(), baked.tree().node_count());
}
