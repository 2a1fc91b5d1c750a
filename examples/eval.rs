//! Evaluates every patch of a model on a grid and prints one line per sample.
//!
//! ```text
//! cargo run --release --example eval -- examples/models/teapot.bpt --grid 5
//! ```
//!
//! Each line is `patch u v x y z nx ny nz`. For a `.bpt` model, `patch` is the patch index and
//! `(u, v)` run over `[0, 1]^2`; for a NURBS `.json` surface, `patch` is the surface index (0)
//! and `(u, v)` run over its own knot domain. `N x N` samples per patch, borders included.
//! Errors go to stderr with a non-zero exit status.

use std::io::Write;
use std::process::ExitCode;

use spline_tess::parse::{self, NurbsJsonBuffers};
use spline_tess::{PatchHeader, SurfacePoint};

fn usage() -> String {
    "usage: eval MODEL(.bpt|.json) [--grid N]   (N >= 2, default 9)".to_string()
}

fn parse_args() -> Result<(String, usize), String> {
    let mut args = std::env::args().skip(1);
    let mut model = None;
    let mut grid = 9usize;
    while let Some(a) = args.next() {
        match a.as_str() {
            "--grid" => {
                let n = args.next().ok_or_else(usage)?;
                grid = n
                    .parse()
                    .map_err(|_| format!("--grid takes a whole number, got `{n}`"))?;
            }
            "-h" | "--help" => return Err(usage()),
            _ if model.is_none() && !a.starts_with("--") => model = Some(a),
            _ => return Err(format!("unexpected argument `{a}`\n{}", usage())),
        }
    }
    if grid < 2 {
        return Err(format!("--grid must be at least 2\n{}", usage()));
    }
    Ok((model.ok_or_else(usage)?, grid))
}

fn line(
    out: &mut impl Write,
    patch: usize,
    u: f32,
    v: f32,
    s: &SurfacePoint,
) -> std::io::Result<()> {
    let (p, n) = (s.position, s.normal);
    writeln!(
        out,
        "{patch} {u} {v} {} {} {} {} {} {}",
        p.x, p.y, p.z, n.x, n.y, n.z
    )
}

fn param(lo: f32, hi: f32, k: usize, n: usize) -> f32 {
    if k + 1 == n {
        hi
    } else {
        lo + (hi - lo) * (k as f32 / (n - 1) as f32)
    }
}

fn run() -> Result<(), String> {
    let (path, grid) = parse_args()?;
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{path}: {e}"))?;
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    let io = |e: std::io::Error| e.to_string();
    if path.ends_with(".json") {
        let size = parse::nurbs_json_size(&text).map_err(|e| format!("{path}: {e}"))?;
        let mut ku = vec![0.0; size.knots_u];
        let mut kv = vec![0.0; size.knots_v];
        let mut pts = vec![[0.0; 3]; size.points];
        let mut w = vec![0.0; size.points];
        let buffers = NurbsJsonBuffers {
            knots_u: &mut ku,
            knots_v: &mut kv,
            points: &mut pts,
            weights: &mut w,
        };
        let surface =
            parse::parse_nurbs_json(&text, buffers).map_err(|e| format!("{path}: {e}"))?;
        let d = surface.domain();
        for i in 0..grid {
            for j in 0..grid {
                let (u, v) = (param(d.u0, d.u1, i, grid), param(d.v0, d.v1, j, grid));
                line(&mut out, 0, u, v, &surface.evaluate(u, v)).map_err(io)?;
            }
        }
    } else {
        let size = parse::bpt_size(&text).map_err(|e| format!("{path}: {e}"))?;
        let mut headers = vec![PatchHeader::default(); size.patches];
        let mut pts = vec![[0.0; 3]; size.points];
        let set =
            parse::parse_bpt(&text, &mut headers, &mut pts).map_err(|e| format!("{path}: {e}"))?;
        for (k, patch) in set.iter().enumerate() {
            for i in 0..grid {
                for j in 0..grid {
                    let (u, v) = (param(0.0, 1.0, i, grid), param(0.0, 1.0, j, grid));
                    line(&mut out, k, u, v, &patch.evaluate(u, v)).map_err(io)?;
                }
            }
        }
    }
    out.flush().map_err(io)
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("eval: {e}");
            ExitCode::FAILURE
        }
    }
}
