//! Where triangles go: caller buffers (indexed) or a streaming [`TriangleSink`].

use core::fmt;

/// One output vertex.
///
/// A vertex on a boundary curve is shared by every patch along the curve; it carries the
/// parameters and index of the patch of lower index along the curve, and a vertex at a patch
/// corner (or a pole) those of the first patch that has it at a corner: the same from every
/// triangle that has it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Vertex {
    /// Position in model space.
    pub position: [f32; 3],
    /// Unit surface normal.
    pub normal: [f32; 3],
    /// The patch's own parameters `(u, v)` in `[0, 1]`.
    pub uv: [f32; 2],
    /// Index of the patch the parameters belong to.
    pub patch: u32,
}

/// No corner's key ([`TriangleSink::keyed_triangle`]; a tessellator's keys are vertex
/// numbers, far below it): the empty entry of a key-addressed corner cache.
#[cfg(feature = "embedded-graphics")]
pub(crate) const NO_KEY: u64 = u64::MAX;

/// An index type for triangle buffers: `u16` or `u32`.
pub trait MeshIndex: Copy + fmt::Debug + Default + private::Sealed {
    /// Largest vertex count the type can index.
    const LIMIT: usize;
    /// `i` as an index (`i < LIMIT`).
    fn from_index(i: u32) -> Self;
    /// The index as a `u32`.
    fn to_u32(self) -> u32;
}

impl MeshIndex for u16 {
    const LIMIT: usize = u16::MAX as usize + 1;
    fn from_index(i: u32) -> Self {
        i as u16
    }
    fn to_u32(self) -> u32 {
        self as u32
    }
}

impl MeshIndex for u32 {
    const LIMIT: usize = u32::MAX as usize;
    fn from_index(i: u32) -> Self {
        i
    }
    fn to_u32(self) -> u32 {
        self
    }
}

mod private {
    pub trait Sealed {}
    impl Sealed for u16 {}
    impl Sealed for u32 {}
}

/// Receives a frame's triangles one at a time, with their vertices, so that a consumer (a
/// rasterizer) needs no mesh buffer.
///
/// Triangles are counter-clockwise in the patch's `(u, v)` domain, so with the patch's normal
/// `S_u x S_v` they are counter-clockwise seen from the side the normal points to. A vertex
/// shared by several triangles is passed to each of them with the same bits.
pub trait TriangleSink {
    /// One triangle of patch `patch`.
    fn triangle(&mut self, patch: u32, corners: [&Vertex; 3]);

    /// Whether the sink wants patch `patch`'s triangles: a source may skip a patch (and the
    /// work of evaluating it) when this is false. Sources need not ask; the default wants
    /// every patch.
    fn wants_patch(&self, patch: u32) -> bool {
        let _ = patch;
        true
    }

    /// Whether the sink reads the vertices' parameters ([`Vertex::uv`] and
    /// [`Vertex::patch`]): a source may leave them zero (and spare the work of finding the
    /// patch every triangle gives a shared vertex) when this is false. The default reads them.
    fn wants_parameters(&self) -> bool {
        true
    }

    /// One triangle of patch `patch` whose corners are named by keys, with `corner(i)` giving
    /// corner `i`'s vertex (evaluated when asked).
    ///
    /// As long as the source does not change (for a [`Tessellator`](crate::Tessellator): from
    /// one [`update`](crate::Tessellator::update) to the next, over any number of passes),
    /// corners with equal keys are the same vertex with the same bits, so a sink that does
    /// work per vertex (a renderer projecting corners) can keep that work by key and ask only
    /// for the corners it does not have. Corners with different keys may still be the same
    /// vertex. Sources that know no keys call [`triangle`](Self::triangle) instead.
    ///
    /// The default asks for the three corners and passes them to
    /// [`triangle`](Self::triangle).
    fn keyed_triangle(
        &mut self,
        patch: u32,
        keys: [u64; 3],
        corner: &mut dyn FnMut(usize) -> Vertex,
    ) {
        let _ = keys;
        let [a, b, c] = [0, 1, 2].map(corner);
        self.triangle(patch, [&a, &b, &c]);
    }
}

/// A sink behind a reference is a sink, so that `&mut dyn TriangleSink` can be handed where
/// an `impl TriangleSink` is asked for (one copy of a generic source's code for every sink).
impl<S: TriangleSink + ?Sized> TriangleSink for &mut S {
    fn triangle(&mut self, patch: u32, corners: [&Vertex; 3]) {
        (**self).triangle(patch, corners);
    }

    fn wants_patch(&self, patch: u32) -> bool {
        (**self).wants_patch(patch)
    }

    fn wants_parameters(&self) -> bool {
        (**self).wants_parameters()
    }

    fn keyed_triangle(
        &mut self,
        patch: u32,
        keys: [u64; 3],
        corner: &mut dyn FnMut(usize) -> Vertex,
    ) {
        (**self).keyed_triangle(patch, keys, corner);
    }
}

/// What [`Tessellator::stream_with_info`](crate::Tessellator::stream_with_info) tells about
/// each triangle besides its vertices.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct TriangleInfo {
    /// The patch it belongs to.
    pub patch: u32,
    /// Each corner's parameters `(u, v)` in that patch (a vertex on a shared curve carries its
    /// owner's parameters; these are the triangle's own patch's; at a collapsed edge, the point
    /// of that edge the corner sits at).
    pub uv: [[f32; 2]; 3],
    /// An upper bound of the distance between the patch and the triangle at the same
    /// parameters, in model units (computed, not estimated: see the bound's derivation in
    /// the `deviation` module).
    pub bound: f32,
}

/// Numbers of vertices and triangles of a frame's mesh.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct MeshSize {
    /// Vertices.
    pub vertices: usize,
    /// Triangles.
    pub triangles: usize,
}

/// Why an indexed mesh could not be written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum WriteError {
    /// The buffers are too small for the mesh; they are untouched.
    BuffersTooSmall {
        /// What the mesh needs.
        needed: MeshSize,
    },
    /// The index type cannot address this many vertices (use `u32`); the buffers are
    /// untouched.
    IndexOverflow {
        /// Vertices of the mesh.
        vertices: usize,
    },
    /// The `remap` buffer is shorter than
    /// [`Tessellator::remap_len`](crate::Tessellator::remap_len); the buffers are untouched.
    RemapTooSmall {
        /// Entries needed.
        needed: usize,
    },
}

impl fmt::Display for WriteError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            WriteError::BuffersTooSmall { needed } => write!(
                f,
                "buffers too small: the mesh needs {} vertices and {} triangles",
                needed.vertices, needed.triangles
            ),
            WriteError::IndexOverflow { vertices } => {
                write!(f, "{vertices} vertices do not fit the index type")
            }
            WriteError::RemapTooSmall { needed } => {
                write!(f, "remap too small: {needed} entries needed")
            }
        }
    }
}

impl core::error::Error for WriteError {}
