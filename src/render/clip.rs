//! Clipping a triangle in view space, before projection.
//!
//! The near plane is a real clip (nothing in front of it can be projected). The four side
//! planes sit at twice the viewport's half-extent (a guard band): they only keep projected
//! coordinates small enough for the fixed-point edge functions, and the pixels outside the
//! viewport are cut by the rasteriser.

use glam::Vec3;

/// Guard band: side planes at this multiple of the viewport's half-extent.
const GUARD: f32 = 2.0;

/// Corners a triangle can have after five planes.
pub(crate) const MAX_CORNERS: usize = 8;

/// A corner in view space with its shade.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct ClipVertex {
    pub view: Vec3,
    pub shade: f32,
}

/// A clipped polygon: corners, and whether the edge from corner `k` to `k + 1` lies on the
/// original triangle's edge that was marked for the wireframe.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Polygon {
    pub corners: [ClipVertex; MAX_CORNERS],
    pub wire: [bool; MAX_CORNERS],
    pub len: usize,
}

/// The five planes as `n · v + d >= 0`, from the near distance and the side planes' slopes
/// (object units with an orthographic camera): each plane is made where it is asked for, so
/// that a renderer's set-up keeps 16 bytes on the stack rather than 96.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Frustum {
    near: f32,
    sides: [f32; 2],
    perspective: bool,
}

/// The planes of a [`Frustum`].
const PLANES: usize = 5;

impl Frustum {
    /// The clip planes for near distance `near` and half-extent `half` (slopes when
    /// `perspective`, object units otherwise).
    pub fn new(near: f32, half: [f32; 2], perspective: bool) -> Frustum {
        Frustum {
            near,
            sides: half.map(|h| GUARD * h),
            perspective,
        }
    }

    /// Plane `k` (below [`PLANES`]).
    fn plane(&self, k: usize) -> (Vec3, f32) {
        let [sx, sy] = self.sides;
        match (self.perspective, k) {
            (_, 0) => (Vec3::Z, -self.near),
            (true, 1) => (Vec3::new(-1.0, 0.0, sx), 0.0),
            (true, 2) => (Vec3::new(1.0, 0.0, sx), 0.0),
            (true, 3) => (Vec3::new(0.0, -1.0, sy), 0.0),
            (true, _) => (Vec3::new(0.0, 1.0, sy), 0.0),
            (false, 1) => (Vec3::new(-1.0, 0.0, 0.0), sx),
            (false, 2) => (Vec3::new(1.0, 0.0, 0.0), sx),
            (false, 3) => (Vec3::new(0.0, -1.0, 0.0), sy),
            (false, _) => (Vec3::new(0.0, 1.0, 0.0), sy),
        }
    }

    fn distance(&self, k: usize, v: Vec3) -> f32 {
        let (n, d) = self.plane(k);
        n.dot(v) + d
    }

    /// Whether `v` is on the inner side of every plane (a triangle whose corners all are needs
    /// no clipping: [`clip`](Self::clip) would return it unchanged).
    pub fn contains(&self, v: Vec3) -> bool {
        match self.perspective {
            // The planes' distances without their products by 0 and 1 (where `f32` is
            // software, each costs a call): `(-x + 0 y) + s z` is `s z - x` exactly, and a
            // coordinate that is not finite fails a plane either way (`0 · ∞` is NaN in the
            // products; here the plane of that coordinate is not finite or NaN).
            true => {
                let (near, [sx, sy]) = (self.near, self.sides);
                let (x, y, z) = (v.x, v.y, v.z);
                let (ax, ay) = (sx * z, sy * z);
                z - near >= 0.0 && ax - x >= 0.0 && ax + x >= 0.0 && ay - y >= 0.0 && ay + y >= 0.0
            }
            false => (0..PLANES).all(|k| self.distance(k, v) >= 0.0),
        }
    }

    /// Clips triangle `t`; `wire[i]` marks the edge from corner `i` to `i + 1`. An empty
    /// polygon (`len < 3`) when nothing is left.
    pub fn clip(&self, t: [ClipVertex; 3], wire: [bool; 3]) -> Polygon {
        let mut poly = Polygon::default();
        poly.corners[..3].copy_from_slice(&t);
        poly.wire[..3].copy_from_slice(&wire);
        poly.len = 3;
        for k in 0..PLANES {
            let inside = poly.corners[..poly.len]
                .iter()
                .all(|c| self.distance(k, c.view) >= 0.0);
            if inside {
                continue;
            }
            let mut out = Polygon::default();
            for i in 0..poly.len {
                let (a, b) = (poly.corners[i], poly.corners[(i + 1) % poly.len]);
                let (da, db) = (self.distance(k, a.view), self.distance(k, b.view));
                if da >= 0.0 {
                    push(&mut out, a, poly.wire[i]);
                }
                if (da >= 0.0) != (db >= 0.0) {
                    let s = da / (da - db);
                    let c = ClipVertex {
                        view: a.view + (b.view - a.view) * s,
                        shade: a.shade + (b.shade - a.shade) * s,
                    };
                    // Entering: the new edge continues the old one; leaving: it runs
                    // along the plane.
                    push(&mut out, c, da < 0.0 && poly.wire[i]);
                }
            }
            poly = out;
            if poly.len < 3 {
                poly.len = 0;
                break;
            }
        }
        poly
    }
}

fn push(p: &mut Polygon, c: ClipVertex, wire: bool) {
    if p.len < MAX_CORNERS {
        p.corners[p.len] = c;
        p.wire[p.len] = wire;
        p.len += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(x: f32, y: f32, z: f32) -> ClipVertex {
        ClipVertex {
            view: Vec3::new(x, y, z),
            shade: z,
        }
    }

    /// `contains` says what the five planes' distances say, for points inside, outside, on
    /// the planes and not finite, with either projection.
    #[test]
    fn containment_is_the_planes_test() {
        let mut rng = crate::test_rng::TestRng::new(0xc1_1b);
        let special = [
            0.0,
            -0.0,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            1e30,
            -1e-30,
        ];
        for perspective in [true, false] {
            let f = Frustum::new(0.25, [0.75, 0.5], perspective);
            for k in 0..20_000 {
                let mut c = [0; 3].map(|_| rng.signed(1 << 12) as f32 / 1024.0);
                if k % 5 == 0 {
                    c[k % 3] = special[k % special.len()];
                }
                if k % 7 == 0 {
                    // On a side plane, or the near plane.
                    c[0] = 1.5 * c[2];
                    c[2] = if k % 2 == 0 { 0.25 } else { c[2] };
                }
                let v = Vec3::from_array(c);
                let planes = (0..5).all(|k| f.distance(k, v) >= 0.0);
                assert_eq!(f.contains(v), planes, "{v:?}, perspective {perspective}");
            }
        }
    }

    #[test]
    fn a_triangle_inside_is_unchanged() {
        let f = Frustum::new(0.1, [1.0, 1.0], true);
        let t = [at(0.0, 0.0, 1.0), at(0.5, 0.0, 1.0), at(0.0, 0.5, 2.0)];
        let p = f.clip(t, [true, false, true]);
        assert_eq!(p.len, 3);
        assert_eq!(&p.corners[..3], &t);
        assert_eq!(&p.wire[..3], &[true, false, true]);
    }

    #[test]
    fn the_near_plane_cuts_a_corner_off() {
        let f = Frustum::new(1.0, [1.0, 1.0], true);
        let t = [at(0.0, 0.0, 0.5), at(0.5, 0.0, 2.0), at(-0.5, 0.0, 2.0)];
        let p = f.clip(t, [true; 3]);
        assert_eq!(p.len, 4);
        for c in &p.corners[..4] {
            assert!(c.view.z >= 1.0 - 1e-6);
            // Shade is interpolated with the position (here it equals z).
            assert!((c.shade - c.view.z).abs() < 1e-6);
        }
        // The edge along the near plane is not a wireframe edge.
        assert_eq!(p.wire[..4].iter().filter(|&&w| w).count(), 3);
    }

    #[test]
    fn a_triangle_behind_the_eye_vanishes() {
        let f = Frustum::new(0.1, [1.0, 1.0], true);
        let t = [at(0.0, 0.0, -1.0), at(1.0, 0.0, -1.0), at(0.0, 1.0, -2.0)];
        assert_eq!(f.clip(t, [true; 3]).len, 0);
    }

    #[test]
    fn the_guard_band_bounds_the_slopes() {
        let f = Frustum::new(0.1, [0.5, 0.5], true);
        let t = [
            at(-100.0, 0.0, 1.0),
            at(100.0, 0.0, 1.0),
            at(0.0, 100.0, 1.0),
        ];
        let p = f.clip(t, [true; 3]);
        assert!(p.len >= 3);
        for c in &p.corners[..p.len] {
            assert!(c.view.x.abs() <= GUARD * 0.5 + 1e-4 && c.view.y.abs() <= GUARD * 0.5 + 1e-4);
        }
    }
}
