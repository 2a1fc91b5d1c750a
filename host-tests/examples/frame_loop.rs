//! One view's frames in a loop, for a profiler or for timing two builds against each other:
//! the teapot at 1024x768, 1 px, eye (6,-6,4), baked at `BAKE_REL` (default 2.5e-4) of its
//! diagonal. `FRAMES` frames (default 200), each an update and an indexed write. With
//! `ORBIT=1` the eye goes around the model a degree a frame (frames are history-free, so this
//! differs from the fixed view only in the views). Prints the last frame's triangles and the
//! best and mean frame times. The bake happens before the loop and is not timed (a profile of
//! the whole run includes it).
//!
//! ```text
//! cargo run --release -p host-tests --example frame_loop
//! ORBIT=1 BAKE_REL=1e-3 cargo run --release -p host-tests --example frame_loop
//! perf record -g target/release/examples/frame_loop
//! ```

use std::time::Instant;

use host_tests::model_file::ModelFile;
use host_tests::runtime::{BakedHierarchy, VecStorage};
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
    let rel: f32 = env("BAKE_REL", 2.5e-4);
    let frames: usize = env("FRAMES", 200).max(1);
    let path = host_tests::models_dir().join("teapot.bpt");
    let file = ModelFile::read(path.to_str().expect("a UTF-8 path")).expect("a model");
    let diag = file.patches().aabb().expect("patches").diagonal();
    let orbit = std::env::var("ORBIT").is_ok_and(|v| v == "1");
    let view_at = |frame: usize| {
        let angle = if orbit {
            (frame as f32).to_radians()
        } else {
            0.0
        };
        let (s, c) = angle.sin_cos();
        let eye = Vec3::new(6.0 * c + 6.0 * s, 6.0 * s - 6.0 * c, 4.0);
        let camera = Camera::new(
            eye,
            Vec3::new(0.0, 0.0, 1.2),
            Vec3::Z,
            Projection::Perspective {
                fov_y_degrees: 40.0,
            },
            0.01 * diag,
            [1024, 768],
        )
        .expect("a valid camera");
        View::Screen {
            camera,
            tolerance_px: 1.0,
        }
    };
    {
        let settings = BakeSettings {
            tolerance: Tolerance::Relative(rel),
            ..BakeSettings::default()
        };
        let bake = BakedHierarchy::bake(&file, &settings).expect("a bisection bake");
        let tree = bake.tree();
        let mut storage = VecStorage::new(&tree, 1 << 12, 1 << 16);
        let mut selection = storage.tessellator(tree);
        let mut remap = vec![0u32; tree.vertex_count() + (1 << 16)];
        let mut vertices = vec![Vertex::default(); 1 << 20];
        let mut triangles = vec![[0u32; 3]; 1 << 21];
        let (mut best, mut total, mut count) = (f64::INFINITY, 0.0, 0);
        for k in 1..=frames {
            let view = view_at(k);
            let start = Instant::now();
            let stats = selection.update(&view).unwrap();
            selection
                .write_mesh(&mut vertices, &mut triangles, &mut remap)
                .expect("room");
            let ms = start.elapsed().as_secs_f64() * 1e3;
            best = best.min(ms);
            total += ms;
            count = stats.triangles;
        }
        println!(
            "triangles {count} best {best:.3} ms mean {:.3} ms",
            total / frames as f64
        );
    }
}
