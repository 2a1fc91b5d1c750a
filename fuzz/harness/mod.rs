//! The bodies of the fuzz targets, shared by `cargo fuzz` (one thin binary per target in
//! `fuzz_targets/`) and by `host-tests/tests/fuzz_corpus.rs`, which replays the committed seed
//! corpus (`fuzz/seeds/<target>/`) on every `cargo test`, so the targets keep compiling and
//! every crash found stays a regression test.
//!
//! Each body panics (an `assert!` or a kernel panic) on a finding and returns otherwise.

#![allow(dead_code)]

pub mod bisect;
pub mod bytes;
pub mod hierarchy_bytes;
pub mod inputs;
#[path = "../../examples/common/model_file.rs"]
pub mod model_file;
pub mod render;

/// A target's body.
pub type Body = fn(&[u8]);

/// Every target: its name (the folder of its seeds and its `cargo fuzz` binary) and body.
pub const TARGETS: &[(&str, Body)] = &[
    ("parse_bpt", inputs::parse_bpt),
    ("parse_nurbs_json", inputs::parse_nurbs_json),
    ("evaluate", inputs::evaluate),
    ("render", render::render),
    ("bisect", bisect::bisect),
    ("hierarchy_bytes", hierarchy_bytes::hierarchy_bytes),
];

/// Targets whose work per input is bounded, with their bodies with the bounds lifted: the
/// committed seeds go through both.
pub const UNBOUNDED: &[(&str, Body)] = &[("bisect", bisect::bisect_unbounded)];
