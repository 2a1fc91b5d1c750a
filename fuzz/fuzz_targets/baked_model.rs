//! Any bytes: loading a baked model returns a typed error, or a model whose every record and
//! sample can be read.
#![no_main]

#[path = "../harness/mod.rs"]
mod harness;

libfuzzer_sys::fuzz_target!(|data: &[u8]| harness::inputs::baked_model(data));
