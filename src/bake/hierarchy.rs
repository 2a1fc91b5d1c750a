//! The bake: every patch's square cut into cells (`cells`), their triangles halved, and halved
//! again, until each triangle is within the tolerance of the surface, the mesh kept conforming
//! across hypotenuses and shared curves; each triangle recorded with its kept deviation
//! vectors, each vertex with its point.

use core::fmt;

use super::runner::{BakeRunner, InOrder};
use super::Tolerance;
use crate::deviation::kept::keep;
use crate::deviation::lattice::{coarse, deviation_vectors, POINTS, STEPS};
use glam::Vec3;

/// How much larger than its triangles' own a diamond's shared bound may be (in model units):
/// past it, each keeps its own (the bytes then keep both).
const SHARED_SLACK: f32 = 0.07;

/// Vectors of a coarse lattice ([`coarse`]).
const COARSE: usize = (STEPS / 2 + 1) * (STEPS / 2 + 2) / 2;
// A diamond's two lattices are looked at in full by `keep`.
const _: () = assert!(2 * POINTS <= crate::deviation::kept::MAX_VECTORS);
use crate::model::Model;
use crate::patch::Side;
use crate::tessellator::address::{point_on, root_count, side_parameter, unit, SideLink, Tri, ONE};
use crate::tessellator::hierarchy::cell_corner;
use crate::tessellator::quantize::{round_normal, LogGrid, PositionGrid};
use crate::tessellator::{
    HierarchyNode, HierarchyPatch, HierarchyVertex, MAX_CELL_LEVEL, NO_VERTEX,
};

/// What to bake.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BakeSettings {
    /// Where halving stops: a triangle within this bound of the surface is not halved.
    pub tolerance: Tolerance,
    /// Most halvings from a cell's diagonal (two halve a side; at most 30, and a cell's
    /// lattice stops halving at 24).
    pub max_depth: u8,
    /// Most cell levels in a direction (see [`Cells`](crate::tessellator::Cells)): 0 keeps
    /// every patch one cell, a square halved as it is; at most
    /// [`MAX_CELL_LEVEL`], the default.
    pub max_cell_level: u8,
}

impl Default for BakeSettings {
    fn default() -> Self {
        BakeSettings {
            tolerance: Tolerance::Relative(1e-3),
            max_depth: 24,
            max_cell_level: MAX_CELL_LEVEL,
        }
    }
}

/// The caller's storage for a bake.
#[derive(Debug)]
pub struct BakeBuffers<'a> {
    /// One per triangle of the hierarchy.
    pub nodes: &'a mut [HierarchyNode],
    /// One per vertex (patch corners and halving points).
    pub vertices: &'a mut [HierarchyVertex],
    /// One per patch.
    pub patches: &'a mut [HierarchyPatch],
    /// Working memory: one per triangle, as many as `nodes`.
    pub scratch: &'a mut [BakeScratch],
}

/// Working memory of a bake, one per triangle: its place in the hierarchy, and its bound's
/// job for a [`BakeRunner`] (88 bytes in all).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BakeScratch {
    tri: Tri,
    pub(super) corners: [u32; 3],
    /// A batch's job ([`BakeRunner`]): the triangle across a diamond, where its bound is
    /// the diamond's.
    partner: Option<(Tri, [u32; 3])>,
    /// And its result.
    bound: HierarchyNode,
}

/// How much a bake wrote.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BakeSize {
    /// Triangles of the hierarchy.
    pub nodes: usize,
    /// Vertices.
    pub vertices: usize,
}

/// Why a bake failed.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum BakeError {
    /// The model has no patch.
    NoPatches,
    /// The tolerance is not a positive finite number.
    BadTolerance(f32),
    /// `max_depth` is above 30.
    TooDeep(u8),
    /// A curve is shared by more than two patch edges (not supported).
    NonManifold {
        /// The curve.
        curve: u32,
    },
    /// The patch buffer holds fewer entries than the model has patches.
    PatchesTooSmall {
        /// Entries needed.
        needed: usize,
    },
    /// The node (or scratch) buffer filled up: the hierarchy has more than `capacity`
    /// triangles. How many is known only once a bake completes (a triangle is halved or not
    /// by its bound, which is computed as the bake goes): bake again into larger buffers, as
    /// the crate docs' example does, and [`BakeSize`] then gives the exact sizes (for
    /// statics, say).
    NodesFull {
        /// Entries of the smaller of the two.
        capacity: usize,
    },
    /// The vertex buffer filled up: the hierarchy has more than `capacity` vertices (see
    /// [`NodesFull`](Self::NodesFull)).
    VerticesFull {
        /// Its entries.
        capacity: usize,
    },
    /// A [`BakeRunner`] left jobs of a batch undone (it must run each job once).
    JobsSkipped {
        /// Jobs left undone.
        skipped: usize,
    },
}

impl fmt::Display for BakeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BakeError::NoPatches => write!(f, "the model has no patch"),
            BakeError::BadTolerance(t) => write!(f, "tolerance {t} is not positive"),
            BakeError::TooDeep(d) => write!(f, "max_depth {d} is above 30"),
            BakeError::NonManifold { curve } => {
                write!(f, "curve {curve} is shared by more than two patch edges")
            }
            BakeError::PatchesTooSmall { needed } => {
                write!(f, "patch buffer too small: {needed} entries needed")
            }
            BakeError::NodesFull { capacity } => {
                write!(
                    f,
                    "node buffer full: the hierarchy has more than {capacity} triangles"
                )
            }
            BakeError::VerticesFull { capacity } => {
                write!(
                    f,
                    "vertex buffer full: the hierarchy has more than {capacity} vertices"
                )
            }
            BakeError::JobsSkipped { skipped } => {
                write!(f, "the bake's runner left {skipped} jobs undone")
            }
        }
    }
}

impl core::error::Error for BakeError {}

/// How far a bake has come: handed to [`bake_hierarchy_with_progress`]'s callback.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BakeProgress {
    /// Triangles whose bound is recorded.
    pub recorded: usize,
    /// Triangles made so far (the recorded ones and those waiting): the hierarchy has at
    /// least this many.
    pub made: usize,
}

/// Bakes `model` into `out` (see the [module docs](super)).
pub fn bake_hierarchy(
    model: &Model<'_>,
    settings: &BakeSettings,
    out: BakeBuffers<'_>,
) -> Result<BakeSize, BakeError> {
    bake_hierarchy_with_progress(model, settings, out, &mut |_| {})
}

/// [`bake_hierarchy`], calling `progress` every 4,096 triangles recorded (a host shows it:
/// a fine bake of a large model takes seconds).
pub fn bake_hierarchy_with_progress(
    model: &Model<'_>,
    settings: &BakeSettings,
    out: BakeBuffers<'_>,
    progress: &mut dyn FnMut(BakeProgress),
) -> Result<BakeSize, BakeError> {
    bake_hierarchy_with(model, settings, out, progress, &InOrder)
}

/// [`bake_hierarchy_with_progress`], with the triangles' bounds (most of a bake's time)
/// computed by `runner`: one after another ([`InOrder`]), or on all cores (`Parallel`, feature
/// `std`). Each bound depends on its triangle alone, so the hierarchy is the same bit for bit
/// whatever runs it.
pub fn bake_hierarchy_with(
    model: &Model<'_>,
    settings: &BakeSettings,
    out: BakeBuffers<'_>,
    progress: &mut dyn FnMut(BakeProgress),
    runner: &dyn BakeRunner,
) -> Result<BakeSize, BakeError> {
    let count = model.patches.len();
    if count == 0 {
        return Err(BakeError::NoPatches);
    }
    if settings.max_depth > 30 {
        return Err(BakeError::TooDeep(settings.max_depth));
    }
    let diagonal = model.patches.aabb().map_or(f32::NAN, |b| b.diagonal());
    let tolerance = settings.tolerance.in_model_units(diagonal);
    if !(tolerance > 0.0 && tolerance.is_finite()) {
        return Err(BakeError::BadTolerance(tolerance));
    }
    if out.patches.len() < count {
        return Err(BakeError::PatchesTooSmall { needed: count });
    }
    let capacity = out.nodes.len().min(out.scratch.len());
    let mut baker = Baker {
        model,
        grid: PositionGrid::of(&model.patches),
        scales: LogGrid::scales(&model.patches),
        bounds: LogGrid::bounds(&model.patches),
        nodes: out.nodes,
        vertices: out.vertices,
        patches: &mut out.patches[..count],
        scratch: out.scratch,
        capacity,
        node_count: 0,
        vertex_count: 0,
        max_depth: settings.max_depth,
    };
    baker.link_sides()?;
    baker.corners()?;
    let max_cell_level = settings.max_cell_level.min(MAX_CELL_LEVEL);
    super::cells::choose(model, baker.patches, baker.scratch, max_cell_level);
    baker.cell_vertices()?;
    for p in 0..count {
        let rec = baker.patches[p];
        baker.patches[p].first_root = baker.node_count as u32;
        for k in 0..root_count(rec.cells) {
            let tri = Tri::root(p as u32, rec.cells, k);
            baker.push_node(tri, tri.corners.map(|g| cell_corner(&rec, g)))?;
        }
    }
    // The bounds of the triangles made so far in one batch (each depends on its triangle
    // alone), then each halved or not in order (which makes the next batch).
    let (mut i, mut bounded) = (0, 0);
    while i < baker.node_count {
        if i == bounded {
            bounded = baker.node_count;
            baker.bound_batch(i..bounded, runner)?;
        }
        if i % 4096 == 4095 {
            progress(BakeProgress {
                recorded: i + 1,
                made: baker.node_count,
            });
        }
        let bound = baker.scratch[i].bound;
        let node = &mut baker.nodes[i];
        (node.vectors, node.scale, node.remainder) = (bound.vectors, bound.scale, bound.remainder);
        if baker.nodes[i].children == 0 && baker.object_bound(i) > tolerance {
            baker.split(i, 0)?;
        }
        i += 1;
    }
    baker.share_diamonds(runner)?;
    let (n, v) = (baker.node_count, baker.vertex_count);
    // A leaf keeps one bound: the bake's tolerance (rounded up), or its own where that is
    // larger (a leaf at the depth limit). The bytes keep the first once and the others apart.
    for node in baker.nodes[..n].iter_mut().filter(|x| x.children == 0) {
        let own = node.object_bound();
        *node = HierarchyNode {
            remainder: baker
                .bounds
                .round_up(if own > tolerance { own } else { tolerance }),
            ..HierarchyNode::default()
        };
    }
    super::orientation::orient(
        model,
        baker.patches,
        &mut baker.vertices[..v],
        &mut baker.scratch[..n],
    );
    // Normals rounded to the bytes' octahedral codes, once they point out.
    for x in baker.vertices[..v].iter_mut() {
        x.normal = round_normal(x.normal);
    }
    Ok(BakeSize {
        nodes: baker.node_count,
        vertices: baker.vertex_count,
    })
}

struct Baker<'m, 'o> {
    model: &'o Model<'m>,
    /// The grids the records are rounded to (the bytes' own).
    grid: PositionGrid,
    scales: LogGrid,
    bounds: LogGrid,
    nodes: &'o mut [HierarchyNode],
    vertices: &'o mut [HierarchyVertex],
    patches: &'o mut [HierarchyPatch],
    scratch: &'o mut [BakeScratch],
    capacity: usize,
    node_count: usize,
    vertex_count: usize,
    max_depth: u8,
}

/// A job's bound before its runner computed it: a remainder no bound has (a bound's is a
/// number, or infinite), so that a job left undone is found ([`done`]).
const UNDONE: HierarchyNode = HierarchyNode {
    children: 0,
    vertex: 0,
    vectors: [[0; 3]; crate::deviation::kept::KEPT],
    scale: 0.0,
    remainder: f32::NAN,
};

/// Whether every job of a batch was run: none is left [`UNDONE`] (jobs outside the batch
/// hold bounds already).
fn done(jobs: &[BakeScratch]) -> Result<(), BakeError> {
    let skipped = jobs.iter().filter(|j| j.bound.remainder.is_nan()).count();
    match skipped {
        0 => Ok(()),
        skipped => Err(BakeError::JobsSkipped { skipped }),
    }
}

/// What a triangle's bound is computed from: the model, the vertices made so far, and the
/// grids the bound is rounded to. Read only: the jobs of a batch share it.
struct BoundSource<'a, 'm> {
    model: &'a Model<'m>,
    vertices: &'a [HierarchyVertex],
    scales: LogGrid,
    bounds: LogGrid,
}

impl BoundSource<'_, '_> {
    /// The lattice of triangle `tri` with corners `corners`: its deviation vectors and
    /// remainder (`None` where not finite).
    fn lattice(&self, tri: Tri, corners: [u32; 3]) -> Option<([Vec3; POINTS], f32)> {
        let patch = self.model.patches.patch(tri.patch as usize)?;
        let points = corners.map(|v| self.vertices[v as usize].position);
        let grid = tri.corners.map(|p| [p[0] as u32, p[1] as u32]);
        let (vectors, remainder) =
            deviation_vectors::<STEPS, POINTS>(&patch, grid, ONE as u32, points);
        let finite = remainder.is_finite() && vectors.iter().all(|v| v.is_finite());
        finite.then_some((vectors, remainder))
    }

    /// The record of a bound from `vectors` (keeping a few of `candidates`) and `remainder`.
    fn bound_of(&self, vectors: &[Vec3], candidates: &[Vec3], remainder: f32) -> HierarchyNode {
        let scales = self.scales;
        let k = keep(vectors, candidates, |s| scales.round_up(s));
        HierarchyNode {
            vectors: k.vectors,
            scale: k.scale,
            remainder: self
                .bounds
                .round_up((remainder + k.widening) * (1.0 + 1.0 / 1024.0)),
            ..HierarchyNode::default()
        }
    }

    /// The bound of triangle `tri` with corners `corners`: its kept deviation vectors.
    fn triangle(&self, tri: Tri, corners: [u32; 3]) -> HierarchyNode {
        match self.lattice(tri, corners) {
            Some((vectors, remainder)) => self.bound_of(&vectors, &coarse(&vectors), remainder),
            None => HierarchyNode {
                remainder: f32::INFINITY,
                ..HierarchyNode::default()
            },
        }
    }

    /// The one bound of a diamond's two triangles `a` and `b` (each with its corners): the
    /// vectors kept from both lattices, the widening covering both, the larger remainder.
    fn diamond(&self, a: (Tri, [u32; 3]), b: (Tri, [u32; 3])) -> HierarchyNode {
        match (self.lattice(a.0, a.1), self.lattice(b.0, b.1)) {
            (Some((a, ra)), Some((b, rb))) => {
                let mut vectors = [Vec3::ZERO; 2 * POINTS];
                vectors[..POINTS].copy_from_slice(&a);
                vectors[POINTS..].copy_from_slice(&b);
                let (ca, cb) = (coarse(&a), coarse(&b));
                let mut candidates = [Vec3::ZERO; 2 * COARSE];
                candidates[..COARSE].copy_from_slice(&ca);
                candidates[COARSE..].copy_from_slice(&cb);
                self.bound_of(&vectors, &candidates, ra.max(rb))
            }
            _ => HierarchyNode {
                remainder: f32::INFINITY,
                ..HierarchyNode::default()
            },
        }
    }
}

impl Baker<'_, '_> {
    /// Which side of which patch each shared side joins.
    fn link_sides(&mut self) -> Result<(), BakeError> {
        let edges = self.model.topology.edges();
        let curves = self.model.topology.curves();
        for (c, curve) in curves.iter().enumerate() {
            if curve.uses > 2 {
                return Err(BakeError::NonManifold { curve: c as u32 });
            }
        }
        for p in 0..self.patches.len() {
            let mut links = [None; 4];
            for side in Side::ALL {
                let Some(crate::EdgeLink::Curve { curve, reversed }) =
                    edges.get(p).map(|e| e[side.index()])
                else {
                    continue;
                };
                if !curves.get(curve as usize).is_some_and(|c| c.is_shared()) {
                    continue;
                }
                'find: for (q, e) in edges.iter().enumerate().take(self.patches.len()) {
                    for other in Side::ALL {
                        if (q, other) == (p, side) {
                            continue;
                        }
                        if let crate::EdgeLink::Curve {
                            curve: c2,
                            reversed: r2,
                        } = e[other.index()]
                        {
                            if c2 == curve {
                                links[side.index()] = Some(SideLink {
                                    patch: q as u32,
                                    side: other,
                                    flip: reversed != r2,
                                });
                                break 'find;
                            }
                        }
                    }
                }
            }
            self.patches[p].links = links;
            self.patches[p].poles = crate::tessellator::hierarchy::poles_of(&self.model.patches, p);
        }
        Ok(())
    }

    /// One vertex per distinct patch corner (corners whose control points are equal bit for
    /// bit are one vertex).
    fn corners(&mut self) -> Result<(), BakeError> {
        let corner_point = |p: usize, k: usize| {
            self.model.patches.patch(p).map_or([0; 3], |patch| {
                let (du, dv) = (patch.degree_u(), patch.degree_v());
                let (i, j) = [(0, 0), (du, 0), (du, dv), (0, dv)][k];
                patch.control_point(i, j).to_array().map(f32::to_bits)
            })
        };
        for p in 0..self.patches.len() {
            for k in 0..4 {
                let here = corner_point(p, k);
                let mut found = None;
                'search: for q in 0..=p {
                    for j in 0..4 {
                        if (q, j) == (p, k) {
                            break 'search;
                        }
                        if corner_point(q, j) == here {
                            found = Some(self.patches[q].corners[j]);
                            break 'search;
                        }
                    }
                }
                self.patches[p].corners[k] = match found {
                    Some(v) => v,
                    None => {
                        let m = ONE;
                        let g = [[0, 0], [m, 0], [m, m], [0, m]][k];
                        self.push_vertex(p as u32, g)?
                    }
                };
            }
        }
        Ok(())
    }

    /// The vertices at the corners of each patch's cells (with more than one cell): one
    /// record per corner, in [`HierarchyPatch::cell_vertices`]'s order; a corner of the patch,
    /// a point of a curve of a patch before it, or a point of a collapsed side is a copy
    /// written out as that vertex (the pole's, for a collapsed side).
    fn cell_vertices(&mut self) -> Result<(), BakeError> {
        for p in 0..self.patches.len() {
            let rec = self.patches[p];
            if rec.cells == [0, 0] {
                continue;
            }
            let [a, b] = rec.cells;
            self.patches[p].cell_vertices = self.vertex_count as u32;
            for i in 0..=(1u32 << a) {
                for j in 0..=(1u32 << b) {
                    let g = [
                        (i * (ONE as u32 >> a)) as u16,
                        (j * (ONE as u32 >> b)) as u16,
                    ];
                    let same = self.existing_vertex(p, g);
                    match same {
                        Some(v) => {
                            let copy = self.vertices[v as usize];
                            let n = self.vertex_count;
                            let slot = self
                                .vertices
                                .get_mut(n)
                                .ok_or(BakeError::VerticesFull { capacity: n })?;
                            *slot = copy;
                            self.vertex_count += 1;
                        }
                        None => {
                            self.push_vertex(p as u32, g)?;
                        }
                    }
                }
            }
        }
        Ok(())
    }

    /// The vertex a cell corner `g` of patch `p` is written out as, where one is already
    /// made: a corner of the patch, a pole, or a point of a curve of a patch before it (the
    /// records' links and cells set, and the patches before it done).
    fn existing_vertex(&self, p: usize, g: [u16; 2]) -> Option<u32> {
        let rec = &self.patches[p];
        if let Some(k) = [[0, 0], [ONE, 0], [ONE, ONE], [0, ONE]]
            .iter()
            .position(|&c| c == g)
        {
            return Some(rec.corners[k]);
        }
        for side in Side::ALL {
            let on = match side {
                Side::V0 => g[1] == 0,
                Side::U1 => g[0] == ONE,
                Side::V1 => g[1] == ONE,
                Side::U0 => g[0] == 0,
            };
            if !on {
                continue;
            }
            if let Some(pole) = self.pole_of_side(p, side) {
                return Some(self.vertices[pole as usize].output);
            }
            if let Some(l) = rec.links[side.index()] {
                let t = side_parameter(side, g);
                let there = point_on(l.side, if l.flip { ONE - t } else { t });
                let other = &self.patches[l.patch as usize];
                // A patch before this one, or this one's own other side where its corner is
                // already made (corners go along `v` first).
                let made = match (l.patch as usize).cmp(&p) {
                    core::cmp::Ordering::Less => true,
                    core::cmp::Ordering::Equal => cell_corner(rec, there) < cell_corner(rec, g),
                    core::cmp::Ordering::Greater => false,
                };
                if made {
                    return Some(self.vertices[cell_corner(other, there) as usize].output);
                }
            }
        }
        None
    }

    fn push_vertex(&mut self, patch: u32, at: [u16; 2]) -> Result<u32, BakeError> {
        let n = self.vertex_count;
        let slot = self
            .vertices
            .get_mut(n)
            .ok_or(BakeError::VerticesFull { capacity: n })?;
        let (u, v) = unit(at);
        let s = self
            .model
            .patches
            .patch(patch as usize)
            .map(|bp| bp.evaluate(u, v));
        // The point rounded to the bytes' grid: every bound is measured against it.
        *slot = HierarchyVertex {
            position: self
                .grid
                .round(s.map_or([0.0; 3], |s| s.position.to_array())),
            normal: s.map_or([0.0; 3], |s| s.normal.to_array()),
            uv: at,
            patch,
            output: n as u32,
        };
        self.vertex_count += 1;
        Ok(n as u32)
    }

    fn push_node(&mut self, tri: Tri, corners: [u32; 3]) -> Result<usize, BakeError> {
        let n = self.node_count;
        if n >= self.capacity {
            return Err(BakeError::NodesFull {
                capacity: self.capacity,
            });
        }
        self.nodes[n] = HierarchyNode {
            children: 0,
            vertex: NO_VERTEX,
            ..HierarchyNode::default()
        };
        self.scratch[n] = BakeScratch {
            tri,
            corners,
            ..BakeScratch::default()
        };
        self.node_count += 1;
        Ok(n)
    }

    /// The bounds of nodes `range` (made, not yet bounded) into their scratch, by `runner`;
    /// an error where it left a job undone (each job's bound starts as [`UNDONE`]).
    fn bound_batch(
        &mut self,
        range: core::ops::Range<usize>,
        runner: &dyn BakeRunner,
    ) -> Result<(), BakeError> {
        for job in &mut self.scratch[range.clone()] {
            job.bound = UNDONE;
        }
        let source = BoundSource {
            model: self.model,
            vertices: &self.vertices[..self.vertex_count],
            scales: self.scales,
            bounds: self.bounds,
        };
        runner.run(&mut self.scratch[range.clone()], &|job| {
            job.bound = source.triangle(job.tri, job.corners);
        });
        done(&self.scratch[range])
    }

    /// Gives the two halved triangles of each diamond (halved at one vertex, across their
    /// hypotenuse) one bound, which holds for both: the vectors kept from both lattices, the
    /// widening covering both, the larger remainder. Where either is split the other is too,
    /// so little changes; the bytes keep one bound a diamond.
    fn share_diamonds(&mut self, runner: &dyn BakeRunner) -> Result<(), BakeError> {
        // Each diamond's pair, found in order, is a job of its first triangle's scratch.
        let mut pairs = 0;
        for i in 0..self.node_count {
            self.scratch[i].partner = None;
            if self.nodes[i].children == 0 {
                continue;
            }
            let t = self.scratch[i].tri;
            let patches = &*self.patches;
            let link = |p: u32, s: Side| patches.get(p as usize).and_then(|r| r.links[s.index()]);
            let cells = |p: u32| patches.get(p as usize).map_or([0, 0], |r| r.cells);
            let Some(n) = t.across(link, cells) else {
                continue;
            };
            let j = self.locate(&n);
            let partner = j > i
                && self.scratch[j].tri == n
                && self.nodes[j].children != 0
                && self.nodes[j].vertex == self.nodes[i].vertex;
            if partner {
                self.scratch[i].partner = Some((n, self.scratch[j].corners));
                self.scratch[i].bound = UNDONE;
                pairs += 1;
            }
        }
        if pairs == 0 {
            return Ok(());
        }
        let source = BoundSource {
            model: self.model,
            vertices: &self.vertices[..self.vertex_count],
            scales: self.scales,
            bounds: self.bounds,
        };
        runner.run(&mut self.scratch[..self.node_count], &|job| {
            if let Some(across) = job.partner {
                job.bound = source.diamond((job.tri, job.corners), across);
            }
        });
        done(&self.scratch[..self.node_count])?;
        for i in 0..self.node_count {
            let Some((n, _)) = self.scratch[i].partner else {
                continue;
            };
            let j = self.locate(&n);
            let bound = self.scratch[i].bound;
            // Shared only where it costs little: the diamond's bound in model units at most
            // SHARED_SLACK over the larger of its triangles' own.
            let own = self.nodes[i]
                .object_bound()
                .max(self.nodes[j].object_bound());
            let shared = bound.object_bound();
            if shared.is_nan() || shared > own * (1.0 + SHARED_SLACK) {
                continue;
            }
            for k in [i, j] {
                let node = &mut self.nodes[k];
                (node.vectors, node.scale, node.remainder) =
                    (bound.vectors, bound.scale, bound.remainder);
            }
        }
        Ok(())
    }

    /// Node `i`'s bound in model units.
    fn object_bound(&self, i: usize) -> f32 {
        self.nodes[i].object_bound()
    }

    /// The node of the leaf that holds triangle `t` (its own, or a coarser one's).
    fn locate(&self, t: &Tri) -> usize {
        let rec = &self.patches[t.patch as usize];
        let mut n = rec.first_root as usize + t.root_index(rec.cells);
        let target = t.centroid3();
        while self.scratch[n].tri != *t && self.nodes[n].children != 0 {
            n = self.nodes[n].children as usize
                + self.scratch[n].tri.half_toward(target, rec.cells);
        }
        n
    }

    /// Halves leaf `i` and the triangle across its hypotenuse (halving coarser ones first
    /// where needed, so that one of their halves is across), unless it is at the depth
    /// limit or the triangle across cannot be made. `depth` guards the recursion (a coarser
    /// triangle across is at least one level up, so the guard is never reached by a cell's 24 levels).
    fn split(&mut self, i: usize, depth: u32) -> Result<(), BakeError> {
        let t = self.scratch[i].tri;
        let cells = self.patches[t.patch as usize].cells;
        if self.nodes[i].children != 0 || !t.can_split(cells) || t.level(cells) >= self.max_depth {
            return Ok(());
        }
        let mut across = None;
        let patches = &*self.patches;
        let link = |p: u32, s: Side| patches.get(p as usize).and_then(|r| r.links[s.index()]);
        let cells = |p: u32| patches.get(p as usize).map_or([0, 0], |r| r.cells);
        if let Some(n) = t.across(link, cells) {
            loop {
                let leaf = self.locate(&n);
                if self.scratch[leaf].tri == n {
                    across = Some(leaf);
                    break;
                }
                let before = self.node_count;
                if depth > 64 {
                    return Ok(());
                }
                self.split(leaf, depth + 1)?;
                if self.node_count == before {
                    // The coarser leaf stays whole (it cannot be halved): so does this one,
                    // which would otherwise leave a vertex on its side.
                    return Ok(());
                }
            }
        }
        let v = self.push_vertex(t.patch, t.midpoint())?;
        if let Some(pole) = self.pole(&t) {
            // A point of a collapsed side is the pole: written out as its corner's vertex.
            self.vertices[v as usize] = HierarchyVertex {
                output: pole,
                ..self.vertices[pole as usize]
            };
        }
        for k in [Some(i), across].into_iter().flatten() {
            let BakeScratch { tri, corners, .. } = self.scratch[k];
            let [a, b, c] = corners;
            let [h0, h1] = tri.children();
            let first = self.push_node(h0, [v, a, b])?;
            self.push_node(h1, [v, c, a])?;
            self.nodes[k].children = first as u32;
            self.nodes[k].vertex = v;
        }
        Ok(())
    }

    /// The corner vertex of the side `t`'s hypotenuse lies on, if that side is collapsed (as
    /// the run time names it: `Hierarchy::pole`).
    fn pole(&self, t: &Tri) -> Option<u32> {
        self.pole_of_side(t.patch as usize, t.hypotenuse_side()?)
    }

    /// The corner vertex of side `side` of patch `p`, if that side is collapsed.
    fn pole_of_side(&self, p: usize, side: Side) -> Option<u32> {
        let collapsed = self.model.patches.patch(p)?.is_collapsed(side);
        let corner = match side {
            Side::V0 | Side::U0 => 0,
            Side::U1 => 1,
            Side::V1 => 2,
        };
        collapsed.then(|| self.patches[p].corners[corner])
    }
}
