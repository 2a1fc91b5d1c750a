//! Screen bounds cover the deviation they bound. The oracle's (`host_tests::screen_bound`):
//! on every patch of the teapot, for the error-control views, each triangle of a uniform
//! 4 x 4 split has a directional bound at least its deviation on screen sampled at 24 steps
//! per side, and at most its isotropic bound. The kernel's (`triangle_screen_bound`): the
//! same check on more models and views, below.

use host_tests::model_file::ModelFile;
use host_tests::reference::RefPatch;
use host_tests::screen::{triangle_deviation, Measure, Meter, ERROR_VIEWS};
use host_tests::screen_bound::screen_bound;

#[test]
fn screen_bounds_cover_the_sampled_deviation() {
    let path = host_tests::models_dir().join("teapot.bpt");
    let file = ModelFile::read(path.to_str().expect("a UTF-8 path")).expect("the teapot");
    let patches = file.patches();
    let diag = patches.aabb().expect("patches").diagonal();
    let refs: Vec<RefPatch> = patches.iter().map(|p| RefPatch::from_kernel(&p)).collect();
    let (mut checked, mut tightest) = (0, f64::INFINITY);
    for view in ERROR_VIEWS.iter().filter(|v| v.model == "teapot.bpt") {
        let [eye, target] = [view.eye, view.target].map(|p| p.map(|c| c as f64));
        let near = (0.01 * diag) as f64;
        let meter = Meter::new(eye, target, [0.0, 0.0, 1.0], 40.0, near, view.viewport);
        for r in &refs {
            let n = 4;
            for i in 0..n {
                for j in 0..n {
                    let s = |k: usize| k as f64 / n as f64;
                    let q = [
                        [s(i), s(j)],
                        [s(i + 1), s(j)],
                        [s(i + 1), s(j + 1)],
                        [s(i), s(j + 1)],
                    ];
                    for uv in [[q[0], q[1], q[2]], [q[0], q[2], q[3]]] {
                        let corners = uv.map(|[u, v]| r.point(u, v));
                        let sampled =
                            triangle_deviation(r, uv, corners, 24, Measure::Screen(&meter)).worst;
                        let bound = screen_bound(r, uv, &meter).expect("a polynomial patch");
                        assert!(
                            bound.hull >= sampled && bound.hull <= bound.isotropic,
                            "{}: {uv:?} bound {bound:?} sampled {sampled}",
                            view.name
                        );
                        if sampled > 0.0 {
                            checked += 1;
                            tightest = tightest.min(bound.hull / sampled);
                        }
                    }
                }
            }
        }
    }
    assert!(
        checked > 500,
        "only {checked} triangles had something on screen"
    );
    println!("{checked} triangles, smallest bound / sampled {tightest:.3}");
}

/// The kernel's screen bound (`triangle_screen_bound`, in `f32` with its rounding slack)
/// covers the deviation on screen sampled in `f64` at 24 steps per side: on every patch of
/// the teapot for the error-control views, and of every NURBS fixture (rational ones among
/// them) seen from 1.3 and 0.4 diagonals away (the near view cuts some patches with the near
/// plane), each triangle of a uniform 6 x 6 split of the grid.
/// An eye, the point it looks at, the viewport and a name.
type SeenFrom = ([f32; 3], [f32; 3], [u32; 2], &'static str);

#[test]
fn the_kernels_screen_bound_covers_the_sampled_deviation() {
    use spline_tess::bake::triangle_screen_bound;
    use spline_tess::{Camera, GridPoint, Projection, Vec3};

    let mut models = vec![host_tests::models_dir().join("teapot.bpt")];
    models.extend(host_tests::nurbs_fixtures());
    let mut ratios = Vec::new();
    for path in models {
        let file = ModelFile::read(path.to_str().expect("a UTF-8 path")).expect("a model");
        let patches = file.patches();
        let aabb = patches.aabb().expect("patches");
        let diag = aabb.diagonal();
        let centre = (aabb.min + aabb.max) * 0.5;
        let name = host_tests::name(&path);
        let mut views: Vec<SeenFrom> = ERROR_VIEWS
            .iter()
            .filter(|v| name == "teapot.bpt" && v.model == "teapot.bpt")
            .map(|v| (v.eye, v.target, v.viewport, v.name))
            .collect();
        if views.is_empty() {
            let dir = Vec3::new(0.8, -0.5, 0.35).normalize();
            for (away, label) in [(1.3, "far"), (0.4, "near")] {
                let eye = centre + dir * (away * diag);
                views.push((eye.to_array(), centre.to_array(), [1024, 768], label));
            }
        }
        for (eye, target, viewport, label) in views {
            let near = 0.01 * diag;
            let camera = Camera::new(
                Vec3::from_array(eye),
                Vec3::from_array(target),
                Vec3::Z,
                Projection::Perspective {
                    fov_y_degrees: 40.0,
                },
                near,
                viewport,
            )
            .expect("a camera");
            let [eye, target] = [eye, target].map(|p| p.map(|c| c as f64));
            let meter = Meter::new(eye, target, [0.0, 0.0, 1.0], 40.0, near as f64, viewport);
            for patch in patches.iter() {
                let r = RefPatch::from_kernel(&patch);
                let n = 6u32;
                let g = |k: u32| (k * GridPoint::MAX as u32 / n) as u16;
                for i in 0..n {
                    for j in 0..n {
                        let q = [
                            GridPoint::new(g(i), g(j)),
                            GridPoint::new(g(i + 1), g(j)),
                            GridPoint::new(g(i + 1), g(j + 1)),
                            GridPoint::new(g(i), g(j + 1)),
                        ];
                        for corners in [[q[0], q[1], q[2]], [q[0], q[2], q[3]]] {
                            let uv = corners
                                .map(|p| [p.u, p.v].map(|c| c as f64 / GridPoint::MAX as f64));
                            let points = uv.map(|[u, v]| r.point(u, v));
                            let sampled =
                                triangle_deviation(&r, uv, points, 24, Measure::Screen(&meter))
                                    .worst;
                            let bound = triangle_screen_bound(&patch, corners, &camera) as f64;
                            assert!(
                                bound >= sampled,
                                "{name} {label}: {uv:?} bound {bound} sampled {sampled}"
                            );
                            if sampled > 1e-3 {
                                ratios.push(bound / sampled);
                            }
                        }
                    }
                }
            }
        }
    }
    ratios.sort_by(f64::total_cmp);
    assert!(
        ratios.len() > 2000,
        "only {} triangles on screen",
        ratios.len()
    );
    println!(
        "{} triangles: kernel screen bound / sampled min {:.3}, median {:.3}, 90% {:.3}",
        ratios.len(),
        ratios[0],
        ratios[ratios.len() / 2],
        ratios[ratios.len() * 9 / 10]
    );
}
