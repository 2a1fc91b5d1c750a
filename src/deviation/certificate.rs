//! How far a camera may move before a triangle's judgement on screen can change: a
//! certificate that lets a frame reuse the judgement of a frame before it.
//!
//! # What is certified
//!
//! A triangle judged in a perspective view is *within* (its bound at most the tolerance) or
//! *over*. The run time decides that from the isotropic bound `I` and, where `I` is over, the
//! directional bound `D` (see `screen`): within when `I <= tol` or `D <= tol`, over when both
//! are over. A camera step moves every corner of the triangle by at most `δ` in view
//! coordinates and turns every deviation vector by at most `ρ` times its length (the bounds
//! [`Camera::moved_from`](crate::Camera::moved_from) gives for the model's sphere). Here are
//! upper and lower bounds of `I` and `D` over every camera within `(δ, ρ)` of this one with the
//! same projection, viewport and near plane. Where the upper bounds are within the tolerance
//! by a margin, or the lower bounds over it by a margin, the judgement stands for every such
//! camera; the run time then keeps it instead of judging again (see `tessellator::select`).
//!
//! # The bounds
//!
//! Take corners `v_i` (view coordinates) that stay inside every plane of the view, as the
//! check below asks: then neither frame clips the triangle, and the polygon `F` of `screen` is
//! the triangle itself in both. The corners move to `v_i'` with `|v_i' - v_i| <= δ`.
//!
//! - **Depths.** `z_i' ∈ [z_i - δ, z_i + δ]`, so the least depth moves by at most `δ`, and
//!   the view extent `Σ` (largest `|x| + |y| + |z|`) by at most `3 δ`; the rounding
//!   `η = slack + 16 ε Σ` by at most `48 ε δ`.
//! - **Rays.** `τ = (x / z, y / z)`: `|τ_x' - τ_x| <= (|Δx| z + |x| |Δz|) / (z z') <=
//!   δ (1 + |τ_x|) / (z - δ)`, likewise `τ_y`, so `|τ' - τ| <= Δ = δ (2 + |τ_x| + |τ_y|) /
//!   (z - δ)`.
//! - **Vectors.** `e_k' - e_k = (M' - M) e`, at most `ρ |e| <= ρ big` long.
//! - **One corner's term** `g = max_k φ(τ, e_k) + r √(1 + |τ|²) + m (widen + 16 ε spread)`:
//!   `φ(τ, e) = |e_⊥ - τ e_z|` moves by at most `|e_z| |Δτ| + |Δe| √(1 + |τ'|²)`, so by
//!   `big Δ + ρ big (t + Δ)` with `t = √(1 + |τ|²)`; `r t` by at most `r Δ`; `spread = 1 +
//!   |τ_x| + |τ_y|` by at most `2 Δ`; and `widen = 2 η spread / (z - η)` stays under
//!   `2 η⁺ (spread + 2 Δ) / (z - δ - η⁺)`, `η⁺` the rounding at extent `Σ + 3 δ`.
//! - **The bound** `f / z_min · max_i g_i`, with `z_min = max(near, z_low - m - η)`: above by
//!   taking every term up and `z_min` at `z_low - δ`; below by taking `φ` and `r t` down, the
//!   nonnegative rest as 0, and `z_min` at `z_low + δ` with the least rounding `η >= slack`.
//! - **The isotropic bound** is a function of the least depth and the extent alone, falling
//!   with the depth and rising with the extent (`screen::isotropic_from`): at
//!   `(z_low - δ, Σ + 3 δ)` it is above, at `(z_low + δ, Σ - 3 δ)` below.
//!
//! **Rounding.** Both frames move the corners into view coordinates with an error of at most
//! `16 ε Σ` each (`screen`'s module docs), so `δ` is taken `32 ε (Σ + 3 δ)` larger; the
//! vectors' rotations are within `ρ`'s own rounding (`moved_from`). The bounds here and the
//! judgement they stand for are each a few dozen roundings of their exact values: where no
//! difference cancels they are within a relative `2^-16` of them. The one difference that can
//! cancel is the least depth `z_low - m - η`, kept off the eye by the near plane: a triangle
//! is certified only where `(z_high + δ + m + η⁺) ε` is at most `2^-16` of the near plane's
//! distance, so that this difference too is within a relative `2^-16`. A certificate asks the
//! bounds to clear the tolerance by a relative `2^-8`, far more than these roundings move
//! them.
//!
//! The orthographic projection is not certified (it is judged every frame).

use glam::Vec3;

use super::screen::{isotropic_from, view_extent, SCREEN_SLACK};
use super::EPS;
use crate::math::{max, min, sqrt};
use crate::view::{Camera, Projection};

/// The relative margin by which a certificate's bounds must clear the tolerance.
const MARGIN: f32 = 1.0 / 256.0;

/// The largest of `budgets` (camera steps, as `(δ, ρ)`, in increasing order) over which the
/// judgement of the flat triangle `corners` (view coordinates, as `screen::bound_on_screen`
/// takes them) with deviation in the hull of `e` (view coordinates, none longer than `big`)
/// widened by `r`, and the corners' rounding `slack`, is certain: `(over, k)`, the judgement
/// and the budget's index. `None` where not even the first is.
#[allow(clippy::too_many_arguments)]
pub(crate) fn lasting(
    camera: &Camera,
    corners: [Vec3; 3],
    e: &[Vec3],
    big: f32,
    r: f32,
    slack: f32,
    tolerance: f32,
    budgets: &[[f32; 2]],
) -> Option<(bool, usize)> {
    if let Projection::Orthographic { .. } = camera.projection() {
        return None;
    }
    let m = big + r;
    let size = view_extent(&corners);
    let (near, focal) = (camera.near(), camera.focal());
    if !(m.is_finite() && size.is_finite() && slack.is_finite() && near > 0.0) {
        return None;
    }
    // Per corner: its ray, `t = √(1 + |τ|²)`, and the largest `φ` of the vectors (plain
    // square roots: the lower bounds take them down by the margin's share), found once the
    // isotropic bounds alone do not decide.
    let mut rays = [([0.0f32; 2], 0.0f32, 0.0f32); 3];
    for (ray, v) in rays.iter_mut().zip(&corners) {
        if v.z.is_nan() || v.z <= 0.0 {
            return None;
        }
        let (tx, ty) = (v.x / v.z, v.y / v.z);
        *ray = ([tx, ty], sqrt(1.0 + tx * tx + ty * ty), f32::NAN);
    }
    let mut phis_found = false;
    let z_low = corners.iter().map(|v| v.z).fold(f32::INFINITY, min);
    let z_high = corners.iter().map(|v| v.z).fold(0.0f32, max);
    let ([sx, sy], [nx, ny]) = camera.side_planes();
    let mut found = None;
    for (k, &[delta, rho]) in budgets.iter().enumerate() {
        let delta = delta * (1.0 + MARGIN / 64.0) + 32.0 * EPS * (size + 3.0 * delta);
        let eta_up = slack + 16.0 * EPS * (size + 3.0 * delta);
        // Inside every plane in both frames (so neither clips it), and off the eye enough
        // that the least depth's difference keeps its relative rounding (see above).
        let w = m + slack;
        let inside = corners.iter().all(|p| {
            p.z - delta >= near
                && p.x.abs() + delta - sx * (p.z - delta) <= w * nx
                && p.y.abs() + delta - sy * (p.z - delta) <= w * ny
        });
        let keeps_rounding = (z_high + delta + m + eta_up) * EPS <= near / 65536.0;
        if !(inside && keeps_rounding && z_low - delta - eta_up > 0.0) {
            break;
        }
        let i_up = isotropic_from(camera, z_low - delta, size + 3.0 * delta, m, slack);
        if i_up <= tolerance * (1.0 - MARGIN) {
            match found {
                Some((true, _)) => break,
                _ => found = Some((false, k)),
            }
            continue;
        }
        if !phis_found {
            for ([tx, ty], _, phi) in rays.iter_mut() {
                let worst = e
                    .iter()
                    .map(|d| {
                        let (a, b) = (d.x - *tx * d.z, d.y - *ty * d.z);
                        a * a + b * b
                    })
                    .fold(0.0f32, max);
                *phi = sqrt(worst);
            }
            phis_found = true;
        }
        let (mut g_up, mut g_low) = (0.0f32, 0.0f32);
        for (&([tx, ty], t, phi), v) in rays.iter().zip(&corners) {
            let z = v.z;
            let step = delta * (2.0 + tx.abs() + ty.abs()) / (z - delta);
            let spread = 1.0 + tx.abs() + ty.abs() + 2.0 * step;
            let widen = 2.0 * eta_up * spread / (z - delta - eta_up);
            let turn = rho * big * (t + step);
            let up = phi + big * step + turn + r * (t + step) + m * (widen + 16.0 * EPS * spread);
            let low = max(0.0, phi - big * step - turn - 32.0 * EPS * m * spread)
                + r * max(0.0, t - step);
            g_up = max(g_up, up);
            g_low = max(g_low, low);
        }
        let z_min_low = max(near, z_low - delta - m - eta_up);
        let z_min_high = max(near, z_low + delta - m - slack);
        let d_up = focal / z_min_low * g_up * SCREEN_SLACK;
        let d_low = focal / z_min_high * g_low;
        let i_low = isotropic_from(
            camera,
            z_low + delta,
            max(0.0, size - 3.0 * delta),
            m,
            slack,
        );
        let within = min(i_up, d_up) <= tolerance * (1.0 - MARGIN);
        let over = min(i_low, d_low) > tolerance * (1.0 + MARGIN);
        if !(within || over) {
            break;
        }
        match found {
            Some((o, _)) if o != over => break,
            _ => found = Some((over, k)),
        }
    }
    found
}
