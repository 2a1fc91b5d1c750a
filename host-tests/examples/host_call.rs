//! The one call a host program makes for a frame, timed: `host::Baked::tessellate` (its
//! storage sized and allocated, the update on all cores, the mesh written out with a face per
//! triangle), on the host's bake (`host::BAKE`) of the teapot at 1024x768, 1 px, eye `EYE`
//! (default `6,-6,4`; `2.2,-1.5,2.6` is the close-up below the bake) looking at (0, 0, 1.2).
//! Prints the triangles and the best and mean of `FRAMES` calls (default 200). The bake is
//! not timed. `frame_loop` times the kernel alone, in storage it keeps.
//!
//! ```text
//! cargo run --release -p host-tests --example host_call
//! EYE=2.2,-1.5,2.6 cargo run --release -p host-tests --example host_call
//! ```

use std::time::Instant;

use spline_tess::host::{self, Surfaces};
use spline_tess::{Camera, Projection, Vec3, View};

fn main() {
    let frames: usize = std::env::var("FRAMES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(200)
        .max(1);
    let eye: Vec<f32> = std::env::var("EYE")
        .unwrap_or_else(|_| "6,-6,4".into())
        .split(',')
        .map(|x| x.trim().parse().expect("EYE is x,y,z"))
        .collect();
    let [x, y, z] = eye[..] else {
        panic!("EYE is x,y,z");
    };
    let path = host_tests::models_dir().join("teapot.bpt");
    let teapot = Surfaces::read(path.to_str().expect("a UTF-8 path")).expect("the teapot");
    let baked = teapot.bake(&host::BAKE).expect("a bake");
    let camera = Camera::new(
        Vec3::new(x, y, z),
        Vec3::new(0.0, 0.0, 1.2),
        Vec3::Z,
        Projection::Perspective {
            fov_y_degrees: 40.0,
        },
        0.06,
        [1024, 768],
    )
    .expect("a valid camera");
    let view = View::Screen {
        camera,
        tolerance_px: 1.0,
    };
    let (mut best, mut total, mut triangles) = (f64::INFINITY, 0.0, 0);
    for _ in 0..frames {
        let start = Instant::now();
        let mesh = baked.tessellate(&view).expect("a frame");
        let ms = start.elapsed().as_secs_f64() * 1e3;
        best = best.min(ms);
        total += ms;
        triangles = mesh.triangles.len();
    }
    println!(
        "triangles {triangles} best {best:.3} ms mean {:.3} ms",
        total / frames as f64
    );
}
