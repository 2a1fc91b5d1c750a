//! The run time: a frame's mesh found top-down from the patches' roots (their cells).
//!
//! # The search
//!
//! Every triangle is judged once, when it becomes a leaf: the patches' roots first, then
//! the halves of every triangle that is halved. A leaf whose bound is over the tolerance is
//! halved with the triangle across its hypotenuse (halving a coarser one there first, which is
//! found by walking down from its patch's root, or with the hierarchy's links by walking up
//! from the triangle across to the first halved parent: see `links`). Only a leaf over the tolerance, or one a
//! halved triangle needs halved, is ever halved, and every leaf of the result is judged, so
//! the result is the unique coarsest conforming mesh within the tolerance (see the [module
//! docs](super)), whatever the order.
//!
//! Leaves waiting to be judged are kept on a stack of the caller's, as many as fit. A leaf
//! that finds it full is not lost: every node has a bit saying it was judged, and when the
//! stack has run dry the patches of the leaves it had no room for are walked (a bit per patch
//! number modulo 32 says which) and their leaves not yet judged are judged then, until a walk
//! finds none. A short stack costs walks, never the result.
//!
//! Below the bake (a view finer than the bake) the same search goes on with vertices the run
//! time makes and bounds it computes (see `refine`); those triangles have no bits, so a walk
//! judges them again.
//!
//! # Storage
//!
//! Bits, in the caller's `u32`s ([`Hierarchy::bit_words`]): per node, whether the mesh halves
//! it (above the bake, or below it for a leaf of the bake), whether it was judged and whether
//! it is hidden (not written out); per vertex, whether the frame's count has seen it. A
//! triangle that is not halved is told by its bit, with nothing of the hierarchy decoded. A
//! stack of waiting triangles, and a
//! pool of vertices below the bake ([`RefinedVertex`]), both of any length.

use core::cell::Cell;
use core::fmt;

use super::address::{on_side, Tri};
use super::bits::{bit, clear, set, Layout};
use super::hierarchy::{walk, walk_roots, Hierarchy, Pending, RUN_TIME};
use super::judge::{judge, Bound};
use super::refine::{key, Pool, PoolSlot};
#[cfg(feature = "reuse")]
use super::reuse::Judgement;
use super::reuse::Reuse;
use super::storage::{StackSlot, TessellatorStorage};
use crate::deviation::certificate::Asked;
use crate::deviation::PatchBounds;
use crate::math::max;
use crate::patch::Side;
use crate::view::{Camera, View};
use crate::Arithmetic;
use glam::Vec3;

/// What a frame did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct FrameStats {
    /// Triangles written out. (The vertices they use are counted on demand:
    /// [`Tessellator::mesh_size`].)
    pub triangles: usize,
    /// Triangles judged.
    pub judged: usize,
    /// Triangles whose judgement was kept from a frame before, certified to hold (see
    /// `Tessellator::with_reuse`, feature `reuse`): not judged again, and not counted in `judged`.
    pub kept: usize,
    /// Triangles left out for lying beyond a plane of the view.
    pub hidden: usize,
    /// Vertices made below the bake (a view finer than the bake).
    pub refined: usize,
    /// Leaves still over the tolerance: the pool of vertices below the bake was full, or
    /// the grid's finest step was reached.
    pub left_over: usize,
    /// An upper bound of every written triangle's bound, in the view's units (pixels or
    /// model units): at most the tolerance when nothing is left over, and what the frame
    /// honours when something is. (A frame that kept a triangle's judgement knows only that
    /// its bound is within the tolerance: the tolerance is then this bound.)
    pub worst_bound: f32,
    /// Walks of the mesh made for leaves the stack had no room for.
    pub sweeps: usize,
    /// Most leaves waiting at once.
    pub stack_peak: usize,
    /// The pool of vertices below the bake filled up and left leaves over the tolerance: a
    /// larger pool gives a finer frame (the leaves it left whole are in
    /// [`left_over`](Self::left_over)).
    pub pool_full: bool,
    /// The mesh is the last frame's, changed where the view changed it (a step: see
    /// `Tessellator::with_reuse`, feature `reuse`), not searched from the roots. The same
    /// mesh either way; [`judged`](Self::judged) and [`kept`](Self::kept) then count the
    /// mesh's triangles and the triangles it halves for their own bound, not every triangle a
    /// search looks at.
    pub stepped: bool,
}

/// Why a tessellator could not be made: its storage is too small for its hierarchy.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum TessellatorError {
    /// The bits are fewer than [`Hierarchy::bit_words`].
    BitsTooShort {
        /// Words needed.
        needed: usize,
    },
    /// The stack holds fewer than [`Tessellator::MIN_STACK`] entries.
    StackTooShort {
        /// Entries needed.
        needed: usize,
    },
    /// The judgements for reuse are fewer than [`Hierarchy::judgement_slots`].
    JudgementsTooShort {
        /// Slots needed.
        needed: usize,
    },
}

impl fmt::Display for TessellatorError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TessellatorError::BitsTooShort { needed } => {
                write!(f, "bit storage too short: {needed} words needed")
            }
            TessellatorError::StackTooShort { needed } => {
                write!(f, "stack too short: {needed} entries needed")
            }
            TessellatorError::JudgementsTooShort { needed } => {
                write!(f, "judgement storage too short: {needed} slots needed")
            }
        }
    }
}

impl core::error::Error for TessellatorError {}

/// Why a view cannot be tessellated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum UpdateError {
    /// The view's tolerance is not a positive finite number.
    BadTolerance,
}

impl fmt::Display for UpdateError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            UpdateError::BadTolerance => {
                write!(f, "the tolerance is not a positive finite number")
            }
        }
    }
}

impl core::error::Error for UpdateError {}

/// The run time of a baked hierarchy: each [`update`](Self::update) finds the frame's mesh
/// for a view; [`stream`](Self::stream) and [`write_mesh`](Self::write_mesh) write it out.
///
/// Its storage is the caller's: [`Hierarchy::bit_words`] words of bits and a stack of waiting
/// triangles, at least [`MIN_STACK`](Self::MIN_STACK) long (a longer one saves walks on
/// fine frames; see `stats().sweeps`).
#[derive(Debug)]
pub struct Tessellator<'t, 's> {
    pub(super) tree: Hierarchy<'t>,
    pub(super) bits: &'s mut [u32],
    pub(super) pool: Pool<'s>,
    pub(super) stack: &'s mut [StackSlot],
    pub(super) len: usize,
    pub(super) full: bool,
    /// The patches of the triangles the stack had no room for, as bit `patch % 32` (a walk
    /// looks for them in these patches only).
    pub(super) dropped_patches: u32,
    /// A triangle below the bake found no room on the stack this frame.
    pub(super) dropped_below: bool,
    /// A walk judged leaves below the bake again: the figures need a recount.
    pub(super) recount: bool,
    /// Triangles below the bake being judged at once, one inside the other.
    inline: usize,
    /// The vertices the frame's written triangles use, once a walk counted them (see
    /// [`count`](Self::count)).
    pub(super) vertices: Option<usize>,
    pub(super) layout: Layout,
    /// The last frame's view.
    pub(super) view: Option<View>,
    /// The sphere around the model's control points, where patches can be culled for facing
    /// away (see `cull`).
    pub(super) sphere: Option<crate::bound::BoundingSphere>,
    /// Judgements kept from frame to frame, if the caller gave room for them.
    pub(super) reuse: Option<Reuse<'s>>,
    /// A step judges its lapsed triangles on the threads (see `step`; set by
    /// `update_parallel`).
    #[cfg(all(feature = "std", not(target_os = "none")))]
    pub(super) step_threads: bool,
    pub(super) stats: FrameStats,
    /// The model's box ([`PatchSet::aabb`](crate::PatchSet::aabb)), found once: a renderer
    /// asks for it every frame.
    #[cfg(feature = "embedded-graphics")]
    model_box: Option<crate::bound::Aabb>,
    /// The frame's last corners in view coordinates (see [`viewed`](Self::viewed)).
    pub(super) viewed: ViewedCorners,
    /// The frame's move of the bytes' grid points into view coordinates in integers, with
    /// `Arithmetic::Integer` (see `grid_view`).
    grid_view: Option<super::grid_view::GridView>,
    /// The frame's constants for a first look at triangles in integers, with `grid_view`
    /// (see `grid_judge`).
    grid_judge: super::grid_judge::GridJudge,
    /// What a first look's bound within the tolerance must be over to raise the frame's
    /// worst bound (see `grid_judge`).
    quotient_limit: super::grid_judge::QuotientLimit,
    /// How triangles' bounds are computed from their kept vectors.
    pub(super) arithmetic: Arithmetic,
    /// The node whose judgement over the tolerance is halving triangles now (kept with
    /// each halving for reuse: see `step`).
    pub(super) trigger: u32,
    /// A part of a frame searched on a thread of its own (see `parallel`); `None`: the whole
    /// model.
    #[cfg(all(feature = "std", not(target_os = "none")))]
    pub(super) group: Option<super::parallel::Group<'s>>,
}

/// Entries of [`ViewedCorners`]: 16 where `f32` is software (it saves `fw_teapot`'s frame 0
/// 10% of its update on ARMv6-M, 46.78M -> 42.18M instructions, for 256 bytes of RAM); none
/// (one unused) on a bare-metal part where it is hardware (the lookups cost the Cortex-M4F 4%
/// more than the moves they save); 64 on a host, where the points' decoding and the move
/// cost more than a lookup (measured 2026-11-27 with `frame_loop`, best of 1,000 frames:
/// the single-patch threejs model 0.376 -> 0.346 ms, the teapot at 2.5e-4 1.39 -> 1.28 ms;
/// 16 entries save less, 256 no more).
const VIEWED: usize = if !crate::math::HARD_FLOAT {
    16
} else if cfg!(target_os = "none") {
    1
} else {
    64
};

/// Whether judgements read corners through [`ViewedCorners`].
pub(super) const CACHE_VIEWED: bool = VIEWED > 1;

/// Whether [`ViewedCorners`] keeps two vertices a set (the last two of those whose numbers
/// it maps there), not one: where `f32` is software, whose misses cost most. `fw_teapot`'s
/// frame 0 update moves about 1,400 corners into the view instead of 1,757 on ARMv6-M, 8.16M
/// -> 8.07M instructions (RV32IMC 6.45M -> 6.39M); on a host, `frame_loop`'s updates took
/// about 1% more instructions two ways.
const TWO_WAY: bool = !crate::math::HARD_FLOAT;
const _: () = assert!(VIEWED.is_power_of_two());
const _: () = assert!(!TWO_WAY || !CACHE_VIEWED || VIEWED >= 2);

/// The last vertices of the bake moved into the frame's view coordinates, by vertex number
/// (direct-mapped, 16 bytes an entry): a judged triangle's corners are mostly its parent's and
/// its sibling's, each moved once instead of once a triangle. Emptied by every frame (a view
/// of its own); the same bits as moving them again.
#[derive(Debug)]
pub(super) struct ViewedCorners([Cell<(u32, [u32; 3])>; VIEWED]);

impl ViewedCorners {
    const EMPTY: (u32, [u32; 3]) = (u32::MAX, [0; 3]);

    pub(super) fn new() -> Self {
        ViewedCorners(core::array::from_fn(|_| Cell::new(Self::EMPTY)))
    }

    pub(super) fn clear(&self) {
        for e in &self.0 {
            e.set(Self::EMPTY);
        }
    }

    /// Vertex `v` (of a hierarchy of `vertices`) in the frame's view coordinates, which
    /// `moved` gives: kept for the bake's vertices where there is a cache ([`VIEWED`]).
    #[inline(always)]
    pub(super) fn get(&self, v: u32, vertices: usize, moved: impl FnOnce() -> Vec3) -> Vec3 {
        let bits = self.get_bits(v, vertices, || moved().to_array().map(f32::to_bits));
        Vec3::from_array(bits.map(f32::from_bits))
    }

    /// Vertex `v` in the frame's view coordinates in fixed point (see `grid_view`), which
    /// `moved` gives: kept as [`get`](Self::get) keeps points (a frame keeps one kind).
    #[inline(always)]
    pub(super) fn get_fixed(
        &self,
        v: u32,
        vertices: usize,
        moved: impl FnOnce() -> [i32; 3],
    ) -> [i32; 3] {
        let bits = self.get_bits(v, vertices, || moved().map(|x| x as u32));
        bits.map(|x| x as i32)
    }

    #[inline(always)]
    fn get_bits(&self, v: u32, vertices: usize, moved: impl FnOnce() -> [u32; 3]) -> [u32; 3] {
        if !CACHE_VIEWED || v as usize >= vertices {
            return moved();
        }
        self.get_bits_in(TWO_WAY, v, moved)
    }

    /// [`get_bits`](Self::get_bits) of a bake's vertex `v`: direct-mapped, or `two_way`, each
    /// pair of entries the last two vertices of its set, the last first (on every target:
    /// the tests check both).
    #[inline(always)]
    fn get_bits_in(&self, two_way: bool, v: u32, moved: impl FnOnce() -> [u32; 3]) -> [u32; 3] {
        // (`VIEWED` is a power of two.)
        let set = v as usize & (VIEWED - 1);
        let first = &self.0[if two_way { set & !1 } else { set }];
        let (key, at) = first.get();
        if key == v {
            return at;
        }
        if two_way {
            let second = &self.0[set | 1];
            let (older, at) = second.get();
            if older == v {
                return at;
            }
            // (The first entry read again, not kept from above: kept, ARMv6-M's frame 0 took
            // 0.01M instructions more.)
            second.set((key, first.get().1));
        }
        let at = moved();
        first.set((v, at));
        at
    }
}

/// Whether two views are the same bit for bit (`==` on floats takes `0.0` and `-0.0` as
/// equal, and they are not the same camera to every rounding).
fn same_view(a: &View, b: &View) -> bool {
    let bits = |v: &View| {
        let mut out = [0u32; 24];
        match v {
            View::Screen {
                camera,
                tolerance_px,
            } => {
                out[0] = 1;
                out[1] = tolerance_px.to_bits();
                out[2..].copy_from_slice(&camera.bits());
            }
            View::Object { tolerance } => {
                out[0] = 2;
                out[1] = tolerance.to_bits();
            }
        }
        out
    };
    bits(a) == bits(b)
}

/// A root of the hierarchy by its patch and its number there ([`Hierarchy::root`]), in the
/// order of the patches, then of their roots.
pub(super) type RootAt = (u32, u32);

/// A part of a frame: the roots `lo..hi` (see `parallel`).
pub(super) type Part = (RootAt, RootAt);

/// Whether some root of patch `p` is in `part` (`None`: the whole model).
pub(super) fn patch_in_part(part: Option<Part>, p: u32) -> bool {
    part.is_none_or(|(lo, hi)| lo.0 <= p && (p < hi.0 || (p == hi.0 && hi.1 > 0)))
}

/// Whether root `at` is in `part` (`None`: the whole model).
pub(super) fn root_in_part(part: Option<Part>, at: RootAt) -> bool {
    part.is_none_or(|(lo, hi)| lo <= at && at < hi)
}

/// Most walks of a frame for the leaves its stack had no room for. Each walk judges the
/// leaves below the bake again (they have no bit), so a stack far too short for a frame deep
/// below the bake could take many: past this many, the frame stops searching and reports the
/// bound it honours (see [`FrameStats::worst_bound`]).
const MAX_SWEEPS: usize = 16;

/// Deepest nesting of triangles below the bake judged at once for want of stack room.
const INLINE_DEPTH: usize = 16;

impl<'t, 's> Tessellator<'t, 's> {
    /// Fewest stack entries a run time takes.
    pub const MIN_STACK: usize = 4;

    /// A tessellator of `tree` in `storage` (see [`TessellatorStorage`] for its sizes).
    pub fn new<const BITS: usize, const STACK: usize, const POOL: usize>(
        tree: Hierarchy<'t>,
        storage: &'s mut TessellatorStorage<BITS, STACK, POOL>,
    ) -> Result<Self, TessellatorError> {
        Self::from_slices(
            tree,
            &mut storage.bits,
            &mut storage.stack,
            &mut storage.pool,
        )
    }

    /// A tessellator of `tree` in the caller's slices, for sizes chosen at run time: `bits`
    /// of at least [`Hierarchy::bit_words`] words, `stack` of at least
    /// [`MIN_STACK`](Self::MIN_STACK) entries, and `pool` for vertices below the bake (any
    /// length, none included: a frame finer than the bake then reports what it honours).
    pub fn from_slices(
        tree: Hierarchy<'t>,
        bits: &'s mut [u32],
        stack: &'s mut [StackSlot],
        pool: &'s mut [PoolSlot],
    ) -> Result<Self, TessellatorError> {
        Self::from_slices_culling(tree, bits, stack, pool, tree.culling_sphere())
    }

    /// [`from_slices`](Self::from_slices) with the model's culling sphere (`culling_sphere`,
    /// of every control point: a part of a frame on a host's threads takes its frame's).
    pub(super) fn from_slices_culling(
        tree: Hierarchy<'t>,
        bits: &'s mut [u32],
        stack: &'s mut [StackSlot],
        pool: &'s mut [PoolSlot],
        sphere: Option<crate::bound::BoundingSphere>,
    ) -> Result<Self, TessellatorError> {
        if bits.len() < tree.bit_words() {
            return Err(TessellatorError::BitsTooShort {
                needed: tree.bit_words(),
            });
        }
        if stack.len() < Self::MIN_STACK {
            return Err(TessellatorError::StackTooShort {
                needed: Self::MIN_STACK,
            });
        }
        let t = Tessellator::bare(tree, bits, stack, Pool::new(pool), sphere);
        #[cfg(feature = "embedded-graphics")]
        let t = Tessellator {
            model_box: tree.model.aabb(),
            ..t
        };
        Ok(t)
    }

    /// A tessellator over `tree` in this storage, before any frame (with no model box yet).
    fn bare(
        tree: Hierarchy<'t>,
        bits: &'s mut [u32],
        stack: &'s mut [StackSlot],
        pool: Pool<'s>,
        sphere: Option<crate::bound::BoundingSphere>,
    ) -> Self {
        Tessellator {
            tree,
            bits,
            pool,
            stack,
            len: 0,
            full: false,
            dropped_patches: 0,
            dropped_below: false,
            recount: false,
            inline: 0,
            vertices: None,
            layout: Layout::of(&tree),
            view: None,
            sphere,
            reuse: None,
            #[cfg(all(feature = "std", not(target_os = "none")))]
            step_threads: false,
            stats: FrameStats::default(),
            #[cfg(feature = "embedded-graphics")]
            model_box: None,
            viewed: ViewedCorners::new(),
            grid_view: None,
            grid_judge: super::grid_judge::GridJudge::OFF,
            quotient_limit: super::grid_judge::QuotientLimit::NONE,
            arithmetic: Arithmetic::default(),
            trigger: super::reuse::NO_NODE,
            #[cfg(all(feature = "std", not(target_os = "none")))]
            group: None,
        }
    }

    /// A tessellator that reads this one's frame (its mesh, hidden and culled triangles,
    /// view and figures) from a copy of its bits in `bits`, for another thread to walk or
    /// write out (see `parallel_write`: a tessellator is not `Sync`, for its cache of viewed
    /// corners). `None` where the frame has vertices below the bake, which it does not copy,
    /// or `bits` is too short.
    #[cfg(all(feature = "std", not(target_os = "none")))]
    pub(super) fn reading_copy<'b>(&self, bits: &'b mut [u32]) -> Option<Tessellator<'t, 'b>> {
        let n = self.tree.bit_words();
        if self.pool.used > 0 || bits.len() < n || self.bits.len() < n {
            return None;
        }
        bits[..n].copy_from_slice(&self.bits[..n]);
        let mut copy = Tessellator::bare(self.tree, bits, &mut [], Pool::new(&mut []), self.sphere);
        copy.vertices = self.vertices;
        copy.view = self.view;
        copy.stats = self.stats;
        copy.grid_view = self.grid_view;
        copy.grid_judge = self.grid_judge;
        copy.arithmetic = self.arithmetic;
        #[cfg(feature = "embedded-graphics")]
        {
            copy.model_box = self.model_box;
        }
        Some(copy)
    }

    /// This tessellator, keeping each frame's judgements in `judgements` (at least
    /// [`Hierarchy::judgement_slots`], emptied here) with certificates of how far the camera
    /// may move before they can change, so that a camera step judges again only the
    /// triangles whose certificates ran out (see `reuse` and `deviation/certificate.rs`).
    /// With the hierarchy's links ([`Hierarchy::with_links`]), a frame within the bake is
    /// then a step from the one before ([`FrameStats::stepped`]): the last mesh changed only
    /// where a judgement made again flipped, with no search from the roots (see `step`). A
    /// camera jump (past the longest certificate) asks for no certificates and costs a cold
    /// frame; the frame after it writes them, and the frames after that step. With `std`,
    /// `update_parallel` makes a step's judgements again on a host's threads.
    /// Every frame is still the view's unique mesh, the same a tessellator without them
    /// finds; only [`FrameStats::judged`], [`FrameStats::kept`],
    /// [`FrameStats::worst_bound`] and [`FrameStats::stepped`] tell them apart.
    ///
    /// ```
    /// # use spline_tess::tessellator::{Hierarchy, Judgement, Tessellator, TessellatorStorage};
    /// # fn run(tree: Hierarchy<'_>, views: &[spline_tess::View]) {
    /// let mut storage = TessellatorStorage::<1024, 64, 0>::new();
    /// let mut judgements = vec![Judgement::NONE; tree.judgement_slots()];
    /// let mut tessellator = Tessellator::new(tree, &mut storage)
    ///     .and_then(|t| t.with_reuse(&mut judgements))
    ///     .expect("storage sized for the hierarchy");
    /// for view in views {
    ///     let stats = tessellator.update(view).expect("a valid tolerance");
    ///     println!("{} judged, {} kept", stats.judged, stats.kept);
    /// }
    /// # }
    /// ```
    #[cfg(feature = "reuse")]
    pub fn with_reuse(mut self, judgements: &'s mut [Judgement]) -> Result<Self, TessellatorError> {
        let needed = self.tree.judgement_slots();
        if judgements.len() < needed {
            return Err(TessellatorError::JudgementsTooShort { needed });
        }
        self.reuse = crate::bound::BoundingSphere::of_points(self.tree.model.points())
            .map(|sphere| Reuse::new(judgements, sphere));
        Ok(self)
    }

    /// This tessellator, computing triangles' bounds from their kept vectors in `arithmetic`
    /// (see [`Arithmetic`]) instead of the target's default: a host takes
    /// [`Arithmetic::Integer`] to find the frames a part without an FPU finds.
    ///
    /// ```
    /// # use spline_tess::tessellator::{Hierarchy, Tessellator, TessellatorStorage};
    /// # use spline_tess::Arithmetic;
    /// # fn run(tree: Hierarchy<'_>) {
    /// let mut storage = TessellatorStorage::<1024, 64, 0>::new();
    /// let tessellator = Tessellator::new(tree, &mut storage)
    ///     .expect("storage sized for the hierarchy")
    ///     .with_arithmetic(Arithmetic::Integer);
    /// # }
    /// ```
    pub fn with_arithmetic(mut self, arithmetic: Arithmetic) -> Self {
        self.arithmetic = arithmetic;
        self
    }

    /// The model's box, kept from [`new`](Self::new).
    #[cfg(feature = "embedded-graphics")]
    pub(crate) fn model_box(&self) -> Option<crate::bound::Aabb> {
        self.model_box
    }

    /// The last frame's figures.
    pub fn stats(&self) -> FrameStats {
        self.stats
    }

    /// The hierarchy.
    pub fn tree(&self) -> Hierarchy<'t> {
        self.tree
    }

    /// The hierarchy it tessellates, borrowed (a renderer keeps it for a frame: a copy of the
    /// bytes' layout would take a firmware's stack).
    #[cfg(feature = "embedded-graphics")]
    pub(crate) fn hierarchy(&self) -> &Hierarchy<'t> {
        &self.tree
    }

    pub(super) fn layout(&self) -> Layout {
        self.layout
    }

    /// The nodes' bits: set where the frame's mesh halves a node.
    pub(super) fn halved(&self) -> &[u32] {
        &self.bits[self.layout().halved..self.layout().judged]
    }

    /// The vertex `h` is halved at in the current mesh, if it is.
    #[cfg_attr(not(target_os = "none"), inline)]
    pub(super) fn split_vertex(&self, h: &Pending) -> Option<u32> {
        let baked = self.tree.is_baked(h);
        if baked && !bit(self.halved(), h.node) {
            // (Most triangles a frame asks about: a bit, and nothing decoded.)
            return None;
        }
        match self.tree.baked_halving(h) {
            Some((_, v)) => Some(v),
            // Below the bake: in the pool, if anything is (most frames make nothing there).
            _ if self.pool.used == 0 || !cfg!(feature = "refine") => None,
            // A triangle that cannot be halved never was: its hypotenuse's midpoint, rounded
            // to the grid, may be another vertex of the pool (found by the bisect fuzz
            // target: a walk took such triangles as halved, and below them every triangle
            // again, down to its depth limit, 2^30 triangles).
            _ if !h.tri.can_split(self.tree.cells(h.tri.patch)) => None,
            _ => {
                let at = key(&self.tree, h.tri.patch, h.tri.midpoint());
                let base = self.tree.vertex_count() as u32;
                self.pool.find(at).map(|slot| base + slot as u32)
            }
        }
    }

    pub(super) fn is_split(&self, h: &Pending) -> bool {
        self.split_vertex(h).is_some()
    }

    /// Whether leaf `h` is left out as hidden: a triangle of the bake by its bit, one below it
    /// by [`judge::hidden_below_the_bake`](super::judge::hidden_below_the_bake), with `bounds`
    /// holding the last patch's bounds it needed (walks go patch by patch).
    #[cfg_attr(not(target_os = "none"), inline)]
    pub(super) fn is_hidden(&self, h: &Pending, bounds: &mut Option<(u32, PatchBounds)>) -> bool {
        if self.is_culled(h.tri.patch) {
            return true;
        }
        if h.node != RUN_TIME {
            return bit(&self.bits[self.layout().hidden..], h.node);
        }
        if !cfg!(feature = "refine") {
            return false; // (never reached: such a build makes no triangle below the bake)
        }
        let Some(View::Screen { camera, .. }) = &self.view else {
            return false;
        };
        let patch = match *bounds {
            Some((p, b)) if p == h.tri.patch => b,
            _ => {
                let Some(b) = self.tree.patch_of(h.tri.patch).map(|p| PatchBounds::of(&p)) else {
                    return false;
                };
                *bounds = Some((h.tri.patch, b));
                b
            }
        };
        super::judge::hidden_below_the_bake(self, camera, h, &patch)
    }

    /// Whether `h`, a triangle of the bake, was judged this frame.
    pub(super) fn is_judged(&self, h: &Pending) -> bool {
        h.node != RUN_TIME && bit(&self.bits[self.layout().judged..], h.node)
    }

    /// The pool's entry of vertex `v`, or `Err` with its number in the bake.
    fn below_the_bake(&self, v: u32) -> Result<Option<&PoolSlot>, usize> {
        match (v as usize).checked_sub(self.tree.vertex_count()) {
            None => Err(v as usize),
            Some(slot) => Ok(self.pool.entries.get(slot)),
        }
    }

    /// Vertex `v`, whose point `p` gives, in `camera`'s view coordinates
    /// (`camera.to_view(p())`): kept for the bake's vertices in a small cache where there is
    /// one ([`VIEWED`]), emptied by each frame (`camera` is the frame's). (With
    /// `Arithmetic::Integer` over bytes, [`fixed_on_grid`](Self::fixed_on_grid).)
    pub(super) fn viewed(&self, v: u32, p: impl FnOnce() -> Vec3, camera: &Camera) -> Vec3 {
        self.viewed
            .get(v, self.tree.vertex_count(), || camera.to_view(p()))
    }

    /// Vertex `v` of the bake in the frame's fixed point (`grid`'s, see `grid_view`), kept in
    /// the cache of [`viewed`](Self::viewed); `None` for a vertex not on the grid (below the
    /// bake). Its point is read from the bytes only where the cache misses. (A frame has a
    /// `grid` only over bytes, where every vertex of the bake has its point.)
    pub(super) fn fixed_on_grid(
        &self,
        v: u32,
        grid: &super::grid_view::GridView,
    ) -> Option<[i32; 3]> {
        let vertices = self.tree.vertex_count();
        ((v as usize) < vertices).then(|| {
            self.viewed.get_fixed(v, vertices, || {
                grid.fixed(self.tree.grid_point(v as usize).unwrap_or_default())
            })
        })
    }

    /// The frame's move of the bake's points in integers, if it makes one (see `grid_view`).
    pub(super) fn grid_view(&self) -> Option<&super::grid_view::GridView> {
        self.grid_view.as_ref()
    }

    /// The frame's constants for a first look at triangles in integers, if it takes one
    /// (see `grid_judge`).
    pub(super) fn grid_judge(&self) -> Option<&super::grid_judge::GridJudge> {
        // (Never on a bare-metal part with an FPU, which leaves the look's code out.)
        Some(&self.grid_judge).filter(|g| crate::math::INTEGER_FORMS && g.is_on())
    }

    /// The point of vertex `v`: the bake's, or one below it.
    pub(super) fn position(&self, v: u32) -> [f32; 3] {
        match self.below_the_bake(v) {
            Err(baked) => self.tree.position(baked).unwrap_or_default(),
            Ok(e) => e.map_or([0.0; 3], |e| e.vertex.position),
        }
    }

    /// The unit normal of vertex `v`: the bake's, or one below it.
    pub(super) fn normal(&self, v: u32) -> [f32; 3] {
        match self.below_the_bake(v) {
            Err(baked) => self.tree.normal(baked).unwrap_or_default(),
            Ok(e) => e.map_or([0.0; 3], |e| e.vertex.normal),
        }
    }

    /// The vertices written out at the corners of leaf `h`: their own, or where a corner lies
    /// on a side collapsed to a pole, the pole's corner vertex.
    #[cfg_attr(not(target_os = "none"), inline)]
    fn written_corners(&self, h: &Pending) -> [u32; 3] {
        let poles = self.tree.poles(h.tri.patch);
        if poles == 0 {
            return h.corners;
        }
        let mut out = h.corners;
        for (o, g) in out.iter_mut().zip(h.tri.corners) {
            for side in Side::ALL {
                if poles & (1 << side.index()) != 0 && on_side(side, g) {
                    *o = self.tree.pole(h.tri.patch, side).unwrap_or(*o);
                    break;
                }
            }
        }
        out
    }

    /// The vertices written out for leaf `h`, or `None` where two are one: a triangle with two
    /// corners on a side collapsed to a pole is a segment, which its neighbours' sides
    /// already draw. They come counter-clockwise seen from outside: in the order of `h`'s
    /// corners, or in the order [`oriented`](Self::oriented) gives for a flipped patch.
    pub(super) fn written(&self, h: &Pending) -> Option<[u32; 3]> {
        let [a, b, c] = self.oriented(h, self.written_corners(h));
        (a != b && b != c && c != a).then_some([a, b, c])
    }

    /// Whether leaf `h` is written out (what [`written`](Self::written) tells, without the
    /// order of its corners: a frame's count asks it of every leaf).
    pub(super) fn is_written(&self, h: &Pending) -> bool {
        let [a, b, c] = self.written_corners(h);
        a != b && b != c && c != a
    }

    /// `corners` of leaf `h` (its vertices, or anything per corner) in the order it is
    /// written: as they are (counter-clockwise in `(u, v)`), or with the last two swapped in
    /// a patch the bake flipped (see `bake`'s orientation rule).
    pub(super) fn oriented<T: Copy>(&self, h: &Pending, corners: [T; 3]) -> [T; 3] {
        let [a, b, c] = corners;
        match self.tree.flip(h.tri.patch) {
            true => [a, c, b],
            false => [a, b, c],
        }
    }

    /// Queues `h`, or notes that a walk must find it.
    /// A triangle below the bake that finds the stack full is judged at once instead (it has
    /// no bit a walk could find it by), up to [`INLINE_DEPTH`] deep; past that it is dropped
    /// and the frame's figures are recounted (see [`update`](Self::update)).
    #[cfg_attr(not(target_os = "none"), inline(always))]
    pub(super) fn push(&mut self, h: Pending) {
        self.push_slot(StackSlot::of(&h));
    }

    /// [`push`](Self::push) of the triangle `slot` holds.
    #[cfg_attr(not(target_os = "none"), inline(always))]
    fn push_slot(&mut self, slot: StackSlot) {
        match self.stack.get_mut(self.len) {
            Some(s) => {
                *s = slot;
                self.len += 1;
                self.stats.stack_peak = self.stats.stack_peak.max(self.len);
            }
            None => self.push_over(slot.get()),
        }
    }

    /// [`push`](Self::push) of `h` to a full stack.
    #[inline(never)]
    fn push_over(&mut self, h: Pending) {
        if h.node == RUN_TIME && self.inline < INLINE_DEPTH {
            if let Some(view) = self.view {
                self.inline += 1;
                self.process(&view, view.tolerance(), h);
                self.inline -= 1;
            }
        } else {
            self.full = true;
            self.dropped_patches |= 1 << (h.tri.patch % 32);
            self.dropped_below |= h.node == RUN_TIME;
        }
    }

    /// Finds the mesh of `view`: the coarsest conforming mesh of the hierarchy's triangles
    /// whose bounds are within the tolerance (see the [module docs](super)); a tolerance that
    /// is not a positive finite number is refused.
    ///
    /// The mesh depends on the view alone, so a view equal to the last one (the same camera
    /// and tolerance, bit for bit) keeps the mesh it has, and costs nothing: a firmware that
    /// redraws an unmoved view with another style need not track that itself. Any other view
    /// is searched from the patches' roots.
    pub fn update(&mut self, view: &View) -> Result<FrameStats, UpdateError> {
        if self.is_last_view(view)? {
            return Ok(self.stats);
        }
        if self.step(view) {
            return Ok(self.stats);
        }
        Ok(self.select(view))
    }

    /// Whether `view` is the last frame's, bit for bit (its mesh is kept); refused where its
    /// tolerance is not a positive finite number.
    pub(super) fn is_last_view(&self, view: &View) -> Result<bool, UpdateError> {
        let t = view.tolerance();
        if !(t > 0.0 && t.is_finite()) {
            return Err(UpdateError::BadTolerance);
        }
        Ok(self.view.is_some_and(|last| same_view(&last, view)))
    }

    /// [`update`](Self::update) with a valid tolerance.
    pub(super) fn select(&mut self, view: &View) -> FrameStats {
        self.begin(view);
        let (tree, tolerance) = (self.tree, view.tolerance());
        let part = self.part();
        for p in 0..tree.patch_count() as u32 {
            if !patch_in_part(part, p) {
                continue;
            }
            for k in 0..tree.root_count(p) {
                if root_in_part(part, (p, k as u32)) {
                    let root = tree.root(p, k);
                    self.list(root.node);
                    self.push(root);
                    self.drain(view, tolerance);
                }
            }
        }
        let stats = self.finish(view);
        self.mark_steady();
        stats
    }

    /// Empties the frame's bits, pool and figures for `view`, and culls its patches.
    pub(super) fn begin(&mut self, view: &View) {
        let words = self.tree.bit_words();
        // (Parts of a frame on one thread share their bits: each sets its own nodes'.)
        if self.part().is_none() {
            self.bits[..words].fill(0);
        }
        self.pool.clear();
        self.stats = FrameStats::default();
        self.vertices = None;
        let whole = self.part().is_none();
        if let Some(reuse) = self.reuse.as_mut().filter(|_| cfg!(feature = "reuse")) {
            reuse.advance(self.view.as_ref(), view);
            if whole {
                reuse.steady = false;
                reuse.unlist_all();
            }
        }
        self.view = Some(*view);
        self.viewed.clear();
        self.grid_view = match (self.arithmetic, view) {
            (Arithmetic::Integer, View::Screen { camera, .. }) if crate::math::INTEGER_FORMS => {
                self.tree
                    .grid()
                    .and_then(|grid| super::grid_view::GridView::new(camera, &grid))
            }
            _ => None,
        };
        self.grid_judge = match (&self.grid_view, view) {
            (Some(grid), View::Screen { camera, .. }) => {
                super::grid_judge::GridJudge::new(camera, view.tolerance(), grid)
            }
            _ => None,
        }
        .unwrap_or(super::grid_judge::GridJudge::OFF);
        (self.full, self.dropped_below, self.recount) = (false, false, false);
        self.dropped_patches = 0;
        // (Empty but after a step that gave up: see `step`.)
        self.len = 0;
        self.cull(view);
    }

    /// Whether some root of patch `p` is this search's (every patch but in a part of a
    /// frame).
    pub(super) fn in_group(&self, p: u32) -> bool {
        patch_in_part(self.part(), p)
    }

    /// Whether triangle `t` is this search's: its root is (every root but in a part of a
    /// frame).
    fn holds(&self, t: &Tri) -> bool {
        let part = self.part();
        part.is_none()
            || root_in_part(
                part,
                (t.patch, t.root_index(self.tree.cells(t.patch)) as u32),
            )
    }

    /// The roots of this search where it is a part of a frame (see `parallel`).
    pub(super) fn part(&self) -> Option<Part> {
        #[cfg(all(feature = "std", not(target_os = "none")))]
        return self.group.as_ref().map(|g| (g.lo, g.hi));
        #[cfg(not(all(feature = "std", not(target_os = "none"))))]
        None
    }

    /// Notes `h`, in a part of a frame: a halved triangle whose triangle across is another
    /// part's, or a leaf the part left unjudged. The whole frame's search takes them up.
    fn leave_to_frame(&mut self, h: &Pending) {
        #[cfg(all(feature = "std", not(target_os = "none")))]
        if let Some(g) = self.group.as_mut() {
            g.leave(h);
        }
        let _ = h;
    }

    /// Has [`finish`](Self::finish) walk every patch for leaves not judged yet (as for those
    /// the stack had no room for).
    #[cfg(all(feature = "std", not(target_os = "none")))]
    pub(super) fn walk_for_unjudged(&mut self) {
        self.full = true;
        self.dropped_patches = u32::MAX;
    }

    /// The end of a frame's search: walks for the leaves the stack had no room for, and the
    /// figures (a part of a frame leaves them to the whole frame).
    pub(super) fn finish(&mut self, view: &View) -> FrameStats {
        let (tree, tolerance) = (self.tree, view.tolerance());
        while self.full && self.stats.sweeps < MAX_SWEEPS {
            self.full = false;
            self.stats.sweeps += 1;
            // Leaves below the bake were judged (they are never dropped but past the inline
            // depth): a walk looks for them only then.
            let below = core::mem::take(&mut self.dropped_below);
            // Only the patches of the triangles left out: a leaf is unjudged only there.
            let patches = core::mem::take(&mut self.dropped_patches);
            let part = self.part();
            let wanted =
                |_: &mut (), p: u32| patches & (1 << (p % 32)) != 0 && patch_in_part(part, p);
            let root = |p: u32, k: usize| root_in_part(part, (p, k as u32));
            walk_roots(tree, &mut (), wanted, root, |_, h| {
                let unjudged = if h.node == RUN_TIME {
                    below
                } else {
                    !self.is_judged(h)
                };
                if unjudged && !self.is_split(h) {
                    self.push(*h);
                    self.drain(view, tolerance);
                }
                self.split_vertex(h)
            });
            self.recount |= below;
        }
        if self.part().is_some() {
            #[cfg(all(feature = "std", not(target_os = "none")))]
            if let Some(g) = self.group.as_mut() {
                g.walk |= self.full;
            }
            return self.stats;
        }
        if self.full || self.recount {
            // A walk judged leaves below the bake again (and counted them again where left
            // over), or the search was cut short: one judgement of every leaf gives the
            // frame's true figures.
            self.account(view, tolerance);
        }
        if self.full || self.recount || self.pool.used > 0 {
            // Leaves below the bake have no bit to say they were counted, and a search cut
            // short may have counted some twice: a walk counts.
            self.count();
        }
        // (A split refused for a full pool may have been made later by another way, as the
        // walks' figures tell: then the pool held the frame.)
        self.stats.pool_full &= self.stats.left_over > 0;
        self.stats
    }

    /// Judges every leaf of the current mesh once: the frame's worst bound and its leaves
    /// left over, whatever the search did.
    fn account(&mut self, view: &View, tolerance: f32) {
        let (mut worst, mut over) = (0.0f32, 0);
        walk(self.tree, |h| {
            if let Some(v) = self.split_vertex(h) {
                return Some(v);
            }
            let j = judge(self, view, h, true, Asked::NONE);
            if !j.hidden {
                worst = max(worst, j.bound.value());
                over += usize::from(j.bound.is_over(tolerance));
            }
            None
        });
        self.stats.worst_bound = worst;
        self.stats.left_over = over;
    }

    /// Judges the queued leaves, halving those over `tolerance`.
    pub(super) fn drain(&mut self, view: &View, tolerance: f32) {
        while self.len > 0 {
            self.len -= 1;
            let h = self.stack[self.len].get();
            self.process(view, tolerance, h);
        }
    }

    /// Judges leaf `h` (if it still is one, and not judged yet), halving it if it is over
    /// `tolerance`.
    pub(super) fn process(&mut self, view: &View, tolerance: f32, h: Pending) {
        let layout = self.layout();
        if self.is_split(&h) || self.is_judged(&h) {
            return;
        }
        if h.node != RUN_TIME {
            set(&mut self.bits[layout.judged..], h.node);
        }
        // A triangle that cannot be halved is judged in full: its bound is the frame's when
        // over. (One that can stops once over.)
        let baked = self.tree.baked_first_half(&h).is_some();
        // (A part of a frame leaves a leaf of the bake over the tolerance to the whole
        // frame: it stops judging once over, as for a triangle it can halve.)
        let parted = self.part().is_some();
        let halvable = baked || parted || (cfg!(feature = "refine") && !self.pool.is_full());
        // A judgement kept from a frame before, certified to hold at this one (never for a
        // culled patch: culling comes first, as in `judge`).
        let reuse = self.reuse.as_ref().filter(|_| cfg!(feature = "reuse"));
        let kept = match reuse {
            Some(r) if h.node != RUN_TIME && !self.is_culled(h.tri.patch) => r.kept(h.node),
            _ => None,
        };
        // Over the tolerance: with the bound in full where it was judged so.
        let over_by = match kept {
            Some(over) => {
                self.stats.kept += 1;
                if !over {
                    // (Its bound is within the tolerance; which bound, it does not know.)
                    self.stats.worst_bound = max(self.stats.worst_bound, tolerance);
                    self.count_leaf(&h);
                    return;
                }
                None
            }
            None => {
                self.stats.judged += 1;
                let j = self.judge_and_keep(view, &h, !halvable);
                if j.hidden {
                    if h.node != RUN_TIME {
                        set(&mut self.bits[layout.hidden..], h.node);
                    }
                    self.stats.hidden += 1;
                    return;
                }
                // (One match: a test of whether it is within and then a raise of the worst
                // bound, each matching the bound, took a host's cold frame 1% more.)
                let worst = &mut self.stats.worst_bound;
                let within = match j.bound {
                    Bound::Value(b) if crate::math::at_most(b, tolerance) => {
                        *worst = max(*worst, b);
                        true
                    }
                    Bound::Value(_) => false,
                    Bound::Within(q) => {
                        self.quotient_limit.raise(worst, q);
                        true
                    }
                };
                if within {
                    self.count_leaf(&h);
                    return;
                }
                (!halvable).then_some(j.bound.value())
            }
        };
        if parted && !(baked && self.split(&h, 0)) {
            // Left unjudged, for the whole frame to find (see `parallel`).
            if h.node != RUN_TIME {
                clear(&mut self.bits[layout.judged..], h.node);
            }
            self.leave_to_frame(&h);
            return;
        }
        // (The halvings this makes are `h`'s: see `step`.)
        let before = self.trigger;
        if cfg!(feature = "reuse") {
            self.trigger = h.node;
        }
        let halved = !parted && self.split(&h, 0);
        if cfg!(feature = "reuse") {
            self.trigger = before;
        }
        if !parted && !halved {
            // (Its bound in full, where the judgement stopped once it was over or was kept.)
            let bound = match over_by {
                Some(b) => b,
                None => judge(self, view, &h, true, Asked::NONE).bound.value(),
            };
            self.stats.left_over += 1;
            self.stats.worst_bound = max(self.stats.worst_bound, bound);
            self.count_leaf(&h);
        }
    }

    /// The leaf of the current mesh that holds `t` (its own, or a coarser one).
    pub(super) fn locate(&self, t: &Tri) -> Pending {
        let cells = self.tree.cells(t.patch);
        self.locate_from(self.tree.root(t.patch, t.root_index(cells)), t)
    }

    /// [`locate`](Self::locate) from `h`, a triangle of the mesh's halvings that holds `t`:
    /// the same leaf, as the halvings above `h` lead to it (a triangle once halved stays
    /// halved in a frame).
    pub(super) fn locate_from(&self, mut h: Pending, t: &Tri) -> Pending {
        let cells = self.tree.cells(t.patch);
        let target = t.centroid3();
        while h.tri != *t {
            let Some(v) = self.split_vertex(&h) else {
                break;
            };
            h = self.tree.halves(&h, v)[h.tri.half_toward(target, cells)];
        }
        h
    }

    /// Halves node `node` of the bake, and the nodes above it that are not yet, by their
    /// links, so that its halves are in the mesh (true where they are; nothing to do for
    /// no node, the parent of a root). `depth` bounds the recursion as in
    /// [`split`](Self::split).
    pub(super) fn halve_down_to(&mut self, node: u32, depth: u32) -> bool {
        let Some(l) = self.tree.linked(node) else {
            return true;
        };
        if bit(self.halved(), node) {
            return true;
        }
        depth <= 64 && self.halve_down_to(l.parent, depth + 1) && self.split(&l.place, depth)
    }

    /// Halves `h` and the triangle across its hypotenuse (halving coarser ones first), and
    /// queues the halves; false when it cannot (below the bake: the pool is full, or the grid's
    /// finest step is reached), and then `h` stays whole. `depth` bounds the recursion (a
    /// coarser triangle across is at least one level up, so 64 is never reached by the
    /// 24 levels of a cell).
    pub(super) fn split(&mut self, h: &Pending, depth: u32) -> bool {
        if self.is_split(h) {
            return true;
        }
        if !h.tri.can_split(self.tree.cells(h.tri.patch)) || depth > 64 {
            return false;
        }
        let halving = self.tree.baked_halving(h);
        if halving.is_none() && self.pool.is_full() {
            // No room below the bake: no need to look across.
            self.stats.pool_full |= cfg!(feature = "refine");
            return false;
        }
        let mut across = None;
        // With links, the triangle across is the mate the bake halved with `h`, in the mesh
        // once its parents are halved.
        let mate = halving
            .and_then(|_| self.tree.linked(h.node))
            .and_then(|l| self.tree.linked(l.mate));
        // (Across a part of a frame's border, to another part's root: the whole frame's.)
        let mut leave = false;
        if let Some(m) = mate {
            if !self.holds(&m.place.tri) {
                leave = true;
            } else if !self.halve_down_to(m.parent, depth + 1) {
                return false;
            } else {
                across = Some(m.place);
            }
        } else if let Some(n) = h
            .tri
            .across(|p, s| self.tree.link(p, s), |p| self.tree.cells(p))
        {
            if !self.holds(&n) {
                leave = true;
            } else {
                // (Each leaf found coarser is halved, and the search goes on from it: searching
                // from the root again took `fw_teapot`'s frame 0 update 0.23M instructions more
                // on ARMv6-M, 0.14M on the Cortex-M4F.)
                let mut leaf = self.locate(&n);
                while leaf.tri != n {
                    if !self.split(&leaf, depth + 1) {
                        return false;
                    }
                    leaf = self.locate_from(leaf, &n);
                }
                across = Some(leaf);
            }
        }
        // A triangle across that is halved already is not halved again (its halves were
        // queued then): where parts of a frame were searched apart (see `parallel`), the part
        // across may have halved it while this one left `h` whole; below the bake, a leaf of
        // the bake whose triangle across was halved into the pool may not know it. (Within
        // the bake on one thread a diamond's triangles are halved together: a firmware leaves
        // the test out there.)
        let parts = cfg!(all(feature = "std", not(target_os = "none")));
        if (parts || halving.is_none()) && across.is_some_and(|x| self.is_split(&x)) {
            across = None;
        }
        let v = match halving {
            Some((_, v)) => {
                for x in [across, Some(*h)].into_iter().flatten() {
                    if self.tree.is_baked(&x) {
                        set(self.bits, x.node);
                        self.note_trigger(x.node);
                    }
                }
                v
            }
            // Below the bake (the code is left out of builds without refinement).
            _ if !cfg!(feature = "refine") => return false,
            _ => match self
                .pool
                .make(&self.tree, &h.tri, self.tree.vertex_count() as u32)
            {
                Some(v) => {
                    self.stats.refined += 1;
                    for x in [across, Some(*h)].into_iter().flatten() {
                        if self.tree.is_baked(&x) {
                            set(self.bits, x.node);
                            self.note_trigger(x.node);
                        }
                    }
                    v
                }
                None => {
                    self.stats.pool_full = true;
                    return false;
                }
            },
        };
        if leave {
            self.leave_to_frame(h);
        }
        // Leaves judged and kept whole until now stop being leaves: all but `h` at the top of
        // the recursion, which `process` halves as soon as it judged it.
        if let Some(x) = across {
            self.uncount_leaf(&x);
        }
        if depth > 0 {
            self.uncount_leaf(h);
        }
        // The halves across first, so that `h`'s own are judged first: the search goes down
        // into `h` before it goes across.
        for x in [across, Some(*h)].into_iter().flatten() {
            let [h0, h1] = self.tree.halves(&x, v);
            let (s0, s1) = (StackSlot::of(&h0), StackSlot::of(&h1));
            self.list(h0.node);
            self.list(h1.node);
            self.push_slot(s1);
            self.push_slot(s0);
        }
        true
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::bake::{bake_hierarchy, BakeBuffers, BakeScratch, BakeSettings, Tolerance};
    use crate::tessellator::{HierarchyNode, HierarchyPatch, HierarchyVertex};
    use crate::{BoundaryCurve, EdgeLink, Model, PatchHeader, PatchSet};

    /// The one-patch bump (a bicubic square with its middle raised), baked at `relative` of
    /// its diagonal into buffers of `N` nodes, handed to `f` with its model and its diagonal.
    pub(crate) fn with_bump<const N: usize>(
        relative: f32,
        f: impl FnOnce(&Model<'_>, Hierarchy<'_>, f32),
    ) {
        let mut points = [[0.0f32; 3]; 16];
        for (k, p) in points.iter_mut().enumerate() {
            let (i, j) = (k / 4, k % 4);
            let z = if (1..3).contains(&i) && (1..3).contains(&j) {
                1.0
            } else {
                0.0
            };
            *p = [i as f32, j as f32, z];
        }
        let headers = [PatchHeader {
            degree_u: 3,
            degree_v: 3,
            first_point: 0,
        }];
        let patches = PatchSet::new(&headers, &points, None).unwrap();
        let (mut edges, mut curves) = ([[EdgeLink::Collapsed; 4]], [BoundaryCurve::default(); 4]);
        let model = Model::build(patches, &mut edges, &mut curves).unwrap();
        let mut nodes = [HierarchyNode::default(); N];
        let mut vertices = [HierarchyVertex::default(); N];
        let mut records = [HierarchyPatch::default()];
        let mut scratch = [BakeScratch::default(); N];
        let buffers = BakeBuffers {
            nodes: &mut nodes,
            vertices: &mut vertices,
            patches: &mut records,
            scratch: &mut scratch,
        };
        let settings = BakeSettings {
            tolerance: Tolerance::Relative(relative),
            ..BakeSettings::default()
        };
        let size = bake_hierarchy(&model, &settings, buffers).unwrap();
        let tree = Hierarchy::new(
            patches,
            &nodes[..size.nodes],
            &vertices[..size.vertices],
            &records,
        )
        .unwrap();
        f(&model, tree, model.patches.aabb().unwrap().diagonal());
    }

    /// A view finer than the bake is refined into the pool with the feature `refine`, and
    /// left whole without it (as with a full pool), its bound reported either way.
    #[test]
    fn views_finer_than_the_bake_refine_only_with_the_feature() {
        with_bump::<512>(2e-2, |_, tree, diagonal| {
            let mut storage = TessellatorStorage::<128, 64, 256>::new();
            let mut selection = Tessellator::new(tree, &mut storage).unwrap();
            // A hundredth of the bake's tolerance: far below the bake.
            let tolerance = 1e-2 * Tolerance::Relative(2e-2).in_model_units(diagonal);
            let stats = selection.update(&View::Object { tolerance }).unwrap();
            if cfg!(feature = "refine") {
                assert!(stats.refined > 0);
            } else {
                assert_eq!(stats.refined, 0);
                assert!(stats.left_over > 0);
            }
            assert!((stats.worst_bound > tolerance) == (stats.left_over > 0));
            assert!(stats.worst_bound.is_finite());
        });
    }

    /// The cache of corners gives every vertex the bits it was given, direct-mapped or two
    /// ways, and two ways keeps the last two vertices of a set: a vertex read between two
    /// reads of another in its set is found again without a move.
    #[test]
    fn viewed_corners_keep_the_bits_they_were_given() {
        let moved = |v: u32| [v, v.wrapping_mul(3), !v];
        for two_way in [false, true] {
            let cache = ViewedCorners::new();
            let mut moves = 0;
            let mut rng = crate::test_rng::TestRng::new(0x71e3_0001);
            for k in 0..20_000u32 {
                let v = match k % 3 {
                    0 => rng.next_u32() % 64,
                    _ => rng.next_u32() % 4096,
                };
                let got = cache.get_bits_in(two_way, v, || {
                    moves += 1;
                    moved(v)
                });
                assert_eq!(got, moved(v), "{v}, {two_way}");
            }
            assert!(moves < 20_000, "{moves}");
            if VIEWED >= 2 {
                cache.clear();
                let (a, b) = (5, 5 + VIEWED as u32);
                let mut moves = 0;
                for v in [a, b, a, b, a] {
                    cache.get_bits_in(two_way, v, || {
                        moves += 1;
                        moved(v)
                    });
                }
                assert_eq!(moves, if two_way { 2 } else { 5 }, "{two_way}");
            }
        }
    }
}
