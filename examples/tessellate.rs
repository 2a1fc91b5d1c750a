//! Tessellates a model for one view or along a camera path, writes the last frame as OBJ, and
//! prints one JSON line of frame statistics per frame.
//!
//! ```text
//! cargo run --release --example tessellate -- examples/models/teapot.bpt \
//!     --tolerance 1 --eye 8,-10,6 --target 0,0,1.5 --up 0,0,1 --fov 40 --viewport 1024x768 \
//!     --obj out/teapot.obj
//! cargo run --release --example tessellate -- examples/models/teapot.bpt \
//!     --object-tolerance 0.01 --obj out/teapot.obj
//! ```
//!
//! MODEL is `.bpt` or NURBS `.json`. Its hierarchy is baked on the fly (`--bake-tolerance`,
//! relative to the bounding-box diagonal, default 2.5e-4: `host::BAKE`), or read from the file `--baked` names
//! (written by the `bake` example from the same model). `--path FILE` holds one camera per
//! line, `ex ey ez tx ty tz ux uy uz fov`, applied in order; the OBJ is the last frame.
//! `--budget N` fits the tolerance to at most N triangles per frame. `--near D` sets the near
//! plane (default 1% of the model's diagonal). `--split` tessellates the model with every
//! patch split into four (`PatchSet::split`); the OBJ's groups are then the quarters
//! (`patch_K` is quarter K, a part of patch K / 4). The JSON line gives each frame's figures:
//! triangles, vertices, triangles judged, vertices made below the bake, leaves left over, and
//! the bound the frame honours.
//!
//! OBJ: `v` and `vn` per vertex (vertices on shared curves are shared by index, so the mesh is
//! welded), `vt` per face corner's own parameters (the patch's; for NURBS, the surface's), one
//! `g patch_K` per patch (for NURBS, K is the surface index: the file holds one surface, so
//! K = 0), and `f v/vt/vn`. A vertex whose parameters differ between the faces that use it (a
//! shared curve, a pole, the seam of a closed surface) has one `vt` per face's value.

mod common;

use std::process::ExitCode;
use std::time::Instant;

use common::hierarchy_file;
use common::model_file::{write_obj, BakedHierarchy, ModelFile};
use spline_tess::bake::BakeSettings;
use spline_tess::bake::Tolerance;
use spline_tess::host::Mesh;
use spline_tess::tessellator::{PoolSlot, StackSlot, Tessellator};
use spline_tess::{Camera, FrameStats, Projection, Vec3, Vertex, View};

const USAGE: &str = "usage: tessellate MODEL(.bpt|.json) (--object-tolerance EPS | --tolerance PX \
                     --eye X,Y,Z --target X,Y,Z --up X,Y,Z --fov DEG --viewport WxH) \
                     [--budget N] [--path FILE] [--bake-tolerance REL | --baked FILE] [--near D] \
                     [--split] --obj OUT.obj";

#[derive(Default)]
struct Args {
    model: String,
    object_tolerance: Option<f32>,
    tolerance: Option<f32>,
    eye: Option<Vec3>,
    target: Option<Vec3>,
    up: Option<Vec3>,
    fov: Option<f32>,
    viewport: Option<[u32; 2]>,
    budget: Option<usize>,
    path: Option<String>,
    bake_tolerance: Option<f32>,
    baked: Option<String>,
    near: Option<f32>,
    split: bool,
    obj: String,
}

fn vec3(flag: &str, v: Option<String>) -> Result<Vec3, String> {
    let v = v.ok_or_else(|| format!("{flag} needs X,Y,Z"))?;
    let parts: Vec<f32> = v
        .split(',')
        .map(|x| x.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("{flag}: cannot read `{v}`"))?;
    match parts.as_slice() {
        [x, y, z] => Ok(Vec3::new(*x, *y, *z)),
        _ => Err(format!("{flag}: expected X,Y,Z, got `{v}`")),
    }
}

fn value<T: std::str::FromStr>(flag: &str, v: Option<String>) -> Result<T, String> {
    let v = v.ok_or_else(|| format!("{flag} needs a value\n{USAGE}"))?;
    v.parse()
        .map_err(|_| format!("{flag}: cannot read `{v}`\n{USAGE}"))
}

fn parse_args() -> Result<Args, String> {
    let mut a = Args::default();
    let mut model = None;
    let mut obj = None;
    let mut args = std::env::args().skip(1);
    while let Some(x) = args.next() {
        match x.as_str() {
            "--object-tolerance" => a.object_tolerance = Some(value(&x, args.next())?),
            "--tolerance" => a.tolerance = Some(value(&x, args.next())?),
            "--eye" => a.eye = Some(vec3(&x, args.next())?),
            "--target" => a.target = Some(vec3(&x, args.next())?),
            "--up" => a.up = Some(vec3(&x, args.next())?),
            "--fov" => a.fov = Some(value(&x, args.next())?),
            "--viewport" => {
                let v: String = value(&x, args.next())?;
                let (w, h) = v
                    .split_once('x')
                    .ok_or_else(|| format!("--viewport: expected WxH, got `{v}`"))?;
                a.viewport = Some([
                    value("--viewport", Some(w.into()))?,
                    value("--viewport", Some(h.into()))?,
                ]);
            }
            "--budget" => a.budget = Some(value(&x, args.next())?),
            "--path" => a.path = Some(value(&x, args.next())?),
            "--bake-tolerance" => a.bake_tolerance = Some(value(&x, args.next())?),
            "--baked" => a.baked = Some(value(&x, args.next())?),
            "--split" => a.split = true,
            "--near" => a.near = Some(value(&x, args.next())?),
            "--obj" => obj = Some(value::<String>(&x, args.next())?),
            "-h" | "--help" => return Err(USAGE.to_string()),
            _ if model.is_none() && !x.starts_with("--") => model = Some(x),
            _ => return Err(format!("unexpected argument `{x}`\n{USAGE}")),
        }
    }
    a.model = model.ok_or(USAGE)?;
    a.obj = obj.ok_or(format!("--obj is required\n{USAGE}"))?;
    Ok(a)
}

/// The views to render, in order.
fn views(a: &Args, diag: f32) -> Result<Vec<View>, String> {
    if let Some(t) = a.object_tolerance {
        return Ok(vec![View::Object { tolerance: t }]);
    }
    let tol = a.tolerance.ok_or(format!(
        "give --object-tolerance or --tolerance with a camera\n{USAGE}"
    ))?;
    let viewport = a.viewport.unwrap_or([1024, 768]);
    let near = a.near.unwrap_or(0.01 * diag);
    let camera = |eye, target, up, fov: f32| {
        Camera::new(
            eye,
            target,
            up,
            Projection::Perspective { fov_y_degrees: fov },
            near,
            viewport,
        )
        .map(|camera| View::Screen {
            camera,
            tolerance_px: tol,
        })
        .map_err(|e| format!("camera: {e}"))
    };
    match &a.path {
        Some(path) => {
            let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
            let mut out = Vec::new();
            for (n, line) in text.lines().enumerate() {
                let line = line.trim();
                if line.is_empty() || line.starts_with('#') {
                    continue;
                }
                let v: Vec<f32> = line
                    .split_whitespace()
                    .map(str::parse)
                    .collect::<Result<_, _>>()
                    .map_err(|_| format!("{path}:{}: cannot read `{line}`", n + 1))?;
                let [ex, ey, ez, tx, ty, tz, ux, uy, uz, fov] = v[..] else {
                    return Err(format!("{path}:{}: expected 10 numbers", n + 1));
                };
                out.push(camera(
                    Vec3::new(ex, ey, ez),
                    Vec3::new(tx, ty, tz),
                    Vec3::new(ux, uy, uz),
                    fov,
                )?);
            }
            Ok(out)
        }
        None => {
            let need = |x: Option<Vec3>, f: &str| x.ok_or(format!("{f} is required\n{USAGE}"));
            Ok(vec![camera(
                need(a.eye, "--eye")?,
                need(a.target, "--target")?,
                a.up.unwrap_or(Vec3::Z),
                a.fov.unwrap_or(45.0),
            )?])
        }
    }
}

/// Bakes the model's hierarchy (or reads the one `--baked` names) and writes the frames.
fn run_frames(args: &Args, file: &ModelFile, views: &[View]) -> Result<(), String> {
    let bake = match &args.baked {
        Some(path) => {
            let bytes = std::fs::read(path).map_err(|e| format!("{path}: {e}"))?;
            hierarchy_file::from_bytes(&bytes, file, None).map_err(|e| format!("{path}: {e}"))?
        }
        None => {
            let settings = BakeSettings {
                tolerance: Tolerance::Relative(args.bake_tolerance.unwrap_or(2.5e-4)),
                ..BakeSettings::default()
            };
            BakedHierarchy::bake(file, &settings).map_err(|e| format!("bake: {e}"))?
        }
    };
    let mut links = Vec::new();
    let tree = bake.linked_tree(&mut links);
    let mut bits = vec![0u32; tree.bit_words()];
    let mut stack = vec![StackSlot::default(); 4096];
    let mut pool = vec![PoolSlot::default(); 1 << 16];
    let mut selection = Tessellator::from_slices(tree, &mut bits, &mut stack, &mut pool)
        .map_err(|e| format!("run time: {e}"))?;
    let mut remap = vec![0u32; selection.remap_len()];
    let (mut vertices, mut triangles) = (Vec::new(), Vec::<[u32; 3]>::new());
    let mut last = FrameStats::default();
    for (frame, view) in views.iter().enumerate() {
        let start = Instant::now();
        let (s, tolerance) = match args.budget {
            Some(n) => {
                let fit = selection
                    .update_to_budget(view, n)
                    .map_err(|e| format!("frame {frame}: {e}"))?;
                (fit.stats, fit.tolerance)
            }
            None => (
                selection
                    .update(view)
                    .map_err(|e| format!("frame {frame}: {e}"))?,
                view.tolerance(),
            ),
        };
        last = s;
        let size = selection.mesh_size();
        vertices.resize(size.vertices, Vertex::default());
        triangles.resize(size.triangles, [0; 3]);
        selection
            .write_mesh(&mut vertices, &mut triangles, &mut remap)
            .map_err(|e| format!("frame {frame}: {e}"))?;
        let ms = start.elapsed().as_secs_f64() * 1e3;
        println!(
            "{{\"frame\":{frame},\"tolerance\":{tolerance},\"triangles\":{},\"vertices\":{},\
             \"judged\":{},\"hidden\":{},\"refined\":{},\"left_over\":{},\"worst_bound\":{},\
             \"ms\":{ms:.3}}}",
            s.triangles, size.vertices, s.judged, s.hidden, s.refined, s.left_over, s.worst_bound
        );
    }
    let mesh = Mesh::of_frame(&mut selection, &file.surfaces(), last)
        .map_err(|e| format!("last frame: {e}"))?;
    write_obj(&args.obj, &mesh)
}

fn run() -> Result<(), String> {
    let args = parse_args()?;
    let read = ModelFile::read(&args.model)?;
    // The bake tolerance and the default near plane are relative to the model's own diagonal.
    let diag = read.patches().aabb().map_or(1.0, |b| b.diagonal());
    if args.split && args.baked.is_some() {
        return Err("--split bakes the split model on the fly: drop --baked".into());
    }
    let file = if args.split { read.split()?.0 } else { read };
    run_frames(&args, &file, &views(&args, diag)?)
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("tessellate: {e}");
            ExitCode::FAILURE
        }
    }
}
