//! Triangles come counter-clockwise seen from outside, with outward normals (the bake's
//! orientation rule, `spline_tess::bake`): on every model, the written mesh's signed volume
//! about the centre of the control points' box is positive where the rule knows the side
//! (as the bake judges it: the volume is at least 1% of the volume's absolute integral, here
//! measured on the mesh), and every triangle's (but those where the surface's normal turns
//! by more than a right angle from corner to corner, and those thinner than the tolerance,
//! whose corners lie within it of a line, so that the side they turn around is not
//! determined by a mesh within the tolerance) normals at the corners its own patch evaluated
//! agree with its winding (their sum points to the side its corners turn counter-clockwise
//! around) (a corner shared with another patch carries that patch's normal,
//! which points the other way only where two coincident patches face opposite ways, as the
//! teacup's two bottoms do: those are counted). The Utah teapot, whose patches all face inward
//! as drawn, and Gumbo come out with a positive volume.

use host_tests::model_file::ModelFile;
use host_tests::runtime::{indexed, streamed, BakedHierarchy, VecStorage};
use host_tests::{bpt_models, name, nurbs_fixtures};
use spline_tess::bake::{BakeSettings, Tolerance};
use spline_tess::View;

type V3 = [f64; 3];

fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[test]
fn meshes_face_out_with_normals_along_their_winding() {
    let bake = BakeSettings {
        tolerance: Tolerance::Relative(1e-3),
        ..BakeSettings::default()
    };
    let mut known = 0;
    for path in bpt_models().into_iter().chain(nurbs_fixtures()) {
        let label = name(&path);
        let file = ModelFile::read(path.to_str().unwrap()).unwrap();
        let baked = BakedHierarchy::bake(&file, &bake).unwrap();
        let tree = baked.tree();
        let aabb = file.patches().aabb().unwrap();
        let diag = aabb.diagonal();
        let c = aabb.center().to_array().map(f64::from);
        let mut storage = VecStorage::new(&tree, 1024, 1 << 16);
        let mut tess = storage.tessellator(tree);
        let tolerance = 2e-3 * diag;
        tess.update(&View::Object { tolerance }).unwrap();
        let mesh = indexed(&mut tess);
        let patch_of: Vec<u32> = streamed(&tess).iter().map(|t| t.patch).collect();
        let p = |i: u32| mesh.vertices[i as usize].position.map(f64::from);
        let n = |i: u32| mesh.vertices[i as usize].normal.map(f64::from);
        let (mut volume, mut size) = (0.0, 0.0);
        let (mut agree, mut against, mut faces) = (0, 0, 0);
        let (mut shared, mut thin) = (0, 0);
        for (k, &[a, b, d]) in mesh.triangles.iter().enumerate() {
            let tetra = dot(sub(p(a), c), cross(sub(p(b), c), sub(p(d), c))) / 6.0;
            volume += tetra;
            size += tetra.abs();
            let face = cross(sub(p(b), p(a)), sub(p(d), p(a)));
            let area = dot(face, face).sqrt();
            let corners = [a, b, d];
            if area < 1e-12 * (diag as f64).powi(2) {
                continue;
            }
            // Where the surface's normal turns by more than a right angle between two corners
            // (a side collapsed to a pole or to a line, as the lid's knob of `teapot_orig28`
            // has: its normal there is a limit), the flat triangle may turn any way: left out.
            let folded = (0..3).any(|i| dot(n(corners[i]), n(corners[(i + 1) % 3])) < 0.0);
            if folded {
                continue;
            }
            let longest = (0..3)
                .map(|i| {
                    let d = sub(p(corners[i]), p(corners[(i + 1) % 3]));
                    dot(d, d).sqrt()
                })
                .fold(0.0, f64::max);
            if area / longest < tolerance as f64 {
                thin += 1;
                continue;
            }
            faces += 1;
            // The corners the triangle's own patch evaluated carry its normal; a corner from
            // another patch carries that patch's (the same side where the two agree, which
            // coincident patches facing opposite ways, as the teacup's two bottoms, do not).
            let own = |i: u32| mesh.vertices[i as usize].patch == patch_of[k];
            let along: f64 = corners
                .iter()
                .filter(|&&i| own(i))
                .map(|&i| dot(n(i), face))
                .sum();
            if along > 0.0 {
                agree += 1;
            } else {
                against += 1;
            }
            shared += usize::from(corners.iter().any(|&i| !own(i) && dot(n(i), face) <= 0.0));
        }
        println!(
            "{label}: {} triangles, signed volume {volume:.4} ({:.1}% of its absolute sum), \
             normals along the winding on {agree} of {faces} triangles ({shared} with a corner \
             of a patch facing the other way; {thin} thinner than the tolerance left out)",
            mesh.triangles.len(),
            100.0 * volume / size
        );
        assert_eq!(
            against, 0,
            "{label}: {against} triangles' normals oppose their winding"
        );
        if volume.abs() >= 0.01 * size {
            known += 1;
            assert!(
                volume > 0.0,
                "{label}: signed volume {volume} is not positive"
            );
        }
        if label == "teapot.bpt" || label == "gumbo.bpt" {
            assert!(volume > 0.0, "{label}: signed volume {volume}");
        }
    }
    assert!(known >= 6, "only {known} models with a known side");
}
