//! The band renderer: any triangles, camera, style, band height and target (see
//! `harness/render.rs`).
#![no_main]

#[path = "../harness/mod.rs"]
mod harness;

libfuzzer_sys::fuzz_target!(|data: &[u8]| harness::render::render(data));
