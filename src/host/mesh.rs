//! A frame as an owned, indexed mesh, and its OBJ and PLY text.

use std::collections::HashMap;
use std::io::{self, Write};
use std::vec;
use std::vec::Vec;

use super::{HostError, Surfaces};
use crate::{FrameStats, ParamRect, Tessellator, Vertex};

/// A frame's mesh ([`Baked::tessellate`](super::Baked::tessellate)): vertices shared by
/// index (shared curves share theirs: no cracks), triangles counter-clockwise seen from
/// outside, and each face's own parameters.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions.
    pub positions: Vec<[f32; 3]>,
    /// Unit surface normals, one per vertex.
    pub normals: Vec<[f32; 3]>,
    /// Triangles, as indices of vertices.
    pub triangles: Vec<[u32; 3]>,
    /// Each triangle's patch and its corners' parameters, in the order of `triangles`.
    pub faces: Vec<Face>,
    /// What the frame did: its bound, triangles judged, vertices made below the bake.
    pub stats: FrameStats,
}

/// One triangle's patch and its corners' parameters.
///
/// A vertex that several patches share (a shared curve, a patch corner), a pole, or a vertex
/// on the seam of a closed NURBS surface has different parameters in different faces: each
/// face gives its own.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Face {
    /// The patch (a Bezier piece, for a NURBS surface).
    pub patch: u32,
    /// Each corner's `(u, v)` in the file's own parameters: the patch's unit square for BPT,
    /// the surface's knot parameters for NURBS.
    pub uv: [[f32; 2]; 3],
}

impl ParamRect {
    /// `(u, v)` of the unit square mapped onto the rectangle, exact at both ends of each
    /// side (neighbouring pieces of a NURBS surface give their shared knot the same bits).
    pub(crate) fn map(&self, uv: [f32; 2]) -> [f32; 2] {
        let lerp = |a: f32, b: f32, t: f32| {
            if t <= 0.5 {
                a + (b - a) * t
            } else {
                b - (b - a) * (1.0 - t)
            }
        };
        [lerp(self.u0, self.u1, uv[0]), lerp(self.v0, self.v1, uv[1])]
    }
}

impl Mesh {
    /// The current frame of `tessellator` (of a hierarchy of `surfaces`), whose
    /// [`update`](Tessellator::update) gave `stats`: what
    /// [`Baked::tessellate`](super::Baked::tessellate) returns, for a tessellator of one's own
    /// (one kept from frame to frame, say).
    pub fn of_frame(
        tessellator: &mut Tessellator<'_, '_>,
        surfaces: &Surfaces,
        stats: FrameStats,
    ) -> Result<Mesh, HostError> {
        // Room for three vertices a triangle (or every vertex there is): written with no
        // walk first to count them, on all cores (the same mesh as on one).
        let triangles_len = tessellator.stats().triangles;
        let room = (3 * triangles_len).min(tessellator.remap_len());
        let mut vertices = vec![Vertex::default(); room];
        let mut triangles = vec![[0u32; 3]; triangles_len];
        let mut remap = vec![0u32; tessellator.remap_len()];
        let size = tessellator.write_mesh_parallel(&mut vertices, &mut triangles, &mut remap)?;
        vertices.truncate(size.vertices);
        triangles.truncate(size.triangles);
        let domains = surfaces.domains();
        let mut faces = Vec::with_capacity(triangles.len());
        // (The walk gives the triangles in the order `write_mesh` wrote them.)
        tessellator.each_face(|patch, uv| {
            let domain = domains.get(patch as usize).copied();
            faces.push(Face {
                patch,
                uv: uv.map(|uv| domain.map_or(uv, |d| d.map(uv))),
            });
        });
        Ok(Mesh {
            positions: vertices.iter().map(|v| v.position).collect(),
            normals: vertices.iter().map(|v| v.normal).collect(),
            triangles,
            faces,
            stats,
        })
    }

    /// Whether the mesh holds together for writing: a normal per position, a face per
    /// triangle, every index below the vertex count.
    fn check(&self) -> io::Result<()> {
        let n = self.positions.len();
        let fits = self.normals.len() == n
            && self.faces.len() == self.triangles.len()
            && self.triangles.iter().flatten().all(|&v| (v as usize) < n);
        if fits {
            Ok(())
        } else {
            Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                "a mesh with a normal per position, a face per triangle and indices below the \
                 vertex count",
            ))
        }
    }

    /// Texture coordinates per face corner, one per distinct (vertex, parameters): the list
    /// and each face corner's index in it.
    fn texture(&self) -> (Vec<[f32; 2]>, Vec<[usize; 3]>) {
        let mut list = Vec::new();
        let mut seen: HashMap<(u32, [u32; 2]), usize> = HashMap::new();
        let corners = self
            .faces
            .iter()
            .zip(&self.triangles)
            .map(|(f, t)| {
                [0, 1, 2].map(|k| {
                    *seen
                        .entry((t[k], f.uv[k].map(f32::to_bits)))
                        .or_insert_with(|| {
                            list.push(f.uv[k]);
                            list.len() - 1
                        })
                })
            })
            .collect();
        (list, corners)
    }

    /// Writes the mesh as Wavefront OBJ: `v` and `vn` per vertex, `vt` per distinct corner
    /// parameters, `g patch_K` for each run of faces of patch K, and `f v/vt/vn`.
    ///
    /// ```
    /// # use spline_tess::host::{Face, Mesh};
    /// let mesh = Mesh {
    ///     positions: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
    ///     normals: vec![[0.0, 0.0, 1.0]; 3],
    ///     triangles: vec![[0, 1, 2]],
    ///     faces: vec![Face { patch: 0, uv: [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]] }],
    ///     ..Mesh::default()
    /// };
    /// let mut obj = Vec::new();
    /// mesh.write_obj(&mut obj)?;
    /// assert!(String::from_utf8(obj)?.contains("f 1/1/1 2/2/2 3/3/3"));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// A mesh that does not hold together (see [`Mesh`]'s fields: a normal per position, a
    /// face per triangle, indices below the vertex count) is an `InvalidInput` error.
    pub fn write_obj(&self, w: &mut impl Write) -> io::Result<()> {
        self.check()?;
        let mut w = io::BufWriter::new(w);
        let (texture, corners) = self.texture();
        writeln!(
            w,
            "# spline-tess: {} vertices, {} texture coordinates, {} triangles",
            self.positions.len(),
            texture.len(),
            self.triangles.len()
        )?;
        for [x, y, z] in &self.positions {
            writeln!(w, "v {x} {y} {z}")?;
        }
        for [u, v] in &texture {
            writeln!(w, "vt {u} {v}")?;
        }
        for [x, y, z] in &self.normals {
            writeln!(w, "vn {x} {y} {z}")?;
        }
        let mut group = None;
        for ((t, f), c) in self.triangles.iter().zip(&self.faces).zip(&corners) {
            if group != Some(f.patch) {
                writeln!(w, "g patch_{}", f.patch)?;
                group = Some(f.patch);
            }
            write!(w, "f")?;
            for (&v, vt) in t.iter().zip(c) {
                let v = u64::from(v) + 1;
                write!(w, " {v}/{}/{v}", vt + 1)?;
            }
            writeln!(w)?;
        }
        w.flush()
    }

    /// Writes the mesh as ASCII PLY: vertices with positions and normals, faces with their
    /// corners' indices, their parameters (`texcoord`, six values) and their patch.
    ///
    /// ```
    /// # use spline_tess::host::{Face, Mesh};
    /// let mesh = Mesh {
    ///     positions: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
    ///     normals: vec![[0.0, 0.0, 1.0]; 3],
    ///     triangles: vec![[0, 1, 2]],
    ///     faces: vec![Face { patch: 7, uv: [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]] }],
    ///     ..Mesh::default()
    /// };
    /// let mut ply = Vec::new();
    /// mesh.write_ply(&mut ply)?;
    /// assert!(String::from_utf8(ply)?.ends_with("3 0 1 2 6 0 0 1 0 0 1 7\n"));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// A mesh that does not hold together is an `InvalidInput` error, as for
    /// [`write_obj`](Self::write_obj).
    pub fn write_ply(&self, w: &mut impl Write) -> io::Result<()> {
        self.check()?;
        let mut w = io::BufWriter::new(w);
        write!(
            w,
            "ply\nformat ascii 1.0\ncomment spline-tess\n\
             element vertex {}\n\
             property float x\nproperty float y\nproperty float z\n\
             property float nx\nproperty float ny\nproperty float nz\n\
             element face {}\n\
             property list uchar uint vertex_indices\n\
             property list uchar float texcoord\n\
             property uint patch\n\
             end_header\n",
            self.positions.len(),
            self.triangles.len()
        )?;
        for (p, n) in self.positions.iter().zip(&self.normals) {
            writeln!(w, "{} {} {} {} {} {}", p[0], p[1], p[2], n[0], n[1], n[2])?;
        }
        for (t, f) in self.triangles.iter().zip(&self.faces) {
            let [a, b, c] = f.uv;
            writeln!(
                w,
                "3 {} {} {} 6 {} {} {} {} {} {} {}",
                t[0], t[1], t[2], a[0], a[1], b[0], b[1], c[0], c[1], f.patch
            )?;
        }
        w.flush()
    }
}
