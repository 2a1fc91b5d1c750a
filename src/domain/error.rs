//! Why a [`DomainMesh`](super::DomainMesh) cannot be built, or cannot take a point in or out.

use core::fmt;

#[cfg(doc)]
use super::{DomainIndex, DomainMesh};

/// Why storage cannot hold a [`DomainMesh`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum MeshStorageError {
    /// Fewer than 4 vertex slots or 2 triangle slots.
    TooSmall,
    /// More slots of either kind than the index type numbers ([`DomainIndex::MAX_SLOTS`]).
    TooLarge,
}

/// Why a point could not be inserted. The mesh is unchanged.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum InsertError {
    /// A vertex already has these coordinates.
    Duplicate {
        /// The existing vertex.
        vertex: u16,
    },
    /// Every vertex slot is in use.
    VerticesFull,
    /// Too few free triangle slots.
    TrianglesFull {
        /// Free slots the insertion needs.
        needed: usize,
    },
}

/// Why a vertex could not be removed. The mesh is unchanged.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum RemoveError {
    /// The four corners stay.
    Corner,
    /// No live vertex has this index.
    NotAVertex,
    /// No Delaunay ear was found; exact predicates make this unreachable for a mesh built by
    /// this type, so it means the storage was tampered with.
    NoEar,
}

impl fmt::Display for MeshStorageError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            MeshStorageError::TooSmall => "mesh storage needs 4 vertex and 2 triangle slots",
            MeshStorageError::TooLarge => "mesh storage has more slots than its index type numbers",
        })
    }
}

impl fmt::Display for InsertError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            InsertError::Duplicate { vertex } => write!(f, "vertex {vertex} is already there"),
            InsertError::VerticesFull => f.write_str("no free vertex slot"),
            InsertError::TrianglesFull { needed } => {
                write!(f, "needs {needed} free triangle slots")
            }
        }
    }
}

impl fmt::Display for RemoveError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            RemoveError::Corner => "the corners cannot be removed",
            RemoveError::NotAVertex => "no such vertex",
            RemoveError::NoEar => "no Delaunay ear found (corrupted mesh)",
        })
    }
}

impl core::error::Error for MeshStorageError {}
impl core::error::Error for InsertError {}
impl core::error::Error for RemoveError {}
