//! Bakes of the hierarchy (`spline_tess::bake::bake_hierarchy`) of every model: their
//! triangles, vertices and bytes. Prints a Markdown table.
//!
//! ```text
//! cargo run --release -p host-tests --example bintree_figures -- 1e-3
//! ```
//!
//! The arguments are tolerances relative to each model's control-point diagonal (default
//! 1e-3). *Bytes* are the hierarchy's compact bytes (`encode_hierarchy`), what a firmware keeps
//! in flash and `Hierarchy::from_bytes` reads in place, and *bytes / vertex* those over the
//! vertices the bytes hold (the records' copies of cell corners left out). *Records* are the
//! bake's records at their in-memory sizes (nodes, vertices and patch records: what a firmware
//! kept in flash before the bytes, and what `Hierarchy::new` reads in RAM); *ratio* is bytes
//! over records. *Bake s* is one run on all cores (the bake and its encoding;
//! `scripts/bake_speed.sh` compares one thread with all).

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
        "| model | rel. tol. | patches | triangles (nodes) | leaves | vertices | records | bytes | ratio | bytes / vertex | bake s |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for rel in rels {
        for path in bpt_models().into_iter().chain(nurbs_fixtures()) {
            let file = ModelFile::read(path.to_str().expect("a UTF-8 path")).expect("a model");
            let settings = BakeSettings {
                tolerance: Tolerance::Relative(rel),
                ..BakeSettings::default()
            };
            let start = Instant::now();
            let bake = BakedHierarchy::bake(&file, &settings).expect("a bisection bake");
            let encoded = bake.encoded();
            let seconds = start.elapsed().as_secs_f64();
            let tree = bake.tree_from(&encoded);
            let leaves = bake.nodes.iter().filter(|n| n.children == 0).count();
            let records = bake.nodes.len() * size_of::<HierarchyNode>()
                + bake.vertices.len() * size_of::<HierarchyVertex>()
                + bake.patches.len() * size_of::<HierarchyPatch>();
            let bytes = encoded.len();
            println!(
                "| {} | {rel:e} | {} | {} | {leaves} | {} | {records} | {bytes} | {:.3} | {:.1} | {seconds:.2} |",
                name(&path),
                bake.patches.len(),
                bake.nodes.len(),
                tree.vertex_count(),
                bytes as f64 / records as f64,
                bytes as f64 / tree.vertex_count() as f64
            );
        }
    }
}
