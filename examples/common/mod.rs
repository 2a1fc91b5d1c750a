//! Code the host examples share.

#![allow(dead_code)]

pub mod framebuffer;
pub mod hierarchy_file;
pub mod image;
pub mod model_file;
