//! What a caller sets for the run time: the refinement cap, the storage cap on interior
//! samples, and back-patch culling.

/// Largest refinement factor (a refined triangle has at most `MAX_FACTOR²` pieces plus
/// `3 MAX_FACTOR` along its sides); [`Settings::max_factor`] is capped here.
pub const MAX_FACTOR: u8 = 64;

/// Run-time settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Settings {
    /// Interior samples per patch the storage holds, at most (the rest of a patch's list is
    /// never used; refinement takes over).
    pub max_interior_samples: u16,
    /// Largest refinement factor of a triangle (1 turns refinement off; values above
    /// [`MAX_FACTOR`] count as it).
    pub max_factor: u8,
    /// Whether patches that show the eye only their back are left out.
    pub back_patches: BackPatches,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            max_interior_samples: u16::MAX,
            max_factor: MAX_FACTOR,
            back_patches: BackPatches::CullWhenClosed,
        }
    }
}

/// Whether a frame leaves out the patches that face away from the eye.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum BackPatches {
    /// Left out where that hides nothing. Checked once, when the tessellator is made: the model is
    /// closed (every boundary curve shared by exactly two patch edges), the two patches along every
    /// curve have their normals `S_u × S_v` on the same side, and the sign of the enclosed volume
    /// (by quadrature, taken only when it is at least 1% of the integral of its absolute value)
    /// says which side is out
    /// ([`Tessellator::culls_back_patches`](super::Tessellator::culls_back_patches) tells). Checked
    /// per frame: the model's bounding sphere lies wholly beyond the near plane (so the eye is
    /// outside and nothing cuts the surface open). Then a patch whose outward
    /// [`NormalCone`](crate::NormalCone) faces away from the eye at every control point is culled
    /// like one off the view
    /// ([`FrameStats::back_facing_patches`](super::FrameStats::back_facing_patches)). Drawn
    /// otherwise.
    #[default]
    CullWhenClosed,
    /// Always drawn.
    Draw,
}
