//! A bake's records as a hierarchy's compact bytes (the layout is the run time's:
//! `tessellator/format.rs`), which [`Hierarchy::from_bytes`] reads in place.
//!
//! The records are renumbered on the way: nodes level by level (so no node stores where its
//! halves are), vertices with the patches' and cells' corners first and then the halvings'
//! in node order (so the first triangle halved at a vertex does not store it), and the
//! copies the records keep of cell corners on other patches' curves left out.

use core::fmt;

use crate::tessellator::format::{
    fnv1a, link_code, model_fingerprint, put_coordinate, Layout, BOUND_LEN, CHECKSUM_AT, FAR,
    FAR_LEN, FNV_OFFSET, HEADER_LEN, LEAF_CODE_AT, LEAF_LEN, MAGIC, VECTOR_BYTES, VERTEX_LEN, WIDE,
};
use crate::tessellator::quantize::{normal_code, normal_of, LogGrid, PositionGrid};
use crate::tessellator::{
    Hierarchy, HierarchyError, HierarchyNode, HierarchyPatch, HierarchyVertex, FORMAT_VERSION, KEPT,
};

/// Why records could not be written as bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum EncodeError {
    /// The records are not a hierarchy of the model.
    Records(HierarchyError),
    /// The records halve a node more than once, or name a node twice as a half.
    Malformed,
    /// A record holds a value the bytes cannot (records not rounded as
    /// [`bake_hierarchy`](super::bake_hierarchy) rounds them): node `node`'s bound, or with
    /// `node` `u32::MAX`, a vertex's point or normal.
    NotOnGrid {
        /// The node (in the bytes' order).
        node: u32,
    },
    /// `scratch` has fewer entries than needed ([`encode_scratch_len`]).
    ScratchTooSmall {
        /// Entries needed.
        needed: usize,
    },
    /// `out` has fewer bytes than the hierarchy takes.
    OutputTooSmall {
        /// Bytes needed.
        needed: usize,
    },
}

impl fmt::Display for EncodeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EncodeError::Records(e) => write!(f, "the records are not a hierarchy: {e}"),
            EncodeError::Malformed => f.write_str("the records halve a node twice"),
            EncodeError::NotOnGrid { node } => {
                write!(f, "record {node} holds a value the bytes cannot hold")
            }
            EncodeError::ScratchTooSmall { needed } => {
                write!(f, "scratch too small: {needed} entries needed")
            }
            EncodeError::OutputTooSmall { needed } => {
                write!(f, "output too small: {needed} bytes needed")
            }
        }
    }
}

impl core::error::Error for EncodeError {}

impl From<HierarchyError> for EncodeError {
    fn from(e: HierarchyError) -> Self {
        EncodeError::Records(e)
    }
}

/// Entries of `scratch` [`encode_hierarchy`] takes for records of `nodes` nodes and
/// `vertices` vertices.
pub const fn encode_scratch_len(nodes: usize, vertices: usize) -> usize {
    nodes + 2 * vertices
}

const NONE: u32 = u32::MAX;

/// [`EncodeError::NotOnGrid`]'s node for a vertex.
const NO_NODE: u32 = u32::MAX;

/// The records renumbered: `scratch[..nodes]` holds the records' node of each node in the
/// bytes' order, `scratch[nodes..]` each record vertex's number in the bytes (or `NONE`).
struct Renumbered {
    fixed: usize,
    owners: usize,
    cell_corners: usize,
}

fn renumber(
    nodes: &[HierarchyNode],
    vertices: &[HierarchyVertex],
    patches: &[HierarchyPatch],
    scratch: &mut [u32],
) -> Result<Renumbered, EncodeError> {
    let (order, vmap) = scratch.split_at_mut(nodes.len());
    let vmap = &mut vmap[..vertices.len()];
    // Nodes level by level: the roots in patch order, then each halved node's halves.
    let mut len = 0;
    for p in patches {
        for k in 0..crate::tessellator::address::root_count(p.cells) {
            *order.get_mut(len).ok_or(EncodeError::Malformed)? = p.first_root + k as u32;
            len += 1;
        }
    }
    let mut i = 0;
    while i < len {
        let n = nodes[order[i] as usize];
        if n.children != 0 {
            if len + 2 > order.len() {
                return Err(EncodeError::Malformed);
            }
            order[len] = n.children;
            order[len + 1] = n.children + 1;
            len += 2;
        }
        i += 1;
    }
    if len != nodes.len() {
        return Err(EncodeError::Malformed);
    }
    // Vertices: the patches' corners, their cells' corners, then the halvings'.
    vmap.fill(NONE);
    let mut next = 0u32;
    let mut take = |vmap: &mut [u32], v: u32| {
        let out = vertices[v as usize].output as usize;
        if vmap[out] == NONE {
            vmap[out] = next;
            next += 1;
        }
    };
    let mut cell_corners = 0;
    for p in patches {
        for &c in &p.corners {
            take(vmap, c);
        }
    }
    for p in patches {
        let [a, b] = p.cells;
        if [a, b] != [0, 0] {
            let n = ((1u32 << a) + 1) * ((1u32 << b) + 1);
            for k in 0..n {
                take(vmap, p.cell_vertices + k);
            }
            cell_corners += n as usize;
        }
    }
    let fixed = next as usize;
    let mut owners = 0;
    for &old in order.iter() {
        let n = nodes[old as usize];
        if n.children != 0 && vmap[n.vertex as usize] == NONE {
            vmap[n.vertex as usize] = next;
            next += 1;
            owners += 1;
        }
    }
    Ok(Renumbered {
        fixed,
        owners,
        cell_corners,
    })
}

/// Writes `tree`'s records (it must read records: [`Hierarchy::new`]) as compact bytes into
/// `out`, with `scratch` of at least [`encode_scratch_len`] entries; returns the bytes
/// written. A hierarchy of the same model read from them ([`Hierarchy::from_bytes`]) gives
/// the same meshes.
///
/// ```
/// # use spline_tess::bake::{bake_hierarchy, encode_hierarchy, encode_scratch_len};
/// # use spline_tess::bake::{BakeBuffers, BakeScratch, BakeSettings};
/// # use spline_tess::tessellator::{Hierarchy, HierarchyNode, HierarchyPatch, HierarchyVertex};
/// # use spline_tess::{Model, PatchHeader, PatchSet, EdgeLink, BoundaryCurve};
/// let headers = [PatchHeader { degree_u: 1, degree_v: 1, first_point: 0 }];
/// let points = [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.2], [1.0, 1.0, 0.0]];
/// let patches = PatchSet::new(&headers, &points, None).unwrap();
/// let (mut edges, mut curves) = ([[EdgeLink::Collapsed; 4]], [BoundaryCurve::default(); 4]);
/// let model = Model::build(patches, &mut edges, &mut curves).unwrap();
/// let (mut nodes, mut vertices) = (vec![HierarchyNode::default(); 256], vec![HierarchyVertex::default(); 256]);
/// let (mut records, mut scratch) = ([HierarchyPatch::default()], vec![BakeScratch::default(); 256]);
/// let buffers = BakeBuffers { nodes: &mut nodes, vertices: &mut vertices, patches: &mut records, scratch: &mut scratch };
/// let size = bake_hierarchy(&model, &BakeSettings::default(), buffers).unwrap();
/// let tree = Hierarchy::new(patches, &nodes[..size.nodes], &vertices[..size.vertices], &records).unwrap();
///
/// let mut work = vec![0u32; encode_scratch_len(size.nodes, size.vertices)];
/// let mut bytes = vec![0u8; 4096];
/// let len = encode_hierarchy(&tree, &mut work, &mut bytes).unwrap();
/// let read = Hierarchy::from_bytes(patches, &bytes[..len]).unwrap();
/// assert_eq!(read.node_count(), tree.node_count());
/// ```
pub fn encode_hierarchy(
    tree: &Hierarchy<'_>,
    scratch: &mut [u32],
    out: &mut [u8],
) -> Result<usize, EncodeError> {
    let Some((nodes, vertices, patches)) = tree.records() else {
        return Err(EncodeError::Malformed);
    };
    let model = tree.model();
    let needed = encode_scratch_len(nodes.len(), vertices.len());
    let Some(scratch) = scratch.get_mut(..needed) else {
        return Err(EncodeError::ScratchTooSmall { needed });
    };
    let r = renumber(nodes, vertices, patches, scratch)?;
    let roots: usize = patches
        .iter()
        .map(|p| crate::tessellator::address::root_count(p.cells))
        .sum();
    let model_grids = (LogGrid::scales(&model), LogGrid::bounds(&model));
    let (scales, bounds) = model_grids;
    // A record's value as its code, if it is on the grid.
    let code = |g: &LogGrid, x: f32, i: usize| {
        let b = g.up(x);
        match g.value(b).to_bits() == x.to_bits() {
            true => Ok(b),
            false => Err(EncodeError::NotOnGrid { node: i as u32 }),
        }
    };
    // The leaves' common bound (the least), the leaves apart, and the partners whose owner
    // is too far back for a byte.
    let (order, rest) = scratch.split_at_mut(nodes.len());
    let (vmap, owner_node) = rest.split_at_mut(vertices.len());
    let (mut leaf_code, mut apart, mut far, mut own) = (u8::MAX, 0usize, 0usize, 0usize);
    let mut owners = 0usize;
    for (i, &old) in order.iter().enumerate() {
        let n = &nodes[old as usize];
        if n.children == 0 {
            leaf_code = leaf_code.min(code(&bounds, n.remainder, i)?);
        } else if vmap[n.vertex as usize] as usize == r.fixed + owners {
            owner_node[owners] = old;
            owners += 1;
        } else {
            let o = vmap[n.vertex as usize] as usize - r.fixed;
            far += usize::from(owners - 1 - o >= FAR as usize);
            own += usize::from(!same_bound(n, &nodes[owner_node[o] as usize]));
        }
    }
    let (order, vmap, owner_node) = (&*order, &*vmap, &*owner_node);
    for (i, &old) in order.iter().enumerate() {
        let n = &nodes[old as usize];
        if n.children == 0 && code(&bounds, n.remainder, i)? != leaf_code {
            apart += 1;
        }
    }
    let counts = [
        patches.len(),
        nodes.len(),
        roots,
        r.fixed + r.owners,
        r.fixed,
        r.owners,
        r.cell_corners,
        far,
        apart,
        own,
    ];
    let l = Layout::of(counts).ok_or(EncodeError::Malformed)?;
    let Some(out) = out.get_mut(..l.len) else {
        return Err(EncodeError::OutputTooSmall { needed: l.len });
    };
    out.fill(0);
    let vnum = |v: u32| vmap[vertices[v as usize].output as usize];
    let mut w = Writer { out };
    // Header.
    w.bytes(0, &MAGIC);
    w.u16(4, FORMAT_VERSION);
    w.u16(6, if l.index == 4 { WIDE } else { 0 });
    w.u32(12, model_fingerprint(&model));
    for (k, c) in counts.into_iter().enumerate() {
        w.u32(16 + 4 * k, c as u32);
    }
    w.out[LEAF_CODE_AT] = leaf_code;
    // Patches and cell corners. A node's number in the bytes: its place in `order`.
    let mut first_root = 0u32;
    let mut cell = 0usize;
    for (p, rec) in patches.iter().enumerate() {
        let (at, width) = (HEADER_LEN + p * l.patch_len, l.number);
        w.out[at] = rec.cells[0] | rec.cells[1] << 4;
        w.out[at + 1] = u8::from(rec.flip) | rec.poles << 4;
        let numbers = rec.links.map(|link| link_code(link, width)).into_iter();
        let numbers = numbers.chain(rec.corners.map(vnum));
        let numbers = numbers.chain([first_root, cell as u32]);
        for (k, n) in numbers.enumerate() {
            w.index(at + 2 + width * k, width, n);
        }
        first_root += crate::tessellator::address::root_count(rec.cells) as u32;
        for (k, &c) in rec.cone.iter().enumerate() {
            w.u32(at + 2 + 10 * width + 4 * k, c.to_bits());
        }
        let [a, b] = rec.cells;
        if [a, b] != [0, 0] {
            for k in 0..((1u32 << a) + 1) * ((1u32 << b) + 1) {
                w.index(
                    l.cell_at + cell * l.index,
                    l.index,
                    vnum(rec.cell_vertices + k),
                );
                cell += 1;
            }
        }
    }
    let grid = PositionGrid::of(&model);
    // Halvings, owners, partners and bounds, in node order. A halving's vertex was
    // numbered in this order: the next owner's number where it is the first at it.
    let (mut s, mut owners, mut partners) = (0usize, 0usize, 0usize);
    let (mut far, mut apart, mut own) = (0usize, 0usize, 0usize);
    let mut shared = true;
    for (i, &old) in order.iter().enumerate() {
        let n = &nodes[old as usize];
        let mut owner = false;
        if n.children != 0 {
            w.set_bit(l.split_at, i);
            let v = vmap[n.vertex as usize];
            owner = v == (l.fixed + owners) as u32;
            if owner {
                w.set_bit(l.owner_at, s);
                owners += 1;
            } else {
                // Its bound: its owner's, or its own.
                let o = v as usize - l.fixed;
                shared = same_bound(n, &nodes[owner_node[o] as usize]);
                if !shared {
                    w.set_bit(l.own_at, partners);
                }
                // How far back its owner is among the owners, or in the far partners.
                let back = owners - 1 - (v as usize - l.fixed);
                if back < FAR as usize {
                    w.out[l.partner_at + partners] = back as u8;
                } else {
                    w.out[l.partner_at + partners] = FAR;
                    w.u32(l.far_at + far * FAR_LEN, partners as u32);
                    w.u32(l.far_at + far * FAR_LEN + 4, v);
                    far += 1;
                }
                partners += 1;
            }
            s += 1;
        }
        let remainder = code(&bounds, n.remainder, i)?;
        if n.children != 0 {
            let mut record = [0u8; BOUND_LEN];
            for (k, v) in n.vectors.iter().enumerate() {
                for (c, &x) in v.iter().enumerate() {
                    if !(-31..=31).contains(&x) {
                        return Err(EncodeError::NotOnGrid { node: i as u32 });
                    }
                    put_coordinate(&mut record, 3 * k + c, x);
                }
            }
            record[VECTOR_BYTES] = code(&scales, n.scale, i)?;
            record[VECTOR_BYTES + 1] = remainder;
            // A diamond's bound at its owner's place; a partner's own in its own list.
            if owner {
                let at = l.bound_at + (vmap[n.vertex as usize] as usize - l.fixed) * BOUND_LEN;
                w.out[at..at + BOUND_LEN].copy_from_slice(&record);
            } else if !shared {
                let at = l.own_bound_at + own * BOUND_LEN;
                w.out[at..at + BOUND_LEN].copy_from_slice(&record);
                own += 1;
            }
        } else {
            if n.scale != 0.0 || n.vectors != [[0; 3]; KEPT] {
                return Err(EncodeError::NotOnGrid { node: i as u32 });
            }
            if remainder != leaf_code {
                let at = l.leaf_at + apart * LEAF_LEN;
                w.u32(at, (i - s) as u32);
                w.out[at + 4] = remainder;
                apart += 1;
            }
        }
    }
    w.counts(l.split_at, l.split_count_at, l.nodes, l.count);
    w.counts(l.owner_at, l.owner_count_at, l.splits(), l.count);
    w.counts(l.own_at, l.own_count_at, l.splits() - l.owners, l.count);
    // Vertices, in their new order.
    for (old, &new) in vmap.iter().enumerate() {
        if new == NONE {
            continue;
        }
        let at = l.vertex_at + new as usize * VERTEX_LEN;
        let v = &vertices[old];
        let q = grid.encode(v.position);
        let bits = |p: [f32; 3]| p.map(f32::to_bits);
        // The normal's code, or a neighbour of it whose normal is the record's.
        let base = normal_code(v.normal);
        let n = (0..10i8)
            .map(|k| match k {
                0 => base,
                _ => [
                    base[0].saturating_add((k - 1) / 3 - 1),
                    base[1].saturating_add((k - 1) % 3 - 1),
                ],
            })
            .find(|&c| bits(normal_of(c)) == bits(v.normal));
        let (true, Some(n)) = (bits(grid.decode(q)) == bits(v.position), n) else {
            return Err(EncodeError::NotOnGrid { node: NO_NODE });
        };
        for (k, x) in q.iter().enumerate() {
            w.u16(at + 2 * k, *x);
        }
        for (k, x) in n.iter().enumerate() {
            w.out[at + 6 + k] = *x as u8;
        }
    }
    let sum = fnv1a(FNV_OFFSET, &w.out[CHECKSUM_AT + 4..]);
    w.u32(CHECKSUM_AT, sum);
    Ok(l.len)
}

/// Whether two records hold the same bound, bit for bit.
fn same_bound(a: &HierarchyNode, b: &HierarchyNode) -> bool {
    a.vectors == b.vectors
        && a.scale.to_bits() == b.scale.to_bits()
        && a.remainder.to_bits() == b.remainder.to_bits()
}

struct Writer<'o> {
    out: &'o mut [u8],
}

impl Writer<'_> {
    fn bytes(&mut self, at: usize, b: &[u8]) {
        self.out[at..at + b.len()].copy_from_slice(b);
    }
    fn u16(&mut self, at: usize, x: u16) {
        self.bytes(at, &x.to_le_bytes());
    }
    fn u32(&mut self, at: usize, x: u32) {
        self.bytes(at, &x.to_le_bytes());
    }
    fn index(&mut self, at: usize, width: usize, x: u32) {
        match width {
            2 => self.u16(at, x as u16),
            _ => self.u32(at, x),
        }
    }
    fn set_bit(&mut self, bits_at: usize, i: usize) {
        self.out[bits_at + 4 * (i / 32) + (i % 32) / 8] |= 1 << (i % 8);
    }
    /// Writes each word's count of set bits before it.
    fn counts(&mut self, bits_at: usize, counts_at: usize, len: usize, width: usize) {
        let mut total = 0u32;
        for w in 0..len.div_ceil(32) {
            self.index(counts_at + width * w, width, total);
            let at = bits_at + 4 * w;
            let word = u32::from_le_bytes([
                self.out[at],
                self.out[at + 1],
                self.out[at + 2],
                self.out[at + 3],
            ]);
            total += word.count_ones();
        }
    }
}
