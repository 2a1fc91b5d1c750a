//! Code the host examples share.

#![allow(dead_code)]

pub mod framebuffer;
pub mod image;
pub mod model_file;
pub mod obj;
