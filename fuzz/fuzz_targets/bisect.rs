//! The bisection run time: any model of a small set, bake tolerances, stack and pool sizes,
//! cameras, tolerances, budgets and update sequences; every frame written into small and exact
//! buffers and streamed (see `harness/bisect.rs`).
#![no_main]

#[path = "../harness/mod.rs"]
mod harness;

libfuzzer_sys::fuzz_target!(|data: &[u8]| harness::bisect::bisect(data));
