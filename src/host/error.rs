//! Why a host step failed: the kernel's own error of the step, or the file system's.

use core::fmt;
use std::io;

use crate::bake::{BakeError, EncodeError};
use crate::parse::{BptError, NurbsJsonError};
use crate::tessellator::{FormatError, HierarchyError, LinkError, TessellatorError, UpdateError};
use crate::{DecomposeError, PatchSetError, TopologyError, WriteError};

/// Why a step of [`host`](super) failed.
#[derive(Debug)]
#[non_exhaustive]
pub enum HostError {
    /// Reading or writing a file.
    Io(io::Error),
    /// The bytes are neither BPT text nor NURBS JSON (not UTF-8).
    NotText,
    /// Patches of one's own came with a rectangle of parameters for other than each.
    Domains {
        /// Patches.
        patches: usize,
        /// Rectangles.
        domains: usize,
    },
    /// A BPT text does not parse.
    Bpt(BptError),
    /// A NURBS JSON text does not parse.
    NurbsJson(NurbsJsonError),
    /// A NURBS surface does not decompose into Bezier patches.
    Decompose(DecomposeError),
    /// The patches are not a valid patch set.
    Patches(PatchSetError),
    /// The patches' shared curves do not make a model.
    Topology(TopologyError),
    /// The bake failed.
    Bake(BakeError),
    /// The bake's bytes could not be written.
    Encode(EncodeError),
    /// A bake's bytes (a cache file's, say) are not a hierarchy of these surfaces.
    Format(FormatError),
    /// A bake's records do not hold together.
    Hierarchy(HierarchyError),
    /// A hierarchy's links could not be filled.
    Links(LinkError),
    /// The tessellator's storage does not fit the hierarchy.
    Tessellator(TessellatorError),
    /// The view cannot be tessellated.
    Update(UpdateError),
    /// The mesh could not be written out.
    Write(WriteError),
}

impl fmt::Display for HostError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            HostError::Io(e) => write!(f, "{e}"),
            HostError::NotText => write!(f, "the model is not text (BPT or NURBS JSON)"),
            HostError::Domains { patches, domains } => {
                write!(f, "{patches} patches with {domains} parameter rectangles")
            }
            HostError::Bpt(e) => write!(f, "BPT: {e}"),
            HostError::NurbsJson(e) => write!(f, "NURBS JSON: {e}"),
            HostError::Decompose(e) => write!(f, "NURBS decomposition: {e}"),
            HostError::Patches(e) => write!(f, "patches: {e}"),
            HostError::Topology(e) => write!(f, "topology: {e}"),
            HostError::Bake(e) => write!(f, "bake: {e}"),
            HostError::Encode(e) => write!(f, "bake bytes: {e}"),
            HostError::Format(e) => write!(f, "bake bytes: {e}"),
            HostError::Hierarchy(e) => write!(f, "hierarchy: {e}"),
            HostError::Links(e) => write!(f, "hierarchy links: {e}"),
            HostError::Tessellator(e) => write!(f, "tessellator: {e}"),
            HostError::Update(e) => write!(f, "view: {e}"),
            HostError::Write(e) => write!(f, "mesh: {e}"),
        }
    }
}

impl std::error::Error for HostError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            HostError::Io(e) => Some(e),
            HostError::NotText | HostError::Domains { .. } => None,
            HostError::Bpt(e) => Some(e),
            HostError::NurbsJson(e) => Some(e),
            HostError::Decompose(e) => Some(e),
            HostError::Patches(e) => Some(e),
            HostError::Topology(e) => Some(e),
            HostError::Bake(e) => Some(e),
            HostError::Encode(e) => Some(e),
            HostError::Format(e) => Some(e),
            HostError::Hierarchy(e) => Some(e),
            HostError::Links(e) => Some(e),
            HostError::Tessellator(e) => Some(e),
            HostError::Update(e) => Some(e),
            HostError::Write(e) => Some(e),
        }
    }
}

macro_rules! from {
    ($($error:ty => $variant:ident),* $(,)?) => {
        $(impl From<$error> for HostError {
            fn from(e: $error) -> Self {
                HostError::$variant(e)
            }
        })*
    };
}

from! {
    io::Error => Io,
    BptError => Bpt,
    NurbsJsonError => NurbsJson,
    DecomposeError => Decompose,
    PatchSetError => Patches,
    TopologyError => Topology,
    BakeError => Bake,
    EncodeError => Encode,
    FormatError => Format,
    HierarchyError => Hierarchy,
    LinkError => Links,
    TessellatorError => Tessellator,
    UpdateError => Update,
    WriteError => Write,
}
