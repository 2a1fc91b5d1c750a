//! Any text: the NURBS JSON reader returns a typed error or a surface that evaluates and
//! decomposes without panicking.
#![no_main]

#[path = "../harness/mod.rs"]
mod harness;

libfuzzer_sys::fuzz_target!(|data: &[u8]| harness::inputs::parse_nurbs_json(data));
