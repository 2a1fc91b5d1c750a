//! The tessellator: a frame's mesh found in a baked [`Hierarchy`] of halvings, where each
//! patch's cells are halved at a hypotenuse, and halved again, wherever a triangle's bound on
//! screen is over the tolerance. The hierarchy holds every triangle's bound, so a frame within
//! the bake evaluates no surface point and no bound of its own.
//!
//! # The hierarchy
//!
//! Each patch's `(u, v)` square is cut into `2^a x 2^b` cells ([`Cells`], chosen by the bake
//! from the patch's shape, so that a patch stretched in one direction gets triangles as long
//! as they are wide), each cell two right triangles. A triangle is halved from its
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
//! [`Tessellator::update`].
//!
//! # The bake
//!
//! [`bake_hierarchy`](crate::bake::bake_hierarchy) halves each patch in model space until every triangle is within the bake's
//! tolerance (or at the depth limit), and records for every triangle of that hierarchy a few
//! deviation vectors and a remainder ([`HierarchyNode`]): the surface over the triangle lies
//! within the hull of the zero vector and the kept vectors, widened by the remainder, around
//! the flat triangle through its corners' recorded points (the `deviation` module derives the
//! lattice's vectors and remainder; `kept` how a few vectors stand for 28). The run time
//! projects those vectors at the view rays of the flat triangle (the directional bound of
//! `deviation/screen.rs`), so a deviation along the line of sight counts for what it moves on
//! screen, and a triangle off screen for nothing.
//!
//! Where the bake's triangles run out (a view finer than the bake), the run time halves them
//! further into a caller pool of vertices ([`PoolSlot`]), evaluating the new vertices and
//! bounding the new triangles itself. That takes the crate's default feature `refine`: a build
//! without it (a firmware that keeps its views within the bake, and so holds no surface
//! evaluation in its code) leaves such leaves whole, as a full pool does. Either way a leaf
//! still over the tolerance is reported ([`FrameStats::left_over`], with the bound it has
//! in [`FrameStats::worst_bound`], and a full pool in [`FrameStats::pool_full`]), not hidden.
//!
//! # Reuse from frame to frame
//!
//! A view equal to the last keeps its mesh. With room for a judgement per node
//! (`Tessellator::with_reuse`, feature `reuse`), a tessellator keeps each triangle's
//! judgement with a certificate of how far the camera may move before it can change (derived
//! in `deviation/certificate.rs`; `reuse` keeps the odometer that measures the camera's
//! steps): the search takes a kept judgement where it would judge, so a camera step judges
//! again only the triangles whose certificates ran out, and finds the same unique mesh. With
//! the hierarchy's links too, a frame within the bake is a *step* from the one before (see
//! `step`): the last mesh is kept, the judgements that ran out are made again, and the mesh
//! changes only where one of them flipped, with no search from the roots.
//!
//! # Storage
//!
//! A tessellator keeps nothing of its own: bits for its hierarchy, a stack of triangles
//! waiting to be judged and the pool are the caller's, sized at compile time
//! ([`TessellatorStorage`]) or at run time ([`Tessellator::from_slices`]); see `storage`.

pub(crate) mod address;
mod bits;
mod budget;
mod count;
mod cull;
mod directional_look;
pub(crate) mod format;
mod grid_judge;
pub(crate) mod grid_view;
pub(crate) mod hierarchy;
mod judge;
mod links;
mod output;
#[cfg(all(feature = "std", not(target_os = "none")))]
mod parallel;
#[cfg(all(feature = "std", not(target_os = "none")))]
mod parallel_write;
pub(crate) mod quantize;
mod refine;
mod reuse;
mod select;
mod step;
mod storage;

pub use crate::deviation::kept::KEPT;
pub use address::{Cells, SideLink, MAX_CELL_LEVEL};
pub use bits::bit_words_for;
pub use budget::{BudgetError, BudgetFit};
pub use format::{model_fingerprint, FormatError, Part, FORMAT_VERSION, MAGIC};
pub use hierarchy::{Hierarchy, HierarchyError, PatchInfo};
pub use links::{LinkError, NodeLink};
pub use refine::PoolSlot;
pub use reuse::{Judgement, LEVELS as REUSE_LEVELS};
pub use select::{FrameStats, Tessellator, TessellatorError, UpdateError};
pub use storage::{StackSlot, TessellatorStorage};

/// No vertex: a leaf's [`HierarchyNode::vertex`].
pub const NO_VERTEX: u32 = u32::MAX;

/// One triangle of the baked hierarchy.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct HierarchyNode {
    /// Index of the first of its two halves (the second follows it), or 0 for a leaf of the
    /// bake.
    pub children: u32,
    /// The vertex at its hypotenuse's midpoint, or [`NO_VERTEX`] for a leaf of the bake.
    pub vertex: u32,
    /// Kept deviation vectors, quantised: vector `i` is `scale * vectors[i]` in model units
    /// (coordinates in `-31..=31`: the compact bytes keep six bits of each).
    pub vectors: [[i8; 3]; KEPT],
    /// Model units per quantisation step.
    pub scale: f32,
    /// The remainder: the deviation lies in the hull of zero and the kept vectors widened by
    /// this much.
    pub remainder: f32,
}

impl Default for HierarchyNode {
    fn default() -> Self {
        HierarchyNode {
            children: 0,
            vertex: NO_VERTEX,
            vectors: [[0; 3]; KEPT],
            scale: 0.0,
            remainder: 0.0,
        }
    }
}

/// The largest square of a quantised vector the bytes can keep (`3 Q²`, `Q` its largest
/// coordinate).
pub(crate) const LARGEST_SQUARE: usize = 3 * (crate::deviation::kept::Q as usize).pow(2);

/// [`sqrt_above`](crate::math::sqrt_above) of every square of a quantised vector a node of
/// the bytes can keep, evaluated when the crate is built (`f32`'s operations are IEEE's
/// there too: the same bits), on a host: the judgement of a node on screen takes the root of
/// its longest vector's square, two dependent divisions; read from here, a host's cold frame
/// took about 1% less time (`frame_loop`). (A part keeps its flash, and computes them.)
#[cfg(not(target_os = "none"))]
static ROOTS_ABOVE: [f32; LARGEST_SQUARE + 1] = {
    let mut roots = [0.0; LARGEST_SQUARE + 1];
    let mut n = 0;
    while n < roots.len() {
        roots[n] = crate::math::sqrt_above(n as f32);
        n += 1;
    }
    roots
};
#[cfg(target_os = "none")]
static ROOTS_ABOVE: [f32; 0] = [];

/// One vertex of the baked hierarchy: a patch corner or a hypotenuse's midpoint.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct HierarchyVertex {
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

/// One patch of the baked hierarchy: its corners' vertices, its cells and their roots, what its
/// sides join, which side of it is out, and the cone of its outward normals.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct HierarchyPatch {
    /// Vertices at `(0, 0)`, `(1, 0)`, `(1, 1)`, `(0, 1)`.
    pub corners: [u32; 4],
    /// How its square is cut into cells: `2^cells[0]` along `u` by `2^cells[1]` along `v`,
    /// each the two roots of its hierarchy. A patch across a shared curve cuts the curve
    /// into as many cells.
    pub cells: Cells,
    /// The node of its first root: its roots are the `2^(a + b + 1)` nodes from here, cell
    /// `(i, j)`'s two at `2 (i 2^b + j)` and one more (below and above the cell's diagonal
    /// from `(u1, v0)` to `(u0, v1)`). The patches' roots come first, in patch order.
    pub first_root: u32,
    /// With more than one cell, the first of its cell corners' `(2^a + 1)(2^b + 1)` vertices,
    /// corner `(i, j)` at `i (2^b + 1) + j` (those on its corners, or on a curve of a patch
    /// before it, written out as those patches' vertices); unused with one cell.
    pub cell_vertices: u32,
    /// Per side (`V0, U1, V1, U0`), the other patch's side on the same curve, if shared.
    pub links: [Option<SideLink>; 4],
    /// The sides collapsed to a point (a pole), a bit per side (`1 << side.index()`), as the
    /// model's patch has them: a vertex on such a side is written out as the corner vertex
    /// there, and a triangle with two corners on it (a segment) is not written.
    pub poles: u8,
    /// The patch's outside is on the side of `S_v × S_u` (not `S_u × S_v`): its triangles
    /// are written clockwise in `(u, v)` and its vertices' normals are `S_v × S_u` (see the
    /// bake's orientation rule, [`bake_hierarchy`](crate::bake::bake_hierarchy)).
    pub flip: bool,
    /// A cone holding every outward normal of the patch, as its unit axis and the sine of its
    /// half-angle (`[x, y, z, sin]`), where the model is closed and the cone is narrower than
    /// a half-space; a sine of 1 or more where not. A tessellator culls a patch whose cone
    /// faces away from the eye.
    pub cone: [f32; 4],
}

/// [`HierarchyPatch::cone`] of a patch without a cone.
pub const NO_CONE: [f32; 4] = [0.0, 0.0, 0.0, 1.0];

impl Default for HierarchyPatch {
    fn default() -> Self {
        HierarchyPatch {
            corners: [0; 4],
            cells: [0, 0],
            first_root: 0,
            cell_vertices: 0,
            links: [None; 4],
            poles: 0,
            flip: false,
            cone: NO_CONE,
        }
    }
}

impl HierarchyNode {
    /// The bound of the node's deviation in model units: its longest kept vector plus the
    /// remainder.
    pub fn object_bound(&self) -> f32 {
        self.longest() + self.remainder
    }

    /// The longest kept vector's length, rounded up (a bound of the root of the largest
    /// square, the squares' few roundings covered).
    pub(crate) fn longest(&self) -> f32 {
        crate::deviation::kept::longest_of(&self.kept())
    }

    /// An upper bound of the longest kept vector's length from the quantised vectors: the
    /// root of the largest integer square times the scale, rounded up (`q · scale` rounds to
    /// within a relative `ε` of itself, the root and the product add two more roundings,
    /// `4 ε` covers them). A few roundings apart from [`longest`](Self::longest), which the
    /// bake and a view in model units take; the run time's judgements on screen take this one,
    /// which needs no vector in floats.
    pub(crate) fn longest_quantised(&self) -> f32 {
        let square = |q: &[i8; 3]| q.iter().map(|&c| c as i32 * c as i32).sum::<i32>();
        let n = self.vectors.iter().map(square).max().unwrap_or(0);
        let root = match ROOTS_ABOVE.get(n as usize) {
            Some(&root) => root,
            None => crate::math::sqrt_above(n as f32),
        };
        root * self.scale * (1.0 + 4.0 * crate::deviation::EPS)
    }

    /// The kept vectors in model units.
    pub(crate) fn kept(&self) -> [glam::Vec3; KEPT] {
        crate::deviation::kept::dequantize(&self.vectors, self.scale)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The roots evaluated when the crate is built are the bits the judgement would compute,
    /// and a node's longest vector reads them where it can, computing the others.
    #[test]
    fn the_roots_built_in_are_the_computed_ones() {
        for (n, &root) in ROOTS_ABOVE.iter().enumerate() {
            assert_eq!(
                root.to_bits(),
                crate::math::sqrt_above(n as f32).to_bits(),
                "{n}"
            );
        }
        for vector in [[31, 31, 31], [-31, 0, 1], [100, -100, 7], [0, 0, 0]] {
            let node = HierarchyNode {
                vectors: [vector, [1, 2, 3], [0; 3], [-1, 0, 0]],
                scale: 0.25,
                ..HierarchyNode::default()
            };
            let square = vector
                .iter()
                .map(|&c| c as i32 * c as i32)
                .sum::<i32>()
                .max(14);
            let computed =
                crate::math::sqrt_above(square as f32) * 0.25 * (1.0 + 4.0 * crate::deviation::EPS);
            assert_eq!(node.longest_quantised().to_bits(), computed.to_bits());
        }
    }
}
