//! What the renderer draws with: shading, light, surface colour, wireframe and background.

use embedded_graphics::pixelcolor::Rgb888;

/// How a triangle's colour varies.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Shading {
    /// One shade per triangle, from its geometric normal.
    Flat,
    /// Shades at the corners from the vertex normals, interpolated across.
    #[default]
    Gouraud,
}

/// A directional light, fixed to the camera.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Light {
    /// Direction towards the light in view coordinates: x right, y up, z away from the eye.
    /// Need not be unit length; zero means a headlight.
    pub direction: [f32; 3],
    /// Shade of a surface facing away from the light, in `[0, 1]`.
    pub ambient: f32,
}

impl Default for Light {
    /// From above left of the eye, with 0.2 ambient.
    fn default() -> Self {
        Light {
            direction: [-0.4, 0.6, -0.7],
            ambient: 0.2,
        }
    }
}

/// Triangle edges drawn over the shading.
///
/// (With feature `defmt`, this and [`Style`] implement `defmt::Format` by hand:
/// `embedded-graphics` colours support only the older defmt.)
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wireframe {
    /// Line colour.
    pub color: Rgb888,
    /// Pixels within this distance of an edge, on either side, take the line colour (0.5 gives
    /// lines about one pixel wide).
    pub half_width: f32,
}

/// What the renderer draws with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Style {
    /// Flat or Gouraud.
    pub shading: Shading,
    /// The light.
    pub light: Light,
    /// Surface colour at full light.
    pub color: Rgb888,
    /// Edges to overlay, if any.
    pub wireframe: Option<Wireframe>,
    /// Colour for the pixels no triangle covers; `None` leaves them untouched (clear the
    /// target first).
    pub background: Option<Rgb888>,
}

impl Default for Style {
    /// Gouraud, the default light, a light grey surface, no wireframe, no background.
    fn default() -> Self {
        Style {
            shading: Shading::Gouraud,
            light: Light::default(),
            color: Rgb888::new(230, 230, 230),
            wireframe: None,
            background: None,
        }
    }
}
