//! What stands between the hierarchy and fewer triangles: at each error view, the coarsest
//! conforming mesh of the hierarchy selected by an oracle with the *measured* error instead
//! of the kernel's bound, with one cell a patch and with the bake's cells, and selected by
//! `f64` bounds of the kernel's kind. Prints a Markdown table.
//!
//! ```text
//! cargo run --release -p host-tests --example hierarchy_limits
//! ```
//!
//! Every count is `host_tests::bintree::bintree_from` (the oracles' conforming bisection,
//! sharing no code with the kernel) over the roots the bake chose (`HierarchyPatch::cells`,
//! bake at 1e-3 of the diagonal), or one cell a patch, splitting a triangle when its test is
//! over the tolerance:
//!
//! - *measured*: the triangle's error on screen sampled as `error_figures` samples it (12
//!   steps a side, `f64`): no bound can select fewer triangles of this hierarchy (to the
//!   sampling's few percent);
//! - *bound, lattice*: the directional bound on screen of `host_tests::screen_bound` from the
//!   lattice of step 1/12 with all its deviation vectors (the form the kernel's bound takes);
//! - *bound, 4 kept*: the same from 4 kept vectors, as the bake keeps them;
//! - with `BOUND_VARIANTS=1`, what smaller records would cost: 3 and 2 kept vectors, the
//!   segment along the flat triangle's normal between the lowest and highest deviation
//!   (`screen_bound::segment_vectors`, three numbers a triangle), and the isotropic bound.
//!
//! The oracles cull nothing (the kernel leaves out patches facing away), so their counts are
//! comparable with each other, not with the kernel's. *n_u x n_v grid* is `error_figures`'
//! reference (the smallest verified grid per patch with a factor per direction), read from
//! the file `GRID_CACHE` names where `error_figures` left it there, computed otherwise.

use host_tests::bintree::{bintree_from, cell_roots, model_spot, unit, Bin};
use host_tests::model_file::ModelFile;
use host_tests::reference::RefPatch;
use host_tests::runtime::BakedHierarchy;
use host_tests::screen::{grid_triangles, triangle_deviation, Measure, Meter, ERROR_VIEWS};
use host_tests::screen_bound::{screen_bound_kept, SEGMENT};
use spline_tess::bake::BakeSettings;

const GRID_DENSE: usize = 8;

/// The `n_u x n_v` grid of the case named `name`, from the cache file if it has it.
fn cached_grid(name: &str) -> Option<usize> {
    let path = std::env::var("GRID_CACHE").ok()?;
    let text = std::fs::read_to_string(path).ok()?;
    text.lines().find_map(|line| {
        let mut parts = line.split('\t');
        (parts.next()? == name).then_some(())?;
        parts.next()?;
        parts.next()?.parse().ok()
    })
}

fn main() {
    // The bounds a compact record could keep in place of four vectors (`BOUND_VARIANTS=1`).
    let variants = std::env::var_os("BOUND_VARIANTS").is_some();
    print!(
        "| view | n_u x n_v grid | one cell, measured | cells, measured | cells, bound, lattice | \
         cells, bound, 4 kept |"
    );
    if variants {
        print!(" 3 kept | 2 kept | normal segment | isotropic |");
    }
    println!();
    println!(
        "|---|---|---|---|---|---|{}",
        if variants { "---|---|---|---|" } else { "" }
    );
    for view in ERROR_VIEWS {
        let path = host_tests::models_dir().join(view.model);
        let file = ModelFile::read(path.to_str().expect("a UTF-8 path")).expect("a model");
        let baked = BakedHierarchy::bake(&file, &BakeSettings::default()).expect("a bake");
        let cells: Vec<[u8; 2]> = baked.patches.iter().map(|p| p.cells).collect();
        let diag = file.patches().aabb().expect("patches").diagonal() as f64;
        let refs: Vec<RefPatch> = file
            .patches()
            .iter()
            .map(|p| RefPatch::from_kernel(&p))
            .collect();
        let meter = Meter::new(
            view.eye.map(f64::from),
            view.target.map(f64::from),
            [0.0, 0.0, 1.0],
            40.0,
            0.01 * diag,
            view.viewport,
        );
        let tol = view.tol as f64;
        let measured = |(p, c): Bin| {
            let uv = c.map(unit);
            let corners = uv.map(|[u, v]| refs[p].point(u, v));
            let m = triangle_deviation(&refs[p], uv, corners, 12, Measure::Screen(&meter));
            if m.visible {
                m.worst
            } else {
                0.0
            }
        };
        let bound = |keep: usize| {
            let (refs, meter) = (&refs, &meter);
            move |(p, c): Bin| {
                screen_bound_kept(&refs[p], c.map(unit), meter, 12, keep)
                    .map_or(f64::INFINITY, |b| b.hull)
            }
        };
        let isotropic = |(p, c): Bin| {
            screen_bound_kept(&refs[p], c.map(unit), &meter, 12, usize::MAX)
                .map_or(f64::INFINITY, |b| b.isotropic)
        };
        let spot = |p, g| model_spot(&refs, diag, p, g);
        let count = |cells: &[[u8; 2]], error: &dyn Fn(Bin) -> f64| {
            bintree_from(cell_roots(cells), tol, spot, error).len()
        };
        let grid = cached_grid(view.name).unwrap_or_else(|| {
            grid_triangles(&refs, tol, GRID_DENSE, 512, Measure::Screen(&meter))[1]
        });
        let one = vec![[0, 0]; refs.len()];
        let mut row = vec![
            count(&one, &measured),
            count(&cells, &measured),
            count(&cells, &bound(usize::MAX)),
            count(&cells, &bound(4)),
        ];
        if variants {
            row.push(count(&cells, &bound(3)));
            row.push(count(&cells, &bound(2)));
            row.push(count(&cells, &bound(SEGMENT)));
            row.push(count(&cells, &isotropic));
        }
        let cell = |n: &usize| format!(" {n} ({:.2}) |", *n as f64 / grid as f64);
        let cells: String = row.iter().map(cell).collect();
        println!("| {} | {grid} |{cells}", view.name);
    }
}
