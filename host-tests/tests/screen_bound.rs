//! Screen bounds cover the deviation they bound. The oracle's (`host_tests::screen_bound`):
//! on every patch of the teapot, for the error-control views, each triangle of a uniform
//! 4 x 4 split has a directional bound at least its deviation on screen sampled at 24 steps
//! per side, and at most its isotropic bound. (The kernel's own bound on screen is checked
//! against the same sampling on every frame of `bisection.rs`.)

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
