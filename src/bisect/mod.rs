//! Tessellation by bisection: each patch's square is halved at a hypotenuse, and halved again,
//! where a triangle's bound on screen is over the tolerance; a baked hierarchy holds every
//! triangle's bound, so a frame evaluates no surface point and no bound of its own.
//!
//! # The hierarchy
//!
//! Each patch's `(u, v)` square is two right triangles. A triangle is halved from its
//! right-angle corner to its hypotenuse's midpoint, and the halves are right triangles again
//! (longest-edge bisection, the meshes of ROAM and of right-triangulated irregular networks).
//! The triangle across a hypotenuse, in the same patch or in the patch across a shared curve,
//! is halved with it, and a coarser one across is halved first, so the mesh has no
//! T-junction inside a patch and none across a shared curve: both sides of a curve halve it at
//! the same parameters and share one vertex there.
//!
//! A frame's mesh is the coarsest such mesh whose triangles are all within the tolerance: a
//! triangle is halved exactly when its own bound is over, or when a triangle that is halved
//! needs it halved to stay conforming. That mesh is unique (the set of meshes whose triangles
//! are all within the tolerance is closed under intersection), so a frame depends on its view
//! alone, never on the frames before it, and it is found top-down from the squares by
//! [`Selection::update`].
//!
//! # The bake
//!
//! [`bake_bintree`] halves each patch in model space until every triangle is within the bake's
//! tolerance (or at the depth limit), and records for every triangle of that hierarchy a few
//! deviation vectors and a remainder ([`BintreeNode`]): the surface over the triangle lies
//! within the hull of the zero vector and the kept vectors, widened by the remainder, around
//! the flat triangle through its corners' recorded points (the `deviation` module derives the
//! lattice's vectors and remainder; `kept` how a few vectors stand for 28). The run time
//! projects those vectors at the view rays of the flat triangle (the directional bound of
//! `deviation/screen.rs`), so a deviation along the line of sight counts for what it moves on
//! screen, and a triangle off screen for nothing.
//!
//! Where the bake's triangles run out (a view finer than the bake), the run time halves them
//! further into a caller pool of vertices ([`RefinedVertex`]), evaluating the new vertices and
//! bounding the new triangles itself. That takes the crate's default feature `refine`: a build
//! without it (a firmware that keeps its views within the bake, and so holds no surface
//! evaluation in its code) leaves such leaves whole, as a full pool does. Either way a leaf
//! still over the tolerance is reported ([`SelectionStats::left_over`], with the bound it has
//! in [`SelectionStats::worst_bound`]), not hidden.

mod address;
mod bake;
mod bits;
mod budget;
mod count;
mod judge;
mod kept;
mod lattice;
mod output;
mod refine;
mod select;
mod source;
mod tree;

pub use address::SideLink;
pub use bake::{
    bake_bintree, BakeScratch, BintreeBakeError, BintreeBuffers, BintreeSettings, BintreeSize,
};
pub use bits::bit_words_for;
pub use budget::{BintreeFit, BintreeFitError};
pub use kept::KEPT;
pub use refine::RefinedVertex;
pub use select::{Selection, SelectionError, SelectionStats};
pub use source::write_rust_source;
pub use tree::{Bintree, BintreeError, Pending};

/// No vertex: a leaf's [`BintreeNode::vertex`].
pub const NO_VERTEX: u32 = u32::MAX;

/// One triangle of the baked hierarchy.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BintreeNode {
    /// Index of the first of its two halves (the second follows it), or 0 for a leaf of the
    /// bake.
    pub children: u32,
    /// The vertex at its hypotenuse's midpoint, or [`NO_VERTEX`] for a leaf of the bake.
    pub vertex: u32,
    /// Kept deviation vectors, quantised: vector `i` is `scale * vectors[i]` in model units.
    pub vectors: [[i8; 3]; KEPT],
    /// Model units per quantisation step.
    pub scale: f32,
    /// The remainder: the deviation lies in the hull of zero and the kept vectors widened by
    /// this much.
    pub remainder: f32,
}

impl Default for BintreeNode {
    fn default() -> Self {
        BintreeNode {
            children: 0,
            vertex: NO_VERTEX,
            vectors: [[0; 3]; KEPT],
            scale: 0.0,
            remainder: 0.0,
        }
    }
}

/// One vertex of the baked hierarchy: a patch corner or a hypotenuse's midpoint.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BintreeVertex {
    /// Position in model space.
    pub position: [f32; 3],
    /// Unit surface normal.
    pub normal: [f32; 3],
    /// Parameters in `patch` on the grid of `2^15` steps per side.
    pub uv: [u16; 2],
    /// The patch it was evaluated in.
    pub patch: u32,
    /// The vertex written out for it: itself, or for a point of a side collapsed to a pole,
    /// the pole's corner vertex (a triangle with two corners on the pole is a segment, and is
    /// not written).
    pub output: u32,
}

/// One patch of the baked hierarchy: its corners' vertices and what its sides join.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BintreePatch {
    /// Vertices at `(0, 0)`, `(1, 0)`, `(1, 1)`, `(0, 1)`.
    pub corners: [u32; 4],
    /// Per side (`V0, U1, V1, U0`), the other patch's side on the same curve, if shared.
    pub links: [Option<SideLink>; 4],
}
