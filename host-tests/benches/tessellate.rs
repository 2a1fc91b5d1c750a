//! Run-time figures (criterion): full tessellation of the teapot and Gumbo at 0.5 px and 1 px
//! on a 1024x768 view, and one frame after a 1-degree orbit step against a full rebuild.
//!
//! ```text
//! cargo bench -p host-tests --bench tessellate
//! ```
//!
//! Each model is baked once (relative tolerance 2.5e-4) before measuring. "full" builds a
//! tessellator over preallocated storage, updates it to the view and writes the indexed mesh;
//! "step" moves an existing tessellator between two views 1 degree apart on an orbit (update
//! and write); "step_update" is the update alone. Triangle counts are printed to stderr.

use criterion::{criterion_group, criterion_main, Criterion};
use host_tests::model_file::{bake_to_vec, ModelFile};
use host_tests::runtime::RuntimeStorage;
use spline_tess::bake::{BakeSettings, BakedModel, Tolerance};
use spline_tess::tessellator::Settings;
use spline_tess::{Camera, Projection, Vec3, Vertex, View};

const VIEWPORT: [u32; 2] = [1024, 768];

fn view(center: Vec3, diag: f32, degrees: f32, tol: f32) -> View {
    let a = degrees.to_radians();
    let eye = center + Vec3::new(a.cos(), a.sin(), 0.45).normalize() * (1.3 * diag);
    let camera = Camera::new(
        eye,
        center,
        Vec3::Z,
        Projection::Perspective {
            fov_y_degrees: 40.0,
        },
        0.01 * diag,
        VIEWPORT,
    )
    .unwrap();
    View::Screen {
        camera,
        tolerance_px: tol,
    }
}

fn bench(c: &mut Criterion) {
    for model in ["teapot.bpt", "gumbo.bpt"] {
        let path = host_tests::models_dir().join(model);
        let file = ModelFile::read(path.to_str().unwrap()).unwrap();
        let bake = BakeSettings {
            tolerance: Tolerance::Relative(2.5e-4),
            max_curve_samples: 256,
            max_interior_samples: 4096,
        };
        let bytes = file.with_model(|m| bake_to_vec(m, &bake)).unwrap().unwrap();
        let baked = BakedModel::from_bytes(&bytes).unwrap();
        let patches = file.patches();
        let aabb = patches.aabb().unwrap();
        let (center, diag) = (aabb.center(), aabb.diagonal());
        let settings = Settings::default();
        let mut storage = RuntimeStorage::new(&baked, &settings);
        let mut vertices = vec![Vertex::default(); 1 << 21];
        let mut triangles = vec![[0u32; 3]; 1 << 22];
        let mut group = c.benchmark_group(model.trim_end_matches(".bpt"));
        group.sample_size(10);
        group.measurement_time(std::time::Duration::from_secs(4));
        for tol in [1.0f32, 0.5] {
            let v = view(center, diag, 30.0, tol);
            {
                let mut t = storage.tessellator(patches, baked, settings);
                let s = t.update(&v).unwrap();
                eprintln!(
                    "{model} {tol} px: {} triangles, {} vertices, {} refined patches, predicted {:.3} px",
                    s.triangles, s.vertices, s.refined_patches, s.max_predicted_error
                );
            }
            group.bench_function(format!("full_{tol}px"), |b| {
                b.iter(|| {
                    let mut t = storage.tessellator(patches, baked, settings);
                    t.update(&v).unwrap();
                    t.write_mesh(&mut vertices, &mut triangles).unwrap()
                })
            });
        }
        let (a, b) = (view(center, diag, 30.0, 1.0), view(center, diag, 31.0, 1.0));
        let mut t = storage.tessellator(patches, baked, settings);
        t.update(&a).unwrap();
        let s = t.update(&b).unwrap();
        eprintln!(
            "{model} 1 degree step: +{} -{} samples, {} triangles estimated of {}",
            s.inserted, s.deleted, s.estimated, s.triangles
        );
        let mut flip = false;
        group.bench_function("step_1px", |bench| {
            bench.iter(|| {
                flip = !flip;
                t.update(if flip { &a } else { &b }).unwrap();
                t.write_mesh(&mut vertices, &mut triangles).unwrap()
            })
        });
        group.bench_function("step_update_1px", |bench| {
            bench.iter(|| {
                flip = !flip;
                t.update(if flip { &a } else { &b }).unwrap()
            })
        });
        group.bench_function("full_update_1px", |bench| {
            bench.iter(|| {
                let mut t = storage.tessellator(patches, baked, settings);
                t.update(&b).unwrap()
            })
        });
        group.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
