//! Host-side helpers for the bisection run time (`spline_tess::bisect`): a bake in `Vec`s
//! (`model_file::BakedBintree`, which the examples share), its run-time storage, and its
//! frames as streamed triangles.

use spline_tess::bisect::{Bintree, Pending, RefinedVertex, Selection};

pub use crate::model_file::BakedBintree;
use crate::runtime::Streamed;

/// Run-time storage for a [`Selection`] in `Vec`s.
#[derive(Debug)]
pub struct SelectionStorage {
    bits: Vec<u32>,
    stack: Vec<Pending>,
    pool: Vec<RefinedVertex>,
}

impl SelectionStorage {
    /// Storage for `tree` with a stack of `stack` entries and a pool of `pool` vertices
    /// below the bake.
    pub fn new(tree: &Bintree<'_>, stack: usize, pool: usize) -> Self {
        SelectionStorage {
            bits: vec![0; tree.bit_words()],
            stack: vec![Pending::default(); stack],
            pool: vec![RefinedVertex::default(); pool],
        }
    }

    /// A run time over `tree` in this storage.
    pub fn selection<'t>(&mut self, tree: Bintree<'t>) -> Selection<'t, '_> {
        Selection::new(tree, &mut self.bits, &mut self.stack, &mut self.pool)
            .expect("storage sized for the tree")
    }
}

/// The current frame as streamed triangles.
pub fn streamed(selection: &Selection<'_, '_>) -> Vec<Streamed> {
    let mut out = Vec::new();
    selection.stream_with_info(|info, c| out.push(Streamed::of(info, c)));
    out
}
