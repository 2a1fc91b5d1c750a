//! Code the host examples share.

#![allow(dead_code)]

pub mod model_file;
pub mod runtime_storage;
