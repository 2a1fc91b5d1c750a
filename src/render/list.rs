//! The frame's triangle list: every screen triangle of a frame, projected once and packed in
//! 22 bytes, so that the bands rasterise from it instead of asking the source again.

use super::clip::ClipVertex;
use super::project::{
    depth_from_u16, depth_to_u16, shade_from_u8, shade_to_u8, CornerCache, Setup,
};
use super::raster::{snap_checked, ScreenVertex, Triangle, HALF, SUBPIXELS};
use crate::sink::{TriangleSink, Vertex};

/// A triangle after projection, as the frame's triangle list keeps it: corners at 1/16 pixel
/// in `i16`, depth keys in `u16`, shades in `u8` and the wireframe edges in one byte (22
/// bytes). See [`Renderer::with_triangle_list`](super::Renderer::with_triangle_list).
///
/// Its contents are private; `Default` gives an empty slot to build the caller's buffer from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ScreenTriangle {
    x: [i16; 3],
    y: [i16; 3],
    depth: [u16; 3],
    shade: [u8; 3],
    wire: u8,
}

impl ScreenTriangle {
    /// Packs a projected triangle; `None` when a corner does not fit the 1/16-pixel `i16`
    /// range (beyond about ±2,047 pixels) or is not finite.
    pub(super) fn pack(v: &[ScreenVertex; 3], wire: [bool; 3]) -> Option<ScreenTriangle> {
        let fit = |c: f32| {
            let s = snap_checked(c)?;
            i16::try_from(s).ok()
        };
        let mut t = ScreenTriangle::default();
        for i in 0..3 {
            t.x[i] = fit(v[i].xy[0])?;
            t.y[i] = fit(v[i].xy[1])?;
            t.depth[i] = depth_to_u16(v[i].depth);
            t.shade[i] = shade_to_u8(v[i].shade);
            t.wire |= (wire[i] as u8) << i;
        }
        Some(t)
    }

    /// The corners and wireframe edges as they were packed (positions on the 1/16-pixel
    /// grid, depth and shade as [`project`](super::project) rounds them).
    #[cfg(test)]
    pub(super) fn unpack(&self) -> ([ScreenVertex; 3], [bool; 3]) {
        let sub = 1.0 / SUBPIXELS as f32;
        let v = [0, 1, 2].map(|i| ScreenVertex {
            xy: [self.x[i] as f32 * sub, self.y[i] as f32 * sub],
            depth: depth_from_u16(self.depth[i]),
            shade: shade_from_u8(self.shade[i]),
        });
        (v, [0, 1, 2].map(|i| self.wire & (1 << i) != 0))
    }

    /// The triangle ready for scan conversion (as [`Triangle::new`] sets up the unpacked
    /// corners); `None` when it has no area.
    pub(super) fn triangle(&self) -> Option<Triangle> {
        let wide = |c: [i16; 3]| c.map(i64::from);
        Triangle::from_snapped(
            wide(self.x),
            wide(self.y),
            self.depth.map(depth_from_u16),
            self.shade.map(shade_from_u8),
            [0, 1, 2].map(|i| self.wire & (1 << i) != 0),
        )
    }

    /// Whether it may cover a pixel centre of the rows `rows` stands for.
    pub(super) fn meets(&self, rows: &SubpixelRows) -> bool {
        let [a, b, c] = self.y;
        a.min(b).min(c) as i32 <= rows.top_max && a.max(b).max(c) as i32 >= rows.bottom_min
    }
}

/// Pixel rows `first..end` as limits on a triangle's highest and lowest corner, in
/// subpixels: a triangle covers no centre of those rows when its top lies below the last
/// row's centre or its bottom above the first row's centre.
pub(super) struct SubpixelRows {
    top_max: i32,
    bottom_min: i32,
}

impl SubpixelRows {
    pub fn new(rows: &core::ops::Range<i32>) -> Self {
        let (sub, half) = (SUBPIXELS as i32, HALF as i32);
        SubpixelRows {
            top_max: (rows.end - 1).saturating_mul(sub).saturating_add(half),
            bottom_min: rows.start.saturating_mul(sub).saturating_add(half),
        }
    }
}

/// The sink that fills the list from one pass over the source.
///
/// When a triangle does not fit (the list is full, or a corner is out of `i16`), the list keeps
/// the patches before that triangle's patch and the frame resumes there: each band draws the
/// list, then streams the patches from `resume` on. That needs the source to hand patches in
/// increasing order (a [`Tessellator`](crate::Tessellator) does); when it does not, the list is
/// given up (`overflow`) and every band streams the whole frame.
pub(super) struct ListSink<'a, 'b, 'c> {
    pub setup: &'a Setup<'a>,
    pub list: &'b mut [ScreenTriangle],
    pub len: usize,
    /// Triangles handed over by the source.
    pub handed: u32,
    /// The patch of the last triangle, and where its triangles start in the list.
    current: Option<(u32, usize)>,
    /// Whether the patches came in increasing order so far.
    increasing: bool,
    /// The first patch the list does not hold.
    pub resume: Option<u32>,
    /// Set when the list is given up.
    pub overflow: bool,
    /// Corners in view space by key.
    corners: &'c mut CornerCache,
}

impl<'a, 'b, 'c> ListSink<'a, 'b, 'c> {
    pub fn new(
        setup: &'a Setup<'a>,
        list: &'b mut [ScreenTriangle],
        corners: &'c mut CornerCache,
    ) -> Self {
        ListSink {
            setup,
            list,
            len: 0,
            handed: 0,
            current: None,
            increasing: true,
            resume: None,
            overflow: false,
            corners,
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

    /// Whether the list is neither given up nor cut at a patch.
    fn open(&self) -> bool {
        !self.overflow && self.resume.is_none()
    }

    /// Lists one admitted triangle, its corners in view space (`inside`: all inside the clip
    /// planes).
    fn take(&mut self, patch: u32, corners: [ClipVertex; 3], inside: bool) {
        match self.current {
            Some((p, _)) if p == patch => {}
            Some((p, _)) if p > patch => {
                self.increasing = false;
                self.current = Some((patch, self.len));
            }
            _ => self.current = Some((patch, self.len)),
        }
        let mut fits = true;
        self.setup.project(corners, inside, |v, wire| {
            match (ScreenTriangle::pack(&v, wire), self.list.get_mut(self.len)) {
                (Some(t), Some(slot)) if fits => {
                    *slot = t;
                    self.len += 1;
                }
                _ => fits = false,
            }
        });
        if !fits {
            match self.current {
                Some((p, start)) if self.increasing => {
                    self.len = start;
                    self.resume = Some(p);
                }
                _ => self.overflow = true,
            }
        }
    }
}

impl TriangleSink for ListSink<'_, '_, '_> {
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
        let (corners, inside) = self.corners.corners(self.setup, keys, corner);
        self.take(patch, corners, inside);
    }

    fn wants_patch(&self, _patch: u32) -> bool {
        self.open()
    }
}

/// Passes on the triangles of the patches from `first` on (those a partial list does not
/// hold).
pub(super) struct Remaining<'s, S> {
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
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_packed_triangle_is_22_bytes() {
        assert_eq!(core::mem::size_of::<ScreenTriangle>(), 22);
    }

    #[test]
    fn packing_keeps_the_snapped_corners_and_rows() {
        let v = |x: f32, y: f32| ScreenVertex {
            xy: [x, y],
            depth: 300.0,
            shade: super::super::project::quantize_shade(0.2),
        };
        let corners = [v(0.5, 0.49), v(10.25, 3.0), v(-4.0, 20.97)];
        let t = ScreenTriangle::pack(&corners, [true, false, true]).unwrap();
        let (back, wire) = t.unpack();
        assert_eq!(wire, [true, false, true]);
        for (a, b) in corners.iter().zip(&back) {
            assert_eq!(snap_checked(a.xy[0]), snap_checked(b.xy[0]));
            assert_eq!(snap_checked(a.xy[1]), snap_checked(b.xy[1]));
            assert_eq!((a.depth, a.shade), (b.depth, b.shade));
        }
        let tri = Triangle::new(back, wire).unwrap();
        let [first, last] = tri.rows();
        for r in first - 3..=last + 3 {
            let inside = (first..=last).contains(&r);
            assert_eq!(t.meets(&SubpixelRows::new(&(r..r + 1))), inside, "row {r}");
            for end in r + 1..r + 4 {
                let meets = first < end && last >= r;
                assert_eq!(
                    t.meets(&SubpixelRows::new(&(r..end))),
                    meets,
                    "rows {r}..{end}"
                );
            }
        }
        let direct = t.triangle().unwrap();
        assert_eq!(direct.rows(), tri.rows());
        for r in first..=last {
            assert_eq!(direct.span(r, -50..50), tri.span(r, -50..50));
        }
        assert!(
            ScreenTriangle::pack(&[v(0.0, 0.0), v(2100.0, 0.0), v(0.0, 1.0)], [false; 3]).is_none()
        );
        assert!(
            ScreenTriangle::pack(&[v(0.0, 0.0), v(f32::NAN, 0.0), v(0.0, 1.0)], [false; 3])
                .is_none()
        );
    }
}
