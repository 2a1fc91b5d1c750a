//! A hierarchy's links (`Hierarchy::fill_links`, `with_links`): the run time finds the triangle
//! across a hypotenuse by them instead of walking down to it, and the meshes are the same bit
//! for bit, on every model of the repository, from its records and from its bytes, within the
//! bake and below it, with a stack long enough and one so short that walks find what it had no
//! room for, and with judgements kept from frame to frame. Links that are not the
//! hierarchy's are refused.
//!
//! Also here, as it is the same comparison: `write_mesh` into buffers with room to spare (one
//! walk, no count) and into buffers of exactly the mesh's size (a count first) write the mesh
//! `mesh_size` sizes.

use host_tests::bake_relative as bake;
use host_tests::runtime::{indexed, Mesh, VecStorage};
use host_tests::{bpt_models, models_dir, nurbs_fixtures};
use spline_tess::tessellator::{FrameStats, Judgement, LinkError, NodeLink, Tessellator};
use spline_tess::{Hierarchy, Vec3, Vertex, View};

/// Views of a model: in model units within and below the bake, cameras from afar and from
/// close by (below the bake), and an orbit of small steps (for kept judgements).
fn views(tree: &Hierarchy<'_>) -> Vec<View> {
    let b = tree.model().aabb().unwrap();
    let (c, d) = (b.center(), b.diagonal());
    let mut views = vec![
        View::Object {
            tolerance: 2e-2 * d,
        },
        View::Object {
            tolerance: 2e-3 * d,
        },
    ];
    let eyes = [
        (Vec3::new(1.0, -1.0, 0.6), [320, 240], 1.0),
        (Vec3::new(0.1, 0.5, 0.2), [640, 480], 1.0),
        (Vec3::new(0.35, -0.3, 0.25), [1024, 768], 0.5),
    ];
    for (eye, size, tolerance_px) in eyes {
        for degrees in [0.0f32, 1.0, 2.0] {
            let (s, k) = degrees.to_radians().sin_cos();
            let eye = Vec3::new(k * eye.x - s * eye.y, s * eye.x + k * eye.y, eye.z);
            let camera = host_tests::screen::camera_40(c + eye * d, c, 0.01 * d, size);
            views.push(View::Screen {
                camera,
                tolerance_px,
            });
        }
    }
    views
}

/// A frame's figures but for how many triangles were judged (and kept), which depend on the
/// order the search halves in, and for the worst bound, which a frame that keeps judgements
/// knows less exactly (see [`worst_bound_holds`]).
fn figures(s: FrameStats) -> FrameStats {
    FrameStats {
        judged: 0,
        kept: 0,
        stack_peak: 0,
        sweeps: 0,
        // (Whether a frame was a step from the one before: the same mesh either way.)
        stepped: false,
        worst_bound: 0.0,
        ..s
    }
}

/// Whether `reusing`'s worst bound is what `FrameStats::worst_bound` promises beside the
/// exact one of a frame that keeps no judgement (`fresh`, of the same mesh): an upper bound
/// of it, within the tolerance where nothing is left over (a judgement kept knows only that
/// its bound is within; one a certificate made, only the certificate's bound, above it).
fn worst_bound_holds(reusing: &FrameStats, fresh: &FrameStats, tolerance: f32) -> bool {
    reusing.worst_bound >= fresh.worst_bound
        && (fresh.left_over > 0 || reusing.worst_bound <= tolerance)
}

/// The current frame written into buffers with room to spare, without a count first.
fn written_at_once(t: &mut Tessellator<'_, '_>) -> Mesh {
    let n = 3 * t.stats().triangles;
    let mut vertices = vec![Vertex::default(); n];
    let mut triangles = vec![[0u32; 3]; n];
    let mut remap = vec![0u32; t.remap_len()];
    let size = t
        .write_mesh(&mut vertices, &mut triangles, &mut remap)
        .expect("room to spare");
    vertices.truncate(size.vertices);
    triangles.truncate(size.triangles);
    Mesh {
        vertices,
        triangles,
    }
}

/// Links give the same meshes and figures on every model, from records and from bytes, with a
/// long stack, a short one, and kept judgements.
#[test]
fn links_give_the_same_meshes_on_every_model() {
    let models: Vec<_> = bpt_models().into_iter().chain(nurbs_fixtures()).collect();
    assert!(models.len() >= 12, "the repository's models");
    let mut compared = 0;
    for path in &models {
        let name = path.display();
        let baked = bake(path, 1e-2);
        let bytes = baked.encoded();
        // The records with a short stack, the bytes with a long one.
        let stores = [
            (baked.tree(), Tessellator::MIN_STACK),
            (baked.tree_from(&bytes), 256),
        ];
        for (plain, stack) in stores {
            let mut links = vec![NodeLink::default(); plain.link_slots()];
            plain.fill_links(&mut links).unwrap();
            let linked = plain.with_links(&links).unwrap();
            let mut a = VecStorage::new(&plain, stack, 4096);
            let mut b = VecStorage::new(&plain, stack, 4096);
            let mut judgements = vec![Judgement::NONE; plain.judgement_slots()];
            let mut x = a.tessellator(plain);
            let mut y = b.tessellator(linked).with_reuse(&mut judgements).unwrap();
            for view in views(&plain) {
                let (sx, sy) = (x.update(&view).unwrap(), y.update(&view).unwrap());
                // (Where `y` kept judgements, its worst bound is only known to be within.)
                let kept = FrameStats {
                    kept: sy.kept,
                    ..sx
                };
                assert_eq!(figures(kept), figures(sy), "{name}: frame figures");
                assert!(
                    worst_bound_holds(&sy, &sx, view.tolerance()),
                    "{name}: worst bound {} against {}",
                    sy.worst_bound,
                    sx.worst_bound
                );
                let my = written_at_once(&mut y);
                let mx = indexed(&mut x);
                assert!(!mx.triangles.is_empty(), "{name}");
                assert_eq!(mx, my, "{name}: meshes with and without links");
                compared += sx.triangles;
            }
        }
    }
    assert!(compared > 10_000, "{compared}");
}

/// Links too short, of another hierarchy, or changed are refused with the node that is wrong.
#[test]
fn links_not_of_the_hierarchy_are_refused() {
    let teaspoon = bake(&models_dir().join("teaspoon.bpt"), 1e-2);
    let teacup = bake(&models_dir().join("teacup.bpt"), 1e-2);
    let tree = teaspoon.tree();
    let mut links = vec![NodeLink::default(); tree.link_slots()];
    let short = tree.link_slots() - 1;
    assert_eq!(
        tree.fill_links(&mut links[..short]),
        Err(LinkError::TooShort {
            needed: tree.link_slots()
        })
    );
    assert_eq!(
        tree.with_links(&links[..short]).err(),
        Some(LinkError::TooShort {
            needed: tree.link_slots()
        })
    );
    // Empty links are not this hierarchy's.
    assert!(matches!(
        tree.with_links(&links),
        Err(LinkError::Mismatch { .. })
    ));
    tree.fill_links(&mut links).unwrap();
    assert!(tree.with_links(&links).is_ok());
    // Another model's.
    let other = teacup.tree();
    let mut theirs = vec![NodeLink::default(); other.link_slots()];
    other.fill_links(&mut theirs).unwrap();
    let err = tree.with_links(&theirs).unwrap_err();
    assert!(matches!(err, LinkError::Mismatch { .. }), "{err:?}");
    assert!(err.to_string().contains("not this hierarchy's"), "{err}");
    // One link swapped with another: each swap is found.
    let mut refused = 0;
    for (i, j) in [(0, 1), (3, 40), (100, 101), (7, short)] {
        let mut changed = links.clone();
        changed.swap(i, j);
        if changed[i] != changed[j] {
            assert!(tree.with_links(&changed).is_err(), "{i} <-> {j}");
            refused += 1;
        }
    }
    assert_eq!(refused, 4);
}
