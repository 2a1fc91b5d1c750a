//! Writing a frame's mesh as Wavefront OBJ.

use std::fmt::Write as _;

use spline_tess::Vertex;

use super::model_file::ModelFile;

/// Writes `v`, `vt` (the patch's own parameters; for NURBS, the surface's), `vn`, one
/// `g patch_K` per patch in `groups` (K = 0 for a NURBS file, which holds one surface) and
/// `f a/a/a b/b/b c/c/c`, creating the folder.
pub fn write_obj(
    path: &str,
    file: &ModelFile,
    nurbs: bool,
    vertices: &[Vertex],
    groups: &[(usize, std::ops::Range<usize>)],
    triangles: &[[u32; 3]],
) -> Result<(), String> {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# spline-tess: {} vertices, {} triangles",
        vertices.len(),
        triangles.len()
    );
    for v in vertices {
        let [x, y, z] = v.position;
        let _ = writeln!(s, "v {x} {y} {z}");
    }
    for v in vertices {
        let r = file.domains[v.patch as usize];
        let (u, w) = (
            r.u0 + v.uv[0] * (r.u1 - r.u0),
            r.v0 + v.uv[1] * (r.v1 - r.v0),
        );
        let _ = writeln!(s, "vt {u} {w}");
    }
    for v in vertices {
        let [x, y, z] = v.normal;
        let _ = writeln!(s, "vn {x} {y} {z}");
    }
    let mut current = None;
    for (patch, range) in groups {
        let group = if nurbs { 0 } else { *patch };
        if current != Some(group) {
            let _ = writeln!(s, "g patch_{group}");
            current = Some(group);
        }
        for t in &triangles[range.clone()] {
            let [a, b, c] = t.map(|i| i + 1);
            let _ = writeln!(s, "f {a}/{a}/{a} {b}/{b}/{b} {c}/{c}/{c}");
        }
    }
    if let Some(dir) = std::path::Path::new(path).parent() {
        if !dir.as_os_str().is_empty() {
            std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        }
    }
    std::fs::write(path, s).map_err(|e| format!("{path}: {e}"))
}
