//! The tessellator under arbitrary use: bytes choose a model of a small set, a bake tolerance, the run time's stack and pool sizes, and a sequence of views
//! (cameras, object tolerances, budgets, any of them invalid); every frame is written into
//! small and exact buffers and streamed.
//!
//! What must hold: no panic; a tolerance is refused exactly when it is not a positive finite
//! number; a refused write leaves the buffers untouched; every written index points at a
//! written vertex; the stream is the indexed mesh, vertex for vertex; a frame with nothing left
//! over is within its tolerance by its own bound, and one whose pool filled up leaves some; the same view again gives the
//! same mesh, and so does a run time with another stack (history and storage do not matter); a
//! budget frame keeps its budget.
//!
//! The work one input asks for is bounded ([`Limits`]), so that a fuzzer runs hundreds of
//! inputs a second: a pool below the bake of at most 128 vertices and budgets of at most
//! 4,096 triangles. The committed seeds are replayed with the limits lifted as well
//! ([`bisect_unbounded`]: pools of 4,096 and budgets up to 65,535), which is where the slow
//! cases found before the limits stay covered.

use std::sync::OnceLock;

use spline_tess::bake::BakeSettings;
use spline_tess::bake::Tolerance;
use spline_tess::tessellator::{PoolSlot, StackSlot, Tessellator};
use spline_tess::Arithmetic;
use spline_tess::{Camera, Projection, TriangleSink, Vec3, Vertex, View, WriteError};

use super::bytes::Bytes;
use super::model_file::{BakedHierarchy, ModelFile};

/// The models: poles (teaspoon, teapot, hemisphere), seams (torus), a degree-1 direction and
/// open edges (quarter cylinder).
const MODELS: [(&str, &str); 5] = [
    ("bpt", include_str!("../../examples/models/teaspoon.bpt")),
    ("bpt", include_str!("../../examples/models/teapot.bpt")),
    (
        "json",
        include_str!("../../examples/models/nurbs/tinynurbs_hemisphere.json"),
    ),
    (
        "json",
        include_str!("../../examples/models/nurbs/rational_torus.json"),
    ),
    (
        "json",
        include_str!("../../examples/models/nurbs/verb_quarter_cylinder.json"),
    ),
];

/// Model `model` of [`MODELS`], parsed.
fn model_file(model: usize) -> ModelFile {
    let (kind, text) = MODELS[model];
    if kind == "bpt" {
        ModelFile::from_bpt(text)
    } else {
        ModelFile::from_nurbs_json(text)
    }
    .expect("a repository model parses")
}

/// Tolerances that must be refused or survived.
const SPECIAL: [f32; 10] = [
    1.0,
    0.5,
    2.0,
    0.0,
    -1.0,
    f32::NAN,
    f32::INFINITY,
    1e-7,
    1e30,
    f32::MIN_POSITIVE,
];

fn camera(r: &mut Bytes<'_>, center: Vec3, diag: f32) -> Option<Camera> {
    let coord = |r: &mut Bytes<'_>, s: f32| r.i8() as f32 / 32.0 * s;
    let eye = center + Vec3::new(coord(r, diag), coord(r, diag), coord(r, diag));
    let target = center
        + Vec3::new(
            coord(r, 0.25 * diag),
            coord(r, 0.25 * diag),
            coord(r, 0.25 * diag),
        );
    let up = match r.u8() % 4 {
        0 => Vec3::Z,
        1 => Vec3::Y,
        2 => Vec3::X,
        _ => Vec3::new(r.i8() as f32, r.i8() as f32, r.i8() as f32),
    };
    let projection = if r.u8().is_multiple_of(4) {
        Projection::Orthographic {
            height: r.value(&[0.0, -1.0, f32::NAN], diag),
        }
    } else {
        Projection::Perspective {
            fov_y_degrees: r.value(&[40.0, 60.0, 0.0, 180.0, 179.9, f32::NAN], 30.0),
        }
    };
    let near = r.value(&[0.0, -1.0, f32::INFINITY], 0.01 * diag);
    let viewport = [(r.u16() % 1200) as u32, (r.u16() % 900) as u32];
    Camera::new(eye, target, up, projection, near, viewport).ok()
}

/// Bit-exact digest of a vertex.
fn vertex_bits(v: &Vertex) -> [u32; 9] {
    let p = v.position.map(f32::to_bits);
    let n = v.normal.map(f32::to_bits);
    let t = v.uv.map(f32::to_bits);
    [p[0], p[1], p[2], n[0], n[1], n[2], t[0], t[1], v.patch]
}

/// Bake tolerances, relative to the diagonal.
const BAKES: [f32; 2] = [1e-2, 3e-3];

fn baked(model: usize, bake: usize) -> &'static BakedHierarchy {
    static CACHE: [[OnceLock<BakedHierarchy>; BAKES.len()]; MODELS.len()] =
        [const { [const { OnceLock::new() }; BAKES.len()] }; MODELS.len()];
    CACHE[model][bake].get_or_init(|| {
        let file = model_file(model);
        let settings = BakeSettings {
            tolerance: Tolerance::Relative(BAKES[bake]),
            ..BakeSettings::default()
        };
        BakedHierarchy::bake(&file, &settings).expect("a repository model bakes")
    })
}

/// Collects the stream.
#[derive(Default, PartialEq)]
struct Stream {
    triangles: Vec<(u32, [[u32; 9]; 3])>,
}

impl TriangleSink for Stream {
    fn triangle(&mut self, patch: u32, corners: [&Vertex; 3]) {
        self.triangles.push((patch, corners.map(vertex_bits)));
    }
}

/// The current frame written whole (`None` past `limit` triangles), after a write into small
/// buffers that must be refused untouched or succeed.
fn written(
    s: &mut Tessellator<'_, '_>,
    r: &mut Bytes<'_>,
    limit: usize,
) -> Option<(Vec<Vertex>, Vec<[u32; 3]>)> {
    let need = s.mesh_size();
    let mut remap = vec![0u32; s.remap_len()];
    let marker = Vertex {
        patch: 0xdead_beef,
        ..Vertex::default()
    };
    let (sv, st) = (
        (r.u16() as usize).min(need.vertices + 1),
        (r.u16() as usize).min(need.triangles + 1),
    );
    let mut vs = vec![marker; sv];
    let mut ts = vec![[7u32; 3]; st];
    match s.write_mesh(&mut vs, &mut ts, &mut remap) {
        Ok(size) => {
            assert_eq!(size, need);
            assert!(vs[size.vertices..].iter().all(|v| *v == marker));
        }
        Err(WriteError::BuffersTooSmall { needed }) => {
            assert_eq!(needed, need);
            assert!(vs.iter().all(|v| *v == marker) && ts.iter().all(|t| *t == [7; 3]));
        }
        Err(e) => panic!("a write into remap_len entries: {e}"),
    }
    if need.triangles > limit {
        return None;
    }
    let mut vs = vec![Vertex::default(); need.vertices];
    let mut ts = vec![[0u32; 3]; need.triangles];
    s.write_mesh(&mut vs, &mut ts, &mut remap)
        .expect("exact buffers");
    for t in &ts {
        assert!(t.iter().all(|&i| (i as usize) < vs.len()), "{t:?}");
    }
    let mut stream = Stream::default();
    s.stream(&mut stream);
    assert_eq!(stream.triangles.len(), ts.len(), "stream != mesh count");
    for ((_, corners), t) in stream.triangles.iter().zip(&ts) {
        assert_eq!(
            *corners,
            t.map(|i| vertex_bits(&vs[i as usize])),
            "the stream is not the indexed mesh"
        );
    }
    Some((vs, ts))
}

/// What one input may ask for.
pub struct Limits {
    /// The pool sizes a byte chooses from.
    pub pools: [usize; 4],
    /// Budgets are below this.
    pub budgets: usize,
}

/// The limits of the `bisect` target.
pub const FAST: Limits = Limits {
    pools: [0, 16, 64, 128],
    budgets: 4097,
};

/// The limits lifted: what the target asked for before it had them.
pub const UNBOUNDED: Limits = Limits {
    pools: [0, 16, 256, 4096],
    budgets: 1 << 16,
};

/// The `bisect` target.
pub fn bisect(data: &[u8]) {
    run(data, &FAST);
}

/// The `bisect` target with its limits lifted (for the committed seeds).
pub fn bisect_unbounded(data: &[u8]) {
    run(data, &UNBOUNDED);
}

fn run(data: &[u8], limits: &Limits) {
    let mut r = Bytes::new(data);
    let model = r.u8() as usize % MODELS.len();
    let bake = r.u8() as usize % BAKES.len();
    let b = baked(model, bake);
    let tree = b.tree();
    let stack = 4 + r.u8() as usize % 64;
    let pool = limits.pools[r.u8() as usize % 4];
    let mut bits = vec![0u32; tree.bit_words()];
    let mut stack_slots = vec![StackSlot::default(); stack];
    let mut pool_slots = vec![PoolSlot::default(); pool];
    // Bounds in either arithmetic, by the stack's parity (no byte of its own: the seeds keep
    // their meaning).
    let arithmetic = match stack % 2 {
        0 => Arithmetic::Float,
        _ => Arithmetic::Integer,
    };
    let mut s = Tessellator::from_slices(tree, &mut bits, &mut stack_slots, &mut pool_slots)
        .expect("storage sized for the tree")
        .with_arithmetic(arithmetic);
    let aabb = b.file.patches().aabb().expect("a model has patches");
    let (center, diag) = ((aabb.min + aabb.max) * 0.5, aabb.diagonal());
    for _ in 0..4 {
        if r.is_empty() {
            break;
        }
        let view = match r.u8() % 3 {
            0 => View::Object {
                tolerance: r.value(&SPECIAL, 2e-3) * diag,
            },
            _ => match camera(&mut r, center, diag) {
                Some(camera) => View::Screen {
                    camera,
                    tolerance_px: r.value(&SPECIAL, 1.0),
                },
                None => continue,
            },
        };
        if r.u8().is_multiple_of(4) {
            let budget = r.u16() as usize % limits.budgets;
            if let Ok(fit) = s.update_to_budget(&view, budget) {
                assert!(fit.stats.triangles <= budget, "over budget");
            }
            continue;
        }
        let tolerance = view.tolerance();
        let valid = tolerance > 0.0 && tolerance.is_finite();
        let stats = match s.update(&view) {
            Ok(stats) => stats,
            Err(e) => {
                assert!(!valid, "tolerance {tolerance} refused: {e}");
                continue;
            }
        };
        assert!(valid, "tolerance {tolerance} taken");
        if stats.left_over == 0 {
            assert!(
                stats.worst_bound <= tolerance,
                "bound {} over {tolerance} with nothing left over",
                stats.worst_bound
            );
        }
        assert!(
            !stats.pool_full || stats.left_over > 0,
            "a full pool leaves leaves over: {stats:?} pool {pool} view {view:?}"
        );
        let Some(first) = written(&mut s, &mut r, 1 << 14) else {
            continue;
        };
        s.update(&view).expect("the same view again");
        let again = written(&mut s, &mut r, 1 << 14).expect("the same frame again");
        assert!(first == again, "the same view twice differs");
    }
}
