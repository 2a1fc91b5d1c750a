//! One view's frames in a loop, for a profiler or for timing two builds against each other:
//! the teapot at 1024x768, 1 px, eye (6,-6,4), baked at `BAKE_REL` (default 2.5e-4) of its
//! diagonal, read with its links (`Hierarchy::with_links`, as `host::Baked` reads it). `FRAMES` frames (default 200), each an update and an indexed write, each a cold
//! one (a new tessellator on the same storage: a view equal to the last would keep its mesh).
//! With `MODEL` (a path under `examples/models`, `nurbs/rational_torus.json` say) another
//! model, seen as the error table's 1.3-diagonal views see it. With `ORBIT=1` the eye goes
//! around the model a degree a frame (`DEGREES` for another step), and with `REUSE=1` too the
//! tessellator keeps its judgements from frame to frame (`Tessellator::with_reuse`). With
//! `PARALLEL=1` each update searches on all cores (`Tessellator::update_parallel`), and the write is on all cores too (`Tessellator::write_mesh_parallel`). Prints the last frame's
//! triangles, the best, mean and median frame times and the median update's, the mean
//! triangles judged and judgements kept a frame, and how many frames were steps from the one
//! before (`FrameStats::stepped`). The bake happens before the loop and is not timed (a
//! profile of the whole run includes it).
//!
//! With `TABLE=1`, a table instead: for each camera view of the error table
//! (`host_tests::screen::ERROR_VIEWS`, each model baked at `BAKE_REL`, default 1e-3 there as in
//! the error table): a cold frame of the view (median of 21), the same on all cores
//! (`Tessellator::update_parallel`, median of 21) and, with `GLU_PEER` set,
//! libGLU's NURBS tessellator on the same camera (best of fifteen, its peer's own figure); then
//! an orbit of 48 steps from the view (the eye a degree further around the target's vertical
//! each), each step's view as a cold frame (best of three, median over the steps) and as a step
//! from the one before (the tessellator kept; median over the steps), without and with reuse;
//! for the orbit's cold frames and its steps with reuse, the update alone too (the cold
//! update's best of three, median over the steps), and the same two on all cores
//! (`update_parallel`: a cold frame's search on the threads, a step's judgements made again
//! on them), and how many of those frames were steps from the one before; and the same view
//! again (median of 21). All in this one run; a frame is an update and an indexed write.
//!
//! ```text
//! cargo run --release -p host-tests --example frame_loop
//! ORBIT=1 BAKE_REL=1e-3 cargo run --release -p host-tests --example frame_loop
//! TABLE=1 GLU_PEER=target/glu/glu_peer cargo run --release -p host-tests --example frame_loop
//! perf record -g target/release/examples/frame_loop
//! ```

use std::time::Instant;

use host_tests::glu::run_glu;
use host_tests::model_file::ModelFile;
use host_tests::reference::RefPatch;
use host_tests::runtime::{BakedHierarchy, VecStorage};
use host_tests::screen::{camera_40, ERROR_VIEWS};
use spline_tess::bake::BakeSettings;
use spline_tess::bake::Tolerance;
use spline_tess::{Camera, Projection, Vec3, Vertex, View};

fn env<T: std::str::FromStr>(name: &str, default: T) -> T {
    std::env::var(name)
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

fn main() {
    if std::env::var("TABLE").is_ok_and(|v| v == "1") {
        table();
        return;
    }
    let rel: f32 = env("BAKE_REL", 2.5e-4);
    let frames: usize = env("FRAMES", 200).max(1);
    let model = std::env::var("MODEL").ok();
    let path = host_tests::models_dir().join(model.as_deref().unwrap_or("teapot.bpt"));
    let file = ModelFile::read(path.to_str().expect("a UTF-8 path")).expect("a model");
    let bounds = file.patches().aabb().expect("patches");
    let diag = bounds.diagonal();
    // The teapot's view, or another model's from the error table's direction.
    let (eye, target) = match model {
        None => (Vec3::new(6.0, -6.0, 4.0), Vec3::new(0.0, 0.0, 1.2)),
        Some(_) => {
            let c = bounds.center();
            (c + Vec3::new(0.7, -0.6, 0.4).normalize() * (1.3 * diag), c)
        }
    };
    // `EYE=x,y,z` (and `TARGET`) for another view of the model, `TOL` for another tolerance.
    let point = |name: &str, default: Vec3| {
        std::env::var(name).map_or(default, |v| {
            let p: Vec<f32> = v
                .split(',')
                .map(|x| x.trim().parse().expect("a number"))
                .collect();
            Vec3::new(p[0], p[1], p[2])
        })
    };
    let (eye, target) = (point("EYE", eye), point("TARGET", target));
    let tolerance_px: f32 = env("TOL", 1.0);
    // `SIZE=240x240` for another viewport.
    let size: Vec<u32> = std::env::var("SIZE")
        .unwrap_or_else(|_| "1024x768".into())
        .split('x')
        .map(|v| v.parse().expect("a size"))
        .collect();
    let orbit = std::env::var("ORBIT").is_ok_and(|v| v == "1");
    let degrees: f32 = env("DEGREES", 1.0);
    let view_at = |frame: usize| {
        let angle = if orbit {
            (frame as f32 * degrees).to_radians()
        } else {
            0.0
        };
        let (s, c) = angle.sin_cos();
        let d = eye - target;
        let eye = target + Vec3::new(c * d.x - s * d.y, s * d.x + c * d.y, d.z);
        let camera = Camera::new(
            eye,
            target,
            Vec3::Z,
            Projection::Perspective {
                fov_y_degrees: 40.0,
            },
            0.01 * diag,
            [size[0], size[1]],
        )
        .expect("a valid camera");
        View::Screen {
            camera,
            tolerance_px,
        }
    };
    {
        let settings = BakeSettings {
            tolerance: Tolerance::Relative(rel),
            ..BakeSettings::default()
        };
        let bake = BakedHierarchy::bake(&file, &settings).expect("a bisection bake");
        let mut links = Vec::new();
        let tree = bake.linked_tree(&mut links);
        let mut storage = VecStorage::new(&tree, 1 << 12, 1 << 16);
        let reuse = std::env::var("REUSE").is_ok_and(|v| v == "1");
        let parallel = std::env::var("PARALLEL").is_ok_and(|v| v == "1");
        let mut judgements =
            vec![spline_tess::tessellator::Judgement::NONE; tree.judgement_slots()];
        let mut selection = storage.tessellator(tree);
        if reuse {
            selection = selection.with_reuse(&mut judgements).expect("slots");
        }
        let mut remap = vec![0u32; tree.vertex_count() + (1 << 16)];
        let mut vertices = vec![Vertex::default(); 1 << 20];
        let mut triangles = vec![[0u32; 3]; 1 << 21];
        let (mut best, mut total, mut count) = (f64::INFINITY, 0.0, 0);
        let (mut judged, mut kept, mut refined, mut stepped) = (0, 0, 0, 0);
        let (mut updates, mut whole) = (Vec::new(), Vec::new());
        for k in 1..=frames {
            let view = view_at(k);
            if !orbit && !reuse {
                // A cold frame: a view equal to the last keeps its mesh.
                selection = storage.tessellator(tree);
            }
            let start = Instant::now();
            let stats = match parallel {
                true => selection.update_parallel(&view),
                false => selection.update(&view),
            }
            .unwrap();
            updates.push(start.elapsed().as_secs_f64() * 1e3);
            match parallel {
                true => selection.write_mesh_parallel(&mut vertices, &mut triangles, &mut remap),
                false => selection.write_mesh(&mut vertices, &mut triangles, &mut remap),
            }
            .expect("room");
            let ms = start.elapsed().as_secs_f64() * 1e3;
            whole.push(ms);
            stepped += usize::from(stats.stepped);
            best = best.min(ms);
            total += ms;
            count = stats.triangles;
            judged += stats.judged;
            kept += stats.kept;
            refined += stats.refined;
        }
        println!(
            "triangles {count} best {best:.3} ms mean {:.3} ms median {:.3} ms (update {:.3} ms) judged {} kept {} refined {} (means) stepped {stepped} of {frames}",
            total / frames as f64,
            median(&mut whole),
            median(&mut updates),
            judged / frames,
            kept / frames,
            refined / frames
        );
    }
}

/// The median of `v` (sorted in place).
fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The table of `TABLE=1` (see the module docs).
fn table() {
    let rel: f32 = env("BAKE_REL", 1e-3);
    let peer = std::env::var("GLU_PEER").ok();
    const REPEATS: usize = 21;
    const STEPS: usize = 48;
    println!(
        "| view | triangles | cold ms | GLU triangles | GLU ms | cold / GLU | cold ms, all cores | all cores / GLU | orbit: cold ms | orbit: step ms | orbit: step with reuse ms | reuse step / cold | orbit update: cold ms | orbit update: step with reuse ms | update: step / cold | orbit update, all cores: cold ms | orbit update, all cores: step with reuse ms | all cores: step / cold | frames stepped | judgements kept | same view again ms |"
    );
    println!(
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
    );
    let mut baked: Vec<(&str, ModelFile, BakedHierarchy)> = Vec::new();
    for v in ERROR_VIEWS {
        if !baked.iter().any(|(m, ..)| *m == v.model) {
            let path = host_tests::models_dir().join(v.model);
            let file = ModelFile::read(path.to_str().expect("a UTF-8 path")).expect("a model");
            let settings = BakeSettings {
                tolerance: Tolerance::Relative(rel),
                ..BakeSettings::default()
            };
            let bake = BakedHierarchy::bake(&file, &settings).expect("a bisection bake");
            baked.push((v.model, file, bake));
        }
        let (_, file, bake) = baked.iter().find(|(m, ..)| *m == v.model).expect("baked");
        let diag = file.patches().aabb().expect("patches").diagonal();
        let near = 0.01 * diag;
        let target = Vec3::from_array(v.target);
        let view_at = |degrees: f32| {
            let (s, c) = degrees.to_radians().sin_cos();
            let d = Vec3::from_array(v.eye) - target;
            let eye = target + Vec3::new(c * d.x - s * d.y, s * d.x + c * d.y, d.z);
            View::Screen {
                camera: camera_40(eye, target, near, v.viewport),
                tolerance_px: v.tol,
            }
        };
        let mut links = Vec::new();
        let tree = bake.linked_tree(&mut links);
        let mut storage = VecStorage::new(&tree, 1 << 12, 1 << 16);
        let mut remap = vec![0u32; tree.vertex_count() + (1 << 16)];
        let mut vertices = vec![Vertex::default(); 1 << 20];
        let mut triangles = vec![[0u32; 3]; 1 << 21];
        let view = view_at(0.0);
        let all_cores = std::cell::Cell::new(false);
        // The frame's time, its update's alone, and its figures.
        let mut timed = |selection: &mut spline_tess::Tessellator<'_, '_>, view: &View| {
            let start = Instant::now();
            let stats = match all_cores.get() {
                true => selection.update_parallel(view),
                false => selection.update(view),
            }
            .expect("a valid view");
            let update = start.elapsed().as_secs_f64() * 1e3;
            match all_cores.get() {
                true => selection.write_mesh_parallel(&mut vertices, &mut triangles, &mut remap),
                false => selection.write_mesh(&mut vertices, &mut triangles, &mut remap),
            }
            .expect("room");
            (start.elapsed().as_secs_f64() * 1e3, update, stats)
        };
        let (mut cold, mut parallel) = (Vec::new(), Vec::new());
        let mut count = 0;
        for _ in 0..REPEATS {
            let mut selection = storage.tessellator(tree);
            let (ms, _, stats) = timed(&mut selection, &view);
            cold.push(ms);
            count = stats.triangles;
        }
        all_cores.set(true);
        for _ in 0..REPEATS {
            let mut selection = storage.tessellator(tree);
            let (ms, _, stats) = timed(&mut selection, &view);
            assert_eq!(
                stats.triangles, count,
                "{}: the same mesh on all cores",
                v.name
            );
            parallel.push(ms);
        }
        all_cores.set(false);
        // The orbit's views, each cold (best of three, and its update's best) and as a step
        // from the one before.
        let (mut orbit_cold, mut orbit) = (Vec::new(), Vec::new());
        let mut cold_updates = Vec::new();
        for k in 1..=STEPS {
            let step_view = view_at(k as f32);
            let (mut best, mut best_update) = (f64::INFINITY, f64::INFINITY);
            for _ in 0..3 {
                let (ms, update, _) = timed(&mut storage.tessellator(tree), &step_view);
                (best, best_update) = (best.min(ms), best_update.min(update));
            }
            orbit_cold.push(best);
            cold_updates.push(best_update);
        }
        // The orbit's cold updates on all cores (best of three).
        all_cores.set(true);
        let mut cold_parallel_updates = Vec::new();
        for k in 1..=STEPS {
            let step_view = view_at(k as f32);
            let best = (0..3)
                .map(|_| timed(&mut storage.tessellator(tree), &step_view).1)
                .fold(f64::INFINITY, f64::min);
            cold_parallel_updates.push(best);
        }
        all_cores.set(false);
        let mut again = Vec::new();
        {
            let mut selection = storage.tessellator(tree);
            timed(&mut selection, &view);
            for _ in 0..REPEATS {
                again.push(timed(&mut selection, &view).0);
            }
            for k in 1..=STEPS {
                orbit.push(timed(&mut selection, &view_at(k as f32)).0);
            }
        }
        // The same orbit with the judgements kept from step to step, on one thread and on all
        // cores (`update_parallel`: a step's judgements made again on the threads, with the
        // same figures).
        let (mut reused, mut kept, mut judged) = (Vec::new(), 0, 0);
        let (mut reused_updates, mut stepped) = (Vec::new(), 0);
        let mut reused_parallel_updates = Vec::new();
        for parallel in [false, true] {
            let mut judgements =
                vec![spline_tess::tessellator::Judgement::NONE; tree.judgement_slots()];
            let mut selection = storage
                .tessellator(tree)
                .with_reuse(&mut judgements)
                .expect("slots for every node");
            all_cores.set(parallel);
            timed(&mut selection, &view);
            for k in 1..=STEPS {
                let (ms, update, stats) = timed(&mut selection, &view_at(k as f32));
                if parallel {
                    reused_parallel_updates.push(update);
                    continue;
                }
                reused.push(ms);
                reused_updates.push(update);
                kept += stats.kept;
                judged += stats.judged;
                stepped += usize::from(stats.stepped);
            }
        }
        all_cores.set(false);
        let (cold_parallel_update, reused_parallel_update) = (
            median(&mut cold_parallel_updates),
            median(&mut reused_parallel_updates),
        );
        let reused = median(&mut reused);
        let (cold_update, reused_update) = (median(&mut cold_updates), median(&mut reused_updates));
        let kept_share = kept as f64 / (kept + judged).max(1) as f64;
        let (cold, again) = (median(&mut cold), median(&mut again));
        let parallel = median(&mut parallel);
        let (orbit_cold, orbit) = (median(&mut orbit_cold), median(&mut orbit));
        let glu = peer.as_deref().map(|binary| {
            let refs: Vec<RefPatch> = file
                .patches()
                .iter()
                .map(|p| RefPatch::from_kernel(&p))
                .collect();
            run_glu(
                binary,
                &refs,
                v.eye,
                v.target,
                v.viewport,
                near,
                v.tol as f64,
            )
        });
        let (glu_tris, glu_ms, ratio, parallel_ratio) = match &glu {
            Some(run) => (
                run.triangles.len().to_string(),
                format!("{:.2}", run.ms),
                format!("{:.2}", cold / run.ms),
                format!("{:.2}", parallel / run.ms),
            ),
            None => ("-".into(), "-".into(), "-".into(), "-".into()),
        };
        println!(
            "| {} | {count} | {cold:.2} | {glu_tris} | {glu_ms} | {ratio} | {parallel:.2} | {parallel_ratio} | {orbit_cold:.2} | {orbit:.2} | {reused:.2} | {:.2} | {cold_update:.3} | {reused_update:.3} | {:.2} | {cold_parallel_update:.3} | {reused_parallel_update:.3} | {:.2} | {stepped} of {STEPS} | {:.0}% | {again:.3} |",
            v.name,
            reused / orbit_cold,
            reused_update / cold_update,
            reused_parallel_update / cold_parallel_update,
            100.0 * kept_share
        );
    }
}
