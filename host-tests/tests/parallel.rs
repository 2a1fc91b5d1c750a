//! A frame searched on several threads (`Tessellator::update_parallel`) is the frame searched
//! on one, bit for bit: on every model of the repository, from its records with links and
//! from its bytes without, within the bake and below it, on pools of 1, 2 and 3 threads, with a
//! tessellator kept from view to view, with the bounds in floats and in integers. A mesh
//! written on several threads (`Tessellator::write_mesh_parallel`) is the mesh written on one,
//! with the same errors.

use host_tests::bake_relative as bake;
use host_tests::runtime::Mesh;
use host_tests::runtime::{indexed, VecStorage};
use host_tests::{bpt_models, nurbs_fixtures};
use spline_tess::tessellator::{FrameStats, NodeLink, Tessellator};
use spline_tess::{Arithmetic, Camera, Hierarchy, Projection, Vec3, Vertex, View, WriteError};

/// Views of a model: in model units within and below the bake, and cameras from afar, from
/// close by (below the bake) and from inside its box.
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
    let eyes = [
        (Vec3::new(1.0, -1.0, 0.6), [320, 240], 1.0),
        (Vec3::new(0.1, 0.5, 0.2), [640, 480], 1.0),
        (Vec3::new(0.35, -0.3, 0.25), [1024, 768], 0.5),
        (Vec3::new(0.05, 0.02, 0.01), [320, 240], 2.0),
    ];
    for (eye, size, tolerance_px) in eyes {
        let camera = host_tests::screen::camera_40(c + eye * d, c, 0.01 * d, size);
        views.push(View::Screen {
            camera,
            tolerance_px,
        });
    }
    views
}

/// A frame's figures but for how the search went: what it judged, its walks and its stack,
/// the worst bound of what it judged (on the way, not only the mesh's), and where it walked
/// for leaves the stack had no room for, the vertices it made below the bake (a walk counts
/// some again).
fn figures(s: FrameStats) -> FrameStats {
    FrameStats {
        judged: 0,
        sweeps: 0,
        stack_peak: 0,
        worst_bound: 0.0,
        refined: if s.sweeps > 0 { 0 } else { s.refined },
        ..s
    }
}

/// The current frame written on the threads of `pool` (`write_mesh_parallel`), into buffers
/// of three vertices a triangle (which it takes without a count of the vertices, where the
/// frame has none yet) and of the triangles.
fn written_on_threads(t: &mut Tessellator<'_, '_>, pool: &rayon::ThreadPool) -> Mesh {
    let triangles = t.stats().triangles;
    let mut mesh = Mesh {
        vertices: vec![Vertex::default(); 3 * triangles],
        triangles: vec![[0; 3]; triangles],
    };
    let mut remap = vec![0u32; t.remap_len()];
    // (`install` takes what is `Send`: a tessellator is not `Sync`, but `&mut` it is `Send`.)
    let (v, tr, r) = (&mut mesh.vertices, &mut mesh.triangles, &mut remap);
    let size = pool
        .install(move || t.write_mesh_parallel(v, tr, r))
        .expect("room for three vertices a triangle");
    assert_eq!(size.triangles, triangles);
    mesh.vertices.truncate(size.vertices);
    mesh
}

#[test]
fn parallel_frames_are_the_frames_of_one_thread() {
    let models: Vec<_> = bpt_models().into_iter().chain(nurbs_fixtures()).collect();
    assert!(models.len() >= 12, "the repository's models");
    let (mut compared, mut full_pools) = (0, 0);
    for (k, path) in models.iter().enumerate() {
        let name = path.display();
        // Fine enough that the frames are spread over the threads (a hierarchy of fewer than
        // 1,024 nodes is searched on the calling thread), but for the one-patch cylinder.
        let mut rel = 1e-2;
        let mut baked = bake(path, rel);
        while baked.tree().node_count() < 1024 && rel > 1e-3 {
            rel /= 3.0;
            baked = bake(path, rel);
        }
        let bytes = baked.encoded();
        let mut links = vec![NodeLink::default(); baked.tree().link_slots()];
        baked.tree().fill_links(&mut links).unwrap();
        let trees = [
            baked.tree().with_links(&links).unwrap(),
            baked.tree_from(&bytes),
        ];
        for (store, tree) in trees.into_iter().enumerate() {
            let threads = 1 + (k + store) % 3;
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut a = VecStorage::new(&tree, 256, 1 << 18);
            let mut b = VecStorage::new(&tree, 256, 1 << 18);
            // Bounds in either arithmetic: the threads take the tessellator's.
            let arithmetic = [Arithmetic::Float, Arithmetic::Integer][(k + store) % 2];
            let (mut x, mut y) = (
                a.tessellator(tree).with_arithmetic(arithmetic),
                b.tessellator(tree).with_arithmetic(arithmetic),
            );
            for view in views(&tree) {
                let sx = x.update(&view).unwrap();
                let sy = pool.install(|| y.update_parallel(&view)).unwrap();
                let written = written_on_threads(&mut y, &pool);
                if sx.pool_full {
                    // (A full pool makes a frame depend on which halvings came first.)
                    full_pools += 1;
                    continue;
                }
                let (mx, my) = (indexed(&mut x), indexed(&mut y));
                // (Either walked: both counts of vertices made are left out.)
                let walked = |s: FrameStats| FrameStats {
                    sweeps: sx.sweeps + sy.sweeps,
                    ..s
                };
                assert_eq!(
                    figures(walked(sx)),
                    figures(walked(sy)),
                    "{name}, {threads} threads"
                );
                if sx.left_over == 0 {
                    assert!(sy.worst_bound <= view.tolerance(), "{name}");
                }
                assert_eq!(mx, my, "{name}, {threads} threads: meshes");
                assert_eq!(mx, written, "{name}, {threads} threads: written on threads");
                assert_eq!(mx, written_on_threads(&mut y, &pool), "{name}: counted");
                compared += mx.triangles.len();
            }
            // The same view again keeps its mesh.
            let last = *views(&tree).last().unwrap();
            let before = indexed(&mut y);
            pool.install(|| y.update_parallel(&last)).unwrap();
            assert_eq!(before, indexed(&mut y), "{name}");
        }
    }
    assert!(compared > 10_000, "{compared}");
    assert!(full_pools <= 2, "{full_pools} frames with a full pool");
}

/// The same on fine bakes (2.5e-4 of the diagonal, the host's default) seen as the error
/// table's 1.3-diagonal views see them, orbiting: views where a part's border leaves many
/// halvings to the whole frame (one of them found a triangle across halved alone, which the
/// whole frame's search once counted out of the mesh a second time).
/// Their meshes written on two and three threads are the mesh written on one (frames within
/// the bake, of thousands of triangles: what `write_mesh_parallel` shares out; the
/// single-patch surface cut into parts by its roots).
#[test]
fn parallel_frames_on_fine_bakes() {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let three = rayon::ThreadPoolBuilder::new()
        .num_threads(3)
        .build()
        .unwrap();
    let models = [
        "nurbs/rational_torus.json",
        "teapot.bpt",
        "nurbs/threejs_nurbs_example.json",
    ];
    for model in models {
        let baked = bake(&host_tests::models_dir().join(model), 2.5e-4);
        let mut links = vec![NodeLink::default(); baked.tree().link_slots()];
        baked.tree().fill_links(&mut links).unwrap();
        let tree = baked.tree().with_links(&links).unwrap();
        let b = tree.model().aabb().unwrap();
        let (c, d) = (b.center(), b.diagonal());
        let mut a = VecStorage::new(&tree, 4096, 1 << 16);
        let mut s = VecStorage::new(&tree, 4096, 1 << 16);
        let (mut x, mut y) = (a.tessellator(tree), s.tessellator(tree));
        for degrees in [0.0f32, 7.0, 33.0, 90.0] {
            let (sin, cos) = degrees.to_radians().sin_cos();
            let dir = Vec3::new(0.7, -0.6, 0.4).normalize();
            let dir = Vec3::new(cos * dir.x - sin * dir.y, sin * dir.x + cos * dir.y, dir.z);
            let camera = Camera::new(
                c + dir * (1.3 * d),
                c,
                Vec3::Z,
                Projection::Perspective {
                    fov_y_degrees: 40.0,
                },
                0.01 * d,
                [1024, 768],
            )
            .unwrap();
            let view = View::Screen {
                camera,
                tolerance_px: 1.0,
            };
            let sx = x.update(&view).unwrap();
            let sy = pool.install(|| y.update_parallel(&view)).unwrap();
            assert_eq!(figures(sx), figures(sy), "{model} at {degrees} degrees");
            let written = written_on_threads(&mut y, &pool);
            let on_three = written_on_threads(&mut y, &three);
            let mx = indexed(&mut x);
            assert!(
                mx.triangles.len() >= 1024,
                "{model}: {}",
                mx.triangles.len()
            );
            assert_eq!(mx, indexed(&mut y), "{model} at {degrees}");
            assert_eq!(mx, written, "{model} at {degrees}: written on threads");
            assert_eq!(
                mx, on_three,
                "{model} at {degrees}: written on three threads"
            );
        }
    }
}

/// A frame on threads gives the same figures every time, all of them (what it judged, the
/// vertices it asked for below the bake, its walks), whichever thread takes which part: on a
/// model of one patch cut into parts by its roots, and on the teapot, within the bake and below
/// it, on three threads.
#[test]
fn a_frame_on_threads_has_the_same_figures_every_time() {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(3)
        .build()
        .unwrap();
    for model in ["nurbs/threejs_nurbs_example.json", "teapot.bpt"] {
        let baked = bake(&host_tests::models_dir().join(model), 2e-3);
        let tree = baked.tree();
        // Large enough to be spread over the threads (see `small_frames_stay_...`).
        assert!(tree.node_count() >= 1024, "{model}: {}", tree.node_count());
        let mut storage = VecStorage::new(&tree, 256, 1 << 18);
        for view in views(&tree) {
            let mut first = None;
            for _ in 0..12 {
                let mut t = storage.tessellator(tree);
                let stats = pool.install(|| t.update_parallel(&view)).unwrap();
                assert_eq!(*first.get_or_insert(stats), stats, "{model}");
            }
        }
    }
}

/// A small hierarchy's frame is searched on the calling thread, searched as `update`
/// searches it (the same judgements, to the count): fewer than 1,024 nodes. A large one's is
/// spread over the threads, which judge more (each part judges what it leaves to the whole
/// frame again).
#[test]
fn small_frames_stay_on_the_calling_thread() {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let path = host_tests::models_dir().join("nurbs/verb_quarter_cylinder.json");
    let teapot = host_tests::models_dir().join("teapot.bpt");
    for (path, small) in [(path, true), (teapot, false)] {
        let baked = bake(&path, if small { 1e-2 } else { 1e-3 });
        let tree = baked.tree();
        assert_eq!(tree.node_count() < 1024, small, "{}", tree.node_count());
        let mut a = VecStorage::new(&tree, 256, 4096);
        let mut b = VecStorage::new(&tree, 256, 4096);
        let (mut one, mut spread) = (a.tessellator(tree), b.tessellator(tree));
        let view = views(&tree)[2];
        let (s1, s2) = pool.install(|| {
            (
                one.update(&view).unwrap(),
                spread.update_parallel(&view).unwrap(),
            )
        });
        assert_eq!(figures(s1), figures(s2));
        assert_eq!(
            s1.judged == s2.judged,
            small,
            "{}: {} and {}",
            path.display(),
            s1.judged,
            s2.judged
        );
    }
}

/// Buffers too small for a mesh written on threads give `write_mesh`'s errors, and are left
/// untouched: a remap too short, too few triangles, too few vertices (counted). Indexed by
/// `u16`, the same mesh.
#[test]
fn a_mesh_written_on_threads_that_does_not_fit_gives_the_same_errors() {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let baked = bake(&host_tests::models_dir().join("teapot.bpt"), 1e-3);
    let tree = baked.tree();
    let mut storage = VecStorage::new(&tree, 256, 1 << 16);
    let mut t = storage.tessellator(tree);
    let view = views(&tree)[1]; // (within the bake: its pool is empty)
    t.update(&view).unwrap();
    let size = t.mesh_size();
    assert!(
        size.triangles >= 2048,
        "{size:?}: large enough for the threads"
    );
    let cases = [
        (size.vertices, size.triangles, t.remap_len() - 1),
        (size.vertices, size.triangles - 1, t.remap_len()),
        (size.vertices - 1, size.triangles, t.remap_len()),
    ];
    for (vertices, triangles, remap) in cases {
        let sentinel = Vertex {
            patch: 7,
            ..Vertex::default()
        };
        let mut run = |parallel: bool| -> (Result<_, WriteError>, Mesh) {
            let mut mesh = Mesh {
                vertices: vec![sentinel; vertices],
                triangles: vec![[9; 3]; triangles],
            };
            let mut remap = vec![0u32; remap];
            let written = match parallel {
                true => {
                    let (t, v, tr, r) =
                        (&mut t, &mut mesh.vertices, &mut mesh.triangles, &mut remap);
                    pool.install(move || t.write_mesh_parallel(v, tr, r))
                }
                false => t.write_mesh(&mut mesh.vertices, &mut mesh.triangles, &mut remap),
            };
            (written, mesh)
        };
        let (one, threads) = (run(false), run(true));
        assert!(one.0.is_err(), "{vertices} {triangles} {remap}");
        assert_eq!(one, threads, "{vertices} {triangles} {remap}");
        assert!(threads.1.vertices.iter().all(|v| *v == sentinel));
        assert!(threads.1.triangles.iter().all(|t| *t == [9; 3]));
    }
    // Indexed by `u16`.
    let mut room = (
        vec![Vertex::default(); 3 * size.triangles],
        vec![[0u16; 3]; size.triangles],
    );
    let mut remap = vec![0u32; t.remap_len()];
    let one = t.write_mesh(&mut room.0, &mut room.1, &mut remap);
    let (t, v, tr, r) = (&mut t, &mut room.0, &mut room.1, &mut remap);
    let threads = pool.install(move || t.write_mesh_parallel(v, tr, r));
    assert_eq!(one, threads);
}
