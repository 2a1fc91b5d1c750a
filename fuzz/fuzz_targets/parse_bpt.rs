//! Any text: the BPT parser returns a typed error or patches whose topology builds and whose
//! evaluation is finite.
#![no_main]

#[path = "../harness/mod.rs"]
mod harness;

libfuzzer_sys::fuzz_target!(|data: &[u8]| harness::inputs::parse_bpt(data));
