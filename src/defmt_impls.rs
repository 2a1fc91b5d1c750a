//! `defmt::Format` for the public types that hold `glam` vectors (glam has no defmt support).

use glam::Vec3;

use crate::bound::{Aabb, BoundingSphere};
use crate::frame::SurfacePoint;

struct V(Vec3);

impl defmt::Format for V {
    fn format(&self, f: defmt::Formatter<'_>) {
        defmt::write!(f, "({}, {}, {})", self.0.x, self.0.y, self.0.z)
    }
}

impl defmt::Format for SurfacePoint {
    fn format(&self, f: defmt::Formatter<'_>) {
        defmt::write!(
            f,
            "SurfacePoint {{ position: {}, partial_u: {}, partial_v: {}, normal: {} }}",
            V(self.position),
            V(self.partial_u),
            V(self.partial_v),
            V(self.normal)
        )
    }
}

impl defmt::Format for Aabb {
    fn format(&self, f: defmt::Formatter<'_>) {
        defmt::write!(f, "Aabb {{ min: {}, max: {} }}", V(self.min), V(self.max))
    }
}

impl defmt::Format for BoundingSphere {
    fn format(&self, f: defmt::Formatter<'_>) {
        defmt::write!(
            f,
            "BoundingSphere {{ center: {}, radius: {} }}",
            V(self.center),
            self.radius
        )
    }
}
