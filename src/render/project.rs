//! From a triangle in object space to screen triangles: view transform, shading, clipping,
//! projection, and the quantization every drawing path shares.
//!
//! Corners leave here with their depth key rounded to an integer in `0..=65535` and their
//! shade rounded to a multiple of 1/255 (the rasteriser snaps positions to 1/16 pixel itself).
//! That is exactly what a [`ListSlot`](super::ListSlot) can hold, so a triangle drawn straight
//! from the source and one kept in the frame's triangle list give the same pixels.

use glam::Vec3;

use super::clip::{self, ClipVertex, Frustum};
use super::raster::ScreenVertex;
use super::{Shading, Style};
use crate::bound::BoundingSphere;
use crate::math::{max, normalize};
use crate::sink::{Vertex, NO_KEY};
use crate::view::{Camera, Projection};

/// Per-frame constants.
pub(super) struct Setup<'a> {
    pub camera: &'a Camera,
    pub style: &'a Style,
    frustum: Frustum,
    /// `key = offset + scale * q`, with `q = 1/z` (perspective) or `z` (orthographic); `None`
    /// when there is nothing to draw.
    pub depth: Option<(f32, f32)>,
    light: Vec3,
    perspective: bool,
}

impl<'a> Setup<'a> {
    pub fn new(camera: &'a Camera, bound: Option<BoundingSphere>, style: &'a Style) -> Self {
        let perspective = matches!(camera.projection(), Projection::Perspective { .. });
        let near = camera.near();
        let depth = bound.and_then(|s| {
            let zc = camera.to_view(s.center).z;
            let zn = max(zc - s.radius, near);
            let zf = max(zc + s.radius, zn);
            let (qn, qf) = if perspective {
                (1.0 / zn, 1.0 / zf)
            } else {
                (zn, zf)
            };
            // Keys 1 (far) to 65535 (near); 0 is an empty pixel.
            let scale = if qn != qf { 65534.0 / (qn - qf) } else { 0.0 };
            let ok = scale.is_finite() && zc.is_finite();
            ok.then_some((1.0 - qf * scale, scale))
        });
        let light = normalize(Vec3::from_array(style.light.direction)).unwrap_or(-Vec3::Z);
        Setup {
            camera,
            style,
            frustum: Frustum::new(near, camera.half_extent(), perspective),
            depth,
            light,
            perspective,
        }
    }

    /// Shade of a surface with view-space normal `n` (any length) seen at view position `at`.
    fn shade(&self, n: Vec3, at: Vec3) -> f32 {
        let Some(n) = normalize(n) else {
            return self.style.light.ambient;
        };
        let towards_eye = if self.perspective { -at } else { -Vec3::Z };
        let n = if n.dot(towards_eye) < 0.0 { -n } else { n };
        let a = self.style.light.ambient;
        a + (1.0 - a) * max(n.dot(self.light), 0.0)
    }

    /// Depth key at view depth `z`, rounded (see the module docs).
    fn depth_key(&self, z: f32) -> f32 {
        let (offset, scale) = self.depth.unwrap_or((0.0, 0.0));
        let q = if self.perspective { 1.0 / z } else { z };
        quantize_depth(offset + scale * q)
    }

    /// A vertex in view space, with its shade for Gouraud shading: the part of projecting a
    /// triangle that depends on one corner alone, which a renderer may keep
    /// for the triangles that share the vertex.
    pub fn corner(&self, v: &Vertex) -> ClipVertex {
        let camera = self.camera;
        let view = camera.to_view(Vec3::from_array(v.position));
        let shade = match self.style.shading {
            Shading::Gouraud => {
                let n = camera.rotate_to_view(Vec3::from_array(v.normal));
                self.shade(n, view)
            }
            Shading::Flat => 0.0,
        };
        ClipVertex { view, shade }
    }

    /// Whether `v` lies inside every clip plane ([`Frustum::contains`](clip::Frustum)).
    pub fn inside(&self, v: &ClipVertex) -> bool {
        self.frustum.contains(v.view)
    }

    /// A triangle's [`corner`](Self::corner)s, and whether all three are
    /// [`inside`](Self::inside): what [`project`](Self::project) takes.
    pub fn corners(&self, corners: [&Vertex; 3]) -> ([ClipVertex; 3], bool) {
        let corners = corners.map(|c| self.corner(c));
        let inside = corners.iter().all(|c| self.inside(c));
        (corners, inside)
    }

    /// Hands `out` the screen triangles of a triangle, its corners as
    /// [`corner`](Self::corner) gives them, after clipping (none, one, or a fan), with the
    /// edges to draw as wireframe (`wire[i]` for the edge opposite corner `i`). `inside` tells
    /// whether every corner is [`inside`](Self::inside) (then nothing is clipped).
    pub fn project(
        &self,
        mut t: [ClipVertex; 3],
        inside: bool,
        mut out: impl FnMut([ScreenVertex; 3], [bool; 3]),
    ) {
        let camera = self.camera;
        if self.style.shading == Shading::Flat {
            let [a, b, c] = t.map(|c| c.view);
            let shade = self.shade((b - a).cross(c - a), (a + b + c) / 3.0);
            for c in &mut t {
                c.shade = shade;
            }
        }
        let wire = self.style.wireframe.is_some();
        let screen_of = |c: &ClipVertex| ScreenVertex {
            xy: camera.view_to_pixel(c.view),
            depth: self.depth_key(c.view.z),
            shade: quantize_shade(c.shade),
        };
        if inside {
            // Most triangles: nothing to clip.
            out(t.each_ref().map(screen_of), [wire; 3]);
            return;
        }
        let poly = self.frustum.clip(t, [wire; 3]);
        // Project only the polygon's corners (usually 3 of the 8 slots).
        let n = poly.len;
        let mut screen = [ScreenVertex::default(); clip::MAX_CORNERS];
        for (s, c) in screen.iter_mut().zip(&poly.corners[..n]) {
            *s = screen_of(c);
        }
        for k in 1..n.saturating_sub(1) {
            let edges = [
                poly.wire[k],
                k + 2 == n && poly.wire[n - 1],
                k == 1 && poly.wire[0],
            ];
            out([screen[0], screen[k], screen[k + 1]], edges);
        }
    }
}

/// Entries of a [`CornerCache`]: enough for the corners a tessellator's patch shares between
/// its triangles as it streams them.
const CORNER_CACHE: usize = 64;

/// Keyed corners already taken to view space ([`Setup::corner`]) and tested against the clip
/// planes ([`Setup::inside`]), direct-mapped: a sink that gets
/// [`keyed_triangle`](crate::TriangleSink::keyed_triangle)s asks a corner's vertex (an
/// evaluation, for a tessellator) and transforms it only when the cache does not have it.
pub(super) struct CornerCache {
    entries: [(u64, ClipVertex); CORNER_CACHE],
    /// Whether each entry's corner is inside (apart: a flag beside a `u64` would pad each
    /// entry by 8 bytes).
    inside: [bool; CORNER_CACHE],
}

impl CornerCache {
    #[inline(always)]
    pub fn new() -> Self {
        CornerCache {
            entries: [(NO_KEY, ClipVertex::default()); CORNER_CACHE],
            inside: [false; CORNER_CACHE],
        }
    }

    /// The corners named `keys`, from the cache or through `corner` and `setup`, and whether
    /// all three are inside the clip planes.
    pub fn corners(
        &mut self,
        setup: &Setup<'_>,
        keys: [u64; 3],
        corner: &mut dyn FnMut(usize) -> Vertex,
    ) -> ([ClipVertex; 3], bool) {
        let mut inside = true;
        let corners = core::array::from_fn(|i| {
            let key = keys[i];
            // Fold the key's 64 bits, then a multiplicative hash's top bits.
            let folded = (key ^ (key >> 29) ^ (key >> 47)) as u32;
            let hash = folded.wrapping_mul(0x9e37_79b1) as u64;
            let slot = ((hash * CORNER_CACHE as u64) >> 32) as usize;
            let entry = &mut self.entries[slot];
            // (A stray key equal to `NO_KEY` is only computed again.)
            if entry.0 != key || key == NO_KEY {
                let c = setup.corner(&corner(i));
                *entry = (key, c);
                self.inside[slot] = setup.inside(&c);
            }
            inside &= self.inside[slot];
            entry.1
        });
        (corners, inside)
    }
}

/// A depth key rounded to the nearest integer in `0..=65535` (NaN gives 0).
pub(super) fn quantize_depth(key: f32) -> f32 {
    depth_from_u16(depth_to_u16(key))
}

/// The integer key of [`quantize_depth`].
pub(super) fn depth_to_u16(key: f32) -> u16 {
    // `as` saturates and maps NaN to 0.
    (key + 0.5) as u16
}

/// A key as `f32`.
pub(super) fn depth_from_u16(key: u16) -> f32 {
    key as f32
}

/// A shade clamped to `[0, 1]` and rounded to a multiple of 1/255.
pub(super) fn quantize_shade(shade: f32) -> f32 {
    shade_from_u8(shade_to_u8(shade))
}

/// The level of [`quantize_shade`], `0..=255`.
pub(super) fn shade_to_u8(shade: f32) -> u8 {
    // At most 255: the narrowing is exact.
    shade_level(shade) as u8
}

/// [`shade_to_u8`] as a `u32` (a palette index, with no narrowing to pay per pixel).
pub(super) fn shade_level(shade: f32) -> u32 {
    (shade.clamp(0.0, 1.0) * 255.0 + 0.5) as u32
}

/// A level as a shade in `[0, 1]`.
pub(super) fn shade_from_u8(level: u8) -> f32 {
    level as f32 * (1.0 / 255.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantized_values_round_trip() {
        for key in [
            0.0, 0.49, 0.5, 1.0, 1234.4, 1234.6, 65534.6, 65535.0, 7.0e4, -3.0,
        ] {
            let q = quantize_depth(key);
            assert_eq!(depth_from_u16(depth_to_u16(q)), q, "{key}");
            assert!(
                q == 0.0 || q == 65535.0 || (q - key).abs() <= 0.5,
                "{key} -> {q}"
            );
        }
        assert_eq!(quantize_depth(f32::NAN), 0.0);
        for s in [0.0, 0.001, 0.2, 0.5, 0.999, 1.0, 1.5, -0.5] {
            let q = quantize_shade(s);
            assert_eq!(shade_from_u8(shade_to_u8(q)), q, "{s}");
            assert!(
                (q - s.clamp(0.0, 1.0)).abs() <= 0.5 / 255.0 + 1e-7,
                "{s} -> {q}"
            );
        }
    }
}
