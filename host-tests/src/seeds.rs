//! Seeds of the randomised tests: fixed by default, so `cargo test` gives the same answer
//! every run; fresh on request, for exploration.
//!
//! [`SEED_VAR`] (`SPLINE_TESS_SEED`) chooses:
//!
//! - unset: every test uses the seed written in it (and proptest a fixed seed), so the suite
//!   is deterministic and never writes a regression file while it passes;
//! - `random`: one fresh base seed for the test binary, printed to standard error, mixed into
//!   every test's own seed;
//! - a number: that base seed, to replay what a `random` run printed.
//!
//! A failure that a fresh seed finds is then kept as a fixed test or a committed
//! `*.proptest-regressions` entry.

use std::io::Write as _;
use std::sync::OnceLock;

use proptest::test_runner::{Config, FileFailurePersistence, RngSeed};

/// The environment variable that chooses the seeds (see the module docs).
pub const SEED_VAR: &str = "SPLINE_TESS_SEED";

/// The proptest seed when [`SEED_VAR`] is unset.
const PROPTEST_SEED: u64 = 0x5EED_2026;

/// The base seed of this run: `None` when the written seeds are to be used.
fn base() -> Option<u64> {
    static BASE: OnceLock<Option<u64>> = OnceLock::new();
    *BASE.get_or_init(|| match std::env::var(SEED_VAR) {
        Err(_) => None,
        Ok(s) if s.trim() == "random" => {
            use std::hash::{BuildHasher, Hasher};
            let mut h = std::collections::hash_map::RandomState::new().build_hasher();
            h.write_u128(
                std::time::SystemTime::now()
                    .duration_since(std::time::UNIX_EPOCH)
                    .map_or(0, |d| d.as_nanos()),
            );
            let seed = h.finish();
            // Straight to the stream, past the test harness's capture, so it is always seen.
            let _ = writeln!(
                std::io::stderr(),
                "{SEED_VAR}={seed} (fresh seeds; set it to replay this run)"
            );
            Some(seed)
        }
        Ok(s) => Some(
            s.trim()
                .parse()
                .unwrap_or_else(|_| panic!("{SEED_VAR} must be `random` or a number, not `{s}`")),
        ),
    })
}

/// The seed a test uses where it would use `fixed`.
pub fn seed(fixed: u64) -> u64 {
    match base() {
        None => fixed,
        // splitmix64 of the pair, so nearby written seeds stay apart.
        Some(b) => {
            let mut z = b ^ fixed.wrapping_mul(0x9E37_79B9_7F4A_7C15);
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^ (z >> 31)
        }
    }
}

/// A proptest configuration with `cases` cases and the seed [`SEED_VAR`] chooses.
pub fn proptest_config(cases: u32) -> Config {
    Config {
        cases,
        rng_seed: RngSeed::Fixed(seed(PROPTEST_SEED)),
        // Failures found with fresh seeds go to `<test file>.proptest-regressions`, beside
        // the test (commit them); they are replayed before the generated cases.
        failure_persistence: Some(Box::new(FileFailurePersistence::WithSource(
            "proptest-regressions",
        ))),
        ..Config::default()
    }
}
