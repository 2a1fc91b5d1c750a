//! The run time on every model, along a camera path (far, mid, near, grazing, eye inside the
//! model's bound, looking away so that most patches are behind) and in object-space mode:
//!
//! - every triangle's deviation, sampled densely with the f64 reference and projected with the
//!   camera, is at most the tolerance, and in model units at most the bound the kernel gives
//!   for it; the frame's own largest bound over threshold is at most the tolerance too;
//! - watertight: an edge used by one triangle lies on an open model curve (or one whose other
//!   patch is culled), no edge is used by more than two, and no two vertices share a position;
//! - the streamed triangles are the indexed ones, vertex for vertex;
//! - history independence: after every step of the path, the mesh equals the one a fresh
//!   tessellator builds for that view alone;
//! - budget mode: the budget is never exceeded and 1% less tolerance would exceed it;
//! - all of the above but budget mode again with a pool of a quarter of the slots (and with
//!   the least pool): the prefixes are cut to fit and the bound still holds.

use std::collections::{HashMap, HashSet};

use host_tests::frame_checks::{camera_path, check_watertight, measure_frame};
use host_tests::model_file::{bake_to_vec, ModelFile};
use host_tests::reference::{cross, dot, norm, sub, RefPatch};
use host_tests::runtime::{indexed, streamed, triangle_set, RuntimeStorage};
use host_tests::{bpt_models, name, nurbs_fixtures};
use spline_tess::bake::{BakeSettings, BakedModel, Tolerance};
use spline_tess::tessellator::{PoolSize, Settings, StorageSize};
use spline_tess::{DomainIndex, EdgeLink, FrameStats};

const BAKE: BakeSettings = BakeSettings {
    tolerance: Tolerance::Relative(1e-3),
    max_curve_samples: 256,
    max_interior_samples: 1024,
};
/// +1 when the normals `S_u x S_v` of the closed surface `refs` point out of it, -1 when in:
/// the sign of its volume, `1/3` of the integral of `(S - c) . (S_u x S_v)`, by a 16 x 16
/// midpoint rule per patch (`c` the mean control point).
fn outward_sign(refs: &[RefPatch]) -> f64 {
    let all: Vec<[f64; 3]> = refs.iter().flat_map(|r| r.pts.iter().copied()).collect();
    let c = [0, 1, 2].map(|k| all.iter().map(|p| p[k]).sum::<f64>() / all.len() as f64);
    let n = 16;
    let mut volume = 0.0;
    for r in refs {
        for i in 0..n {
            for j in 0..n {
                let (u, v) = ((i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64);
                let f = r.eval(u, v);
                volume += dot(sub(f.p, c), cross(f.su, f.sv));
            }
        }
    }
    volume.signum()
}

/// Checks that patch `r` shows `eye` only its back: `(P - eye) . n >= 0` at every point of a
/// 33 x 33 grid, `n` the outward normal (`sign` says which way `S_u x S_v` points).
fn assert_back_facing(label: &str, patch: usize, r: &RefPatch, eye: [f64; 3], sign: f64) {
    let n = 32;
    for i in 0..=n {
        for j in 0..=n {
            let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
            let f = r.eval(u, v);
            let normal = cross(f.su, f.sv);
            let d = sub(f.p, eye);
            let facing = sign * dot(d, normal);
            assert!(
                facing >= -1e-9 * norm(d) * norm(normal),
                "{label}: patch {patch} culled as facing away, but faces the eye at ({u}, {v})"
            );
        }
    }
}

/// The pool a run gives the tessellator.
#[derive(Clone, Copy, PartialEq)]
enum Pool {
    /// Every baked step.
    Full,
    /// This fraction of [`Pool::Full`]'s slots (at least the least pool), and of its bound
    /// and vertex caches (none for 0).
    Part(f64),
    /// [`Pool::Full`]'s slots and caches, and this fraction of its triangle states.
    States(f64),
    /// Every baked step a mesh of `u8` slot numbers holds (at most 130 vertices a patch; the
    /// patches baked with more refine from there).
    Narrow,
    /// Every baked step of the model with its patches split into four
    /// ([`PatchSet::split`](spline_tess::PatchSet::split)).
    Split,
}

fn run_model<Ix: DomainIndex>(path: &std::path::Path, pool: Pool) {
    let label = format!(
        "{}{}",
        name(path),
        match pool {
            Pool::Full => String::new(),
            Pool::Part(f) => format!(" (pool {f})"),
            Pool::States(f) => format!(" (triangle states {f})"),
            Pool::Narrow => " (u8 pool)".to_string(),
            Pool::Split => " (split)".to_string(),
        }
    );
    let mut file = ModelFile::read(path.to_str().unwrap()).unwrap();
    if let Pool::Split = pool {
        file = file.split().unwrap().0;
    }
    let bytes = file.with_model(|m| bake_to_vec(m, &BAKE)).unwrap().unwrap();
    let uses: Vec<u32> = file
        .with_model(|m| m.topology.curves().iter().map(|c| c.uses).collect())
        .unwrap();
    let baked = BakedModel::from_bytes(&bytes).unwrap();
    let patches = file.patches();
    let refs: Vec<RefPatch> = patches.iter().map(|p| RefPatch::from_kernel(&p)).collect();
    let aabb = patches.aabb().unwrap();
    let (center, diag) = (aabb.center(), aabb.diagonal());
    let settings = Settings::default();
    let size = match pool {
        Pool::Full | Pool::Split => StorageSize::of(&baked, &settings),
        Pool::Part(f) => {
            let (full, least) = (
                StorageSize::of(&baked, &settings),
                StorageSize::minimum(&baked, &settings),
            );
            StorageSize {
                bounds: (full.bounds as f64 * f) as usize,
                vertex_points: (full.vertex_points as f64 * f) as usize,
                ..full.with_pool(PoolSize {
                    vertices: ((full.vertices as f64 * f) as usize).max(least.vertices),
                    triangles: ((full.triangles as f64 * f) as usize).max(least.triangles),
                })
            }
        }
        Pool::States(f) => {
            let full = StorageSize::of(&baked, &settings);
            StorageSize {
                triangle_states: (full.triangle_states as f64 * f) as usize,
                ..full
            }
        }
        Pool::Narrow => StorageSize::of_indexed::<u8>(&baked, &settings),
    };
    // Frames whose patches found the triangle states short.
    let mut short_frames = 0;
    let mut storage = RuntimeStorage::<Ix>::indexed(&size);
    let mut tess = storage.tessellator(patches, baked, settings);
    let mut cut = 0;
    let mut users: HashMap<u32, Vec<u32>> = HashMap::new();
    for p in 0..baked.patch_count() {
        for link in baked.patch(p).unwrap().edges {
            if let EdgeLink::Curve { curve, .. } = link {
                users.entry(curve).or_default().push(p as u32);
            }
        }
    }
    let mut gaps_out_of_sight = 0;
    // Back-patch culling is on exactly for the closed models (every curve shared by two).
    let closed = uses.iter().all(|&n| n == 2);
    assert_eq!(
        tess.culls_back_patches(),
        closed,
        "{label}: back-patch culling"
    );
    let sign = if closed { outward_sign(&refs) } else { 0.0 };
    let mut back_facing = 0;
    for step in camera_path(center, diag, aabb.min.z) {
        let what = format!("{label} {}", step.label);
        let stats: FrameStats = tess.update(&step.view).unwrap();
        assert!(
            stats.mesh_vertices <= size.vertices && stats.mesh_triangles <= size.triangles,
            "{what}: more slots than the pool"
        );
        assert_eq!(
            stats.prefix_scale > 1.0,
            !stats.pool_needed.fits_in(&PoolSize {
                vertices: size.vertices - 4 * stats.culled_patches,
                triangles: size.triangles - 2 * stats.culled_patches,
            }),
            "{what}: prefixes cut exactly when the pool is short"
        );
        cut += usize::from(stats.prefix_scale > 1.0);
        let mesh = indexed(&mut tess);
        let tris = streamed(&tess);
        assert_eq!(mesh.triangles.len(), tris.len(), "{what}");
        assert_eq!(stats.triangles, tris.len(), "{what}");
        for (t, s) in mesh.triangles.iter().zip(&tris) {
            for (&i, c) in t.iter().zip(&s.corners) {
                assert_eq!(mesh.vertices[i as usize], *c, "{what}: stream != indexed");
            }
        }
        let open = |p: u32, side: usize| match baked.patch(p as usize).unwrap().edges[side] {
            EdgeLink::Collapsed => false,
            EdgeLink::Curve { curve, .. } => {
                uses[curve as usize] == 1
                    || users[&curve]
                        .iter()
                        .any(|&q| q != p && tess.is_culled(q as usize))
            }
        };
        let gaps = check_watertight(&what, &mesh, &tris, &open, step.meter.as_ref(), &refs);
        gaps_out_of_sight += gaps;
        for p in (0..baked.patch_count()).filter(|&p| tess.is_back_facing(p)) {
            let meter = step
                .meter
                .as_ref()
                .expect("culled for facing only through a camera");
            assert_back_facing(&what, p, &refs[p], meter.eye(), sign);
            back_facing += 1;
        }
        assert_eq!(
            stats.back_facing_patches,
            (0..baked.patch_count())
                .filter(|&p| tess.is_back_facing(p))
                .count()
        );
        let tolerance = step.view.tolerance() as f64;
        let short = stats.patches_without_states > 0;
        short_frames += usize::from(short);
        assert_eq!(
            short,
            stats.triangle_states_needed > size.triangle_states,
            "{what}: patches without states exactly when the arena is short of what they need"
        );
        assert!(
            short || stats.max_predicted_error as f64 <= tolerance * (1.0 + 1e-6),
            "{what}: the frame's bound {} is over the tolerance",
            stats.max_predicted_error
        );
        // With triangle states short, the frame is within the bound it reports.
        let allowed = tolerance.max(stats.max_predicted_error as f64);
        let (worst, tightest) = measure_frame(&refs, &tris, step.meter.as_ref());
        assert!(
            tightest >= 1.0,
            "{what}: a triangle's bound is {tightest} of its measured deviation"
        );
        let slack = if step.meter.is_some() {
            1e-3
        } else {
            1e-6 * diag as f64
        };
        println!(
            "{what}: {} triangles, {} vertices, +{} -{}, {} estimated, {} refined, {} culled, \
             {gaps} open edges out of sight, bound {:.3}, measured {:.3} (allowed {:.3}), \
             bound / true at least {tightest:.3}",
            stats.triangles,
            stats.vertices,
            stats.inserted,
            stats.deleted,
            stats.estimated,
            stats.refined_patches,
            stats.culled_patches,
            stats.max_predicted_error,
            worst,
            allowed
        );
        assert!(
            worst <= allowed * 1.001 + slack,
            "{what}: deviation {worst} > {allowed}"
        );
        // History independence.
        let mut fresh_storage = RuntimeStorage::<Ix>::indexed(&size);
        let mut fresh = fresh_storage.tessellator(patches, baked, settings);
        fresh.update(&step.view).unwrap();
        let a: HashSet<_> = triangle_set(&tris).into_iter().collect();
        let b: HashSet<_> = triangle_set(&streamed(&fresh)).into_iter().collect();
        assert!(
            a == b,
            "{what}: incremental mesh differs from a fresh build"
        );
    }
    assert!(
        !closed || back_facing > 0,
        "{label}: a closed model, and no patch culled for facing away along the path"
    );
    if let Pool::States(f) = pool {
        assert!(
            short_frames > 0,
            "{label}: the triangle states were never short ({f})"
        );
        return;
    }
    assert_eq!(short_frames, 0, "{label}: a state for every triangle slot");
    // The views from inside and near the model leave out triangles off the view.
    assert!(
        gaps_out_of_sight > 0,
        "{label}: no triangle left out off the view along the path"
    );
    if let Pool::Part(f) = pool {
        // A quarter of the slots is short on the near views of every model; the least pool
        // is short everywhere but the views with nothing in sight.
        assert!(cut > 0, "{label}: the pool was never short (pool {f})");
        return;
    }
    // Budget mode on the mid view.
    let path = camera_path(center, diag, aabb.min.z);
    let mid = path.iter().find(|s| s.label == "mid").unwrap();
    let full = tess.update_unrefined(&mid.view).unwrap().triangles;
    for budget in [full / 3, full / 2, full + 10] {
        let (stats, fit) = tess.update_to_budget(&mid.view, budget).unwrap();
        assert!(
            stats.triangles <= budget,
            "{label}: {} > budget {budget}",
            stats.triangles
        );
        assert_eq!(
            stats.triangles, fit.triangles,
            "{label}: prediction is exact"
        );
        // The fit keeps its word: the frame is within the bound it reports.
        assert_eq!(fit.bound, stats.max_predicted_error, "{label}");
        let (worst, tightest) = measure_frame(&refs, &streamed(&tess), mid.meter.as_ref());
        let slack = if mid.meter.is_some() {
            1e-3
        } else {
            1e-6 * diag as f64
        };
        println!(
            "{label} budget {budget}: {} triangles, tolerance {:.4}, bound {:.4}, measured {worst:.4}",
            stats.triangles, fit.tolerance, fit.bound
        );
        assert!(
            tightest >= 1.0 && worst <= fit.bound as f64 * 1.001 + slack,
            "{label} budget {budget}: deviation {worst} > reported bound {}",
            fit.bound
        );
        if !fit.exhausted {
            let finer = tess
                .update_unrefined(&mid.view.with_tolerance(fit.tolerance * 0.99))
                .unwrap();
            assert!(
                finer.triangles > budget,
                "{label}: tolerance not minimal within 1%"
            );
        }
    }
}

#[test]
fn bpt_models_along_a_camera_path() {
    for path in bpt_models() {
        run_model::<u16>(&path, Pool::Full);
    }
}

#[test]
fn nurbs_fixtures_along_a_camera_path() {
    for path in nurbs_fixtures() {
        run_model::<u16>(&path, Pool::Full);
    }
}

/// A triangle-state arena too short for the path's refined frames: the patches without
/// states stay uncut, every frame is still watertight, history-independent and within the
/// bound it reports, and every triangle within the bound it is written with.
#[test]
fn bpt_models_with_few_triangle_states() {
    for path in bpt_models() {
        run_model::<u16>(&path, Pool::States(0.02));
        run_model::<u16>(&path, Pool::States(0.0));
    }
}

/// Pools of one-byte slot numbers: the patches baked with more than a mesh of them holds
/// stop there and refine, and every frame keeps every property of a full pool's.
#[test]
fn bpt_models_in_one_byte_pools() {
    for path in bpt_models() {
        run_model::<u8>(&path, Pool::Narrow);
    }
}

#[test]
fn bpt_models_in_short_pools() {
    for path in bpt_models() {
        run_model::<u16>(&path, Pool::Part(0.25));
        run_model::<u16>(&path, Pool::Part(0.0));
    }
}

/// Every patch split into four: the seams between quarters are shared curves like any other,
/// and every property of the whole patches' frames holds.
#[test]
fn models_split_into_quarters() {
    for path in bpt_models().into_iter().chain(nurbs_fixtures()) {
        run_model::<u16>(&path, Pool::Split);
    }
}

#[test]
fn nurbs_fixtures_in_short_pools() {
    for path in nurbs_fixtures() {
        run_model::<u16>(&path, Pool::Part(0.25));
    }
}
