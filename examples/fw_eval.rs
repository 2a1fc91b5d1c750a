//! Firmware: evaluates the teapot, compiled in as const data, and checks the results against
//! the values the host computed (`examples/data/fw_eval_expected.rs`, generated and kept current
//! by `host-tests/tests/firmware_data.rs`).
//!
//! ```text
//! cargo run --release --example fw_eval --target thumbv7em-none-eabihf
//! ```
//!
//! Runs under QEMU `mps2-an386` (see `.cargo/config.toml`) and exits 0 when every value is
//! within 1e-6 of the model's size of the host's (and says how many are bit-identical), 1
//! otherwise. It then times evaluations with SysTick: QEMU runs with `-icount shift=0`, so one
//! instruction takes 1 ns of virtual time and the 25 MHz SysTick advances once per 40
//! instructions. Only integers are printed, to keep float formatting out of the image.
//!
//! On the host, `cargo run --example fw_eval` runs the same check.

#![cfg_attr(target_os = "none", no_std, no_main)]

mod data {
    include!("data/teapot.rs");
}
mod expected {
    include!("data/fw_eval_expected.rs");
}

use spline_tess::PatchSet;

/// Largest accepted difference, relative to the teapot's size (about 7 units).
const TOLERANCE: f32 = 1e-6 * 8.0;

/// Result of comparing the device's evaluations with the host's.
struct Check {
    values: usize,
    within_tolerance: usize,
    bit_identical: usize,
}

fn check(set: &PatchSet<'_>) -> Check {
    let g = expected::GRID;
    let mut c = Check {
        values: 0,
        within_tolerance: 0,
        bit_identical: 0,
    };
    for (p, patch) in set.iter().enumerate() {
        for i in 0..g {
            for j in 0..g {
                let (u, v) = (i as f32 / (g - 1) as f32, j as f32 / (g - 1) as f32);
                let e = patch.evaluate(u, v);
                let got = [
                    e.position.x,
                    e.position.y,
                    e.position.z,
                    e.normal.x,
                    e.normal.y,
                    e.normal.z,
                ];
                let want = expected::EXPECTED[(p * g + i) * g + j];
                for (a, b) in got.iter().zip(want) {
                    let b = f32::from_bits(b);
                    c.values += 1;
                    c.bit_identical += (a.to_bits() == b.to_bits()) as usize;
                    c.within_tolerance += ((a - b).abs() <= TOLERANCE) as usize;
                }
            }
        }
    }
    c
}

/// Evaluations per patch side in the timing loop.
const TIMING_GRID: usize = 16;

/// Evaluates every patch on the timing grid; returns a checksum so nothing is optimised away.
fn timing_pass(set: &PatchSet<'_>, patch: usize) -> u32 {
    let mut sum = 0u32;
    if let Some(p) = set.patch(patch) {
        for i in 0..TIMING_GRID {
            for j in 0..TIMING_GRID {
                let u = core::hint::black_box(i as f32 / (TIMING_GRID - 1) as f32);
                let v = core::hint::black_box(j as f32 / (TIMING_GRID - 1) as f32);
                let e = p.evaluate(u, v);
                sum = sum.rotate_left(5) ^ e.position.x.to_bits() ^ e.normal.z.to_bits();
            }
        }
    }
    sum
}

fn teapot() -> Option<PatchSet<'static>> {
    PatchSet::new(&data::TEAPOT_HEADERS, &data::TEAPOT_POINTS, None).ok()
}

#[cfg(target_os = "none")]
#[allow(dead_code)]
#[path = "common/firmware.rs"]
mod shared;

#[cfg(target_os = "none")]
mod firmware {
    use cortex_m::peripheral::syst::SystClkSource;
    use cortex_m::peripheral::SYST;
    use cortex_m_rt::entry;
    use cortex_m_semihosting::hprintln;

    use super::shared::finish;
    use panic_semihosting as _;

    /// SysTick ticks per instruction under `-icount shift=0` on mps2-an386: 25 MHz vs 1 GHz.
    const INSTRUCTIONS_PER_TICK: u64 = 40;
    const SYSTICK_HZ: u64 = 25_000_000;

    #[entry]
    fn main() -> ! {
        let Some(set) = super::teapot() else {
            hprintln!("fw_eval: the teapot data is invalid");
            finish(false)
        };
        let c = super::check(&set);
        hprintln!(
            "fw_eval: {} of {} values within tolerance, {} bit-identical to the host",
            c.within_tolerance,
            c.values,
            c.bit_identical
        );

        let Some(mut cp) = cortex_m::Peripherals::take() else {
            finish(false)
        };
        cp.SYST.set_clock_source(SystClkSource::Core);
        cp.SYST.set_reload(0x00FF_FFFF);
        cp.SYST.clear_current();
        cp.SYST.enable_counter();
        let mut ticks = 0u64;
        let mut checksum = 0u32;
        for patch in 0..set.len() {
            // One patch (256 evaluations) stays far below the 24-bit counter's wrap.
            let start = SYST::get_current();
            checksum ^= super::timing_pass(&set, patch);
            let end = SYST::get_current();
            ticks += u64::from(start.wrapping_sub(end) & 0x00FF_FFFF);
        }
        let evaluations = (set.len() * super::TIMING_GRID * super::TIMING_GRID) as u64;
        let per_second = evaluations * SYSTICK_HZ / ticks.max(1);
        let instructions = ticks * INSTRUCTIONS_PER_TICK / evaluations;
        hprintln!(
            "fw_eval: {} evaluations in {} SysTick ticks: {} evaluations/s of QEMU icount time, ~{} instructions per evaluation (checksum {:08x})",
            evaluations,
            ticks,
            per_second,
            instructions,
            checksum
        );
        finish(c.within_tolerance == c.values && c.values > 0)
    }
}

#[cfg(not(target_os = "none"))]
fn main() -> std::process::ExitCode {
    let Some(set) = teapot() else {
        eprintln!("fw_eval: the teapot data is invalid");
        return std::process::ExitCode::FAILURE;
    };
    let c = check(&set);
    let checksum = (0..set.len()).fold(0, |acc, p| acc ^ timing_pass(&set, p));
    println!(
        "fw_eval (host): {} of {} values within tolerance, {} bit-identical (checksum {checksum:08x})",
        c.within_tolerance, c.values, c.bit_identical
    );
    if c.within_tolerance == c.values && c.values > 0 {
        std::process::ExitCode::SUCCESS
    } else {
        std::process::ExitCode::FAILURE
    }
}
