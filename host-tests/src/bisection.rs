//! Host-side helpers for the bisection run time (`spline_tess::bisect`): a bake in `Vec`s,
//! its run-time storage, and its frames as streamed triangles.

use spline_tess::bisect::{
    bake_bintree, BakeScratch, Bintree, BintreeBakeError, BintreeBuffers, BintreeNode,
    BintreePatch, BintreeSettings, BintreeVertex, Pending, RefinedVertex, Selection,
};

use crate::model_file::ModelFile;
use crate::runtime::Streamed;

/// A baked hierarchy in `Vec`s, with the model it was baked from.
#[derive(Clone, Debug)]
pub struct BakedBintree {
    /// The model.
    pub file: ModelFile,
    /// Nodes.
    pub nodes: Vec<BintreeNode>,
    /// Vertices.
    pub vertices: Vec<BintreeVertex>,
    /// Patches.
    pub patches: Vec<BintreePatch>,
}

impl BakedBintree {
    /// Bakes `file` with `settings`, growing the buffers until they fit.
    pub fn bake(file: &ModelFile, settings: &BintreeSettings) -> Result<Self, String> {
        let count = file.patches().len();
        let (mut nodes, mut vertices) = (1usize << 18, 1usize << 16);
        loop {
            let mut n = vec![BintreeNode::default(); nodes];
            let mut v = vec![BintreeVertex::default(); vertices];
            let mut p = vec![BintreePatch::default(); count];
            let mut s = vec![BakeScratch::default(); nodes];
            let result = file.with_model(|m| {
                bake_bintree(
                    m,
                    settings,
                    BintreeBuffers {
                        nodes: &mut n,
                        vertices: &mut v,
                        patches: &mut p,
                        scratch: &mut s,
                    },
                )
            })?;
            match result {
                Ok(size) => {
                    n.truncate(size.nodes);
                    v.truncate(size.vertices);
                    return Ok(BakedBintree {
                        file: file.clone(),
                        nodes: n,
                        vertices: v,
                        patches: p,
                    });
                }
                Err(BintreeBakeError::NodesFull { .. }) => nodes *= 2,
                Err(BintreeBakeError::VerticesFull { .. }) => vertices *= 2,
                Err(e) => return Err(e.to_string()),
            }
        }
    }

    /// The checked hierarchy.
    pub fn tree(&self) -> Bintree<'_> {
        Bintree::new(
            self.file.patches(),
            &self.nodes,
            &self.vertices,
            &self.patches,
        )
        .expect("a fresh bake checks")
    }

    /// Bytes the records take in memory (nodes, vertices, patches).
    pub fn bytes(&self) -> usize {
        std::mem::size_of_val(self.nodes.as_slice())
            + std::mem::size_of_val(self.vertices.as_slice())
            + std::mem::size_of_val(self.patches.as_slice())
    }
}

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
