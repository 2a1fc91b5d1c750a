//! Checks the run-time tests share: a camera path through and around a model, the measured
//! deviation of a frame, and watertightness of an indexed mesh.

use std::collections::{HashMap, HashSet};

use spline_tess::{Camera, Projection, Vec3, View};

use crate::reference::RefPatch;
use crate::runtime::Streamed;
use crate::screen::{triangle_deviation, Measure, Meter};
use crate::widen;

/// Barycentric steps of the dense deviation check.
pub const DENSE: usize = 8;
/// The viewport of the path's cameras.
pub const VIEWPORT: [u32; 2] = [160, 120];

/// One view of a camera path: a name, the view, and the tests' own camera for it.
pub struct Step {
    /// Name in messages.
    pub label: &'static str,
    /// The view.
    pub view: View,
    /// The `f64` camera (none in object mode).
    pub meter: Option<Meter>,
}

/// Views of a model (centre, diagonal, lowest point) from far to inside it, grazing, looking
/// away, and in object mode.
pub fn camera_path(center: Vec3, diag: f32, floor: f32) -> Vec<Step> {
    let dir = Vec3::new(1.0, -2.0, 0.7).normalize();
    let near = 0.02 * diag;
    let camera = |label, eye: Vec3, target: Vec3, fov: f32, tol: f32| {
        let cam = Camera::new(
            eye,
            target,
            Vec3::Z,
            Projection::Perspective { fov_y_degrees: fov },
            near,
            VIEWPORT,
        )
        .unwrap();
        Step {
            label,
            view: View::Screen {
                camera: cam,
                tolerance_px: tol,
            },
            meter: Some(Meter::new(
                widen(eye),
                widen(target),
                [0.0, 0.0, 1.0],
                fov as f64,
                near as f64,
                VIEWPORT,
            )),
        }
    };
    let low = Vec3::new(center.x, center.y, floor + 0.05 * diag);
    vec![
        camera("far", center + dir * (3.0 * diag), center, 40.0, 1.0),
        // From below: a closed model shows the eye some patches' backs whole.
        camera(
            "far below",
            center + Vec3::new(-0.5, -0.5, -0.7).normalize() * (3.0 * diag),
            center,
            40.0,
            1.0,
        ),
        camera("mid", center + dir * (1.2 * diag), center, 40.0, 0.5),
        camera("near", center + dir * (0.6 * diag), center, 50.0, 1.0),
        camera("grazing", low + Vec3::X * (1.5 * diag), low, 40.0, 1.0),
        camera("inside", center, center + Vec3::X, 60.0, 2.0),
        camera(
            "behind",
            center + dir * (0.4 * diag),
            center + dir * (3.0 * diag),
            60.0,
            1.0,
        ),
        Step {
            label: "object",
            view: View::Object {
                tolerance: 2e-3 * diag,
            },
            meter: None,
        },
        camera("far again", center + dir * (3.0 * diag), center, 40.0, 1.0),
    ]
}

/// Largest measured deviation of the frame's triangles (on screen, or in model units), and
/// the smallest ratio of a triangle's bound from the kernel to its measured deviation in model
/// units.
pub fn measure_frame(refs: &[RefPatch], tris: &[Streamed], meter: Option<&Meter>) -> (f64, f64) {
    let (mut worst, mut tightest) = (0.0f64, f64::INFINITY);
    for t in tris {
        let r = &refs[t.patch as usize];
        let corners = t.corners.map(|c| c.position.map(|x| x as f64));
        let uv = t.uv.map(|[u, v]| [u as f64, v as f64]);
        let object = triangle_deviation(r, uv, corners, DENSE, Measure::Object);
        if object.worst > 0.0 {
            tightest = tightest.min(t.bound as f64 / object.worst);
        }
        let m = match meter {
            None => object,
            Some(m) => triangle_deviation(r, uv, corners, DENSE, Measure::Screen(m)),
        };
        worst = worst.max(m.worst);
    }
    (worst, tightest)
}

/// Watertightness of the indexed mesh; `open(patch, side)` says whether an edge may be
/// used once there. Through a camera, an edge may also be used once where it lies beyond one
/// of the view's planes (the kernel leaves out triangles off the view): a gap there is out of
/// sight. Returns the count of such edges.
///
/// An edge is its two vertices and the surface point at the middle of its parameters (from
/// `refs`, to a millionth of the mesh's size): two surface curves with the same ends, each
/// drawn as one chord (the two halves of the teapot handle's cross-section, far away), are two
/// edges on one segment, each with its two triangles, not one edge with four. An edge at a
/// pole (a vertex one patch uses at two parameters) is its two vertices alone: the triangles
/// around a pole meet along segments from it whose parameters differ.
pub fn check_watertight(
    label: &str,
    mesh: &crate::runtime::Mesh,
    tris: &[Streamed],
    open: &dyn Fn(u32, usize) -> bool,
    meter: Option<&Meter>,
    refs: &[RefPatch],
) -> usize {
    check_watertight_of_parts(label, mesh, tris, open, meter, refs, &|p, [u, v]| {
        (p, [u as f64, v as f64])
    })
}

/// [`check_watertight`] of a model whose patches are parts of others (`PatchSet::split`):
/// `origin(patch, uv)` names a triangle corner's patch and parameters in the model the parts
/// come from, so that a surface passing through one point at two parameters of one patch of
/// it (two of its parts) is not taken for a crack.
pub fn check_watertight_of_parts(
    label: &str,
    mesh: &crate::runtime::Mesh,
    tris: &[Streamed],
    open: &dyn Fn(u32, usize) -> bool,
    meter: Option<&Meter>,
    refs: &[RefPatch],
    origin: &dyn Fn(u32, [f32; 2]) -> (u32, [f64; 2]),
) -> usize {
    let mut out_of_sight = 0;
    let size = mesh
        .vertices
        .iter()
        .flat_map(|v| v.position)
        .fold(1e-30f64, |m, x| m.max((x as f64).abs()));
    let near = size * 1e-5;
    // Vertices a patch uses on a side collapsed to a pole, or at two parameters.
    let mut first: HashMap<u32, (u32, [u32; 2])> = HashMap::new();
    let mut poles: HashSet<u32> = HashSet::new();
    for (t, s) in mesh.triangles.iter().zip(tris) {
        let collapsed = refs[s.patch as usize].collapsed();
        for (&v, uv) in t.iter().zip(s.uv) {
            let here = (s.patch, uv.map(f32::to_bits));
            let seen = *first.entry(v).or_insert(here);
            let on_pole = (collapsed[0] && uv[1] == 0.0)
                || (collapsed[1] && uv[0] == 1.0)
                || (collapsed[2] && uv[1] == 1.0)
                || (collapsed[3] && uv[0] == 0.0);
            if on_pole || (seen.0 == here.0 && seen.1 != here.1) {
                poles.insert(v);
            }
        }
    }
    // The surface point at the middle of an edge's parameters (none at a pole).
    let middle = |k: usize, i: usize, j: usize| {
        let (t, s) = (mesh.triangles[k], &tris[k]);
        if poles.contains(&t[i]) || poles.contains(&t[j]) {
            return None;
        }
        let (x, y) = (s.uv[i], s.uv[j]);
        let mid = [(x[0] + y[0]) as f64 / 2.0, (x[1] + y[1]) as f64 / 2.0];
        Some(refs[s.patch as usize].point(mid[0], mid[1]))
    };
    // Per vertex pair, its edges: a middle point, the uses, the first triangle, and the
    // distinct triangles on it. Coincident patches (the teacup's bottom is two patches on
    // top of each other, facing opposite ways) make coincident triangles; an edge may be
    // used by more than two triangles only through such duplicates.
    type Edge = (Option<[f64; 3]>, usize, usize, HashSet<[u32; 3]>);
    let mut pairs: HashMap<(u32, u32), Vec<Edge>> = HashMap::new();
    for (k, t) in mesh.triangles.iter().enumerate() {
        let mut sorted = *t;
        sorted.sort();
        for i in 0..3 {
            let j = (i + 1) % 3;
            let m = middle(k, i, j);
            let edges = pairs.entry((t[i].min(t[j]), t[i].max(t[j]))).or_default();
            let same = |e: &&mut Edge| match (e.0, m) {
                (Some(p), Some(q)) => crate::reference::dist(p, q) <= near,
                (None, None) => true,
                _ => false,
            };
            match edges.iter_mut().find(|e| same(e)) {
                Some(e) => {
                    e.1 += 1;
                    e.3.insert(sorted);
                }
                None => edges.push((m, 1, k, HashSet::from([sorted]))),
            }
        }
    }
    let uses = pairs
        .iter()
        .flat_map(|(&(a, b), edges)| edges.iter().map(move |e| ((a, b), e.1, e.2, e.3.len())));
    for ((a, b), n, k, distinct) in uses {
        // An edge from a vertex to itself (the side of a triangle on a pole) has no length:
        // nothing is across it, and the pole's triangles all have one.
        if a == b {
            continue;
        }
        assert!(
            distinct <= 2 && (n <= 2 || n == 2 * distinct),
            "{label}: edge {a}-{b} used by {n} triangles, {distinct} distinct"
        );
        if n == 1 {
            let t = &tris[k];
            let pa = mesh.vertices[a as usize].position;
            let pb = mesh.vertices[b as usize].position;
            if meter.is_some_and(|m| m.outside_one_plane(&[pa, pb].map(|p| p.map(f64::from)))) {
                out_of_sight += 1;
                continue;
            }
            let ia = t.corners.iter().position(|c| c.position == pa).unwrap();
            let pb = mesh.vertices[b as usize].position;
            let ib = t.corners.iter().position(|c| c.position == pb).unwrap();
            let (x, y) = (t.uv[ia], t.uv[ib]);
            let side = if x[1] == 0.0 && y[1] == 0.0 {
                0
            } else if x[0] == 1.0 && y[0] == 1.0 {
                1
            } else if x[1] == 1.0 && y[1] == 1.0 {
                2
            } else if x[0] == 0.0 && y[0] == 0.0 {
                3
            } else {
                panic!(
                    "{label}: interior edge {x:?}-{y:?} of patch {} used once",
                    t.patch
                )
            };
            assert!(
                open(t.patch, side),
                "{label}: edge on shared side {side} of patch {} used once",
                t.patch
            );
        }
    }
    let mut seen: HashMap<[u32; 3], u32> = HashMap::new();
    for (i, v) in mesh.vertices.iter().enumerate() {
        if let Some(j) = seen.insert(v.position.map(f32::to_bits), i as u32) {
            // Nodes of culled patches are written but unused; only used vertices count.
            let used = |x: u32| mesh.triangles.iter().any(|t| t.contains(&x));
            // A surface may pass through one point at two parameters of one patch (the
            // teaspoon's nearly collapsed side u = 1 of patch 12 is at (0, -1, 0.0178571) at
            // v = 0.25 and at v = 1, bit for bit): such vertices are distinct. A crack
            // would be one curve point made twice, by two patches.
            let at = |x: u32| {
                tris.iter().zip(&mesh.triangles).filter_map(move |(t, ti)| {
                    Some(origin(t.patch, t.uv[ti.iter().position(|&y| y == x)?]))
                })
            };
            let twice_in_one_patch =
                at(i as u32).any(|(p, a)| at(j).any(|(q, b)| p == q && a != b));
            assert!(
                !(used(i as u32) && used(j)) || twice_in_one_patch,
                "{label}: vertices {j} and {i} share a position {:?}",
                v.position
            );
        }
    }
    out_of_sight
}
