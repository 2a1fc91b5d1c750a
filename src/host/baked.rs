//! A model's bake in owned storage: its records from a fresh bake, or its compact bytes from a
//! cache file; and a view's frame of it as an owned mesh.

use std::vec;
use std::vec::Vec;

use super::{HostError, Mesh, Surfaces};
use crate::bake::{
    bake_hierarchy_with, encode_hierarchy, encode_scratch_len, BakeBuffers, BakeError, BakeScratch,
    BakeSettings, Parallel, Tolerance,
};
use crate::tessellator::{
    Hierarchy, HierarchyNode, HierarchyPatch, HierarchyVertex, NodeLink, PoolSlot, StackSlot,
};
use crate::{Tessellator, View};

/// A model's bake: the surfaces, the settings and the hierarchy (see [`bake`](crate::bake)).
#[derive(Clone, Debug)]
pub struct Baked {
    surfaces: Surfaces,
    /// `None` for a hierarchy read from bytes, which do not say.
    settings: Option<BakeSettings>,
    store: Store,
    /// The hierarchy's links, filled once (see [`NodeLink`]): a frame finds the triangle
    /// across a hypotenuse by them.
    links: Vec<NodeLink>,
}

#[derive(Clone, Debug)]
enum Store {
    /// A fresh bake's records.
    Records {
        nodes: Vec<HierarchyNode>,
        vertices: Vec<HierarchyVertex>,
        patches: Vec<HierarchyPatch>,
    },
    /// Compact bytes, checked against the surfaces ([`Hierarchy::from_bytes`]).
    Bytes(Vec<u8>),
}

/// A cache file's first bytes, before the settings and the hierarchy's bytes.
const CACHE_MAGIC: &[u8; 16] = b"spline-tess bake";

/// Entries a bake starts with (the repository's models at 2.5e-4 of their diagonal fit), and
/// the most it grows to (doubling; 64M nodes take 7.5 GB of records and scratch): a bake that
/// needs more is a `BakeError::NodesFull` (or `VerticesFull`).
const FIRST_NODES: usize = 1 << 17;
const FIRST_VERTICES: usize = 1 << 16;
const MAX_NODES: usize = 1 << 26;

/// Stack entries and vertices below the bake a frame starts with, and the most vertices it
/// grows its pool to (16 times at a time, the frame made again) while the pool fills up. A
/// frame within the bake makes none: a small first pool spares it filling megabytes.
const STACK: usize = 4096;
const FIRST_POOL: usize = 1 << 12;
const MAX_POOL: usize = 1 << 20;

impl Baked {
    /// Bakes `surfaces` with `settings` on all cores, growing the buffers until the hierarchy
    /// fits.
    pub(super) fn bake(surfaces: &Surfaces, settings: &BakeSettings) -> Result<Baked, HostError> {
        let count = surfaces.patches().len();
        let (mut nodes, mut vertices) = (FIRST_NODES, FIRST_VERTICES);
        loop {
            let mut n = vec![HierarchyNode::default(); nodes];
            let mut v = vec![HierarchyVertex::default(); vertices];
            let mut p = vec![HierarchyPatch::default(); count];
            let mut s = vec![BakeScratch::default(); nodes];
            let buffers = BakeBuffers {
                nodes: &mut n,
                vertices: &mut v,
                patches: &mut p,
                scratch: &mut s,
            };
            let baked = surfaces.with_model(|m| {
                bake_hierarchy_with(m, settings, buffers, &mut |_| {}, &Parallel)
            })?;
            match baked {
                Ok(size) => {
                    n.truncate(size.nodes);
                    v.truncate(size.vertices);
                    return Baked {
                        surfaces: surfaces.clone(),
                        settings: Some(*settings),
                        store: Store::Records {
                            nodes: n,
                            vertices: v,
                            patches: p,
                        },
                        links: Vec::new(),
                    }
                    .linked();
                }
                Err(BakeError::NodesFull { .. }) if nodes < MAX_NODES => nodes *= 2,
                Err(BakeError::VerticesFull { .. }) if vertices < MAX_NODES => vertices *= 2,
                Err(e) => return Err(e.into()),
            }
        }
    }

    /// A bake of `surfaces` from its compact bytes ([`to_bytes`](Self::to_bytes)), checked
    /// to be a hierarchy of these surfaces. (The bytes do not say which settings made them:
    /// [`settings`](Self::settings) is then `None`.)
    pub fn from_bytes(surfaces: Surfaces, bytes: Vec<u8>) -> Result<Baked, HostError> {
        Hierarchy::from_bytes(surfaces.patches(), &bytes)?;
        Baked {
            surfaces,
            settings: None,
            store: Store::Bytes(bytes),
            links: Vec::new(),
        }
        .linked()
    }

    /// This bake with its links filled.
    fn linked(mut self) -> Result<Baked, HostError> {
        let tree = self.unlinked()?;
        let mut links = vec![NodeLink::default(); tree.link_slots()];
        tree.fill_links(&mut links)?;
        self.links = links;
        Ok(self)
    }

    /// The surfaces.
    pub fn surfaces(&self) -> &Surfaces {
        &self.surfaces
    }

    /// The settings of the bake, where known (not for one read from bare bytes).
    pub fn settings(&self) -> Option<&BakeSettings> {
        self.settings.as_ref()
    }

    /// The hierarchy, to hand a [`Tessellator`] (for frames with buffers of one's own, or a
    /// renderer), with its links ([`Hierarchy::with_links`]).
    pub fn hierarchy(&self) -> Result<Hierarchy<'_>, HostError> {
        Ok(self.unlinked()?.with_own_links(&self.links))
    }

    /// The hierarchy without its links.
    fn unlinked(&self) -> Result<Hierarchy<'_>, HostError> {
        let patches = self.surfaces.patches();
        Ok(match &self.store {
            Store::Records {
                nodes,
                vertices,
                patches: records,
            } => Hierarchy::new(patches, nodes, vertices, records)?,
            Store::Bytes(bytes) => Hierarchy::from_bytes(patches, bytes)?,
        })
    }

    /// The hierarchy's compact bytes ([`encode_hierarchy`]): what a firmware keeps in flash
    /// ([`write_rust_source`](crate::bake::write_rust_source), or `include_bytes!`).
    pub fn to_bytes(&self) -> Result<Vec<u8>, HostError> {
        if let Store::Bytes(bytes) = &self.store {
            return Ok(bytes.clone());
        }
        let tree = self.hierarchy()?;
        let (nodes, vertices) = (tree.node_count(), tree.vertex_count());
        let mut scratch = vec![0u32; encode_scratch_len(nodes, vertices)];
        let patches = self.surfaces.patches().len();
        let mut out = vec![0u8; 64 + 64 * (nodes + vertices + patches)];
        let len = encode_hierarchy(&tree, &mut scratch, &mut out)?;
        out.truncate(len);
        Ok(out)
    }

    /// A cache file's bytes: a magic, the settings, then [`to_bytes`](Self::to_bytes).
    pub(super) fn cache_bytes(&self, settings: &BakeSettings) -> Result<Vec<u8>, HostError> {
        let mut out = CACHE_MAGIC.to_vec();
        out.extend_from_slice(&settings_bytes(settings));
        out.extend_from_slice(&self.to_bytes()?);
        Ok(out)
    }

    /// The bake a cache file's bytes hold, where they hold one of `surfaces` with `settings`
    /// (its bytes checked as [`from_bytes`](Self::from_bytes) checks them).
    pub fn read_cache(surfaces: &Surfaces, settings: &BakeSettings, bytes: &[u8]) -> Option<Baked> {
        let rest = bytes.strip_prefix(CACHE_MAGIC)?;
        let rest = rest.strip_prefix(&settings_bytes(settings)[..])?;
        let mut baked = Baked::from_bytes(surfaces.clone(), rest.to_vec()).ok()?;
        baked.settings = Some(*settings);
        Some(baked)
    }

    /// The frame of `view`: the coarsest mesh of the hierarchy within the view's tolerance
    /// (see [`Tessellator::update`]; searched on all cores, [`Tessellator::update_parallel`],
    /// the same mesh), refined below the bake into a pool of vertices that
    /// grows until the frame is within it (or reaches 1M vertices; the frame's
    /// [`stats`](Mesh::stats) then report the bound it keeps).
    ///
    /// Each call checks the hierarchy and sets up a tessellator's storage anew. For frame
    /// after frame (an animation, a viewer), keep one [`Tessellator`] over
    /// [`hierarchy`](Self::hierarchy) and take each frame's mesh with
    /// [`Mesh::of_frame`]: a frame then costs its update and its write alone.
    pub fn tessellate(&self, view: &View) -> Result<Mesh, HostError> {
        let tree = self.hierarchy()?;
        let mut bits = vec![0u32; tree.bit_words()];
        let mut stack = vec![StackSlot::default(); STACK];
        let mut pool_len = FIRST_POOL;
        loop {
            let mut pool = vec![PoolSlot::default(); pool_len];
            let mut t = Tessellator::from_slices(tree, &mut bits, &mut stack, &mut pool)?;
            let stats = t.update_parallel(view)?;
            if stats.pool_full && pool_len < MAX_POOL {
                pool_len *= 16;
                continue;
            }
            return Mesh::of_frame(&mut t, &self.surfaces, stats);
        }
    }
}

/// The settings as a cache file keeps them.
fn settings_bytes(settings: &BakeSettings) -> [u8; 7] {
    let (kind, tolerance) = match settings.tolerance {
        Tolerance::Absolute(t) => (0, t),
        Tolerance::Relative(t) => (1, t),
    };
    let t = tolerance.to_bits().to_le_bytes();
    [
        kind,
        t[0],
        t[1],
        t[2],
        t[3],
        settings.max_depth,
        settings.max_cell_level,
    ]
}
