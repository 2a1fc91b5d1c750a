//! Fuzzing on stable: every fuzz target's body (`fuzz/harness/`, what `cargo fuzz` runs) takes
//! a few thousand pseudo-random inputs from a fixed seed, so that a panic of the kind a
//! coverage-guided campaign finds in a second fails `cargo test`, and so CI, without nightly.
//!
//! Half the inputs are fresh bytes of random length; half are the target's committed seeds
//! (`fuzz/seeds/<target>/`) changed the way libFuzzer's simplest mutations change them: bytes
//! overwritten, flipped, inserted, removed, set to extreme values, or runs spliced in from
//! another seed. A seed reaches deep into a target (a valid camera, a model, a frame), and a
//! few changed bytes then explore around it.
//!
//! The inputs are the same every run (set `SPLINE_TESS_SEED=random` for fresh ones, see
//! `host_tests::seeds`). A failing input is printed in hex: commit it as a seed, and the
//! corpus test replays it from then on.

#[path = "../../fuzz/harness/mod.rs"]
mod harness;

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;

use host_tests::seeds::seed;

/// Inputs per target: about 30 s for all of them in a test build on a 2-core machine, most of
/// it in the run times (see the numbers in each target's module docs).
const SWEEP: &[(&str, usize)] = &[
    ("parse_bpt", 20_000),
    ("parse_nurbs_json", 20_000),
    ("evaluate", 20_000),
    ("render", 30_000),
    ("bisect", 6_000),
    ("hierarchy_bytes", 20_000),
];

/// xorshift64*: small, fast and the same everywhere.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }

    fn byte(&mut self) -> u8 {
        (self.next() >> 32) as u8
    }
}

fn seeds_of(target: &str) -> Vec<Vec<u8>> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../fuzz/seeds")
        .join(target);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    files.iter().map(|f| std::fs::read(f).unwrap()).collect()
}

/// A seed changed by one to eight mutations.
fn mutated(rng: &mut Rng, seeds: &[Vec<u8>]) -> Vec<u8> {
    let mut data = seeds[rng.below(seeds.len())].clone();
    for _ in 0..1 + rng.below(8) {
        let at = rng.below(data.len() + 1);
        match rng.below(7) {
            0 if at < data.len() => data[at] = rng.byte(),
            1 if at < data.len() => data[at] ^= 1 << rng.below(8),
            2 => data.insert(at, rng.byte()),
            3 if at < data.len() => {
                data.remove(at);
            }
            4 if at < data.len() => data[at] = [0, 1, 0x7f, 0x80, 0xff][rng.below(5)],
            5 => {
                let other = &seeds[rng.below(seeds.len())];
                let from = rng.below(other.len());
                let run = &other[from..(from + 1 + rng.below(16)).min(other.len())];
                let at = at.min(data.len());
                data.splice(at..(at + run.len()).min(data.len()), run.iter().copied());
            }
            _ => data.truncate(at.max(1)),
        }
    }
    data
}

fn hex(data: &[u8]) -> String {
    data.iter().map(|b| format!("{b:02x}")).collect()
}

/// Sweeps `target`'s body with its share of [`SWEEP`].
fn sweep(target: &str) {
    let (_, body) = harness::TARGETS
        .iter()
        .find(|(name, _)| *name == target)
        .unwrap_or_else(|| panic!("no target {target}"));
    let (_, inputs) = SWEEP.iter().find(|(name, _)| *name == target).unwrap();
    let seeds = seeds_of(target);
    let fixed = target.bytes().fold(0x5eed_f022_2026_u64, |h, b| {
        (h ^ b as u64).wrapping_mul(0x100_0000_01b3)
    });
    let mut rng = Rng(seed(fixed) | 1);
    let start = std::time::Instant::now();
    for i in 0..*inputs {
        let data = if i % 2 == 0 || seeds.is_empty() {
            let len = rng.below(256);
            (0..len).map(|_| rng.byte()).collect()
        } else {
            mutated(&mut rng, &seeds)
        };
        let outcome = catch_unwind(AssertUnwindSafe(|| body(&data)));
        assert!(
            outcome.is_ok(),
            "{target}: input {i} of the sweep fails; as a seed for fuzz/seeds/{target}/: {}",
            hex(&data)
        );
    }
    println!(
        "{target}: {inputs} inputs in {:.1} s",
        start.elapsed().as_secs_f64()
    );
}

#[test]
fn every_target_is_swept() {
    for (target, _) in harness::TARGETS {
        assert!(
            SWEEP.iter().any(|(name, _)| name == target),
            "{target} is not swept"
        );
    }
}

macro_rules! sweeps {
    ($($name:ident),* $(,)?) => {
        $(
            #[test]
            fn $name() {
                sweep(stringify!($name));
            }
        )*
    };
}

sweeps!(
    parse_bpt,
    parse_nurbs_json,
    evaluate,
    render,
    bisect,
    hierarchy_bytes,
);
