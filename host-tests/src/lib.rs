//! Shared helpers of the host tests: model files, an independent `f64` reference, and the
//! kernel loaded from the same files.
//!
//! The reference shares no code with the kernel: it reads BPT files with its own parser, NURBS
//! fixtures with `serde_json`, evaluates Bezier patches by direct Bernstein sums and NURBS
//! surfaces by Cox-de Boor basis functions, all in `f64`.

pub mod bintree;
pub mod frame_checks;
pub mod glu;
#[path = "../../examples/common/model_file.rs"]
pub mod model_file;
pub mod peers;
pub mod reference;
pub mod runtime;
pub mod screen;
pub mod screen_bound;
pub mod seeds;

use std::path::PathBuf;

use spline_tess::parse::{self, NurbsJsonBuffers};
use spline_tess::{NurbsSurface, PatchHeader, PatchSet};

/// Largest kernel position error, relative to the model's bounding-box diagonal.
pub const POSITION_TOL: f64 = 1e-5;
/// Largest kernel normal error away from poles, in radians.
pub const NORMAL_TOL: f64 = 1e-3;
/// "Away from poles": at least this far in (normalised) parameter from a collapsed edge.
pub const POLE_ZONE: f64 = 1e-2;

/// True when `(s, t)` (parameters scaled to `[0, 1]`) lies within [`POLE_ZONE`] of a collapsed
/// edge; `collapsed` is `[v = 0, u = 1, v = 1, u = 0]`.
pub fn near_pole(collapsed: [bool; 4], s: f64, t: f64) -> bool {
    (collapsed[0] && t < POLE_ZONE)
        || (collapsed[2] && t > 1.0 - POLE_ZONE)
        || (collapsed[3] && s < POLE_ZONE)
        || (collapsed[1] && s > 1.0 - POLE_ZONE)
}

/// The repository's model folder.
pub fn models_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../examples/models")
}

/// Every `.bpt` model, sorted by name.
pub fn bpt_models() -> Vec<PathBuf> {
    list(models_dir(), "bpt")
}

/// Every NURBS JSON fixture, sorted by name.
pub fn nurbs_fixtures() -> Vec<PathBuf> {
    list(models_dir().join("nurbs"), "json")
}

fn list(dir: PathBuf, ext: &str) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == ext))
        .collect();
    v.sort();
    assert!(!v.is_empty(), "no .{ext} files in {}", dir.display());
    v
}

/// File name without folder, for messages.
pub fn name(path: &std::path::Path) -> String {
    path.file_name().unwrap().to_string_lossy().into_owned()
}

/// The model file at `path` baked at `relative` of its diagonal (the tests' one call).
///
/// # Panics
/// Where the file cannot be read or baked.
pub fn bake_relative(path: &std::path::Path, relative: f32) -> model_file::BakedHierarchy {
    let file = model_file::ModelFile::read(path.to_str().expect("a UTF-8 path")).expect("a model");
    let settings = spline_tess::bake::BakeSettings {
        tolerance: spline_tess::bake::Tolerance::Relative(relative),
        ..spline_tess::bake::BakeSettings::default()
    };
    model_file::BakedHierarchy::bake(&file, &settings).expect("a bake")
}

/// Storage of a BPT model parsed by the kernel.
pub struct KernelBpt {
    /// Patch headers.
    pub headers: Vec<PatchHeader>,
    /// Control points.
    pub points: Vec<[f32; 3]>,
}

impl KernelBpt {
    /// Parses `text` with the kernel's parser.
    pub fn parse(text: &str) -> Self {
        let size = parse::bpt_size(text).expect("valid BPT");
        let mut headers = vec![PatchHeader::default(); size.patches];
        let mut points = vec![[0.0; 3]; size.points];
        parse::parse_bpt(text, &mut headers, &mut points).expect("valid BPT");
        KernelBpt { headers, points }
    }

    /// The patches.
    pub fn set(&self) -> PatchSet<'_> {
        PatchSet::new(&self.headers, &self.points, None).expect("valid patch set")
    }
}

/// Storage of a NURBS JSON fixture parsed by the kernel.
pub struct KernelNurbs {
    degrees: (usize, usize),
    /// u knots.
    pub knots_u: Vec<f32>,
    /// v knots.
    pub knots_v: Vec<f32>,
    /// Control points.
    pub points: Vec<[f32; 3]>,
    /// Weights.
    pub weights: Vec<f32>,
    rational: bool,
}

impl KernelNurbs {
    /// Parses `text` with the kernel's parser.
    pub fn parse(text: &str) -> Self {
        let size = parse::nurbs_json_size(text).expect("valid NURBS JSON");
        let mut k = KernelNurbs {
            degrees: (0, 0),
            knots_u: vec![0.0; size.knots_u],
            knots_v: vec![0.0; size.knots_v],
            points: vec![[0.0; 3]; size.points],
            weights: vec![0.0; size.points],
            rational: false,
        };
        let buffers = NurbsJsonBuffers {
            knots_u: &mut k.knots_u,
            knots_v: &mut k.knots_v,
            points: &mut k.points,
            weights: &mut k.weights,
        };
        let s = parse::parse_nurbs_json(text, buffers).expect("valid NURBS JSON");
        k.degrees = (s.degree_u(), s.degree_v());
        k.rational = s.weights().is_some();
        if !k.rational {
            k.weights.iter_mut().for_each(|w| *w = 1.0);
        }
        k
    }

    /// The surface.
    pub fn surface(&self) -> NurbsSurface<'_> {
        NurbsSurface::new(
            self.degrees.0,
            self.degrees.1,
            &self.knots_u,
            &self.knots_v,
            &self.points,
            if self.rational {
                Some(&self.weights)
            } else {
                None
            },
        )
        .expect("valid surface")
    }
}

/// Angle in radians between two vectors.
pub fn angle(a: [f64; 3], b: [f64; 3]) -> f64 {
    let cross = reference::cross(a, b);
    reference::norm(cross).atan2(reference::dot(a, b))
}

/// `[f32; 3]` as `[f64; 3]`.
pub fn widen(v: spline_tess::Vec3) -> [f64; 3] {
    [v.x as f64, v.y as f64, v.z as f64]
}

/// A small deterministic random generator (xorshift64*), so failures reproduce.
pub struct Rng(u64);

impl Rng {
    /// Seeded generator.
    pub fn new(seed: u64) -> Self {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }

    /// The generator a test uses where it writes `fixed`: seeded with `fixed` unless
    /// [`seeds::SEED_VAR`] asks for fresh seeds.
    pub fn for_test(fixed: u64) -> Self {
        Rng::new(seeds::seed(fixed))
    }

    /// Uniform in `[0, 1)`.
    pub fn unit(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let x = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D);
        (x >> 11) as f64 / (1u64 << 53) as f64
    }
}
