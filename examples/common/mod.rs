//! Code the host examples share.

#![allow(dead_code)]

pub mod model_file;
