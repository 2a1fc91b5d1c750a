//! Writing a frame's mesh as Wavefront OBJ, with each face's own patch parameters.
//!
//! Positions (`v`) and normals (`vn`) are the indexed mesh's vertices, shared by index, so the
//! mesh stays welded. Texture coordinates (`vt`) are per face corner: a vertex that several
//! patches share (a boundary curve, a patch corner), a pole (a collapsed side, one vertex for
//! a whole side of the square) or a vertex on the seam of a closed NURBS surface (at `u = 0`
//! and `u = 1` at once) has different parameters in different faces, so it gets one `vt` per
//! distinct value, and every face corner `f v/vt/vn` points at its own face's. A `vt` is in
//! the file's parameters: the patch's `(u, v)` in `[0, 1]` for BPT, the surface's knot
//! parameters for NURBS.

use std::collections::HashMap;
use std::fmt::Write as _;

use spline_tess::tessellator::Tessellator;
use spline_tess::{ParamRect, TriangleInfo, Vertex};

use super::model_file::ModelFile;

/// One face of the OBJ: its patch, its corners' vertex indices and their own parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObjFace {
    /// The patch the face belongs to.
    pub patch: u32,
    /// Indices into the mesh's vertices.
    pub vertices: [u32; 3],
    /// Each corner's `(u, v)` in the face's own patch, in `[0, 1]`.
    pub uv: [[f32; 2]; 3],
}

/// The faces of the run time's current frame: `triangles` as `write_mesh` wrote them, with
/// each corner's parameters in the face's own patch.
pub fn frame_faces(selection: &Tessellator<'_, '_>, triangles: &[[u32; 3]]) -> Vec<ObjFace> {
    faces_of(|f| selection.stream_with_info(|info, _| f(info)), triangles)
}

/// The faces of a frame whose `stream_with_info` is `stream`, `triangles` as its
/// `write_mesh` wrote them (the stream gives the triangles in the write's order).
pub fn faces_of(
    stream: impl FnOnce(&mut dyn FnMut(&TriangleInfo)),
    triangles: &[[u32; 3]],
) -> Vec<ObjFace> {
    let mut faces = Vec::with_capacity(triangles.len());
    stream(&mut |info| {
        let k = faces.len();
        faces.push(ObjFace {
            patch: info.patch,
            vertices: triangles.get(k).copied().unwrap_or_default(),
            uv: info.uv,
        });
    });
    debug_assert_eq!(faces.len(), triangles.len());
    faces
}

/// `t` in `[0, 1]` mapped to `[a, b]`, exact at both ends (so neighbouring pieces of a NURBS
/// surface give their shared knot the same bits).
fn map(a: f32, b: f32, t: f32) -> f32 {
    if t <= 0.5 {
        a + (b - a) * t
    } else {
        b - (b - a) * (1.0 - t)
    }
}

/// A face corner's parameters in the file's own parameters.
fn file_params(domain: ParamRect, uv: [f32; 2]) -> [f32; 2] {
    [
        map(domain.u0, domain.u1, uv[0]),
        map(domain.v0, domain.v1, uv[1]),
    ]
}

/// The OBJ text: `v`, `vt` (one per distinct vertex and parameters), `vn`, one `g patch_K`
/// per run of faces of patch K (K = 0 for a NURBS file, which holds one surface) and
/// `f v/vt/vn`.
pub fn obj_text(file: &ModelFile, nurbs: bool, vertices: &[Vertex], faces: &[ObjFace]) -> String {
    let mut s = String::new();
    let mut texture: Vec<[f32; 2]> = Vec::new();
    let mut seen: HashMap<(u32, [u32; 2]), usize> = HashMap::new();
    let corners: Vec<[usize; 3]> = faces
        .iter()
        .map(|f| {
            let domain = file.domains[f.patch as usize];
            [0, 1, 2].map(|k| {
                let t = file_params(domain, f.uv[k]);
                *seen
                    .entry((f.vertices[k], t.map(f32::to_bits)))
                    .or_insert_with(|| {
                        texture.push(t);
                        texture.len() - 1
                    })
            })
        })
        .collect();
    let _ = writeln!(
        s,
        "# spline-tess: {} vertices, {} texture coordinates, {} triangles",
        vertices.len(),
        texture.len(),
        faces.len()
    );
    for v in vertices {
        let [x, y, z] = v.position;
        let _ = writeln!(s, "v {x} {y} {z}");
    }
    for [u, w] in &texture {
        let _ = writeln!(s, "vt {u} {w}");
    }
    for v in vertices {
        let [x, y, z] = v.normal;
        let _ = writeln!(s, "vn {x} {y} {z}");
    }
    let mut current = None;
    for (f, t) in faces.iter().zip(&corners) {
        let group = if nurbs { 0 } else { f.patch };
        if current != Some(group) {
            let _ = writeln!(s, "g patch_{group}");
            current = Some(group);
        }
        let _ = write!(s, "f");
        for (v, vt) in f.vertices.iter().zip(t) {
            let _ = write!(s, " {}/{}/{}", v + 1, vt + 1, v + 1);
        }
        let _ = writeln!(s);
    }
    s
}

/// Writes [`obj_text`] to `path`, creating the folder.
pub fn write_obj(
    path: &str,
    file: &ModelFile,
    nurbs: bool,
    vertices: &[Vertex],
    faces: &[ObjFace],
) -> Result<(), String> {
    let s = obj_text(file, nurbs, vertices, faces);
    if let Some(dir) = std::path::Path::new(path).parent() {
        if !dir.as_os_str().is_empty() {
            std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        }
    }
    std::fs::write(path, s).map_err(|e| format!("{path}: {e}"))
}
