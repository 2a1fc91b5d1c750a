//! How few triangles a selection of this kind could reach: oracle tessellators beside the
//! verified uniform grid, on the views of the error-control table: four with a perfect error
//! measure, four with a sound bound, and two that select per sample from the kernel's own
//! bake with the kernel's own bound. Prints a Markdown table.
//!
//! ```text
//! cargo run --release -p host-tests --example oracle_selection
//! ```
//!
//! The oracles triangulate each patch on its own (as the grid does: no shared boundaries, so
//! cracks; all but the last bintree), by Delaunay insertion in (u,v) with the kernel's `DomainMesh`, starting from the
//! square's two triangles (the bintrees: by bisection). The first four measure a triangle's
//! error exactly as `error_figures` does: the surface against the triangle's linear
//! interpolant at the same (u,v), 12 steps per side with the `f64` reference, projected, only
//! samples on screen counting. None is sound (sampled, not bounded) nor crack-free, and greedy
//! insertion is not optimal: they show what a tessellator that is both, selecting the same
//! way, can hope for before a bound's margin and shared boundaries.
//!
//! - *Adaptive*: inserts the worst point of the triangle with the largest projected error
//!   until every triangle is within the tolerance. Each triangle is judged by its own
//!   projection: the selection is not a prefix of any fixed order.
//! - *Nested*: inserts in the order of largest *object-space* error (the view-independent
//!   order a bake records) and stops at the shortest prefix whose every triangle is within
//!   the tolerance on screen: Chhugani & Kumar's per-patch prefix, with an exact measure in
//!   place of a bound and no curve sampled apart.
//! - *Nested, patch scale*: the same prefix, each triangle judged by its error in model units
//!   times one scale for the whole patch (pixels per model unit at the nearest part of its
//!   control net that can show): the kernel's form of the test, with the exact error in place
//!   of its bound.
//! - *Bintree*: no Delaunay insertion, but longest-edge bisection of the square's two right
//!   triangles (a triangle over the tolerance is halved at its hypotenuse's midpoint, and the
//!   one across the hypotenuse too, so the mesh stays conforming), judged by the same sampled
//!   error on screen. Every triangle such a mesh can have is fixed in advance, so a bake could
//!   store a bound for each (see *bintree, kernel's bound* below).
//!
//! The other two select as *adaptive* does, but judge each triangle by a computed bound of its
//! deviation on screen (`host_tests::screen_bound`, where both are derived) instead of the
//! sampled error, and stop when every bound is within the tolerance: a selection that is
//! sound, still without shared boundaries.
//!
//! - *Isotropic bound*: the triangle's bound in model units times the largest scale of the
//!   projection over the triangle, the form the kernel's run time uses.
//! - *Directional bound*: the deviation vectors of the triangle's lattice projected one by one
//!   at the corners' view rays, plus the remainder: a deviation along the line of sight moves
//!   no pixel, and this bound sees it. Its last column checks it: the bound over the triangle's
//!   deviation on screen sampled at 24 steps per side (a sound bound is at least 1).
//!
//! *Bintree, kernel's bound* is the bintree judged by the kernel's own bound on screen
//! (`bake::triangle_screen_bound`, directional and sound; corners rounded to the kernel's
//! parameter grid): a sound selection, still without shared boundaries. *Bintree, bound,
//! shared curves* is the same over the whole model at once: a triangle across a curve two
//! patches share (its corners found by their points in model space) conforms too, so the
//! mesh has no crack; the column says what shared boundaries cost this selection. Its next
//! column is the median of its triangles' sampled error on screen over the tolerance (those
//! with a sample on screen), as `error_figures` reports the kernel's.
//! The column after it judges the same shared-curve bintree by `host_tests::screen_bound`'s
//! directional bound (sound, in `f64`, sharing no code with the kernel) built on lattices of
//! 2, 3, 4 and 6 steps per side: 3, 7, 12 and 25 deviation vectors besides the corners, the
//! remainder shrinking with the square of the steps. A bake holding a bound for every
//! bisection triangle would store that many vectors per triangle, so the column says what
//! each size of such a bake gives.
//! The next keeps only 4, 6 or 8 of the 6-step lattice's 25 vectors
//! (`host_tests::screen_bound::keep_vectors`: farthest from the kept ones' hull first, the
//! remainder widened by the largest distance of a vector left out from that hull, so still
//! sound): what a bake that chooses the vectors it stores could give.
//!
//! A second table gives, per model, the leaves of the shared-curve bintree split until the
//! bound in model units (`host_tests::screen_bound`'s `object`, on the 6-step lattice) is
//! within 1e-3 and 2.5e-4 of the diagonal: the triangles, about half the nodes, that a bake to
//! that tolerance would hold a bound for, whatever the view.
//!
//! The last two take the points a bake recorded instead of choosing their own: the kernel's
//! own bake of the model (at 1e-3 and at 2.5e-4 of its diagonal), and the kernel's own bound
//! on screen (`bake::triangle_screen_bound`), so they show what a run time built from the
//! kernel's parts could reach with *per-sample* selection (still without shared curves):
//!
//! - *Baked per sample*: a step is kept when its deviation at its own point, before it went
//!   in (the surface against the triangle of the baked steps before it that held the point),
//!   shows more than the tolerance on screen; the kept steps are triangulated. Then, in
//!   rounds, every triangle whose bound is over the tolerance takes the first baked step
//!   inside it that it does not hold (all of a round's steps go in together, in order, so the
//!   result depends on the view alone); what is still over once no such step is left is cut
//!   uniformly, each triangle by the smallest factor whose pieces are all within the
//!   tolerance.
//!
//! Two settings from the environment, for the per-sample columns: `PER_SAMPLE_ROUNDS=N` stops
//! the rounds after `N` (0: the kept steps alone, then uniform cuts), and `PER_SAMPLE_ONLY=1`
//! leaves every other oracle out (their columns print 0), which takes a few seconds instead
//! of half a minute:
//!
//! ```text
//! PER_SAMPLE_ONLY=1 PER_SAMPLE_ROUNDS=1 cargo run --release -p host-tests --example oracle_selection
//! ```

use std::collections::HashMap;

use host_tests::bintree::{self, bintree, Bin};
use host_tests::model_file::ModelFile;
use host_tests::reference::{dist, RefPatch, V3};
use host_tests::screen::{grid_size, triangle_deviation, Measure, Meter, ERROR_VIEWS};
use host_tests::screen_bound::{screen_bound, screen_bound_kept};
use spline_tess::bake::{triangle_screen_bound, BakedModel};
use spline_tess::{
    BezierPatch, Camera, DomainMesh, GridPoint, MeshTriangle, MeshVertex, Projection, Vec3,
};

/// Barycentric steps per side of a measured triangle (as `error_figures`).
const DENSE: usize = 12;
/// Barycentric steps per side when a bound is checked.
const CHECK_DENSE: usize = 24;
/// Steps per side of a grid triangle (as `error_figures`).
const GRID_DENSE: usize = 8;
/// The bakes the per-sample oracle reads (relative tolerances; the caps of `error_figures`).
const BAKES: [f32; 2] = [1e-3, 2.5e-4];
/// Largest uniform factor the per-sample oracle tries on a triangle (no case comes near).
const MAX_FACTOR: u32 = 32;
/// Vertex slots per patch; no case comes near.
const VERTICES: usize = 1 << 14;

/// A triangle's largest error and where it is, in (u,v).
#[derive(Clone, Copy)]
struct Worst {
    error: f64,
    at: [f64; 2],
}

/// How an oracle judges a triangle and picks the next point.
#[derive(Clone, Copy, PartialEq)]
enum Selection {
    /// The sampled error on screen.
    Adaptive,
    /// The prefix of the order of the sampled error in model units.
    Nested,
    /// The same prefix, judged by the sampled error in model units times one scale for the
    /// whole patch (the kernel's form, without a bound's margin).
    NestedPatchScale,
    /// The isotropic bound on screen.
    Isotropic,
    /// The directional bound on screen.
    Directional,
}

/// The largest projected and object-space errors of the triangle with corner parameters
/// `uv` on patch `r`.
fn measure(r: &RefPatch, uv: [[f64; 2]; 3], meter: &Meter) -> (Worst, Worst) {
    let corners: [V3; 3] = uv.map(|[u, v]| r.point(u, v));
    let none = Worst {
        error: 0.0,
        at: [0.0; 2],
    };
    let (mut screen, mut object) = (none, none);
    for i in 0..=DENSE {
        for j in 0..=DENSE - i {
            let (a, b) = (i as f64 / DENSE as f64, j as f64 / DENSE as f64);
            let c = 1.0 - a - b;
            let at = [0, 1].map(|k| uv[0][k] * c + uv[1][k] * a + uv[2][k] * b);
            let s = r.point(at[0], at[1]);
            let l = [0, 1, 2].map(|k| corners[0][k] * c + corners[1][k] * a + corners[2][k] * b);
            if let Some(d) = meter.deviation(s, l) {
                if d > screen.error {
                    screen = Worst { error: d, at };
                }
            }
            let d = dist(s, l);
            if d > object.error {
                object = Worst { error: d, at };
            }
        }
    }
    (screen, object)
}

/// How one triangle is judged: the value held against the tolerance, and the value and
/// point that order the insertions.
fn judge(
    r: &RefPatch,
    uv: [[f64; 2]; 3],
    meter: &Meter,
    selection: Selection,
    patch_scale: f64,
) -> (f64, Worst) {
    match selection {
        Selection::NestedPatchScale => {
            let (_, object) = measure(r, uv, meter);
            (object.error * patch_scale, object)
        }
        Selection::Adaptive | Selection::Nested => {
            let (screen, object) = measure(r, uv, meter);
            let order = if selection == Selection::Nested {
                object
            } else {
                screen
            };
            (screen.error, order)
        }
        Selection::Isotropic | Selection::Directional => {
            let b = screen_bound(r, uv, meter).expect("a polynomial patch");
            let error = if selection == Selection::Isotropic {
                b.isotropic
            } else {
                b.hull
            };
            (error, Worst { error, at: b.at })
        }
    }
}

/// The final triangles of one oracle on patch `r`: corner parameters, and the value each was
/// held to (its bound, for the bounded selections).
fn oracle(r: &RefPatch, meter: &Meter, tol: f64, selection: Selection) -> Vec<Judged> {
    let mut room = MeshRoom::new();
    let mut mesh = room.square();
    let mut judged: HashMap<[GridPoint; 3], (f64, Worst)> = HashMap::new();
    let patch_scale = patch_scale(r, meter);
    let keys = |mesh: &DomainMesh<'_>| -> Vec<[GridPoint; 3]> {
        domain_triangles(mesh).into_iter().map(key).collect()
    };
    loop {
        let (mut worst, mut next): (f64, Option<(Worst, [GridPoint; 3])>) = (0.0, None);
        for key in keys(&mesh) {
            let (held, order) = *judged
                .entry(key)
                .or_insert_with(|| judge(r, key.map(unit), meter, selection, patch_scale));
            worst = worst.max(held);
            // The nested order runs over every triangle; the others refine one over.
            let nested = matches!(selection, Selection::Nested | Selection::NestedPatchScale);
            let candidate = nested || held > tol;
            if candidate && next.is_none_or(|(n, _)| order.error > n.error) {
                next = Some((order, key));
            }
        }
        let done = |mesh: &DomainMesh<'_>| {
            let held = |k: &[GridPoint; 3]| judged[k].0;
            keys(mesh).iter().map(|k| (k.map(unit), held(k))).collect()
        };
        let Some((next, key)) = next.filter(|_| worst > tol) else {
            return done(&mesh);
        };
        let [u, v] = next.at.map(|c| (c * GridPoint::MAX as f64).round() as u16);
        let midpoint = |(a, b): (GridPoint, GridPoint)| GridPoint {
            u: ((a.u as u32 + b.u as u32) / 2) as u16,
            v: ((a.v as u32 + b.v as u32) / 2) as u16,
        };
        let edges = [(0, 1), (1, 2), (2, 0)].map(|(i, j)| (key[i], key[j]));
        // Where the worst point rounds to a vertex (a sliver), the longest edge's midpoint.
        let longest = edges
            .into_iter()
            .max_by_key(|(a, b)| {
                (a.u.abs_diff(b.u) as u32).pow(2) + (a.v.abs_diff(b.v) as u32).pow(2)
            })
            .map(midpoint)
            .expect("three edges");
        if mesh.insert(GridPoint { u, v }).is_err() && mesh.insert(longest).is_err() {
            eprintln!("a patch stopped at {worst:.3} px: no point left to insert");
            return done(&mesh);
        }
    }
}

/// Pixels per model unit at the nearest part of patch `r`'s control net that can show: the
/// focal length over the least depth of the net (at least the near plane's), times
/// `sqrt(1 + |τ|²)` for the largest slope `τ` of a control point, the slopes clamped to the
/// view's corners (the kernel's per-patch form, on the control net instead of its hull;
/// zero when the whole net is beyond one of the view's planes: the patch stays two triangles).
fn patch_scale(r: &RefPatch, meter: &Meter) -> f64 {
    if meter.outside_one_plane(&r.pts) {
        return 0.0;
    }
    let v: Vec<V3> = r.pts.iter().map(|&p| meter.view(p)).collect();
    if v.is_empty() {
        return 0.0;
    }
    let z_min = v
        .iter()
        .map(|p| p[2])
        .fold(f64::INFINITY, f64::min)
        .max(meter.near());
    let [w, h] = meter.viewport().map(|x| 0.5 * x as f64 / meter.focal());
    let slope = v
        .iter()
        .map(|p| {
            let z = p[2].max(meter.near());
            let (tx, ty) = ((p[0] / z).clamp(-w, w), (p[1] / z).clamp(-h, h));
            (1.0 + tx * tx + ty * ty).sqrt()
        })
        .fold(1.0f64, f64::max);
    meter.focal() / z_min * slope
}

/// Lattices (steps per side) of the `f64` directional bound the last bintree column tries.
const BINTREE_LATTICES: [usize; 4] = [2, 3, 4, 6];

/// How many of the 6-step lattice's vectors the column after it keeps.
const BINTREE_KEPT: [usize; 3] = [4, 6, 8];

/// A final triangle's corner parameters and the value it was held to.
type Judged = ([[f64; 2]; 3], f64);

/// Bound over sampled deviation, on screen, of every triangle (held to its bound) with
/// something on screen.
fn bound_over_true(r: &RefPatch, triangles: &[Judged], meter: &Meter) -> Vec<f64> {
    triangles
        .iter()
        .filter_map(|&(uv, bound)| {
            let corners = uv.map(|[u, v]| r.point(u, v));
            let sampled = triangle_deviation(r, uv, corners, CHECK_DENSE, Measure::Screen(meter));
            (sampled.worst > 0.0).then(|| bound / sampled.worst)
        })
        .collect()
}

/// Barycentric coordinates of `q` in the domain triangle `t` (exact enough: grid units in
/// `f64`).
fn barycentric(t: [GridPoint; 3], q: GridPoint) -> [f64; 3] {
    let [a, b, c, q] = [t[0], t[1], t[2], q].map(|g| [g.u as f64, g.v as f64]);
    let det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
    let l1 = ((q[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (q[1] - a[1])) / det;
    let l2 = ((b[0] - a[0]) * (q[1] - a[1]) - (q[0] - a[0]) * (b[1] - a[1])) / det;
    [1.0 - l1 - l2, l1, l2]
}

/// Whether `q` lies in the closed domain triangle `t`.
fn holds(t: [GridPoint; 3], q: GridPoint) -> bool {
    barycentric(t, q).iter().all(|&l| l >= -1e-12)
}

/// The domain triangles of `mesh`, by their corners.
fn domain_triangles(mesh: &DomainMesh<'_>) -> Vec<[GridPoint; 3]> {
    mesh.triangles()
        .map(|ids| ids.map(|id| mesh.point(id).expect("a vertex of the mesh")))
        .collect()
}

/// A domain triangle's corners in one order (its key whichever corner comes first).
fn key(mut t: [GridPoint; 3]) -> [GridPoint; 3] {
    t.sort_by_key(|p| (p.u, p.v));
    t
}

/// A grid point's (u,v) in the unit square.
fn unit(p: GridPoint) -> [f64; 2] {
    [p.u, p.v].map(|c| c as f64 / GridPoint::MAX as f64)
}

/// Room for one patch's domain mesh.
struct MeshRoom {
    vertices: Vec<MeshVertex>,
    triangles: Vec<MeshTriangle>,
}

impl MeshRoom {
    fn new() -> MeshRoom {
        MeshRoom {
            vertices: vec![MeshVertex::default(); VERTICES],
            triangles: vec![MeshTriangle::default(); DomainMesh::triangles_for(VERTICES)],
        }
    }

    /// A fresh mesh of the square's two triangles.
    fn square(&mut self) -> DomainMesh<'_> {
        DomainMesh::new(&mut self.vertices, &mut self.triangles).expect("room for the square")
    }
}

/// The deviation on screen of each baked step at its own point before it went in: the
/// steps replayed in order, each measured against the triangle that held it.
fn step_deviations(r: &RefPatch, steps: &[GridPoint], meter: &Meter) -> Vec<f64> {
    let mut room = MeshRoom::new();
    let mut mesh = room.square();
    let point = |g: GridPoint| {
        let [u, v] = unit(g);
        r.point(u, v)
    };
    let mut deviations = Vec::with_capacity(steps.len());
    for &q in steps {
        let held = domain_triangles(&mesh).into_iter().find(|&t| holds(t, q));
        let deviation = held.map_or(0.0, |t| {
            let l = barycentric(t, q);
            let corners = t.map(point);
            let linear = [0, 1, 2].map(|k| (0..3).map(|i| l[i] * corners[i][k]).sum());
            meter.deviation(point(q), linear).unwrap_or(0.0)
        });
        deviations.push(deviation);
        // (A step that is already a vertex changes nothing.)
        let _ = mesh.insert(q);
    }
    deviations
}

/// The smallest uniform factor whose pieces of `t` are all within `tol` by `bound`, with its
/// piece count (`MAX_FACTOR`'s when none is).
fn uniform_pieces(
    t: [GridPoint; 3],
    tol: f64,
    bound: &mut impl FnMut([GridPoint; 3]) -> f32,
) -> usize {
    for f in 2..=MAX_FACTOR {
        let at = |i: u32, j: u32| {
            let (a, b) = (i as f64 / f as f64, j as f64 / f as f64);
            let c = 1.0 - a - b;
            let mix = |x: [f64; 3]| (c * x[0] + a * x[1] + b * x[2]).round() as u16;
            GridPoint {
                u: mix(t.map(|g| g.u as f64)),
                v: mix(t.map(|g| g.v as f64)),
            }
        };
        let within = (0..f).all(|i| {
            (0..f - i).all(|j| {
                let up = [at(i, j), at(i + 1, j), at(i, j + 1)];
                let down = [at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)];
                bound(up) as f64 <= tol && (i + j + 1 == f || bound(down) as f64 <= tol)
            })
        });
        if within {
            return (f * f) as usize;
        }
    }
    (MAX_FACTOR * MAX_FACTOR) as usize
}

/// Rounds of the per-sample oracle at most: `PER_SAMPLE_ROUNDS`, or until none is left.
fn per_sample_rounds() -> usize {
    std::env::var("PER_SAMPLE_ROUNDS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(usize::MAX)
}

/// The triangles of the per-sample oracle on `patch` with the baked `steps`, after at most
/// `rounds` rounds.
fn per_sample(
    patch: &BezierPatch<'_>,
    r: &RefPatch,
    steps: &[GridPoint],
    meter: &Meter,
    camera: &Camera,
    tol: f64,
    rounds: usize,
) -> usize {
    let deviations = step_deviations(r, steps, meter);
    let mut room = MeshRoom::new();
    let mut mesh = room.square();
    let mut held = vec![false; steps.len()];
    for (k, &q) in steps.iter().enumerate() {
        if deviations[k] > tol {
            held[k] = true;
            let _ = mesh.insert(q);
        }
    }
    let mut bounds: HashMap<[GridPoint; 3], f32> = HashMap::new();
    let mut bound = |t: [GridPoint; 3]| {
        *bounds
            .entry(key(t))
            .or_insert_with(|| triangle_screen_bound(patch, t, camera))
    };
    for _ in 0..rounds {
        let mut round: Vec<usize> = domain_triangles(&mesh)
            .into_iter()
            .filter(|&t| bound(t) as f64 > tol)
            .filter_map(|t| (0..steps.len()).find(|&k| !held[k] && holds(t, steps[k])))
            .collect();
        if round.is_empty() {
            break;
        }
        round.sort_unstable();
        round.dedup();
        for k in round {
            held[k] = true;
            let _ = mesh.insert(steps[k]);
        }
    }
    domain_triangles(&mesh)
        .into_iter()
        .map(|t| {
            if bound(t) as f64 <= tol {
                1
            } else {
                uniform_pieces(t, tol, &mut bound)
            }
        })
        .sum()
}

fn main() {
    let (rounds, per_sample_only) = (
        per_sample_rounds(),
        std::env::var_os("PER_SAMPLE_ONLY").is_some(),
    );
    println!(
        "| case | grid | adaptive oracle | adaptive / grid | nested oracle | nested / grid \
         | nested, patch scale | nested, patch scale / grid | bintree | bintree / grid \
         | bintree, kernel's bound | bintree, bound / grid \
         | bintree, bound, shared curves | bintree, shared / grid | bintree, shared: median error / tol \
         | bintree, shared, f64 bound on lattices of 2 / 3 / 4 / 6 steps: / grid \
         | bintree, shared, 4 / 6 / 8 of the 6-step lattice's vectors kept: / grid \
         | isotropic bound | isotropic / grid | directional bound | directional / grid \
         | directional bound / sampled: min, median \
         | baked 1e-3 per sample | per sample / grid | baked 2.5e-4 per sample | per sample / grid |"
    );
    println!(
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
    );
    let mut loaded: Vec<(&str, ModelFile, Vec<Vec<u8>>)> = Vec::new();
    // Per model: the leaves of the shared-curve bintree in model space at each of `BAKES`.
    let mut in_model_space: Vec<(&str, Vec<usize>)> = Vec::new();
    for view in ERROR_VIEWS {
        let (model, name, viewport) = (view.model, view.name, view.viewport);
        let [eye, target] = [view.eye, view.target].map(|p| p.map(|c| c as f64));
        let tol = view.tol as f64;
        if !loaded.iter().any(|(m, _, _)| *m == model) {
            let path = host_tests::models_dir().join(model);
            let file = ModelFile::read(path.to_str().expect("a UTF-8 path")).expect("a model");
            let bakes = BAKES
                .map(|rel| file.bake_relative(rel).expect("a bake"))
                .to_vec();
            loaded.push((model, file, bakes));
        }
        let (_, file, bakes) = loaded.iter().find(|(m, _, _)| *m == model).expect("loaded");
        let baked: Vec<BakedModel<'_>> = bakes
            .iter()
            .map(|b| BakedModel::from_bytes(b).expect("a fresh bake reads back"))
            .collect();
        let patches = file.patches();
        let diag = patches.aabb().expect("patches").diagonal();
        // The near plane of `error_figures`, rounded to f32 as its camera's is.
        let near = (0.01 * diag) as f64;
        let meter = Meter::new(eye, target, [0.0, 0.0, 1.0], 40.0, near, viewport);
        // The kernel's camera, as `error_figures` makes it.
        let camera = Camera::new(
            Vec3::from_array(view.eye),
            Vec3::from_array(view.target),
            Vec3::Z,
            Projection::Perspective {
                fov_y_degrees: 40.0,
            },
            0.01 * diag,
            viewport,
        )
        .expect("a valid camera");
        let refs: Vec<RefPatch> = patches.iter().map(|p| RefPatch::from_kernel(&p)).collect();
        let mut grid = 0;
        let mut counts = [0usize; 5];
        let mut bins = [0usize; 3];
        let mut shared_median = f64::NAN;
        let mut lattice_ratios = [f64::NAN; BINTREE_LATTICES.len()];
        let mut kept_ratios = [f64::NAN; BINTREE_KEPT.len()];
        let mut baked_counts = [0usize; BAKES.len()];
        let mut ratios: Vec<f64> = Vec::new();
        let selections = [
            Selection::Adaptive,
            Selection::Nested,
            Selection::NestedPatchScale,
            Selection::Isotropic,
            Selection::Directional,
        ];
        for (p, r) in refs.iter().enumerate() {
            let patch = patches.patch(p).expect("a patch");
            for (count, b) in baked_counts.iter_mut().zip(&baked) {
                let steps: Vec<GridPoint> = b
                    .patch(p)
                    .expect("a baked patch")
                    .samples
                    .iter()
                    .map(|s| s.point)
                    .collect();
                *count += per_sample(&patch, r, &steps, &meter, &camera, tol, rounds);
            }
            grid += grid_size(r, tol, GRID_DENSE, 512, Measure::Screen(&meter))
                .map_or(2 * 511 * 511, |n| 2 * (n - 1) * (n - 1));
            for (count, &selection) in counts.iter_mut().zip(&selections) {
                if per_sample_only {
                    continue;
                }
                let triangles = oracle(r, &meter, tol, selection);
                *count += triangles.len();
                if selection == Selection::Directional {
                    ratios.extend(bound_over_true(r, &triangles, &meter));
                }
            }
        }
        if !per_sample_only {
            let unit = bintree::unit;
            let apart = |p: usize, [u, v]: [u32; 2]| [p as i64, u as i64, v as i64];
            // Model space: a shared curve's point computed from either patch lands on one spot.
            let shared = |p: usize, g: [u32; 2]| bintree::model_spot(&refs, diag as f64, p, g);
            let sampled = |(p, t): Bin| measure(&refs[p], t.map(unit), &meter).0.error;
            let grid_points = |t: [[u32; 2]; 3]| {
                t.map(|g| {
                    let [u, v] = unit(g);
                    GridPoint::from_unit(u as f32, v as f32)
                })
            };
            let bounded = |(p, t): Bin| {
                let patch = patches.patch(p).expect("a patch");
                triangle_screen_bound(&patch, grid_points(t), &camera) as f64
            };
            bins[0] = bintree(refs.len(), tol, apart, sampled).len();
            bins[1] = bintree(refs.len(), tol, apart, bounded).len();
            let leaves = bintree(refs.len(), tol, shared, bounded);
            bins[2] = leaves.len();
            for (ratio, n) in lattice_ratios.iter_mut().zip(BINTREE_LATTICES) {
                let bound = |(p, t): Bin| {
                    screen_bound_kept(&refs[p], t.map(unit), &meter, n, usize::MAX)
                        .map_or(f64::INFINITY, |b| b.hull)
                };
                *ratio = bintree(refs.len(), tol, shared, bound).len() as f64 / grid as f64;
            }
            if !in_model_space.iter().any(|(m, _)| *m == model) {
                // Every triangle a bake of the model to `rel` of its diagonal must hold a bound
                // for is a node of this mesh (its leaves, and about as many above them).
                let object = |(p, t): Bin| {
                    screen_bound_kept(&refs[p], t.map(unit), &meter, 6, usize::MAX)
                        .map_or(f64::INFINITY, |b| b.object)
                };
                let leaves = BAKES
                    .map(|rel| bintree(refs.len(), rel as f64 * diag as f64, shared, object).len())
                    .to_vec();
                in_model_space.push((model, leaves));
            }
            for (ratio, k) in kept_ratios.iter_mut().zip(BINTREE_KEPT) {
                let bound = |(p, t): Bin| {
                    screen_bound_kept(&refs[p], t.map(unit), &meter, 6, k)
                        .map_or(f64::INFINITY, |b| b.hull)
                };
                *ratio = bintree(refs.len(), tol, shared, bound).len() as f64 / grid as f64;
            }
            // The median error on screen over the tolerance, of the triangles that show.
            let mut errors: Vec<f64> = leaves
                .iter()
                .map(|&(p, t)| measure(&refs[p], t.map(unit), &meter).0.error / tol)
                .filter(|&e| e > 0.0)
                .collect();
            errors.sort_by(f64::total_cmp);
            shared_median = errors.get(errors.len() / 2).copied().unwrap_or(f64::NAN);
        }
        ratios.sort_by(f64::total_cmp);
        let cells = |counts: &[usize]| -> Vec<String> {
            counts
                .iter()
                .map(|&c| format!("{c} | {:.2}", c as f64 / grid as f64))
                .collect()
        };
        println!(
            "| {name} | {grid} | {} | {} | {shared_median:.2} | {} | {} | {} | {:.3}, {:.3} | {} |",
            cells(&counts[..3]).join(" | "),
            cells(&bins).join(" | "),
            lattice_ratios.map(|r| format!("{r:.2}")).join(" / "),
            kept_ratios.map(|r| format!("{r:.2}")).join(" / "),
            cells(&counts[3..]).join(" | "),
            ratios.first().copied().unwrap_or(f64::NAN),
            ratios.get(ratios.len() / 2).copied().unwrap_or(f64::NAN),
            cells(&baked_counts).join(" | "),
        );
    }
    println!();
    println!(
        "| model | shared-curve bintree in model space, leaves: at 1e-3 of the diagonal | at 2.5e-4 |"
    );
    println!("|---|---|---|");
    for (model, leaves) in &in_model_space {
        println!("| {model} | {} | {} |", leaves[0], leaves[1]);
    }
}
