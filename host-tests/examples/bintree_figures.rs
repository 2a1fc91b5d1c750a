//! Bakes of the hierarchy (`spline_tess::bake::bake_hierarchy`) of every model: their
//! triangles, vertices and bytes. Prints a Markdown table.
//!
//! ```text
//! cargo run --release -p host-tests --example bintree_figures -- 1e-3
//! ```
//!
//! The arguments are tolerances relative to each model's control-point diagonal (default
//! 1e-3). *Bytes* are the records as a firmware keeps them in flash (`write_rust_source`'s
//! statics: nodes, vertices and patch records at their in-memory sizes). *Bake s* is one run
//! on one core.

use std::time::Instant;

use host_tests::model_file::ModelFile;
use host_tests::runtime::BakedHierarchy;
use host_tests::{bpt_models, name, nurbs_fixtures};
use spline_tess::bake::BakeSettings;
use spline_tess::bake::Tolerance;
use spline_tess::tessellator::{HierarchyNode, HierarchyPatch, HierarchyVertex};

fn main() {
    let rels: Vec<f32> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let rels = if rels.is_empty() { vec![1e-3] } else { rels };
    println!(
        "| model | rel. tol. | patches | triangles (nodes) | leaves | vertices | bytes | bake s | bytes / vertex |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    for rel in rels {
        for path in bpt_models().into_iter().chain(nurbs_fixtures()) {
            let file = ModelFile::read(path.to_str().expect("a UTF-8 path")).expect("a model");
            let settings = BakeSettings {
                tolerance: Tolerance::Relative(rel),
                ..BakeSettings::default()
            };
            let start = Instant::now();
            let bake = BakedHierarchy::bake(&file, &settings).expect("a bisection bake");
            let seconds = start.elapsed().as_secs_f64();
            let leaves = bake.nodes.iter().filter(|n| n.children == 0).count();
            let bytes = bake.nodes.len() * size_of::<HierarchyNode>()
                + bake.vertices.len() * size_of::<HierarchyVertex>()
                + bake.patches.len() * size_of::<HierarchyPatch>();
            println!(
                "| {} | {rel:e} | {} | {} | {leaves} | {} | {bytes} | {seconds:.2} | {:.1} |",
                name(&path),
                bake.patches.len(),
                bake.nodes.len(),
                bake.vertices.len(),
                bytes as f64 / bake.vertices.len() as f64
            );
        }
    }
}
