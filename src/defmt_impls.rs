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

/// An `embedded-graphics` colour as `rgb(r, g, b)` (embedded-graphics implements the older
/// defmt 0.3 only).
#[cfg(feature = "embedded-graphics")]
struct Rgb(embedded_graphics::pixelcolor::Rgb888);

#[cfg(feature = "embedded-graphics")]
impl defmt::Format for Rgb {
    fn format(&self, f: defmt::Formatter<'_>) {
        use embedded_graphics::pixelcolor::RgbColor;
        defmt::write!(f, "rgb({}, {}, {})", self.0.r(), self.0.g(), self.0.b())
    }
}

#[cfg(feature = "embedded-graphics")]
impl defmt::Format for crate::render::Wireframe {
    fn format(&self, f: defmt::Formatter<'_>) {
        defmt::write!(
            f,
            "Wireframe {{ color: {}, half_width: {} }}",
            Rgb(self.color),
            self.half_width
        )
    }
}

#[cfg(feature = "embedded-graphics")]
impl defmt::Format for crate::render::Style {
    fn format(&self, f: defmt::Formatter<'_>) {
        defmt::write!(
            f,
            "Style {{ shading: {}, light: {}, color: {}, wireframe: {}, background: {} }}",
            self.shading,
            self.light,
            Rgb(self.color),
            self.wireframe,
            self.background.map(Rgb)
        )
    }
}
