//! spline-tess in a window: a model (the Utah teapot by default) tessellated and drawn by the
//! kernel's band renderer on `embedded-graphics-simulator`, as a firmware draws on its display:
//! 16-row bands, each pushed once.
//!
//! ```sh
//! cd examples/simulator && cargo run --release [-- MODEL.bpt|MODEL.json] [--size WxH]
//! ```
//!
//! - Drag with the mouse to orbit; the wheel zooms.
//! - `+` and `-` halve and double the tolerance (pixels); `s` switches Gouraud and flat
//!   shading; `w` the wireframe; `q` or Escape quits.
//! - The top rows show the frame's triangles, its tolerance and the bound it keeps, and its
//!   cost (update and render, ms).
//!
//! Headless (CI): with `EG_SIMULATOR_DUMP=FILE.png` it draws `--frames N` frames of a scripted
//! orbit (default 4) and the simulator writes the last to the file and exits; then
//! `--check FILE.png` draws the same frames into a framebuffer of its own, through the same
//! renderer, and compares every pixel with the file. Headless frames show `headless` for
//! their cost, so that their pixels depend on the view alone.

use std::process::ExitCode;
use std::time::Instant;

use embedded_graphics::mono_font::ascii::FONT_6X10;
use embedded_graphics::mono_font::MonoTextStyle;
use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::prelude::*;
use embedded_graphics::text::{Baseline, Text};
use embedded_graphics_simulator::{
    OutputSettingsBuilder, SimulatorDisplay, SimulatorEvent, Window,
};
use spline_tess::host::{Baked, Surfaces};
use spline_tess::render::{ListSlot, Renderer, Shading, Style, Wireframe};
use spline_tess::tessellator::{PoolSlot, StackSlot};
use spline_tess::{Camera, FrameStats, Projection, Tessellator, Vec3, View};

/// Rows of a band: the firmware demo's.
const BAND_ROWS: u32 = 16;
/// Rows at the top for the frame's figures.
const TEXT_ROWS: u32 = 24;

/// Where the camera is: around the model's centre, at a distance, a longitude and a latitude.
#[derive(Clone, Copy, Debug)]
struct Orbit {
    distance: f32,
    longitude: f32,
    latitude: f32,
}

impl Orbit {
    fn eye(&self, center: Vec3) -> Vec3 {
        let (sa, ca) = self.longitude.sin_cos();
        let (se, ce) = self.latitude.sin_cos();
        center + Vec3::new(ca * ce, sa * ce, se) * self.distance
    }
}

/// What the keys change.
#[derive(Clone, Copy, Debug)]
struct Controls {
    orbit: Orbit,
    tolerance: f32,
    shading: Shading,
    wireframe: bool,
}

struct Args {
    model: String,
    size: [u32; 2],
    frames: usize,
    check: Option<String>,
}

fn parse_args() -> Result<Args, String> {
    let mut args = Args {
        model: concat!(env!("CARGO_MANIFEST_DIR"), "/../models/teapot.bpt").to_string(),
        size: [320, 240],
        frames: 4,
        check: None,
    };
    let mut it = std::env::args().skip(1);
    while let Some(a) = it.next() {
        let mut value = || it.next().ok_or(format!("{a} needs a value"));
        match a.as_str() {
            "--size" => {
                let v = value()?;
                let (w, h) = v.split_once('x').ok_or(format!("--size: WxH, not {v}"))?;
                let parse = |s: &str| s.parse::<u32>().map_err(|_| format!("--size: {v}"));
                args.size = [parse(w)?, parse(h)?];
            }
            "--frames" => {
                args.frames = value()?.parse().map_err(|_| "--frames: a count")?;
            }
            "--check" => args.check = Some(value()?),
            _ if !a.starts_with("--") => args.model = a,
            _ => return Err(format!("unknown argument {a}")),
        }
    }
    Ok(args)
}

/// The model: its bake, and where it is.
struct Model {
    baked: Baked,
    center: Vec3,
    radius: f32,
}

impl Model {
    fn read(model: &str) -> Result<Model, String> {
        let surfaces = Surfaces::read(model).map_err(|e| format!("{model}: {e}"))?;
        let baked = surfaces
            .bake(&spline_tess::host::BAKE)
            .map_err(|e| format!("bake: {e}"))?;
        let bound = surfaces.patches().aabb().ok_or("the model is empty")?;
        Ok(Model {
            baked,
            center: bound.center(),
            radius: 0.5 * bound.diagonal(),
        })
    }
}

/// The tessellator's storage (it keeps the tessellator from frame to frame).
struct Storage {
    bits: Vec<u32>,
    stack: Vec<StackSlot>,
    pool: Vec<PoolSlot>,
}

/// Everything a frame is drawn with: the model, its tessellator (kept from frame to frame:
/// the hierarchy is checked once), and the renderer's storage.
struct Scene<'m, 's> {
    center: Vec3,
    radius: f32,
    tess: Tessellator<'m, 's>,
    depth: Vec<u16>,
    list: Vec<ListSlot>,
    colors: Vec<Rgb888>,
}

impl<'m, 's> Scene<'m, 's> {
    fn new(model: &'m Model, storage: &'s mut Storage, width: u32) -> Result<Self, String> {
        let tree = model.baked.hierarchy().map_err(|e| e.to_string())?;
        storage.bits = vec![0; tree.bit_words()];
        let tess = Tessellator::from_slices(
            tree,
            &mut storage.bits,
            &mut storage.stack,
            &mut storage.pool,
        )
        .map_err(|e| e.to_string())?;
        Ok(Scene {
            center: model.center,
            radius: model.radius,
            tess,
            depth: vec![0; (width * BAND_ROWS) as usize],
            list: vec![ListSlot::default(); 1 << 16],
            colors: vec![Rgb888::BLACK; (width * BAND_ROWS) as usize],
        })
    }

    /// Draws the frame of `controls` onto `target` (its top rows left for the figures):
    /// the frame's stats and its update and render times.
    fn draw<D>(
        &mut self,
        controls: &Controls,
        target: &mut D,
    ) -> Result<(FrameStats, f64, f64), String>
    where
        D: DrawTarget<Color = Rgb888>,
    {
        let size = target.bounding_box().size;
        let [w, h] = [size.width, size.height - TEXT_ROWS];
        let camera = Camera::new(
            controls.orbit.eye(self.center),
            self.center,
            Vec3::Z,
            Projection::Perspective {
                fov_y_degrees: 40.0,
            },
            0.01 * self.radius,
            [w, h],
        )
        .map_err(|e| format!("camera: {e}"))?;
        let view = View::Screen {
            camera,
            tolerance_px: controls.tolerance,
        };
        let start = Instant::now();
        let stats = self.tess.update(&view).map_err(|e| e.to_string())?;
        let update_ms = start.elapsed().as_secs_f64() * 1e3;
        let style = Style {
            shading: controls.shading,
            wireframe: controls.wireframe.then_some(Wireframe {
                color: Rgb888::new(60, 40, 30),
                half_width: 0.35,
            }),
            background: Some(Rgb888::new(24, 28, 40)),
            ..Style::default()
        };
        let start = Instant::now();
        let mut below = target.translated(Point::new(0, TEXT_ROWS as i32));
        Renderer::with_triangle_list(&mut self.depth, &mut self.list)
            .draw_bands(&self.tess, &camera, &style, &mut self.colors, &mut below)
            .map_err(|_| "the display failed".to_string())?;
        let render_ms = start.elapsed().as_secs_f64() * 1e3;
        Ok((stats, update_ms, render_ms))
    }
}

/// The figures' rows: triangles, tolerance and bound; the cost (or `headless`).
fn figures<D>(
    target: &mut D,
    controls: &Controls,
    stats: &FrameStats,
    cost: Option<(f64, f64)>,
) -> Result<(), D::Error>
where
    D: DrawTarget<Color = Rgb888>,
{
    let width = target.bounding_box().size.width;
    target.fill_solid(
        &embedded_graphics::primitives::Rectangle::new(Point::zero(), Size::new(width, TEXT_ROWS)),
        Rgb888::BLACK,
    )?;
    let style = MonoTextStyle::new(&FONT_6X10, Rgb888::new(220, 220, 200));
    let first = format!(
        "{} triangles  tol {:.2} px  bound {:.2} px",
        stats.triangles, controls.tolerance, stats.worst_bound
    );
    let second = match cost {
        Some((u, r)) => format!(
            "update {u:.2} ms  render {r:.2} ms  judged {}",
            stats.judged
        ),
        None => format!("headless  judged {}", stats.judged),
    };
    Text::with_baseline(&first, Point::new(2, 1), style, Baseline::Top).draw(target)?;
    Text::with_baseline(&second, Point::new(2, 12), style, Baseline::Top).draw(target)?;
    Ok(())
}

/// The scripted orbit's controls at frame `k`: 30 degrees a frame at 1 px.
fn scripted(start: Orbit, k: usize) -> Controls {
    Controls {
        orbit: Orbit {
            longitude: start.longitude + k as f32 * 30f32.to_radians(),
            ..start
        },
        tolerance: 1.0,
        shading: Shading::Gouraud,
        wireframe: true,
    }
}

/// Draws the first `frames` frames of the scripted orbit from `start` onto `target`, the
/// last with its figures (`headless` for its cost): the last frame's stats.
fn scripted_frames<D>(
    scene: &mut Scene<'_, '_>,
    frames: usize,
    start: Orbit,
    target: &mut D,
) -> Result<FrameStats, String>
where
    D: DrawTarget<Color = Rgb888>,
{
    let mut last = None;
    for k in 0..frames {
        let controls = scripted(start, k);
        let (stats, ..) = scene.draw(&controls, target)?;
        last = Some((controls, stats));
    }
    let (controls, stats) = last.ok_or("no frame")?;
    figures(target, &controls, &stats, None).map_err(|_| "text")?;
    Ok(stats)
}

/// An `Rgb888` framebuffer, the check's own target.
struct Framebuffer {
    size: Size,
    pixels: Vec<Rgb888>,
}

impl OriginDimensions for Framebuffer {
    fn size(&self) -> Size {
        self.size
    }
}

impl DrawTarget for Framebuffer {
    type Color = Rgb888;
    type Error = core::convert::Infallible;
    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb888>>>(
        &mut self,
        pixels: I,
    ) -> Result<(), Self::Error> {
        for Pixel(p, c) in pixels {
            if p.x >= 0
                && p.y >= 0
                && (p.x as u32) < self.size.width
                && (p.y as u32) < self.size.height
            {
                self.pixels[(p.y as u32 * self.size.width + p.x as u32) as usize] = c;
            }
        }
        Ok(())
    }
}

/// Compares the frames drawn headless with the PNG at `path`, pixel by pixel.
fn check(scene: &mut Scene<'_, '_>, args: &Args, start: Orbit) -> Result<(), String> {
    let [w, h] = args.size;
    let mut own = Framebuffer {
        size: Size::new(w, h),
        pixels: vec![Rgb888::BLACK; (w * h) as usize],
    };
    let stats = scripted_frames(scene, args.frames, start, &mut own)?;
    let path = args.check.as_deref().unwrap_or_default();
    let file = std::fs::File::open(path).map_err(|e| format!("{path}: {e}"))?;
    let mut reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .map_err(|e| format!("{path}: {e}"))?;
    let mut buffer = vec![0; reader.output_buffer_size().ok_or("PNG size")?];
    let info = reader
        .next_frame(&mut buffer)
        .map_err(|e| format!("{path}: {e}"))?;
    if [info.width, info.height] != [w, h] || info.color_type != png::ColorType::Rgb {
        return Err(format!(
            "{path}: {}x{} {:?}, not {w}x{h} RGB",
            info.width, info.height, info.color_type
        ));
    }
    let differ = own
        .pixels
        .iter()
        .zip(buffer.chunks_exact(3))
        .filter(|(p, b)| [p.r(), p.g(), p.b()] != [b[0], b[1], b[2]])
        .count();
    if differ > 0 {
        return Err(format!(
            "{path}: {differ} of {} pixels differ from the renderer's own",
            w * h
        ));
    }
    println!(
        "simulator: {path} matches the renderer's own frame {} ({} triangles, bound {:.3} px, {} pixels)",
        args.frames - 1,
        stats.triangles,
        stats.worst_bound,
        w * h
    );
    Ok(())
}

fn run() -> Result<(), String> {
    let args = parse_args()?;
    let [w, h] = args.size;
    if w == 0 || h <= TEXT_ROWS || w > 4096 || h > 4096 {
        return Err(format!(
            "--size {w}x{h}: from 1x{} to 4096x4096",
            TEXT_ROWS + 1
        ));
    }
    let model = Model::read(&args.model)?;
    let mut storage = Storage {
        bits: Vec::new(),
        stack: vec![StackSlot::default(); 4096],
        pool: vec![PoolSlot::default(); 1 << 16],
    };
    let mut scene = Scene::new(&model, &mut storage, w)?;
    let start = Orbit {
        distance: 2.4 * scene.radius,
        longitude: -45f32.to_radians(),
        latitude: 25f32.to_radians(),
    };
    if args.check.is_some() {
        return check(&mut scene, &args, start);
    }
    // (The simulator writes or checks the first frame and exits under any of these.)
    let headless = [
        "EG_SIMULATOR_DUMP",
        "EG_SIMULATOR_DUMP_RAW",
        "EG_SIMULATOR_CHECK",
        "EG_SIMULATOR_CHECK_RAW",
    ]
    .iter()
    .any(|v| std::env::var_os(v).is_some());
    let mut display = SimulatorDisplay::<Rgb888>::new(Size::new(w, h));
    let mut window = Window::new("spline-tess", &OutputSettingsBuilder::new().build());
    if headless {
        // The scripted frames; the simulator writes the last one and exits.
        scripted_frames(&mut scene, args.frames, start, &mut display)?;
        window.update(&display);
        return Err("EG_SIMULATOR_* is set, but the simulator did not exit".into());
    }
    let mut controls = Controls {
        orbit: start,
        tolerance: 1.0,
        shading: Shading::Gouraud,
        wireframe: true,
    };
    let mut drag: Option<Point> = None;
    let mut dirty = true;
    loop {
        if dirty {
            let (stats, u, r) = scene.draw(&controls, &mut display)?;
            figures(&mut display, &controls, &stats, Some((u, r))).map_err(|_| "text")?;
            dirty = false;
        } else {
            // Nothing moved: wait for the next events rather than spin.
            std::thread::sleep(std::time::Duration::from_millis(10));
        }
        window.update(&display);
        for event in window.events() {
            use embedded_graphics_simulator::sdl2::{Keycode, MouseButton};
            match event {
                SimulatorEvent::Quit => return Ok(()),
                SimulatorEvent::KeyDown { keycode, .. } => {
                    match keycode {
                        Keycode::Q | Keycode::Escape => return Ok(()),
                        Keycode::Plus | Keycode::KpPlus | Keycode::Equals => {
                            controls.tolerance = (controls.tolerance * 0.5).max(0.125)
                        }
                        Keycode::Minus | Keycode::KpMinus => {
                            controls.tolerance = (controls.tolerance * 2.0).min(16.0)
                        }
                        Keycode::S => {
                            controls.shading = match controls.shading {
                                Shading::Gouraud => Shading::Flat,
                                Shading::Flat => Shading::Gouraud,
                            }
                        }
                        Keycode::W => controls.wireframe = !controls.wireframe,
                        _ => continue,
                    }
                    dirty = true;
                }
                SimulatorEvent::MouseButtonDown {
                    mouse_btn: MouseButton::Left,
                    point,
                } => drag = Some(point),
                SimulatorEvent::MouseButtonUp { .. } => drag = None,
                SimulatorEvent::MouseMove { point } => {
                    if let Some(from) = drag {
                        let d = point - from;
                        controls.orbit.longitude -= d.x as f32 * 0.01;
                        controls.orbit.latitude =
                            (controls.orbit.latitude + d.y as f32 * 0.01).clamp(-1.5, 1.5);
                        drag = Some(point);
                        dirty = true;
                    }
                }
                SimulatorEvent::MouseWheel { scroll_delta, .. } => {
                    let zoom = 0.9f32.powi(scroll_delta.y);
                    controls.orbit.distance = (controls.orbit.distance * zoom)
                        .clamp(1.05 * scene.radius, 50.0 * scene.radius);
                    dirty = true;
                }
                _ => {}
            }
        }
    }
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("simulator: {e}");
            ExitCode::FAILURE
        }
    }
}
