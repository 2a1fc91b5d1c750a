//! The sink that fills the frame's triangle list from one pass over the source (the slots'
//! format: see the parent module).

use super::{triangle_half, ListSlot, GROUP, MAX_SLOTS, REACH_BACK, WINDOW};
use crate::render::clip::ClipVertex;
use crate::render::project::{
    depth_to_u16, quantize_shade, quantized_level, shade_to_u8, CachedCorners, CornerCache, Setup,
    CORNER_CACHE,
};
use crate::render::raster::{faces_away, snap_checked, ScreenVertex};
use crate::render::{Shading, TriangleSource};
use crate::sink::{TriangleSink, Vertex};

/// Entries of the table that finds a corner already in the list by its value.
const SHARED: usize = 256;

/// An entry of the vertex map (and of the table of values) for a vertex with no corner in
/// the list. Slot 0 never holds a corner: a group's header comes before its triangles'
/// corners, at the front, so corners take slots from the top down to 1 at the lowest, and
/// a lookup takes an entry only at or above the corners in use. (0, not `u16::MAX`: clearing
/// the map is then a `memclr`, which the bands' clears link anyway, and a firmware need not
/// link `memset` as well: 404 bytes of flash.)
pub(in crate::render) const NO_SLOT: u16 = 0;

/// Why a triangle did not go into the list.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum NoRoom {
    /// The list is full.
    Full,
    /// A new corner would fall out of the open group's window.
    Window,
}

/// The sink that fills the list from one pass over the source.
///
/// When a triangle does not fit (the list is full, or a corner is out of `i16`), the list keeps
/// the patches before that triangle's patch and the frame resumes there: each band draws the
/// list, then streams the patches from `resume` on. That needs the source to hand patches in
/// increasing order (a [`Tessellator`](crate::Tessellator) does); when it does not, the list is
/// given up (`overflow`) and every band streams the whole frame.
pub(in crate::render) struct ListSink<'a, 'b, 'c> {
    pub setup: &'a Setup<'a>,
    list: &'b mut [ListSlot],
    /// Group and triangle slots in use: `0..len`.
    pub len: usize,
    /// Triangles listed.
    pub listed: u32,
    /// The slot of the open group's header, if one is open.
    group: Option<usize>,
    /// Corner slots in use: `top..` the list's usable end.
    top: usize,
    /// Corner slots by a hash of their value ([`NO_SLOT`]: none).
    shared: [u16; SHARED],
    /// Triangles handed over by the source.
    pub handed: u32,
    /// The patch of the last triangle, where its groups and corners start in the list, and the
    /// triangles listed before it.
    current: Option<(u32, usize, usize, u32)>,
    /// Whether the patches came in increasing order so far.
    increasing: bool,
    /// The first patch the list does not hold.
    pub resume: Option<u32>,
    /// Set when the list is given up.
    pub overflow: bool,
    /// Corners in view space by key.
    corners: &'c mut CornerCache,
    /// The list value of the corner in each entry of `corners`, where bit `e` of `projected`
    /// is set: a corner shared by triangles inside the clip planes is projected once while
    /// the cache keeps it.
    values: [ListSlot; CORNER_CACHE],
    projected: u64,
    /// The list slot of each vertex's corner, by vertex number (see
    /// [`Renderer::with_vertex_map`](crate::render::Renderer::with_vertex_map)), or [`NO_SLOT`];
    /// empty when the source's keys are not vertex numbers this map holds.
    map: &'c mut [u16],
    /// Whether a patch's triangles that face away are left out (the source's
    /// [`one_sided`](TriangleSource::one_sided)), and whether the current patch's are.
    one_sided: &'a dyn Fn(u32) -> bool,
    cull: bool,
    /// Triangles left out for facing away.
    pub culled: u32,
}

impl<'a, 'b, 'c> ListSink<'a, 'b, 'c> {
    pub fn new(
        setup: &'a Setup<'a>,
        list: &'b mut [ListSlot],
        corners: &'c mut CornerCache,
        map: &'c mut [u16],
        one_sided: &'a dyn Fn(u32) -> bool,
    ) -> Self {
        let end = list.len().min(MAX_SLOTS);
        ListSink {
            setup,
            list: &mut list[..end],
            len: 0,
            listed: 0,
            group: None,
            top: end,
            shared: [NO_SLOT; SHARED],
            handed: 0,
            current: None,
            increasing: true,
            resume: None,
            overflow: false,
            corners,
            values: [ListSlot::default(); CORNER_CACHE],
            projected: 0,
            map,
            one_sided,
            cull: false,
            culled: 0,
        }
    }
}

impl ListSink<'_, '_, '_> {
    /// Counts a triangle handed over; whether the list still takes triangles (its corners
    /// are worth computing).
    fn admit(&mut self) -> bool {
        self.handed += 1;
        self.open()
    }

    /// Slots in use: the groups', the triangles' and the corners'.
    pub fn used(&self) -> usize {
        self.len + (self.list.len() - self.top)
    }

    /// Whether the list is neither given up nor cut at a patch.
    fn open(&self) -> bool {
        !self.overflow && self.resume.is_none()
    }

    /// The offset below `base` of a corner with value `value`: a slot already in the list
    /// within the window below `base`, or a new one. `vertex`: the corner's entry in the
    /// vertex map, which then finds its slot (else a table of values does, which may miss).
    fn corner_slot(
        &mut self,
        value: ListSlot,
        base: usize,
        vertex: Option<usize>,
    ) -> Result<u8, NoRoom> {
        let entry = match vertex {
            Some(v) => v,
            None => {
                let [x, y, d, s] = value.0;
                let h =
                    (x as u32 | (y as u32) << 16) ^ (d as u32 | (s as u32) << 16).rotate_left(7);
                (h.wrapping_mul(0x9e37_79b1) >> 24) as usize % SHARED
            }
        };
        let table: &mut [u16] = match vertex {
            Some(_) => &mut *self.map,
            None => &mut self.shared,
        };
        let known = table.get(entry).map_or(usize::MAX, |&s| s as usize);
        let window = base.saturating_sub(WINDOW)..base;
        // A vertex's entry at or above the corners in use holds its corner: slots are freed
        // only when a triangle does not fit, and then the entries into them are written again
        // (the triangle is pushed again in a new group) or never read again (the list is cut).
        // A value table's entry may be another corner's.
        let same = vertex.is_some() || self.list.get(known) == Some(&value);
        if known >= self.top && window.contains(&known) && same {
            return Ok((base - 1 - known) as u8);
        }
        if self.top <= self.len {
            return Err(NoRoom::Full);
        }
        if self.top - 1 < window.start {
            return Err(NoRoom::Window);
        }
        self.top -= 1;
        self.list[self.top] = value;
        if let Some(e) = table.get_mut(entry) {
            *e = self.top as u16;
        }
        Ok((base - 1 - self.top) as u8)
    }

    /// The list value of a projected corner; `None` when it is out of the list's `i16` range.
    #[inline]
    fn corner_value(&self, v: &ScreenVertex) -> Option<ListSlot> {
        let fit = |c: f32| i16::try_from(snap_checked(c)?).ok();
        // With flat shading the triangle holds the shade (its corners share a slot).
        let flat = self.setup.style.shading == Shading::Flat;
        let shade = if flat { 0 } else { quantized_level(v.shade) };
        Some(ListSlot::corner(
            fit(v.xy[0])?,
            fit(v.xy[1])?,
            depth_to_u16(v.depth),
            shade,
        ))
    }

    /// Adds one projected triangle; false when it does not fit (nothing is added then).
    fn push(&mut self, v: &[ScreenVertex; 3], wire: [bool; 3]) -> bool {
        let flat = self.setup.style.shading == Shading::Flat;
        let mut values = [ListSlot::default(); 3];
        for (value, v) in values.iter_mut().zip(v) {
            let Some(c) = self.corner_value(v) else {
                return false;
            };
            *value = c;
        }
        let level = flat.then(|| quantized_level(v[0].shade));
        self.push_values(values, wire, level, None)
    }

    /// Adds a triangle of corner values `values` (of vertex map entries `vertices`, when
    /// known); false when it does not fit (nothing is added then).
    #[inline(always)]
    fn push_values(
        &mut self,
        values: [ListSlot; 3],
        wire: [bool; 3],
        level: Option<u8>,
        vertices: Option<[usize; 3]>,
    ) -> bool {
        let y = values.map(|v| v.y());
        if self.cull && faces_away(values.map(|v| v.x().into()), y.map(i32::from)) {
            // Behind a triangle that faces the eye: nothing to list, and nothing lost.
            self.culled += 1;
            return true;
        }
        // A corner out of the open group's window closes it: the next group's window starts
        // at the free slots.
        match self.try_push(values, y, wire, level, vertices) {
            Err(NoRoom::Window) => {
                self.group = None;
                self.try_push(values, y, wire, level, vertices).is_ok()
            }
            pushed => pushed.is_ok(),
        }
    }

    /// Whether the group whose header is at `g` has room for one more triangle (flat or not).
    fn group_takes(&self, g: usize, flat: bool) -> bool {
        let used = self.list[g].group_halves();
        used + halves_added(used, flat) <= 2 * GROUP
    }

    /// [`push`](Self::push) into the open group (or a new one when there is none or it is
    /// full); on an error nothing is added.
    fn try_push(
        &mut self,
        values: [ListSlot; 3],
        y: [i16; 3],
        wire: [bool; 3],
        level: Option<u8>,
        vertices: Option<[usize; 3]>,
    ) -> Result<(), NoRoom> {
        let (len, top, group) = (self.len, self.top, self.group);
        let restore = |sink: &mut Self| (sink.len, sink.top, sink.group) = (len, top, group);
        let flat = level.is_some();
        let header = match self.group {
            Some(g) if self.group_takes(g, flat) => g,
            _ => {
                if self.len >= self.top {
                    return Err(NoRoom::Full);
                }
                let base = (self.top + REACH_BACK).min(self.list.len());
                self.list[self.len] = ListSlot::empty_group(base as u16);
                self.group = Some(self.len);
                self.len += 1;
                self.len - 1
            }
        };
        let base = self.list[header].group_base();
        let mut offsets = [0u8; 3];
        for (i, (offset, value)) in offsets.iter_mut().zip(values).enumerate() {
            match self.corner_slot(value, base, vertices.map(|v| v[i])) {
                Ok(o) => *offset = o,
                Err(e) => {
                    restore(self);
                    return Err(e);
                }
            }
        }
        // The triangle goes in the group's next half slot; a flat one in a slot of its own,
        // its shade in the second half (after an odd number of halves, which a list of one
        // shading never has, the half before it is left empty: a triangle of one corner,
        // which draws nothing).
        let used = self.list[header].group_halves();
        let (slot, second) = match level {
            Some(_) => (header + 1 + used.div_ceil(2), false),
            None => (header + 1 + used / 2, used % 2 == 1),
        };
        let end = slot + 1;
        // (Corners all found in the list take no room: the triangle's slot may still not.)
        if end > self.top {
            restore(self);
            return Err(NoRoom::Full);
        }
        let [ab, c_flags] = triangle_half(offsets, wire, level.is_some());
        if second {
            self.list[slot].set_half(1, [ab, c_flags]);
        } else {
            self.list[slot] = ListSlot([ab, c_flags, level.unwrap_or(0) as u16, 0]);
        }
        self.len = end;
        self.listed += 1;
        self.list[header].group_add(halves_added(used, flat), y);
        Ok(())
    }

    /// Lists one admitted triangle, its corners in view space (`inside`: all inside the clip
    /// planes).
    fn take(&mut self, patch: u32, corners: [ClipVertex; 3], inside: bool) {
        self.begin(patch);
        let mut fits = true;
        self.setup.project(corners, inside, |v, wire| {
            fits = fits && self.push(&v, wire);
        });
        self.end(fits);
    }

    /// [`take`](Self::take) for corners from the corner cache, all inside the clip planes and
    /// in three different entries: each corner's list value is computed once while the cache
    /// holds it. The same values as `take` (its screen corners, quantized the same way).
    fn take_cached(&mut self, patch: u32, found: &CachedCorners) {
        self.begin(patch);
        let mut values = [ListSlot::default(); 3];
        let mut fits = true;
        for ((value, c), &entry) in values.iter_mut().zip(&found.corners).zip(&found.entries) {
            let (e, bit) = (entry as usize % CORNER_CACHE, 1u64 << (entry % 64));
            // (Corners in one entry come here only from different triangles: the entry held
            // this corner when its value was kept, else the bit was cleared.)
            if self.projected & bit == 0 {
                match self.corner_value(&self.setup.screen(c)) {
                    Some(v) => self.values[e] = v,
                    None => {
                        fits = false;
                        break;
                    }
                }
                self.projected |= bit;
            }
            *value = self.values[e];
        }
        if fits {
            let level = self
                .setup
                .flat_shade(&found.corners)
                .map(|s| shade_to_u8(quantize_shade(s)));
            let wire = self.setup.style.wireframe.is_some();
            fits = self.push_values(values, [wire; 3], level, None);
        }
        self.end(fits);
    }

    /// [`take`](Self::take) for a Gouraud-shaded triangle whose corners are vertices `keys`
    /// of the vertex map: a corner already listed is taken from the list, the others are
    /// projected once. The same values as `take`. `None` (nothing done) when a corner is not
    /// in the map or not inside the clip planes: `take` then clips the triangle.
    fn take_mapped(
        &mut self,
        patch: u32,
        keys: [u64; 3],
        corner: &mut dyn FnMut(usize) -> Vertex,
    ) -> Option<()> {
        let mut values = [ListSlot::default(); 3];
        let mut vertices = [0usize; 3];
        for i in 0..3 {
            let v = usize::try_from(keys[i]).ok()?;
            let slot = *self.map.get(v)? as usize;
            // (A slot below the corners in use was freed when a triangle did not fit.)
            values[i] = match self.list.get(slot).filter(|_| slot >= self.top) {
                Some(&listed) => listed,
                None => {
                    let c = self.setup.keyed_corner(keys[i], i, corner);
                    if !self.setup.inside(&c) {
                        return None;
                    }
                    self.corner_value(&self.setup.screen(&c))?
                }
            };
            vertices[i] = v;
        }
        self.begin(patch);
        let wire = self.setup.style.wireframe.is_some();
        let fits = self.push_values(values, [wire; 3], None, Some(vertices));
        self.end(fits);
        Some(())
    }

    /// Opens patch `patch`'s groups when its first triangle comes.
    fn begin(&mut self, patch: u32) {
        let started = match self.current {
            Some((p, ..)) if p == patch => None,
            Some((p, ..)) if p > patch => {
                self.increasing = false;
                Some(patch)
            }
            _ => Some(patch),
        };
        if let Some(patch) = started {
            // A patch starts a group of its own, so that a cut at its start cuts no group.
            self.group = None;
            self.current = Some((patch, self.len, self.top, self.listed));
            self.cull = (self.one_sided)(patch);
        }
    }

    /// After a triangle: when it did not `fit`, the list is cut at its patch's start (or
    /// given up).
    fn end(&mut self, fits: bool) {
        if !fits {
            match self.current {
                Some((p, len, top, listed)) if self.increasing => {
                    (self.len, self.top, self.listed) = (len, top, listed);
                    self.group = None;
                    self.resume = Some(p);
                }
                _ => self.overflow = true,
            }
        }
    }
}

impl TriangleSink for ListSink<'_, '_, '_> {
    fn wants_parameters(&self) -> bool {
        false
    }

    fn triangle(&mut self, patch: u32, corners: [&Vertex; 3]) {
        if self.admit() {
            let (corners, inside) = self.setup.corners(corners);
            self.take(patch, corners, inside);
        }
    }

    fn keyed_triangle(
        &mut self,
        patch: u32,
        keys: [u64; 3],
        corner: &mut dyn FnMut(usize) -> Vertex,
    ) {
        if !self.admit() {
            return;
        }
        let gouraud = self.setup.style.shading == Shading::Gouraud;
        if gouraud && !self.map.is_empty() && self.take_mapped(patch, keys, corner).is_some() {
            return;
        }
        let found = self.corners.corners_in_entries(self.setup, keys, corner);
        self.projected &= !found.replaced;
        let [a, b, c] = found.entries;
        if found.inside && a != b && b != c && a != c {
            self.take_cached(patch, &found);
        } else {
            self.take(patch, found.corners, false);
        }
    }

    fn wants_patch(&self, _patch: u32) -> bool {
        self.open()
    }
}

/// What [`fill`] listed.
pub(in crate::render) struct Filled {
    /// Triangles handed over by the source.
    pub handed: u32,
    /// `Some((n, resume))` when the list holds the frame's first `n` slots of groups and
    /// triangles: all of the frame, unless patches from `resume` on are left out. `None` when
    /// the list was given up.
    pub listed: Option<(usize, Option<u32>)>,
    /// Triangles listed.
    pub triangles: u32,
    /// Triangles left out for facing away.
    pub culled: u32,
    /// Slots in use.
    pub slots: u32,
}

/// Fills `list` from one pass over `source`'s triangles on `rows`. Out of line, so that the
/// sink's tables take stack only during this pass, not under the bands drawn after it.
#[inline(never)]
pub(in crate::render) fn fill<S: TriangleSource>(
    setup: &Setup<'_>,
    list: &mut [ListSlot],
    corners: &mut CornerCache,
    map: &mut [u16],
    source: &S,
    rows: core::ops::Range<u32>,
) -> Filled {
    // The vertex map serves when it has an entry for every vertex number.
    let map = match source.vertex_numbers() {
        Some(n) if n <= map.len() => &mut map[..n],
        _ => &mut [],
    };
    map.fill(NO_SLOT);
    let one_sided = |patch| source.one_sided(setup.camera, patch);
    let mut sink = ListSink::new(setup, list, corners, map, &one_sided);
    source.stream_rows(setup.camera, rows, &mut sink);
    Filled {
        handed: sink.handed,
        listed: (!sink.overflow).then_some((sink.len, sink.resume)),
        triangles: sink.listed,
        culled: sink.culled,
        slots: sink.used() as u32,
    }
}

/// Passes on the triangles of the patches from `first` on (those a partial list does not
/// hold).
pub(in crate::render) struct Remaining<'s, S> {
    pub first: u32,
    pub sink: &'s mut S,
}

impl<S: TriangleSink> TriangleSink for Remaining<'_, S> {
    fn triangle(&mut self, patch: u32, corners: [&Vertex; 3]) {
        if patch >= self.first {
            self.sink.triangle(patch, corners);
        }
    }

    fn keyed_triangle(
        &mut self,
        patch: u32,
        keys: [u64; 3],
        corner: &mut dyn FnMut(usize) -> Vertex,
    ) {
        if patch >= self.first {
            self.sink.keyed_triangle(patch, keys, corner);
        }
    }

    fn wants_patch(&self, patch: u32) -> bool {
        patch >= self.first && self.sink.wants_patch(patch)
    }

    fn wants_parameters(&self) -> bool {
        self.sink.wants_parameters()
    }
}

/// Half slots a triangle adds to a group that holds `used`: one for a Gouraud-shaded
/// triangle, a whole slot for a flat one (and the half before it after an odd count).
fn halves_added(used: usize, flat: bool) -> usize {
    if flat {
        2 * used.div_ceil(2) + 2 - used
    } else {
        1
    }
}

#[cfg(test)]
mod tests {
    use super::super::{for_each_listed, SubpixelRows};
    use super::*;
    use crate::render::project::tests::view;

    /// A screen corner at `(x, y)`, depth 300, one shade.
    fn v(x: f32, y: f32) -> ScreenVertex {
        ScreenVertex {
            xy: [x, y],
            depth: 300.0,
            shade: crate::render::project::quantize_shade(0.2),
        }
    }

    /// A triangle whose corners are all in the list already still needs its own slot: a full
    /// list refuses it and keeps its corners (it once wrote over the lowest corner slot).
    #[test]
    fn a_full_list_refuses_a_triangle_of_shared_corners() {
        let (camera, style) = view();
        let setup = Setup::new(&camera, None, &style, crate::Arithmetic::Float, None);
        let mut corners = CornerCache::new();
        let t = [v(1.0, 1.0), v(9.0, 2.0), v(3.0, 8.0)];
        // A group header, one slot of two triangles and their three shared corners.
        let mut list = [ListSlot::default(); 5];
        let mut sink = ListSink::new(&setup, &mut list, &mut corners, &mut [], &|_| false);
        assert!(sink.push(&t, [false; 3]));
        assert!(sink.push(&t, [false; 3]));
        assert_eq!((sink.len, sink.used()), (2, 5));
        assert!(!sink.push(&t, [false; 3]), "no slot left for a third");
        assert_eq!((sink.len, sink.used(), sink.listed), (2, 5, 2));
        let kept: [_; 3] = core::array::from_fn(|k| list[2 + k].unpack_corner());
        for (k, c) in kept.iter().enumerate() {
            assert!(t.iter().any(|s| snap_checked(s.xy[1]) == Some(c.1)), "{k}");
        }
        let all = SubpixelRows::new(&(-100..100));
        let mut drawn = 0;
        for_each_listed(&list, 2, &all, |l| {
            drawn += l.snapped().triangle().is_some() as usize
        });
        assert_eq!(drawn, 2);
    }

    /// A group reaches the 256 corner slots below its base: a triangle with a corner further
    /// away starts a new group, whose window starts at the free slots, and every triangle
    /// keeps its own corners.
    #[test]
    fn a_corner_out_of_the_window_starts_a_group() {
        let (camera, style) = view();
        let setup = Setup::new(&camera, None, &style, crate::Arithmetic::Float, None);
        let mut corners = CornerCache::new();
        // A fan around one centre: 200 triangles of new corners, the centre shared by all
        // of them until it falls out of the window.
        let fan = |k: usize| {
            let a = k as f32 * 0.125;
            [v(16.0, 16.0), v(a, 1.0), v(a + 0.0625, 30.0)]
        };
        let mut list = [ListSlot::default(); 1024];
        let mut sink = ListSink::new(&setup, &mut list, &mut corners, &mut [], &|_| false);
        for k in 0..200 {
            assert!(sink.push(&fan(k), [false; 3]), "{k}");
        }
        let (len, listed) = (sink.len, sink.listed);
        assert_eq!(listed, 200);
        let all = SubpixelRows::new(&(-100..100));
        let mut k = 0;
        for_each_listed(&list, len, &all, |t| {
            let want = fan(k).map(|c| (snap_checked(c.xy[0]), snap_checked(c.xy[1])));
            let got = t.corners.map(|c| {
                let (x, y, ..) = c.unpack_corner();
                (Some(x), Some(y))
            });
            assert_eq!(got, want, "triangle {k}");
            k += 1;
        });
        assert_eq!(k, 200);
        // More than one group, and more than one copy of the centre.
        let centres = list[len..]
            .iter()
            .filter(|c| {
                let (x, y, ..) = c.unpack_corner();
                Some(x) == snap_checked(16.0) && Some(y) == snap_checked(16.0)
            })
            .count();
        assert!(centres > 1, "{centres}");
    }
}
