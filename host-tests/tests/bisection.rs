//! The tessellator (`spline_tess::tessellator`) on every model, along the camera path of the
//! run-time tests (far, mid, near, grazing, eye inside the model's bound, looking away,
//! object mode):
//!
//! - every triangle's deviation, sampled densely with the f64 reference and projected with the
//!   camera, is at most the tolerance where the bake's triangles sufficed, and at most the
//!   bound the frame reports where they ran out; in model units every triangle is within the
//!   bound it is streamed with;
//! - watertight: an edge used by one triangle lies on an open model curve or out of sight, no
//!   edge is used by more than two, and no two vertices share a position;
//! - the streamed triangles are the indexed ones, vertex for vertex;
//! - a patch culled for facing away (in a closed model: the rational torus) shows the eye
//!   only its back, at every point of a 33 x 33 grid of the `f64` reference, and its
//!   neighbours' sides along it are the only other sides used once;
//! - history independence: the mesh after each step equals a fresh run time's for that view,
//!   and a run time's with a stack of 8 (which walks the mesh for the leaves it had no room
//!   for);
//! - budget mode: the budget is never exceeded, the frame is within the bound it reports,
//!   and 1% less tolerance would exceed the budget;
//! - the frame is the coarsest conforming one: the same triangles as the oracles' bisection
//!   (`host_tests::bintree`), which finds neighbours its own way, splitting by the same
//!   bounds.

use std::collections::{HashMap, HashSet};

use host_tests::bintree::{bintree_from, cell_roots, children, model_spot, Bin, BINTREE_BITS};
use host_tests::frame_checks::{camera_path, check_watertight, measure_frame, Step};
use host_tests::model_file::ModelFile;
use host_tests::reference::RefPatch;
use host_tests::runtime::{streamed, BakedHierarchy, VecStorage};
use host_tests::runtime::{triangle_set, Mesh};
use host_tests::{bpt_models, name, nurbs_fixtures};
use spline_tess::bake::BakeSettings;
use spline_tess::bake::Tolerance;
use spline_tess::tessellator::BudgetError;
use spline_tess::Arithmetic;
use spline_tess::{EdgeLink, Vertex, View};

const BAKE: BakeSettings = BakeSettings {
    tolerance: Tolerance::Relative(1e-3),
    max_depth: 24,
    max_cell_level: spline_tess::tessellator::MAX_CELL_LEVEL,
};

/// A model file, its hierarchy with [`BAKE`], and its patches in the `f64` reference.
fn baked(path: &std::path::Path) -> (ModelFile, BakedHierarchy, Vec<RefPatch>) {
    let file = ModelFile::read(path.to_str().unwrap()).unwrap();
    let baked = BakedHierarchy::bake(&file, &BAKE).unwrap();
    let refs = file
        .patches()
        .iter()
        .map(|p| RefPatch::from_kernel(&p))
        .collect();
    (file, baked, refs)
}

fn run_model(path: &std::path::Path) {
    let label = name(path);
    let (file, baked, refs) = baked(path);
    let tree = baked.tree();
    let patches = file.patches();
    let aabb = patches.aabb().unwrap();
    let (center, diag) = (aabb.center(), aabb.diagonal());
    let (edges, uses): (Vec<[EdgeLink; 4]>, Vec<u32>) = file
        .with_model(|m| {
            (
                m.topology.edges().to_vec(),
                m.topology.curves().iter().map(|c| c.uses).collect(),
            )
        })
        .unwrap();
    let links: Vec<_> = (0..tree.patch_count())
        .map(|p| tree.patch(p).expect("patch").links)
        .collect();
    let open_curve = |p: u32, side: usize| match edges[p as usize][side] {
        EdgeLink::Collapsed => false,
        EdgeLink::Curve { curve, .. } => uses[curve as usize] == 1,
    };
    // Outward: `S_u x S_v`, or its opposite where the bake flipped the patch.
    let outward: Vec<f64> = (0..tree.patch_count())
        .map(|p| tree.patch(p).expect("patch"))
        .map(|p| if p.flip { -1.0 } else { 1.0 })
        .collect();
    let mut storage = VecStorage::new(&tree, 1 << 16, 1 << 16);
    let mut fresh_storage = VecStorage::new(&tree, 1 << 16, 1 << 16);
    // A stack of 8: leaves it has no room for are found by walks, to the same mesh.
    let mut short_storage = VecStorage::new(&tree, 8, 1 << 16);
    // (In integers over the compact bytes, as a part without an FPU reads them: the judged
    // corners are moved into the view from their grid points in integers too.)
    let bytes = baked.encoded();
    let bytes_tree = baked.tree_from(&bytes);
    let mut integer_storage = VecStorage::new(&bytes_tree, 1 << 16, 1 << 16);
    let (mut sweeps, mut integer_apart) = (0, 0);
    let mut remap = vec![0u32; tree.vertex_count() + (1 << 16)];
    let mut selection = storage.tessellator(tree);
    let mut left_over_frames = 0;
    // The path, then views finer than the bake (1e-3 of the diagonal): the run time goes on
    // below it.
    let mut path = camera_path(center, diag, aabb.min.z);
    path.push(Step {
        label: "object, finer than the bake",
        view: View::Object {
            tolerance: 3e-4 * diag,
        },
        meter: None,
    });
    let near = path.iter().find(|s| s.label == "near").unwrap();
    path.push(Step {
        label: "near at 0.25 px",
        view: near.view.with_tolerance(0.25),
        meter: near.meter.clone(),
    });
    let (mut refined, mut culled_patches) = (0, 0);
    for step in path {
        let what = format!("{label} {}", step.label);
        let stats = selection.update(&step.view).unwrap();
        // The same view again keeps the mesh (the checks below, and the next step's against
        // a fresh run time, see the kept one).
        assert_eq!(
            selection.update(&step.view).unwrap(),
            stats,
            "{}",
            step.label
        );
        let size = selection.mesh_size();
        let mut mesh = Mesh {
            vertices: vec![Vertex::default(); size.vertices],
            triangles: vec![[0u32; 3]; size.triangles],
        };
        let written = selection
            .write_mesh(&mut mesh.vertices, &mut mesh.triangles, &mut remap)
            .unwrap();
        assert_eq!(written, size, "{what}");
        let tris = streamed(&selection);
        assert_eq!(tris.len(), stats.triangles, "{what}");
        for (t, s) in mesh.triangles.iter().zip(&tris) {
            for (&i, c) in t.iter().zip(&s.corners) {
                assert_eq!(mesh.vertices[i as usize], *c, "{what}: stream != indexed");
            }
        }
        // A side is open where its curve is, or where the patch across is culled for facing
        // away (which must be true: checked here with the f64 reference's normals).
        let culled: Vec<bool> = (0..refs.len() as u32)
            .map(|p| selection.is_culled(p))
            .collect();
        for (p, _) in culled.iter().enumerate().filter(|(_, &c)| c) {
            let eye = step.meter.as_ref().expect("culling needs a camera").eye();
            assert_back_facing(&what, p, &refs[p], eye, outward[p]);
            culled_patches += 1;
        }
        let open = |p: u32, side: usize| {
            open_curve(p, side) || links[p as usize][side].is_some_and(|l| culled[l.patch as usize])
        };
        let gaps = check_watertight(&what, &mesh, &tris, &open, step.meter.as_ref(), &refs);
        let tolerance = step.view.tolerance() as f64;
        assert_eq!(
            stats.left_over > 0,
            stats.worst_bound as f64 > tolerance,
            "{what}: the frame's bound is over the tolerance exactly where leaves are left over"
        );
        left_over_frames += usize::from(stats.left_over > 0);
        refined += stats.refined;
        let allowed = tolerance.max(stats.worst_bound as f64);
        let (worst, tightest) = measure_frame(&refs, &tris, step.meter.as_ref());
        let slack = if step.meter.is_some() {
            1e-3
        } else {
            1e-6 * diag as f64
        };
        println!(
            "{what}: {} triangles, {} vertices ({} below the bake), {} judged, {} hidden, {} left \
             over, stack {} ({} sweeps), {gaps} open edges out of sight, bound {:.3}, measured \
             {worst:.3} (allowed {allowed:.3}), bound / true at least {tightest:.3}",
            stats.triangles,
            size.vertices,
            stats.refined,
            stats.judged,
            stats.hidden,
            stats.left_over,
            stats.stack_peak,
            stats.sweeps,
            stats.worst_bound,
        );
        assert!(
            tightest >= 1.0,
            "{what}: a triangle's bound is {tightest} of its measured deviation"
        );
        assert!(
            worst <= allowed * 1.001 + slack,
            "{what}: deviation {worst} > {allowed}"
        );
        // History independence: a fresh run time finds the same mesh.
        let mut fresh = fresh_storage.tessellator(tree);
        fresh.update(&step.view).unwrap();
        let a: HashSet<_> = triangle_set(&tris).into_iter().collect();
        let b: HashSet<_> = triangle_set(&streamed(&fresh)).into_iter().collect();
        assert!(a == b, "{what}: the mesh differs from a fresh run time's");
        let mut short = short_storage.tessellator(tree);
        sweeps += short.update(&step.view).unwrap().sweeps;
        let c: HashSet<_> = triangle_set(&streamed(&short)).into_iter().collect();
        assert!(a == c, "{what}: the mesh differs with a short stack");
        // Bounds from the kept vectors in integers, over the bytes (what a part without an
        // FPU computes): sound too, where they take other triangles.
        let mut integer = integer_storage
            .tessellator(bytes_tree)
            .with_arithmetic(Arithmetic::Integer);
        let integer_stats = integer.update(&step.view).unwrap();
        let d: HashSet<_> = triangle_set(&streamed(&integer)).into_iter().collect();
        if a != d {
            integer_apart += 1;
            let allowed = tolerance.max(integer_stats.worst_bound as f64);
            let (worst, tightest) = measure_frame(&refs, &streamed(&integer), step.meter.as_ref());
            println!(
                "{what}, bounds in integers: {} triangles, measured {worst:.3} (allowed \
                 {allowed:.3})",
                integer_stats.triangles
            );
            assert!(
                tightest >= 1.0 && worst <= allowed * 1.001 + slack,
                "{what}, bounds in integers: deviation {worst} > {allowed}"
            );
        }
    }
    assert!(sweeps > 0, "{label}: a stack of 8 never ran short");
    println!("{label}: bounds in integers took other triangles in {integer_apart} views");
    // Budget mode on the mid view: within the budget, within the bound it reports, and
    // minimal (1% less tolerance exceeds the budget).
    let path = camera_path(center, diag, aabb.min.z);
    let mid = path.iter().find(|s| s.label == "mid").unwrap();
    let full = selection.update(&mid.view).unwrap().triangles;
    // The fewest triangles: the roots of the patches in sight (a patch cut into many cells
    // has many).
    let coarsest = selection
        .update(&mid.view.with_tolerance(f32::MAX))
        .unwrap()
        .triangles;
    for budget in [full / 3, full / 2, full + 10] {
        if budget < coarsest {
            assert_eq!(
                selection.update_to_budget(&mid.view, budget),
                Err(BudgetError::TooSmall { minimum: coarsest }),
                "{label}: a budget below the roots"
            );
            continue;
        }
        let fit = selection.update_to_budget(&mid.view, budget).unwrap();
        assert!(
            fit.stats.triangles <= budget,
            "{label}: over budget {budget}"
        );
        assert_eq!(
            fit.stats,
            selection.stats(),
            "{label}: the fit's frame is the current one"
        );
        let (worst, tightest) = measure_frame(&refs, &streamed(&selection), mid.meter.as_ref());
        println!(
            "{label} budget {budget}: {} triangles, tolerance {:.4}, bound {:.4}, measured {worst:.4}",
            fit.stats.triangles, fit.tolerance, fit.bound
        );
        assert!(
            tightest >= 1.0 && worst <= fit.bound as f64 * 1.001 + 1e-3,
            "{label} budget {budget}: deviation {worst} > reported bound {}",
            fit.bound
        );
        if !fit.exhausted {
            let finer = selection
                .update(&mid.view.with_tolerance(fit.tolerance * 0.99))
                .unwrap();
            assert!(
                finer.triangles > budget,
                "{label}: tolerance not minimal within 1%"
            );
        }
    }
    println!("{label}: {refined} vertices made below the bake, {culled_patches} patches culled");
    if label == "rational_torus.json" {
        assert!(culled_patches > 0, "{label}: a closed model culls nothing");
    }
    assert!(refined > 0, "{label}: no view went below the bake");
    assert_eq!(
        left_over_frames, 0,
        "{label}: a pool of 65536 vertices ran short"
    );
}

/// The mesh is the coarsest conforming one within the tolerance: the same triangles as
/// `host_tests::bintree::bintree` (the oracles' bisection, which finds neighbours its own
/// way: by their corners' points in model space) splitting by the bake's own bounds.
fn coarsest(path: &std::path::Path) {
    let label = name(path);
    let (file, baked, refs) = baked(path);
    let tree = baked.tree();
    let patches = file.patches();
    let diag = patches.aabb().unwrap().diagonal() as f64;
    // Every baked triangle's bound, by its corners on the oracles' grid (half the kernel's).
    let mut bounds: HashMap<Bin, f32> = HashMap::new();
    let cells: Vec<[u8; 2]> = (0..tree.patch_count())
        .map(|p| tree.patch(p).expect("patch").cells)
        .collect();
    let mut stack: Vec<(Bin, usize)> = cell_roots(&cells)
        .into_iter()
        .enumerate()
        .map(|(i, b)| (b, i))
        .collect();
    while let Some((b, i)) = stack.pop() {
        let node = tree.node(i).expect("node");
        bounds.insert(b, node.object_bound());
        if node.children != 0 {
            for (k, c) in children(b).into_iter().enumerate() {
                stack.push((c, node.children as usize + k));
            }
        }
    }
    let spot = |p: usize, g: [u32; 2]| model_spot(&refs, diag, p, g);
    let mut storage = VecStorage::new(&tree, 1 << 16, 1 << 16);
    let mut selection = storage.tessellator(tree);
    for rel in [2e-3, 5e-3] {
        let tolerance = (rel * diag) as f32;
        selection.update(&View::Object { tolerance }).unwrap();
        // (Corners as sets: a flipped patch writes its triangles the other way round.)
        let ours: HashSet<Bin> = streamed(&selection)
            .iter()
            .map(|t| {
                let mut g =
                    t.uv.map(|[u, v]| [u, v].map(|x| (x * (1u32 << BINTREE_BITS) as f32) as u32));
                g.sort();
                (t.patch as usize, g)
            })
            .collect();
        let theirs: HashSet<Bin> = bintree_from(cell_roots(&cells), tolerance as f64, spot, |b| {
            bounds.get(&b).map_or(0.0, |&x| x as f64)
        })
        .into_iter()
        // Triangles with two corners on a pole are not written.
        .filter(|&(p, t)| {
            let s = t.map(|g| spot(p, g));
            s[0] != s[1] && s[1] != s[2] && s[2] != s[0]
        })
        .map(|(p, mut t)| {
            t.sort();
            (p, t)
        })
        .collect();
        assert_eq!(ours.len(), theirs.len(), "{label} at {rel}");
        assert!(ours == theirs, "{label} at {rel}: the meshes differ");
    }
}

#[test]
fn the_mesh_is_the_coarsest_conforming_one() {
    for model in [
        "teapot.bpt",
        "nurbs/tinynurbs_hemisphere.json",
        "teaspoon.bpt",
    ] {
        coarsest(&host_tests::models_dir().join(model));
    }
}

#[test]
fn bpt_models_along_a_camera_path() {
    for path in bpt_models() {
        run_model(&path);
    }
}

#[test]
fn nurbs_fixtures_along_a_camera_path() {
    for path in nurbs_fixtures() {
        run_model(&path);
    }
}

/// Checks that patch `r` shows `eye` only its back: `(P - eye) . n >= 0` at every point of a
/// 33 x 33 grid, `n` the outward normal (`sign` times `S_u x S_v`).
fn assert_back_facing(label: &str, patch: usize, r: &RefPatch, eye: [f64; 3], sign: f64) {
    use host_tests::reference::{cross, dot, norm, sub};
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
