//! The camera and the view: what a frame must achieve, a tolerance in pixels for a camera
//! ([`View::Screen`]) or in model units ([`View::Object`]).
//!
//! A [`Camera`] is a look-at camera with a perspective or orthographic projection, a near
//! plane and a viewport in pixels; it moves points into view coordinates (x right, y up,
//! z away from the eye) and projects them to pixels (x right, y down). The tessellator judges
//! each triangle's bound on screen through it (`deviation`'s `screen` module derives how a
//! deviation in model space moves pixels), and leaves out what lies beyond one of its planes:
//! the near plane and the four sides of the viewport.

use core::fmt;

use glam::Vec3;

use crate::math::{normalize, sqrt};

/// How the camera projects.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Projection {
    /// Perspective with a vertical field of view, in degrees (strictly between 0 and 180).
    Perspective {
        /// Vertical field of view in degrees.
        fov_y_degrees: f32,
    },
    /// Parallel projection showing `height` object units from the bottom to the top of the
    /// viewport.
    Orthographic {
        /// Object-space height of the view.
        height: f32,
    },
}

/// Why a [`Camera`] cannot be built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum CameraError {
    /// A coordinate is NaN or infinite.
    NotFinite,
    /// The eye is at the target.
    EyeAtTarget,
    /// `up` is zero or parallel to the view direction.
    BadUp,
    /// The field of view is not strictly between 0 and 180 degrees, or the orthographic height
    /// is not positive.
    BadProjection,
    /// The near plane is not positive (perspective) or negative (orthographic).
    BadNear,
    /// The viewport has no pixels.
    EmptyViewport,
}

impl fmt::Display for CameraError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            CameraError::NotFinite => "camera coordinate is NaN or infinite",
            CameraError::EyeAtTarget => "eye and target are the same point",
            CameraError::BadUp => "up vector is zero or parallel to the view direction",
            CameraError::BadProjection => "field of view or orthographic height out of range",
            CameraError::BadNear => "near plane distance out of range",
            CameraError::EmptyViewport => "viewport has no pixels",
        })
    }
}

impl core::error::Error for CameraError {}

/// A validated camera: position, orientation, projection, near plane and viewport.
///
/// ```
/// use spline_tess::{Camera, Projection, Vec3};
///
/// let camera = Camera::new(
///     Vec3::new(0.0, -10.0, 0.0), // eye
///     Vec3::ZERO,                  // target
///     Vec3::Z,                     // up
///     Projection::Perspective { fov_y_degrees: 60.0 },
///     0.1,                         // near plane
///     [320, 240],                  // viewport in pixels
/// )?;
/// // The target lands in the middle of the viewport.
/// let [x, y] = camera.project(Vec3::ZERO).unwrap();
/// assert!((x - 160.0).abs() < 1e-3 && (y - 120.0).abs() < 1e-3);
/// # Ok::<(), spline_tess::CameraError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Camera {
    eye: [f32; 3],
    forward: [f32; 3],
    right: [f32; 3],
    up: [f32; 3],
    projection: Projection,
    near: f32,
    viewport: [u32; 2],
    /// Pixels per unit of screen slope (perspective) or per object unit (orthographic).
    focal: f32,
    /// Largest visible |x/z| and |y/z| (perspective).
    slope: [f32; 2],
    /// `sqrt(1 + s²)` for both slopes (perspective; 1 orthographic): the length of a side
    /// plane's normal `(1, -s)`, by which a distance beyond it is divided.
    side_norm: [f32; 2],
    /// At least `sqrt(1 + s_x² + s_y²)`: the length of the ray `(s_x, s_y, 1)` to a corner of
    /// the view (perspective; 1 orthographic).
    corner_ray: f32,
    /// The viewport's centre in pixels, `0.5 w` and `0.5 h` (found once: a pixel position
    /// takes it for every corner).
    centre: [f32; 2],
}

impl Camera {
    /// Every field's bits: two cameras with equal bits are the same camera to every rounding
    /// (`==` takes `0.0` and `-0.0` as equal).
    pub(crate) fn bits(&self) -> [u32; 22] {
        let f = |x: f32| x.to_bits();
        let (kind, extra) = match self.projection {
            Projection::Perspective { fov_y_degrees } => (0, f(fov_y_degrees)),
            Projection::Orthographic { height } => (1, f(height)),
        };
        let [e, d, r, u] = [self.eye, self.forward, self.right, self.up].map(|v| v.map(f));
        [
            e[0],
            e[1],
            e[2],
            d[0],
            d[1],
            d[2],
            r[0],
            r[1],
            r[2],
            u[0],
            u[1],
            u[2],
            kind,
            extra,
            f(self.near),
            self.viewport[0],
            self.viewport[1],
            f(self.focal),
            f(self.slope[0]),
            f(self.slope[1]),
            f(self.side_norm[0]),
            f(self.side_norm[1]),
        ]
    }

    /// How far this camera is from `before`, for whatever lies within `sphere`: an upper
    /// bound of how far any point of the sphere moves in view coordinates between the two
    /// (`[0]`, model units), and of how far any direction of unit length turns (`[1]`: the
    /// largest stretch of the difference of the two rotations).
    ///
    /// With `M` a camera's rows (right, up, forward) and `e` its eye, a point `p = c + q`
    /// (`|q| <= r`) moves by `M'(p - e') - M(p - e) = (M' - M) q + (M'(c - e') - M(c - e))`,
    /// at most `‖M' - M‖ r + |to_view'(c) - to_view(c)|`; a direction `d` turns by
    /// `(M' - M) d`. Both are rounded up past their own roundings (a relative `2^-16`, and
    /// `2^-19` of the distances involved for the moves into view coordinates).
    ///
    /// **The stretch.** For two rotations `Q`, `Q'` it is `1/√2` of the difference's Frobenius
    /// norm: with `R = Q'ᵀ Q` a turn by `φ`, `‖Q' - Q‖ = ‖I - R‖ = 2 sin(φ/2)`, while
    /// `‖Q' - Q‖_F² = 6 - 2 tr R = 8 sin²(φ/2)`. A camera's rows are a rotation only to
    /// within their roundings, `M = Q + E` (each row normalised, or the cross product of two
    /// normalised ones: within a few `ε` of unit length and of right angles, so
    /// `‖E‖_F <= 2^-18` with room to spare), so `‖M' - M‖ <= ‖Q' - Q‖ + 2^-17 <=
    /// (‖M' - M‖_F + 2^-17) / √2 + 2^-17`.
    ///
    /// (The run time reads the two terms apart, [`shift_and_turn_from`](Self::shift_and_turn_from),
    /// to bound the moves of points nearer the centre; the tests read this whole.)
    #[cfg_attr(not(test), allow(dead_code))]
    pub(crate) fn moved_from(
        &self,
        before: &Camera,
        sphere: &crate::bound::BoundingSphere,
    ) -> [f32; 2] {
        let [shift, rho] = self.shift_and_turn_from(before, sphere);
        let delta = rho * sphere.radius * (1.0 + 1.0 / 65536.0) + shift;
        [delta, rho]
    }

    /// [`moved_from`](Self::moved_from) in two parts, `[shift, ρ]`: a point within `d <= r`
    /// of the sphere's centre moves by at most `ρ d (1 + 2^-16) + shift` (`shift`, the
    /// centre's move, with the roundings of both: the derivation is `moved_from`'s, with `d`
    /// for `r`).
    pub(crate) fn shift_and_turn_from(
        &self,
        before: &Camera,
        sphere: &crate::bound::BoundingSphere,
    ) -> [f32; 2] {
        let rows = |c: &Camera| [c.right, c.up, c.forward].map(Vec3::from_array);
        let (a, b) = (rows(before), rows(self));
        let squares: f32 = a
            .iter()
            .zip(&b)
            .map(|(x, y)| (*y - *x).length_squared())
            .sum();
        let frobenius = crate::math::sqrt_above(squares);
        let slack = 1.0 / 131_072.0;
        let rho = ((frobenius + slack) * core::f32::consts::FRAC_1_SQRT_2 + slack)
            * (1.0 + 1.0 / 65536.0);
        let c = sphere.center;
        let shift = (self.to_view(c) - before.to_view(c)).length();
        let reach = (c - self.eye()).length() + (c - before.eye()).length() + sphere.radius;
        let shift = shift * (1.0 + 1.0 / 65536.0) + reach / 524_288.0;
        [shift, rho]
    }

    /// A camera at `eye` looking at `target`, with `up` giving the screen's vertical.
    ///
    /// `near` is the distance of the near clipping plane (perspective: positive; orthographic:
    /// at least 0, measured from the eye).
    pub fn new(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        projection: Projection,
        near: f32,
        viewport: [u32; 2],
    ) -> Result<Self, CameraError> {
        let extra = match projection {
            Projection::Perspective { fov_y_degrees } => fov_y_degrees,
            Projection::Orthographic { height } => height,
        };
        let finite = eye.is_finite()
            && target.is_finite()
            && up.is_finite()
            && extra.is_finite()
            && near.is_finite();
        if !finite {
            return Err(CameraError::NotFinite);
        }
        if viewport[0] == 0 || viewport[1] == 0 {
            return Err(CameraError::EmptyViewport);
        }
        let forward = normalize(target - eye).ok_or(CameraError::EyeAtTarget)?;
        let right = normalize(forward.cross(up)).ok_or(CameraError::BadUp)?;
        let true_up = right.cross(forward);
        let (w, h) = (viewport[0] as f32, viewport[1] as f32);
        let (focal, slope) = match projection {
            Projection::Perspective { fov_y_degrees } => {
                if !(fov_y_degrees > 0.0 && fov_y_degrees < 180.0) {
                    return Err(CameraError::BadProjection);
                }
                if near <= 0.0 {
                    return Err(CameraError::BadNear);
                }
                let half = libm::tanf(fov_y_degrees.to_radians() * 0.5);
                let focal = 0.5 * h / half;
                (focal, [0.5 * w / focal, half])
            }
            Projection::Orthographic { height } => {
                if height <= 0.0 {
                    return Err(CameraError::BadProjection);
                }
                if near < 0.0 {
                    return Err(CameraError::BadNear);
                }
                (h / height, [0.0, 0.0])
            }
        };
        if !(focal.is_finite() && focal > 0.0) {
            return Err(CameraError::BadProjection);
        }
        Ok(Camera {
            eye: eye.to_array(),
            forward: forward.to_array(),
            right: right.to_array(),
            up: true_up.to_array(),
            projection,
            near,
            viewport,
            focal,
            slope,
            side_norm: match projection {
                Projection::Perspective { .. } => slope.map(|s| sqrt(1.0 + s * s)),
                Projection::Orthographic { .. } => [1.0; 2],
            },
            corner_ray: crate::math::sqrt_above(1.0 + slope[0] * slope[0] + slope[1] * slope[1]),
            centre: [0.5 * w, 0.5 * h],
        })
    }

    /// The eye position.
    pub fn eye(&self) -> Vec3 {
        Vec3::from_array(self.eye)
    }

    /// Unit view direction.
    pub fn forward(&self) -> Vec3 {
        Vec3::from_array(self.forward)
    }

    /// The projection.
    pub fn projection(&self) -> Projection {
        self.projection
    }

    /// Near plane distance.
    pub fn near(&self) -> f32 {
        self.near
    }

    /// Viewport `[width, height]` in pixels.
    pub fn viewport(&self) -> [u32; 2] {
        self.viewport
    }

    /// `p` in view coordinates: `(right, up, depth)` relative to the eye.
    pub fn to_view(&self, p: Vec3) -> Vec3 {
        self.rotate_to_view(p - self.eye())
    }

    /// Pixels per unit of screen slope (perspective) or per object unit (orthographic).
    pub(crate) fn focal(&self) -> f32 {
        self.focal
    }

    /// Largest visible `|x/z|` and `|y/z|` (perspective), and the lengths of the side planes'
    /// normals `(1, -s)` by which a distance beyond them is divided.
    pub(crate) fn side_planes(&self) -> ([f32; 2], [f32; 2]) {
        (self.slope, self.side_norm)
    }

    /// At least the length of the ray `(s_x, s_y, 1)` through a corner of the view, the
    /// slopes of [`side_planes`](Self::side_planes) (perspective; 1 orthographic).
    pub(crate) fn corner_ray(&self) -> f32 {
        self.corner_ray
    }

    /// The rotation into view coordinates by its rows: the right, up and forward unit
    /// vectors in model coordinates (each within a few `ε` of unit length).
    pub(crate) fn view_rows(&self) -> [[f32; 3]; 3] {
        [self.right, self.up, self.forward]
    }

    /// Direction `d` in view coordinates (rotation only).
    pub(crate) fn rotate_to_view(&self, d: Vec3) -> Vec3 {
        Vec3::new(
            d.dot(Vec3::from_array(self.right)),
            d.dot(Vec3::from_array(self.up)),
            d.dot(self.forward()),
        )
    }

    /// Direction `d` given in view coordinates, in model coordinates (the rotation back).
    #[cfg(feature = "embedded-graphics")]
    pub(crate) fn rotate_from_view(&self, d: Vec3) -> Vec3 {
        Vec3::from_array(self.right) * d.x + Vec3::from_array(self.up) * d.y + self.forward() * d.z
    }

    /// Pixel coordinates of `p` (x to the right, y down, origin at the top-left corner);
    /// `None` when `p` is closer than the near plane.
    pub fn project(&self, p: Vec3) -> Option<[f32; 2]> {
        let v = self.to_view(p);
        if v.z.is_nan() || v.z < self.near {
            return None;
        }
        Some(self.view_to_pixel(v))
    }

    /// The pixel row of `p`, `project(p)`'s second coordinate, the same bits (without the
    /// view's `x`, which a row does not need: where `f32` is software, a third fewer calls).
    #[cfg(feature = "embedded-graphics")]
    pub(crate) fn project_row(&self, p: Vec3) -> Option<f32> {
        let d = p - self.eye();
        let (y, z) = (d.dot(Vec3::from_array(self.up)), d.dot(self.forward()));
        if z.is_nan() || z < self.near {
            return None;
        }
        let s = match self.projection {
            Projection::Perspective { .. } => self.focal / z,
            Projection::Orthographic { .. } => self.focal,
        };
        Some(self.centre[1] - y * s)
    }

    /// Pixel coordinates of a point given in view coordinates (in front of the eye).
    pub(crate) fn view_to_pixel(&self, v: Vec3) -> [f32; 2] {
        let s = match self.projection {
            Projection::Perspective { .. } => self.focal / v.z,
            Projection::Orthographic { .. } => self.focal,
        };
        [self.centre[0] + v.x * s, self.centre[1] - v.y * s]
    }

    #[cfg(feature = "embedded-graphics")]
    /// Half the viewport's extent in view space: slopes `x/z`, `y/z` at its edges
    /// (perspective) or object units (orthographic).
    pub(crate) fn half_extent(&self) -> [f32; 2] {
        match self.projection {
            Projection::Perspective { .. } => self.slope,
            Projection::Orthographic { .. } => [
                0.5 * self.viewport[0] as f32 / self.focal,
                0.5 * self.viewport[1] as f32 / self.focal,
            ],
        }
    }
}

/// What the tessellation must achieve in a frame.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum View {
    /// On-screen error at most `tolerance_px` pixels for `camera`; patches outside the view
    /// are culled.
    Screen {
        /// The camera.
        camera: Camera,
        /// Largest allowed projected deviation, in pixels.
        tolerance_px: f32,
    },
    /// Object-space deviation at most `tolerance` everywhere, nothing culled (for tests and
    /// for users that do not display).
    Object {
        /// Largest allowed deviation, in model units.
        tolerance: f32,
    },
}

impl View {
    /// The tolerance as given: pixels for [`View::Screen`], model units for [`View::Object`].
    pub fn tolerance(&self) -> f32 {
        match self {
            View::Screen { tolerance_px, .. } => *tolerance_px,
            View::Object { tolerance } => *tolerance,
        }
    }

    /// The same view with another tolerance.
    pub fn with_tolerance(self, t: f32) -> View {
        match self {
            View::Screen { camera, .. } => View::Screen {
                camera,
                tolerance_px: t,
            },
            View::Object { .. } => View::Object { tolerance: t },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bound::BoundingSphere;
    use crate::test_rng::TestRng;

    /// A point's pixel row is its projection's, bit for bit, and `None` where that is.
    #[cfg(feature = "embedded-graphics")]
    #[test]
    fn a_row_is_the_projections_row() {
        let mut rng = TestRng::new(0x20_77);
        let mut r = |k: i64| rng.signed(k) as f32 / 100.0;
        for case in 0..2_000 {
            let projection = match case % 2 {
                0 => Projection::Perspective {
                    fov_y_degrees: 40.0,
                },
                _ => Projection::Orthographic { height: 3.0 },
            };
            let eye = Vec3::new(r(900), r(900), r(900));
            let Ok(camera) = Camera::new(
                eye,
                Vec3::new(r(50), r(50), r(50)),
                Vec3::Z,
                projection,
                0.1,
                [240, 160],
            ) else {
                continue;
            };
            for _ in 0..20 {
                let p = Vec3::new(r(900), r(900), r(900));
                let row = camera.project_row(p).map(f32::to_bits);
                assert_eq!(row, camera.project(p).map(|[_, y]| y.to_bits()), "{p}");
            }
        }
    }

    /// A camera's rows and eye in `f64`.
    fn exact(c: &Camera) -> ([[f64; 3]; 3], [f64; 3]) {
        let row = |r: [f32; 3]| r.map(f64::from);
        (
            [row(c.right), row(c.up), row(c.forward)],
            c.eye().to_array().map(f64::from),
        )
    }

    /// `moved_from` bounds every move: of random points of the sphere in view coordinates and
    /// of random unit directions, measured in `f64`, over random steps (turns of the eye about
    /// the target from a hundredth of a degree to a right angle, slides, rolls of the up
    /// vector); the turn's bound is within a few percent of the largest turn found (the
    /// difference's largest stretch, not its Frobenius norm, `√2` times more).
    #[test]
    fn a_step_moves_no_point_and_turns_no_direction_further_than_it_says() {
        let mut rng = TestRng::new(0x5eed_1234_abcd_0001);
        let unit = |rng: &mut TestRng| rng.signed(1 << 20) as f32 / (1 << 20) as f32;
        let sphere = BoundingSphere {
            center: Vec3::new(0.3, -0.2, 1.1),
            radius: 2.5,
        };
        let (mut closest, mut worst_ratio) = (0.0f64, 0.0f64);
        for k in 0..400 {
            let target = sphere.center + Vec3::new(unit(&mut rng), unit(&mut rng), 0.0);
            let eye = Vec3::new(9.0 * unit(&mut rng) + 10.0, 6.0 * unit(&mut rng), 4.0);
            let angle = 10f32
                .powf(-2.0 + 4.0 * (unit(&mut rng) + 1.0) / 2.0)
                .to_radians();
            let (s, c) = angle.sin_cos();
            let about = eye - target;
            let turned = target
                + Vec3::new(
                    c * about.x - s * about.y,
                    s * about.x + c * about.y,
                    about.z,
                );
            let slide =
                Vec3::new(unit(&mut rng), unit(&mut rng), unit(&mut rng)) * 0.1 * (k % 3) as f32;
            let up = Vec3::new(0.2 * unit(&mut rng) * (k % 2) as f32, 0.0, 1.0);
            let lens = Projection::Perspective {
                fov_y_degrees: 40.0,
            };
            let before = Camera::new(eye, target, Vec3::Z, lens, 0.05, [320, 240]).unwrap();
            let after = Camera::new(turned + slide, target, up, lens, 0.05, [320, 240]).unwrap();
            let [delta, rho] = after.moved_from(&before, &sphere);
            let ((m0, e0), (m1, e1)) = (exact(&before), exact(&after));
            let view = |m: &[[f64; 3]; 3], e: &[f64; 3], p: [f64; 3]| {
                let q = [p[0] - e[0], p[1] - e[1], p[2] - e[2]];
                m.map(|r| r[0] * q[0] + r[1] * q[1] + r[2] * q[2])
            };
            let length = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            let mut turn = 0.0f64;
            for _ in 0..64 {
                let d = [unit(&mut rng), unit(&mut rng), unit(&mut rng)].map(f64::from);
                let n = length(d);
                if n < 1e-3 {
                    continue;
                }
                let d = d.map(|x| x / n);
                let (a, b) = (view(&m0, &[0.0; 3], d), view(&m1, &[0.0; 3], d));
                turn = turn.max(length([b[0] - a[0], b[1] - a[1], b[2] - a[2]]));
                let r = f64::from(sphere.radius) * f64::from(unit(&mut rng)).abs();
                let p = sphere.center.to_array().map(f64::from);
                let p = [p[0] + r * d[0], p[1] + r * d[1], p[2] + r * d[2]];
                let (a, b) = (view(&m0, &e0, p), view(&m1, &e1, p));
                let moved = length([b[0] - a[0], b[1] - a[1], b[2] - a[2]]);
                assert!(
                    moved <= f64::from(delta),
                    "step {k}: a point moved {moved}, bound {delta}"
                );
            }
            assert!(
                turn <= f64::from(rho),
                "step {k}: a direction turned {turn}, bound {rho}"
            );
            if turn > 1e-3 {
                let ratio = f64::from(rho) / turn;
                closest = if closest == 0.0 {
                    ratio
                } else {
                    closest.min(ratio)
                };
                worst_ratio = worst_ratio.max(ratio);
            }
        }
        // Tight: some step's bound within 1% of a turn found, none far above (64 random
        // directions miss the largest stretch by a little).
        assert!(
            closest < 1.01 && worst_ratio < 1.3,
            "{closest} {worst_ratio}"
        );
    }
}
