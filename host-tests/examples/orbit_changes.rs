//! What an orbit step changes in the bisection run time's mesh: the work a frame-to-frame
//! update would have to do, beside what the top-down search does every frame.
//!
//! ```text
//! cargo run --release -p host-tests --example orbit_changes
//! ```
//!
//! The teapot's hierarchy at `fw_teapot`'s bake (2e-3 of the diagonal), its frames at 240x240
//! and 1 px, the eye orbiting the target about the vertical through it, at `fw_teapot`'s
//! first eye's radius and height, 48 steps of each size from there. Per step size: the
//! triangles of a frame, how many of them are not in the frame before (added) and how many of
//! the frame before are gone (removed), and how many triangles the search judges. Prints a
//! Markdown table.

use std::collections::HashSet;

use host_tests::model_file::ModelFile;
use host_tests::runtime::triangle_set;
use host_tests::runtime::{streamed, BakedHierarchy, VecStorage};
use spline_tess::bake::BakeSettings;
use spline_tess::bake::Tolerance;
use spline_tess::{Camera, Projection, Vec3, View};

/// `fw_teapot`'s bake (`examples/common/fw_bisect_frames.rs`).
const BAKE: BakeSettings = BakeSettings {
    tolerance: Tolerance::Relative(2e-3),
    max_depth: 24,
    max_cell_level: spline_tess::tessellator::MAX_CELL_LEVEL,
};

/// Steps per step size.
const STEPS: usize = 48;

fn main() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/models/teapot.bpt");
    let file = ModelFile::read(path).expect("the teapot");
    let baked = BakedHierarchy::bake(&file, &BAKE).expect("a bisection bake");
    let tree = baked.tree();
    let mut storage = VecStorage::new(&tree, 1 << 12, 0);
    let mut selection = storage.tessellator(tree);
    // `fw_teapot`'s first frame: eye (9, -12, 7), target (0, 0, 1.5).
    let target = Vec3::new(0.0, 0.0, 1.5);
    let (radius, height, start) = (15.0f32, 7.0f32, (-12.0f32).atan2(9.0));
    println!(
        "| step | frames | triangles (mean) | added per step (mean / max) | removed per step (mean / max) | judged per frame (mean) |"
    );
    println!("|---|---|---|---|---|---|");
    for degrees in [0.25f32, 0.5, 1.0, 2.0, 4.0] {
        let mut last: Option<HashSet<[(u32, u32, u32); 3]>> = None;
        let (mut triangles, mut judged) = (0usize, 0usize);
        let (mut added, mut removed) = (Vec::new(), Vec::new());
        for k in 0..=STEPS {
            let angle = start + (k as f32 * degrees).to_radians();
            let eye = Vec3::new(radius * angle.cos(), radius * angle.sin(), height);
            let camera = Camera::new(
                eye,
                target,
                Vec3::Z,
                Projection::Perspective {
                    fov_y_degrees: 40.0,
                },
                0.05,
                [240, 240],
            )
            .expect("a camera");
            let stats = selection
                .update(&View::Screen {
                    camera,
                    tolerance_px: 1.0,
                })
                .unwrap();
            let mesh: HashSet<_> = triangle_set(&streamed(&selection)).into_iter().collect();
            if let Some(before) = &last {
                added.push(mesh.difference(before).count());
                removed.push(before.difference(&mesh).count());
                triangles += stats.triangles;
                judged += stats.judged;
            }
            last = Some(mesh);
        }
        let mean = |v: &[usize]| v.iter().sum::<usize>() as f64 / v.len() as f64;
        let most = |v: &[usize]| v.iter().copied().max().unwrap_or(0);
        println!(
            "| {degrees}° | {STEPS} | {:.0} | {:.1} / {} | {:.1} / {} | {:.0} |",
            triangles as f64 / STEPS as f64,
            mean(&added),
            most(&added),
            mean(&removed),
            most(&removed),
            judged as f64 / STEPS as f64,
        );
    }
}
