//! Measuring meshes against the surface, in `f64` and with a camera of the tests' own: the
//! deviation of a triangle (the surface against the triangle's linear interpolant at the same
//! parameters), in model units or projected on screen, and the reference every leanness claim
//! is measured against: the smallest uniform grid per patch whose verified deviation is within
//! the tolerance.
//!
//! On screen, a sample counts when the surface point lands on the screen (in front of the near
//! plane and inside the viewport) and the interpolant's point is in front of the near plane:
//! what is off screen or behind the near plane is never drawn.

use crate::reference::{cross, dist, dot, RefPatch, V3};

/// A perspective camera in `f64`, written here (not the kernel's).
#[derive(Clone, Debug)]
pub struct Meter {
    eye: V3,
    basis: [V3; 3],
    focal: f64,
    near: f64,
    viewport: [u32; 2],
}

fn unit(a: V3) -> V3 {
    let l = dot(a, a).sqrt();
    [a[0] / l, a[1] / l, a[2] / l]
}

fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

impl Meter {
    /// A camera at `eye` looking at `target`, `up` giving the screen's vertical, with a
    /// vertical field of view of `fov` degrees.
    pub fn new(eye: V3, target: V3, up: V3, fov: f64, near: f64, viewport: [u32; 2]) -> Meter {
        let f = unit(sub(target, eye));
        let r = unit(cross(f, up));
        let u = cross(r, f);
        Meter {
            eye,
            basis: [r, u, f],
            focal: 0.5 * viewport[1] as f64 / (fov.to_radians() * 0.5).tan(),
            near,
            viewport,
        }
    }

    /// The eye.
    pub fn eye(&self) -> V3 {
        self.eye
    }

    /// Pixels per model unit at depth 1 (the focal length in pixels).
    pub fn focal(&self) -> f64 {
        self.focal
    }

    /// The viewport, pixels.
    pub fn viewport(&self) -> [u32; 2] {
        self.viewport
    }

    /// Depth of the near plane.
    pub fn near(&self) -> f64 {
        self.near
    }

    /// A direction in view coordinates `(right, up, depth)`.
    pub fn rotate(&self, d: V3) -> V3 {
        [
            dot(d, self.basis[0]),
            dot(d, self.basis[1]),
            dot(d, self.basis[2]),
        ]
    }

    /// A point in view coordinates `(right, up, depth)`.
    pub fn view(&self, p: V3) -> V3 {
        self.rotate(sub(p, self.eye))
    }

    /// Signed distances of a point in view coordinates beyond the view's planes: near, left,
    /// right, bottom, top (positive outside; the side planes' normalised).
    pub fn beyond_planes(&self, v: V3) -> [f64; 5] {
        let sx = 0.5 * self.viewport[0] as f64 / self.focal;
        let sy = 0.5 * self.viewport[1] as f64 / self.focal;
        let (nx, ny) = ((1.0 + sx * sx).sqrt(), (1.0 + sy * sy).sqrt());
        [
            self.near - v[2],
            (-v[0] - sx * v[2]) / nx,
            (v[0] - sx * v[2]) / nx,
            (-v[1] - sy * v[2]) / ny,
            (v[1] - sy * v[2]) / ny,
        ]
    }

    /// The part of the convex polygon `points` (view coordinates) in front of the near plane
    /// and within `margin` of the side planes, by clipping one plane after another.
    pub fn clip(&self, points: &[V3], margin: f64) -> Vec<V3> {
        let mut polygon = points.to_vec();
        for k in 0..5 {
            let limit = if k == 0 { 0.0 } else { margin };
            let outside = |v: &V3| self.beyond_planes(*v)[k] - limit;
            let mut kept = Vec::with_capacity(polygon.len() + 1);
            for (i, &a) in polygon.iter().enumerate() {
                let b = polygon[(i + 1) % polygon.len()];
                let (da, db) = (outside(&a), outside(&b));
                if da <= 0.0 {
                    kept.push(a);
                }
                if (da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0) {
                    let t = da / (da - db);
                    kept.push([0, 1, 2].map(|c| a[c] + t * (b[c] - a[c])));
                }
            }
            polygon = kept;
            if polygon.is_empty() {
                break;
            }
        }
        polygon
    }

    /// Pixel position of view coordinates in front of the eye.
    fn pixel(&self, v: V3) -> [f64; 2] {
        let s = self.focal / v[2];
        [
            0.5 * self.viewport[0] as f64 + v[0] * s,
            0.5 * self.viewport[1] as f64 - v[1] * s,
        ]
    }

    /// True when every point of `points` lies beyond one and the same plane of the view (so
    /// their convex hull is out of sight).
    pub fn outside_one_plane(&self, points: &[V3]) -> bool {
        let d: Vec<[f64; 5]> = points
            .iter()
            .map(|&p| self.beyond_planes(self.view(p)))
            .collect();
        (0..5).any(|k| d.iter().all(|x| x[k] > 0.0))
    }

    /// True when `p` is in front of the near plane and projects inside the viewport.
    pub fn on_screen(&self, p: V3) -> bool {
        let v = self.view(p);
        if v[2] < self.near {
            return false;
        }
        let [x, y] = self.pixel(v);
        x >= 0.0 && x <= self.viewport[0] as f64 && y >= 0.0 && y <= self.viewport[1] as f64
    }

    /// Projected distance in pixels between the surface point `s` and the interpolant's `l`,
    /// or `None` when the sample does not count (see the module docs).
    pub fn deviation(&self, s: V3, l: V3) -> Option<f64> {
        let (vs, vl) = (self.view(s), self.view(l));
        if vs[2] < self.near || vl[2] < self.near {
            return None;
        }
        let (ps, pl) = (self.pixel(vs), self.pixel(vl));
        let inside = ps[0] >= 0.0
            && ps[0] <= self.viewport[0] as f64
            && ps[1] >= 0.0
            && ps[1] <= self.viewport[1] as f64;
        inside.then(|| ((ps[0] - pl[0]).powi(2) + (ps[1] - pl[1]).powi(2)).sqrt())
    }
}

/// Where deviations are measured.
#[derive(Clone, Copy, Debug)]
pub enum Measure<'a> {
    /// In model units.
    Object,
    /// In pixels, through a camera.
    Screen(&'a Meter),
}

/// The measured deviation of one triangle.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Measured {
    /// Largest deviation over the samples that count.
    pub worst: f64,
    /// Largest deviation in model units over the same samples.
    pub worst_object: f64,
    /// Whether any sample counted (on screen, for a camera).
    pub visible: bool,
}

/// Deviation of the triangle with corner parameters `uv` and corner points `corners` from
/// patch `r`, at `dense` barycentric steps per side.
pub fn triangle_deviation(
    r: &RefPatch,
    uv: [[f64; 2]; 3],
    corners: [V3; 3],
    dense: usize,
    measure: Measure<'_>,
) -> Measured {
    let mut m = Measured::default();
    for i in 0..=dense {
        for j in 0..=dense - i {
            let (a, b) = (i as f64 / dense as f64, j as f64 / dense as f64);
            let c = 1.0 - a - b;
            let u = uv[0][0] * c + uv[1][0] * a + uv[2][0] * b;
            let v = uv[0][1] * c + uv[1][1] * a + uv[2][1] * b;
            let s = r.point(u.clamp(0.0, 1.0), v.clamp(0.0, 1.0));
            let l = [0, 1, 2].map(|k| corners[0][k] * c + corners[1][k] * a + corners[2][k] * b);
            let d = match measure {
                Measure::Object => Some(dist(s, l)),
                Measure::Screen(meter) => meter.deviation(s, l),
            };
            if let Some(d) = d {
                m.visible = true;
                m.worst = m.worst.max(d);
                m.worst_object = m.worst_object.max(dist(s, l));
            }
        }
    }
    m
}

/// Largest measured deviation of the uniform `n x n` vertex grid of patch `r` (cells split
/// along one diagonal).
pub fn grid_deviation(r: &RefPatch, n: usize, dense: usize, measure: Measure<'_>) -> f64 {
    grid_deviation_uv(r, [n, n], dense, measure)
}

/// Largest measured deviation of the uniform `n_u x n_v` vertex grid of patch `r` (`n_u`
/// vertices along `u`, cells split along one diagonal).
pub fn grid_deviation_uv(
    r: &RefPatch,
    [nu, nv]: [usize; 2],
    dense: usize,
    measure: Measure<'_>,
) -> f64 {
    let su = |k: usize| k as f64 / (nu - 1) as f64;
    let sv = |k: usize| k as f64 / (nv - 1) as f64;
    let mut worst = 0.0f64;
    for i in 0..nu - 1 {
        for j in 0..nv - 1 {
            let q = [
                [su(i), sv(j)],
                [su(i + 1), sv(j)],
                [su(i + 1), sv(j + 1)],
                [su(i), sv(j + 1)],
            ];
            let p = q.map(|[u, v]| r.point(u, v));
            for (a, b, c) in [(0, 1, 2), (0, 2, 3)] {
                let m =
                    triangle_deviation(r, [q[a], q[b], q[c]], [p[a], p[b], p[c]], dense, measure);
                worst = worst.max(m.worst);
            }
        }
    }
    worst
}

/// The smallest `n` (from 2, up to `limit`) whose uniform grid on patch `r` has a measured
/// deviation at most `tolerance`, found by doubling then bisection (the deviation falls as
/// `n` grows); `None` past `limit`.
pub fn grid_size(
    r: &RefPatch,
    tolerance: f64,
    dense: usize,
    limit: usize,
    measure: Measure<'_>,
) -> Option<usize> {
    let ok = |n: usize| grid_deviation(r, n, dense, measure) <= tolerance;
    if ok(2) {
        return Some(2);
    }
    let (mut lo, mut hi) = (2usize, 4usize);
    while !ok(hi) {
        lo = hi;
        hi *= 2;
        if hi > limit {
            return None;
        }
    }
    while hi - lo > 1 {
        let mid = (lo + hi) / 2;
        if ok(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Some(hi)
}

/// The `n_u x n_v` vertex grid (`2 (n_u - 1)(n_v - 1)` triangles) with the fewest triangles
/// whose measured deviation on patch `r` is at most `tolerance`, each of `n_u`, `n_v` from 2 up
/// to `limit`: the stronger reference of a uniform tessellator with a factor per direction (as
/// the Direct3D 11 tessellator has). `None` when no grid within `limit` is.
///
/// The search walks the staircase of the smallest `n_v` for each `n_u` (the deviation falls
/// as either grows): from the smallest `n_u` that any `n_v` up to the cap serves, with its
/// smallest `n_v`, `n_u` grows by one and `n_v` falls while the grid stays within the
/// tolerance, until `n_v` reaches the smallest any `n_u` up to the cap allows (past there a
/// larger `n_u` only adds triangles). The cap on each factor is 8 times the smallest `n x n`
/// grid's `n` (within `limit`): a grid stretched further than 8 to 1 beside the square one is
/// not looked for (checking a factor of `limit` costs a `limit x limit` grid).
pub fn grid_size_uv(
    r: &RefPatch,
    tolerance: f64,
    dense: usize,
    limit: usize,
    measure: Measure<'_>,
) -> Option<[usize; 2]> {
    let square = grid_size(r, tolerance, dense, limit, measure)?;
    let limit = limit.min(8 * square);
    let ok = |nu: usize, nv: usize| grid_deviation_uv(r, [nu, nv], dense, measure) <= tolerance;
    let triangles = |[nu, nv]: [usize; 2]| 2 * (nu - 1) * (nv - 1);
    // The smallest `n` in `2..=limit` for which `within(n)` holds (it holds for every larger
    // one), by bisection; `None` when `within(limit)` does not.
    let smallest = |within: &dyn Fn(usize) -> bool| {
        if within(2) {
            return Some(2);
        }
        if !within(limit) {
            return None;
        }
        let (mut lo, mut hi) = (2, limit);
        while hi - lo > 1 {
            let mid = (lo + hi) / 2;
            if within(mid) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        Some(hi)
    };
    let mut nu = smallest(&|nu| ok(nu, limit))?;
    let nv_least = smallest(&|nv| ok(limit, nv))?;
    let mut nv = smallest(&|nv| ok(nu, nv))?;
    let mut best = [nu, nv];
    while nv > nv_least && nu < limit && 2 * nu * (nv_least - 1) < triangles(best) {
        nu += 1;
        // `n_v` for this `n_u` is at most the last one's.
        while nv > nv_least && ok(nu, nv - 1) {
            nv -= 1;
        }
        if triangles([nu, nv]) < triangles(best) {
            best = [nu, nv];
        }
    }
    Some(best)
}

/// The triangles of the two uniform references over every patch of `refs`: the smallest
/// `n x n` grid per patch ([`grid_size`]) and the smallest `n_u x n_v` one
/// ([`grid_size_uv`]), summed; a patch that no grid within `limit` serves counts
/// `2 (limit - 1)^2`. The patches are shared among the machine's cores.
pub fn grid_triangles(
    refs: &[RefPatch],
    tolerance: f64,
    dense: usize,
    limit: usize,
    measure: Measure<'_>,
) -> [usize; 2] {
    let worst = 2 * (limit - 1) * (limit - 1);
    let one = |r: &RefPatch| {
        [
            grid_size(r, tolerance, dense, limit, measure).map_or(worst, |n| 2 * (n - 1) * (n - 1)),
            grid_size_uv(r, tolerance, dense, limit, measure)
                .map_or(worst, |[nu, nv]| 2 * (nu - 1) * (nv - 1)),
        ]
    };
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let next = std::sync::atomic::AtomicUsize::new(0);
    let sums: Vec<[usize; 2]> = std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                scope.spawn(|| {
                    let mut sum = [0, 0];
                    loop {
                        let k = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                        let Some(r) = refs.get(k) else {
                            return sum;
                        };
                        let [a, b] = one(r);
                        sum = [sum[0] + a, sum[1] + b];
                    }
                })
            })
            .collect();
        workers
            .into_iter()
            .map(|w| w.join().expect("a grid worker"))
            .collect()
    });
    sums.iter().fold([0, 0], |a, b| [a[0] + b[0], a[1] + b[1]])
}

/// A camera view of the error-control figures: a model file (under the models folder), a
/// name for the table, the eye and the point it looks at (up is `+z`, 40 degree vertical
/// field of view), the viewport and the tolerance in pixels.
#[derive(Clone, Copy, Debug)]
pub struct ScreenView {
    /// Model file.
    pub model: &'static str,
    /// Name in the tables.
    pub name: &'static str,
    /// Eye.
    pub eye: [f32; 3],
    /// The point looked at.
    pub target: [f32; 3],
    /// Viewport in pixels.
    pub viewport: [u32; 2],
    /// Tolerance in pixels.
    pub tol: f32,
}

/// The camera views the error-control issue names, which `error_figures` and
/// `oracle_selection` both measure.
pub const ERROR_VIEWS: [ScreenView; 8] = [
    ScreenView {
        model: "teapot.bpt",
        name: "teapot 240x240 1 px, eye (8,-8,5)",
        eye: [8.0, -8.0, 5.0],
        target: [0.0, 0.0, 1.2],
        viewport: [240, 240],
        tol: 1.0,
    },
    ScreenView {
        model: "teapot.bpt",
        name: "teapot 1024x768 1 px, eye (6,-6,4)",
        eye: [6.0, -6.0, 4.0],
        target: [0.0, 0.0, 1.2],
        viewport: [1024, 768],
        tol: 1.0,
    },
    ScreenView {
        model: "teapot.bpt",
        name: "teapot 1024x768 0.5 px, eye (6,-6,4)",
        eye: [6.0, -6.0, 4.0],
        target: [0.0, 0.0, 1.2],
        viewport: [1024, 768],
        tol: 0.5,
    },
    ScreenView {
        model: "teapot.bpt",
        name: "teapot 1024x768 1 px, eye (9,0,0.3)",
        eye: [9.0, 0.0, 0.3],
        target: [0.0, 0.0, 1.0],
        viewport: [1024, 768],
        tol: 1.0,
    },
    ScreenView {
        model: "teapot.bpt",
        name: "teapot 1024x768 0.5 px, eye (9,0,0.3)",
        eye: [9.0, 0.0, 0.3],
        target: [0.0, 0.0, 1.0],
        viewport: [1024, 768],
        tol: 0.5,
    },
    ScreenView {
        model: "teapot.bpt",
        name: "teapot close-up 1024x768 1 px, eye (2.2,-1.5,2.6)",
        eye: [2.2, -1.5, 2.6],
        target: [0.0, 0.0, 1.5],
        viewport: [1024, 768],
        tol: 1.0,
    },
    ScreenView {
        model: "gumbo.bpt",
        name: "Gumbo 1024x768 1 px, eye (60,-50,40)",
        eye: [60.0, -50.0, 40.0],
        target: [12.0, 7.0, 9.7],
        viewport: [1024, 768],
        tol: 1.0,
    },
    ScreenView {
        model: "teaspoon.bpt",
        name: "teaspoon 128x160 1 px, eye (0.9,-1.3,0.8)",
        eye: [0.9, -1.3, 0.8],
        target: [0.0, -0.4, 0.0],
        viewport: [128, 160],
        tol: 1.0,
    },
];

/// The kernel's camera of the figures and tests: at `eye` looking at `target`, up `+z`, a
/// perspective of 40 degrees vertically, the near plane at `near`, `viewport` pixels.
///
/// # Panics
/// Where the camera is not valid (the eye at the target, a zero viewport).
pub fn camera_40(
    eye: spline_tess::Vec3,
    target: spline_tess::Vec3,
    near: f32,
    viewport: [u32; 2],
) -> spline_tess::Camera {
    spline_tess::Camera::new(
        eye,
        target,
        spline_tess::Vec3::Z,
        spline_tess::Projection::Perspective {
            fov_y_degrees: 40.0,
        },
        near,
        viewport,
    )
    .expect("a valid camera")
}
