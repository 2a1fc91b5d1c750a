//! Bakes a model's hierarchy and prints one summary line.
//!
//! ```text
//! cargo run --release --example bake -- examples/models/teapot.bpt --tolerance 1e-3 --relative \
//!     --out out/teapot.hierarchy --rust out/teapot_hierarchy.rs
//! ```
//!
//! MODEL is `.bpt` or NURBS `.json` (decomposed into its rational Bezier pieces). The tolerance
//! is in object-space units, or with `--relative` a fraction of the model's bounding-box
//! diagonal. `--out FILE` writes the hierarchy as a file that `tessellate --baked` reads (see
//! `examples/common/hierarchy_file.rs`); `--rust FILE` writes it, with the model's patches, as
//! statics a firmware compiles in. The summary line is
//! `patches P triangles N leaves L vertices V bytes B seconds T`.

mod common;

use std::process::ExitCode;
use std::time::Instant;

use common::hierarchy_file;
use common::model_file::{BakedHierarchy, ModelFile};
use spline_tess::bake::Tolerance;
use spline_tess::bake::{write_rust_source, BakeSettings};

const USAGE: &str =
    "usage: bake MODEL(.bpt|.json) --tolerance EPS [--relative] [--out FILE] [--rust FILE.rs]";

struct Args {
    model: String,
    tolerance: f32,
    relative: bool,
    rust: Option<String>,
    out: Option<String>,
}

fn parse_args() -> Result<Args, String> {
    let mut args = std::env::args().skip(1);
    let (mut model, mut tolerance, mut rust, mut out) = (None, None, None, None);
    let mut relative = false;
    fn value<T: std::str::FromStr>(flag: &str, v: Option<String>) -> Result<T, String> {
        let v = v.ok_or_else(|| format!("{flag} needs a value\n{USAGE}"))?;
        v.parse()
            .map_err(|_| format!("{flag}: cannot read `{v}`\n{USAGE}"))
    }
    while let Some(a) = args.next() {
        match a.as_str() {
            "--tolerance" => tolerance = Some(value::<f32>("--tolerance", args.next())?),
            "--relative" => relative = true,
            "--rust" => rust = Some(value::<String>("--rust", args.next())?),
            "--out" => out = Some(value::<String>("--out", args.next())?),
            "-h" | "--help" => return Err(USAGE.to_string()),
            _ if model.is_none() && !a.starts_with("--") => model = Some(a),
            _ => return Err(format!("unexpected argument `{a}`\n{USAGE}")),
        }
    }
    Ok(Args {
        model: model.ok_or(USAGE)?,
        tolerance: tolerance.ok_or(format!("--tolerance is required\n{USAGE}"))?,
        relative,
        rust,
        out,
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
        ..BakeSettings::default()
    };
    let start = Instant::now();
    let baked = BakedHierarchy::bake(&file, &settings)?;
    let seconds = start.elapsed().as_secs_f64();
    if let Some(path) = &args.out {
        let bytes = hierarchy_file::to_bytes(&file, &settings, &baked);
        std::fs::write(path, bytes).map_err(|e| format!("{path}: {e}"))?;
    }
    if let Some(path) = &args.rust {
        let mut src = String::new();
        write_rust_source(&mut src, "MODEL", &file.patches(), &baked.encoded())
            .map_err(|e| e.to_string())?;
        std::fs::write(path, src).map_err(|e| format!("{path}: {e}"))?;
    }
    println!(
        "patches {} triangles {} leaves {} vertices {} bytes {} seconds {seconds:.3}",
        baked.patches.len(),
        baked.nodes.len(),
        baked.nodes.iter().filter(|n| n.children == 0).count(),
        baked.vertices.len(),
        baked.bytes(),
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
