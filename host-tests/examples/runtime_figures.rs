//! Run-time figures on the host: full tessellation of the teapot and Gumbo at 1 px and 0.5 px
//! on a 1024x768 view, and one frame after a 1-degree orbit step against a full rebuild.
//! Prints a Markdown table.
//!
//! ```text
//! cargo run --release -p host-tests --example runtime_figures
//! ```
//!
//! Each model is baked once (relative tolerance 2.5e-4, caps 256 per curve and 4096 per patch
//! interior) before measuring. *Full* builds a tessellator over preallocated storage, updates it
//! to the view and writes the indexed mesh; *step* moves an existing tessellator between two
//! views 1 degree apart on an orbit (update and write); *update* columns leave the write out.
//! Every time is the median of repeated runs in this process, on one core.

use std::time::Instant;

use host_tests::model_file::ModelFile;
use host_tests::runtime::RuntimeStorage;
use spline_tess::bake::BakedModel;
use spline_tess::tessellator::Settings;
use spline_tess::{Camera, Projection, Vec3, Vertex, View};

const VIEWPORT: [u32; 2] = [1024, 768];

/// Runs of a full rebuild and of a step whose median is reported.
const FULL_RUNS: usize = 9;
const STEP_RUNS: usize = 31;

fn view(center: Vec3, diag: f32, degrees: f32, tol: f32) -> View {
    let a = degrees.to_radians();
    let eye = center + Vec3::new(a.cos(), a.sin(), 0.45).normalize() * (1.3 * diag);
    let camera = Camera::new(
        eye,
        center,
        Vec3::Z,
        Projection::Perspective {
            fov_y_degrees: 40.0,
        },
        0.01 * diag,
        VIEWPORT,
    )
    .expect("a valid camera");
    View::Screen {
        camera,
        tolerance_px: tol,
    }
}

/// Median of `runs` timings of `f`, in milliseconds.
fn median_ms(runs: usize, mut f: impl FnMut()) -> f64 {
    let mut t: Vec<f64> = (0..runs)
        .map(|_| {
            let start = Instant::now();
            f();
            start.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    t.sort_by(f64::total_cmp);
    t[runs / 2]
}

fn main() {
    println!(
        "| model | tolerance | triangles | full (ms) | Mtri/s | full update alone (ms) | \
         1-degree step, update + write (ms) | step / full | step update alone (ms) |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    for model in ["teapot.bpt", "gumbo.bpt"] {
        let path = host_tests::models_dir().join(model);
        let file = ModelFile::read(path.to_str().expect("a UTF-8 path")).expect("a model");
        let bytes = file.bake_relative(2.5e-4).expect("a bake");
        let baked = BakedModel::from_bytes(&bytes).expect("a fresh bake reads back");
        let patches = file.patches();
        let aabb = patches.aabb().expect("patches");
        let (center, diag) = (aabb.center(), aabb.diagonal());
        let settings = Settings::default();
        let mut storage = RuntimeStorage::new(&baked, &settings);
        let mut vertices = vec![Vertex::default(); 1 << 21];
        let mut triangles = vec![[0u32; 3]; 1 << 22];
        let name = model.trim_end_matches(".bpt");
        for tol in [1.0f32, 0.5] {
            let v = view(center, diag, 30.0, tol);
            let count = storage
                .tessellator(patches, baked, settings)
                .update(&v)
                .expect("an update")
                .triangles;
            let full = median_ms(FULL_RUNS, || {
                let mut t = storage.tessellator(patches, baked, settings);
                t.update(&v).expect("an update");
                t.write_mesh(&mut vertices, &mut triangles).expect("room");
            });
            let full_update = median_ms(FULL_RUNS, || {
                let mut t = storage.tessellator(patches, baked, settings);
                t.update(&v).expect("an update");
            });
            let mtri = count as f64 / full / 1e3;
            let (a, b) = (view(center, diag, 30.0, tol), view(center, diag, 31.0, tol));
            let mut t = storage.tessellator(patches, baked, settings);
            t.update(&a).expect("an update");
            let mut flip = false;
            let step = median_ms(STEP_RUNS, || {
                flip = !flip;
                t.update(if flip { &b } else { &a }).expect("an update");
                t.write_mesh(&mut vertices, &mut triangles).expect("room");
            });
            let step_update = median_ms(STEP_RUNS, || {
                flip = !flip;
                t.update(if flip { &b } else { &a }).expect("an update");
            });
            println!(
                "| {name} | {tol} px | {count} | {full:.1} | {mtri:.2} | {full_update:.1} | \
                 {step:.2} | {:.2} | {step_update:.2} |",
                step / full
            );
        }
    }
}
