//! The OBJ that `host::Mesh::write_obj` writes (and `tessellate` and `teapot` with it) keeps
//! every face's own parameters.
//!
//! For every face of every model in `examples/models` (the tea set and Gumbo, with their
//! poles, and the NURBS fixtures, with their seams and poles), in object mode and in several
//! views, the surface evaluated by the `f64` reference at each corner's `vt` (in the file's
//! parameters: the patch's for BPT, the surface's knots for NURBS) is that corner's `v`, to
//! within 1e-5 of the model's bounding-box diagonal. Positions stay shared by index (each
//! `v` is one mesh vertex), so the mesh stays welded while a vertex that several faces see
//! at different parameters gets several `vt`.

use std::collections::{HashMap, HashSet};

use host_tests::model_file::ModelFile;
use host_tests::reference::{self, RefNurbs, RefPatch, V3};
use host_tests::runtime::{indexed, BakedHierarchy, VecStorage};
use host_tests::{bpt_models, name, nurbs_fixtures};
use spline_tess::bake::BakeSettings;
use spline_tess::bake::Tolerance;
use spline_tess::host::Mesh;
use spline_tess::{Camera, Projection, Vec3, View};

const BAKE: BakeSettings = BakeSettings {
    tolerance: Tolerance::Relative(1e-3),
    max_depth: 24,
    max_cell_level: spline_tess::tessellator::MAX_CELL_LEVEL,
};

/// Largest distance between `v` and the surface at `vt`, over the diagonal.
const LIMIT: f64 = 1e-5;

/// The `f64` surface of a model file.
enum Surface {
    Patches(Vec<RefPatch>),
    Nurbs(RefNurbs),
}

impl Surface {
    fn point(&self, group: usize, u: f64, v: f64) -> V3 {
        match self {
            Surface::Patches(p) => p[group].point(u, v),
            Surface::Nurbs(n) => n.eval(u, v).p,
        }
    }
}

/// What the OBJ text holds.
#[derive(Default)]
struct Obj {
    v: Vec<V3>,
    vt: Vec<[f64; 2]>,
    vn: usize,
    /// `(group, [(v, vt, vn); 3])`, indices from 0.
    faces: Vec<(usize, [[usize; 3]; 3])>,
}

fn parse(text: &str) -> Obj {
    let mut obj = Obj::default();
    let mut group = usize::MAX;
    for line in text.lines() {
        let mut words = line.split_whitespace();
        let num = |w: Option<&str>| w.unwrap().parse::<f64>().unwrap();
        match words.next() {
            Some("v") => obj
                .v
                .push([num(words.next()), num(words.next()), num(words.next())]),
            Some("vt") => obj.vt.push([num(words.next()), num(words.next())]),
            Some("vn") => obj.vn += 1,
            Some("g") => {
                let g = words.next().unwrap();
                group = g.strip_prefix("patch_").unwrap().parse().unwrap();
            }
            Some("f") => {
                let corner = |w: &str| -> [usize; 3] {
                    let ix: Vec<usize> = w.split('/').map(|x| x.parse().unwrap()).collect();
                    assert_eq!(ix.len(), 3, "f v/vt/vn expected, got {w}");
                    [ix[0] - 1, ix[1] - 1, ix[2] - 1]
                };
                let c: Vec<[usize; 3]> = words.map(corner).collect();
                assert_eq!(c.len(), 3, "{line}");
                assert_ne!(group, usize::MAX, "a face before any group");
                obj.faces.push((group, [c[0], c[1], c[2]]));
            }
            _ => {}
        }
    }
    obj
}

fn views(center: Vec3, diag: f32) -> Vec<(&'static str, View)> {
    let dir = Vec3::new(1.0, -2.0, 0.7).normalize();
    let camera = |eye: Vec3, target: Vec3, fov: f32, tol: f32| View::Screen {
        camera: Camera::new(
            eye,
            target,
            Vec3::Z,
            Projection::Perspective { fov_y_degrees: fov },
            0.02 * diag,
            [320, 240],
        )
        .unwrap(),
        tolerance_px: tol,
    };
    vec![
        (
            "object coarse",
            View::Object {
                tolerance: 1e-2 * diag,
            },
        ),
        (
            "object fine",
            View::Object {
                tolerance: 5e-4 * diag,
            },
        ),
        (
            "far",
            camera(center + dir * (3.0 * diag), center, 40.0, 1.0),
        ),
        (
            "near",
            camera(center + dir * (0.6 * diag), center, 50.0, 0.5),
        ),
        ("inside", camera(center, center + Vec3::X, 60.0, 2.0)),
    ]
}

#[test]
fn every_face_corner_carries_its_own_parameters() {
    let models: Vec<_> = bpt_models().into_iter().chain(nurbs_fixtures()).collect();
    let mut shared_total = 0usize;
    for path in models {
        let label = name(&path);
        let text = std::fs::read_to_string(&path).unwrap();
        let nurbs = label.ends_with(".json");
        let file = ModelFile::read(path.to_str().unwrap()).unwrap();
        let surfaces = file.surfaces();
        let surface = if nurbs {
            Surface::Nurbs(RefNurbs::read(&text))
        } else {
            Surface::Patches(reference::read_bpt(&text))
        };
        let baked = BakedHierarchy::bake(&file, &BAKE).unwrap();
        let tree = baked.tree();
        let bounds = file.patches().aabb().unwrap();
        let diag = bounds.diagonal();
        let center = (bounds.min + bounds.max) * 0.5;
        let mut storage = VecStorage::new(&tree, 1024, 1 << 16);
        let mut selection = storage.tessellator(tree);
        for (view_label, view) in views(center, diag) {
            let stats = selection.update(&view).unwrap();
            let mesh = indexed(&mut selection);
            let mut text = Vec::new();
            Mesh::of_frame(&mut selection, &surfaces, stats)
                .unwrap()
                .write_obj(&mut text)
                .unwrap();
            let obj = parse(&String::from_utf8(text).unwrap());
            let at = format!("{label}, {view_label}");
            assert_eq!(obj.v.len(), mesh.vertices.len(), "{at}: one v per vertex");
            assert_eq!(obj.vn, mesh.vertices.len(), "{at}: one vn per vertex");
            assert_eq!(
                obj.faces.len(),
                mesh.triangles.len(),
                "{at}: one f per triangle"
            );
            let mut worst = 0.0f64;
            let mut texture_of: HashMap<usize, HashSet<usize>> = HashMap::new();
            for (k, (group, corners)) in obj.faces.iter().enumerate() {
                for (c, &[v, vt, vn]) in corners.iter().enumerate() {
                    assert_eq!(
                        v, mesh.triangles[k][c] as usize,
                        "{at}: face {k} welded by index"
                    );
                    assert_eq!(vn, v, "{at}: face {k}: vn is the vertex's");
                    let [u, w] = obj.vt[vt];
                    let s = surface.point(*group, u, w);
                    worst = worst.max(reference::dist(s, obj.v[v]) / diag as f64);
                    texture_of.entry(v).or_default().insert(vt);
                }
            }
            assert!(
                worst <= LIMIT,
                "{at}: a corner's v is {worst:e} x diagonal from the surface at its vt"
            );
            let shared = texture_of.values().filter(|s| s.len() > 1).count();
            shared_total += shared;
            println!(
                "{at}: {} faces, {} v, {} vt, {shared} vertices with several vt, worst {worst:.1e}",
                obj.faces.len(),
                obj.v.len(),
                obj.vt.len()
            );
        }
    }
    // Shared curves, poles and seams are everywhere in these models: the per-face rule must
    // have been exercised.
    assert!(shared_total > 1000, "{shared_total}");
}
