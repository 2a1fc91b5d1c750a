//! The run time's typed errors and its behaviour on hostile views: bad cameras, buffers too
//! small (untouched, and saying what is needed), an index type too narrow, and random cameras
//! anywhere (inside, behind, far away) without a panic.

use host_tests::model_file::ModelFile;
use host_tests::models_dir;
use host_tests::runtime::{edge_uses, indexed, BakedHierarchy, VecStorage};
use host_tests::seeds::proptest_config;
use proptest::prelude::*;
use spline_tess::bake::BakeSettings;
use spline_tess::bake::Tolerance;
use spline_tess::{Camera, CameraError, Projection, Vec3, Vertex, View, WriteError};

fn teaspoon() -> BakedHierarchy {
    let file = ModelFile::read(models_dir().join("teaspoon.bpt").to_str().unwrap()).unwrap();
    let settings = BakeSettings {
        tolerance: Tolerance::Relative(2e-3),
        ..BakeSettings::default()
    };
    BakedHierarchy::bake(&file, &settings).unwrap()
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
fn small_buffers_are_untouched_and_say_what_is_needed() {
    let baked = teaspoon();
    let tree = baked.tree();
    let mut storage = VecStorage::new(&tree, 256, 1 << 18);
    let mut t = storage.tessellator(tree);
    let stats = t.update(&View::Object { tolerance: 1e-3 }).unwrap();
    let need = t.mesh_size();
    assert_eq!(need.triangles, stats.triangles);
    let mut remap = vec![0u32; t.remap_len()];
    let marker = Vertex {
        patch: 7777,
        ..Vertex::default()
    };
    let mut v = vec![marker; need.vertices - 1];
    let mut tr = vec![[9u32; 3]; need.triangles];
    let err = t.write_mesh(&mut v, &mut tr, &mut remap).unwrap_err();
    assert_eq!(err, WriteError::BuffersTooSmall { needed: need });
    assert!(err.to_string().contains("too small"), "{err}");
    assert!(v.iter().all(|x| *x == marker) && tr.iter().all(|x| *x == [9; 3]));
    let mut v = vec![marker; need.vertices];
    let mut tr = vec![[9u32; 3]; need.triangles - 1];
    assert_eq!(
        t.write_mesh(&mut v, &mut tr, &mut remap),
        Err(WriteError::BuffersTooSmall { needed: need })
    );
    assert!(v.iter().all(|x| *x == marker));
    // A mesh past 65 536 vertices cannot use u16 indices.
    t.update(&View::Object { tolerance: 1e-5 }).unwrap();
    let need = t.mesh_size();
    assert!(need.vertices > 65_536, "{need:?}");
    let mut v = vec![marker; need.vertices];
    let mut tr = vec![[0u16; 3]; need.triangles];
    let mut remap = vec![0u32; t.remap_len()];
    assert_eq!(
        t.write_mesh(&mut v, &mut tr, &mut remap),
        Err(WriteError::IndexOverflow {
            vertices: need.vertices
        })
    );
    assert!(v.iter().all(|x| *x == marker));
}

proptest! {
    #![proptest_config(proptest_config(48))]

    /// Any camera (inside the model, behind it, far away, grazing) and tolerance gives a mesh,
    /// never a panic, and the mesh never uses an edge more than twice; a budget is kept or
    /// refused with a typed error.
    #[test]
    fn random_views_never_panic(
        eye in prop::array::uniform3(-40.0f32..40.0),
        tol in 0.05f32..50.0,
        budget in 2usize..4000,
    ) {
        let baked = teaspoon();
        let tree = baked.tree();
        let mut storage = VecStorage::new(&tree, 64, 4096);
        let mut t = storage.tessellator(tree);
        let Ok(cam) = camera(Vec3::from_array(eye)) else { return Ok(()) };
        let view = View::Screen { camera: cam, tolerance_px: tol };
        let stats = t.update(&view).unwrap();
        let mesh = indexed(&mut t);
        prop_assert_eq!(mesh.triangles.len(), stats.triangles);
        prop_assert!(edge_uses(&mesh).values().all(|&(n, _)| n <= 2));
        match t.update_to_budget(&view, budget) {
            Ok(fit) => {
                prop_assert!(fit.stats.triangles <= budget);
                prop_assert!(fit.tolerance > 0.0);
            }
            Err(e) => prop_assert!(e.to_string().contains("budget"), "{}", e),
        }
    }
}
