//! Vertices below the bake: where a view is finer than the bake, the run time halves its
//! leaves further, evaluating the new vertices and bounding the new triangles itself.
//!
//! The halving goes on exactly as above the bake: the same hierarchy, the same rule (a leaf
//! over the tolerance is halved with the triangle across its hypotenuse), so the mesh stays
//! conforming and history-free. A new vertex goes into a caller pool, an open-addressed table
//! keyed by where it is: its patch and grid point, a point of a shared curve named by the
//! patch of lower index (so the two patches along the curve find one vertex, evaluated once,
//! from that patch), a point of a side collapsed to a pole written out as the pole's corner.
//! A triangle below the bake is bounded from its own lattice of step `1/6` (see
//! `deviation`'s module docs and `lattice`): 28 evaluations, the vectors projected as the
//! bake's are.
//!
//! When the pool is full (past seven eighths, to keep probes short), a leaf that needs a new
//! vertex stays whole and is counted as left over, with its bound in the frame's worst: the
//! frame reports what it honours ([`FrameStats::pool_full`](super::FrameStats::pool_full)).
//!
//! Without the crate feature `refine` the selection makes no vertex here (as with a full
//! pool), and this code and the surface evaluation it calls are left out of a build.

use super::address::{on_side, point_on, side_parameter, unit, Point, Tri};
use super::hierarchy::Hierarchy;
use super::HierarchyVertex;
use crate::patch::Side;

/// An empty entry's key.
const EMPTY: u64 = u64::MAX;

/// One entry of a tessellator's pool of vertices below the bake (see
/// [`TessellatorStorage`](super::TessellatorStorage)): opaque, the caller only provides
/// room for them.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PoolSlot {
    key: u64,
    pub(super) vertex: HierarchyVertex,
    pub(super) seen: bool,
}

impl PoolSlot {
    /// An empty slot.
    pub const EMPTY: PoolSlot = PoolSlot {
        key: EMPTY,
        vertex: HierarchyVertex {
            position: [0.0; 3],
            normal: [0.0; 3],
            uv: [0; 2],
            patch: 0,
            output: 0,
        },
        seen: false,
    };
}

impl Default for PoolSlot {
    fn default() -> Self {
        PoolSlot::EMPTY
    }
}

/// Where grid point `g` of patch `patch` is, as one key from every patch that has it: a point
/// of a shared side is named by the patch of lower index (its own grid point there).
pub(super) fn key(tree: &Hierarchy<'_>, patch: u32, g: Point) -> (u32, Point) {
    let mut best = (patch, g);
    for side in Side::ALL {
        if !on_side(side, g) {
            continue;
        }
        if let Some(l) = tree.link(patch, side) {
            let t = side_parameter(side, g);
            let there = point_on(l.side, if l.flip { super::address::ONE - t } else { t });
            best = best.min((l.patch, there));
        }
    }
    best
}

fn packed((patch, g): (u32, Point)) -> u64 {
    ((patch as u64) << 32) | ((g[0] as u64) << 16) | g[1] as u64
}

/// The slot to start probing at for `key` (a multiplicative hash).
fn start(key: u64, len: usize) -> usize {
    let h = key.wrapping_mul(0x9E37_79B9_7F4A_7C15);
    ((h >> 32) as usize) % len.max(1)
}

/// The pool of vertices below the bake: the caller's entries, how many are used, and whether
/// all the others are known to be empty.
#[derive(Debug)]
pub(super) struct Pool<'s> {
    pub entries: &'s mut [PoolSlot],
    pub used: usize,
    /// Every entry but the `used` ones is empty. The caller's entries are not known to be, nor
    /// a frame's after the next [`clear`](Self::clear): the frame's first vertex below the
    /// bake empties them ([`make`](Self::make)), so that a frame within the bake (most are)
    /// never writes the pool.
    pub clean: bool,
}

impl Pool<'_> {
    /// The pool in the caller's `entries`, whatever they hold.
    pub fn new(entries: &mut [PoolSlot]) -> Pool<'_> {
        Pool {
            entries,
            used: 0,
            clean: false,
        }
    }

    /// Empties the pool (see [`clean`](Self::clean): the entries are wiped when the frame makes
    /// its first vertex).
    pub fn clear(&mut self) {
        if self.used > 0 {
            self.clean = false;
        }
        self.used = 0;
    }

    /// Wipes the entries where they are not known to be empty.
    fn wipe(&mut self) {
        if !self.clean {
            for e in self.entries.iter_mut() {
                e.key = EMPTY;
            }
            (self.used, self.clean) = (0, true);
        }
    }

    /// Whether the pool takes no more vertices (past seven eighths, to keep probes short).
    pub fn is_full(&self) -> bool {
        let len = self.entries.len();
        self.used + 1 > len - len / 8
    }

    /// The slot of the vertex at `at` (a [`key`]), if the pool holds it.
    pub fn find(&self, at: (u32, Point)) -> Option<usize> {
        if !self.clean {
            return None; // (nothing made since the last frame's entries)
        }
        let key = packed(at);
        let len = self.entries.len();
        let mut i = start(key, len);
        for _ in 0..len {
            match self.entries[i].key {
                EMPTY => return None,
                k if k == key => return Some(i),
                _ => i = (i + 1) % len,
            }
        }
        None
    }

    /// Makes the vertex at the midpoint of `t`'s hypotenuse (if the pool has room): evaluated
    /// from the patch that names it, written out as the pole where `t`'s hypotenuse lies on a
    /// collapsed side; `base` is added to the slot to make its vertex number.
    pub fn make(&mut self, tree: &Hierarchy<'_>, t: &Tri, base: u32) -> Option<u32> {
        if self.is_full() {
            return None;
        }
        self.wipe();
        let len = self.entries.len();
        let at = key(tree, t.patch, t.midpoint());
        let k = packed(at);
        let mut i = start(k, len);
        while self.entries[i].key != EMPTY {
            i = (i + 1) % len;
        }
        let (u, v) = unit(at.1);
        let s = tree.patch_of(at.0).map(|bp| bp.evaluate(u, v));
        let id = base + i as u32;
        let pole = t
            .hypotenuse_side()
            .and_then(|side| tree.pole(t.patch, side));
        let vertex = match pole {
            Some(corner) => HierarchyVertex {
                position: tree.position(corner as usize).unwrap_or_default(),
                normal: tree.normal(corner as usize).unwrap_or_default(),
                uv: at.1,
                patch: at.0,
                output: corner,
            },
            None => HierarchyVertex {
                position: s.map_or([0.0; 3], |s| s.position.to_array()),
                // The outward normal: negated where the bake flipped the patch.
                normal: s.map_or([0.0; 3], |s| match tree.flip(at.0) {
                    true => (-s.normal).to_array(),
                    false => s.normal.to_array(),
                }),
                uv: at.1,
                patch: at.0,
                output: id,
            },
        };
        self.entries[i] = PoolSlot {
            key: k,
            vertex,
            seen: false,
        };
        self.used += 1;
        Some(id)
    }
}
