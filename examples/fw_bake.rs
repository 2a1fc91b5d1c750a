//! Firmware: bakes one teapot patch on the device, in stack scratch, and checks the bytes
//! against the host's bake of the same patch (`examples/data/fw_bake_expected.rs`, generated and
//! kept current by `host-tests/tests/firmware_data.rs`).
//!
//! ```text
//! cargo run --release --example fw_bake --target thumbv7em-none-eabihf
//! ```
//!
//! Runs under QEMU `mps2-an386` and exits 0 when every byte matches, 1 otherwise. It prints the
//! bake's numbers and its instruction count (QEMU `-icount shift=0`: SysTick at 25 MHz advances
//! once per 40 instructions; wraps of the 24-bit counter are counted by its interrupt). The
//! scratch (about 16 KiB here: 260 vertex slots, 514 triangle slots and their deviations) is on
//! the stack; a real part would size the caps to its RAM.
//!
//! On the host, `cargo run --example fw_bake` runs the same check.

#![cfg_attr(target_os = "none", no_std, no_main)]

#[allow(dead_code)] // only the points are used
mod data {
    include!("data/teapot.rs");
}
mod settings {
    include!("data/fw_bake_settings.rs");
}
mod expected {
    include!("data/fw_bake_expected.rs");
}

use settings::{CURVE_CAP, INTERIOR_CAP, SETTINGS};
use spline_tess::bake::{
    bake_model, baked_size, BakeError, BakeScratch, BakeSummary, CurveSample, CurveSegment,
    InteriorSample, TriangleDeviation,
};
use spline_tess::{BoundaryCurve, DomainMesh, EdgeLink, MeshTriangle, MeshVertex, Model, PatchSet};

const VERTICES: usize = 4 + 4 * CURVE_CAP + INTERIOR_CAP;
const TRIANGLES: usize = DomainMesh::triangles_for(VERTICES);
/// Room for the largest bake these caps allow: header, 4 curves, 1 patch, all samples (the
/// patch's steps: its interior samples and its curve requests).
const OUT: usize = baked_size(1, 4, 4 * CURVE_CAP, INTERIOR_CAP + 4 * CURVE_CAP);

/// Bakes the patch into `out`; returns the summary.
fn bake(out: &mut [u8; OUT]) -> Result<BakeSummary, BakeError> {
    let set = PatchSet::new(&settings::HEADER, &data::TEAPOT_POINTS, None)
        .map_err(|_| BakeError::BadTolerance)?;
    let mut edges = [[EdgeLink::Collapsed; 4]; 1];
    let mut curves = [BoundaryCurve::default(); 4];
    let model = Model::build(set, &mut edges, &mut curves).map_err(|_| BakeError::BadTolerance)?;
    let mut vertices = [MeshVertex::default(); VERTICES];
    let mut triangles = [MeshTriangle::default(); TRIANGLES];
    let mut deviations = [TriangleDeviation::default(); TRIANGLES];
    let mut segments = [CurveSegment::default(); CURVE_CAP + 1];
    let mut curve_samples = [CurveSample::default(); 4 * CURVE_CAP];
    let mut interior_samples = [InteriorSample::default(); INTERIOR_CAP + 4 * CURVE_CAP];
    let scratch = BakeScratch {
        vertices: &mut vertices,
        triangles: &mut triangles,
        deviations: &mut deviations,
        segments: &mut segments,
        curve_samples: &mut curve_samples,
        interior_samples: &mut interior_samples,
    };
    bake_model(&model, &SETTINGS, scratch, out)
}

/// Bytes equal to the host's.
fn matches(out: &[u8], summary: &BakeSummary) -> bool {
    out.get(..summary.bytes) == Some(&expected::BAKED[..])
}

#[cfg(target_os = "none")]
#[path = "common/firmware.rs"]
mod firmware;

#[cfg(target_os = "none")]
mod device {
    use super::firmware::{finish, instructions, start_clock};
    use cortex_m_rt::entry;
    use cortex_m_semihosting::hprintln;
    use panic_semihosting as _;

    #[entry]
    fn main() -> ! {
        let Some(cp) = cortex_m::Peripherals::take() else {
            finish(false)
        };
        start_clock(cp.SYST);
        let start = instructions();
        let mut out = [0u8; super::OUT];
        let result = super::bake(&mut out);
        let used = instructions().saturating_sub(start);
        let summary = match result {
            Ok(s) => s,
            Err(_) => {
                hprintln!("fw_bake: the bake failed");
                finish(false)
            }
        };
        let ok = super::matches(&out, &summary);
        hprintln!(
            "fw_bake: {} curve and {} interior samples, {} bytes, {} of the host's bytes: {}; ~{} instructions",
            summary.curve_samples,
            summary.interior_samples,
            summary.bytes,
            super::expected::BAKED.len(),
            if ok { "bit-identical" } else { "DIFFERENT" },
            used
        );
        finish(ok)
    }
}

#[cfg(not(target_os = "none"))]
fn main() -> std::process::ExitCode {
    let mut out = [0u8; OUT];
    match bake(&mut out) {
        Ok(summary) if matches(&out, &summary) => {
            println!(
                "fw_bake (host): {} curve and {} interior samples, {} bytes, bit-identical",
                summary.curve_samples, summary.interior_samples, summary.bytes
            );
            std::process::ExitCode::SUCCESS
        }
        Ok(_) => {
            eprintln!("fw_bake (host): the bytes differ from examples/data/fw_bake_expected.rs");
            std::process::ExitCode::FAILURE
        }
        Err(e) => {
            eprintln!("fw_bake (host): {e}");
            std::process::ExitCode::FAILURE
        }
    }
}
