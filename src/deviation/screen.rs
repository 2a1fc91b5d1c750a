//! The bound of a triangle's deviation *on screen*, from the directions of its lattice's
//! deviation vectors: a deviation along the line of sight moves no pixel, and the object-space
//! bound (the length of the worst vector, times the projection's largest scale) charges it in
//! full.
//!
//! # The bound
//!
//! Take the lattice of the module docs above: points `x_k` of step `1/6` on the domain
//! triangle `T`, `e_k = S(x_k) - L(x_k)`, and the remainder `R = ½ ρ² / 36`. On each of the 36
//! small triangles, `e = S - L` is the linear interpolant of three `e_k` plus at most `R`, so
//! everywhere on `T`
//!
//! `e(x) ∈ conv{e_k} + B(r)`, with `r = R + slack`
//!
//! (`slack` covers each computed `e_k`'s distance from the exact one, see
//! [`PatchBounds::slack`](super::PatchBounds::slack)), and `|e(x)| <= m = max_k |e_k| + r`.
//!
//! **Perspective.** In view coordinates (right, up, depth), with `f` the focal length in
//! pixels, the flat point `l = L(x)` and the surface point `s = l + e` land
//! `f |e_⊥ - τ e_z| / s_z` apart, where `τ = l_⊥ / l_z` is `l`'s view ray:
//! `s_⊥/s_z - l_⊥/l_z = (l_z e_⊥ - l_⊥ e_z) / (l_z s_z)`. A deviation counts where `s` is on
//! screen (in front of the near plane, within the side planes) and `l` in front of the near
//! plane, as the tolerance is defined. Then `l`, within `m` of `s`, lies in `F`: the flat
//! triangle clipped to the near plane and to the side planes moved out by `m`, a convex
//! polygon. So:
//!
//! - `s_z >= z_min = max(near, min_F l_z - m)` (`l_z` is linear, least at a vertex of `F`);
//! - `τ` lies in the convex hull of the rays `τ_i` of `F`'s vertices (the central projection
//!   maps segments in front of the eye to segments);
//! - `φ(τ, e) = |e_⊥ - τ e_z|` is convex in `e` for a fixed `τ` and in `τ` for a fixed `e`, so
//!   over `e ∈ conv{e_k} + B(r)` it is at most `max_k φ(τ, e_k) + r √(1 + |τ|²)` (the norm of
//!   `e ↦ e_⊥ - τ e_z`), and each term is largest at one of the `τ_i`.
//!
//! Hence every deviation of the triangle that counts is at most
//!
//! `f / z_min · max_i ( max_k φ(τ_i, e_k) + r √(1 + |τ_i|²) )` pixels,
//!
//! and 0 where `F` is empty. Since `φ(τ, e) <= |e| √(1 + |τ|²)`, it is never above the
//! isotropic form `f / z_min · m · max_i √(1 + |τ_i|²)`; where a surface faces the eye its
//! deviation runs along the rays and the directional form is far smaller.
//!
//! **Orthographic.** Every ray is the depth axis: `f (max_k |e_k⊥| + r)`, with `f` pixels per
//! object unit (nothing is clipped: a bound over the whole triangle covers what counts).
//!
//! **Rounding.** The flat triangle's corners in view coordinates are off the exact ones by at
//! most `η = slack + 16 ε Σ` (`Σ`: the largest `|x| + |y| + |z|` of the corners; the corner
//! points are within the slack, the move into view coordinates and each clipping
//! intersection within a few `ε Σ`). So `F` is taken with the near plane moved in by `η`
//! and the side planes out by `m + η`, `z_min` with `η` less, and each ray `τ_i` is widened by
//! `dτ = 2 η (1 + |τ_x| + |τ_y|) / (z_i - η)`, which moves `φ` by at most `m dτ` (its slope in
//! `τ` is `|e_z| <= m`). The rotation of each `e_k`, the cancellation in `e_⊥ - τ e_z` and the
//! ray's own two roundings (`v_⊥` times `1 / v_z`: `τ` within `2 ε |τ|`, which moves `φ` by
//! at most `2 ε m |τ|`) are covered by `16 ε m (1 + |τ_x| + |τ_y|)`, the few relative
//! roundings of the sums and the final scale by `2^-10`. (A node's kept vectors read in
//! integers cover their own roundings in `max_k φ`: see `vectors`.) A view whose near plane is
//! within `η` of the eye gives no bound (infinity): the isotropic one decides there.
//!
//! **The isotropic bound without the vectors.** Every vertex `v` of `F` has `v_z >= z_f =
//! max(min_corners z, near - η)` (clipping only cuts the flat triangle) and lies within the
//! side planes moved out by `w = m + η`: `|v_x| <= s_x v_z + w n_x`, so `|τ_x| <= T_x = s_x +
//! w n_x / z_f`, likewise `T_y`. With `φ(τ, e_k) <= |e_k| √(1 + |τ|²)`, `|e_k| <= big`,
//! `m = big + r` and `spread <= P = 1 + T_x + T_y`, each vertex's term is at most
//! `m (S + 2 η P / (z_f - η) + 16 ε P)` with `S = √(1 + T_x² + T_y²)`, and `z_min >=
//! max(near, z_f - m - η)`. Every depth divided by here, `z_f`, `z_f - η` and `z_min`, is at
//! least `z_ℓ = min(z_f - η, max(near, z_f - m - η))`, so with `a = w (n_x + n_y) / z_ℓ`:
//! `T_x + T_y <= s_x + s_y + a`, `P <= 1 + s_x + s_y + a`, and by the triangle inequality
//! `S = |(1, s_x, s_y) + (0, T_x - s_x, T_y - s_y)| <= √(1 + s_x² + s_y²) + a` (the first
//! term the camera's, found once). Each vertex's term is then at most
//! `m (√(1 + s_x² + s_y²) + a + 2 η (1 + s_x + s_y + a) / z_ℓ + 16 ε (1 + s_x + s_y + a))`,
//! and the bound at most `f / z_ℓ` times that: one division, every term a sum of
//! nonnegative ones, so its roundings are relative ones, which the screen's slack covers as
//! for the bound above. That is [`isotropic_bound_on_screen`], from the corners and `m`
//! alone: where it is already within a tolerance, the vectors need not be looked at. (Its
//! looseness over `S` and the three depths is `a`, about `m / z` of the view: a thousandth
//! of it at a pixel's tolerance on a screen a thousand pixels wide.)
//!
//! `host-tests/tests/screen_bound.rs` checks this bound against the deviation measured on
//! screen in `f64` by dense sampling and reports how tight it is.

use glam::Vec3;

use super::vectors::Deviations;
use super::EPS;
use crate::math::{larger, max, min, sqrt_one_plus_above};
use crate::view::{Camera, Projection};

/// Most vertices of a triangle clipped by five planes.
const CLIPPED: usize = 8;

/// Relative enlargement of the computed bound, for its own few roundings.
pub(crate) const SCREEN_SLACK: f32 = 1.0 + 1.0 / 1024.0;

/// A convex polygon in view coordinates, clipped one plane at a time.
struct Polygon {
    v: [Vec3; CLIPPED],
    n: usize,
}

/// A plane the polygon is clipped to, by its signed distance inside.
#[derive(Clone, Copy)]
enum ClipPlane {
    /// `p.z - near`.
    Near(f32),
    /// `w - (sign · p[axis] - slope · p.z) / norm` (axis 0: x, 1: y): within `w` of a side
    /// plane of the view.
    Side {
        axis: usize,
        sign: f32,
        slope: f32,
        norm: f32,
        w: f32,
    },
}

impl ClipPlane {
    fn inside(&self, p: Vec3) -> f32 {
        match *self {
            ClipPlane::Near(near) => p.z - near,
            ClipPlane::Side {
                axis,
                sign,
                slope,
                norm,
                w,
            } => w - (sign * p[axis] - slope * p.z) / norm,
        }
    }
}

impl Polygon {
    /// The part inside `plane` (Sutherland–Hodgman). One copy for every plane, rather than
    /// one per plane as a closure would make (flash).
    #[inline(never)]
    fn clip(&self, plane: ClipPlane) -> Polygon {
        let inside = |p: Vec3| plane.inside(p);
        let mut out = Polygon {
            v: [Vec3::ZERO; CLIPPED],
            n: 0,
        };
        let mut push = |p: Vec3| {
            if out.n < CLIPPED {
                out.v[out.n] = p;
                out.n += 1;
            }
        };
        for i in 0..self.n {
            let (a, b) = (self.v[i], self.v[(i + 1) % self.n]);
            let (da, db) = (inside(a), inside(b));
            if da >= 0.0 {
                push(a);
            }
            if (da >= 0.0) != (db >= 0.0) {
                let t = da / (da - db);
                push(a + (b - a) * t);
            }
        }
        out
    }
}

/// The bound on `camera`'s screen, in pixels, of a deviation `e(x) ∈ conv{e_k} + B(r)` over
/// the flat triangle `corners` (moved into view coordinates by `camera.to_view`; `size` at
/// least their [`view_extent`], which a caller finds once for every bound), with the
/// vectors `e_k` in view coordinates too (rotated, not moved), `big` at least their largest
/// length and `slack` the rounding slack of the corners (see the module docs). `e` may hold
/// any vectors whose hull, widened by `r`, holds the deviation: a lattice's in view
/// coordinates, or a bake's few kept ones as quantised (see `vectors`). Its roots are upper
/// bounds ([`sqrt_one_plus_above`](crate::math::sqrt_one_plus_above), and the vectors'
/// `sqrt_above`): the bound stays a bound.
///
/// Once the vertices of the clipped polygon taken so far put it above `stop`, it stops there
/// and returns that: a value above `stop` and at most the bound (the bound is the largest
/// term of all vertices at the least depth of all, and fewer vertices give a smaller or equal
/// term at a greater or equal depth, computed the same way: rounding keeps the order). With
/// `stop` infinite, the bound. `inside`: the caller knows that each corner lies inside every
/// plane as the test below finds it (see `tessellator::grid_judge`), which it then skips.
#[allow(clippy::too_many_arguments)]
pub(crate) fn bound_on_screen(
    camera: &Camera,
    corners: [Vec3; 3],
    size: f32,
    e: &impl Deviations,
    big: f32,
    r: f32,
    slack: f32,
    stop: f32,
    inside: bool,
) -> f32 {
    let m = big + r;
    let focal = camera.focal();
    if let Projection::Orthographic { .. } = camera.projection() {
        return focal * ((e.worst(camera, [0.0, 0.0]) + r) * SCREEN_SLACK + 16.0 * EPS * m);
    }
    let eta = slack + 16.0 * EPS * size;
    let near = camera.near() - eta;
    if near.is_nan() || near <= 0.0 || !m.is_finite() || !eta.is_finite() {
        return f32::INFINITY;
    }
    let ([sx, sy], [nx, ny]) = camera.side_planes();
    let w = m + eta;
    // A triangle inside every plane is its own clipped polygon (the common case: no copy,
    // nor a polygon to clear).
    // Tested without the clip's divisions (`nx`, `ny` > 0): where the two forms round apart,
    // a corner on a plane, the test may skip a clip that would move it by a rounding, which
    // only leaves the polygon a hair larger.
    let (wx, wy) = (w * nx, w * ny);
    let inside = inside
        || corners.iter().all(|&p| {
            p.z >= near
                && (-p.x - sx * p.z) <= wx
                && (p.x - sx * p.z) <= wx
                && (-p.y - sy * p.z) <= wy
                && (p.y - sy * p.z) <= wy
        });
    let clipped;
    let front: &[Vec3] = if inside {
        &corners
    } else {
        let side = |axis: usize, sign: f32| {
            let (slope, norm) = if axis == 0 { (sx, nx) } else { (sy, ny) };
            ClipPlane::Side {
                axis,
                sign,
                slope,
                norm,
                w,
            }
        };
        let mut polygon = Polygon {
            v: [Vec3::ZERO; CLIPPED],
            n: 3,
        };
        polygon.v[..3].copy_from_slice(&corners);
        for plane in [
            ClipPlane::Near(near),
            side(0, -1.0),
            side(0, 1.0),
            side(1, -1.0),
            side(1, 1.0),
        ] {
            polygon = polygon.clip(plane);
        }
        clipped = polygon;
        &clipped.v[..clipped.n]
    };
    if front.is_empty() {
        return 0.0;
    }
    let mut z_low = f32::INFINITY;
    let mut worst = 0.0f32;
    // Over `stop` yet? Asked without a division: `f S g > stop z_min` (a few roundings from
    // the quotient's test); the bound so far is then found and returned only where it is
    // over.
    let stops = stop < f32::INFINITY;
    let focal_slack = camera.focal() * SCREEN_SLACK;
    for &v in front {
        z_low = min(z_low, v.z);
        let z = v.z - eta;
        if z.is_nan() || z <= 0.0 {
            return f32::INFINITY;
        }
        // The ray through `v` by its depth's reciprocal (two roundings, see the module docs).
        let inverse = 1.0 / v.z;
        let (tx, ty) = (v.x * inverse, v.y * inverse);
        let spread = 1.0 + tx.abs() + ty.abs();
        let widen = 2.0 * eta * spread / z;
        let g = e.worst(camera, [tx, ty])
            + r * sqrt_one_plus_above(tx * tx + ty * ty)
            + m * (widen + 16.0 * EPS * spread);
        worst = larger(worst, g);
        if stops && focal_slack * worst > stop * least_depth(camera, z_low, m, eta) {
            let so_far = on_screen(camera, z_low, m, eta, worst);
            if so_far > stop {
                return so_far;
            }
        }
    }
    on_screen(camera, z_low, m, eta, worst)
}

/// The bound on screen of a deviation whose worst term over the triangle's corners is `g`
/// (the corners' nearest depth `z_low`, the deviation at most `m` long, the rounding `eta`):
/// `g` at the least depth the deviation can reach, `z_low - m - eta` but not nearer than the
/// near plane, in pixels with the screen's slack; infinity for NaN.
fn on_screen(camera: &Camera, z_low: f32, m: f32, eta: f32, g: f32) -> f32 {
    let bound = camera.focal() / least_depth(camera, z_low, m, eta) * g * SCREEN_SLACK;
    if bound.is_nan() {
        f32::INFINITY
    } else {
        bound
    }
}

/// The least depth a deviation at most `m` long can reach from corners whose nearest depth is
/// `z_low`, with their rounding `eta`, but not nearer than the near plane: the `z_min` of the
/// module docs.
fn least_depth(camera: &Camera, z_low: f32, m: f32, eta: f32) -> f32 {
    max(camera.near(), z_low - m - eta)
}

/// The largest `|x| + |y| + |z|` of points in view coordinates: the `Σ` of the rounding
/// `η = slack + 16 ε Σ` of moving them there (see the module docs).
pub(crate) fn view_extent(points: &[Vec3; 3]) -> f32 {
    points
        .iter()
        .map(|v| v.x.abs() + v.y.abs() + v.z.abs())
        .fold(0.0f32, max)
}

/// An upper bound of [`bound_on_screen`]'s bound (and so of the deviation on screen) from the
/// corners alone (`size` at least their [`view_extent`]): the isotropic bound over the rays
/// that the flat triangle's part that can show may have (see the module docs), for a deviation
/// at most `m` long of which `slack` is the corners' rounding. Infinity where the view's near plane or the triangle come within
/// the rounding of the eye.
pub(crate) fn isotropic_bound_on_screen(
    camera: &Camera,
    corners: [Vec3; 3],
    size: f32,
    m: f32,
    slack: f32,
) -> f32 {
    if let Projection::Orthographic { .. } = camera.projection() {
        return camera.focal() * (m * SCREEN_SLACK + 16.0 * EPS * m);
    }
    let z_corner = corners.iter().map(|v| v.z).fold(f32::INFINITY, min);
    isotropic_from(camera, z_corner, size, m, slack)
}

/// [`isotropic_bound_on_screen`] (perspective) from the corners' least depth `z_corner` and
/// their [`view_extent`] `size`: in exact arithmetic it falls as `z_corner` grows and rises
/// with `size` (see `certificate`, which bounds it for corners moved by a camera step).
pub(crate) fn isotropic_from(camera: &Camera, z_corner: f32, size: f32, m: f32, slack: f32) -> f32 {
    let eta = slack + 16.0 * EPS * size;
    let near = camera.near() - eta;
    let z_f = max(z_corner, near);
    let z = z_f - eta;
    if near.is_nan() || near <= 0.0 || z.is_nan() || z <= 0.0 || !m.is_finite() {
        return f32::INFINITY;
    }
    let ([sx, sy], [nx, ny]) = camera.side_planes();
    let w = m + eta;
    // One division: every depth the bound divides by is at least `z_least` (see the module
    // docs), and `T_x + T_y - s_x - s_y` at most `reach`.
    let z_min = max(camera.near(), z_f - m - eta);
    let z_least = min(z, z_min);
    let over = 1.0 / z_least;
    let reach = w * (nx + ny) * over;
    let spread = 1.0 + sx + sy + reach;
    let s = camera.corner_ray() + reach;
    let g = m * (s + 2.0 * eta * spread * over + 16.0 * EPS * spread);
    let bound = camera.focal() * over * g * SCREEN_SLACK;
    if bound.is_nan() {
        f32::INFINITY
    } else {
        bound
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::TestRng;

    /// A random case `k` of the tests below: a camera, a triangle in its view coordinates
    /// around its target (some reaching behind the eye or past the sides), deviation vectors
    /// of any direction (rotated into the view), at least their longest length, and a
    /// remainder.
    fn random_case(rng: &mut TestRng, k: usize) -> (Camera, [Vec3; 3], [Vec3; 4], f32, f32) {
        let mut unit = |scale: f32| rng.signed(1 << 20) as f32 / (1 << 20) as f32 * scale;
        let eye = Vec3::new(unit(10.0), unit(10.0), 8.0 + unit(4.0));
        let camera = Camera::new(
            eye,
            Vec3::new(unit(1.0), unit(1.0), unit(1.0)),
            Vec3::Z,
            Projection::Perspective {
                fov_y_degrees: 40.0,
            },
            0.05,
            [240, 240],
        )
        .unwrap();
        let reach = [0.5, 3.0, 12.0][k % 3];
        let centre = Vec3::new(unit(2.0), unit(2.0), unit(2.0));
        let corners: [Vec3; 3] = core::array::from_fn(|_| {
            camera.to_view(centre + Vec3::new(unit(reach), unit(reach), unit(reach)))
        });
        let big = [1e-3, 2e-2, 0.3][k % 3] * (1.0 + unit(0.5));
        let vectors: [Vec3; 4] = core::array::from_fn(|_| {
            let v = Vec3::new(unit(1.0), unit(1.0), unit(1.0));
            camera.rotate_to_view(v.normalize_or_zero() * big * (0.5 + unit(0.5)).abs())
        });
        let longest = vectors.iter().map(|v| v.length()).fold(0.0, max) * 1.0001;
        (camera, corners, vectors, longest, big * 0.05)
    }

    /// The isotropic bound is at least the directional one, for triangles in front of the
    /// eye, across its near plane and off to the sides, with deviation vectors of any
    /// direction within `big`; and it is not loose beyond the isotropic form's own slack.
    #[test]
    fn the_isotropic_bound_covers_the_directional_one() {
        let mut rng = TestRng::new(0x1507_0b1e);
        let (mut compared, mut worst_ratio) = (0, 0.0f32);
        for k in 0..4000 {
            let (camera, corners, vectors, longest, r) = random_case(&mut rng, k);
            let size = view_extent(&corners);
            let directional = bound_on_screen(
                &camera,
                corners,
                size,
                &vectors,
                longest,
                r,
                r,
                f32::INFINITY,
                false,
            );
            let isotropic = isotropic_bound_on_screen(&camera, corners, size, longest + r, r);
            assert!(
                isotropic >= directional,
                "{k}: isotropic {isotropic} below directional {directional}"
            );
            if directional.is_finite() && directional > 0.0 && isotropic.is_finite() {
                compared += 1;
                worst_ratio = worst_ratio.max(isotropic / directional);
            }
        }
        assert!(compared > 3000, "{compared}");
        assert!(worst_ratio > 1.5, "never looser: {worst_ratio}");
    }

    /// A bound that stops over `stop` is over it exactly where the full bound is, and at most
    /// the full bound; under `stop` it is the full bound.
    #[test]
    fn a_bound_stopped_over_a_value_is_over_it_exactly_where_the_bound_is() {
        let mut rng = TestRng::new(0x5709_b0dd);
        let (mut stopped, mut under) = (0, 0);
        for k in 0..4000 {
            let (camera, corners, vectors, longest, r) = random_case(&mut rng, k);
            let size = view_extent(&corners);
            let bound = |stop| {
                bound_on_screen(&camera, corners, size, &vectors, longest, r, r, stop, false)
            };
            let full = bound(f32::INFINITY);
            if !full.is_finite() || full == 0.0 {
                continue;
            }
            for stop in [0.3, 0.9, 0.99, 1.01, 2.0].map(|x| x * full) {
                let b = bound(stop);
                assert_eq!(b > stop, full > stop, "{k}: {b} against {full} at {stop}");
                assert!(b <= full, "{k}: {b} over the bound {full}");
                if b != full {
                    stopped += 1;
                } else if full <= stop {
                    under += 1;
                }
            }
        }
        assert!(
            stopped > 1000 && under > 1000,
            "{stopped} stopped, {under} under"
        );
    }
}
