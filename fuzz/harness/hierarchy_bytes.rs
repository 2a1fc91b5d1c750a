//! A hierarchy's compact bytes, changed: read against the teaspoon's patches
//! (`Hierarchy::from_bytes`), and where they are taken, a few frames made and written.
//!
//! The input's first byte chooses how the bytes are made. Bit 1 set: the teaspoon's own
//! bytes (baked at 1e-2 of its diagonal), with the rest of the input as edits (three bytes
//! each: an offset, spread over the bytes, and a value to xor there); else the rest of the
//! input as it is. Bit 0 set: the model's fingerprint and the checksum are put right after
//! that, so that the checks past them (and the frames) are reached.
//!
//! What must hold: no panic, and a frame of bytes that were taken is written whole, every
//! index pointing at a written vertex.

use std::sync::OnceLock;

use spline_tess::bake::{BakeSettings, Tolerance};
use spline_tess::tessellator::{model_fingerprint, PoolSlot, StackSlot, Tessellator};
use spline_tess::{Camera, Hierarchy, Projection, Vec3, Vertex, View};

use super::bytes::Bytes;
use super::model_file::{BakedHierarchy, ModelFile};

/// The teaspoon and its bytes.
fn teaspoon() -> &'static (BakedHierarchy, Vec<u8>) {
    static BAKE: OnceLock<(BakedHierarchy, Vec<u8>)> = OnceLock::new();
    BAKE.get_or_init(|| {
        let file = ModelFile::from_bpt(include_str!("../../examples/models/teaspoon.bpt"))
            .expect("the teaspoon parses");
        let settings = BakeSettings {
            tolerance: Tolerance::Relative(1e-2),
            ..BakeSettings::default()
        };
        let baked = BakedHierarchy::bake(&file, &settings).expect("the teaspoon bakes");
        let bytes = baked.encoded();
        (baked, bytes)
    })
}

fn fnv1a(bytes: &[u8]) -> u32 {
    let mut h = 0x811c_9dc5u32;
    for &b in bytes {
        h ^= b as u32;
        h = h.wrapping_mul(0x0100_0193);
    }
    h
}

pub fn hierarchy_bytes(data: &[u8]) {
    let (baked, fresh) = teaspoon();
    let patches = baked.file.patches();
    let mut r = Bytes::new(data);
    let mode = r.u8();
    let mut bytes = if mode & 2 != 0 {
        let mut b = fresh.clone();
        while !r.is_empty() {
            let at = r.u16() as usize * b.len() / 65_536;
            b[at] ^= r.u8();
        }
        b
    } else {
        data.get(1..).unwrap_or_default().to_vec()
    };
    if mode & 1 != 0 && bytes.len() >= 16 {
        bytes[12..16].copy_from_slice(&model_fingerprint(&patches).to_le_bytes());
        let sum = fnv1a(&bytes[12..]);
        bytes[8..12].copy_from_slice(&sum.to_le_bytes());
    }
    let Ok(tree) = Hierarchy::from_bytes(patches, &bytes) else {
        return;
    };
    let mut bits = vec![0u32; tree.bit_words()];
    let mut stack = vec![StackSlot::default(); 64];
    let mut pool = vec![PoolSlot::default(); 64];
    let Ok(mut s) = Tessellator::from_slices(tree, &mut bits, &mut stack, &mut pool) else {
        panic!("storage sized by the hierarchy is refused");
    };
    let diag = patches.aabb().map_or(1.0, |b| b.diagonal());
    let camera = Camera::new(
        Vec3::new(0.9, -1.3, 0.8),
        Vec3::new(0.0, -0.4, 0.0),
        Vec3::Z,
        Projection::Perspective {
            fov_y_degrees: 40.0,
        },
        0.01,
        [128, 160],
    );
    let mut views = vec![
        View::Object {
            tolerance: 2e-2 * diag,
        },
        View::Object {
            tolerance: 5e-3 * diag,
        },
    ];
    if let Ok(camera) = camera {
        views.push(View::Screen {
            camera,
            tolerance_px: 1.0,
        });
    }
    for view in views {
        s.update(&view).expect("a valid tolerance");
        let size = s.mesh_size();
        let mut remap = vec![0u32; s.remap_len()];
        let mut vs = vec![Vertex::default(); size.vertices];
        let mut ts = vec![[0u32; 3]; size.triangles];
        let written = s
            .write_mesh(&mut vs, &mut ts, &mut remap)
            .expect("exact buffers");
        assert_eq!(written, size);
        assert!(ts.iter().flatten().all(|&i| (i as usize) < vs.len()));
        s.stream(&mut Count(0));
    }
}

/// A sink that counts.
struct Count(usize);

impl spline_tess::TriangleSink for Count {
    fn triangle(&mut self, _: u32, _: [&Vertex; 3]) {
        self.0 += 1;
    }
}
