//! The frame's triangle list: every screen triangle of a frame, projected once and kept in
//! 8-byte slots, so that the bands rasterise from it instead of asking the source again.
//!
//! A corner takes one slot at the back of the list: its position at 1/16 pixel in `i16`, its
//! depth key and its shade. Triangles that share a corner share its slot: a corner is looked
//! up by value in a small hash table before it is added. At the front, triangles come in
//! groups of at most [`GROUP`] of one patch, each after a header slot with the number of half
//! slots its triangles take, the subpixel rows they span (so that a band skips the groups that
//! miss it without looking at their corners) and its corner *base*. A triangle takes half a
//! slot (4 bytes): its three corners as offsets of one byte below the base, and its wireframe
//! edges; with flat shading a second half holds its shade. A group's corners are the 256
//! slots below its base: a corner found further away is added again, and a group whose new
//! corners reach past the window ends there. On a tessellated mesh a Gouraud-shaded frame of
//! `T` triangles takes about `1.25 T` slots (about 10 bytes a triangle), where three corners of
//! its own would take 28.

mod sink;

pub(super) use sink::{fill, Remaining};

use super::raster::{Snapped, HALF, SUBPIXELS};

/// One slot of the frame's triangle list (8 bytes): a screen triangle or one of its corners
/// (see [`Renderer::with_triangle_list`](super::Renderer::with_triangle_list) and the module
/// docs).
///
/// Its contents are private; `Default` gives an empty slot to build the caller's buffer from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ListSlot([u16; 4]);

/// A triangle's flags (the high byte of its half slot's second word): wireframe edges in bits
/// 0 to 2, and [`FLAT`].
const FLAT: u8 = 1 << 3;

/// Triangles in a group, at most.
const GROUP: usize = 64;

/// Slots below a group's base its triangles can reach (offsets are one byte).
const WINDOW: usize = 256;

/// Corner slots above the free ones that a new group's window keeps in reach (corners of the
/// triangles just listed, which the next ones share).
const REACH_BACK: usize = 128;

/// Slots a list uses at most: corner numbers are `u16`.
const MAX_SLOTS: usize = u16::MAX as usize;

/// Half a slot: a triangle (corner offsets and flags), or a flat triangle's shade level.
type Half = [u16; 2];

impl ListSlot {
    /// A corner: `x`, `y` on the 1/16-pixel grid, its depth key and shade level.
    fn corner(x: i16, y: i16, depth: u16, shade: u8) -> ListSlot {
        ListSlot([x as u16, y as u16, depth, shade as u16])
    }

    /// A corner slot's `x`, in subpixels.
    fn x(&self) -> i16 {
        self.0[0] as i16
    }

    /// A corner slot's `y`, in subpixels.
    fn y(&self) -> i16 {
        self.0[1] as i16
    }

    /// A corner slot as the rasteriser takes it: `x`, `y` in subpixels, depth key, shade
    /// level.
    fn unpack_corner(&self) -> (i32, i32, u16, u8) {
        let [x, y, depth, shade] = self.0;
        (x as i16 as i32, y as i16 as i32, depth, shade as u8)
    }

    /// Sets half `k` (0 or 1) of a triangle slot.
    fn set_half(&mut self, k: usize, half: Half) {
        [self.0[2 * k], self.0[2 * k + 1]] = half;
    }

    /// A group header: no triangles yet, an empty span of rows, corners below slot `base`.
    fn empty_group(base: u16) -> ListSlot {
        ListSlot([0, i16::MAX as u16, i16::MIN as u16, base])
    }

    /// A group header's half slots.
    fn group_halves(&self) -> usize {
        self.0[0] as usize
    }

    /// A group header's corner base.
    fn group_base(&self) -> usize {
        self.0[3] as usize
    }

    /// Counts one more triangle of `halves` half slots, with corner rows `y`, in a group
    /// header.
    fn group_add(&mut self, halves: usize, y: [i16; 3]) {
        let [count, top, bottom, _] = &mut self.0;
        *count += halves as u16;
        let (lo, hi) = (y[0].min(y[1]).min(y[2]), y[0].max(y[1]).max(y[2]));
        *top = (*top as i16).min(lo) as u16;
        *bottom = (*bottom as i16).max(hi) as u16;
    }

    /// Whether a group header's triangles may cover a pixel centre of the rows `rows`
    /// stands for.
    fn group_meets(&self, rows: &SubpixelRows) -> bool {
        rows.meet(self.0[1] as i16, self.0[2] as i16)
    }
}

/// A triangle's half slot: its corners' offsets below the group's base, its wireframe edges
/// `wire`, and whether a half with its shade follows.
fn triangle_half(offsets: [u8; 3], wire: [bool; 3], flat: bool) -> Half {
    let flags = wire[0] as u8 | (wire[1] as u8) << 1 | (wire[2] as u8) << 2 | (flat as u8 * FLAT);
    [
        offsets[0] as u16 | (offsets[1] as u16) << 8,
        offsets[2] as u16 | (flags as u16) << 8,
    ]
}

/// Hands `f` the triangles in the first `front` slots of `list` (a list this module filled)
/// whose group may meet `rows`, in order, each with its corners (a triangle naming a slot
/// outside the list is left out: never in a list this module wrote).
pub(super) fn for_each_listed<'l>(
    list: &'l [ListSlot],
    front: usize,
    rows: &SubpixelRows,
    mut f: impl FnMut(ListedTriangle<'l>),
) {
    let front = list.get(..front).unwrap_or(&[]);
    let mut at = 0;
    while let Some(header) = front.get(at) {
        let halves = header.group_halves();
        let group = front
            .get(at + 1..at + 1 + halves.div_ceil(2))
            .unwrap_or(&[]);
        at += 1 + halves.div_ceil(2);
        if !header.group_meets(rows) {
            continue;
        }
        // Offsets are one byte: `base - 1 - offset` stays in the group's window, whose
        // slots are a fixed-size array (no bounds check per corner) unless the list is
        // shorter than a window.
        let base = header.group_base();
        let window = list.get(base.saturating_sub(WINDOW)..base).unwrap_or(&[]);
        match <&[ListSlot; WINDOW]>::try_from(window) {
            Ok(full) => group_triangles(group, halves, |off| Some(&full[WINDOW - 1 - off]), &mut f),
            Err(_) => group_triangles(
                group,
                halves,
                |off| window.get(window.len().wrapping_sub(1 + off)),
                &mut f,
            ),
        }
    }
}

/// Hands `f` the triangles of one group, `halves` half slots in `group`, with their corners
/// `corner(offset)`.
#[inline(always)]
fn group_triangles<'l>(
    group: &[ListSlot],
    halves: usize,
    corner: impl Fn(usize) -> Option<&'l ListSlot>,
    f: &mut impl FnMut(ListedTriangle<'l>),
) {
    let mut triangle = |ab: u16, c_flags: u16, flat: Option<u8>| {
        let at = |off: u16| corner((off & 0xff) as usize);
        if let (Some(a), Some(b), Some(c)) = (at(ab), at(ab >> 8), at(c_flags)) {
            f(ListedTriangle {
                corners: [a, b, c],
                flags: (c_flags >> 8) as u8,
                flat,
            });
        }
    };
    for (i, slot) in group.iter().enumerate() {
        let [ab, c_flags, second_ab, second_c_flags] = slot.0;
        if (c_flags >> 8) as u8 & FLAT != 0 {
            triangle(ab, c_flags, Some(second_ab as u8));
            continue;
        }
        triangle(ab, c_flags, None);
        if 2 * i + 1 < halves {
            triangle(second_ab, second_c_flags, None);
        }
    }
}

/// A triangle of the list with its corner slots.
pub(super) struct ListedTriangle<'l> {
    corners: [&'l ListSlot; 3],
    /// Its wireframe edges (bits 0 to 2).
    flags: u8,
    /// Its shade level with flat shading.
    flat: Option<u8>,
}

impl ListedTriangle<'_> {
    /// Its corners as the rasteriser takes them (as [`Snapped::new`] snaps the same
    /// corners).
    #[inline(always)]
    pub fn snapped(&self) -> Snapped {
        let c = self.corners.map(ListSlot::unpack_corner);
        let shade = match self.flat {
            Some(level) => [level; 3],
            None => c.map(|c| c.3),
        };
        Snapped {
            x: c.map(|c| c.0),
            y: c.map(|c| c.1),
            depth: c.map(|c| c.2),
            shade,
            wire: [0, 1, 2].map(|i| self.flags & (1 << i) != 0),
        }
    }

    /// Whether it may cover a pixel centre of the rows `rows` stands for.
    pub fn meets(&self, rows: &SubpixelRows) -> bool {
        let [a, b, c] = self.corners.map(ListSlot::y);
        rows.meet(a.min(b).min(c), a.max(b).max(c))
    }
}

/// Pixel rows `first..end` as limits on a triangle's highest and lowest corner, in
/// subpixels: a triangle covers no centre of those rows when its top lies below the last
/// row's centre or its bottom above the first row's centre.
#[derive(Clone, Copy)]
pub(super) struct SubpixelRows {
    top_max: i32,
    bottom_min: i32,
}

impl SubpixelRows {
    /// Whether something from subpixel row `top` down to `bottom` may cover a pixel centre
    /// of these rows.
    fn meet(&self, top: i16, bottom: i16) -> bool {
        top as i32 <= self.top_max && bottom as i32 >= self.bottom_min
    }

    pub fn new(rows: &core::ops::Range<i32>) -> Self {
        let (sub, half) = (SUBPIXELS as i32, HALF as i32);
        SubpixelRows {
            top_max: (rows.end - 1).saturating_mul(sub).saturating_add(half),
            bottom_min: rows.start.saturating_mul(sub).saturating_add(half),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::project::{depth_from_u16, shade_from_u8, shade_to_u8};
    use crate::render::raster::{snap_checked, ScreenVertex, Triangle};

    #[test]
    fn a_slot_is_8_bytes() {
        assert_eq!(core::mem::size_of::<ListSlot>(), 8);
    }

    #[test]
    fn slots_keep_the_snapped_corners_and_rows() {
        let v = |x: f32, y: f32| ScreenVertex {
            xy: [x, y],
            depth: 300.0,
            shade: crate::render::project::quantize_shade(0.2),
        };
        let fit = |c: f32| i16::try_from(snap_checked(c).unwrap()).unwrap();
        let corners = [v(0.5, 0.49), v(10.25, 3.0), v(-4.0, 20.97)];
        // A group of one triangle, then its corners.
        let mut list = [ListSlot::default(); 5];
        let mut y = [0; 3];
        for (k, c) in corners.iter().enumerate() {
            let level = shade_to_u8(c.shade);
            y[k] = fit(c.xy[1]);
            list[2 + k] = ListSlot::corner(fit(c.xy[0]), y[k], 300, level);
        }
        let wire = [true, false, true];
        // Corners 2, 3, 4 below base 5: offsets 2, 1, 0.
        list[0] = ListSlot::empty_group(5);
        list[0].group_add(1, y);
        list[1].set_half(0, triangle_half([2, 1, 0], wire, false));
        fn first_of(list: &[ListSlot]) -> Option<ListedTriangle<'_>> {
            let mut first = None;
            for_each_listed(list, 2, &SubpixelRows::new(&(-100..100)), |t| {
                if first.is_none() {
                    first = Some(t);
                }
            });
            first
        }
        fn count(list: &[ListSlot], rows: &SubpixelRows) -> usize {
            let mut n = 0;
            for_each_listed(list, 2, rows, |_| n += 1);
            n
        }
        let listed = first_of(&list).unwrap();
        let sub = 1.0 / SUBPIXELS as f32;
        let back = [2, 3, 4].map(|k| {
            let (x, y, depth, shade) = list[k].unpack_corner();
            ScreenVertex {
                xy: [x as f32 * sub, y as f32 * sub],
                depth: depth_from_u16(depth),
                shade: shade_from_u8(shade),
            }
        });
        for (a, b) in corners.iter().zip(&back) {
            assert_eq!(snap_checked(a.xy[0]), snap_checked(b.xy[0]));
            assert_eq!(snap_checked(a.xy[1]), snap_checked(b.xy[1]));
            assert_eq!((a.depth, a.shade), (b.depth, b.shade));
        }
        let tri = Triangle::new(back, wire).unwrap();
        let [first, last] = tri.rows();
        for r in first - 3..=last + 3 {
            let inside = (first..=last).contains(&r);
            let one = SubpixelRows::new(&(r..r + 1));
            assert_eq!(listed.meets(&one), inside, "row {r}");
            // The group spans the same rows as its one triangle.
            assert_eq!(list[0].group_meets(&one), inside, "row {r}");
            assert_eq!(count(&list, &one), inside as usize);
            for end in r + 1..r + 4 {
                let meets = first < end && last >= r;
                assert_eq!(
                    listed.meets(&SubpixelRows::new(&(r..end))),
                    meets,
                    "rows {r}..{end}"
                );
            }
        }
        let direct = listed.snapped().triangle().unwrap();
        assert_eq!(direct.rows(), tri.rows());
        for r in first..=last {
            assert_eq!(direct.span(r, -50..50, None), tri.span(r, -50..50, None));
        }
        // A flat triangle takes its shade from the half after its own.
        list[0].group_add(1, y);
        list[1].set_half(0, triangle_half([2, 1, 0], wire, true));
        list[1].set_half(1, [200, 0]);
        let flat = first_of(&list).unwrap().snapped().triangle().unwrap();
        let mut shaded = back;
        for c in &mut shaded {
            c.shade = shade_from_u8(200);
        }
        let expected = Triangle::new(shaded, wire).unwrap();
        for r in first..=last {
            assert_eq!(flat.span(r, -50..50, None), expected.span(r, -50..50, None));
        }
        // A corner offset below the list's start: the triangle is left out, not a panic.
        list[1].set_half(0, triangle_half([2, 1, 9], wire, true));
        assert!(first_of(&list).is_none());
    }
}
