//! Any control net, weights and parameters: construction is a typed error or evaluation gives
//! a finite unit normal (positions may overflow to infinity only for huge inputs).
#![no_main]

#[path = "../harness/mod.rs"]
mod harness;

libfuzzer_sys::fuzz_target!(|data: &[u8]| harness::inputs::evaluate(data));
