//! The run time under arbitrary use: bytes choose a model from a small set, bake caps, run-time
//! settings, and a sequence of views (cameras, object tolerances, budgets, any of them
//! invalid), then every frame is written into small and exact buffers and streamed.
//!
//! What must hold: no panic; a refused write leaves the buffers untouched and says what the
//! mesh needs; every written index points at a written vertex; the stream is the indexed mesh,
//! vertex for vertex; writing or streaming twice, or updating twice to the same view, gives
//! the same output; a budget frame keeps its budget.
//!
//! The work one input asks for is bounded ([`Limits`]), so that a fuzzer runs a hundred
//! inputs a second or more: refinement factors of at most 4 and meshes written in full up to
//! 4,096 triangles. The committed seeds are replayed with the limits lifted as well
//! ([`runtime_unbounded`]: factors up to 255, full writes up to 32,768 triangles).

use std::sync::OnceLock;

use spline_tess::bake::{BakeSettings, BakedModel, Tolerance};
use spline_tess::tessellator::{Settings, StorageSize, Tessellator, TessellatorError};
use spline_tess::{
    Camera, DomainIndex, FrameStats, MeshIndex, Projection, TriangleSink, Vec3, Vertex, View,
    WriteError,
};

use super::bytes::Bytes;
use super::model_file::{bake_to_vec, ModelFile};
use super::runtime_storage::RuntimeStorage;

/// The models: poles (teaspoon, teapot, hemisphere), seams (torus), a degree-1 direction and
/// open edges (quarter cylinder).
pub(crate) const MODELS: [(&str, &str); 5] = [
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

/// Bake variants: relative tolerance, curve cap, interior cap.
const BAKES: [(f32, u16, u16); 3] = [(1e-2, 4, 8), (1e-3, 32, 64), (1e-3, 256, 1024)];

/// What one input may ask for.
pub struct Limits {
    /// Largest refinement factor but for the largest ones (from 240 on, with `wide_factors`).
    pub factors: u8,
    /// Whether factors of 240 and more are asked for.
    pub wide_factors: bool,
    /// Largest mesh written in full (bigger frames are still counted and written into small
    /// buffers).
    pub full_write: usize,
}

/// The limits of the `runtime` target.
pub const FAST: Limits = Limits {
    factors: 4,
    wide_factors: false,
    full_write: 1 << 12,
};

/// The limits lifted: what the target asked for before it had them.
pub const UNBOUNDED: Limits = Limits {
    factors: 8,
    wide_factors: true,
    full_write: 1 << 15,
};

struct Baked {
    file: ModelFile,
    bytes: Vec<u8>,
    diag: f32,
    center: Vec3,
}

/// Model `model` of [`MODELS`], parsed.
pub(crate) fn model_file(model: usize) -> ModelFile {
    let (kind, text) = MODELS[model];
    if kind == "bpt" {
        ModelFile::from_bpt(text)
    } else {
        ModelFile::from_nurbs_json(text)
    }
    .expect("a repository model parses")
}

fn baked(model: usize, bake: usize) -> &'static Baked {
    static CACHE: [[OnceLock<Baked>; BAKES.len()]; MODELS.len()] =
        [const { [const { OnceLock::new() }; BAKES.len()] }; MODELS.len()];
    CACHE[model][bake].get_or_init(|| {
        let file = model_file(model);
        let (tol, curve, interior) = BAKES[bake];
        let settings = BakeSettings {
            tolerance: Tolerance::Relative(tol),
            max_curve_samples: curve,
            max_interior_samples: interior,
        };
        let bytes = file
            .with_model(|m| bake_to_vec(m, &settings))
            .expect("a repository model has a topology")
            .expect("a repository model bakes");
        let aabb = file.patches().aabb().expect("a model has patches");
        Baked {
            diag: aabb.diagonal(),
            center: (aabb.min + aabb.max) * 0.5,
            file,
            bytes,
        }
    })
}

/// Tolerances that must be refused or survived.
pub(crate) const SPECIAL: [f32; 10] = [
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

pub(crate) fn camera(r: &mut Bytes<'_>, center: Vec3, diag: f32) -> Option<Camera> {
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
pub(crate) fn vertex_bits(v: &Vertex) -> [u32; 9] {
    let p = v.position.map(f32::to_bits);
    let n = v.normal.map(f32::to_bits);
    let t = v.uv.map(f32::to_bits);
    [p[0], p[1], p[2], n[0], n[1], n[2], t[0], t[1], v.patch]
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

/// Writes into buffers of the given lengths, checking the promises of `write_mesh`.
fn write_small<I: MeshIndex + PartialEq, Ix: DomainIndex>(
    tess: &mut Tessellator<'_, '_, Ix>,
    vertices: usize,
    triangles: usize,
) {
    let need = tess.mesh_size();
    let marker = Vertex {
        patch: 0xdead_beef,
        ..Vertex::default()
    };
    let mut vs = vec![marker; vertices];
    let mut ts = vec![[I::from_index(7); 3]; triangles];
    match tess.write_mesh(&mut vs, &mut ts) {
        Ok(size) => {
            assert_eq!(size, need);
            for t in &ts[..size.triangles] {
                assert!(
                    t.iter().all(|i| (i.to_u32() as usize) < size.vertices),
                    "{t:?}"
                );
            }
            assert!(vs[size.vertices..].iter().all(|v| *v == marker));
        }
        Err(WriteError::BuffersTooSmall { needed }) => {
            assert_eq!(needed, need);
            assert!(vertices < need.vertices || triangles < need.triangles);
            assert!(
                vs.iter().all(|v| *v == marker) && ts.iter().all(|t| *t == [I::from_index(7); 3])
            );
        }
        Err(WriteError::IndexOverflow { vertices: n }) => {
            assert_eq!(n, need.vertices);
            assert!(n > I::LIMIT);
            assert!(vs.iter().all(|v| *v == marker));
        }
        Err(e @ WriteError::ScratchTooSmall { .. }) => {
            panic!("storage sized by StorageSize::of has the scratch of every frame: {e}")
        }
    }
}

/// Checks the current frame: sizes, small and full writes, the stream, repeatability.
fn check_frame<Ix: DomainIndex>(
    tess: &mut Tessellator<'_, '_, Ix>,
    stats: &FrameStats,
    r: &mut Bytes<'_>,
    full_write: usize,
) {
    let need = tess.mesh_size();
    assert_eq!(
        (need.vertices, need.triangles),
        (stats.vertices, stats.triangles)
    );
    let (sv, st) = (r.u16() as usize, r.u16() as usize);
    if r.u8().is_multiple_of(2) {
        write_small::<u16, Ix>(tess, sv.min(need.vertices + 1), st.min(need.triangles + 1));
    } else {
        write_small::<u32, Ix>(tess, sv.min(need.vertices + 1), st.min(need.triangles + 1));
    }
    if need.triangles > full_write {
        return;
    }
    let mut vs = vec![Vertex::default(); need.vertices];
    let mut ts = vec![[0u32; 3]; need.triangles];
    tess.write_mesh(&mut vs, &mut ts).expect("exact buffers");
    let (vs2, ts2) = {
        let mut vs2 = vec![Vertex::default(); need.vertices];
        let mut ts2 = vec![[0u32; 3]; need.triangles];
        tess.write_mesh(&mut vs2, &mut ts2).expect("exact buffers");
        (vs2, ts2)
    };
    assert!(
        vs.iter().map(vertex_bits).eq(vs2.iter().map(vertex_bits)),
        "write_mesh twice differs"
    );
    assert_eq!(ts, ts2, "write_mesh twice differs");
    for v in &vs {
        assert!(v.position.iter().all(|x| x.is_finite()), "{v:?}");
        assert!(v.normal.iter().all(|x| x.is_finite()), "{v:?}");
    }
    let mut stream = Stream::default();
    tess.stream(&mut stream);
    assert_eq!(
        stream.triangles.len(),
        ts.len(),
        "stream and write_mesh disagree on the count"
    );
    for ((_, corners), t) in stream.triangles.iter().zip(&ts) {
        let indexed = t.map(|i| vertex_bits(&vs[i as usize]));
        assert_eq!(*corners, indexed, "the stream is not the indexed mesh");
    }
    let mut again = Stream::default();
    tess.stream(&mut again);
    assert!(again == stream, "stream twice differs");
}

/// The `runtime` target.
pub fn runtime(data: &[u8]) {
    run(data, &FAST);
}

/// The `runtime` target with its limits lifted (for the committed seeds).
pub fn runtime_unbounded(data: &[u8]) {
    run(data, &UNBOUNDED);
}

fn run(data: &[u8], limits: &Limits) {
    let mut r = Bytes::new(data);
    let model = r.u8() as usize % MODELS.len();
    let bake = r.u8() as usize % BAKES.len();
    let b = baked(model, bake);
    let baked = BakedModel::from_bytes(&b.bytes).expect("a fresh bake reads back");
    // Factors past 8 only make meshes slower to check; the largest ones stay possible.
    let max_factor = match r.u8() {
        x @ 240.. if limits.wide_factors => x,
        x => x % (limits.factors + 1),
    };
    let max_interior_samples = match r.u8() {
        0..=199 => u16::MAX,
        x => u16::from(x - 200) * 4,
    };
    let settings = Settings {
        max_interior_samples,
        max_factor,
        ..Settings::default()
    };
    // The same frames over a pool of `u16` slot numbers, then of `u8` ones (where the bake's
    // curve samples fit a one-byte mesh).
    let frames = r.clone();
    let mut storage = RuntimeStorage::new(&baked, &settings);
    let tess = storage.tessellator(b.file.patches(), baked, settings);
    run_frames(tess, b, r, limits);
    let size = StorageSize::of_indexed::<u8>(&baked, &settings);
    let mut storage = RuntimeStorage::<u8>::indexed(&size);
    match storage.try_tessellator(b.file.patches(), baked, settings) {
        Ok(tess) => run_frames(tess, b, frames, limits),
        Err(TessellatorError::PatchTooLarge { .. }) => {}
        Err(e) => panic!("storage sized by StorageSize::of_indexed: {e}"),
    }
}

/// Up to six frames of `r`'s views, each checked.
fn run_frames<Ix: DomainIndex>(
    mut tess: Tessellator<'_, '_, Ix>,
    b: &Baked,
    mut r: Bytes<'_>,
    limits: &Limits,
) {
    for _ in 0..6 {
        if r.is_empty() {
            break;
        }
        let kind = r.u8() % 4;
        let view = if kind == 0 {
            View::Object {
                tolerance: r.value(&SPECIAL, 0.01 * b.diag),
            }
        } else {
            let Some(camera) = camera(&mut r, b.center, b.diag) else {
                continue;
            };
            View::Screen {
                camera,
                tolerance_px: r.value(&SPECIAL, 1.0),
            }
        };
        let stats = match kind {
            3 => {
                let budget = r.u16() as usize;
                match tess.update_to_budget(&view, budget) {
                    Ok((stats, fit)) => {
                        assert!(
                            stats.triangles <= budget,
                            "{} > budget {budget}",
                            stats.triangles
                        );
                        assert!(
                            fit.tolerance > 0.0
                                && fit.triangles == stats.triangles
                                && fit.bound == stats.max_predicted_error,
                            "{fit:?} {stats:?}"
                        );
                        stats
                    }
                    Err(e) => {
                        let _ = e.to_string();
                        continue;
                    }
                }
            }
            2 => match tess.update_unrefined(&view) {
                Ok(s) => s,
                Err(e) => {
                    let _ = e.to_string();
                    continue;
                }
            },
            _ => match tess.update(&view) {
                Ok(s) => s,
                Err(e) => {
                    let _ = e.to_string();
                    continue;
                }
            },
        };
        check_frame(&mut tess, &stats, &mut r, limits.full_write);
        // The same view again changes nothing.
        if kind == 1 {
            let before = tess.mesh_size();
            let again = tess.update(&view).expect("the same view updates again");
            assert_eq!((again.inserted, again.deleted), (0, 0), "{again:?}");
            assert_eq!(tess.mesh_size(), before);
        }
    }
}
