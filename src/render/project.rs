//! From a triangle in object space to screen triangles: view transform, shading, clipping,
//! projection, and the quantization every drawing path shares.
//!
//! Corners leave here with their depth key rounded to an integer in `0..=65535` and their
//! shade rounded to a multiple of 1/255 (the rasteriser snaps positions to 1/16 pixel itself).
//! That is exactly what a [`ListSlot`](super::ListSlot) can hold, so a triangle drawn straight
//! from the source and one kept in the frame's triangle list give the same pixels.

use glam::Vec3;

use super::clip::{self, ClipVertex, Frustum};
use super::fixed::{
    exact_fixed, f32_of, fixed_of, level_of_shade, shade_of_level, FixedView, GridReading,
};
use super::raster::ScreenVertex;
use super::{Shading, Style};
use crate::bound::BoundingSphere;
use crate::math::{max, normalize, HARD_FLOAT, INTEGER_FORMS};
use crate::sink::{Vertex, NO_KEY};
use crate::tessellator::Hierarchy;
use crate::view::{Camera, Projection};
use crate::Arithmetic;

/// Per-frame constants.
pub(super) struct Setup<'a> {
    pub camera: &'a Camera,
    pub style: &'a Style,
    frustum: Frustum,
    /// `key = offset + scale * q`, with `q = 1/z` (perspective) or `z` (orthographic); `None`
    /// when there is nothing to draw.
    pub depth: Option<(f32, f32)>,
    light: Vec3,
    /// The light's direction in model coordinates, and the eye (perspective) or the view
    /// direction turned back (orthographic): a vertex's shade from its model normal, with no
    /// normal moved into view coordinates (see [`corner`](Self::corner)).
    model_light: Vec3,
    towards_eye: Vec3,
    perspective: bool,
    /// The view in integers, where the arithmetic is [`Arithmetic::Integer`] and the frame
    /// allows it (see `fixed`).
    fixed: Option<FixedView>,
    /// The source's hierarchy, where the view in integers reads its vertices from its bytes
    /// (see [`keyed_corner`](Self::keyed_corner)).
    coded: Option<(&'a Hierarchy<'a>, GridReading)>,
}

impl<'a> Setup<'a> {
    /// The constants of a frame of `camera` drawing a source within `bound` (its hierarchy
    /// `hierarchy`, where it has one) in `style` with `arithmetic`. (Out of line: inlined,
    /// its temporaries take room in the renderer's frame, on a firmware's deepest stack.)
    #[inline(never)]
    pub fn new(
        camera: &'a Camera,
        bound: Option<BoundingSphere>,
        style: &'a Style,
        arithmetic: Arithmetic,
        hierarchy: Option<&'a Hierarchy<'a>>,
    ) -> Self {
        let perspective = matches!(camera.projection(), Projection::Perspective { .. });
        let near = camera.near();
        let range = bound.map(|s| {
            let zc = camera.to_view(s.center).z;
            let zn = max(zc - s.radius, near);
            (zc, zn, max(zc + s.radius, zn))
        });
        let depth = range.and_then(|(zc, zn, zf)| {
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
        let fixed = match (arithmetic, &bound, range) {
            (Arithmetic::Integer, Some(sphere), Some((_, zn, zf))) if depth.is_some() => {
                FixedView::new(camera, sphere, light, style.light.ambient)
                    .map(|f| f.with_depth(zn, zf))
            }
            _ => None,
        };
        // (A bare-metal part with an FPU leaves the code out: see `math::INTEGER_FORMS`.)
        let coded = fixed.as_ref().zip(hierarchy).filter(|_| INTEGER_FORMS);
        let coded = coded.and_then(|(f, h)| {
            let grid = h.grid()?;
            Some((h, f.grid_reading(grid.min, grid.step)?))
        });
        Setup {
            camera,
            style,
            frustum: Frustum::new(near, camera.half_extent(), perspective),
            depth,
            light,
            model_light: camera.rotate_from_view(light),
            towards_eye: if perspective {
                camera.eye()
            } else {
                -camera.forward()
            },
            perspective,
            fixed,
            coded,
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

    /// Shade of a vertex with model normal `n` at model position `p`, for Gouraud shading: as
    /// [`shade`](Self::shade) in view coordinates (a rotation keeps dot products), without
    /// moving the normal there. A unit normal (as a tessellator's vertices have: within a few
    /// `ε` of 1) is taken as it is; another is normalised first, and zero gives the ambient.
    fn vertex_shade(&self, n: Vec3, p: Vec3) -> f32 {
        let length2 = n.dot(n);
        let n = if (length2 - 1.0).abs() <= 1.0 / 1024.0 {
            n
        } else {
            match normalize(n) {
                Some(n) => n,
                None => return self.style.light.ambient,
            }
        };
        let towards_eye = if self.perspective {
            self.towards_eye - p
        } else {
            self.towards_eye
        };
        let d = n.dot(self.model_light);
        let d = if n.dot(towards_eye) < 0.0 { -d } else { d };
        let a = self.style.light.ambient;
        a + (1.0 - a) * max(d, 0.0)
    }

    /// A vertex in view space, with its shade for Gouraud shading: the part of projecting a
    /// triangle that depends on one corner alone, which a renderer may keep
    /// for the triangles that share the vertex.
    pub fn corner(&self, v: &Vertex) -> ClipVertex {
        if let Some(c) = self.fixed.as_ref().and_then(|f| self.fixed_corner(f, v)) {
            return c;
        }
        let p = Vec3::from_array(v.position);
        let view = self.camera.to_view(p);
        let shade = match self.style.shading {
            Shading::Gouraud => self.vertex_shade(Vec3::from_array(v.normal), p),
            Shading::Flat => 0.0,
        };
        ClipVertex { view, shade }
    }

    /// [`corner`](Self::corner) of vertex `key` of a keyed triangle, its corner `i`: where
    /// the view is in integers and the key is a vertex of the source's hierarchy, read from
    /// the hierarchy's bytes (its grid point and normal code, see `fixed`), else from
    /// `corner(i)`. (Where `f32` is software, that spares the vertex's decoding into `f32`
    /// and its reading back into integers.)
    #[inline]
    pub fn keyed_corner(
        &self,
        key: u64,
        i: usize,
        corner: &mut dyn FnMut(usize) -> Vertex,
    ) -> ClipVertex {
        if INTEGER_FORMS {
            if let Some(c) = self.coded_corner(key) {
                return c;
            }
        }
        self.corner(&corner(i))
    }

    /// [`keyed_corner`](Self::keyed_corner) from the hierarchy's bytes, where it can be.
    /// (Out of line: inlined in the renderer's sinks, its frame would add to a firmware's
    /// deepest stack.)
    #[inline(never)]
    fn coded_corner(&self, key: u64) -> Option<ClipVertex> {
        let (f, (tree, grid)) = self.fixed.as_ref().zip(self.coded.as_ref())?;
        let v = usize::try_from(key).ok()?;
        let gouraud = self.style.shading == Shading::Gouraud;
        let c = f.grid_corner(grid, tree.grid_point(v)?, tree.normal_code(v)?, gouraud)?;
        let shade = c.level.map_or(0.0, shade_of_level);
        Some(Self::clip_vertex(f, c.view, shade))
    }

    /// [`corner`](Self::corner) in integers (see `fixed`): the view position as the exact
    /// `f32` of its integers, the shade as that of its level. `None` where the view in
    /// integers does not take the vertex.
    fn fixed_corner(&self, f: &FixedView, v: &Vertex) -> Option<ClipVertex> {
        let c = f.corner(v.position, v.normal)?;
        let shade = match (self.style.shading, c.level) {
            (Shading::Flat, _) => 0.0,
            (Shading::Gouraud, Some(level)) => shade_of_level(level),
            (Shading::Gouraud, None) => {
                self.vertex_shade(Vec3::from_array(v.normal), Vec3::from_array(v.position))
            }
        };
        Some(Self::clip_vertex(f, c.view, shade))
    }

    /// A corner at view position `view` (in `f`'s units) with shade `shade`.
    #[inline(always)]
    fn clip_vertex(f: &FixedView, view: [i32; 3], shade: f32) -> ClipVertex {
        let m = f.units();
        ClipVertex {
            view: Vec3::new(f32_of(view[0], m), f32_of(view[1], m), f32_of(view[2], m)),
            shade,
        }
    }

    /// `v` in the view units of `f`, where they hold it.
    fn fixed_view(f: &FixedView, v: Vec3) -> Option<[i32; 3]> {
        let m = f.units();
        Some([fixed_of(v.x, m)?, fixed_of(v.y, m)?, fixed_of(v.z, m)?])
    }

    /// Whether `v` lies inside every clip plane ([`Frustum::contains`](clip::Frustum); in
    /// integers, within their roundings, where the view is).
    pub fn inside(&self, v: &ClipVertex) -> bool {
        match &self.fixed {
            Some(f) => Self::fixed_view(f, v.view).is_some_and(|x| f.inside(x)),
            None => self.frustum.contains(v.view),
        }
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
        if let Some(shade) = self.flat_shade(&t) {
            for c in &mut t {
                c.shade = shade;
            }
        }
        let wire = self.style.wireframe.is_some();
        if inside {
            // Most triangles: nothing to clip.
            out(t.each_ref().map(|c| self.screen(c)), [wire; 3]);
            return;
        }
        let poly = self.frustum.clip(t, [wire; 3]);
        // Project only the polygon's corners (usually 3 of the 8 slots).
        let n = poly.len;
        let mut screen = [ScreenVertex::default(); clip::MAX_CORNERS];
        for (s, c) in screen.iter_mut().zip(&poly.corners[..n]) {
            *s = self.screen(c);
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

    /// The shade of triangle `t` with flat shading (its corners' then all take it), `None`
    /// with Gouraud shading (each corner keeps its own).
    #[inline]
    pub fn flat_shade(&self, t: &[ClipVertex; 3]) -> Option<f32> {
        (self.style.shading == Shading::Flat).then(|| {
            let [a, b, c] = t.each_ref().map(|c| c.view);
            self.shade((b - a).cross(c - a), (a + b + c) / 3.0)
        })
    }

    /// A corner inside the clip planes on screen: pixel position, depth key and shade, the
    /// last two quantized (see the module docs).
    #[inline]
    pub fn screen(&self, c: &ClipVertex) -> ScreenVertex {
        if let Some(f) = &self.fixed {
            let v = Self::fixed_view(f, c.view);
            let xy = v.and_then(|v| f.pixel(v)).map_or_else(
                || self.camera.view_to_pixel(c.view),
                |p| p.map(|x| f32_of(x, 4)),
            );
            // (The float path's key where the view does not read it in integers.)
            let depth = v.and_then(|v| f.depth_key(v[2]));
            return ScreenVertex {
                xy,
                depth: depth.map_or_else(|| self.depth_key(c.view.z), depth_from_u16),
                shade: shade_of_level(level_of_shade(c.shade)),
            };
        }
        ScreenVertex {
            xy: self.camera.view_to_pixel(c.view),
            depth: self.depth_key(c.view.z),
            shade: quantize_shade(c.shade),
        }
    }
}

/// Entries of a [`CornerCache`]: enough for the corners a tessellator's patch shares between
/// its triangles as it streams them. Even, and at most 64: [`CachedCorners::replaced`] has a
/// bit per entry, `CornerCache::recent` one per pair.
pub(super) const CORNER_CACHE: usize = 64;
const _: () = assert!(CORNER_CACHE <= 64 && CORNER_CACHE.is_multiple_of(2));

/// Keyed corners already taken to view space ([`Setup::corner`]) and tested against the clip
/// planes ([`Setup::inside`]): a sink that gets
/// [`keyed_triangle`](crate::TriangleSink::keyed_triangle)s asks a corner's vertex (an
/// evaluation, for a tessellator) and transforms it only when the cache does not have it.
///
/// Two-way: a key's hash names a pair of entries, and a new corner replaces the one of the pair
/// used less recently (a direct-mapped cache of the same size transforms the colliding
/// corners again).
pub(super) struct CornerCache {
    entries: [(u64, ClipVertex); CORNER_CACHE],
    /// Whether each entry's corner is inside (apart: a flag beside a `u64` would pad each
    /// entry by 8 bytes).
    inside: [bool; CORNER_CACHE],
    /// Bit `k`: entry `2k + 1` of pair `k` was used after entry `2k`.
    recent: u64,
}

impl CornerCache {
    #[inline(always)]
    pub fn new() -> Self {
        CornerCache {
            entries: [(NO_KEY, ClipVertex::default()); CORNER_CACHE],
            inside: [false; CORNER_CACHE],
            recent: 0,
        }
    }

    /// The corners named `keys`, from the cache or through `corner` and `setup`, and whether
    /// all three are inside the clip planes.
    #[inline]
    pub fn corners(
        &mut self,
        setup: &Setup<'_>,
        keys: [u64; 3],
        corner: &mut dyn FnMut(usize) -> Vertex,
    ) -> ([ClipVertex; 3], bool) {
        let found = self.corners_in_entries(setup, keys, corner);
        (found.corners, found.inside)
    }

    /// As [`corners`](Self::corners), with the entries that hold them: what lets a sink keep
    /// more of each corner beside the cache.
    pub fn corners_in_entries(
        &mut self,
        setup: &Setup<'_>,
        keys: [u64; 3],
        corner: &mut dyn FnMut(usize) -> Vertex,
    ) -> CachedCorners {
        let mut inside = true;
        let mut entries = [0u8; 3];
        let mut replaced = 0u64;
        let corners = core::array::from_fn(|i| {
            let key = keys[i];
            let pair = pair_of(key);
            let first = 2 * pair;
            // (A stray key equal to `NO_KEY` is only computed again.)
            let known = key != NO_KEY;
            let slot = if known && self.entries[first].0 == key {
                first
            } else if known && self.entries[first + 1].0 == key {
                first + 1
            } else {
                // The entry of the pair used less recently.
                let slot = first + 1 - (self.recent >> pair & 1) as usize;
                let c = setup.keyed_corner(key, i, corner);
                self.entries[slot] = (key, c);
                self.inside[slot] = setup.inside(&c);
                replaced |= 1 << slot;
                slot
            };
            let bit = 1u64 << pair;
            self.recent = (self.recent & !bit) | ((slot - first) as u64) << pair;
            inside &= self.inside[slot];
            entries[i] = slot as u8;
            self.entries[slot].1
        });
        CachedCorners {
            corners,
            inside,
            entries,
            replaced,
        }
    }
}

/// The pair of [`CornerCache`] entries that may hold the corner named `key`: the key's 64 bits
/// folded, then a multiplicative hash's top bits.
fn pair_of(key: u64) -> usize {
    let folded = (key ^ (key >> 29) ^ (key >> 47)) as u32;
    let hash = folded.wrapping_mul(0x9e37_79b1) as u64;
    ((hash * (CORNER_CACHE / 2) as u64) >> 32) as usize
}

/// A triangle's corners as [`CornerCache::corners_in_entries`] finds them.
pub(super) struct CachedCorners {
    /// The corners in view space.
    pub corners: [ClipVertex; 3],
    /// Whether all three are inside the clip planes.
    pub inside: bool,
    /// The cache entry of each (below [`CORNER_CACHE`]).
    pub entries: [u8; 3],
    /// Bit `e` set: entry `e` now holds another corner than before the call.
    pub replaced: u64,
}

/// A depth key rounded to the nearest integer in `0..=65535` (NaN gives 0).
pub(super) fn quantize_depth(key: f32) -> f32 {
    depth_from_u16(depth_to_u16(key))
}

/// The integer key of [`quantize_depth`].
pub(super) fn depth_to_u16(key: f32) -> u16 {
    // Where `f32` is software, a key that is an integer already (as every quantised one is)
    // is read from its bits: the same value.
    if !HARD_FLOAT {
        if let Some(k) = exact_fixed(key, 0) {
            return k.clamp(0, 65535) as u16;
        }
    }
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

/// The level of a quantised shade (one [`quantize_shade`] gives, or the integer path's, see
/// `fixed`): [`shade_to_u8`], read from its bits where `f32` is software (the same level for
/// every such shade).
pub(super) fn quantized_level(shade: f32) -> u8 {
    match HARD_FLOAT {
        true => shade_to_u8(shade),
        false => level_of_shade(shade),
    }
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
pub(super) mod tests {
    use super::*;

    /// A 32x32 orthographic view and the default style.
    pub fn view() -> (Camera, Style) {
        let camera = Camera::new(
            Vec3::new(0.0, 0.0, 4.0),
            Vec3::ZERO,
            Vec3::Y,
            Projection::Orthographic { height: 4.0 },
            0.1,
            [32, 32],
        )
        .unwrap();
        (camera, Style::default())
    }

    #[test]
    fn the_corner_cache_keeps_two_corners_per_pair_and_replaces_the_older() {
        let (camera, style) = view();
        let setup = Setup::new(&camera, None, &style, Arithmetic::Float, None);
        // Three keys of one pair, and one of another.
        let pair = pair_of(1);
        let mut same = (2..).filter(|&k| pair_of(k) == pair);
        let [a, b, c] = [1, same.next().unwrap(), same.next().unwrap()];
        let other = (2..).find(|&k| pair_of(k) != pair).unwrap();
        let mut cache = CornerCache::new();
        // Each key's corner sits at x = key, so a wrong entry shows.
        let ask = |cache: &mut CornerCache, keys: [u64; 3]| {
            let mut evaluated = [false; 3];
            let found = cache.corners_in_entries(&setup, keys, &mut |i| {
                evaluated[i] = true;
                Vertex {
                    position: [keys[i] as f32, 0.0, 0.0],
                    ..Vertex::default()
                }
            });
            for (c, &k) in found.corners.iter().zip(&keys) {
                assert_eq!(camera.to_view(Vec3::new(k as f32, 0.0, 0.0)), c.view);
            }
            let entries = found.entries.map(|e| e as usize);
            (evaluated, entries, found.replaced)
        };
        // `a` and `b` take both entries of the pair (one triangle: no entry twice).
        let (evaluated, entries, replaced) = ask(&mut cache, [a, b, other]);
        assert_eq!(evaluated, [true; 3]);
        assert_eq!(entries[0] / 2, pair);
        assert_eq!(entries[1] / 2, pair);
        assert_ne!(entries[0], entries[1]);
        assert_eq!(replaced.count_ones(), 3);
        let (ea, eb) = (entries[0], entries[1]);
        // Both are kept; `a` is now the more recent.
        let (evaluated, entries, replaced) = ask(&mut cache, [b, a, other]);
        assert_eq!(
            (evaluated, entries, replaced),
            ([false; 3], [eb, ea, entries[2]], 0)
        );
        // `c` replaces `b`, the less recently used, and `a` stays.
        let (evaluated, entries, replaced) = ask(&mut cache, [c, a, other]);
        assert_eq!(evaluated, [true, false, false]);
        assert_eq!([entries[0], entries[1]], [eb, ea]);
        assert_eq!(replaced, 1 << eb);
        // `b` comes back in place of `c`, `a` being the more recent.
        let (evaluated, entries, replaced) = ask(&mut cache, [a, b, other]);
        assert_eq!(evaluated, [false, true, false]);
        assert_eq!([entries[0], entries[1]], [ea, eb]);
        assert_eq!(replaced, 1 << eb);
    }

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
