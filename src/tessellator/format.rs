//! A hierarchy's compact bytes, read in place ([`Hierarchy::from_bytes`]): what a firmware
//! keeps in flash (`include_bytes!`), at any alignment.
//!
//! # Layout (version 4)
//!
//! Every number is little-endian; nothing is aligned. A header of [`HEADER_LEN`] bytes:
//!
//! | at | what |
//! |---|---|
//! | 0 | [`MAGIC`] |
//! | 4 | version (`u16`, [`FORMAT_VERSION`]) |
//! | 6 | flags (`u16`): bit 0, vertex numbers are `u32` (else `u16`) |
//! | 8 | checksum (`u32`): FNV-1a of every byte from 12 on |
//! | 12 | fingerprint of the model's patches (`u32`, FNV-1a of headers, points, weights) |
//! | 16 | patches, nodes, roots, vertices, fixed vertices, owners, cell corners, far partners, leaves apart, partners with their own bound (`u32` each) |
//! | 56 | the leaves' common bound's code (`u8`), then three zero bytes |
//!
//! then these sections, one after the other:
//!
//! 1. **Patches**, [`PATCH_LEN`] bytes each, or [`NARROW_PATCH_LEN`] where every number of
//!    theirs fits a `u16` (*narrow*: at most 65,535 vertices, 8,191 patches, 65,535 roots and
//!    65,535 cell corners): cells (`a | b << 4`), flags (bit 0 flipped, bits 4-7 the poles),
//!    four links (`patch << 3 | side << 1 | flip`, or all ones), four corner vertices, the
//!    first root's node, the first cell corner (`u32` each, `u16` each narrow), the cone
//!    (four `f32`).
//! 2. **Cell corners**: the vertex at each cell corner of the patches with more than one
//!    cell, `(2^a + 1)(2^b + 1)` a patch, corner `(i, j)` at `i (2^b + 1) + j`.
//! 3. **Halvings**: a bit per node, set where the bake halves it, in `u32` words, then per
//!    word the halved nodes before it (`u16` for at most 65,535 nodes, else `u32`). Nodes
//!    are numbered level by level: the patches' roots first, then the halves of each halved
//!    node in the order of the nodes, so the halves of the `s`-th halved node are nodes
//!    `roots + 2 s` and `roots + 2 s + 1`: no node stores where its halves are.
//! 4. **Owners**: a bit per halved node, set where it is the first (in node order) of the
//!    triangles halved at its vertex (a diamond's first), in words and counts as above. The
//!    `o`-th owner's vertex is vertex `fixed + o`, and its diamond's bound the `o`-th: no
//!    owner stores either.
//! 5. **Partners**: for each halved node that is not an owner (a diamond's second, across
//!    its owner's hypotenuse), in order, a byte: how many owners back its owner is (of those
//!    before it, 0 the last), or [`FAR`] where that is 255 or more.
//! 6. **Own bounds**: a bit per partner, set where it keeps a bound of its own (the bake
//!    shares a diamond's bound only where that costs little), in words and counts as above.
//! 7. **Far partners**, [`FAR_LEN`] bytes each, sorted: the partner's rank among the
//!    partners and its owner's vertex (`u32` each). The teapot has 16 of 1,714 partners so.
//! 8. **Bounds of the diamonds**, [`BOUND_LEN`] bytes an owner, in order: the kept vectors'
//!    coordinates (six bits each, `c + 32`, packed from the low bits up), the scale's code and
//!    the remainder's (one byte each, see `quantize`): the bound of both triangles halved at
//!    the owner's vertex, or of the owner alone where its partner has its own.
//! 9. **Partners' own bounds**, [`BOUND_LEN`] bytes each, in order of the partners that have
//!    one.
//! 10. **Leaves apart**, [`LEAF_LEN`] bytes each, sorted: a leaf's rank among the leaves
//!     (`u32`) and its bound's code, for the leaves whose bound is not the common one (the
//!     bake's tolerance: a leaf keeps no vector, and no other bound where it is within the
//!     tolerance; those at the depth limit are apart).
//! 11. **Vertices**, [`VERTEX_LEN`] bytes each: the point on the grid of the model's box
//!     (`u16` each) and the octahedral code of the normal (`i8` each). The fixed vertices
//!     (patch and cell corners) come first, then the owners'.
//!
//! The grids (the box, and the unit of the logarithmic codes) follow from the model, which the
//! fingerprint ties the bytes to.
//!
//! Vertex numbers are `u16` where the hierarchy has at most 65,535 vertices.
//!
//! # Checks
//!
//! [`HierarchyBytes::parse`] checks the length, magic, version and checksum;
//! [`HierarchyBytes::check`] that the bytes belong to the model and that every number in
//! them is in range (the same checks as [`Hierarchy::new`]'s, and the bit counts), so that no
//! later read is out of bounds and no walk loops. Every read still goes through `get`: bad
//! bytes give an error or a wrong mesh, never a panic.

use core::fmt;

use super::address::{root_count, Cells, SideLink, MAX_CELL_LEVEL};
use super::hierarchy::{cone_ok, links_agree, poles_of, PatchInfo, Shape};
use super::quantize::{normal_of, LogGrid, PositionGrid};
use super::{HierarchyNode, KEPT, NO_VERTEX};
use crate::model::PatchSet;
use crate::patch::Side;

#[cfg(doc)]
use super::Hierarchy;

/// The first bytes of a hierarchy's bytes.
pub const MAGIC: [u8; 4] = *b"STHY";

/// The format version this crate reads and writes.
pub const FORMAT_VERSION: u16 = 4;

/// Bytes of the header.
pub const HEADER_LEN: usize = LEAF_CODE_AT + 4;

/// Bytes of a patch record.
pub const PATCH_LEN: usize = 58;

/// Bytes of a narrow patch record (see the [module docs](self)).
pub const NARROW_PATCH_LEN: usize = 38;

/// Bytes of a diamond's bound: six bits a vector coordinate, a byte for the scale and one for
/// the remainder.
pub const BOUND_LEN: usize = VECTOR_BYTES + 2;

/// Bytes of a bound's vectors: `3 KEPT` coordinates of six bits.
pub(crate) const VECTOR_BYTES: usize = (3 * KEPT * 6).div_ceil(8);

/// Coordinate `k` of the six-bit coordinates at `bytes` (each stored as `c + 32`).
fn coordinate(bytes: &[u8], k: usize) -> i8 {
    let (at, shift) = (6 * k / 8, 6 * k % 8);
    let lo = bytes.get(at).copied().unwrap_or(0) as u16;
    let hi = bytes.get(at + 1).copied().unwrap_or(0) as u16;
    ((((hi << 8) | lo) >> shift) & 63) as i8 - 32
}

/// The kept vectors' six-bit coordinates (each stored as `c + 32`, packed from the low bits
/// up) at `bytes`, [`VECTOR_BYTES`] of them (fewer read as zero bytes): four from each three
/// bytes, read as one 24-bit word. (Read one by one, each with its two bytes checked, they
/// took `fw_teapot`'s frame 0 update 0.10M instructions more on ARMv6-M: 1,335 nodes.)
fn vector_coordinates(bytes: &[u8]) -> [[i8; 3]; KEPT] {
    const ZEROS: [u8; VECTOR_BYTES] = [0; VECTOR_BYTES];
    let b: &[u8; VECTOR_BYTES] = bytes
        .get(..VECTOR_BYTES)
        .and_then(|b| b.try_into().ok())
        .unwrap_or(&ZEROS);
    let word = |i: usize| u32::from(b[i]) | u32::from(b[i + 1]) << 8 | u32::from(b[i + 2]) << 16;
    let (w0, w1, w2) = (word(0), word(3), word(6));
    let c = |w: u32, j: u32| ((w >> (6 * j)) & 63) as i8 - 32;
    [
        [c(w0, 0), c(w0, 1), c(w0, 2)],
        [c(w0, 3), c(w1, 0), c(w1, 1)],
        [c(w1, 2), c(w1, 3), c(w2, 0)],
        [c(w2, 1), c(w2, 2), c(w2, 3)],
    ]
}

/// Writes coordinate `k` (in `-32..=31`) into the six-bit coordinates at `bytes`.
pub(crate) fn put_coordinate(bytes: &mut [u8], k: usize, c: i8) {
    let (at, shift) = (6 * k / 8, 6 * k % 8);
    let v = ((c as i16 + 32) as u16 & 63) << shift;
    bytes[at] |= v as u8;
    if let Some(b) = bytes.get_mut(at + 1) {
        *b |= (v >> 8) as u8;
    }
}

/// Bytes of a vertex.
pub const VERTEX_LEN: usize = 8;

/// Flag: vertex numbers are `u32`.
pub(crate) const WIDE: u16 = 1;

/// Where the checksum is; it covers the bytes after it.
pub(crate) const CHECKSUM_AT: usize = 8;

/// A part of a hierarchy's bytes that breaks the format's rules.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Part {
    /// The header's counts.
    Header,
    /// This patch's record.
    Patch(u32),
    /// This node.
    Node(u32),
    /// The halving or owner bits, or their counts.
    Bits,
    /// This partner entry.
    Partner(u32),
}

/// Why bytes are not a hierarchy of a model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum FormatError {
    /// Fewer bytes than the header, or than the header's counts take.
    Truncated {
        /// Bytes needed.
        needed: usize,
        /// Bytes given.
        found: usize,
    },
    /// More bytes than the header's counts take.
    TrailingBytes {
        /// Bytes the hierarchy takes.
        expected: usize,
        /// Bytes given.
        found: usize,
    },
    /// The bytes do not start with [`MAGIC`].
    BadMagic,
    /// A version this crate does not read.
    UnsupportedVersion {
        /// The version in the bytes.
        found: u16,
    },
    /// The checksum does not match: the bytes were changed.
    ChecksumMismatch {
        /// The header's.
        stored: u32,
        /// The bytes'.
        computed: u32,
    },
    /// The bytes were baked from other patches than the model's.
    ModelMismatch {
        /// The header's fingerprint.
        stored: u32,
        /// The model's.
        model: u32,
    },
    /// The checksum matches, but a part breaks the format's rules.
    Malformed(Part),
}

impl fmt::Display for FormatError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FormatError::Truncated { needed, found } => {
                write!(f, "hierarchy truncated: {found} of {needed} bytes")
            }
            FormatError::TrailingBytes { expected, found } => {
                write!(f, "hierarchy has {found} bytes, its header says {expected}")
            }
            FormatError::BadMagic => f.write_str("not a hierarchy (bad magic)"),
            FormatError::UnsupportedVersion { found } => write!(
                f,
                "hierarchy format version {found}, this crate reads {FORMAT_VERSION}"
            ),
            FormatError::ChecksumMismatch { stored, computed } => write!(
                f,
                "hierarchy corrupted: checksum {computed:#010x}, header says {stored:#010x}"
            ),
            FormatError::ModelMismatch { stored, model } => write!(
                f,
                "hierarchy baked from other patches: fingerprint {stored:#010x}, model {model:#010x}"
            ),
            FormatError::Malformed(part) => write!(f, "hierarchy malformed at {part:?}"),
        }
    }
}

impl core::error::Error for FormatError {}

/// FNV-1a of `bytes`, continuing from `hash`.
pub(crate) fn fnv1a(mut hash: u32, bytes: &[u8]) -> u32 {
    for &b in bytes {
        hash ^= b as u32;
        hash = hash.wrapping_mul(0x0100_0193);
    }
    hash
}

/// FNV-1a's starting value.
pub(crate) const FNV_OFFSET: u32 = 0x811c_9dc5;

/// The fingerprint of a model's patches: FNV-1a of their headers, points and weights.
pub fn model_fingerprint(model: &PatchSet<'_>) -> u32 {
    let mut h = FNV_OFFSET;
    for header in model.headers() {
        h = fnv1a(h, &[header.degree_u, header.degree_v]);
        h = fnv1a(h, &header.first_point.to_le_bytes());
    }
    for p in model.points() {
        for c in p {
            h = fnv1a(h, &c.to_bits().to_le_bytes());
        }
    }
    if let Some(w) = model.weights() {
        for x in w {
            h = fnv1a(h, &x.to_bits().to_le_bytes());
        }
    }
    h
}

pub(crate) fn u16_at(b: &[u8], at: usize) -> u16 {
    match b.get(at..at + 2) {
        Some(&[x, y]) => u16::from_le_bytes([x, y]),
        _ => 0,
    }
}

pub(crate) fn u32_at(b: &[u8], at: usize) -> u32 {
    match b.get(at..at + 4) {
        Some(&[x, y, z, w]) => u32::from_le_bytes([x, y, z, w]),
        _ => 0,
    }
}

/// The number of `width` bytes (2 or 4) at `at`.
fn number_at(b: &[u8], at: usize, width: usize) -> u32 {
    match width {
        2 => u16_at(b, at) as u32,
        _ => u32_at(b, at),
    }
}

pub(crate) fn f32_at(b: &[u8], at: usize) -> f32 {
    f32::from_bits(u32_at(b, at))
}

/// A link as the bytes hold it, in a number of `width` bytes (all ones: none).
pub(crate) fn link_code(link: Option<SideLink>, width: usize) -> u32 {
    match link {
        None => none(width),
        Some(l) => (l.patch << 3) | ((l.side.index() as u32) << 1) | u32::from(l.flip),
    }
}

/// The number of `width` bytes with every bit set.
fn none(width: usize) -> u32 {
    if width == 2 {
        u16::MAX as u32
    } else {
        u32::MAX
    }
}

fn link_from(code: u32, width: usize) -> Option<SideLink> {
    (code != none(width)).then(|| SideLink {
        patch: code >> 3,
        side: Side::ALL[((code >> 1) & 3) as usize],
        flip: code & 1 != 0,
    })
}

/// The header's counts, and where each section starts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub(crate) struct Layout {
    pub patches: usize,
    pub nodes: usize,
    pub roots: usize,
    pub vertices: usize,
    pub fixed: usize,
    pub owners: usize,
    pub cell_corners: usize,
    pub far_partners: usize,
    pub leaf_exceptions: usize,
    pub own_bounds: usize,
    /// Bytes of a vertex number.
    pub index: usize,
    /// Bytes of a number in a patch record, and of the record.
    pub number: usize,
    pub patch_len: usize,
    /// Bytes of a count of set bits (`u16` for at most 65,535 nodes, else `u32`).
    pub count: usize,
    pub cell_at: usize,
    pub split_at: usize,
    pub split_count_at: usize,
    pub owner_at: usize,
    pub owner_count_at: usize,
    pub partner_at: usize,
    pub own_at: usize,
    pub own_count_at: usize,
    pub far_at: usize,
    pub bound_at: usize,
    pub own_bound_at: usize,
    pub leaf_at: usize,
    pub vertex_at: usize,
    pub len: usize,
}

/// The header's counts, in their order: patches, nodes, roots, vertices, fixed vertices,
/// owners, cell corners, far partners, leaves apart, partners with a bound of their own.
pub(crate) type Counts = [usize; COUNTS];

/// Counts in the header.
pub(crate) const COUNTS: usize = 10;

/// Where the leaves' common bound's code is.
pub(crate) const LEAF_CODE_AT: usize = 16 + 4 * COUNTS;

/// A partner's entry that says "see the far partners".
pub(crate) const FAR: u8 = u8::MAX;

/// Bytes of a far partner: its rank among the partners, its vertex.
pub const FAR_LEN: usize = 8;

/// Bytes of a leaf apart: its rank among the leaves, its bound's code.
pub const LEAF_LEN: usize = 5;

impl Layout {
    /// Halved nodes.
    pub fn splits(&self) -> usize {
        (self.nodes - self.roots) / 2
    }

    /// The layout of a hierarchy of these counts (`None` where the counts are not those of
    /// one, or its length overflows).
    pub fn of(counts: Counts) -> Option<Layout> {
        let [patches, nodes, roots, vertices, fixed, owners, cell_corners, far_partners, leaf_exceptions, own_bounds] =
            counts;
        let splits = nodes.checked_sub(roots)? / 2;
        if roots + 2 * splits != nodes
            || owners > splits
            || far_partners > splits - owners
            || leaf_exceptions > nodes - splits
            || own_bounds > splits - owners
            || fixed.checked_add(owners)? != vertices
            || vertices > u32::MAX as usize - 1
        {
            return None;
        }
        let index = if vertices > u16::MAX as usize { 4 } else { 2 };
        let count = if nodes > u16::MAX as usize { 4 } else { 2 };
        let narrow = index == 2
            && patches <= 8191
            && roots <= u16::MAX as usize
            && cell_corners <= u16::MAX as usize;
        let (number, patch_len) = if narrow {
            (2, NARROW_PATCH_LEN)
        } else {
            (4, PATCH_LEN)
        };
        let words = |bits: usize| bits.div_ceil(32).checked_mul(4);
        let counts = |bits: usize| bits.div_ceil(32).checked_mul(count);
        let mut at = HEADER_LEN;
        let mut take = |bytes: Option<usize>| -> Option<usize> {
            let start = at;
            at = at.checked_add(bytes?)?;
            Some(start)
        };
        take(patches.checked_mul(patch_len))?;
        let cell_at = take(cell_corners.checked_mul(index))?;
        let split_at = take(words(nodes))?;
        let split_count_at = take(counts(nodes))?;
        let owner_at = take(words(splits))?;
        let owner_count_at = take(counts(splits))?;
        let partner_at = take(Some(splits - owners))?;
        let own_at = take(words(splits - owners))?;
        let own_count_at = take(counts(splits - owners))?;
        let far_at = take(far_partners.checked_mul(FAR_LEN))?;
        let bound_at = take(owners.checked_mul(BOUND_LEN))?;
        let own_bound_at = take(own_bounds.checked_mul(BOUND_LEN))?;
        let leaf_at = take(leaf_exceptions.checked_mul(LEAF_LEN))?;
        let vertex_at = take(vertices.checked_mul(VERTEX_LEN))?;
        Some(Layout {
            patches,
            nodes,
            roots,
            vertices,
            fixed,
            owners,
            cell_corners,
            far_partners,
            leaf_exceptions,
            own_bounds,
            index,
            number,
            patch_len,
            count,
            cell_at,
            split_at,
            split_count_at,
            owner_at,
            owner_count_at,
            partner_at,
            own_at,
            own_count_at,
            far_at,
            bound_at,
            own_bound_at,
            leaf_at,
            vertex_at,
            len: at,
        })
    }
}

/// A hierarchy's bytes, their header read: see the [module docs](self).
#[derive(Clone, Copy, Debug)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub(crate) struct HierarchyBytes<'a> {
    bytes: &'a [u8],
    layout: Layout,
    grid: PositionGrid,
    scales: LogGrid,
    bounds: LogGrid,
}

impl<'a> HierarchyBytes<'a> {
    /// Reads the header (the length, magic, version and checksum) of bytes baked from
    /// `model`, whose box and diagonal give the grids.
    pub(crate) fn parse(bytes: &'a [u8], model: &PatchSet<'_>) -> Result<Self, FormatError> {
        if bytes.len() >= 4 && bytes[..4] != MAGIC {
            return Err(FormatError::BadMagic);
        }
        if bytes.len() < HEADER_LEN {
            return Err(FormatError::Truncated {
                needed: HEADER_LEN,
                found: bytes.len(),
            });
        }
        let version = u16_at(bytes, 4);
        if version != FORMAT_VERSION {
            return Err(FormatError::UnsupportedVersion { found: version });
        }
        let counts = core::array::from_fn(|k| u32_at(bytes, 16 + 4 * k) as usize);
        let layout = Layout::of(counts).ok_or(FormatError::Malformed(Part::Header))?;
        if u32_at(bytes, LEAF_CODE_AT) >> 8 != 0 {
            return Err(FormatError::Malformed(Part::Header));
        }
        let wide = u16_at(bytes, 6) & WIDE != 0;
        if wide != (layout.index == 4) || u16_at(bytes, 6) & !WIDE != 0 {
            return Err(FormatError::Malformed(Part::Header));
        }
        if bytes.len() < layout.len {
            return Err(FormatError::Truncated {
                needed: layout.len,
                found: bytes.len(),
            });
        }
        if bytes.len() > layout.len {
            return Err(FormatError::TrailingBytes {
                expected: layout.len,
                found: bytes.len(),
            });
        }
        let stored = u32_at(bytes, CHECKSUM_AT);
        let computed = fnv1a(FNV_OFFSET, &bytes[CHECKSUM_AT + 4..]);
        if stored != computed {
            return Err(FormatError::ChecksumMismatch { stored, computed });
        }
        Ok(HierarchyBytes {
            bytes,
            layout,
            grid: PositionGrid::of(model),
            scales: LogGrid::scales(model),
            bounds: LogGrid::bounds(model),
        })
    }

    /// Checks that the bytes are a hierarchy of `model` whose every number is in range.
    pub(crate) fn check(&self, model: &PatchSet<'_>) -> Result<(), FormatError> {
        let l = &self.layout;
        let (stored, fingerprint) = (u32_at(self.bytes, 12), model_fingerprint(model));
        if stored != fingerprint {
            return Err(FormatError::ModelMismatch {
                stored,
                model: fingerprint,
            });
        }
        if l.patches != model.len() || l.patches == 0 {
            return Err(FormatError::Malformed(Part::Header));
        }
        let (mut roots, mut cell_corners) = (0usize, 0usize);
        for p in 0..l.patches {
            let at = self.patch_at(p);
            let cells = self.cells(p);
            let bad_cells = cells.iter().any(|&c| c > MAX_CELL_LEVEL) || self.byte(at) & 0x88 != 0;
            let bad = bad_cells
                || self.first_root(p) as usize != roots
                || self.first_cell_corner(p) as usize != cell_corners
                || self.byte(at + 1) & 0x0e != 0
                || (0..4).any(|k| self.corner(p, k) as usize >= l.vertices)
                || !links_agree(l.patches, p, |q| {
                    (q < l.patches).then(|| (self.cells(q), self.links(q)))
                })
                || self.poles(p) != poles_of(model, p)
                || !cone_ok(self.cone(p));
            if bad {
                return Err(FormatError::Malformed(Part::Patch(p as u32)));
            }
            roots += root_count(cells);
            if cells != [0, 0] {
                cell_corners += ((1 << cells[0]) + 1) * ((1 << cells[1]) + 1);
            }
        }
        if roots != l.roots || cell_corners != l.cell_corners {
            return Err(FormatError::Malformed(Part::Header));
        }
        for k in 0..l.cell_corners {
            if self.index(l.cell_at + k * l.index) as usize >= l.vertices {
                return Err(FormatError::Malformed(Part::Patch(l.patches as u32)));
            }
        }
        // The bits: counts that add up, nothing past the last, as many halved nodes as the
        // header's counts say, owners too, and every halving after its node.
        let splits = l.splits();
        let counted = |bits_at: usize, counts_at: usize, len: usize| {
            let mut total = 0u32;
            for w in 0..len.div_ceil(32) {
                let word = u32_at(self.bytes, bits_at + 4 * w);
                let used = len - 32 * w;
                if used < 32 && word >> used != 0 {
                    return None;
                }
                if self.count_of(counts_at, w) != total as usize {
                    return None;
                }
                total += word.count_ones();
            }
            Some(total as usize)
        };
        if counted(l.split_at, l.split_count_at, l.nodes) != Some(splits)
            || counted(l.owner_at, l.owner_count_at, splits) != Some(l.owners)
            || counted(l.own_at, l.own_count_at, splits - l.owners) != Some(l.own_bounds)
        {
            return Err(FormatError::Malformed(Part::Bits));
        }
        for i in 0..l.nodes {
            if let Some(s) = self.split_rank(i) {
                if l.roots + 2 * s <= i {
                    return Err(FormatError::Malformed(Part::Node(i as u32)));
                }
            }
        }
        // Partners: each near one names an owner before it, each far one is in the sorted
        // list of far partners with a vertex of an owner, and no other is.
        let (mut owners, mut far) = (0usize, 0usize);
        for k in 0..splits {
            if self.rank(l.owner_at, l.owner_count_at, k).is_some() {
                owners += 1;
                continue;
            }
            let partner = k - owners;
            let bad = match self.byte(l.partner_at + partner) {
                FAR => {
                    let at = l.far_at + far * FAR_LEN;
                    let v = u32_at(self.bytes, at + 4) as usize;
                    far += 1;
                    far > l.far_partners
                        || u32_at(self.bytes, at) as usize != partner
                        || v < l.fixed
                        || v >= l.fixed + owners
                }
                d => d as usize >= owners,
            };
            if bad {
                return Err(FormatError::Malformed(Part::Partner(partner as u32)));
            }
        }
        if far != l.far_partners {
            return Err(FormatError::Malformed(Part::Bits));
        }
        // Leaves apart: sorted, each a leaf.
        let leaves = l.nodes - splits;
        for k in 0..l.leaf_exceptions {
            let at = l.leaf_at + k * LEAF_LEN;
            let rank = u32_at(self.bytes, at) as usize;
            let sorted = k == 0 || u32_at(self.bytes, at - LEAF_LEN) < rank as u32;
            if rank >= leaves || !sorted {
                return Err(FormatError::Malformed(Part::Node(rank as u32)));
            }
        }
        Ok(())
    }

    /// The bytes.
    pub(crate) fn as_bytes(&self) -> &'a [u8] {
        self.bytes
    }

    pub(crate) fn node_count(&self) -> usize {
        self.layout.nodes
    }

    pub(crate) fn vertex_count(&self) -> usize {
        self.layout.vertices
    }

    /// The count of set bits before word `w` of the words whose counts are at `counts_at`.
    fn count_of(&self, counts_at: usize, w: usize) -> usize {
        match self.layout.count {
            2 => u16_at(self.bytes, counts_at + 2 * w) as usize,
            _ => u32_at(self.bytes, counts_at + 4 * w) as usize,
        }
    }

    fn index(&self, at: usize) -> u32 {
        number_at(self.bytes, at, self.layout.index)
    }

    fn patch_at(&self, p: usize) -> usize {
        HEADER_LEN + p * self.layout.patch_len
    }

    /// Number `k` of patch `p`'s record (its links, then its corners, first root and first
    /// cell corner), of the layout's width.
    fn patch_number(&self, p: usize, k: usize) -> u32 {
        let width = self.layout.number;
        number_at(self.bytes, self.patch_at(p) + 2 + width * k, width)
    }

    fn byte(&self, at: usize) -> u8 {
        self.bytes.get(at).copied().unwrap_or(0)
    }

    pub(crate) fn cells(&self, p: usize) -> Cells {
        let c = self.byte(self.patch_at(p));
        [c & 0x0f, c >> 4]
    }

    pub(crate) fn flip(&self, p: usize) -> bool {
        self.byte(self.patch_at(p) + 1) & 1 != 0
    }

    pub(crate) fn poles(&self, p: usize) -> u8 {
        self.byte(self.patch_at(p) + 1) >> 4
    }

    pub(crate) fn link(&self, p: usize, side: Side) -> Option<SideLink> {
        link_from(self.patch_number(p, side.index()), self.layout.number)
    }

    fn links(&self, p: usize) -> [Option<SideLink>; 4] {
        Side::ALL.map(|s| self.link(p, s))
    }

    pub(crate) fn corner(&self, p: usize, k: usize) -> u32 {
        self.patch_number(p, 4 + k)
    }

    pub(crate) fn first_root(&self, p: usize) -> u32 {
        self.patch_number(p, 8)
    }

    fn first_cell_corner(&self, p: usize) -> u32 {
        self.patch_number(p, 9)
    }

    fn cone(&self, p: usize) -> [f32; 4] {
        let at = self.patch_at(p) + 2 + 10 * self.layout.number;
        [0, 1, 2, 3].map(|k| f32_at(self.bytes, at + 4 * k))
    }

    pub(crate) fn patch(&self, p: usize) -> Option<PatchInfo> {
        (p < self.layout.patches).then(|| PatchInfo {
            cells: self.cells(p),
            links: self.links(p),
            flip: self.flip(p),
            poles: self.poles(p),
            cone: self.cone(p),
        })
    }

    /// The vertex at cell corner `(i, j)` of patch `p`.
    pub(crate) fn cell_vertex(&self, p: usize, i: u32, j: u32) -> u32 {
        let first = self.first_cell_corner(p) as usize;
        let rows = (1usize << self.cells(p)[1].min(MAX_CELL_LEVEL)) + 1;
        let k = first + i as usize * rows + j as usize;
        self.index(self.layout.cell_at + k * self.layout.index)
    }

    /// The rank of bit `i` among the set bits of the words at `bits_at` (with their counts
    /// at `counts_at`), if it is set.
    fn rank(&self, bits_at: usize, counts_at: usize, i: usize) -> Option<usize> {
        let w = i / 32;
        let word = u32_at(self.bytes, bits_at + 4 * w);
        let bit = 1u32 << (i % 32);
        (word & bit != 0)
            .then(|| self.count_of(counts_at, w) + (word & (bit - 1)).count_ones() as usize)
    }

    /// The rank of node `i` among the halved nodes, if it is halved.
    fn split_rank(&self, i: usize) -> Option<usize> {
        if i >= self.layout.nodes {
            return None;
        }
        self.rank(self.layout.split_at, self.layout.split_count_at, i)
    }

    /// Where the record keyed `key` is among the `count` records of `len` bytes at `at`, each
    /// starting with its key (`u32`), sorted (a binary search).
    fn sorted_record(&self, at: usize, count: usize, len: usize, key: usize) -> Option<usize> {
        let (mut lo, mut hi) = (0, count);
        while lo < hi {
            let mid = (lo + hi) / 2;
            let record = at + mid * len;
            match (u32_at(self.bytes, record) as usize).cmp(&key) {
                core::cmp::Ordering::Less => lo = mid + 1,
                core::cmp::Ordering::Greater => hi = mid,
                core::cmp::Ordering::Equal => return Some(record),
            }
        }
        None
    }

    /// The vertex of the `partner`-th partner, from the far partners (0 where it is not there).
    fn far(&self, partner: usize) -> usize {
        let l = &self.layout;
        self.sorted_record(l.far_at, l.far_partners, FAR_LEN, partner)
            .map_or(0, |at| u32_at(self.bytes, at + 4) as usize)
    }

    /// The code of the bound of the `leaf`-th leaf: the leaves' common one, or its own where
    /// it is apart.
    fn leaf_code(&self, leaf: usize) -> u8 {
        let l = &self.layout;
        match self.sorted_record(l.leaf_at, l.leaf_exceptions, LEAF_LEN, leaf) {
            Some(at) => self.byte(at + 4),
            None => self.byte(LEAF_CODE_AT),
        }
    }

    /// Whether the `s`-th halved node owns its diamond's bound, and the owners before it.
    fn owner_rank(&self, s: usize) -> (bool, usize) {
        let l = &self.layout;
        let w = s / 32;
        let word = u32_at(self.bytes, l.owner_at + 4 * w);
        let bit = 1u32 << (s % 32);
        let before = self.count_of(l.owner_count_at, w) + (word & (bit - 1)).count_ones() as usize;
        (word & bit != 0, before)
    }

    /// Where the bound of the `s`-th halved node is: its diamond's, or a partner's own.
    fn bound_of(&self, s: usize) -> usize {
        let l = &self.layout;
        let (owner, before) = self.owner_rank(s);
        if !owner {
            let partner = s - before;
            if let Some(k) = self.rank(l.own_at, l.own_count_at, partner) {
                return l.own_bound_at + k * BOUND_LEN;
            }
        }
        l.bound_at + self.owner_from(s, owner, before) * BOUND_LEN
    }

    /// The owner of the diamond of the `s`-th halved node: its rank among the owners.
    fn owner_of(&self, s: usize) -> usize {
        let (owner, before) = self.owner_rank(s);
        self.owner_from(s, owner, before)
    }

    /// [`owner_of`](Self::owner_of) from [`owner_rank`](Self::owner_rank).
    fn owner_from(&self, s: usize, owner: bool, before: usize) -> usize {
        let l = &self.layout;
        if owner {
            return before;
        }
        let partner = s - before;
        match self.byte(l.partner_at + partner) {
            FAR => self.far(partner).saturating_sub(l.fixed),
            d => before.saturating_sub(1 + d as usize),
        }
    }

    /// The shapes of nodes `i` and `i + 1`: halved or a leaf, and its rank among either (one
    /// count of bits for both).
    pub(crate) fn shapes(&self, i: usize) -> [Shape; 2] {
        let l = &self.layout;
        let shape = |i: usize, before: usize, halved: bool| match halved {
            true => Shape::halved(before as u32),
            false => Shape::leaf((i - before) as u32),
        };
        if i >= l.nodes {
            return [Shape::leaf(0); 2];
        }
        let w = i / 32;
        let word = u32_at(self.bytes, l.split_at + 4 * w);
        let bit = 1u32 << (i % 32);
        let before = self.count_of(l.split_count_at, w) + (word & (bit - 1)).count_ones() as usize;
        let first = word & bit != 0;
        let second = match (i + 1) % 32 {
            _ if i + 1 >= l.nodes => return [shape(i, before, first), Shape::leaf(0)],
            0 => u32_at(self.bytes, l.split_at + 4 * (w + 1)) & 1 != 0,
            k => word & (1 << k) != 0,
        };
        let next = before + usize::from(first);
        [shape(i, before, first), shape(i + 1, next, second)]
    }

    /// The first half of node `i` of shape `shape`, if it is halved.
    pub(crate) fn first_half_of_shape(&self, i: usize, shape: Shape) -> Option<u32> {
        (i < self.layout.nodes && shape.is_halved())
            .then(|| (self.layout.roots + 2 * shape.rank()) as u32)
    }

    /// Where node `i` of shape `shape` is halved: its first half's node and its vertex, if it
    /// is.
    pub(crate) fn halving_of_shape(&self, i: usize, shape: Shape) -> Option<(u32, u32)> {
        let first = self.first_half_of_shape(i, shape)?;
        Some((
            first,
            (self.layout.fixed + self.owner_of(shape.rank())) as u32,
        ))
    }

    /// Node `i`: where it is halved, and its bound.
    pub(crate) fn node(&self, i: usize) -> Option<HierarchyNode> {
        let shape = self.shapes(i)[0];
        let (children, vertex) = self.halving_of_shape(i, shape).unwrap_or((0, NO_VERTEX));
        self.bound_of_shape(i, shape).map(|(b, _)| HierarchyNode {
            children,
            vertex,
            ..b
        })
    }

    /// Node `i`'s bound (its halving left out: a leaf's fields), and whether it is a leaf,
    /// with its shape `shape`.
    pub(crate) fn bound_of_shape(&self, i: usize, shape: Shape) -> Option<(HierarchyNode, bool)> {
        if i >= self.layout.nodes {
            return None;
        }
        Some(match shape.is_halved() {
            true => {
                let at = self.bound_of(shape.rank());
                let record = self.bytes.get(at..at + BOUND_LEN).unwrap_or_default();
                // (Where `f32` is hardware, one by one: with the words, the Cortex-M4F's frame 0
                // update in `fw_teapot` took 0.02M to 0.05M instructions more, as the code
                // around them compiled differently.)
                let vectors = match crate::math::HARD_FLOAT {
                    true => {
                        let mut vectors = [[0i8; 3]; KEPT];
                        for (k, v) in vectors.iter_mut().enumerate() {
                            *v = [0, 1, 2].map(|c| coordinate(record, 3 * k + c));
                        }
                        vectors
                    }
                    false => vector_coordinates(record),
                };
                let node = HierarchyNode {
                    children: 0,
                    vertex: NO_VERTEX,
                    vectors,
                    scale: self.scales.value(self.byte(at + VECTOR_BYTES)),
                    remainder: self.bounds.value(self.byte(at + VECTOR_BYTES + 1)),
                };
                (node, false)
            }
            false => {
                let node = HierarchyNode {
                    remainder: self.bounds.value(self.leaf_code(shape.rank())),
                    ..HierarchyNode::default()
                };
                (node, true)
            }
        })
    }

    pub(crate) fn position(&self, v: usize) -> Option<[f32; 3]> {
        let at = self.layout.vertex_at + v * VERTEX_LEN;
        (v < self.layout.vertices).then(|| {
            self.grid
                .decode([0, 1, 2].map(|k| u16_at(self.bytes, at + 2 * k)))
        })
    }

    /// The point of vertex `v` on the grid (`None` past the last).
    pub(crate) fn grid_point(&self, v: usize) -> Option<[u16; 3]> {
        let at = self.layout.vertex_at + v * VERTEX_LEN;
        (v < self.layout.vertices).then(|| [0, 1, 2].map(|k| u16_at(self.bytes, at + 2 * k)))
    }

    /// The grid of the model's box its points lie on.
    pub(crate) fn grid(&self) -> PositionGrid {
        self.grid
    }

    pub(crate) fn normal(&self, v: usize) -> Option<[f32; 3]> {
        self.normal_code(v).map(normal_of)
    }

    /// The octahedral code of vertex `v`'s normal (`None` past the last).
    pub(crate) fn normal_code(&self, v: usize) -> Option<[i8; 2]> {
        let at = self.layout.vertex_at + v * VERTEX_LEN + 6;
        (v < self.layout.vertices).then(|| [0, 1].map(|k| self.byte(at + k) as i8))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn six_bit_coordinates_pack_and_unpack() {
        let values: [i8; 3 * KEPT] = core::array::from_fn(|k| (k as i8 * 5) % 63 - 31);
        let mut bytes = [0u8; VECTOR_BYTES];
        for (k, &c) in values.iter().enumerate() {
            put_coordinate(&mut bytes, k, c);
        }
        for (k, &c) in values.iter().enumerate() {
            assert_eq!(coordinate(&bytes, k), c, "coordinate {k}");
        }
        let vectors = vector_coordinates(&bytes);
        for (k, &c) in values.iter().enumerate() {
            assert_eq!(vectors[k / 3][k % 3], c, "vector coordinate {k}");
        }
        assert_eq!(
            vector_coordinates(&bytes[..VECTOR_BYTES - 1]),
            [[-32; 3]; KEPT]
        );
        assert_eq!(VECTOR_BYTES, 9);
    }
}
