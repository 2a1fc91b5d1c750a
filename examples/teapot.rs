//! The main job: renders a model (the Utah teapot by default) along a camera path, an orbit and
//! then a dolly from far away to very close, with the kernel's tessellator and band renderer.
//!
//! ```text
//! cargo run --release --example teapot
//! cargo run --release --example teapot -- --tolerance 0.5 --frames 48 --size 480x360
//! cargo run --release --example teapot -- --model examples/models/gumbo.bpt --budget 4000
//! ```
//!
//! Writes `out/teapot_NNN.png` per frame, `out/teapot_contact.png` (every frame, half size),
//! and `out/teapot.obj` (the last frame's mesh), and prints a table per frame: eye distance
//! from the target, tolerance in pixels, triangles, triangles judged, vertices made below the
//! bake, the bound the frame honours (pixels), and milliseconds to update the tessellation and
//! to render it (in 16-row bands, with Gouraud shading and the triangles overlaid).
//!
//! Options: `--model FILE` (`.bpt` or NURBS `.json`), `--tolerance PX` (default 1),
//! `--budget N` (fit the tolerance to at most N triangles), `--frames N` (default 24: half
//! orbit, half dolly), `--size WxH` (default 320x240), `--out DIR` (default `out`), `--name
//! NAME` (file prefix, default the model's file stem), `--flat`, `--no-wireframe`,
//! `--bake-tolerance REL` (default 2.5e-4 of the diagonal), `--cache DIR` (default
//! `target/hierarchies`).
//!
//! The model's hierarchy is baked on the first start and kept in the cache folder, keyed by
//! the model's patches and the bake settings: a second start reads it back and bakes nothing.
//! A bake that takes more than a second shows its progress.

mod common;

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use common::framebuffer::Framebuffer;
use common::hierarchy_file::cached;
use common::image::Image;
use common::model_file::{write_obj, ModelFile};
use embedded_graphics::pixelcolor::Rgb888;
use spline_tess::bake::{BakeProgress, BakeSettings, Tolerance};
use spline_tess::host::Mesh;
use spline_tess::render::{ListSlot, Renderer, Shading, Style, Wireframe};
use spline_tess::tessellator::{PoolSlot, StackSlot, Tessellator};
use spline_tess::{Camera, FrameStats, Projection, Vec3, View};

const USAGE: &str = "usage: teapot [--model FILE] [--tolerance PX] [--budget N] [--frames N] \
                     [--size WxH] [--out DIR] [--name NAME] [--flat] [--no-wireframe] \
                     [--bake-tolerance REL] [--cache DIR]";

/// Rows per band (the depth buffer holds `width * BAND` values, as on a small display).
const BAND: u32 = 16;

struct Args {
    model: String,
    tolerance: f32,
    budget: Option<usize>,
    frames: usize,
    size: [u32; 2],
    out: PathBuf,
    name: Option<String>,
    flat: bool,
    wireframe: bool,
    bake_tolerance: f32,
    cache: PathBuf,
}

fn value<T: std::str::FromStr>(flag: &str, v: Option<String>) -> Result<T, String> {
    let v = v.ok_or_else(|| format!("{flag} needs a value\n{USAGE}"))?;
    v.parse()
        .map_err(|_| format!("{flag}: cannot read `{v}`\n{USAGE}"))
}

fn parse_args() -> Result<Args, String> {
    let mut a = Args {
        model: "examples/models/teapot.bpt".into(),
        tolerance: 1.0,
        budget: None,
        frames: 24,
        size: [320, 240],
        out: PathBuf::from("out"),
        name: None,
        flat: false,
        wireframe: true,
        bake_tolerance: 2.5e-4,
        cache: PathBuf::from("target/hierarchies"),
    };
    let mut args = std::env::args().skip(1);
    while let Some(x) = args.next() {
        match x.as_str() {
            "--model" => a.model = value(&x, args.next())?,
            "--tolerance" => a.tolerance = value(&x, args.next())?,
            "--budget" => a.budget = Some(value(&x, args.next())?),
            "--frames" => a.frames = value(&x, args.next())?,
            "--size" => {
                let v: String = value(&x, args.next())?;
                let (w, h) = v
                    .split_once('x')
                    .ok_or_else(|| format!("--size: expected WxH, got `{v}`"))?;
                a.size = [value(&x, Some(w.into()))?, value(&x, Some(h.into()))?];
            }
            "--out" => a.out = PathBuf::from(value::<String>(&x, args.next())?),
            "--name" => a.name = Some(value(&x, args.next())?),
            "--flat" => a.flat = true,
            "--no-wireframe" => a.wireframe = false,
            "--bake-tolerance" => a.bake_tolerance = value(&x, args.next())?,
            "--cache" => a.cache = PathBuf::from(value::<String>(&x, args.next())?),
            "-h" | "--help" => return Err(USAGE.into()),
            _ => return Err(format!("unexpected argument `{x}`\n{USAGE}")),
        }
    }
    if a.frames == 0 || a.size[0] == 0 || a.size[1] == 0 {
        return Err(format!("--frames and --size must be positive\n{USAGE}"));
    }
    Ok(a)
}

/// Eye positions: the first half orbits the target at 2.2 radii, the second half dollies
/// from ten radii to 0.75 of one (inside the bounding sphere, close to the surface).
fn path(frames: usize, center: Vec3, radius: f32) -> Vec<(Vec3, f32)> {
    let orbit = frames.div_ceil(2);
    let dolly = frames - orbit;
    let mut out = Vec::with_capacity(frames);
    let height = 0.45;
    for k in 0..orbit {
        let a = -1.0 + core::f32::consts::TAU * k as f32 / orbit as f32;
        let d = 2.2 * radius;
        let dir = Vec3::new(a.cos(), a.sin(), height).normalize();
        out.push((center + dir * d, d));
    }
    let dir = Vec3::new(0.6, -0.8, 0.35).normalize();
    let (far, close) = (10.0 * radius, 0.75 * radius);
    for k in 0..dolly {
        let t = if dolly > 1 {
            k as f32 / (dolly - 1) as f32
        } else {
            1.0
        };
        let d = far * (close / far).powf(t);
        out.push((center + dir * d, d));
    }
    out
}

fn run() -> Result<(), String> {
    let args = parse_args()?;
    let file = ModelFile::read(&args.model)?;
    let name = args.name.clone().unwrap_or_else(|| {
        std::path::Path::new(&args.model)
            .file_stem()
            .map_or("model".into(), |s| s.to_string_lossy().into_owned())
    });
    let settings = BakeSettings {
        tolerance: Tolerance::Relative(args.bake_tolerance),
        ..BakeSettings::default()
    };
    let start = Instant::now();
    let mut shown = false;
    let mut progress = |p: BakeProgress| {
        let seconds = start.elapsed().as_secs_f64();
        if seconds > 1.0 {
            eprint!(
                "\rbaking the hierarchy (once: kept in {}): {} triangles, {seconds:.1} s",
                args.cache.display(),
                p.recorded
            );
            shown = true;
        }
    };
    let (baked, from_cache) =
        cached(&file, &settings, &args.cache, &mut progress).map_err(|e| format!("bake: {e}"))?;
    if shown {
        eprintln!();
    }
    let bake_ms = start.elapsed().as_secs_f64() * 1e3;
    let mut links = Vec::new();
    let tree = baked.linked_tree(&mut links);
    let bound = file.patches().aabb().ok_or("the model is empty")?;
    let (center, radius) = (bound.center(), 0.5 * bound.diagonal());
    let mut bits = vec![0u32; tree.bit_words()];
    let mut stack = vec![StackSlot::default(); 1 << 12];
    let mut pool = vec![PoolSlot::default(); 1 << 16];
    let mut tess = Tessellator::from_slices(tree, &mut bits, &mut stack, &mut pool)
        .map_err(|e| format!("run time: {e}"))?;
    println!(
        "# {}: {} patches {} in {bake_ms:.0} ms ({} triangles, {} bytes); {} frames at {}x{}",
        args.model,
        baked.patches.len(),
        if from_cache {
            "read from the cache"
        } else {
            "baked"
        },
        baked.nodes.len(),
        baked.bytes(),
        args.frames,
        args.size[0],
        args.size[1]
    );
    println!(
        "{:>5} {:>9} {:>9} {:>9} {:>8} {:>8} {:>8} {:>9} {:>9} {:>7}",
        "frame",
        "distance",
        "tol_px",
        "triangles",
        "judged",
        "refined",
        "bound",
        "update_ms",
        "render_ms",
        "Mtri/s"
    );
    let style = Style {
        shading: if args.flat {
            Shading::Flat
        } else {
            Shading::Gouraud
        },
        color: Rgb888::new(222, 196, 150),
        wireframe: args.wireframe.then_some(Wireframe {
            color: Rgb888::new(60, 40, 30),
            half_width: 0.35,
        }),
        background: Some(Rgb888::new(24, 28, 40)),
        ..Style::default()
    };
    let [w, h] = args.size;
    let mut depth = vec![0u16; (w * BAND) as usize];
    // Room for the frames' projected triangles (a list uses at most 65,535 slots, about 36,000
    // triangles), so that each is projected once per frame.
    let mut list = vec![ListSlot::default(); 1 << 16];
    let mut thumbnails = Vec::new();
    let mut last = FrameStats::default();
    for (k, (eye, distance)) in path(args.frames, center, radius).into_iter().enumerate() {
        let camera = Camera::new(
            eye,
            center,
            Vec3::Z,
            Projection::Perspective {
                fov_y_degrees: 40.0,
            },
            0.01 * radius,
            args.size,
        )
        .map_err(|e| format!("frame {k}: camera: {e}"))?;
        let view = View::Screen {
            camera,
            tolerance_px: args.tolerance,
        };
        let start = Instant::now();
        let (stats, tolerance) = match args.budget {
            Some(n) => {
                let fit = tess
                    .update_to_budget(&view, n)
                    .map_err(|e| format!("frame {k}: {e}"))?;
                (fit.stats, fit.tolerance)
            }
            None => (
                tess.update(&view).map_err(|e| format!("frame {k}: {e}"))?,
                args.tolerance,
            ),
        };
        let update_ms = start.elapsed().as_secs_f64() * 1e3;
        last = stats;
        let mut image = Image::new(w, h, Rgb888::new(0, 0, 0));
        let start = Instant::now();
        let mut target = Framebuffer::new(&mut image.pixels, w, h).ok_or("framebuffer")?;
        Renderer::with_triangle_list(&mut depth, &mut list)
            .draw(&tess, &camera, &style, &mut target)
            .map_err(|e| format!("frame {k}: {e}"))?;
        let render_ms = start.elapsed().as_secs_f64() * 1e3;
        // Triangles per second of the whole frame, update and render.
        let mtri_s = stats.triangles as f64 / (update_ms + render_ms) / 1e3;
        println!(
            "{k:>5} {distance:>9.3} {tolerance:>9.3} {:>9} {:>8} {:>8} {:>8.3} {update_ms:>9.2} {render_ms:>9.2} {mtri_s:>7.2}",
            stats.triangles, stats.judged, stats.refined, stats.worst_bound
        );
        image.write_png(&args.out.join(format!("{name}_{k:03}.png")))?;
        thumbnails.push(image.shrink(2));
    }
    let sheet =
        Image::contact_sheet(&thumbnails, 6, 4, Rgb888::new(8, 8, 12)).ok_or("no frames")?;
    sheet.write_png(&args.out.join(format!("{name}_contact.png")))?;
    let mesh = Mesh::of_frame(&mut tess, &file.surfaces(), last)
        .map_err(|e| format!("last frame: {e}"))?;
    let obj = args.out.join(format!("{name}.obj"));
    write_obj(&obj.to_string_lossy(), &mesh)?;
    println!(
        "# wrote {}/{name}_000.png .. {name}_{:03}.png, {name}_contact.png, {name}.obj",
        args.out.display(),
        args.frames - 1
    );
    Ok(())
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("teapot: {e}");
            ExitCode::FAILURE
        }
    }
}
