//! The host API (`spline_tess::host`, feature `std`): a bake on any number of threads is the
//! same bytes, a cached bake reads back as the same bake, and a frame's owned mesh is the
//! kernel's own frame written into caller buffers.

use host_tests::models_dir;
use spline_tess::bake::{
    bake_hierarchy_with, BakeBuffers, BakeRunner, BakeScratch, BakeSettings, InOrder, Parallel,
    Tolerance,
};
use spline_tess::host::{HostError, Surfaces};
use spline_tess::tessellator::{HierarchyNode, HierarchyPatch, HierarchyVertex};
use spline_tess::{Camera, Projection, Vec3, View};

/// A bake's records (nodes, vertices, patches) in buffers of 65,536.
type Records = (
    Vec<HierarchyNode>,
    Vec<HierarchyVertex>,
    Vec<HierarchyPatch>,
);

/// A bake of `surfaces` by `runner`: its records, cut to their sizes.
fn bake_records(
    surfaces: &Surfaces,
    settings: &BakeSettings,
    runner: &dyn BakeRunner,
) -> Result<Records, spline_tess::bake::BakeError> {
    let n = 1 << 16;
    let mut nodes = vec![HierarchyNode::default(); n];
    let mut vertices = vec![HierarchyVertex::default(); n];
    let mut patches = vec![HierarchyPatch::default(); surfaces.patches().len()];
    let mut scratch = vec![BakeScratch::default(); n];
    let buffers = BakeBuffers {
        nodes: &mut nodes,
        vertices: &mut vertices,
        patches: &mut patches,
        scratch: &mut scratch,
    };
    let size = surfaces
        .with_model(|m| bake_hierarchy_with(m, settings, buffers, &mut |_| {}, runner))
        .expect("a model")?;
    nodes.truncate(size.nodes);
    vertices.truncate(size.vertices);
    Ok((nodes, vertices, patches))
}

/// The compact bytes of a bake of `surfaces` by `runner`.
fn bake_with(surfaces: &Surfaces, settings: &BakeSettings, runner: &dyn BakeRunner) -> Vec<u8> {
    let (nodes, vertices, patches) = bake_records(surfaces, settings, runner).expect("a bake");
    let tree = spline_tess::Hierarchy::new(surfaces.patches(), &nodes, &vertices, &patches)
        .expect("a hierarchy");
    let mut work = vec![0u32; spline_tess::bake::encode_scratch_len(nodes.len(), vertices.len())];
    let mut out = vec![0u8; 64 * (nodes.len() + vertices.len() + patches.len() + 1)];
    let len = spline_tess::bake::encode_hierarchy(&tree, &mut work, &mut out).expect("bytes");
    out.truncate(len);
    out
}

fn relative(t: f32) -> BakeSettings {
    BakeSettings {
        tolerance: Tolerance::Relative(t),
        ..BakeSettings::default()
    }
}

/// One thread, one thread of rayon, three threads of rayon: the same bytes, on a BPT model
/// with shared curves and poles (the diamonds' bounds run in batches too) and a NURBS one.
#[test]
fn a_bake_is_the_same_on_any_number_of_threads() {
    for (file, tolerance) in [
        ("teapot.bpt", 1e-3),
        ("teaspoon.bpt", 5e-4),
        ("nurbs/rational_torus.json", 2e-3),
    ] {
        let surfaces = Surfaces::read(models_dir().join(file)).expect("a model");
        let settings = relative(tolerance);
        let alone = bake_with(&surfaces, &settings, &InOrder);
        for threads in [1, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("a pool");
            let parallel = pool.install(|| bake_with(&surfaces, &settings, &Parallel));
            assert!(alone == parallel, "{file}: {threads} threads");
        }
        // And the host API's bake is that bake.
        let host = surfaces.bake(&settings).expect("a bake");
        assert!(host.to_bytes().expect("bytes") == alone, "{file}");
    }
}

/// `bake_cached` writes the bake once and reads it back: the same bytes and the same frames;
/// a cache of other settings or of damaged bytes is baked again (and rewritten).
#[test]
fn a_cached_bake_reads_back() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("host_api");
    std::fs::create_dir_all(&dir).expect("a folder");
    let path = dir.join("teaspoon.bake");
    let _ = std::fs::remove_file(&path);
    let surfaces = Surfaces::read(models_dir().join("teaspoon.bpt")).expect("a model");
    let settings = relative(1e-3);
    let fresh = surfaces.bake_cached(&settings, &path).expect("a bake");
    let written = std::fs::read(&path).expect("a cache file");
    let cached = surfaces
        .bake_cached(&settings, &path)
        .expect("a cached bake");
    assert_eq!(fresh.to_bytes().unwrap(), cached.to_bytes().unwrap());
    assert_eq!(cached.settings(), Some(&settings));
    let view = View::Object { tolerance: 2e-3 };
    assert_eq!(
        fresh.tessellate(&view).unwrap(),
        cached.tessellate(&view).unwrap()
    );
    // Other settings: baked again, and the file now holds them.
    let coarser = relative(4e-3);
    let other = surfaces.bake_cached(&coarser, &path).expect("a bake");
    assert_eq!(other.settings(), Some(&coarser));
    assert_ne!(std::fs::read(&path).unwrap(), written);
    // Damaged bytes (the checksum fails): baked again.
    let mut bad = std::fs::read(&path).unwrap();
    let last = bad.len() - 1;
    bad[last] ^= 0x40;
    std::fs::write(&path, &bad).unwrap();
    let again = surfaces.bake_cached(&coarser, &path).expect("a bake");
    assert_eq!(again.to_bytes().unwrap(), other.to_bytes().unwrap());
    assert_ne!(std::fs::read(&path).unwrap(), bad);
    // Bytes of another model are not this one's bake.
    let teapot = Surfaces::read(models_dir().join("teapot.bpt")).expect("a model");
    let wrong = spline_tess::host::Baked::from_bytes(teapot, again.to_bytes().unwrap());
    assert!(matches!(wrong, Err(HostError::Format(_))));
}

/// The owned mesh is the kernel's frame: the same vertices and triangles as `write_mesh`
/// into caller buffers (the examples' path), each face with its patch and parameters, and its
/// OBJ and PLY texts count them.
#[test]
fn a_frames_mesh_is_the_kernels_frame() {
    let path = models_dir().join("teapot.bpt");
    let surfaces = Surfaces::read(&path).expect("a model");
    let camera = Camera::new(
        Vec3::new(6.0, -6.0, 4.0),
        Vec3::new(0.0, 0.0, 1.5),
        Vec3::Z,
        Projection::Perspective {
            fov_y_degrees: 40.0,
        },
        0.05,
        [1024, 768],
    )
    .unwrap();
    let view = View::Screen {
        camera,
        tolerance_px: 0.5,
    };
    let mesh = surfaces
        .bake(&spline_tess::host::BAKE)
        .unwrap()
        .tessellate(&view)
        .unwrap();
    let one_call = spline_tess::host::tessellate(&std::fs::read(&path).unwrap(), &view).unwrap();
    assert_eq!(mesh, one_call);
    assert!(mesh.stats.worst_bound <= 0.5 && mesh.stats.left_over == 0);
    // Half a pixel on a large screen stays within the host's bake.
    assert_eq!(mesh.stats.refined, 0);
    // The kernel's own frame of the same bake.
    let baked = host_tests::bake_relative(&path, 2.5e-4);
    let tree = baked.tree();
    let mut storage = host_tests::runtime::VecStorage::new(&tree, 4096, 1 << 16);
    let mut t = storage.tessellator(tree);
    // (The host searches on all cores: the same mesh and figures but for how the search
    // went, the worst bound of the triangles it judged on its way among them.)
    let went = |s: spline_tess::FrameStats| spline_tess::FrameStats {
        judged: 0,
        sweeps: 0,
        stack_peak: 0,
        worst_bound: 0.0,
        ..s
    };
    assert_eq!(went(t.update(&view).unwrap()), went(mesh.stats));
    let kernel = host_tests::runtime::indexed(&mut t);
    assert_eq!(mesh.triangles, kernel.triangles);
    assert_eq!(mesh.positions.len(), kernel.vertices.len());
    for (k, v) in kernel.vertices.iter().enumerate() {
        assert_eq!(mesh.positions[k], v.position);
        assert_eq!(mesh.normals[k], v.normal);
    }
    assert_eq!(mesh.faces.len(), mesh.triangles.len());
    // Each face is the kernel's triangle of the same place in the stream (the teapot's
    // patches have the unit square for their domain).
    let mut streamed = Vec::new();
    t.stream_with_info(|info, _| streamed.push((info.patch, info.uv)));
    let faces: Vec<_> = mesh.faces.iter().map(|f| (f.patch, f.uv)).collect();
    assert_eq!(faces, streamed);
    for (f, t) in mesh.faces.iter().zip(&mesh.triangles) {
        assert!(f.patch < 32);
        for (uv, &v) in f.uv.iter().zip(t) {
            assert!(uv.iter().all(|x| (0.0..=1.0).contains(x)));
            // A corner of a face of this patch has these parameters on it.
            let p = surfaces
                .patches()
                .patch(f.patch as usize)
                .unwrap()
                .position(uv[0], uv[1]);
            let q = Vec3::from_array(mesh.positions[v as usize]);
            assert!((p - q).length() < 1e-3, "{p} {q}");
        }
    }
    let mut obj = Vec::new();
    mesh.write_obj(&mut obj).unwrap();
    let obj = String::from_utf8(obj).unwrap();
    let count = |prefix: &str| obj.lines().filter(|l| l.starts_with(prefix)).count();
    assert_eq!(count("v "), mesh.positions.len());
    assert_eq!(count("vn "), mesh.normals.len());
    assert_eq!(count("f "), mesh.triangles.len());
    let mut ply = Vec::new();
    mesh.write_ply(&mut ply).unwrap();
    let ply = String::from_utf8(ply).unwrap();
    let body = ply.split("end_header\n").nth(1).unwrap();
    assert_eq!(
        body.lines().count(),
        mesh.positions.len() + mesh.triangles.len()
    );
}

/// A runner that leaves a job of every batch undone: the bake fails, it does not keep a
/// triangle with a bound never measured.
#[test]
fn a_runner_that_skips_a_job_fails_the_bake() {
    struct SkipsOne;
    impl BakeRunner for SkipsOne {
        fn run(&self, jobs: &mut [BakeScratch], work: &(dyn Fn(&mut BakeScratch) + Sync)) {
            let n = jobs.len();
            for job in jobs.iter_mut().take(n.saturating_sub(1)) {
                work(job);
            }
        }
    }
    let surfaces = Surfaces::read(models_dir().join("teaspoon.bpt")).expect("a model");
    let baked = bake_records(&surfaces, &relative(1e-3), &SkipsOne).map(|_| ());
    assert_eq!(
        baked,
        Err(spline_tess::bake::BakeError::JobsSkipped { skipped: 1 })
    );
}

/// The writers refuse a mesh that does not hold together, rather than write a broken file.
#[test]
fn the_writers_refuse_a_broken_mesh() {
    use spline_tess::host::{Face, Mesh};
    let good = Mesh {
        positions: vec![[0.0; 3]; 3],
        normals: vec![[0.0, 0.0, 1.0]; 3],
        triangles: vec![[0, 1, 2]],
        faces: vec![Face::default()],
        ..Mesh::default()
    };
    let broken = [
        Mesh {
            triangles: vec![[0, 1, 3]],
            ..good.clone()
        },
        Mesh {
            normals: vec![],
            ..good.clone()
        },
        Mesh {
            faces: vec![],
            ..good.clone()
        },
    ];
    for mesh in broken {
        let e = mesh.write_obj(&mut Vec::new()).unwrap_err();
        assert_eq!(e.kind(), std::io::ErrorKind::InvalidInput);
        let e = mesh.write_ply(&mut Vec::new()).unwrap_err();
        assert_eq!(e.kind(), std::io::ErrorKind::InvalidInput);
    }
    assert!(good.write_obj(&mut Vec::new()).is_ok() && good.write_ply(&mut Vec::new()).is_ok());
}

/// A frame that needs more vertices below the bake than a host's frame starts with grows its
/// pool and makes the frame again: the kernel's frame in a pool that holds them all.
#[test]
fn a_frame_far_below_the_bake_grows_its_pool() {
    let path = models_dir().join("teaspoon.bpt");
    let surfaces = Surfaces::read(&path).expect("a model");
    let view = View::Object { tolerance: 1e-4 };
    let mesh = surfaces
        .bake(&relative(1e-3))
        .unwrap()
        .tessellate(&view)
        .unwrap();
    assert!(
        !mesh.stats.pool_full && mesh.stats.left_over == 0,
        "{:?}",
        mesh.stats
    );
    // More than the 4,096 a host's frame starts with.
    assert!(mesh.stats.refined > 4096, "{}", mesh.stats.refined);
    let baked = host_tests::bake_relative(&path, 1e-3);
    let tree = baked.tree();
    let mut storage = host_tests::runtime::VecStorage::new(&tree, 4096, 1 << 20);
    let mut t = storage.tessellator(tree);
    // (`refined` counts a vertex below the bake each time a halving asks for it, and the
    // search on all cores walks for the leaves its parts left, asking for some again: the
    // mesh is the same.)
    let stats = t.update(&view).unwrap();
    assert_eq!(stats.triangles, mesh.stats.triangles);
    let kernel = host_tests::runtime::indexed(&mut t);
    assert_eq!(kernel.triangles, mesh.triangles);
    let positions: Vec<_> = kernel.vertices.iter().map(|v| v.position).collect();
    assert_eq!(positions, mesh.positions);
}
