//! The run time's typed errors and its behaviour on hostile views: bad tolerances and cameras,
//! buffers too small (untouched), an index type too narrow, a mismatched bake, short storage,
//! and random cameras anywhere (inside, behind, far away) without a panic.

use host_tests::model_file::{bake_to_vec, ModelFile};
use host_tests::models_dir;
use host_tests::runtime::{edge_uses, indexed, RuntimeStorage};
use host_tests::seeds::proptest_config;
use proptest::prelude::*;
use spline_tess::bake::{BakeSettings, BakedModel, Tolerance};
use spline_tess::tessellator::{
    Settings, StorageSize, Tessellator, TessellatorError, TessellatorStorage, UpdateError,
};
use spline_tess::{Camera, CameraError, Projection, Vec3, Vertex, View, WriteError};

fn teaspoon() -> (ModelFile, Vec<u8>) {
    let file = ModelFile::read(models_dir().join("teaspoon.bpt").to_str().unwrap()).unwrap();
    let settings = BakeSettings {
        tolerance: Tolerance::Relative(2e-3),
        max_curve_samples: 64,
        max_interior_samples: 256,
    };
    let bytes = file
        .with_model(|m| bake_to_vec(m, &settings))
        .unwrap()
        .unwrap();
    (file, bytes)
}

fn camera(eye: Vec3) -> Result<Camera, CameraError> {
    Camera::new(
        eye,
        Vec3::ZERO,
        Vec3::Z,
        Projection::Perspective {
            fov_y_degrees: 45.0,
        },
        0.05,
        [320, 240],
    )
}

#[test]
fn bad_cameras_are_typed_errors() {
    let p = Projection::Perspective {
        fov_y_degrees: 45.0,
    };
    let at = |eye, target, up, p, near, vp| Camera::new(eye, target, up, p, near, vp);
    let (e, t) = (Vec3::new(0.0, -5.0, 0.0), Vec3::ZERO);
    assert_eq!(
        at(Vec3::NAN, t, Vec3::Z, p, 0.1, [8, 8]),
        Err(CameraError::NotFinite)
    );
    assert_eq!(
        at(e, e, Vec3::Z, p, 0.1, [8, 8]),
        Err(CameraError::EyeAtTarget)
    );
    assert_eq!(at(e, t, Vec3::Y, p, 0.1, [8, 8]), Err(CameraError::BadUp));
    assert_eq!(
        at(e, t, Vec3::ZERO, p, 0.1, [8, 8]),
        Err(CameraError::BadUp)
    );
    for fov in [0.0, 180.0, -3.0] {
        let q = Projection::Perspective { fov_y_degrees: fov };
        assert_eq!(
            at(e, t, Vec3::Z, q, 0.1, [8, 8]),
            Err(CameraError::BadProjection)
        );
    }
    let q = Projection::Orthographic { height: 0.0 };
    assert_eq!(
        at(e, t, Vec3::Z, q, 0.1, [8, 8]),
        Err(CameraError::BadProjection)
    );
    assert_eq!(at(e, t, Vec3::Z, p, 0.0, [8, 8]), Err(CameraError::BadNear));
    assert_eq!(
        at(e, t, Vec3::Z, p, 0.1, [0, 8]),
        Err(CameraError::EmptyViewport)
    );
    assert!(at(e, t, Vec3::Z, p, 0.1, [8, 8]).is_ok());
}

#[test]
fn storage_bake_and_tolerance_errors() {
    let (file, bytes) = teaspoon();
    let baked = BakedModel::from_bytes(&bytes).unwrap();
    let settings = Settings::default();
    let need = StorageSize::minimum(&baked, &settings);
    // Short storage (a pool below four vertex and two triangle slots per patch): the error
    // names every size.
    let mut st = RuntimeStorage::new(&baked, &settings);
    let mut t = st.tessellator(file.patches(), baked, settings);
    for tol in [0.0, -1.0, f32::NAN, f32::INFINITY] {
        assert_eq!(
            t.update(&View::Object { tolerance: tol }),
            Err(UpdateError::BadTolerance)
        );
    }
    let mut patches = vec![Default::default(); need.patches];
    let mut curves = vec![Default::default(); need.curves];
    let mut order = vec![0u16; need.curve_order];
    let mut vertices = vec![Default::default(); need.vertices];
    let mut triangles = vec![Default::default(); need.triangles - 1];
    let mut states = vec![Default::default(); need.triangles];
    let mut scratch = vec![0u32; need.scratch];
    let storage = TessellatorStorage {
        patches: &mut patches,
        curves: &mut curves,
        curve_order: &mut order,
        vertices: &mut vertices,
        triangles: &mut triangles,
        triangle_states: &mut states,
        bounds: &mut [],
        vertex_points: &mut [],
        scratch: &mut scratch,
    };
    let err = Tessellator::new(file.patches(), baked, settings, storage).unwrap_err();
    assert_eq!(err, TessellatorError::StorageTooSmall { needed: need });
    assert!(err.to_string().contains("storage too small"));
    // A bake of another model.
    let other = ModelFile::read(models_dir().join("teacup.bpt").to_str().unwrap()).unwrap();
    let mut triangles = vec![Default::default(); need.triangles];
    let storage = TessellatorStorage {
        patches: &mut patches,
        curves: &mut curves,
        curve_order: &mut order,
        vertices: &mut vertices,
        triangles: &mut triangles,
        triangle_states: &mut states,
        bounds: &mut [],
        vertex_points: &mut [],
        scratch: &mut scratch,
    };
    let err = Tessellator::new(other.patches(), baked, settings, storage).unwrap_err();
    assert_eq!(err, TessellatorError::ModelMismatch);
}

#[test]
fn small_buffers_are_untouched_and_say_what_is_needed() {
    let (file, bytes) = teaspoon();
    let baked = BakedModel::from_bytes(&bytes).unwrap();
    let settings = Settings::default();
    let mut st = RuntimeStorage::new(&baked, &settings);
    let mut t = st.tessellator(file.patches(), baked, settings);
    let stats = t.update(&View::Object { tolerance: 1e-3 }).unwrap();
    let need = t.mesh_size();
    assert_eq!(
        (need.vertices, need.triangles),
        (stats.vertices, stats.triangles)
    );
    let marker = Vertex {
        patch: 7777,
        ..Vertex::default()
    };
    let mut v = vec![marker; need.vertices - 1];
    let mut tr = vec![[9u32; 3]; need.triangles];
    let err = t.write_mesh(&mut v, &mut tr).unwrap_err();
    assert_eq!(err, WriteError::BuffersTooSmall { needed: need });
    assert!(v.iter().all(|x| *x == marker) && tr.iter().all(|x| *x == [9; 3]));
    let mut v = vec![marker; need.vertices];
    let mut tr = vec![[9u32; 3]; need.triangles - 1];
    assert_eq!(
        t.write_mesh(&mut v, &mut tr),
        Err(WriteError::BuffersTooSmall { needed: need })
    );
    assert!(v.iter().all(|x| *x == marker));
    // A mesh past 65 536 vertices cannot use u16 indices.
    t.update(&View::Object { tolerance: 2e-6 }).unwrap();
    let need = t.mesh_size();
    assert!(need.vertices > 65_536, "{need:?}");
    let mut v = vec![marker; need.vertices];
    let mut tr = vec![[0u16; 3]; need.triangles];
    assert_eq!(
        t.write_mesh(&mut v, &mut tr),
        Err(WriteError::IndexOverflow {
            vertices: need.vertices
        })
    );
    assert!(v.iter().all(|x| *x == marker));
}

#[test]
fn streaming_needs_no_write_scratch_and_write_mesh_says_what_it_needs() {
    let (file, bytes) = teaspoon();
    let baked = BakedModel::from_bytes(&bytes).unwrap();
    let settings = Settings::default();
    let view = View::Object { tolerance: 2e-3 };
    // The reference: storage for every frame, written.
    let mut full = RuntimeStorage::new(&baked, &settings);
    let mut reference = full.tessellator(file.patches(), baked, settings);
    let stats = reference.update(&view).unwrap();
    let mesh = indexed(&mut reference);
    // The same pool with only the least scratch (three per patch, for building): the frame
    // is counted and streamed the same.
    let size = StorageSize {
        scratch: StorageSize::minimum(&baked, &settings).scratch,
        ..StorageSize::of(&baked, &settings)
    };
    assert_eq!(size.scratch, 3 * baked.patch_count());
    let mut short = RuntimeStorage::with_size(&size);
    let mut t = short.tessellator(file.patches(), baked, settings);
    assert_eq!(t.update(&view).unwrap(), stats);
    assert_eq!(t.mesh_size(), reference.mesh_size());
    let mut streamed = 0;
    t.stream_with_info(|_, _| streamed += 1);
    assert_eq!(streamed, stats.triangles);
    for p in 0..baked.patch_count() {
        assert_eq!(t.patch_triangles(p), reference.patch_triangles(p));
    }
    // Writing needs the index tables: a typed error, the buffers untouched.
    let marker = Vertex {
        patch: 7777,
        ..Vertex::default()
    };
    let mut v = vec![marker; mesh.vertices.len()];
    let mut tr = vec![[9u32; 3]; mesh.triangles.len()];
    let Err(WriteError::ScratchTooSmall { needed }) = t.write_mesh(&mut v, &mut tr) else {
        panic!("write_mesh with the least scratch must fail");
    };
    assert!(v.iter().all(|x| *x == marker) && tr.iter().all(|x| *x == [9; 3]));
    assert!(needed > size.scratch && needed <= StorageSize::of(&baked, &settings).scratch);
    assert!(WriteError::ScratchTooSmall { needed }
        .to_string()
        .contains("scratch"));
    // With exactly what it asked for, it writes the reference's mesh.
    let mut enough = RuntimeStorage::with_size(&StorageSize {
        scratch: needed,
        ..size
    });
    let mut t = enough.tessellator(file.patches(), baked, settings);
    t.update(&view).unwrap();
    assert_eq!(indexed(&mut t), mesh);
}

proptest! {
    #![proptest_config(proptest_config(48))]

    /// Any camera (inside the model, behind it, far away, grazing) and tolerance gives a mesh
    /// or a typed error, never a panic, and the mesh never uses an edge more than twice.
    #[test]
    fn random_views_never_panic(
        eye in prop::array::uniform3(-40.0f32..40.0),
        tol in 0.05f32..50.0,
        budget in 2usize..4000,
    ) {
        let (file, bytes) = teaspoon();
        let baked = BakedModel::from_bytes(&bytes).unwrap();
        let settings = Settings { max_factor: 4, ..Settings::default() };
        let mut st = RuntimeStorage::new(&baked, &settings);
        let mut t = st.tessellator(file.patches(), baked, settings);
        let Ok(cam) = camera(Vec3::from_array(eye)) else { return Ok(()) };
        let view = View::Screen { camera: cam, tolerance_px: tol };
        let stats = t.update(&view).unwrap();
        let mesh = indexed(&mut t);
        prop_assert_eq!(mesh.triangles.len(), stats.triangles);
        prop_assert!(edge_uses(&mesh).values().all(|&(n, _)| n <= 2));
        match t.update_to_budget(&view, budget) {
            Ok((s, fit)) => {
                prop_assert!(s.triangles <= budget);
                prop_assert!(fit.tolerance > 0.0);
            }
            Err(e) => prop_assert!(e.to_string().contains("budget too small")),
        }
    }
}

/// The caches change a frame's cost, never its output: a tessellator with full bound and
/// vertex caches, one with caches of a few entries (so entries are taken over all the time)
/// and one with none write the same meshes and stream the same triangles, bit for bit, along
/// a path of views that inserts, deletes, refines and lays the pool out again.
#[test]
fn caches_change_cost_not_output() {
    let (file, bytes) = teaspoon();
    let baked = BakedModel::from_bytes(&bytes).unwrap();
    let settings = Settings::default();
    let full = StorageSize::of(&baked, &settings);
    let sizes = [
        full,
        StorageSize {
            bounds: 7,
            vertex_points: 13,
            ..full
        },
        StorageSize {
            bounds: 0,
            vertex_points: 0,
            ..full
        },
    ];
    let mut storages: Vec<RuntimeStorage> = sizes.iter().map(RuntimeStorage::with_size).collect();
    let mut tessellators: Vec<Tessellator<'_, '_>> = storages
        .iter_mut()
        .map(|s| s.tessellator(file.patches(), baked, settings))
        .collect();
    let eyes = [
        Vec3::new(6.0, -5.0, 4.0),
        Vec3::new(1.5, -1.0, 1.0),
        Vec3::new(1.6, -0.9, 1.0),
        Vec3::new(0.4, 0.3, 0.5),
        Vec3::new(8.0, 3.0, -2.0),
        Vec3::new(1.5, -1.0, 1.0),
    ];
    let mut estimated = vec![0usize; sizes.len()];
    for (k, eye) in eyes.into_iter().enumerate() {
        let view = View::Screen {
            camera: camera(eye).unwrap(),
            tolerance_px: 0.5,
        };
        let mut outputs = Vec::new();
        for (i, tess) in tessellators.iter_mut().enumerate() {
            let stats = tess.update(&view).unwrap();
            estimated[i] += stats.estimated;
            let mesh = indexed(tess);
            let mut streamed = Vec::new();
            tess.stream_with_info(|info, c| {
                streamed.push((info.patch, c.map(|v| bits(std::slice::from_ref(v))[0])))
            });
            outputs.push((stats.triangles, mesh, streamed));
        }
        for o in &outputs[1..] {
            assert_eq!(o.0, outputs[0].0, "view {k}: triangle counts");
            assert!(
                bits(&o.1.vertices) == bits(&outputs[0].1.vertices),
                "view {k}"
            );
            assert_eq!(o.1.triangles, outputs[0].1.triangles, "view {k}");
            assert_eq!(o.2, outputs[0].2, "view {k}: streamed triangles");
        }
    }
    // The full cache spared work the others did again.
    assert!(estimated[0] < estimated[2], "{estimated:?}");
}

/// The bits of every vertex's fields.
/// A sink that records each streamed triangle's corner keys and vertices.
#[derive(Default)]
struct KeyedRecord {
    triangles: Vec<(u32, [u64; 3], [[u32; 9]; 3])>,
}

impl spline_tess::TriangleSink for KeyedRecord {
    fn triangle(&mut self, _: u32, _: [&Vertex; 3]) {
        panic!("a tessellator names its corners");
    }

    fn keyed_triangle(
        &mut self,
        patch: u32,
        keys: [u64; 3],
        corner: &mut dyn FnMut(usize) -> Vertex,
    ) {
        let corners = [0, 1, 2].map(|i| bits(&[corner(i)])[0]);
        self.triangles.push((patch, keys, corners));
    }
}

#[test]
fn stream_keys_name_vertices() {
    // Equal keys are the same vertex with the same bits, over refined frames (edge and face
    // points, curve points at refined factors) and frames that keep the mesh; the keyed
    // stream hands the triangles `stream_with_info` hands.
    let (file, bytes) = teaspoon();
    let baked = BakedModel::from_bytes(&bytes).unwrap();
    let settings = Settings::default();
    let mut storage = RuntimeStorage::with_size(&StorageSize::of(&baked, &settings));
    let mut tess = storage.tessellator(file.patches(), baked, settings);
    let mut refined = 0;
    let mut shared = 0;
    for eye in [
        Vec3::new(6.0, -5.0, 4.0),
        Vec3::new(1.5, -1.0, 1.0),
        Vec3::new(0.4, 0.3, 0.5),
        Vec3::new(8.0, 3.0, -2.0),
    ] {
        for tolerance_px in [2.0, 0.25] {
            let stats = tess
                .update(&View::Screen {
                    camera: camera(eye).unwrap(),
                    tolerance_px,
                })
                .unwrap();
            refined += stats.refined_patches;
            let mut record = KeyedRecord::default();
            tess.stream(&mut record);
            let mut plain = Vec::new();
            tess.stream_with_info(|info, c| {
                plain.push((info.patch, c.map(|v| bits(std::slice::from_ref(v))[0])))
            });
            let keyed: Vec<_> = record.triangles.iter().map(|&(p, _, c)| (p, c)).collect();
            assert_eq!(keyed, plain, "{eye} at {tolerance_px} px");
            let mut named = std::collections::HashMap::new();
            for (_, keys, corners) in &record.triangles {
                for (key, corner) in keys.iter().zip(corners) {
                    let first = named.entry(*key).or_insert(*corner);
                    assert_eq!(first, corner, "key {key:#x}, {eye} at {tolerance_px} px");
                }
            }
            shared += 3 * record.triangles.len() - named.len();
        }
    }
    assert!(
        refined > 0 && shared > 0,
        "{refined} refined, {shared} shared"
    );
}

fn bits(vertices: &[Vertex]) -> Vec<[u32; 9]> {
    vertices
        .iter()
        .map(|v| {
            let f = [
                v.position[0],
                v.position[1],
                v.position[2],
                v.normal[0],
                v.normal[1],
                v.normal[2],
                v.uv[0],
                v.uv[1],
                v.patch as f32,
            ];
            f.map(f32::to_bits)
        })
        .collect()
}
