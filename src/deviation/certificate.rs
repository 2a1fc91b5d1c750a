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
//! check below asks (`z - δ >= near` and `|x| + δ <= s_x (z - δ)`, likewise `y`, for each):
//! then neither frame leaves the triangle out as beyond a plane (that takes all three corners
//! beyond one) nor clips it, and the polygon `F` of `screen` is the triangle itself in both.
//! The corners move to `v_i'` with `|v_i' - v_i| <= δ`.
//!
//! - **Depths.** `z_i' ∈ [z_i - δ, z_i + δ]`, so the least depth moves by at most `δ`, and
//!   the view extent `Σ` (largest `|x| + |y| + |z|`) by at most `3 δ`; the rounding
//!   `η = slack + 16 ε Σ` by at most `48 ε δ`.
//! - **Rays.** `τ = (x / z, y / z)`: `τ' - τ = (Δv_⊥ - τ Δz) / z' = A Δv / z'` with
//!   `A = [I | -τ]`, whose largest stretch is `t = √(1 + |τ|²)` (`A Aᵀ = I + τ τᵀ`), so
//!   `|τ' - τ| <= Δ = δ t / (z - δ)`, and `|τ_x' - τ_x| + |τ_y' - τ_y| <= √2 Δ`. (Bounding
//!   each coordinate apart, `δ (1 + |τ_x|) / (z - δ)`, gave `Δ = δ (2 + |τ_x| + |τ_y|) /
//!   (z - δ)`: twice this on the axis, where certificates lasted about that much less.)
//! - **Vectors.** `e_k' - e_k = (M' - M) e`, at most `ρ |e| <= ρ big` long.
//! - **One corner's term** `g = max_k φ(τ, e_k) + r √(1 + |τ|²) + m (widen + 16 ε spread)`:
//!   `φ(τ, e) = |e_⊥ - τ e_z|` moves by at most `|e_z| |Δτ| + |Δe| √(1 + |τ'|²)`, so by
//!   `big Δ + ρ big (t + Δ)` with `t = √(1 + |τ|²)`; `r t` by at most `r Δ`; `spread = 1 +
//!   |τ_x| + |τ_y|` by at most `√2 Δ <= 2 Δ`; and `widen = 2 η spread / (z - η)` stays under
//!   `2 η⁺ (spread + 2 Δ) / (z - δ - η⁺)`, `η⁺` the rounding at extent `Σ + 3 δ`.
//! - **Vectors turned one by one** (up to four): `φ(τ, e) = |A e|` with `A = [I | -τ]`,
//!   whose largest stretch is `t`. The step turns `e` by an angle `β` with `sin β <= ρ`
//!   (`M' Mᵀ` is a rotation, and `|e' - e| <= ρ |e|`): `e' = |e| (cos β ê + sin β u)` with
//!   `u` a unit vector across `e`, so
//!   `|A e'|² = cos²β |A e|² + 2 cos β sin β |e| (Aᵀ A e)·u + sin²β |e|² |A u|²`. The middle
//!   term is at most `ρ q` with `q = 2 |e| c`, `c` the length of the part of `Aᵀ A e` across
//!   `e`: `c² = |Aᵀ a|² - (a · a)² / |e|²` with `a = A e`, `|Aᵀ a|² = |a|² + (τ · a)²`. So
//!   `|A e'|² <= |a|² + ρ q + ρ² |e|² t²` and `|A e'|² >= (1 - ρ²) |a|² - ρ q`; and
//!   `A' e' = A e' - (τ' - τ) e'_z` with `|e'_z| <= |e_z| + ρ |e|` moves it by at most
//!   `Δ (|e_z| + ρ |e|)`. The upper bound takes the largest of `|a|² + ρ q` over the
//!   vectors, `big` for `|e|` and the largest `|e_z|`; the lower one the vector of the largest
//!   `φ`. Each is kept where it is tighter than the bound above, which it is where a vector
//!   lies across the ray (`c` small: a turn moves `φ` little to first order), as it does near
//!   a silhouette, where most triangles near the tolerance are. `c` comes from a difference
//!   of two near values: it is taken with `8 ε` of their sum more under the root, and the
//!   lower bound `8 ε (|a|² + ρ q)` less, so that rounding does not cancel it below its
//!   value.
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
//! bounds to clear the tolerance by a relative `2^-10`, 32 times what these roundings can
//! move the two apart. (`2^-8` before: 100 one-degree orbit steps of `frame_loop` at 2.5e-4 took
//! 1.2% fewer instructions on the teapot and 1.6% fewer on Gumbo with `2^-10`.)
//!
//! The orthographic projection is not certified (it is judged every frame).

use glam::{Vec3, Vec4};

use super::screen::{isotropic_from, view_extent, SCREEN_SLACK};
use super::EPS;
use crate::math::{larger, max, min, sqrt};
use crate::view::{Camera, Projection};

/// The relative margin by which a certificate's bounds must clear the tolerance (see
/// *Rounding* in the module docs).
const MARGIN: f32 = 1.0 / 1024.0;

/// The camera steps certificates are asked for in a frame.
///
/// A step is a turn `s` of [`levels`](Self::levels) (increasing) and a move `s d` of every
/// point within `d` of [`centre`](Self::centre): `d` the least of the reaches (the fractions
/// [`reaches`](Self::reaches), decreasing, of [`radius`](Self::radius)) that holds the
/// triangle's corners, its *reach class* (see `reuse`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Steps {
    pub levels: &'static [f32],
    pub reaches: &'static [f32],
    pub radius: f32,
    /// The centre the reaches are measured from, in the view's coordinates.
    pub centre: Vec3,
}

impl Steps {
    /// Reach class `class`'s reach (in model units).
    pub fn reach(&self, class: usize) -> f32 {
        self.reaches.get(class).map_or(0.0, |f| f * self.radius)
    }
}

/// The camera steps a certificate is asked for, if any, and the level to try first: a
/// triangle's last certificate is most often its next one's too, and the search goes up or
/// down from there.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Asked<'a> {
    pub steps: Option<&'a Steps>,
    pub start: u8,
    /// The judgement most likely made (the triangle's last): over the tolerance, or within.
    pub guess: bool,
}

impl Asked<'_> {
    /// No certificate asked for.
    pub const NONE: Asked<'static> = Asked {
        steps: None,
        start: 0,
        guess: false,
    };

    /// Whether no certificate is asked for.
    pub fn is_empty(&self) -> bool {
        self.steps.is_none()
    }
}

/// A certified judgement: over the tolerance or not, for camera steps up to `step`, in reach
/// class `class`; `step` is of level `level` of the levels asked for (at least that level,
/// less than the next), where the next search for a certificate starts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Lasting {
    pub over: bool,
    pub level: u8,
    pub class: u8,
    pub step: f32,
}

/// The largest of the steps `asked` over which the judgement `over` of the flat triangle
/// `corners` (view coordinates, as `screen::bound_on_screen` takes them) with deviation in
/// the hull of `e` (view coordinates, none longer than `big`) widened by `r`, and the
/// corners' rounding `slack`, is certain, or a step between it and the next level over
/// which it is certain too. `None` where not even the first is, or where the corners lie
/// beyond every reach. (Certainty over a step is certainty over every smaller one: the
/// search may start anywhere.)
///
/// `bound` is the judgement's bound: the search skips the steps over which the bounds, as
/// they move about in proportion to the step from it, would not clear the tolerance (a guess
/// that saves bounding steps most likely not certain; each step it does bound is bounded in
/// full). The step between two levels is such a guess too: where the bounds reach the
/// tolerance, on a straight line between the bounds over the two levels where both were
/// found, else on the one through the judgement's bound and the level's; [`GUESS_SHORT`] of
/// that step is bounded in full and given only where it is certain. (A certificate is then
/// about as long as the bounds allow, where levels a factor of two apart gave on average
/// about 0.72 of it.)
#[allow(clippy::too_many_arguments)]
pub(crate) fn lasting(
    camera: &Camera,
    corners: [Vec3; 3],
    e: &[Vec3],
    big: f32,
    r: f32,
    slack: f32,
    tolerance: f32,
    over: bool,
    bound: f32,
    asked: Asked<'_>,
) -> Option<Lasting> {
    let steps = asked.steps?;
    Moved::new(camera, corners, e, big, r, slack)?.lasting(
        steps,
        asked.start,
        tolerance,
        over,
        bound,
    )
}

/// The bound on screen of the flat triangle `corners` (as [`lasting`] takes it, with the
/// same `e`, `big`, `r` and `slack`), and with `asked` steps its certificate: `bound` gives
/// the bound on screen, and is called only where the certificate's own bounds do not
/// already decide the judgement.
///
/// Asked for a certificate, a triangle is first bounded over the step of the level the
/// search starts from, for the judgement its last one made (`asked.guess`). Where those
/// bounds decide it, it is the judgement `bound` would give: the bounds of the module docs
/// hold for every camera within the step, `camera` among them, and clear the tolerance by a
/// margin that covers the roundings of the bound on screen (see *Rounding*). The bound
/// returned then stands for the bound on screen: above it where within the tolerance (and
/// still within it), below it and over the tolerance where over. (The search's guesses,
/// which only choose the steps it bounds in full, then take the bound on screen from the
/// largest `φ` of the corners instead.) An exact judgement (`exact`: a leaf left over
/// reports its bound in full) is guessed within, so that one over takes `bound`.
// (Out of line: inlined into the judgement, its lanes made every judgement dearer, asked for a
// certificate or not: `frame_loop`'s 20 cold orbit frames took 228.9M instructions inlined,
// 226.2M out of line, 224.8M before the lanes; 100 steps 342.7M inlined, 344.0M out of line.)
#[allow(clippy::too_many_arguments)]
#[inline(never)]
pub(crate) fn judged_with_lasting(
    camera: &Camera,
    corners: [Vec3; 3],
    e: &[Vec3],
    big: f32,
    r: f32,
    slack: f32,
    tolerance: f32,
    asked: Asked<'_>,
    exact: bool,
    bound: impl FnOnce() -> f32,
) -> (f32, Option<Lasting>) {
    let Some(steps) = asked.steps else {
        return (bound(), None);
    };
    let Some(mut triangle) = Moved::new(camera, corners, e, big, r, slack) else {
        return (bound(), None);
    };
    let guess = asked.guess && !exact;
    let Some(tried) = triangle.first_level(steps, asked.start, tolerance, guess) else {
        return (bound(), None);
    };
    if tried.holds {
        let estimate = triangle.estimate();
        let lasting = triangle.lasting_from(steps, tolerance, guess, estimate, tried);
        return (tried.at, lasting);
    }
    let bound = bound();
    let over = bound > tolerance || bound.is_nan();
    let lasting = match over == guess {
        true => triangle.lasting_from(steps, tolerance, over, bound, tried),
        false => triangle.lasting(steps, asked.start, tolerance, over, bound),
    };
    (bound, lasting)
}

/// The first level a certificate's search bounds a judgement over: its index, the reach
/// class, and whether the judgement is certain over it with the bound that says so.
#[derive(Clone, Copy)]
struct Tried {
    first: usize,
    class: usize,
    holds: bool,
    at: f32,
}

impl Moved<'_> {
    /// [`lasting`] of this triangle, judged `over` with bound `bound`, for `steps` from
    /// level `start` on.
    fn lasting(
        &mut self,
        steps: &Steps,
        start: u8,
        tolerance: f32,
        over: bool,
        bound: f32,
    ) -> Option<Lasting> {
        let tried = self.first_level(steps, start, tolerance, over)?;
        self.lasting_from(steps, tolerance, over, bound, tried)
    }

    /// The judgement `over` bounded over level `start` of `steps` (the last where there are
    /// fewer), in the triangle's reach class: `None` where it has none, or there are no
    /// levels.
    fn first_level(
        &mut self,
        steps: &Steps,
        start: u8,
        tolerance: f32,
        over: bool,
    ) -> Option<Tried> {
        let levels = steps.levels;
        let first = usize::from(start).min(levels.len().checked_sub(1)?);
        let class = reach_class(&self.corners, steps)?;
        let s = levels[first];
        let (holds, at) = self.certain([s * steps.reach(class), s], tolerance, over);
        Some(Tried {
            first,
            class,
            holds,
            at,
        })
    }

    /// An estimate of the bound on screen of the triangle as it is (not a bound: what the
    /// search's guesses take for it where the bound on screen was not needed), from each
    /// corner's largest `φ`.
    fn estimate(&mut self) -> f32 {
        if !self.phis_found {
            self.find_phis();
        }
        let g = largest(self.rays.phi + self.r * self.rays.t);
        self.camera.focal() / max(self.camera.near(), self.z_low - self.m) * g
    }

    /// [`lasting`] of this triangle, judged `over` with bound `bound`, from `tried`.
    fn lasting_from(
        &mut self,
        steps: &Steps,
        tolerance: f32,
        over: bool,
        bound: f32,
        tried: Tried,
    ) -> Option<Lasting> {
        let levels = steps.levels;
        let Tried {
            first,
            class,
            holds,
            mut at,
        } = tried;
        let reach = steps.reach(class);
        // Whether the judgement is certain over step `s`, and the bound that says so; and
        // the guess of whether it is over step `to` from the bound `at` over step `from`.
        let mut certain_at = |s: f32| self.certain([s * reach, s], tolerance, over);
        let threshold = match over {
            true => tolerance * (1.0 + MARGIN),
            false => tolerance * (1.0 - MARGIN),
        };
        let likely = |at: f32, from: f32, to: f32| {
            let guess = bound + (at - bound) * (to / from);
            match over {
                true => guess > threshold,
                false => guess <= threshold,
            }
        };
        // The step at which the bounds, moving in proportion to the step from `bound` as
        // they do to `at` over step `from`, would reach the threshold (a guess).
        let reaches = |at: f32, from: f32| from * (threshold - bound) / (at - bound);
        let mut k = first;
        // The bound over the next level, where it was found not certain.
        let mut beyond = None;
        if holds {
            while k + 1 < levels.len() && likely(at, levels[k], levels[k + 1]) {
                match certain_at(levels[k + 1]) {
                    (true, b) => (k, at) = (k + 1, b),
                    (false, b) => {
                        beyond = Some(b);
                        break;
                    }
                }
            }
        } else {
            let found = (0..first)
                .rev()
                .filter(|&j| !at.is_nan() && likely(at, levels[first], levels[j]))
                .find_map(|j| match certain_at(levels[j]) {
                    (true, b) => Some((j, b)),
                    _ => None,
                })?;
            if k == found.0 + 1 {
                beyond = Some(at);
            }
            (k, at) = found;
        }
        // Between this level and the next: the guess, a little short of it, where it is
        // certain too.
        let mut step = levels[k];
        if let Some(&next) = levels.get(k + 1) {
            let guess = match beyond {
                Some(b) => levels[k] + (next - levels[k]) * (threshold - at) / (b - at),
                None => reaches(at, levels[k]),
            } * GUESS_SHORT;
            if guess.is_finite() && guess > levels[k] * STEP_WORTH {
                let s = if guess < next {
                    guess
                } else {
                    next * GUESS_SHORT
                };
                if let (true, _) = certain_at(s) {
                    step = s;
                }
            }
        }
        Some(Lasting {
            over,
            level: k as u8,
            class: class as u8,
            step,
        })
    }
}

/// How far short of the guess a certificate between levels is asked for (a fraction of it).
const GUESS_SHORT: f32 = 0.9;
/// How much longer than its level a step between levels must be to be asked for.
const STEP_WORTH: f32 = 1.2;

/// The reach class of a triangle with corners `corners` (view coordinates): the last of
/// `steps`' reaches at least as far from its centre as every corner, their roundings (each
/// within `16 ε` of its coordinates' sum, as is the centre) counted in; `None` where not
/// even the first is.
fn reach_class(corners: &[Vec3; 3], steps: &Steps) -> Option<usize> {
    let spread = |v: Vec3| v.x.abs() + v.y.abs() + v.z.abs();
    let centre = steps.centre;
    let far = corners
        .iter()
        .map(|&v| (v - centre).length() + 20.0 * EPS * (spread(v) + spread(centre)))
        .fold(0.0f32, larger)
        * (1.0 + 4.0 * EPS);
    (0..steps.reaches.len())
        .rev()
        .find(|&k| far <= steps.reach(k))
}

/// A triangle judged in a view, ready to be bounded over camera steps (see the module docs).
pub(crate) struct Moved<'a> {
    camera: &'a Camera,
    corners: [Vec3; 3],
    e: &'a [Vec3],
    big: f32,
    r: f32,
    slack: f32,
    m: f32,
    size: f32,
    z_low: f32,
    z_high: f32,
    /// The corners' rays, and the largest `φ` of the vectors at each (plain square roots:
    /// the lower bounds take them down by their share of the margin), found when first asked
    /// for.
    rays: Rays,
    phis_found: bool,
    /// How each vector's `φ` may change as the camera turns at each corner (see `Turns`);
    /// `None` for more vectors than it holds.
    turns: Option<Turns>,
    /// The largest `|e_z|` of the vectors.
    ez: f32,
}

/// The three corners side by side, one a lane of a [`Vec4`] (the fourth lane repeats the
/// first, so that the largest or least of the lanes is the corners'): a certificate bounds
/// all three at once, in the same operations, in the same order, as one at a time (the
/// bounds of one corner are its own lane's, bit for bit).
#[derive(Clone, Copy)]
struct Rays {
    /// `|x|`, `|y|` and `z` of the corners (view coordinates).
    x: Vec4,
    y: Vec4,
    z: Vec4,
    /// The ray `τ = (x / z, y / z)`, `t = √(1 + |τ|²)`, and `1 + |τ_x| + |τ_y|`.
    tx: Vec4,
    ty: Vec4,
    t: Vec4,
    spread: Vec4,
    /// The largest `φ` of the vectors (NaN until found).
    phi: Vec4,
}

/// Three values in the lanes of [`Rays`].
fn lanes([a, b, c]: [f32; 3]) -> Vec4 {
    Vec4::new(a, b, c, a)
}

/// The largest of the lanes, NaN if any is not finite (a bound that is not certain).
fn largest(v: Vec4) -> f32 {
    match v.is_finite() {
        true => v.max_element(),
        false => f32::NAN,
    }
}

/// The lane-wise `max(a, b)` of [`crate::math::max`] where no lane is NaN (its equal values
/// give `a`; a NaN is caught by [`largest`] after).
fn lane_max(a: Vec4, b: Vec4) -> Vec4 {
    b.max(a)
}

/// Lane-wise square roots (each correctly rounded, as [`sqrt`]).
fn lane_sqrt(v: Vec4) -> Vec4 {
    Vec4::new(sqrt(v.x), sqrt(v.y), sqrt(v.z), sqrt(v.w))
}

/// The corners' vectors as a turn of the camera changes their `φ` (see the module docs):
/// `φ_k²` and `q_k = 2 |e_k| c_k`, `c_k` the part of `Aᵀ A e_k` across `e_k`, each at the
/// corners (lanes, as [`Rays`]); and at each corner the vector of the largest `φ` with its
/// `|e_z|` and length, found where a lower bound first asks for it (an upper bound never
/// does: certificates within the tolerance, most of them, go without; `frame_loop`'s 100
/// one-degree orbit updates at 2.5e-4 took 317.9M instructions against 322.1M on the
/// teapot, 193.0M against 195.1M on Gumbo).
#[derive(Clone, Copy)]
struct Turns {
    p: [Vec4; TURNS],
    q: [Vec4; TURNS],
    /// `φ²`, `q`, `|e_z|`, `|e|` of the vector of the largest `φ`, once found.
    largest: Option<[Vec4; 4]>,
}

impl Turns {
    /// At each corner, `φ²`, `q`, `|e_z|` and `|e|` of the vector of the largest `φ` of `e`
    /// (the later of equal ones, as `p >= worst` takes it).
    fn largest(&mut self, e: &[Vec3]) -> [Vec4; 4] {
        if let Some(found) = self.largest {
            return found;
        }
        let mut worst = Vec4::ZERO;
        let [mut lp, mut lq, mut lz, mut ln] = [Vec4::ZERO; 4];
        for ((&p, &q), d) in self.p.iter().zip(&self.q).zip(e) {
            let now = p.cmpge(worst);
            worst = Vec4::select(now, p, worst);
            lp = Vec4::select(now, p, lp);
            lq = Vec4::select(now, q, lq);
            lz = Vec4::select(now, Vec4::splat(d.z.abs()), lz);
            ln = Vec4::select(now, Vec4::splat(sqrt(d.length_squared())), ln);
        }
        *self.largest.insert([lp, lq, lz, ln])
    }
}

/// Most vectors whose turns a certificate follows one by one (the hierarchy keeps four a
/// node; more, and it bounds them all alike).
const TURNS: usize = 4;

impl<'a> Moved<'a> {
    /// Whether the judgement `over` is certain over every camera within `step` of this one,
    /// and the bound that says so: within when an upper bound is within the tolerance by the
    /// margin, over when the lower bounds are over it by the margin. (Only the judgement's
    /// own side is bounded; NaN where no bound is.)
    fn certain(&mut self, step: [f32; 2], tolerance: f32, over: bool) -> (bool, f32) {
        let Some(i) = self.isotropic_side(step, !over) else {
            return (false, f32::NAN);
        };
        if over {
            let least = tolerance * (1.0 + MARGIN);
            if i <= least || i.is_nan() {
                return (false, i);
            }
            let d_low = self.directional_side(step, false);
            (d_low > least, min(i, d_low))
        } else {
            // Within by the isotropic bound alone: the vectors' terms are not needed.
            let most = tolerance * (1.0 - MARGIN);
            if i <= most {
                return (true, i);
            }
            let d_up = self.directional_side(step, true);
            (d_up <= most, min(i, d_up))
        }
    }

    /// The triangle `corners` (view coordinates of `camera`) with deviation in the hull of
    /// `e` widened by `r` (`big` at least the longest), and the corners' rounding `slack`;
    /// `None` where nothing can be certified (an orthographic view, a corner behind the eye,
    /// a value not finite).
    pub fn new(
        camera: &'a Camera,
        corners: [Vec3; 3],
        e: &'a [Vec3],
        big: f32,
        r: f32,
        slack: f32,
    ) -> Option<Self> {
        if let Projection::Orthographic { .. } = camera.projection() {
            return None;
        }
        let m = big + r;
        let size = view_extent(&corners);
        if !(m.is_finite() && size.is_finite() && slack.is_finite() && camera.near() > 0.0) {
            return None;
        }
        if corners.iter().any(|v| v.z.is_nan() || v.z <= 0.0) {
            return None;
        }
        let [x, y, z] = [0, 1, 2].map(|k| lanes(corners.map(|v| v[k])));
        let (tx, ty) = (x / z, y / z);
        let rays = Rays {
            x: x.abs(),
            y: y.abs(),
            z,
            tx,
            ty,
            t: lane_sqrt(1.0 + tx * tx + ty * ty),
            spread: 1.0 + tx.abs() + ty.abs(),
            phi: Vec4::NAN,
        };
        Some(Moved {
            camera,
            corners,
            e,
            big,
            r,
            slack,
            m,
            size,
            z_low: corners.iter().map(|v| v.z).fold(f32::INFINITY, min),
            z_high: corners.iter().map(|v| v.z).fold(0.0f32, larger),
            rays,
            phis_found: false,
            turns: None,
            ez: big,
        })
    }

    /// `δ` of a step, taken larger by the rounding of both frames' moves into view
    /// coordinates, and the rounding `η` at the extent it may reach.
    fn widened(&self, delta: f32) -> (f32, f32) {
        // (`2^-14` of it for its own roundings and the odometer's, far above a few `ε`.)
        let delta = delta * (1.0 + 1.0 / 16_384.0) + 32.0 * EPS * (self.size + 3.0 * delta);
        (delta, self.slack + 16.0 * EPS * (self.size + 3.0 * delta))
    }

    /// Lower and upper bounds of the isotropic bound over every camera within `[δ, ρ]`:
    /// `None` where a camera within it may leave the triangle out or clip it, or where the
    /// rounding of the least depth is not kept (see the module docs).
    #[cfg(test)]
    pub fn isotropic(&self, step: [f32; 2]) -> Option<[f32; 2]> {
        Some([
            self.isotropic_side(step, false)?,
            self.isotropic_side(step, true)?,
        ])
    }

    /// The upper (`up`) or lower bound of the isotropic bound over every camera within
    /// `[δ, ρ]`: `None` where a camera within it may leave the triangle out or clip it, or
    /// where the rounding of the least depth is not kept (see the module docs).
    #[inline(always)]
    fn isotropic_side(&self, [delta, _]: [f32; 2], up: bool) -> Option<f32> {
        let (delta, eta_up) = self.widened(delta);
        let ([sx, sy], _) = self.camera.side_planes();
        let near = self.camera.near();
        // Every corner inside every plane of the view in both frames (so that neither clips
        // the triangle nor leaves it out as beyond a plane), and off the eye enough that the
        // least depth's difference keeps its relative rounding.
        let Rays { x, y, z, .. } = self.rays;
        let inside = (z - delta).cmpge(Vec4::splat(near))
            & (x + delta).cmple(sx * (z - delta))
            & (y + delta).cmple(sy * (z - delta));
        let inside = inside.all();
        let keeps_rounding = (self.z_high + delta + self.m + eta_up) * EPS <= near / 65536.0;
        if !(inside && keeps_rounding && self.z_low - delta - eta_up > 0.0) {
            return None;
        }
        let (camera, m, slack) = (self.camera, self.m, self.slack);
        Some(match up {
            true => isotropic_from(
                camera,
                self.z_low - delta,
                self.size + 3.0 * delta,
                m,
                slack,
            ),
            false => isotropic_from(
                camera,
                self.z_low + delta,
                max(0.0, self.size - 3.0 * delta),
                m,
                slack,
            ),
        })
    }

    /// Each corner's largest `φ`, and where the vectors are few enough, their turns.
    fn find_phis(&mut self) {
        let e = self.e;
        let Rays { tx, ty, .. } = self.rays;
        // `φ²` of vector `d` at each corner, with the parts `a`, `b` of `A d`.
        let phi2 = |d: &Vec3| {
            let (a, b) = (d.x - tx * d.z, d.y - ty * d.z);
            (a * a + b * b, a, b)
        };
        // Every `φ²` (and below, every `q`) finite, or no `φ` (nothing certain): then no lane
        // of the bounds is NaN but by an infinity that stays in it (see `largest`), or in a
        // term whose `min` or `max` with another bound of the same side leaves a bound.
        let found = |worst: Vec4, finite: bool| match finite {
            true => lane_sqrt(worst),
            false => Vec4::NAN,
        };
        let Some(e) = e.get(..TURNS).filter(|_| e.len() <= TURNS) else {
            let (worst, finite) = e.iter().fold((Vec4::ZERO, true), |(w, finite), d| {
                let p = phi2(d).0;
                (lane_max(w, p), finite && p.is_finite())
            });
            self.rays.phi = found(worst, finite);
            self.phis_found = true;
            return;
        };
        // (Filled in place: a copy of the corners' turns was a `memcpy` call for each
        // triangle a step certified.)
        let turns = self.turns.insert(Turns {
            p: [Vec4::ZERO; TURNS],
            q: [Vec4::ZERO; TURNS],
            largest: None,
        });
        let mut worst = Vec4::ZERO;
        for (k, d) in e.iter().enumerate() {
            let n2 = d.length_squared();
            let (p, a, b) = phi2(d);
            // `|Aᵀ a|² = |a|² + (τ · a)²`, and its part along `e`, `|a|² / |e|`: the part
            // across, times `|e|`, from a difference kept off rounding's cancelling.
            let ta = tx * a + ty * b;
            let (whole, along) = (n2 * (p + ta * ta), p * p);
            let q =
                2.0 * lane_sqrt(lane_max(Vec4::ZERO, whole - along) + 8.0 * EPS * (whole + along));
            (turns.p[k], turns.q[k]) = (p, q);
            worst = lane_max(worst, p);
        }
        let finite = turns.p[..e.len()]
            .iter()
            .chain(&turns.q[..e.len()])
            .all(|v| v.is_finite());
        self.rays.phi = found(worst, finite);
        self.ez = e.iter().map(|d| d.z.abs()).fold(0.0f32, larger);
        self.phis_found = true;
    }

    /// Lower and upper bounds of the directional bound over every camera within `[δ, ρ]`,
    /// where [`isotropic`](Self::isotropic) gives bounds (its conditions are this one's).
    #[cfg(test)]
    pub fn directional(&mut self, step: [f32; 2]) -> [f32; 2] {
        [
            self.directional_side(step, false),
            self.directional_side(step, true),
        ]
    }

    /// The upper (`up`) or lower bound of the directional bound over every camera within
    /// `[δ, ρ]`, where [`isotropic`](Self::isotropic) gives bounds (its conditions are this
    /// one's).
    #[inline(always)]
    fn directional_side(&mut self, [delta, rho]: [f32; 2], up: bool) -> f32 {
        if !self.phis_found {
            self.find_phis();
        }
        let (delta, eta_up) = self.widened(delta);
        let (big, r, m) = (self.big, self.r, self.m);
        let Rays {
            z, t, spread, phi, ..
        } = self.rays;
        if !phi.is_finite() {
            return f32::NAN;
        }
        let step = delta * t / (z - delta);
        let spread = spread + 2.0 * step;
        let turn = rho * big * (t + step);
        // The vectors turned one by one where they are few (see the module docs), else each
        // by the longest's turn.
        let bound = if up {
            let mut phi_up = phi + big * step + turn;
            if let Some(Turns { p, q, .. }) = &self.turns {
                let turned = p[..self.e.len()]
                    .iter()
                    .zip(&q[..self.e.len()])
                    .fold(Vec4::ZERO, |w, (&p, &q)| lane_max(w, p + rho * q))
                    + rho * rho * big * big * t * t;
                phi_up = phi_up.min(lane_sqrt(turned) + step * (self.ez + rho * big));
            }
            let widen = 2.0 * eta_up * spread / (z - delta - eta_up);
            phi_up + r * (t + step) + m * (widen + 16.0 * EPS * spread)
        } else {
            let mut phi_low = phi - big * step - turn;
            if let Some(turns) = &mut self.turns {
                let [p, q, ez, n] = turns.largest(self.e);
                let least = (1.0 - rho * rho) * p - rho * q - 8.0 * EPS * (p + rho * q);
                phi_low = lane_max(
                    phi_low,
                    lane_sqrt(lane_max(Vec4::ZERO, least)) - step * (ez + rho * n),
                );
            }
            lane_max(Vec4::ZERO, phi_low - 32.0 * EPS * m * spread)
                + r * lane_max(Vec4::ZERO, t - step)
        };
        // (At least 0 in every lane; NaN, not certain, where a lane is not finite.)
        let g = largest(bound);
        let (near, focal) = (self.camera.near(), self.camera.focal());
        if up {
            let z_min_low = max(near, self.z_low - delta - m - eta_up);
            focal / z_min_low * g * SCREEN_SLACK
        } else {
            let z_min_high = max(near, self.z_low + delta - m - self.slack);
            focal / z_min_high * g
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::deviation::screen::{bound_on_screen, isotropic_bound_on_screen, view_extent};
    use crate::test_rng::TestRng;
    use crate::BoundingSphere;

    /// The judgement the run time makes (`tessellator::judge`) of the flat triangle `corners`
    /// (model space) with deviation vectors `vectors` (model space), as over the tolerance or
    /// not.
    fn judged_over(
        camera: &Camera,
        corners: &[Vec3; 3],
        vectors: &[Vec3; 4],
        big: f32,
        r: f32,
        tolerance: f32,
    ) -> bool {
        let viewed = corners.map(|p| camera.to_view(p));
        let size = view_extent(&viewed);
        if isotropic_bound_on_screen(camera, viewed, size, big + r, r) <= tolerance {
            return false;
        }
        let e = vectors.map(|v| camera.rotate_to_view(v));
        bound_on_screen(camera, viewed, size, &e, big, r, r, tolerance, false) > tolerance
    }

    fn camera(eye: Vec3, target: Vec3) -> Option<Camera> {
        Camera::new(
            eye,
            target,
            Vec3::Z,
            Projection::Perspective {
                fov_y_degrees: 40.0,
            },
            0.05,
            [240, 240],
        )
        .ok()
    }

    /// A random case of the tests below: a camera, a flat triangle (model space) `spread`
    /// about its target, deviation vectors no longer than `big`, and a remainder.
    struct Case {
        eye: Vec3,
        target: Vec3,
        camera: Camera,
        corners: [Vec3; 3],
        vectors: [Vec3; 4],
        big: f32,
        r: f32,
    }

    /// Case `k`, from `unit` (a random value in `-scale..=scale`); `None` for an invalid
    /// camera.
    fn random_case(unit: &mut impl FnMut(f32) -> f32, k: usize, spread: f32) -> Option<Case> {
        let target = Vec3::new(unit(1.0), unit(1.0), unit(1.0));
        let eye = Vec3::new(unit(10.0), unit(10.0), 6.0 + unit(4.0));
        let camera = camera(eye, target)?;
        let reach = [0.3, 1.5, 4.0][k % 3];
        let centre = target + Vec3::new(unit(spread), unit(spread), unit(spread));
        let corners: [Vec3; 3] =
            core::array::from_fn(|_| centre + Vec3::new(unit(reach), unit(reach), unit(reach)));
        let big = [2e-3, 2e-2, 0.2][k % 3] * (1.0 + unit(0.5));
        let vectors: [Vec3; 4] = core::array::from_fn(|_| {
            Vec3::new(unit(1.0), unit(1.0), unit(1.0)).normalize_or_zero()
                * big
                * (0.5 + unit(0.5)).abs()
        });
        Some(Case {
            eye,
            target,
            camera,
            corners,
            vectors,
            big,
            r: big * 0.05,
        })
    }

    /// Random triangles, vectors and cameras, the tolerance near each one's bound: wherever a
    /// certificate is given for a step, every camera within that step judges the triangle
    /// the same (the cameras tried are scaled down from a random move until they fit, so
    /// most lie near the step's edge).
    #[test]
    fn a_certified_judgement_holds_for_every_camera_within_its_step() {
        let mut rng = TestRng::new(0x0ce7_1f1c_a7e5);
        let mut unit = |scale: f32| rng.signed(1 << 20) as f32 / (1 << 20) as f32 * scale;
        let (mut certified, mut tried, mut over, mut between) = (0, 0, 0, 0);
        let mut classes = [0usize; REACHES_FOR_TESTS.len()];
        for k in 0..6000 {
            let Some(Case {
                eye,
                target,
                camera: c0,
                corners,
                vectors,
                big,
                r,
            }) = random_case(&mut unit, k, 1.5)
            else {
                continue;
            };
            let viewed = corners.map(|p| c0.to_view(p));
            let e = vectors.map(|v| c0.rotate_to_view(v));
            // The tolerance within a factor of two of the bound, either side.
            let size = view_extent(&viewed);
            let bound = bound_on_screen(&c0, viewed, size, &e, big, r, r, f32::INFINITY, false);
            if !(bound.is_finite() && bound > 0.0) {
                continue;
            }
            let tolerance = bound * (1.0 + unit(0.5)) / (1.0 + unit(0.5)).max(0.5);
            let Some(own) = BoundingSphere::of_points(&corners.map(|p| p.to_array())) else {
                continue;
            };
            // A model's sphere around the triangle, from as large as its own to several times
            // larger and off its centre: the reach classes vary.
            let centre = own.center + Vec3::new(unit(1.0), unit(1.0), unit(1.0)) * own.radius;
            let far = corners
                .iter()
                .map(|p| (*p - centre).length())
                .fold(0.0, max);
            let model = BoundingSphere {
                center: centre,
                radius: far * (1.01 + 2.5 * unit(1.0).abs()),
            };
            let steps = Steps {
                levels: &LEVELS_FOR_TESTS,
                reaches: &REACHES_FOR_TESTS,
                radius: model.radius,
                centre: c0.to_view(centre),
            };
            // (The search starts at every level in turn.)
            let asked = Asked {
                steps: Some(&steps),
                start: (k % LEVELS_FOR_TESTS.len()) as u8,
                guess: false,
            };
            // (The certificate bounds the judgement's own side: it is given the judgement.)
            let judged = judged_over(&c0, &corners, &vectors, big, r, tolerance);
            let Some(Lasting {
                over: claim,
                level,
                class,
                step,
            }) = lasting(&c0, viewed, &e, big, r, r, tolerance, judged, bound, asked)
            else {
                continue;
            };
            assert!(
                corners
                    .iter()
                    .all(|p| (*p - centre).length() <= steps.reach(class.into())),
                "case {k}: a corner beyond its reach class"
            );
            certified += 1;
            classes[usize::from(class)] += 1;
            over += usize::from(claim);
            let sphere = BoundingSphere {
                radius: steps.reach(class.into()),
                ..model
            };
            // (A step between two levels, where one is given: the certificate covers it.)
            let s = step;
            assert!(
                LEVELS_FOR_TESTS[usize::from(level)] <= s
                    && LEVELS_FOR_TESTS
                        .get(usize::from(level) + 1)
                        .is_none_or(|&next| s < next),
                "case {k}: step {s} is not of level {level}"
            );
            between += usize::from(s > LEVELS_FOR_TESTS[usize::from(level)]);
            let (delta, rho) = (s * sphere.radius, s);
            for _ in 0..4 {
                let (de, dt) = (
                    Vec3::new(unit(1.0), unit(1.0), unit(1.0)) * (4.0 * delta),
                    Vec3::new(unit(1.0), unit(1.0), unit(1.0)) * (4.0 * delta),
                );
                let mut t = 1.0f32;
                let moved = loop {
                    let Some(c1) = camera(eye + de * t, target + dt * t) else {
                        break None;
                    };
                    let [d, p] = c1.moved_from(&c0, &sphere);
                    if d <= delta && p <= rho {
                        break Some(c1);
                    }
                    t *= 0.8;
                    if t < 1e-4 {
                        break None;
                    }
                };
                let Some(c1) = moved else {
                    continue;
                };
                tried += 1;
                let ([sx, sy], _) = c1.side_planes();
                assert!(
                    corners
                        .iter()
                        .map(|p| c1.to_view(*p))
                        .all(|v| v.z >= c1.near()
                            && v.x.abs() <= sx * v.z
                            && v.y.abs() <= sy * v.z),
                    "case {k}: a certified triangle left the view"
                );
                assert_eq!(
                    judged_over(&c1, &corners, &vectors, big, r, tolerance),
                    claim,
                    "case {k}: certified {claim} for step {level}, the moved camera judges otherwise"
                );
            }
        }
        assert!(
            certified > 1000 && over > 200 && between > 200 && tried > 3000,
            "{certified} certified, {over} over, {between} between levels, {tried} tried"
        );
        // Every reach class is certified somewhere.
        assert!(classes.iter().all(|&n| n > 50), "by class: {classes:?}");
    }

    /// Random triangles, vectors and cameras, the tolerance near each one's bound and the
    /// isotropic bound over it (the judgements that take the bound on screen), either guess,
    /// exact or not: a judgement made without the bound on screen is the one it makes, and
    /// the bound given stands for it (at least it where within the tolerance, over the
    /// tolerance where over); an exact judgement over the tolerance takes the bound on
    /// screen itself; a certificate given is for the judgement made.
    #[test]
    fn a_judgement_the_certificate_decides_is_the_bound_on_screens() {
        let mut rng = TestRng::new(0x6e55_f1a5_7000);
        let mut unit = |scale: f32| rng.signed(1 << 20) as f32 / (1 << 20) as f32 * scale;
        let (mut decided, mut computed, mut certified) = (0, 0, 0);
        for k in 0..6000 {
            let Some(Case {
                camera,
                corners,
                vectors,
                big,
                r,
                ..
            }) = random_case(&mut unit, k, 1.5)
            else {
                continue;
            };
            let viewed = corners.map(|p| camera.to_view(p));
            let e = vectors.map(|v| camera.rotate_to_view(v));
            let size = view_extent(&viewed);
            let full = bound_on_screen(&camera, viewed, size, &e, big, r, r, f32::INFINITY, false);
            if !(full.is_finite() && full > 0.0) {
                continue;
            }
            let tolerance = full * (1.0 + unit(0.3)) / (1.0 + unit(0.3));
            if isotropic_bound_on_screen(&camera, viewed, size, big + r, r) <= tolerance {
                continue;
            }
            let over = full > tolerance;
            let Some(own) = BoundingSphere::of_points(&corners.map(|p| p.to_array())) else {
                continue;
            };
            let steps = Steps {
                levels: &LEVELS_FOR_TESTS,
                reaches: &REACHES_FOR_TESTS,
                radius: own.radius * 2.0,
                centre: camera.to_view(own.center),
            };
            let asked = Asked {
                steps: Some(&steps),
                start: (k % LEVELS_FOR_TESTS.len()) as u8,
                guess: k % 3 == 0,
            };
            let exact = k % 5 == 0;
            let stop = if exact { f32::INFINITY } else { tolerance };
            let mut called = false;
            let (bound, lasting) = judged_with_lasting(
                &camera,
                viewed,
                &e,
                big,
                r,
                r,
                tolerance,
                asked,
                exact,
                || {
                    called = true;
                    bound_on_screen(&camera, viewed, size, &e, big, r, r, stop, false)
                },
            );
            assert_eq!(bound > tolerance, over, "case {k}: {bound} against {full}");
            if !over {
                assert!(bound >= full, "case {k}: {bound} < {full} within");
            }
            if exact && over {
                assert!(called && bound == full, "case {k}: exact, over, {bound}");
            }
            if let Some(l) = lasting {
                assert_eq!(l.over, over, "case {k}: certified otherwise");
                certified += 1;
            }
            decided += usize::from(!called);
            computed += usize::from(called);
        }
        assert!(
            decided > 300 && computed > 300 && certified > 600,
            "{decided} decided by the certificate, {computed} by the bound, {certified} certified"
        );
    }

    /// Random triangles, vectors and cameras, each moved as far as a step allows (turned about
    /// the triangle, slid, or both, the move's size found by bisection): the bounds over the
    /// step hold the isotropic and directional bounds of every moved camera (to their own
    /// roundings), and the test reports how close the moves come to them.
    #[test]
    fn the_bounds_over_a_step_hold_the_moved_cameras_bounds() {
        let mut rng = TestRng::new(0x0b0a_57e9_2026);
        let mut unit = |scale: f32| rng.signed(1 << 20) as f32 / (1 << 20) as f32 * scale;
        let (mut checked, mut closest_up, mut closest_low) = (0, 0.0f32, f32::INFINITY);
        for k in 0..3000 {
            let Some(Case {
                eye,
                target,
                camera: c0,
                corners,
                vectors,
                big,
                r,
            }) = random_case(&mut unit, k, 1.0)
            else {
                continue;
            };
            let (viewed, e) = (
                corners.map(|p| c0.to_view(p)),
                vectors.map(|v| c0.rotate_to_view(v)),
            );
            let Some(sphere) = BoundingSphere::of_points(&corners.map(|p| p.to_array())) else {
                continue;
            };
            let Some(mut moved) = Moved::new(&c0, viewed, &e, big, r, r) else {
                continue;
            };
            let s = LEVELS_FOR_TESTS[k % 3] / 4.0;
            let step = [s * sphere.radius, s];
            let Some([i_low, i_up]) = moved.isotropic(step) else {
                continue;
            };
            let [d_low, d_up] = moved.directional(step);
            let axis = Vec3::new(unit(1.0), unit(1.0), unit(1.0)).normalize_or_zero();
            let slide = Vec3::new(unit(1.0), unit(1.0), unit(1.0));
            let kind = k % 3;
            let camera_at = |t: f32| {
                let turn = glam::Quat::from_axis_angle(axis, t * (kind != 1) as u32 as f32);
                let shift = slide * (t * sphere.radius * (kind != 0) as u32 as f32);
                let c = sphere.center;
                camera(
                    c + turn * (eye - c) + shift,
                    c + turn * (target - c) + shift,
                )
            };
            let fits = |t: f32| {
                camera_at(t).is_some_and(|c1| {
                    let [d, p] = c1.moved_from(&c0, &sphere);
                    d <= step[0] && p <= step[1]
                })
            };
            let (mut lo, mut hi) = (0.0f32, 4.0 * s);
            for _ in 0..30 {
                let mid = 0.5 * (lo + hi);
                if fits(mid) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            for t in [lo, -lo, 0.5 * lo] {
                let Some(c1) = camera_at(t).filter(|_| fits(t.abs())) else {
                    continue;
                };
                let viewed = corners.map(|p| c1.to_view(p));
                let e = vectors.map(|v| c1.rotate_to_view(v));
                let size = view_extent(&viewed);
                let i = isotropic_bound_on_screen(&c1, viewed, size, big + r, r);
                let d = bound_on_screen(&c1, viewed, size, &e, big, r, r, f32::INFINITY, false);
                let slack = 1.0 + 1.0 / 4096.0;
                assert!(
                    i_low <= i * slack && i <= i_up * slack,
                    "case {k}: {i_low} {i} {i_up}"
                );
                assert!(
                    d_low <= d * slack && d <= d_up * slack,
                    "case {k}: {d_low} {d} {d_up}"
                );
                checked += 1;
                closest_up = closest_up.max(d / d_up);
                if d_low > 0.0 {
                    closest_low = closest_low.min(d / d_low);
                }
            }
        }
        assert!(checked > 3000, "{checked} moved cameras checked");
        // The moves reach the bounds' edges (measured: within 0.02% of the upper bound and
        // 0.11% of the lower one, over 4,689 moved cameras; 0.7% and 0.8% before the vectors
        // turned one by one), so a bound taken too small fails.
        assert!(
            closest_up > 0.95 && closest_low < 1.05,
            "largest bound / upper {closest_up}, least bound / lower {closest_low}"
        );
    }

    /// `reuse`'s levels (the test keeps its own copy: `deviation` does not see the
    /// tessellator's).
    const LEVELS_FOR_TESTS: [f32; 3] = [1.0 / 32.0, 1.0 / 8.0, 1.0 / 2.0];

    /// `reuse`'s reach classes, likewise.
    const REACHES_FOR_TESTS: [f32; 4] = [1.0, 0.71, 0.5, 0.35];
}
