//! Replays the committed seed corpus of every fuzz target (`fuzz/seeds/<target>/`) through the
//! same bodies `cargo fuzz` runs (`fuzz/harness/`), so the targets keep compiling on stable
//! and every crash a fuzzing campaign found stays a regression test; the targets whose work per
//! input is bounded replay their seeds with the bounds lifted too (`harness::UNBOUNDED`),
//! where the slow cases found before the bounds stay covered. A target without seeds fails
//! the test.

#[path = "../../fuzz/harness/mod.rs"]
mod harness;

use std::path::PathBuf;

#[test]
fn every_seed_of_every_target_passes() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fuzz/seeds");
    let unbounded = harness::UNBOUNDED
        .iter()
        .map(|(target, body)| (*target, body, " (unbounded)"));
    let bodies = harness::TARGETS
        .iter()
        .map(|(target, body)| (*target, body, ""));
    for (target, body, kind) in bodies.chain(unbounded) {
        let dir = root.join(target);
        let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .map(|e| e.unwrap().path())
            .filter(|p| p.is_file())
            .collect();
        files.sort();
        assert!(
            !files.is_empty(),
            "no seeds for {target} in {}",
            dir.display()
        );
        for file in &files {
            let data = std::fs::read(file).unwrap();
            let name = file.file_name().unwrap().to_string_lossy().into_owned();
            let outcome = std::panic::catch_unwind(|| body(&data));
            assert!(outcome.is_ok(), "{target}{kind}: seed {name} fails");
        }
        println!("{target}{kind}: {} seeds replayed", files.len());
    }
}
