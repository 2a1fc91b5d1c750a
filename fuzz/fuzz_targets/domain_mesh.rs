//! Any sequence of insertions and removals: typed errors only, and the Euler count holds.
#![no_main]

#[path = "../harness/mod.rs"]
mod harness;

libfuzzer_sys::fuzz_target!(|data: &[u8]| harness::inputs::domain_mesh(data));
