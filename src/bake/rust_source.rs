//! A baked model as Rust source: `static`s of its patches and of its hierarchy's compact
//! bytes, which a firmware build keeps in flash.

use core::fmt;

use crate::model::PatchSet;

/// Writes `model`'s patches and `hierarchy`, its hierarchy's compact bytes (as
/// [`encode_hierarchy`](super::encode_hierarchy) wrote them), as Rust source: `pub static`s
/// `{name}_HEADERS` and `{name}_POINTS` (and `{name}_WEIGHTS` for a rational model), the
/// patches [`PatchSet::new`] takes, bit for bit (floats by their bits), and
/// `{name}_HIERARCHY`, the bytes [`Hierarchy::from_bytes`](crate::Hierarchy::from_bytes)
/// reads. Include it in a module of its own; the source says how to wrap it. (The bytes
/// alone can be kept as a file and read with `include_bytes!`.)
///
/// ```
/// use spline_tess::bake::write_rust_source;
/// use spline_tess::{PatchHeader, PatchSet};
///
/// let headers = [PatchHeader { degree_u: 1, degree_v: 1, first_point: 0 }];
/// let points = [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]];
/// let model = PatchSet::new(&headers, &points, None).unwrap();
/// let mut src = String::new();
/// write_rust_source(&mut src, "TEAPOT", &model, &[1, 2, 3]).unwrap();
/// assert!(src.contains("pub static TEAPOT_HIERARCHY: [u8; 3] = ["));
/// assert!(src.contains("pub static TEAPOT_POINTS: [[f32; 3]; 4] = ["));
/// ```
pub fn write_rust_source(
    w: &mut impl fmt::Write,
    name: &str,
    model: &PatchSet<'_>,
    hierarchy: &[u8],
) -> fmt::Result {
    writeln!(
        w,
        "// A model baked by spline-tess: its patches and their hierarchy. Wrap them as\n\
         //\n\
         //     let patches = spline_tess::PatchSet::new(&{name}_HEADERS, &{name}_POINTS, None)?;\n\
         //     let hierarchy = spline_tess::Hierarchy::from_bytes(patches, &{name}_HIERARCHY)?;"
    )?;
    if model.weights().is_some() {
        writeln!(
            w,
            "//\n// with `Some(&{name}_WEIGHTS)` in place of `None`: the model is rational."
        )?;
    }
    writeln!(
        w,
        "use spline_tess::PatchHeader;\n\n\
         const fn f(b: [u32; 3]) -> [f32; 3] {{\n    \
         [f32::from_bits(b[0]), f32::from_bits(b[1]), f32::from_bits(b[2])]\n}}\n"
    )?;
    let headers = model.headers();
    writeln!(
        w,
        "pub static {name}_HEADERS: [PatchHeader; {}] = [",
        headers.len()
    )?;
    for h in headers {
        writeln!(
            w,
            "    PatchHeader {{ degree_u: {}, degree_v: {}, first_point: {} }},",
            h.degree_u, h.degree_v, h.first_point
        )?;
    }
    writeln!(w, "];\n")?;
    let points = model.points();
    writeln!(
        w,
        "pub static {name}_POINTS: [[f32; 3]; {}] = [",
        points.len()
    )?;
    for p in points {
        let b = p.map(f32::to_bits);
        writeln!(w, "    f([{:#x}, {:#x}, {:#x}]),", b[0], b[1], b[2])?;
    }
    writeln!(w, "];\n")?;
    if let Some(weights) = model.weights() {
        writeln!(w, "pub static {name}_WEIGHTS: [f32; {}] = [", weights.len())?;
        for x in weights {
            writeln!(w, "    f32::from_bits({:#x}),", x.to_bits())?;
        }
        writeln!(w, "];\n")?;
    }
    let count = |at: usize| crate::tessellator::format::u32_at(hierarchy, at);
    writeln!(
        w,
        "/// Triangles of the hierarchy (for sizing a tessellator's bits at compile time).
         pub const {name}_NODE_COUNT: usize = {};
         /// Vertices of the hierarchy.
         pub const {name}_VERTEX_COUNT: usize = {};
",
        count(20),
        count(28)
    )?;
    writeln!(
        w,
        "pub static {name}_HIERARCHY: [u8; {}] = [",
        hierarchy.len()
    )?;
    for line in hierarchy.chunks(24) {
        write!(w, "   ")?;
        for b in line {
            write!(w, " {b},")?;
        }
        writeln!(w)?;
    }
    writeln!(w, "];")
}
