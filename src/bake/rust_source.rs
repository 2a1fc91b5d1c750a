//! A baked model as Rust source: `static` arrays of its patches and their hierarchy, which a
//! firmware build keeps in flash.

use core::fmt;

use crate::patch::Side;
use crate::tessellator::Hierarchy;

/// Writes `tree` and the patches it was baked from as Rust source: `pub static`s
/// `{name}_HEADERS` and `{name}_POINTS` (and `{name}_WEIGHTS` for a rational model), the
/// patches [`PatchSet::new`](crate::PatchSet::new) takes, and `{name}_NODES`,
/// `{name}_VERTICES` and `{name}_PATCHES`, the records [`Hierarchy::new`] takes, all bit for
/// bit (floats by their bits). Include it in a module of its own; the source says how to wrap
/// it.
///
/// ```
/// use spline_tess::bake::write_rust_source;
/// use spline_tess::tessellator::{Hierarchy, HierarchyNode, HierarchyPatch, HierarchyVertex};
/// use spline_tess::{PatchHeader, PatchSet};
///
/// let headers = [PatchHeader { degree_u: 1, degree_v: 1, first_point: 0 }];
/// let points = [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]];
/// let model = PatchSet::new(&headers, &points, None).unwrap();
/// let nodes = [HierarchyNode::default(); 2];
/// let vertices = [HierarchyVertex::default(); 1];
/// let patches = [HierarchyPatch::default()];
/// let tree = Hierarchy::new(model, &nodes, &vertices, &patches).unwrap();
/// let mut src = String::new();
/// write_rust_source(&mut src, "TEAPOT", &tree).unwrap();
/// assert!(src.contains("pub static TEAPOT_NODES: [Node; 2] = ["));
/// assert!(src.contains("pub static TEAPOT_POINTS: [[f32; 3]; 4] = ["));
/// ```
pub fn write_rust_source(w: &mut impl fmt::Write, name: &str, tree: &Hierarchy<'_>) -> fmt::Result {
    let model = tree.model();
    writeln!(
        w,
        "// A model baked by spline-tess: its patches and their hierarchy. Wrap them as\n\
         //\n\
         //     let patches = spline_tess::PatchSet::new(&{name}_HEADERS, &{name}_POINTS, None)?;\n\
         //     let hierarchy = spline_tess::Hierarchy::new(\n\
         //         patches, &{name}_NODES, &{name}_VERTICES, &{name}_PATCHES)?;"
    )?;
    if model.weights().is_some() {
        writeln!(
            w,
            "//\n// with `Some(&{name}_WEIGHTS)` in place of `None`: the model is rational."
        )?;
    }
    writeln!(
        w,
        "use spline_tess::tessellator::{{HierarchyNode as Node, HierarchyPatch as Patch, \
         HierarchyVertex as Vertex, SideLink}};\nuse spline_tess::{{PatchHeader, Side}};\n\n\
         const fn n(children: u32, vertex: u32, vectors: [[i8; 3]; {k}], scale: u32, remainder: u32) -> Node {{\n    \
         Node {{ children, vertex, vectors, scale: f32::from_bits(scale), remainder: f32::from_bits(remainder) }}\n}}\n\n\
         const fn f(b: [u32; 3]) -> [f32; 3] {{\n    \
         [f32::from_bits(b[0]), f32::from_bits(b[1]), f32::from_bits(b[2])]\n}}\n\n\
         const fn c(b: [u32; 4]) -> [f32; 4] {{\n    \
         [f32::from_bits(b[0]), f32::from_bits(b[1]), f32::from_bits(b[2]), f32::from_bits(b[3])]\n}}\n\n\
         const fn v(position: [u32; 3], normal: [u32; 3], uv: [u16; 2], patch: u32, output: u32) -> Vertex {{\n    \
         Vertex {{ position: f(position), normal: f(normal), uv, patch, output }}\n}}\n",
        k = crate::tessellator::KEPT
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
    let nodes = tree.nodes();
    writeln!(w, "pub static {name}_NODES: [Node; {}] = [", nodes.len())?;
    for node in nodes {
        write!(w, "    n({}, {}, [", node.children, node.vertex)?;
        for (i, q) in node.vectors.iter().enumerate() {
            let sep = if i == 0 { "" } else { ", " };
            write!(w, "{sep}[{}, {}, {}]", q[0], q[1], q[2])?;
        }
        writeln!(
            w,
            "], {:#x}, {:#x}),",
            node.scale.to_bits(),
            node.remainder.to_bits()
        )?;
    }
    writeln!(w, "];\n")?;
    let vertices = tree.vertices();
    writeln!(
        w,
        "pub static {name}_VERTICES: [Vertex; {}] = [",
        vertices.len()
    )?;
    for x in vertices {
        let [p, q] = [x.position, x.normal].map(|a| a.map(f32::to_bits));
        writeln!(
            w,
            "    v([{:#x}, {:#x}, {:#x}], [{:#x}, {:#x}, {:#x}], [{}, {}], {}, {}),",
            p[0], p[1], p[2], q[0], q[1], q[2], x.uv[0], x.uv[1], x.patch, x.output
        )?;
    }
    writeln!(w, "];\n")?;
    let patches = tree.patches();
    writeln!(
        w,
        "pub static {name}_PATCHES: [Patch; {}] = [",
        patches.len()
    )?;
    for p in patches {
        write!(
            w,
            "    Patch {{ corners: {:?}, cells: {:?}, first_root: {}, cell_vertices: {}, links: [",
            p.corners, p.cells, p.first_root, p.cell_vertices
        )?;
        for (i, link) in p.links.iter().enumerate() {
            let sep = if i == 0 { "" } else { ", " };
            match link {
                None => write!(w, "{sep}None")?,
                Some(l) => write!(
                    w,
                    "{sep}Some(SideLink {{ patch: {}, side: Side::{}, flip: {} }})",
                    l.patch,
                    side_name(l.side),
                    l.flip
                )?,
            }
        }
        let cone = p.cone.map(f32::to_bits);
        writeln!(
            w,
            "], flip: {}, cone: c([{:#x}, {:#x}, {:#x}, {:#x}]) }},",
            p.flip, cone[0], cone[1], cone[2], cone[3]
        )?;
    }
    writeln!(w, "];")
}

fn side_name(s: Side) -> &'static str {
    match s {
        Side::V0 => "V0",
        Side::U1 => "U1",
        Side::V1 => "V1",
        Side::U0 => "U0",
    }
}
