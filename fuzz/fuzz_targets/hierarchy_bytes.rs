//! A hierarchy's compact bytes, changed, read and tessellated (see
//! `harness/hierarchy_bytes.rs`).
#![no_main]

#[path = "../harness/mod.rs"]
mod harness;

libfuzzer_sys::fuzz_target!(|data: &[u8]| harness::hierarchy_bytes::hierarchy_bytes(data));
