//! Evaluation speed on the host: the kernel beside curvo's `point_at`, same patches, same
//! parameters, one run.
//!
//! ```text
//! cargo run --release -p host-tests --example eval_speed
//! ```
//!
//! Two sets: the 32 bicubic patches of the Utah teapot, and 32 random degree-7 x 7 rational
//! patches (weights 10^[-1, 1], fixed seed). Each is evaluated on a 32 x 32 grid per patch; a
//! figure is the best of 7 repetitions, in nanoseconds per point.

use std::hint::black_box;
use std::time::Instant;

use curvo::prelude::NurbsSurface3D;
use host_tests::peers::{self, bezier_knots};
use host_tests::{models_dir, KernelBpt, Rng};
use spline_tess::BezierPatch;

const GRID: usize = 32;
const REPEATS: usize = 7;

struct Net {
    du: usize,
    dv: usize,
    points: Vec<[f32; 3]>,
    weights: Vec<f32>,
}

fn params() -> Vec<(f32, f32)> {
    (0..GRID)
        .flat_map(|i| {
            (0..GRID).map(move |j| (i as f32 / (GRID - 1) as f32, j as f32 / (GRID - 1) as f32))
        })
        .collect()
}

/// Best time over the repeats, in ns per point.
fn best(points: usize, mut run: impl FnMut() -> f64) -> f64 {
    let mut best = f64::INFINITY;
    let mut sink = 0.0;
    for _ in 0..REPEATS {
        let t = Instant::now();
        sink += run();
        best = best.min(t.elapsed().as_nanos() as f64 / points as f64);
    }
    black_box(sink);
    best
}

fn curvo_of(n: &Net) -> NurbsSurface3D<f64> {
    let homogeneous = |i: usize, j: usize| {
        let k = i * (n.dv + 1) + j;
        let (p, w) = (n.points[k], n.weights[k] as f64);
        [p[0] as f64 * w, p[1] as f64 * w, p[2] as f64 * w, w]
    };
    let (ku, kv) = (bezier_knots(n.du), bezier_knots(n.dv));
    peers::Net {
        du: n.du,
        dv: n.dv,
        ku: &ku,
        kv: &kv,
        at: &homogeneous,
    }
    .curvo()
}

fn measure(label: &str, nets: &[Net]) {
    let rational = nets.iter().any(|n| n.weights.iter().any(|&w| w != 1.0));
    let kernel: Vec<BezierPatch<'_>> = nets
        .iter()
        .map(|n| {
            if rational {
                BezierPatch::new_rational(n.du, n.dv, &n.points, &n.weights).unwrap()
            } else {
                BezierPatch::new(n.du, n.dv, &n.points).unwrap()
            }
        })
        .collect();
    let curvo: Vec<NurbsSurface3D<f64>> = nets.iter().map(curvo_of).collect();
    let uv = params();
    let count = uv.len() * nets.len();
    let position = best(count, || {
        let mut s = 0.0;
        for p in &kernel {
            for &(u, v) in &uv {
                s += black_box(p).position(black_box(u), black_box(v)).x as f64;
            }
        }
        s
    });
    let evaluate = best(count, || {
        let mut s = 0.0;
        for p in &kernel {
            for &(u, v) in &uv {
                s += black_box(p).evaluate(black_box(u), black_box(v)).normal.x as f64;
            }
        }
        s
    });
    let curvo_point = best(count, || {
        let mut s = 0.0;
        for c in &curvo {
            for &(u, v) in &uv {
                s += black_box(c)
                    .point_at(black_box(u as f64), black_box(v as f64))
                    .x;
            }
        }
        s
    });
    let curvo_normal = best(count, || {
        let mut s = 0.0;
        for c in &curvo {
            for &(u, v) in &uv {
                s += black_box(c)
                    .normal_at(black_box(u as f64), black_box(v as f64))
                    .x;
            }
        }
        s
    });
    println!(
        "| {label} | {position:.0} | {evaluate:.0} | {curvo_point:.0} | {curvo_normal:.0} | {:.1}x |",
        curvo_point / position
    );
}

fn main() {
    let text = std::fs::read_to_string(models_dir().join("teapot.bpt")).unwrap();
    let teapot = KernelBpt::parse(&text);
    let bicubic: Vec<Net> = teapot
        .set()
        .iter()
        .map(|p| Net {
            du: p.degree_u(),
            dv: p.degree_v(),
            points: p.points().to_vec(),
            weights: vec![1.0; p.points().len()],
        })
        .collect();
    let mut rng = Rng::new(42);
    let degree7: Vec<Net> = (0..32)
        .map(|_| Net {
            du: 7,
            dv: 7,
            points: (0..64)
                .map(|_| [0; 3].map(|_| (rng.unit() * 20.0 - 10.0) as f32))
                .collect(),
            weights: (0..64)
                .map(|_| 10f64.powf(rng.unit() * 2.0 - 1.0) as f32)
                .collect(),
        })
        .collect();
    println!("| patches | kernel `position` (ns/point) | kernel `evaluate` with normal (ns/point) | curvo `point_at` (ns/point) | curvo `normal_at` (ns/point) | curvo `point_at` / kernel `position` |");
    println!("|---|---|---|---|---|---|");
    measure("teapot, 32 bicubic polynomial", &bicubic);
    measure("32 random degree 7 x 7 rational", &degree7);
}
