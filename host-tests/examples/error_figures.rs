//! Error-control figures: for every model at several views and tolerances, the kernel's
//! triangles beside the verified uniform grid, the measured error distribution, how tight the
//! kernel's bounds are, the triangles with nothing on screen, and the speed of a full frame.
//! Prints a Markdown table.
//!
//! ```text
//! cargo run --release -p host-tests --example error_figures            # every case
//! cargo run --release -p host-tests --example error_figures -- teapot  # cases naming it
//! ```
//!
//! Each model's hierarchy is baked at 1e-3 of its diagonal (`BAKE_REL` sets another). Every
//! triangle the kernel writes is sampled at 12 barycentric steps per side with the `f64`
//! reference, as the surface against the triangle's linear interpolant at the same parameters,
//! projected with an `f64` camera of the tests' own; only samples that land on screen count
//! (`host_tests::screen`). *n x n grid* is the sum over patches of the smallest uniform n x n
//! vertex grid whose error, measured the same way (8 steps per grid triangle), is within the
//! tolerance: a lower bound for any uniform tessellator with one factor a patch (it has cracks;
//! a crack-free one needs a few more). *n_u x n_v grid* is the same with a factor per
//! direction, chosen per patch to minimise triangles (as the Direct3D 11 tessellator may):
//! the stronger reference. *Ratio* is the kernel's triangles over it; *ratio to n x n* over
//! the first. *Bound / true* compares each triangle's bound from the kernel with its measured
//! deviation in model units (triangles whose deviation is below 1e-9 of the diagonal left
//! out). *Cracks* is 0 when the written mesh passes the tests' watertightness check
//! (`host_tests::frame_checks::check_watertight`: an edge used once lies on an open curve,
//! beside a patch culled for facing away, or out of sight; no edge is used more than twice;
//! no two vertices share a position). *Off screen* counts the triangles with no sample on screen. *Full ms* is a frame
//! from a new run time over the hierarchy with its links (`Hierarchy::with_links`, as the
//! host's `Baked` reads it), its update and the indexed write, best of eleven or of as many as
//! take half a second; *all cores ms*
//! the same with the update and the write on all cores (`Tessellator::update_parallel`,
//! `Tessellator::write_mesh_parallel`), the two timed in
//! five turns each so that a busy moment of the machine spoils at most one; *Mtri/s* the first's
//! triangles per second. *Full / GLU* and *all cores / GLU* divide them by GLU's time.
//!
//! With `SPLIT` set, the kernel tessellates the model with every patch split into four
//! ([`spline_tess::PatchSet::split`]), baked at the same tolerance in the model's units; the
//! grid is still counted on the model's own patches, and every triangle is checked against
//! the model's own surface (a quarter's parameters mapped to its patch's). `SPLIT=2` splits
//! the quarters again (16 pieces a patch), and so on.
//!
//! With `GRID_CACHE` naming a file, the grids of each case are read from it where it has
//! them and written to it where not (they depend on the case alone, not on the bake).
//!
//! With `GLU_PEER` naming the binary built from `host-tests/glu/glu_peer.c` (as
//! `scripts/figures.sh` does), every camera case also goes through libGLU's NURBS tessellator:
//! the same Bezier patches, the same camera as OpenGL matrices, `GLU_PARAMETRIC_ERROR` at the
//! same pixel tolerance, culling on. Its triangles are verified exactly as the kernel's (their
//! corners' parameters come from a parameter surface tessellated alongside), and the table
//! gives its triangles, how many are over the tolerance, the worst error / tolerance and its
//! time (best of fifteen, tessellation alone).

use std::io::Write;
use std::time::Instant;

/// Frames timed per case (the best counts), at least: the checks between cases leave the
/// caches cold, and this machine's times vary from run to run.
const TIMED: usize = 11;

/// Seconds a case's frames are timed for, at least: a frame of a fraction of a millisecond
/// is timed many more than [`TIMED`] times, so that its best is not one a busy moment of the
/// machine spoilt (a frame on all cores waits for both).
const TIMED_FOR: f64 = 0.5;

/// Turns of one-thread and all-core frames a case's timing takes (see [`TIMED_FOR`]).
const ROUNDS: usize = 5;

use host_tests::frame_checks::check_watertight_of_parts;
use host_tests::glu::run_glu;
use host_tests::model_file::{within, ModelFile};
use host_tests::reference::{RefPatch, V3};
use host_tests::runtime::{indexed, streamed, BakedHierarchy, VecStorage};
use host_tests::screen::{grid_triangles, triangle_deviation, Measure, Meter, ERROR_VIEWS};
use spline_tess::bake::BakeSettings;
use spline_tess::bake::Tolerance;
use spline_tess::{Camera, EdgeLink, ParamRect, Projection, Vec3, Vertex, View};

/// The default bake tolerance, relative to the model's diagonal (`BAKE_REL` sets another).
const BAKE_REL: f32 = 1e-3;
const DENSE: usize = 12;
const GRID_DENSE: usize = 8;

/// Where a case looks from.
#[derive(Clone, Copy)]
enum Look {
    /// A camera: eye, target, viewport, tolerance in pixels.
    Screen {
        eye: [f32; 3],
        target: [f32; 3],
        viewport: [u32; 2],
        tol: f32,
    },
    /// Object space, tolerance relative to the diagonal.
    Object { rel: f32 },
    /// A camera placed from the model's own box: direction from its centre, distance in
    /// diagonals.
    Around {
        dir: [f32; 3],
        distance: f32,
        viewport: [u32; 2],
        tol: f32,
    },
}

/// A model as read, what the kernel tessellates (with `SPLIT`, its patches split into `4^L`
/// pieces for `L` levels, piece `k` being `pieces[k]` of patch `k / 4^L`), and the kernel's
/// bake.
struct Baked {
    model: &'static str,
    file: ModelFile,
    pieces: Option<Vec<(u32, ParamRect)>>,
    hierarchy: BakedHierarchy,
}

struct Case {
    name: String,
    model: &'static str,
    look: Look,
}

/// The grids of each case, kept in the file `GRID_CACHE` names (if set) from one run to the
/// next: they depend on the case alone (its model, view and tolerance), not on the bake, and
/// take most of a run (`scripts/figures.sh` runs three tables of the same cases).
struct GridCache {
    path: Option<String>,
    known: Vec<(String, [usize; 2])>,
}

impl GridCache {
    fn open() -> GridCache {
        let path = std::env::var("GRID_CACHE").ok();
        let text = path
            .as_ref()
            .and_then(|p| std::fs::read_to_string(p).ok())
            .unwrap_or_default();
        let known = text
            .lines()
            .filter_map(|line| {
                let mut parts = line.split('\t');
                let name = parts.next()?.to_string();
                let a = parts.next()?.parse().ok()?;
                let b = parts.next()?.parse().ok()?;
                Some((name, [a, b]))
            })
            .collect();
        GridCache { path, known }
    }

    fn get(&mut self, name: &str, compute: impl FnOnce() -> [usize; 2]) -> [usize; 2] {
        if let Some((_, g)) = self.known.iter().find(|(n, _)| n == name) {
            return *g;
        }
        let g = compute();
        self.known.push((name.to_string(), g));
        if let Some(path) = &self.path {
            let mut file = std::fs::OpenOptions::new()
                .create(true)
                .append(true)
                .open(path)
                .expect("the grid cache opens");
            writeln!(file, "{name}\t{}\t{}", g[0], g[1]).expect("the grid cache is written");
        }
        g
    }
}

fn cases() -> Vec<Case> {
    let mut v: Vec<Case> = ERROR_VIEWS
        .iter()
        .map(|w| Case {
            name: w.name.to_string(),
            model: w.model,
            look: Look::Screen {
                eye: w.eye,
                target: w.target,
                viewport: w.viewport,
                tol: w.tol,
            },
        })
        .collect();
    v.extend([Case {
        name: "teapot object 0.02".into(),
        model: "teapot.bpt",
        look: Look::Object { rel: 0.02 / 7.0 },
    }]);
    for model in [
        "teapot.bpt",
        "teapot_orig28.bpt",
        "teapot_westin.bpt",
        "teacup.bpt",
        "teaspoon.bpt",
        "gumbo.bpt",
        "nurbs/geomdl_surface1.json",
        "nurbs/geomdl_surface2_weighted.json",
        "nurbs/rational_torus.json",
        "nurbs/threejs_nurbs_example.json",
        "nurbs/tinynurbs_hemisphere.json",
        "nurbs/verb_quarter_cylinder.json",
    ] {
        let short = model.trim_start_matches("nurbs/");
        for (viewport, tol) in [([240, 240], 1.0), ([1024, 768], 1.0)] {
            v.push(Case {
                name: format!(
                    "{short} {}x{} {tol} px, 1.3 diagonals",
                    viewport[0], viewport[1]
                ),
                model,
                look: Look::Around {
                    dir: [0.7, -0.6, 0.4],
                    distance: 1.3,
                    viewport,
                    tol,
                },
            });
        }
        v.push(Case {
            name: format!("{short} object 2e-3 of the diagonal"),
            model,
            look: Look::Object { rel: 2e-3 },
        });
    }
    v
}

fn widen(p: [f32; 3]) -> V3 {
    p.map(|x| x as f64)
}

fn quantile(v: &mut [f64], f: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * f) as usize]
}

fn main() {
    let only: Vec<String> = std::env::args().skip(1).collect();
    let peer = std::env::var("GLU_PEER").ok();
    let glu_header = if peer.is_some() {
        " GLU triangles | GLU over | GLU worst / tol | GLU ms | full / GLU | all cores / GLU |"
    } else {
        ""
    };
    println!(
        "| case | triangles | n x n grid | n_u x n_v grid | ratio | ratio to n x n | over | cracks | \
         median error / tol | 90% error / tol | bound / true: min, median | off screen | full ms | \
         all cores ms | Mtri/s |{glu_header}"
    );
    println!(
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|{}",
        if peer.is_some() {
            "---|---|---|---|---|---|"
        } else {
            ""
        }
    );
    // Levels of splitting: `SPLIT` unset 0, set 1 (or the number it gives).
    let split_levels: u32 = std::env::var("SPLIT")
        .ok()
        .map_or(0, |v| v.parse().unwrap_or(1));
    let split = split_levels > 0;
    let mut baked_cache: Vec<Baked> = Vec::new();
    let mut grids = GridCache::open();
    for case in cases() {
        if !only.is_empty() && !only.iter().any(|o| case.name.contains(o.as_str())) {
            continue;
        }
        if !baked_cache.iter().any(|b| b.model == case.model) {
            let path = host_tests::models_dir().join(case.model);
            let file = ModelFile::read(path.to_str().expect("a UTF-8 path")).expect("a model");
            let rel = std::env::var("BAKE_REL")
                .ok()
                .and_then(|s| s.parse().ok())
                .unwrap_or(BAKE_REL);
            let (kernel, pieces) = if split {
                let (mut kernel, mut pieces) = file.split().expect("a split");
                for _ in 1..split_levels {
                    let (finer, local) = kernel.split().expect("a split");
                    // Piece `k` of the finer set is `local[k]` of piece `k / 4` before.
                    pieces = local
                        .iter()
                        .enumerate()
                        .map(|(k, &r)| within(pieces[k / 4], r))
                        .collect();
                    kernel = finer;
                }
                let owned = pieces
                    .iter()
                    .enumerate()
                    .map(|(k, &r)| ((k >> (2 * split_levels)) as u32, r))
                    .collect();
                (kernel, Some(owned))
            } else {
                (file.clone(), None)
            };
            // Relative to the model's own diagonal, not the quarters' (a little smaller).
            let diag = file.patches().aabb().expect("patches").diagonal();
            let tolerance = if pieces.is_some() {
                Tolerance::Absolute(rel * diag)
            } else {
                Tolerance::Relative(rel)
            };
            let settings = BakeSettings {
                tolerance,
                ..BakeSettings::default()
            };
            let hierarchy = BakedHierarchy::bake(&kernel, &settings).expect("a bake");
            baked_cache.push(Baked {
                model: case.model,
                file,
                pieces,
                hierarchy,
            });
        }
        let Baked {
            file,
            pieces,
            hierarchy,
            ..
        } = baked_cache
            .iter()
            .find(|b| b.model == case.model)
            .expect("baked above");
        let aabb = file.patches().aabb().expect("patches");
        let (center, diag) = (aabb.center(), aabb.diagonal());
        // The model's own patches: the reference for the grid and for every check.
        let refs: Vec<RefPatch> = file
            .patches()
            .iter()
            .map(|p| RefPatch::from_kernel(&p))
            .collect();
        let near = 0.01 * diag;
        let mut placed: Option<([f32; 3], [f32; 3], [u32; 2])> = None;
        let (view, meter, tol) = match case.look {
            Look::Object { rel } => (
                View::Object {
                    tolerance: rel * diag,
                },
                None,
                (rel * diag) as f64,
            ),
            look => {
                let (eye, target, viewport, tol) = match look {
                    Look::Screen {
                        eye,
                        target,
                        viewport,
                        tol,
                    } => (
                        Vec3::from_array(eye),
                        Vec3::from_array(target),
                        viewport,
                        tol,
                    ),
                    Look::Around {
                        dir,
                        distance,
                        viewport,
                        tol,
                    } => (
                        center + Vec3::from_array(dir).normalize() * (distance * diag),
                        center,
                        viewport,
                        tol,
                    ),
                    Look::Object { .. } => unreachable!(),
                };
                placed = Some((eye.to_array(), target.to_array(), viewport));
                let camera = Camera::new(
                    eye,
                    target,
                    Vec3::Z,
                    Projection::Perspective {
                        fov_y_degrees: 40.0,
                    },
                    near,
                    viewport,
                )
                .expect("a valid camera");
                let meter = Meter::new(
                    widen(eye.to_array()),
                    widen(target.to_array()),
                    [0.0, 0.0, 1.0],
                    40.0,
                    near as f64,
                    viewport,
                );
                (
                    View::Screen {
                        camera,
                        tolerance_px: tol,
                    },
                    Some(meter),
                    tol as f64,
                )
            }
        };
        let measure = match &meter {
            Some(m) => Measure::Screen(m),
            None => Measure::Object,
        };
        // Speed: a full frame, best of `TIMED` or more.
        let mut vertices = vec![Vertex::default(); 1 << 20];
        let mut triangles = vec![[0u32; 3]; 1 << 21];
        let mut links = Vec::new();
        let tree = hierarchy.linked_tree(&mut links);
        let mut store = VecStorage::new(&tree, 1 << 12, 1 << 16);
        let mut remap = vec![0u32; tree.vertex_count() + (1 << 16)];
        // The best of `TIMED` frames or more (`TIMED_FOR`) on one thread and on all cores, in
        // `ROUNDS` turns of each, so that a busy moment of the machine spoils at most one turn
        // of one of them (a pause between turns lets the pool's idle threads sleep, which
        // would otherwise spin beside the one-thread frames); and each frame's figures.
        let mut frame = |all_cores: bool| {
            let start = Instant::now();
            let mut s = store.tessellator(tree);
            let stats = match all_cores {
                true => s.update_parallel(&view),
                false => s.update(&view),
            }
            .unwrap();
            match all_cores {
                true => s.write_mesh_parallel(&mut vertices, &mut triangles, &mut remap),
                false => s.write_mesh(&mut vertices, &mut triangles, &mut remap),
            }
            .expect("room");
            (start.elapsed().as_secs_f64() * 1e3, stats)
        };
        let (mut best, mut all_cores) = (f64::INFINITY, f64::INFINITY);
        let (mut frames, mut parallel_frames) = (Vec::new(), Vec::new());
        for _ in 0..ROUNDS {
            for parallel in [false, true] {
                let (best, frames) = match parallel {
                    false => (&mut best, &mut frames),
                    true => (&mut all_cores, &mut parallel_frames),
                };
                let (began, taken) = (Instant::now(), frames.len());
                while frames.len() - taken < TIMED.div_ceil(ROUNDS)
                    || began.elapsed().as_secs_f64() < TIMED_FOR / ROUNDS as f64
                {
                    let (ms, stats) = frame(parallel);
                    *best = best.min(ms);
                    frames.push(stats);
                }
                std::thread::sleep(std::time::Duration::from_millis(20));
            }
        }
        let last = frames.last().expect("a frame");
        let (count, left_over) = (last.triangles, last.left_over);
        // The same on all cores (`update_parallel`): the same mesh.
        for stats in parallel_frames {
            assert_eq!(stats.triangles, count, "{}: all cores", case.name);
        }
        let mut s = store.tessellator(tree);
        s.update(&view).unwrap();
        let tris = streamed(&s);
        // Cracks, as the tests look for them (`frame_checks::check_watertight`): an edge used
        // once must lie on an open curve, beside a patch culled for facing away, or out of
        // sight; no edge is used more than twice; no two vertices share a position.
        let cracks = {
            let mesh = indexed(&mut s);
            let (edges, uses) = hierarchy
                .file
                .with_model(|m| {
                    let uses: Vec<u32> = m.topology.curves().iter().map(|c| c.uses).collect();
                    (m.topology.edges().to_vec(), uses)
                })
                .expect("a topology");
            let links: Vec<_> = (0..tree.patch_count())
                .map(|p| tree.patch(p).expect("patch").links)
                .collect();
            let culled: Vec<bool> = (0..links.len() as u32).map(|p| s.is_culled(p)).collect();
            let open = |p: u32, side: usize| {
                let curve_open = match edges[p as usize][side] {
                    EdgeLink::Collapsed => false,
                    EdgeLink::Curve { curve, .. } => uses[curve as usize] == 1,
                };
                curve_open || links[p as usize][side].is_some_and(|l| culled[l.patch as usize])
            };
            let kernel_refs: Vec<RefPatch> = hierarchy
                .file
                .patches()
                .iter()
                .map(|p| RefPatch::from_kernel(&p))
                .collect();
            // A split model's pieces named by their patch and its parameters.
            let origin = |p: u32, [u, v]: [f32; 2]| match pieces {
                Some(pieces) => {
                    let (owner, q) = pieces[p as usize];
                    let at = |a: f32, b: f32, t: f32| a as f64 + t as f64 * (b - a) as f64;
                    (owner, [at(q.u0, q.u1, u), at(q.v0, q.v1, v)])
                }
                None => (p, [u as f64, v as f64]),
            };
            let check = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                check_watertight_of_parts(
                    &case.name,
                    &mesh,
                    &tris,
                    &open,
                    meter.as_ref(),
                    &kernel_refs,
                    &origin,
                )
            }));
            match check {
                Ok(_) => "0".to_string(),
                Err(_) => "**crack**".to_string(),
            }
        };
        if left_over > 0 {
            eprintln!("{}: {left_over} leaves of the bake left over", case.name);
        }
        // Verification.
        let (mut errors, mut tight) = (Vec::new(), Vec::new());
        let (mut over, mut off) = (0usize, 0usize);
        let mut min_tight = f64::INFINITY;
        for t in &tris {
            // A quarter's parameters, as its patch's.
            let (patch, uv) = match pieces {
                Some(pieces) => {
                    let (owner, q) = pieces[t.patch as usize];
                    let map = |[u, v]: [f32; 2]| {
                        [
                            q.u0 as f64 + u as f64 * (q.u1 - q.u0) as f64,
                            q.v0 as f64 + v as f64 * (q.v1 - q.v0) as f64,
                        ]
                    };
                    (owner as usize, t.uv.map(map))
                }
                None => (t.patch as usize, t.uv.map(|[u, v]| [u as f64, v as f64])),
            };
            let r = &refs[patch];
            let corners = t.corners.map(|c| widen(c.position));
            let m = triangle_deviation(r, uv, corners, DENSE, measure);
            if !m.visible {
                off += 1;
                continue;
            }
            errors.push(m.worst / tol);
            if m.worst > tol * (1.0 + 1e-6) {
                over += 1;
                if std::env::var("SHOW_OVER").is_ok() {
                    let object = triangle_deviation(r, uv, corners, DENSE, Measure::Object);
                    eprintln!(
                        "over: patch {} uv {:?} measured {:.3} (object {:e}, bound {:e})",
                        t.patch,
                        t.uv,
                        m.worst / tol,
                        object.worst,
                        t.bound
                    );
                }
            }
            let object = match measure {
                Measure::Object => m,
                Measure::Screen(_) => triangle_deviation(r, uv, corners, DENSE, Measure::Object),
            };
            if object.worst > 1e-9 * diag as f64 {
                let ratio = t.bound as f64 / object.worst;
                min_tight = min_tight.min(ratio);
                tight.push(ratio);
            }
        }
        // The uniform grid per patch.
        let [grid, grid_uv] = grids.get(&case.name, || {
            grid_triangles(&refs, tol, GRID_DENSE, 512, measure)
        });
        let glu = match (&peer, placed) {
            (Some(binary), Some((eye, target, viewport))) => {
                let run = run_glu(binary, &refs, eye, target, viewport, near, tol);
                let (mut over, mut worst) = (0usize, 0.0f64);
                for t in &run.triangles {
                    let m = triangle_deviation(&refs[t.0], t.1, t.2, DENSE, measure);
                    worst = worst.max(m.worst / tol);
                    if m.worst > tol * (1.0 + 1e-6) {
                        over += 1;
                    }
                }
                format!(
                    " {} | {over} | {worst:.2} | {:.2} | {:.2} | {:.2} |",
                    run.triangles.len(),
                    run.ms,
                    best / run.ms,
                    all_cores / run.ms
                )
            }
            (Some(_), None) => " – | – | – | – | – | – |".to_string(),
            (None, _) => String::new(),
        };
        println!(
            "| {} | {count} | {grid} | {grid_uv} | {:.2} | {:.2} | {over} | {cracks} | {:.2} | {:.2} | {:.3}, {:.3} | {:.1}% | {best:.2} | {all_cores:.2} | {:.2} |{glu}",
            case.name,
            count as f64 / grid_uv as f64,
            count as f64 / grid as f64,
            quantile(&mut errors, 0.5),
            quantile(&mut errors, 0.9),
            min_tight,
            quantile(&mut tight, 0.5),
            100.0 * off as f64 / tris.len().max(1) as f64,
            count as f64 / best / 1e3
        );
    }
}
