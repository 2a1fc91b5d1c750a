// The views of the tessellation firmware (`fw_bisect`) and the checksum of its meshes, shared (through `#[path]`) by the firmware and the host test that writes the
// expected checksums (host-tests/tests/firmware_data.rs). `no_std`, no allocation.
// Hand-written.

use spline_tess::{Camera, Projection, Vec3, Vertex, View};

/// Viewport of the display.
pub const VIEWPORT: [u32; 2] = [240, 240];

/// The frames: eye, tolerance in pixels. All look at the teapot's middle.
pub const FRAMES: [([f32; 3], f32); 4] = [
    ([9.0, -12.0, 7.0], 1.0),
    ([9.2, -11.85, 7.0], 1.0),
    ([5.0, -6.5, 4.0], 1.0),
    ([5.0, -6.5, 4.0], 0.5),
];

/// The view of frame `k`.
pub fn view(k: usize) -> Option<View> {
    let (eye, tol) = FRAMES.get(k).copied()?;
    let camera = Camera::new(
        Vec3::from_array(eye),
        Vec3::new(0.0, 0.0, 1.5),
        Vec3::Z,
        Projection::Perspective {
            fov_y_degrees: 40.0,
        },
        0.1,
        VIEWPORT,
    )
    .ok()?;
    Some(View::Screen {
        camera,
        tolerance_px: tol,
    })
}

/// FNV-1a over 32-bit words.
pub struct Fnv(pub u32);

impl Fnv {
    /// Mixes one word in.
    pub fn word(&mut self, w: u32) {
        for b in w.to_le_bytes() {
            self.0 = (self.0 ^ b as u32).wrapping_mul(0x0100_0193);
        }
    }
}

/// Checksum of an indexed mesh: every vertex's bits, then every index.
pub fn checksum(vertices: &[Vertex], triangles: &[[u16; 3]]) -> u32 {
    let mut h = Fnv(0x811c_9dc5);
    for v in vertices {
        for x in v.position.iter().chain(&v.normal).chain(&v.uv) {
            h.word(x.to_bits());
        }
        h.word(v.patch);
    }
    for t in triangles {
        for &i in t {
            h.word(i as u32);
        }
    }
    h.0
}
