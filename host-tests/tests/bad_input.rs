//! Bad input of every kind gets its typed error, never a panic.

use host_tests::{models_dir, nurbs_fixtures};
use spline_tess::parse::{
    self, BptError, BptErrorKind, NurbsJsonBuffers, NurbsJsonErrorKind, NurbsJsonSize,
};
use spline_tess::{
    BezierPatch, Direction, NurbsError, NurbsSurface, ParamRect, PatchError, PatchHeader, PatchSet,
    PatchSetError, SplitError,
};

fn square() -> Vec<[f32; 3]> {
    (0..16)
        .map(|k| [(k / 4) as f32, (k % 4) as f32, ((k * 5) % 3) as f32])
        .collect()
}

#[test]
fn patches_reject_non_finite_points_bad_weights_and_bad_sizes() {
    let good = square();
    for (index, bad) in [(3, f32::NAN), (7, f32::INFINITY), (15, f32::NEG_INFINITY)] {
        let mut pts = good.clone();
        pts[index][1] = bad;
        assert_eq!(
            BezierPatch::new(3, 3, &pts).unwrap_err(),
            PatchError::NonFinitePoint { index }
        );
    }
    for (index, w) in [
        (0, 0.0),
        (5, -1.0),
        (9, f32::NAN),
        (12, f32::INFINITY),
        (2, -0.0),
    ] {
        let mut ws = vec![1.0f32; 16];
        ws[index] = w;
        assert_eq!(
            BezierPatch::new_rational(3, 3, &good, &ws).unwrap_err(),
            PatchError::InvalidWeight { index }
        );
    }
    assert_eq!(
        BezierPatch::new_rational(3, 3, &good, &[1.0; 15]).unwrap_err(),
        PatchError::WeightCount {
            expected: 16,
            found: 15
        }
    );
    assert_eq!(
        BezierPatch::new(3, 2, &good).unwrap_err(),
        PatchError::PointCount {
            expected: 12,
            found: 16
        }
    );
    for degree in [0, 8, 200] {
        assert_eq!(
            BezierPatch::new(degree, 1, &good).unwrap_err(),
            PatchError::DegreeOutOfRange { degree }
        );
    }
    // Display names the problem.
    assert_eq!(
        PatchError::InvalidWeight { index: 4 }.to_string(),
        "weight 4 is not a finite positive number"
    );
}

#[test]
fn patch_sets_check_ranges_and_every_patch() {
    let mut pts = square();
    pts.extend(square());
    let headers = [
        PatchHeader {
            degree_u: 3,
            degree_v: 3,
            first_point: 0,
        },
        PatchHeader {
            degree_u: 3,
            degree_v: 3,
            first_point: 16,
        },
    ];
    assert!(PatchSet::new(&headers, &pts, None).is_ok());
    assert_eq!(
        PatchSet::new(&headers, &pts[..31], None).unwrap_err(),
        PatchSetError::PointsOutOfRange { patch: 1 }
    );
    let mut nan = pts.clone();
    nan[20][2] = f32::NAN;
    assert_eq!(
        PatchSet::new(&headers, &nan, None).unwrap_err(),
        PatchSetError::Patch {
            patch: 1,
            error: PatchError::NonFinitePoint { index: 4 }
        }
    );
    let mut ws = vec![1.0; 32];
    ws[3] = 0.0;
    assert_eq!(
        PatchSet::new(&headers, &pts, Some(&ws)).unwrap_err(),
        PatchSetError::Patch {
            patch: 0,
            error: PatchError::InvalidWeight { index: 3 }
        }
    );
    assert_eq!(
        PatchSet::new(&headers, &pts, Some(&ws[..31])).unwrap_err(),
        PatchSetError::WeightCount {
            expected: 32,
            found: 31
        }
    );
    let bad_degree = [PatchHeader {
        degree_u: 0,
        degree_v: 3,
        first_point: 0,
    }];
    assert_eq!(
        PatchSet::new(&bad_degree, &pts, None).unwrap_err(),
        PatchSetError::Patch {
            patch: 0,
            error: PatchError::DegreeOutOfRange { degree: 0 }
        }
    );
}

#[test]
fn splits_refuse_short_buffers_and_points_past_f32() {
    let pts = square();
    let headers = [PatchHeader {
        degree_u: 3,
        degree_v: 3,
        first_point: 0,
    }];
    let set = PatchSet::new(&headers, &pts, None).unwrap();
    let (mut h, mut p, mut w, mut d) = (
        [PatchHeader::default(); 4],
        vec![[0.0; 3]; 64],
        vec![0.0; 64],
        [ParamRect::default(); 4],
    );
    let needed = set.split_size();
    for short in [
        (3, 64, 64, 4),
        (4, 63, 64, 4),
        (4, 64, 63, 4),
        (4, 64, 64, 3),
    ] {
        let e = set
            .split(
                &mut h[..short.0],
                &mut p[..short.1],
                &mut w[..short.2],
                &mut d[..short.3],
            )
            .unwrap_err();
        assert_eq!(e, SplitError::BufferTooSmall { needed });
        assert_eq!(
            e.to_string(),
            "buffers too small: need 4 patches and 64 control points and weights"
        );
    }
    // Finite points near f32::MAX whose homogeneous coordinates overflow, within an extent
    // f32 holds (a squared spread past f32 is refused as soon as the patches are made, below:
    // here the spread is below the points' own rounding), give a typed error.
    let huge: Vec<[f32; 3]> = square()
        .iter()
        .map(|q| q.map(|c| f32::MAX * 0.5 + 1e18 * c))
        .collect();
    let weights = vec![3.0; 16];
    let set = PatchSet::new(&headers, &huge, Some(&weights)).unwrap();
    let e = set.split(&mut h, &mut p, &mut w, &mut d).unwrap_err();
    assert!(matches!(e, SplitError::Patch(_)), "{e:?}");
    assert!(e.to_string().starts_with("a quarter is not a valid patch"));
}

#[test]
fn nurbs_knot_vectors_and_nets_are_validated() {
    let pts = square();
    let good = [0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
    let make = |ku: &[f32], kv: &[f32], w: Option<&[f32]>| {
        NurbsSurface::new(3, 3, ku, kv, &pts, w).map(|_| ())
    };
    assert_eq!(make(&good, &good, None), Ok(()));
    let u = Direction::U;
    let v = Direction::V;
    assert_eq!(
        make(&[0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0], &good, None),
        Err(NurbsError::TooFewKnots {
            direction: u,
            found: 7,
            needed: 8
        })
    );
    assert_eq!(
        make(&good, &[0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 0.5, 1.0], None),
        Err(NurbsError::DecreasingKnots {
            direction: v,
            index: 6
        })
    );
    assert_eq!(
        make(&[0.0, 0.0, 0.0, 0.1, 1.0, 1.0, 1.0, 1.0], &good, None),
        Err(NurbsError::NotClamped { direction: u })
    );
    assert_eq!(
        make(&good, &[0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, f32::NAN], None),
        Err(NurbsError::NonFiniteKnot {
            direction: v,
            index: 7
        })
    );
    assert_eq!(
        make(&[0.0; 8], &good, None),
        Err(NurbsError::KnotMultiplicity {
            direction: u,
            index: 0,
            multiplicity: 8
        })
    );
    // Interior multiplicity above the degree (here 4 > 3) splits the surface: refused.
    let pts9: Vec<[f32; 3]> = (0..36).map(|k| [k as f32, 0.0, (k % 6) as f32]).collect();
    let ku = [0.0, 0.0, 0.0, 0.0, 0.5, 0.5, 0.5, 0.5, 1.0, 1.0, 1.0, 1.0];
    let kv = [0.0, 0.0, 0.0, 0.0, 0.5, 0.5, 1.0, 1.0, 1.0, 1.0];
    assert_eq!(
        NurbsSurface::new(3, 3, &ku, &kv, &pts9[..32], None).map(|_| ()),
        Err(NurbsError::KnotMultiplicity {
            direction: u,
            index: 4,
            multiplicity: 4
        })
    );
    assert_eq!(
        make(&good, &[0.0, 0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0, 1.0], None),
        Err(NurbsError::PointCount {
            expected: 20,
            found: 16
        })
    );
    let mut w = [1.0f32; 16];
    w[6] = -2.0;
    assert_eq!(
        make(&good, &good, Some(&w)),
        Err(NurbsError::InvalidWeight { index: 6 })
    );
    assert_eq!(
        make(&good, &good, Some(&w[..15])),
        Err(NurbsError::WeightCount {
            expected: 16,
            found: 15
        })
    );
    let mut bad = pts.clone();
    bad[9][0] = f32::INFINITY;
    assert_eq!(
        NurbsSurface::new(3, 3, &good, &good, &bad, None).map(|_| ()),
        Err(NurbsError::NonFinitePoint { index: 9 })
    );
    assert_eq!(
        NurbsSurface::new(9, 3, &good, &good, &pts, None).map(|_| ()),
        Err(NurbsError::DegreeOutOfRange {
            direction: u,
            degree: 9
        })
    );
}

fn bpt(text: &str) -> Result<usize, BptError> {
    let mut headers = [PatchHeader::default(); 64];
    let mut points = [[0.0f32; 3]; 1024];
    parse::parse_bpt(text, &mut headers, &mut points).map(|s| s.len())
}

#[test]
fn every_truncation_of_the_teapot_is_a_typed_error() {
    let text = std::fs::read_to_string(models_dir().join("teapot.bpt")).unwrap();
    assert_eq!(bpt(&text), Ok(32));
    let trimmed = text.trim_end();
    let total_lines = trimmed.lines().count();
    let last_line_start = trimmed.rfind('\n').unwrap() + 1;
    for cut in 0..trimmed.len() {
        let prefix = &trimmed[..cut];
        // A cut inside the file's very last number leaves a shorter valid number ("3.1" of
        // "3.15"): the format has no terminator to tell. Everything else must fail.
        let last_token = trimmed[cut..].find(char::is_whitespace).is_none()
            && prefix[last_line_start.min(cut)..]
                .split_whitespace()
                .count()
                == 3
            && !prefix.ends_with(char::is_whitespace);
        if last_token {
            assert_eq!(bpt(prefix), Ok(32), "cut {cut}");
            continue;
        }
        let err = bpt(prefix).expect_err("a truncated file must not parse");
        assert!(
            err.line >= 1 && err.line <= total_lines + 1,
            "cut {cut}: {err}"
        );
        // A cut at the end of a line leaves whole lines: the file ends early.
        if cut > 0 && trimmed.as_bytes()[cut] == b'\n' {
            let lines = prefix.lines().count();
            let complete = if lines <= 1 { 0 } else { (lines - 1) / 17 };
            assert_eq!(
                err,
                BptError {
                    line: lines + 1,
                    kind: BptErrorKind::Truncated {
                        expected: 32,
                        complete
                    }
                },
                "cut after line {lines}"
            );
        }
    }
}

#[test]
fn bpt_errors_name_the_line_and_the_problem() {
    let head = "1\n1 1\n0 0 0\n0 1 0\n1 0 0\n";
    let cases: [(&str, usize, BptErrorKind); 10] = [
        ("", 1, BptErrorKind::BadPatchCount),
        ("x\n", 1, BptErrorKind::BadPatchCount),
        ("1\n1\n", 2, BptErrorKind::BadDegrees),
        ("1\n8 1\n", 2, BptErrorKind::DegreeOutOfRange { degree: 8 }),
        ("1\n0 1\n", 2, BptErrorKind::DegreeOutOfRange { degree: 0 }),
        ("1\n1 1\n0 0\n", 3, BptErrorKind::BadPoint { values: 2 }),
        ("1\n1 1\n0 0 zero\n", 3, BptErrorKind::BadNumber),
        ("1\n1 1\n0 0 0\n\n0 nan 0\n", 5, BptErrorKind::NonFinite),
        ("1\n1 1\n0 0 0\n0 1e39 0\n", 4, BptErrorKind::NonFinite),
        (
            "1\n1 1\n0 0 0\n0 1 0\n1 0 0\n1 1 0\n1 1 1\n",
            7,
            BptErrorKind::TrailingData,
        ),
    ];
    for (text, line, kind) in cases {
        assert_eq!(bpt(text), Err(BptError { line, kind }), "{text:?}");
    }
    assert_eq!(bpt(&format!("{head}1 1 1\n")), Ok(1));
    // Too small a buffer: the sizes needed, and the buffers untouched.
    let mut headers = [PatchHeader::default(); 1];
    let mut points = [[9.0f32; 3]; 3];
    let err = parse::parse_bpt(&format!("{head}1 1 1\n"), &mut headers, &mut points).unwrap_err();
    assert_eq!(
        err.kind,
        BptErrorKind::BufferTooSmall {
            patches: 1,
            points: 4
        }
    );
    assert!(points.iter().all(|p| *p == [9.0; 3]));
    assert_eq!(
        BptError {
            line: 5,
            kind: BptErrorKind::BadNumber
        }
        .to_string(),
        "line 5: not a number"
    );
}

fn json(text: &str) -> Result<(), spline_tess::parse::NurbsJsonError> {
    let (mut ku, mut kv, mut pts, mut w) = ([0.0; 32], [0.0; 32], [[0.0; 3]; 64], [0.0; 64]);
    let b = NurbsJsonBuffers {
        knots_u: &mut ku,
        knots_v: &mut kv,
        points: &mut pts,
        weights: &mut w,
    };
    parse::parse_nurbs_json(text, b).map(|_| ())
}

const SURFACE: &str = r#"{
  "degree_u": 1,
  "degree_v": 1,
  "knots_u": [0, 0, 1, 1],
  "knots_v": [0, 0, 1, 1],
  "control_points": [[[0, 0, 0], [0, 1, 0]],
                     [[1, 0, 0], [1, 1, 1]]],
  "weights": [[1, 1],
              [1, 2]]
}"#;

#[test]
fn json_errors_name_the_line_and_the_problem() {
    assert_eq!(json(SURFACE), Ok(()));
    let with = |from: &str, to: &str| SURFACE.replacen(from, to, 1);
    let kind = |text: String| json(&text).map_err(|e| (e.line, e.kind));
    assert_eq!(
        kind(with(
            "\"knots_u\": [0, 0, 1, 1]",
            "\"knots_u\": [0, 0, 1, 0.5]"
        )),
        Err((
            4,
            NurbsJsonErrorKind::Surface(NurbsError::DecreasingKnots {
                direction: Direction::U,
                index: 3
            })
        ))
    );
    assert_eq!(
        kind(with("[1, 2]]", "[1, 0]]")),
        Err((
            8,
            NurbsJsonErrorKind::Surface(NurbsError::InvalidWeight { index: 3 })
        ))
    );
    assert_eq!(
        kind(with("[1, 2]]", "[1]]")),
        Err((9, NurbsJsonErrorKind::Ragged { field: "weights" }))
    );
    assert_eq!(
        kind(with("[[1, 0, 0], [1, 1, 1]]", "[[1, 0, 0]]")),
        Err((
            7,
            NurbsJsonErrorKind::Ragged {
                field: "control_points"
            }
        ))
    );
    assert_eq!(
        kind(with("  \"degree_v\": 1,\n", "")),
        Err((9, NurbsJsonErrorKind::MissingField { field: "degree_v" }))
    );
    assert_eq!(
        kind(with(
            "\"degree_v\": 1,",
            "\"degree_v\": 1, \"degree_v\": 1,"
        )),
        Err((3, NurbsJsonErrorKind::DuplicateField { field: "degree_v" }))
    );
    assert_eq!(
        kind(with("[0, 1, 0]", "[0, 1e40, 0]")),
        Err((6, NurbsJsonErrorKind::BadNumber))
    );
    assert_eq!(
        kind(with("\"degree_u\": 1", "\"degree_u\": 1.5")),
        Err((2, NurbsJsonErrorKind::BadNumber))
    );
    assert_eq!(
        kind(with("[0, 1, 0]", "[0, 1 0]")),
        Err((
            6,
            NurbsJsonErrorKind::Syntax {
                expected: "`,` or `]`"
            }
        ))
    );
    assert_eq!(
        kind(with("[0, 1, 0]", "[0, 1]")),
        Err((
            6,
            NurbsJsonErrorKind::Syntax {
                expected: "points of three coordinates"
            }
        ))
    );
    // Too-small buffers: the sizes needed, nothing written.
    let (mut ku, mut kv, mut pts, mut w) = ([5.0; 3], [0.0; 4], [[0.0; 3]; 4], [0.0; 4]);
    let b = NurbsJsonBuffers {
        knots_u: &mut ku,
        knots_v: &mut kv,
        points: &mut pts,
        weights: &mut w,
    };
    let err = parse::parse_nurbs_json(SURFACE, b).unwrap_err();
    assert_eq!(
        err.kind,
        NurbsJsonErrorKind::BufferTooSmall {
            needed: NurbsJsonSize {
                knots_u: 4,
                knots_v: 4,
                points: 4
            }
        }
    );
    assert_eq!(ku, [5.0; 3]);
}

#[test]
fn every_truncation_of_every_fixture_is_a_typed_error() {
    for path in nurbs_fixtures() {
        let text = std::fs::read_to_string(&path).unwrap();
        let trimmed = text.trim_end();
        assert!(parse::nurbs_json_size(trimmed).is_ok());
        for cut in (0..trimmed.len()).filter(|&c| trimmed.is_char_boundary(c)) {
            let err = parse::nurbs_json_size(&trimmed[..cut]).expect_err("truncated");
            assert!(err.line >= 1 && err.line <= trimmed.lines().count() + 1);
        }
    }
}

/// Evaluation never panics and never returns NaN, whatever the parameters.
#[test]
fn evaluation_takes_any_parameter() {
    let pts = square();
    let p = BezierPatch::new(3, 3, &pts).unwrap();
    for t in [
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        -1.0,
        2.0,
        1e30,
        -0.0,
        f32::MIN_POSITIVE,
    ] {
        for s in [0.5, t] {
            let e = p.evaluate(t, s);
            assert!(e.position.is_finite() && e.normal.is_finite(), "({t}, {s})");
            assert!((e.normal.length() - 1.0).abs() < 1e-6);
        }
    }
    // A patch collapsed to a single point still has a unit normal (and, a sum over the
    // Bernstein basis, its point to within rounding).
    let point = [[1.0f32, 2.0, 3.0]; 16];
    let e = BezierPatch::new(3, 3, &point).unwrap().evaluate(0.3, 0.7);
    assert!((e.position - spline_tess::Vec3::new(1.0, 2.0, 3.0)).length() < 1e-6);
    assert!((e.normal.length() - 1.0).abs() < 1e-6);
}

/// The bake and the tessellator: typed errors for bad settings, short buffers and records
/// that do not hold together, and for a tolerance that is not a positive finite number; a
/// frame finer than the bake with no pool still gives a mesh, and says its pool was full.
#[test]
fn bisection_errors_are_typed() {
    use spline_tess::bake::{
        bake_hierarchy, BakeBuffers, BakeError, BakeScratch, BakeSettings, Tolerance,
    };
    use spline_tess::tessellator::{
        BudgetError, Hierarchy, HierarchyError, HierarchyNode, HierarchyPatch, HierarchyVertex,
        PoolSlot, StackSlot, Tessellator, TessellatorError, UpdateError,
    };
    use spline_tess::{BoundaryCurve, EdgeLink, Model, PatchHeader, PatchSet, View};

    let headers = [PatchHeader {
        degree_u: 1,
        degree_v: 1,
        first_point: 0,
    }];
    let bake = |points: &[[f32; 3]], settings: BakeSettings, nodes: usize, vertices: usize| {
        let patches = PatchSet::new(&headers, points, None).unwrap();
        let mut edges = [[EdgeLink::Collapsed; 4]];
        let mut curves = [BoundaryCurve::default(); 4];
        let model = Model::build(patches, &mut edges, &mut curves).unwrap();
        let mut n = vec![HierarchyNode::default(); nodes];
        let mut v = vec![HierarchyVertex::default(); vertices];
        let mut p = [HierarchyPatch::default()];
        let mut s = vec![BakeScratch::default(); nodes];
        bake_hierarchy(
            &model,
            &settings,
            BakeBuffers {
                nodes: &mut n,
                vertices: &mut v,
                patches: &mut p,
                scratch: &mut s,
            },
        )
        .map(|size| (n, v, p, size))
    };
    let flat = square();
    let settings = BakeSettings::default();
    for t in [0.0, -1.0, f32::NAN, f32::INFINITY] {
        let bad = BakeSettings {
            tolerance: Tolerance::Absolute(t),
            ..settings
        };
        assert!(matches!(
            bake(&flat, bad, 16, 16),
            Err(BakeError::BadTolerance(_))
        ));
    }
    let deep = BakeSettings {
        max_depth: 31,
        ..settings
    };
    assert_eq!(
        bake(&flat, deep, 16, 16).err(),
        Some(BakeError::TooDeep(31))
    );
    // A bump needs halving: one node slot is short.
    let mut bump = flat.clone();
    bump[0][2] = 1.0;
    let fine = BakeSettings {
        tolerance: Tolerance::Absolute(1e-4),
        ..settings
    };
    assert!(matches!(
        bake(&bump, fine, 2, 64),
        Err(BakeError::NodesFull { .. })
    ));
    assert!(matches!(
        bake(&bump, fine, 4096, 8),
        Err(BakeError::VerticesFull { capacity: 8 })
    ));
    // Records that do not hold together are refused.
    let (mut n, v, p, size) = bake(&bump, BakeSettings::default(), 4096, 4096).unwrap();
    let patches = PatchSet::new(&headers, &bump, None).unwrap();
    n.truncate(size.nodes);
    let v = &v[..size.vertices];
    assert!(Hierarchy::new(patches, &n, v, &p).is_ok());
    let mut broken = n.clone();
    broken[0].children = 0;
    broken[0].children = broken.len() as u32;
    assert!(matches!(
        Hierarchy::new(patches, &broken, v, &p),
        Err(HierarchyError::BadNode { node: 0 })
    ));
    assert_eq!(
        Hierarchy::new(patches, &n[..1], v, &p).err(),
        Some(HierarchyError::Empty)
    );
    let tree = Hierarchy::new(patches, &n, v, &p).unwrap();
    let mut bits = vec![0u32; tree.bit_words() - 1];
    let mut stack = [StackSlot::default(); 8];
    let mut pool: [PoolSlot; 0] = [];
    assert_eq!(
        Tessellator::from_slices(tree, &mut bits, &mut stack, &mut pool).err(),
        Some(TessellatorError::BitsTooShort {
            needed: tree.bit_words()
        })
    );
    let mut bits = vec![0u32; tree.bit_words()];
    assert_eq!(
        Tessellator::from_slices(tree, &mut bits, &mut stack[..2], &mut pool).err(),
        Some(TessellatorError::StackTooShort { needed: 4 })
    );
    assert!(TessellatorError::StackTooShort { needed: 4 }
        .to_string()
        .contains("4 entries needed"));
    // No pool: a view finer than the bake keeps its leaves and says so.
    let mut selection = Tessellator::from_slices(tree, &mut bits, &mut stack, &mut pool).unwrap();
    let stats = selection.update(&View::Object { tolerance: 1e-6 }).unwrap();
    assert!(stats.left_over > 0 && stats.worst_bound > 1e-6);
    assert!(stats.pool_full, "an empty pool is full: {stats:?}");
    // A tolerance that is not a positive finite number is refused, for a frame and a budget.
    for t in [f32::NAN, -1.0, 0.0, -0.0, f32::INFINITY, f32::NEG_INFINITY] {
        assert_eq!(
            selection.update(&View::Object { tolerance: t }),
            Err(UpdateError::BadTolerance),
            "{t}"
        );
        assert_eq!(
            selection.update_to_budget(&View::Object { tolerance: t }, 100),
            Err(BudgetError::BadTolerance),
            "{t}"
        );
    }
    assert!(UpdateError::BadTolerance.to_string().contains("tolerance"));
    // A patch record whose cone is not a unit axis with a sine in [0, 1), nor none, is
    // refused: culling trusts it.
    for cone in [
        [0.0, 0.0, 2.0, 0.5],
        [0.0, 0.0, 1.0, -0.5],
        [f32::NAN, 0.0, 1.0, 0.5],
        [0.0, 0.0, 1.0, f32::NAN],
    ] {
        let mut bad = p;
        bad[0].cone = cone;
        assert_eq!(
            Hierarchy::new(patches, &n, v, &bad).err(),
            Some(HierarchyError::BadPatch { patch: 0 }),
            "{cone:?}"
        );
    }
    let mut fine = p;
    fine[0].cone = [0.0, 0.6, 0.8, 0.3];
    assert!(Hierarchy::new(patches, &n, v, &fine).is_ok());
}

/// A model whose extent overflows `f32` (finite points 6e38 apart) is refused where it is
/// loaded, with a message that says so: as patches, as BPT text and as a NURBS surface.
#[test]
fn models_too_large_for_f32_are_refused_when_loaded() {
    let far = [
        [-3e38, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 0.0, 0.0],
        [3e38, 1.0, 0.0],
    ];
    let headers = [PatchHeader {
        degree_u: 1,
        degree_v: 1,
        first_point: 0,
    }];
    let err = PatchSet::new(&headers, &far, None).unwrap_err();
    assert_eq!(err, PatchSetError::ExtentOverflow);
    assert!(err.to_string().contains("too large"), "{err}");
    // Points 2e19 apart on each axis: each finite, the squared diagonal past f32.
    let wide = [
        [0.0; 3],
        [0.0, 1.0, 0.0],
        [1.0, 0.0, 0.0],
        [2e19, 2e19, 2e19],
    ];
    assert_eq!(
        PatchSet::new(&headers, &wide, None).unwrap_err(),
        PatchSetError::ExtentOverflow
    );
    let text = "1\n1 1\n-3e38 0 0\n0 1 0\n1 0 0\n3e38 1 0\n";
    let err = bpt(text).unwrap_err();
    assert_eq!(err.kind, BptErrorKind::ExtentOverflow);
    assert!(err.to_string().contains("too large"), "{err}");
    let (knots, points, weights) = ([0.0, 0.0, 1.0, 1.0], far, [1.0; 4]);
    let err = NurbsSurface::new(1, 1, &knots, &knots, &points, Some(&weights)).unwrap_err();
    assert_eq!(err, NurbsError::ExtentOverflow);
    assert!(err.to_string().contains("too large"), "{err}");
    // Large but within f32: taken.
    let big = far.map(|p| p.map(|c| c * 1e-20));
    assert!(PatchSet::new(&headers, &big, None).is_ok());
}
