//! Bakes a model into the compact format and prints one summary line.
//!
//! ```text
//! cargo run --release --example bake -- examples/models/teapot.bpt --tolerance 1e-3 --relative \
//!     --out out/teapot.bin --rust out/teapot_baked.rs
//! ```
//!
//! MODEL is `.bpt` or NURBS `.json` (decomposed into its rational Bezier pieces). The tolerance
//! is in object-space units, or with `--relative` a fraction of the model's bounding-box
//! diagonal. `--curve-cap` and `--interior-cap` bound the samples per curve and per patch
//! (default 256 and 4096). The summary line is
//! `patches P curves C samples S (curve Sc, interior Si) bytes B seconds T max_deviation D
//! tolerance E stops tolerance/cap/resolution X/Y/Z`.

mod common;

use std::process::ExitCode;
use std::time::Instant;

use common::model_file::{bake_to_vec, ModelFile};
use spline_tess::bake::{write_rust_source, BakeSettings, BakedModel, Tolerance};

const USAGE: &str = "usage: bake MODEL(.bpt|.json) --tolerance EPS [--relative] --out FILE.bin \
                     [--rust FILE.rs] [--curve-cap N] [--interior-cap N]";

struct Args {
    model: String,
    tolerance: f32,
    relative: bool,
    out: String,
    rust: Option<String>,
    curve_cap: u16,
    interior_cap: u16,
}

fn parse_args() -> Result<Args, String> {
    let mut args = std::env::args().skip(1);
    let (mut model, mut tolerance, mut out, mut rust) = (None, None, None, None);
    let (mut relative, mut curve_cap, mut interior_cap) = (false, 256u16, 4096u16);
    fn value<T: std::str::FromStr>(flag: &str, v: Option<String>) -> Result<T, String> {
        let v = v.ok_or_else(|| format!("{flag} needs a value\n{USAGE}"))?;
        v.parse()
            .map_err(|_| format!("{flag}: cannot read `{v}`\n{USAGE}"))
    }
    while let Some(a) = args.next() {
        match a.as_str() {
            "--tolerance" => tolerance = Some(value::<f32>("--tolerance", args.next())?),
            "--relative" => relative = true,
            "--out" => out = Some(value::<String>("--out", args.next())?),
            "--rust" => rust = Some(value::<String>("--rust", args.next())?),
            "--curve-cap" => curve_cap = value("--curve-cap", args.next())?,
            "--interior-cap" => interior_cap = value("--interior-cap", args.next())?,
            "-h" | "--help" => return Err(USAGE.to_string()),
            _ if model.is_none() && !a.starts_with("--") => model = Some(a),
            _ => return Err(format!("unexpected argument `{a}`\n{USAGE}")),
        }
    }
    Ok(Args {
        model: model.ok_or(USAGE)?,
        tolerance: tolerance.ok_or(format!("--tolerance is required\n{USAGE}"))?,
        relative,
        out: out.ok_or(format!("--out is required\n{USAGE}"))?,
        rust,
        curve_cap,
        interior_cap,
    })
}

fn run() -> Result<(), String> {
    let args = parse_args()?;
    let file = ModelFile::read(&args.model)?;
    let settings = BakeSettings {
        tolerance: if args.relative {
            Tolerance::Relative(args.tolerance)
        } else {
            Tolerance::Absolute(args.tolerance)
        },
        max_curve_samples: args.curve_cap,
        max_interior_samples: args.interior_cap,
    };
    let start = Instant::now();
    let bytes = file.with_model(|model| bake_to_vec(model, &settings))?;
    let seconds = start.elapsed().as_secs_f64();
    let bytes = bytes.map_err(|e| e.to_string())?;
    let baked = BakedModel::from_bytes(&bytes).map_err(|e| format!("reading back: {e}"))?;
    std::fs::write(&args.out, &bytes).map_err(|e| format!("{}: {e}", args.out))?;
    if let Some(path) = &args.rust {
        let mut src = String::new();
        write_rust_source(&mut src, "BAKED", &bytes).map_err(|e| e.to_string())?;
        std::fs::write(path, src).map_err(|e| format!("{path}: {e}"))?;
    }
    let mut stops = [0usize; 3];
    let mut max_deviation = 0.0f32;
    let curves = (0..baked.curve_count()).filter_map(|k| baked.curve(k));
    for c in curves {
        stops[c.stop as usize] += 1;
        let last = c
            .samples
            .iter()
            .last()
            .map_or(c.initial_deviation, |s| s.deviation);
        max_deviation = max_deviation.max(last);
    }
    for p in (0..baked.patch_count()).filter_map(|k| baked.patch(k)) {
        stops[p.stop as usize] += 1;
        let last = p
            .samples
            .iter()
            .last()
            .map_or(p.initial_deviation, |s| s.deviation);
        max_deviation = max_deviation.max(last);
    }
    let (cs, is) = (baked.curve_sample_count(), baked.interior_sample_count());
    println!(
        "patches {} curves {} samples {} (curve {cs}, interior {is}) bytes {} seconds {seconds:.3} \
         max_deviation {max_deviation:e} tolerance {:e} stops tolerance/cap/resolution {}/{}/{}",
        baked.patch_count(),
        baked.curve_count(),
        cs + is,
        bytes.len(),
        baked.tolerance(),
        stops[0],
        stops[1],
        stops[2],
    );
    Ok(())
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("bake: {e}");
            ExitCode::FAILURE
        }
    }
}
