//! Frame-to-frame reuse (`Tessellator::with_reuse`): along camera paths of small and large
//! steps (orbits of a quarter, one and four degrees, a dolly, a turn of the head, a change of
//! tolerance, a jump), every frame of a tessellator that keeps its judgements is the mesh a
//! fresh tessellator finds for the view, bit for bit (positions, normals, parameters,
//! triangles) and with the same triangle and leftover counts; and the judgements are kept
//! (the path exercises the reuse). On the bake's records of every model of the repository,
//! and on the teapot's compact bytes.

use host_tests::bake_relative as bake;
use host_tests::runtime::{indexed, VecStorage};
use host_tests::screen::camera_40;
use host_tests::{bpt_models, models_dir, name, nurbs_fixtures};
use spline_tess::tessellator::Judgement;
use spline_tess::{Arithmetic, Hierarchy, Vec3, View};

/// The path: from `(1, -1.3, 0.7)` diagonals off the centre, orbits around the vertical of
/// 24 steps of 0.25°, 24 of 1° and 6 of 4°, a dolly in by 2% a frame, a turn of the head
/// (the target moving sideways), half the tolerance (all kept judgements dropped), more
/// quarter-degree steps, a jump to the other side and three one-degree steps from there.
fn path(tree: &Hierarchy<'_>) -> Vec<(String, View)> {
    let b = tree.model().aabb().unwrap();
    let (c, d) = (b.center(), b.diagonal());
    let view = |eye: Vec3, target: Vec3, tolerance_px: f32| View::Screen {
        camera: camera_40(eye, target, 0.01 * d, [320, 240]),
        tolerance_px,
    };
    let around = |degrees: f32, distance: f32| {
        let (s, k) = degrees.to_radians().sin_cos();
        let r = Vec3::new(1.0, -1.3, 0.0) * distance * d;
        c + Vec3::new(k * r.x - s * r.y, s * r.x + k * r.y, 0.7 * distance * d)
    };
    let mut views = Vec::new();
    let mut angle = 0.0f32;
    for (steps, step) in [(24, 0.25), (24, 1.0), (6, 4.0)] {
        for _ in 0..steps {
            angle += step;
            views.push((format!("orbit {angle}°"), view(around(angle, 1.0), c, 1.0)));
        }
    }
    for k in 1..=10 {
        let distance = 0.98f32.powi(k);
        views.push((
            format!("dolly {distance}"),
            view(around(angle, distance), c, 1.0),
        ));
    }
    let eye = around(angle, 0.98f32.powi(10));
    for k in 1..=10 {
        let target = c + Vec3::new(0.004 * k as f32 * d, 0.0, 0.0);
        views.push((format!("turn {k}"), view(eye, target, 1.0)));
    }
    let target = c + Vec3::new(0.04 * d, 0.0, 0.0);
    views.push(("half the tolerance".into(), view(eye, target, 0.5)));
    for k in 1..=8 {
        let eye = target + (eye - target) * (1.0 + 0.001 * k as f32);
        views.push((format!("at 0.5 px {k}"), view(eye, target, 0.5)));
    }
    views.push(("jump".into(), view(around(angle + 180.0, 1.5), c, 1.0)));
    for k in 1..=3 {
        let after = angle + 180.0 + k as f32;
        views.push((
            format!("{k}° after the jump"),
            view(around(after, 1.5), c, 1.0),
        ));
    }
    views
}

/// Along the path, a tessellator keeping its judgements gives a fresh one's frames, both
/// computing their bounds in `arithmetic`; returns the judgements kept and made, and the
/// frames that were steps from the one before. `linked`: `tree` has its links.
fn follow(
    name: &str,
    tree: Hierarchy<'_>,
    arithmetic: Arithmetic,
    linked: bool,
) -> (usize, usize, usize) {
    let mut storage = VecStorage::new(&tree, 256, 1 << 14);
    let mut fresh_storage = VecStorage::new(&tree, 256, 1 << 14);
    let mut judgements = vec![Judgement::NONE; tree.judgement_slots()];
    let mut kept = storage
        .tessellator(tree)
        .with_arithmetic(arithmetic)
        .with_reuse(&mut judgements)
        .unwrap();
    let (mut kept_count, mut judged, mut steps) = (0, 0, 0);
    for (label, view) in path(&tree) {
        let stats = kept.update(&view).unwrap();
        kept_count += stats.kept;
        judged += stats.judged;
        let mut fresh = fresh_storage.tessellator(tree).with_arithmetic(arithmetic);
        let expected = fresh.update(&view).unwrap();
        assert_eq!(stats.triangles, expected.triangles, "{name} {label}");
        assert_eq!(stats.left_over, expected.left_over, "{name} {label}");
        assert_eq!(stats.refined, expected.refined, "{name} {label}");
        if stats.stepped {
            steps += 1;
            assert!(linked, "{name} {label}: a step without links");
        } else {
            assert_eq!(
                stats.kept + stats.judged,
                expected.judged,
                "{name} {label}: the same triangles looked at"
            );
        }
        assert_eq!(stats.hidden, expected.hidden, "{name} {label}");
        assert!(
            stats.worst_bound <= view.tolerance() || stats.left_over > 0,
            "{name} {label}"
        );
        assert_eq!(
            indexed(&mut kept),
            indexed(&mut fresh),
            "{name} {label}: the mesh"
        );
    }
    (kept_count, judged, steps)
}

#[test]
fn kept_judgements_give_the_fresh_frames() {
    for (model, relative) in [
        ("teapot.bpt", 1e-3),
        ("teaspoon.bpt", 2e-3),
        ("gumbo.bpt", 2e-3),
    ] {
        let baked = bake(&models_dir().join(model), relative);
        let (kept, judged, steps) = follow(model, baked.tree(), Arithmetic::Float, false);
        // Most of the small steps' judgements carry over; without links, no frame steps.
        assert!(kept > judged / 2, "{model}: {kept} kept, {judged} judged");
        assert_eq!(steps, 0, "{model}: steps without links");
        // With links, most frames are steps from the one before.
        let mut links = Vec::new();
        let label = format!("{model} with links");
        let (_, _, steps) = follow(
            &label,
            baked.linked_tree(&mut links),
            Arithmetic::Float,
            true,
        );
        let frames = path(&baked.tree()).len();
        eprintln!("{label}: {steps} of {frames} frames steps");
        assert!(
            steps > frames / 2,
            "{label}: {steps} of {frames} frames steps"
        );
    }
    // Every other model of the repository (rational patches, poles, open models): the frames
    // must agree; how much is kept is not asked.
    let others = bpt_models()
        .into_iter()
        .chain(nurbs_fixtures())
        .filter(|p| !["teapot.bpt", "teaspoon.bpt", "gumbo.bpt"].contains(&name(p).as_str()));
    for path in others {
        let baked = bake(&path, 5e-3);
        let mut links = Vec::new();
        follow(
            &name(&path),
            baked.linked_tree(&mut links),
            Arithmetic::Float,
            true,
        );
    }
    // The compact bytes, as a firmware reads them.
    let baked = bake(&models_dir().join("teapot.bpt"), 2e-3);
    let bytes = baked.encoded();
    let mut links = vec![Default::default(); baked.tree().link_slots()];
    let linked = baked.tree_from(&bytes);
    linked.fill_links(&mut links).unwrap();
    let linked = linked.with_links(&links).unwrap();
    let (kept, judged, steps) = follow("teapot bytes", linked, Arithmetic::Float, true);
    assert!(
        kept > judged / 2 && steps > 0,
        "teapot bytes: {kept} kept, {judged} judged, {steps} steps"
    );
    // With the bounds in integers (a part without an FPU), the triangles of the bake keep no
    // certificate: every frame is still the fresh one, and only judgements below the bake
    // carry over.
    let (kept, judged, _) = follow(
        "teapot bytes, integer bounds",
        baked.tree_from(&bytes),
        Arithmetic::Integer,
        false,
    );
    assert!(
        kept < judged / 10,
        "integer bounds: {kept} kept, {judged} judged"
    );
}

#[test]
fn too_few_judgement_slots_are_refused() {
    let baked = bake(&models_dir().join("teaspoon.bpt"), 1e-2);
    let tree = baked.tree();
    let mut storage = VecStorage::new(&tree, 64, 0);
    let mut short = vec![Judgement::NONE; tree.judgement_slots() - 1];
    assert_eq!(
        storage.tessellator(tree).with_reuse(&mut short).err(),
        Some(
            spline_tess::tessellator::TessellatorError::JudgementsTooShort {
                needed: tree.judgement_slots()
            }
        )
    );
}

/// Random walks of the camera (fixed seeds): steps of every size from a tenth of a degree to
/// several, the eye nearing and backing off, the target and the tolerance wandering a little;
/// a tessellator that steps from frame to frame gives the fresh frames, and most frames are
/// steps. Where a judgement flips at a coarse triangle, a step takes away whole subtrees and
/// makes halvings again: the walks reach those.
/// A camera jump asks for no certificates: the frame judges what a fresh tessellator judges
/// and keeps nothing, and the frame after it is searched from the roots (it writes the
/// certificates); the one after that steps (the teapot with links, one-degree orbit steps
/// around a 60° jump).
#[test]
fn a_jump_costs_a_cold_frame_and_the_steps_start_again_after_it() {
    let baked = bake(&models_dir().join("teapot.bpt"), 2e-3);
    let mut links = Vec::new();
    let tree = baked.linked_tree(&mut links);
    let b = tree.model().aabb().unwrap();
    let (c, d) = (b.center(), b.diagonal());
    let view = |degrees: f32| {
        let (s, k) = degrees.to_radians().sin_cos();
        let r = Vec3::new(1.0, -1.3, 0.0) * d;
        let eye = c + Vec3::new(k * r.x - s * r.y, s * r.x + k * r.y, 0.7 * d);
        View::Screen {
            camera: camera_40(eye, c, 0.01 * d, [320, 240]),
            tolerance_px: 1.0,
        }
    };
    let mut storage = VecStorage::new(&tree, 256, 1 << 14);
    let mut fresh_storage = VecStorage::new(&tree, 256, 1 << 14);
    let mut judgements = vec![Judgement::NONE; tree.judgement_slots()];
    let mut kept = storage
        .tessellator(tree)
        .with_reuse(&mut judgements)
        .unwrap();
    // Each frame's angle, and whether it steps: not the first (nothing before it), nor the
    // second (the first wrote no certificates), nor the jump, nor the frame after it.
    let expect = [
        (0.0, false),
        (1.0, false),
        (2.0, true),
        (3.0, true),
        (63.0, false),
        (64.0, false),
        (65.0, true),
        (66.0, true),
    ];
    for (degrees, steps) in expect {
        let view = view(degrees);
        let stats = kept.update(&view).unwrap();
        let mut fresh = fresh_storage.tessellator(tree);
        let expected = fresh.update(&view).unwrap();
        let label = format!("at {degrees}°");
        assert_eq!(stats.stepped, steps, "{label}");
        assert_eq!(stats.triangles, expected.triangles, "{label}");
        assert_eq!(indexed(&mut kept), indexed(&mut fresh), "{label}: the mesh");
        if !steps {
            // Nothing held: everything a search looks at is judged.
            assert_eq!(stats.kept, 0, "{label}");
            assert_eq!(stats.judged, expected.judged, "{label}");
        }
    }
}

#[test]
fn random_walks_step_to_the_fresh_frames() {
    for (model, relative, seed) in [
        ("teapot.bpt", 2e-3, 11),
        ("gumbo.bpt", 2e-3, 12),
        ("teacup.bpt", 2e-3, 13),
    ] {
        let baked = bake(&models_dir().join(model), relative);
        let mut links = Vec::new();
        let tree = baked.linked_tree(&mut links);
        let b = tree.model().aabb().unwrap();
        let (c, d) = (b.center(), b.diagonal());
        let mut rng = host_tests::Rng::for_test(seed);
        let mut storage = VecStorage::new(&tree, 256, 1 << 14);
        let mut fresh_storage = VecStorage::new(&tree, 256, 1 << 14);
        let mut judgements = vec![Judgement::NONE; tree.judgement_slots()];
        let mut kept = storage
            .tessellator(tree)
            .with_reuse(&mut judgements)
            .unwrap();
        let (mut angle, mut distance, mut steps) = (0.0f32, 1.0f32, 0);
        let frames = 60;
        for k in 0..frames {
            // Mostly small steps, now and then a large one, and a jump.
            let u = rng.unit() as f32;
            angle += match u {
                ..0.8 => 2.0 * u,
                ..0.96 => 30.0 * (u - 0.8),
                _ => 60.0,
            };
            distance = (distance * (0.97 + 0.06 * rng.unit() as f32)).clamp(0.5, 1.5);
            let (s, q) = angle.to_radians().sin_cos();
            let r = Vec3::new(1.0, -1.3, 0.0) * distance * d;
            let eye = c + Vec3::new(q * r.x - s * r.y, s * r.x + q * r.y, 0.7 * distance * d);
            let target = c + Vec3::new(rng.unit() as f32 - 0.5, 0.0, 0.0) * 0.01 * d;
            let tolerance_px = if rng.unit() < 0.9 { 1.0 } else { 0.75 };
            let view = View::Screen {
                camera: camera_40(eye, target, 0.01 * d, [320, 240]),
                tolerance_px,
            };
            let stats = kept.update(&view).unwrap();
            steps += usize::from(stats.stepped);
            let mut fresh = fresh_storage.tessellator(tree);
            let expected = fresh.update(&view).unwrap();
            let label = format!("{model} frame {k}");
            assert_eq!(stats.triangles, expected.triangles, "{label}");
            assert_eq!(stats.hidden, expected.hidden, "{label}");
            assert_eq!(stats.left_over, expected.left_over, "{label}");
            assert_eq!(indexed(&mut kept), indexed(&mut fresh), "{label}: the mesh");
        }
        assert!(
            steps > frames / 2,
            "{model}: {steps} of {frames} frames steps"
        );
    }
}

/// A step of `update_parallel` makes its judgements again on the threads: along the path,
/// its frames are `update`'s, figures and all (the same judgements, kept in the same order),
/// and the steps are large enough that the threads take them.
#[test]
fn steps_on_the_threads_are_the_steps_on_one() {
    for (model, relative) in [("teapot.bpt", 1e-3), ("gumbo.bpt", 2e-3)] {
        let baked = bake(&models_dir().join(model), relative);
        let mut links = Vec::new();
        let tree = baked.linked_tree(&mut links);
        let mut one_storage = VecStorage::new(&tree, 256, 1 << 14);
        let mut threads_storage = VecStorage::new(&tree, 256, 1 << 14);
        let mut one_judgements = vec![Judgement::NONE; tree.judgement_slots()];
        let mut threads_judgements = vec![Judgement::NONE; tree.judgement_slots()];
        let mut one = one_storage
            .tessellator(tree)
            .with_reuse(&mut one_judgements)
            .unwrap();
        let mut threads = threads_storage
            .tessellator(tree)
            .with_reuse(&mut threads_judgements)
            .unwrap();
        // The steps that judge 512 or more again: the ones the threads judge.
        let mut on_threads = 0;
        for (label, view) in path(&tree) {
            let expected = one.update(&view).unwrap();
            let stats = threads.update_parallel(&view).unwrap();
            let label = format!("{model} {label}");
            assert_eq!(stats, expected, "{label}: the figures");
            assert_eq!(
                indexed(&mut threads),
                indexed(&mut one),
                "{label}: the mesh"
            );
            on_threads += usize::from(stats.stepped && stats.judged >= 512);
        }
        eprintln!("{model}: {on_threads} steps on the threads");
        // (A step judging fewer than 512 again stays on the calling thread.)
        assert!(
            on_threads >= 8,
            "{model}: {on_threads} steps on the threads"
        );
    }
}
