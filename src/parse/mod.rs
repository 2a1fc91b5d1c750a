//! Text model formats, parsed without allocation into caller buffers.
//!
//! Each parser reads its input twice: once to validate it and count what it holds, then to
//! store it. So a too-small buffer gets an error with the exact sizes needed, and on any error
//! the caller's buffers are untouched.

pub mod bpt;
pub mod nurbs_json;

pub use bpt::{bpt_size, parse_bpt, BptError, BptErrorKind, BptSize};
pub use nurbs_json::{
    nurbs_json_size, parse_nurbs_json, NurbsJsonBuffers, NurbsJsonError, NurbsJsonErrorKind,
    NurbsJsonSize,
};
