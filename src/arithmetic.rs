//! Which arithmetic the per-triangle work takes: `f32`, or integers where `f32` is software.

/// How the kernel does its per-triangle arithmetic: in `f32`, or in integers, for parts
/// without an FPU.
///
/// Three parts of a frame take it:
///
/// - **The tessellator's bounds** ([`Tessellator::with_arithmetic`]): a triangle's directional
///   bound on screen from its node's six-bit kept vectors, rotated into the view in `f32`, or
///   read as integers against each ray of the view in 22-bit fixed point. Both are bounds
///   (derived in the crate's `deviation` module); the integer one is above the float one by
///   about `2^-21` of a vector's length, and the two took the same triangles on every view
///   of the crate's soundness tests and of `fw_teapot`. Over a hierarchy's bytes the judged
///   triangles' corners are moved into the view in integers too, from their points on the
///   model box's grid (30-bit by 16-bit products, summed in 64 bits): within a
///   hundred-thousandth of the model's size of the float corners, which the bounds take as
///   more slack (on a host, and where `f32` is software; a bare-metal part with an FPU leaves
///   that code out). From those corners each judged triangle is first looked at in integers:
///   whether a corner is in view of every plane, and whether a linear test in 64-bit
///   integers proves the isotropic bound within the tolerance. It decides as the `f32`
///   judgement would (the frames are the same), and most triangles within need no `f32`
///   operation but the quotient of their bound.
/// - **The rasteriser's planes** (`render::Renderer::with_arithmetic`, feature
///   `embedded-graphics`): a triangle's depth and shade across its pixels, set up from the
///   corners' depth keys and shade levels in `f32` and then in fixed point, or in integers
///   alone, exact but for the last fixed-point bit of each step. Both give each pixel its
///   plane's value at the pixel's centre to within a few hundred `2^-14` of a depth key and
///   `2^-16` of a shade level across a triangle a few hundred pixels wide, so their pictures
///   differ at most where two surfaces meet within that (a few pixels of a frame, where at
///   all). Triangles with a corner beyond 512 pixels (feature `large-viewports`) take `f32`
///   spans either way.
/// - **The renderer's corners** (the same choice): each vertex's view position, shade, clip
///   test and pixel, in `f32`, or in integer products and two divisions, with the view's
///   rotation in 16 bits around the source's bounding sphere. A tessellator's vertex of a
///   hierarchy's bytes is read there, from its point on the model box's grid and its
///   normal's octahedral code (its inverse length from a table and one Newton step), with
///   no `f32` decoding (on a host, and where `f32` is software; a bare-metal part with an
///   FPU leaves that code out and reads the bits of the `f32` vertex, as for any other
///   source). An integer corner lies
///   within `2^-11` of the sphere's radius of the exact one in view space, and its pixel
///   within a sixteenth or two of the float one's, so a frame's picture moves by that along
///   its edges (0.15% of `fw_teapot` frame 0's pixels changed hands); a vertex keeps one
///   position for every triangle that has it, so the mesh stays closed. An orthographic
///   view, or a viewport side over 1,024 pixels, takes `f32` corners either way. On ARMv6-M
///   it takes about 30% off `fw_teapot`'s render.
///
/// Judgements kept from frame to frame (`Tessellator::with_reuse`, feature `reuse`) keep no
/// certificate for a triangle of the bake whose bound was computed in integers: a certificate
/// bounds the float bound over a camera step, which the integer one may stand above by its
/// roundings. Such judgements are made again every frame, and the frames stay the view's own.
///
/// The default follows the target: a host takes [`Arithmetic::Integer`] to find and draw the
/// frames that a part without an FPU finds and draws, bit for bit.
///
/// ```
/// use spline_tess::Arithmetic;
///
/// // `f32` is hardware on a host.
/// assert_eq!(Arithmetic::default(), Arithmetic::Float);
/// ```
///
/// [`Tessellator::with_arithmetic`]: crate::Tessellator::with_arithmetic
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Arithmetic {
    /// In `f32`: the cheaper where `f32` is hardware, and the default there.
    Float,
    /// In integers: the default where `f32` is software (ARMv6-M, RV32IMC), where it takes
    /// most of the soft-float calls out of a frame (README: *Firmware*).
    Integer,
}

impl Default for Arithmetic {
    /// [`Arithmetic::Float`] where `f32` is hardware, [`Arithmetic::Integer`] where it is
    /// software.
    fn default() -> Self {
        if crate::math::HARD_FLOAT {
            Arithmetic::Float
        } else {
            Arithmetic::Integer
        }
    }
}
