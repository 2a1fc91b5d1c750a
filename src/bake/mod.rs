//! The bake: a model's hierarchy of halvings, each triangle with its bound (see
//! [`bake_hierarchy`]), and the hierarchy as Rust source for a firmware
//! ([`write_rust_source`]).

mod cells;
mod encode;
mod hierarchy;
mod orientation;
mod runner;
mod rust_source;

pub use encode::{encode_hierarchy, encode_scratch_len, EncodeError};
pub use hierarchy::{
    bake_hierarchy, bake_hierarchy_with, bake_hierarchy_with_progress, BakeBuffers, BakeError,
    BakeProgress, BakeScratch, BakeSettings, BakeSize,
};
#[cfg(all(feature = "std", not(target_os = "none")))]
pub use runner::Parallel;
pub use runner::{BakeRunner, InOrder};
pub use rust_source::write_rust_source;

/// The bake tolerance: the deviation at which halving stops.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Tolerance {
    /// In object-space units.
    Absolute(f32),
    /// As a fraction of the diagonal of the model's control-point bounding box.
    Relative(f32),
}

impl Tolerance {
    /// The tolerance in model units, for a model whose control-point bounding box has
    /// diagonal `diagonal`.
    pub(crate) fn in_model_units(self, diagonal: f32) -> f32 {
        match self {
            Tolerance::Absolute(t) => t,
            Tolerance::Relative(r) => r * diagonal,
        }
    }
}
