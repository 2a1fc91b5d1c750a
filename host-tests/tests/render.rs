//! The renderer (`spline_tess::render`):
//!
//! - fill rule: random triangulations of a square, seen head-on and tilted, drawn onto
//!   `MockDisplay` (which panics when a pixel is drawn twice) and a counting target: every
//!   pixel whose centre is inside the square is drawn exactly once, no other;
//! - the teapot's coverage mask at 1 px tolerance agrees with a reference rendering (a dense
//!   f64 tessellation, rasterised by the same renderer) on at least 99.5% of the pixels, and
//!   differs only within 2 pixels of the silhouette;
//! - the band height changes nothing, streaming equals drawing the written mesh, frames are
//!   deterministic; target errors and a too-small depth buffer come back as typed errors;
//! - band buffers: `draw_bands` pushes every pixel of the viewport exactly once, one window
//!   per band, with the colours `draw` leaves in a framebuffer; with a triangle list the source
//!   is streamed once and the pixels are the same as without; a list too small for the frame
//!   falls back to streaming; `draw_bands_rgb565` sends the same pixels as big-endian bytes.

use std::convert::Infallible;

use embedded_graphics::draw_target::DrawTarget;
use embedded_graphics::mock_display::MockDisplay;
use embedded_graphics::pixelcolor::{Rgb565, Rgb888};
use embedded_graphics::prelude::{OriginDimensions, Pixel, Point, PointsIter, RgbColor, Size};
use embedded_graphics::primitives::Rectangle;
use host_tests::model_file::ModelFile;
use host_tests::reference::RefPatch;
use host_tests::runtime::{indexed, BakedHierarchy, VecStorage};
use host_tests::{models_dir, Rng};
use spline_tess::bake::BakeSettings;
use spline_tess::bake::Tolerance;
use spline_tess::render::{
    IndexedMesh, ListSlot, RenderError, Renderer, Shading, Style, TriangleSource, Wireframe,
};
use spline_tess::{BoundingSphere, Camera, Projection, Vec3, Vertex, View};

/// Counts how often each pixel is drawn; remembers the last colour.
struct Counting {
    size: Size,
    hits: Vec<u32>,
    color: Vec<Option<Rgb888>>,
    runs: usize,
}

impl Counting {
    fn new(w: u32, h: u32) -> Self {
        Counting {
            size: Size::new(w, h),
            hits: vec![0; (w * h) as usize],
            color: vec![None; (w * h) as usize],
            runs: 0,
        }
    }

    fn mask(&self) -> Vec<bool> {
        self.hits.iter().map(|&h| h > 0).collect()
    }
}

impl OriginDimensions for Counting {
    fn size(&self) -> Size {
        self.size
    }
}

impl DrawTarget for Counting {
    type Color = Rgb888;
    type Error = Infallible;

    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb888>>>(
        &mut self,
        it: I,
    ) -> Result<(), Infallible> {
        for Pixel(p, c) in it {
            assert!(
                p.x >= 0
                    && p.y >= 0
                    && p.x < self.size.width as i32
                    && p.y < self.size.height as i32,
                "pixel {p:?} outside the target"
            );
            let i = (p.y * self.size.width as i32 + p.x) as usize;
            self.hits[i] += 1;
            self.color[i] = Some(c);
        }
        Ok(())
    }

    fn fill_contiguous<I: IntoIterator<Item = Rgb888>>(
        &mut self,
        area: &Rectangle,
        colors: I,
    ) -> Result<(), Infallible> {
        self.runs += 1;
        assert_eq!(area.size.height, 1, "runs are along one row");
        let points = (0..area.size.width as i32).map(|dx| area.top_left + Point::new(dx, 0));
        let pixels: Vec<_> = points.zip(colors).map(|(p, c)| Pixel(p, c)).collect();
        assert_eq!(
            pixels.len(),
            area.size.width as usize,
            "one colour per pixel"
        );
        self.draw_iter(pixels)
    }
}

fn vertex(p: [f32; 3], n: [f32; 3]) -> Vertex {
    Vertex {
        position: p,
        normal: n,
        ..Vertex::default()
    }
}

/// A jittered `n x n` grid over the square `[-1, 1]^2` at z = 0 (the boundary points stay on
/// the boundary), each quad split along a random diagonal, triangles in random orientation.
fn random_square(rng: &mut Rng, n: usize) -> (Vec<Vertex>, Vec<[u32; 3]>) {
    let mut vs = Vec::new();
    let step = 2.0 / n as f64;
    for j in 0..=n {
        for i in 0..=n {
            let jitter = |k: usize, rng: &mut Rng| {
                if k == 0 || k == n {
                    0.0
                } else {
                    (rng.unit() - 0.5) * 0.8 * step
                }
            };
            let x = -1.0 + i as f64 * step + jitter(i, rng);
            let y = -1.0 + j as f64 * step + jitter(j, rng);
            vs.push(vertex([x as f32, y as f32, 0.0], [0.0, 0.0, 1.0]));
        }
    }
    let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut ts = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            let pair = if rng.unit() < 0.5 {
                [[a, b, c], [a, c, d]]
            } else {
                [[a, b, d], [b, c, d]]
            };
            for [x, y, z] in pair {
                ts.push(if rng.unit() < 0.5 {
                    [x, y, z]
                } else {
                    [x, z, y]
                });
            }
        }
    }
    (vs, ts)
}

#[test]
fn shared_edges_draw_each_pixel_once_and_leave_no_gap() {
    let mut rng = Rng::for_test(7);
    for case in 0..60 {
        let (vs, ts) = random_square(&mut rng, 3 + case % 9);
        let mesh = IndexedMesh {
            vertices: &vs,
            triangles: &ts,
        };
        // Orthographic head-on: the square's edges fall at known columns; shifted by a
        // random subpixel offset so that centres also land on edges and vertices.
        let offset = Vec3::new(rng.unit() as f32 * 0.1, rng.unit() as f32 * 0.1, 0.0);
        let camera = Camera::new(
            offset + Vec3::Z * 5.0,
            offset,
            Vec3::Y,
            Projection::Orthographic { height: 3.2 },
            0.1,
            [64, 64],
        )
        .unwrap();
        let style = Style {
            shading: if case % 2 == 0 {
                Shading::Flat
            } else {
                Shading::Gouraud
            },
            wireframe: (case % 3 == 0).then_some(Wireframe {
                color: Rgb888::RED,
                half_width: 0.5,
            }),
            ..Style::default()
        };
        let mut display = MockDisplay::<Rgb565>::new();
        let mut depth = vec![0u16; 64 * (1 + case % 20)];
        Renderer::new(&mut depth)
            .draw(&mesh, &camera, &style, &mut display)
            .unwrap();
        let mut count = Counting::new(64, 64);
        Renderer::new(&mut depth)
            .draw(&mesh, &camera, &style, &mut count)
            .unwrap();
        // The square spans [-1, 1] around the offset: 20 pixels per unit.
        for y in 0..64 {
            for x in 0..64 {
                let px = (x as f32 + 0.5 - 32.0) / 20.0 + offset.x;
                let py = (32.0 - (y as f32 + 0.5)) / 20.0 + offset.y;
                // Vertices snap to 1/16 pixel (up to 1/32 off): centres closer to the edge
                // than 0.05 pixel (0.0025 units) may go either way.
                let inside = px.abs() < 1.0 - 2.5e-3 && py.abs() < 1.0 - 2.5e-3;
                let outside = px.abs() > 1.0 + 2.5e-3 || py.abs() > 1.0 + 2.5e-3;
                let hits = count.hits[y * 64 + x];
                let drawn = display.get_pixel(Point::new(x as i32, y as i32)).is_some();
                assert_eq!(
                    drawn,
                    hits == 1,
                    "case {case}: MockDisplay and counter differ"
                );
                if inside {
                    assert_eq!(
                        hits, 1,
                        "case {case}: pixel {x},{y} inside drawn {hits} times"
                    );
                }
                if outside {
                    assert_eq!(hits, 0, "case {case}: pixel {x},{y} outside drawn");
                }
                assert!(hits <= 1, "case {case}: pixel {x},{y} drawn {hits} times");
            }
        }
    }
}

#[test]
fn a_tilted_square_in_perspective_has_no_overdraw_or_gap() {
    let mut rng = Rng::for_test(11);
    for case in 0..20 {
        let (vs, ts) = random_square(&mut rng, 4 + case % 7);
        let mesh = IndexedMesh {
            vertices: &vs,
            triangles: &ts,
        };
        let eye = Vec3::new(
            (rng.unit() as f32 - 0.5) * 2.0,
            -2.5,
            1.5 + rng.unit() as f32,
        );
        let camera = Camera::new(
            eye,
            Vec3::ZERO,
            Vec3::Z,
            Projection::Perspective {
                fov_y_degrees: 60.0,
            },
            0.05,
            [64, 64],
        )
        .unwrap();
        let mut depth = vec![0u16; 64 * 5];
        let mut count = Counting::new(64, 64);
        let style = Style::default();
        let stats = Renderer::new(&mut depth)
            .draw(&mesh, &camera, &style, &mut count)
            .unwrap();
        assert!(count.hits.iter().all(|&h| h <= 1), "case {case}: overdraw");
        // No gap: the covered pixels are those whose centre falls inside the projected
        // square, which is convex; check against its four projected corners.
        let corners = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]
            .map(|[x, y]| camera.project(Vec3::new(x, y, 0.0)).unwrap());
        let side = |a: [f32; 2], b: [f32; 2], p: [f32; 2]| {
            (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])
        };
        let mut inside_count = 0;
        for y in 0..64 {
            for x in 0..64 {
                let p = [x as f32 + 0.5, y as f32 + 0.5];
                let s: Vec<f32> = (0..4)
                    .map(|k| side(corners[k], corners[(k + 1) % 4], p))
                    .collect();
                let margin = 0.05 * 64.0;
                let inside = s.iter().all(|&v| v > margin) || s.iter().all(|&v| v < -margin);
                if inside {
                    inside_count += 1;
                    assert_eq!(count.hits[y * 64 + x], 1, "case {case}: gap at {x},{y}");
                }
            }
        }
        assert!(inside_count > 100, "case {case}: the square is on screen");
        assert_eq!(stats.pixels as u32, count.hits.iter().sum::<u32>());
        assert_eq!(stats.runs, count.runs as u32);
    }
}

const BAKE: BakeSettings = BakeSettings {
    tolerance: Tolerance::Relative(1e-3),
    max_depth: 24,
    max_cell_level: spline_tess::tessellator::MAX_CELL_LEVEL,
};

/// The teapot and its hierarchy.
fn teapot() -> (ModelFile, BakedHierarchy) {
    let path = models_dir().join("teapot.bpt");
    let file = ModelFile::read(path.to_str().unwrap()).unwrap();
    let baked = BakedHierarchy::bake(&file, &BAKE).unwrap();
    (file, baked)
}

fn camera(eye: [f32; 3], size: [u32; 2]) -> Camera {
    Camera::new(
        Vec3::from_array(eye),
        Vec3::new(0.0, 0.0, 1.5),
        Vec3::Z,
        Projection::Perspective {
            fov_y_degrees: 40.0,
        },
        0.05,
        size,
    )
    .unwrap()
}

/// Views of the teapot: orbit, close, from above, grazing.
const EYES: [[f32; 3]; 5] = [
    [9.0, -12.0, 7.0],
    [-11.0, 4.0, 3.0],
    [4.0, -5.0, 3.5],
    [0.5, -0.5, 12.0],
    [12.0, 0.5, 1.6],
];

/// A dense tessellation of every patch, evaluated in f64: `n x n` quads per patch.
fn dense_reference(file: &ModelFile, n: usize) -> (Vec<Vertex>, Vec<[u32; 3]>) {
    let mut vs = Vec::new();
    let mut ts = Vec::new();
    for patch in file.patches().iter() {
        let r = RefPatch::from_kernel(&patch);
        let base = vs.len() as u32;
        for j in 0..=n {
            for i in 0..=n {
                let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                let p = r.point(u, v);
                vs.push(vertex(p.map(|x| x as f32), [0.0, 0.0, 1.0]));
            }
        }
        let id = |i: usize, j: usize| base + (j * (n + 1) + i) as u32;
        for j in 0..n {
            for i in 0..n {
                ts.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                ts.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
    }
    (vs, ts)
}

/// What `source` draws onto a counting target of `size` with a depth band of `rows` rows.
fn draw_banded(
    size: [u32; 2],
    rows: u32,
    source: &dyn Fn(&mut Renderer, &mut Counting),
) -> Counting {
    let mut depth = vec![0u16; (size[0] * rows) as usize];
    let mut target = Counting::new(size[0], size[1]);
    source(&mut Renderer::new(&mut depth), &mut target);
    target
}

fn mask_of(source: &impl TriangleSource, camera: &Camera, band_rows: u32) -> Counting {
    let [w, h] = camera.viewport();
    let mut target = Counting::new(w, h);
    let mut depth = vec![0u16; (w * band_rows) as usize];
    let style = Style {
        shading: Shading::Flat,
        ..Style::default()
    };
    Renderer::new(&mut depth)
        .draw(source, camera, &style, &mut target)
        .unwrap();
    target
}

#[test]
fn bands_streaming_and_repeats_give_the_same_pixels() {
    let (_, baked) = teapot();
    let tree = baked.tree();
    let mut storage = VecStorage::new(&tree, 1 << 12, 1 << 14);
    let mut tess = storage.tessellator(tree);
    let style = Style {
        wireframe: Some(Wireframe {
            color: Rgb888::BLACK,
            half_width: 0.4,
        }),
        background: Some(Rgb888::BLUE),
        ..Style::default()
    };
    for eye in EYES {
        let camera = camera(eye, [200, 150]);
        tess.update(&View::Screen {
            camera,
            tolerance_px: 1.0,
        })
        .unwrap();
        let draw = |source: &dyn Fn(&mut Renderer, &mut Counting), rows: u32| {
            draw_banded([200, 150], rows, source)
        };
        let streamed = |r: &mut Renderer, t: &mut Counting| {
            r.draw(&tess, &camera, &style, t).unwrap();
        };
        let full = draw(&streamed, 150);
        assert!(
            full.hits.iter().all(|&h| h >= 1),
            "with a background every pixel is drawn"
        );
        for rows in [1, 7, 16, 64] {
            let banded = draw(&streamed, rows);
            assert_eq!(
                banded.color, full.color,
                "eye {eye:?}: {rows}-row bands differ"
            );
            assert_eq!(
                banded.hits, full.hits,
                "eye {eye:?}: {rows}-row bands draw differently"
            );
        }
        let again = draw(&streamed, 16);
        assert_eq!(again.color, full.color, "a second draw differs");
        let mesh = indexed(&mut tess);
        let written = IndexedMesh {
            vertices: &mesh.vertices,
            triangles: &mesh.triangles,
        };
        let from_mesh = draw(
            &|r: &mut Renderer, t: &mut Counting| {
                r.draw(&written, &camera, &style, t).unwrap();
            },
            16,
        );
        assert_eq!(
            from_mesh.color, full.color,
            "eye {eye:?}: streamed != written mesh"
        );
        // Flat and Gouraud differ somewhere, so both are exercised.
        let flat = Style {
            shading: Shading::Flat,
            ..style
        };
        let mut depth = vec![0u16; 200 * 16];
        let mut t = Counting::new(200, 150);
        Renderer::new(&mut depth)
            .draw(&tess, &camera, &flat, &mut t)
            .unwrap();
        assert_ne!(t.color, full.color);
    }
}

/// An indexed mesh drawn with another source's depth range.
struct WithBound<'a> {
    mesh: IndexedMesh<'a, u32>,
    bound: Option<BoundingSphere>,
}

impl TriangleSource for WithBound<'_> {
    fn bound(&self) -> Option<BoundingSphere> {
        self.bound
    }

    fn stream_rows(
        &self,
        camera: &Camera,
        rows: std::ops::Range<u32>,
        sink: &mut impl spline_tess::TriangleSink,
    ) {
        self.mesh.stream_rows(camera, rows, sink);
    }
}

/// The bisection run time as a source: its frames cover the surface as a dense `f64`
/// tessellation does, and streamed (by vertex numbers, band by band) they draw exactly the
/// pixels of their written mesh.
#[test]
fn bisection_frames_cover_the_surface_and_draw_as_their_mesh() {
    let (file, bake) = teapot();
    let tree = bake.tree();
    let mut storage = VecStorage::new(&tree, 1 << 12, 1 << 14);
    let mut selection = storage.tessellator(tree);
    let mut remap = vec![0u32; selection.remap_len()];
    let (rv, rt) = dense_reference(&file, 96);
    let reference = IndexedMesh {
        vertices: &rv,
        triangles: &rt,
    };
    let style = Style {
        wireframe: Some(Wireframe {
            color: Rgb888::BLACK,
            half_width: 0.4,
        }),
        background: Some(Rgb888::BLUE),
        ..Style::default()
    };
    for eye in EYES {
        let camera = camera(eye, [320, 240]);
        selection
            .update(&View::Screen {
                camera,
                tolerance_px: 1.0,
            })
            .unwrap();
        let ours = mask_of(&selection, &camera, 16).mask();
        let want = mask_of(&reference, &camera, 16).mask();
        let differ = ours.iter().zip(&want).filter(|(a, b)| a != b).count();
        let union = ours.iter().zip(&want).filter(|(a, b)| **a || **b).count();
        let agree = 1.0 - differ as f64 / ours.len() as f64;
        println!(
            "eye {eye:?}: {differ} of {union} covered pixels differ ({:.3}% of the pixels agree)",
            100.0 * agree
        );
        assert!(union > 2000, "the teapot is on screen");
        assert!(agree >= 0.995, "eye {eye:?}: {:.3}% agree", 100.0 * agree);
        // At 1 px, coverage may differ only on the rim: every differing pixel has covered and
        // uncovered pixels of the reference within 2 pixels (the tolerance, and half a pixel
        // of sampling on each side).
        let (w, h) = (320usize, 240usize);
        for (i, _) in ours
            .iter()
            .zip(&want)
            .enumerate()
            .filter(|(_, (a, b))| a != b)
        {
            let (x, y) = (i % w, i / w);
            let near = |covered: bool| {
                (y.saturating_sub(2)..(y + 3).min(h)).any(|yy| {
                    (x.saturating_sub(2)..(x + 3).min(w)).any(|xx| want[yy * w + xx] == covered)
                })
            };
            assert!(
                near(true) && near(false),
                "eye {eye:?}: pixel ({x}, {y}) differs away from the silhouette"
            );
        }
        let size = selection.mesh_size();
        let mut vertices = vec![Vertex::default(); size.vertices];
        let mut triangles = vec![[0u32; 3]; size.triangles];
        selection
            .write_mesh(&mut vertices, &mut triangles, &mut remap)
            .unwrap();
        // The written mesh, with the run time's depth range (a source's bound sets it, and
        // the mesh's own box is smaller: its depths would round otherwise).
        let written = WithBound {
            mesh: IndexedMesh {
                vertices: &vertices,
                triangles: &triangles,
            },
            bound: selection.bound(),
        };
        let draw = |source: &dyn Fn(&mut Renderer, &mut Counting), rows: u32| {
            draw_banded([320, 240], rows, source)
        };
        let from_mesh = draw(
            &|r: &mut Renderer, t: &mut Counting| {
                r.draw(&written, &camera, &style, t).unwrap();
            },
            16,
        );
        let streamed = |rows| {
            draw(
                &|r: &mut Renderer, t: &mut Counting| {
                    r.draw(&selection, &camera, &style, t).unwrap();
                },
                rows,
            )
        };
        let differ = |a: &Counting, b: &Counting| {
            a.color
                .iter()
                .zip(&b.color)
                .zip(a.hits.iter().zip(&b.hits))
                .filter(|((a, b), (c, d))| a != b || c != d)
                .count()
        };
        let sixteen = streamed(16);
        assert_eq!(
            differ(&sixteen, &from_mesh),
            0,
            "eye {eye:?}: streamed differs from the written mesh"
        );
        for rows in [1, 7, 240] {
            assert_eq!(
                differ(&streamed(rows), &sixteen),
                0,
                "eye {eye:?}: {rows}-row bands differ from 16-row ones"
            );
        }
    }
}

/// A target that fails after a number of runs.
struct Failing(usize);

impl OriginDimensions for Failing {
    fn size(&self) -> Size {
        Size::new(32, 32)
    }
}

impl DrawTarget for Failing {
    type Color = Rgb565;
    type Error = &'static str;

    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb565>>>(
        &mut self,
        _: I,
    ) -> Result<(), Self::Error> {
        if self.0 == 0 {
            return Err("bus error");
        }
        self.0 -= 1;
        Ok(())
    }
}

#[test]
fn errors_are_typed_and_stop_drawing() {
    let vs = [
        vertex([-1.0, -1.0, 0.0], [0.0, 0.0, 1.0]),
        vertex([1.0, -1.0, 0.0], [0.0, 0.0, 1.0]),
        vertex([0.0, 1.0, 0.0], [0.0, 0.0, 1.0]),
    ];
    let ts = [[0u16, 1, 2]];
    let mesh = IndexedMesh {
        vertices: &vs,
        triangles: &ts,
    };
    let camera = Camera::new(
        Vec3::Z * 4.0,
        Vec3::ZERO,
        Vec3::Y,
        Projection::Orthographic { height: 3.0 },
        0.1,
        [32, 32],
    )
    .unwrap();
    let style = Style::default();
    let mut small = [0u16; 31];
    let e = Renderer::new(&mut small)
        .draw(&mesh, &camera, &style, &mut Failing(100))
        .unwrap_err();
    assert_eq!(e, RenderError::DepthTooSmall { needed: 32 });
    assert!(e.to_string().contains("32"));
    let mut depth = [0u16; 32 * 4];
    let e = Renderer::new(&mut depth)
        .draw(&mesh, &camera, &style, &mut Failing(3))
        .unwrap_err();
    assert_eq!(e, RenderError::Target("bus error"));
    // A target smaller than the viewport is drawn only where it is.
    let mut display = MockDisplay::<Rgb565>::new();
    let big = Camera::new(
        Vec3::Z * 4.0,
        Vec3::ZERO,
        Vec3::Y,
        Projection::Orthographic { height: 3.0 },
        0.1,
        [200, 100],
    )
    .unwrap();
    let mut depth = vec![0u16; 200 * 4];
    Renderer::new(&mut depth)
        .draw(&mesh, &big, &style, &mut display)
        .unwrap();
    let huge = Camera::new(
        Vec3::Z * 4.0,
        Vec3::ZERO,
        Vec3::Y,
        Projection::Orthographic { height: 3.0 },
        0.1,
        [32, spline_tess::render::MAX_VIEWPORT + 1],
    )
    .unwrap();
    let e = Renderer::new(&mut depth)
        .draw(&mesh, &huge, &style, &mut Counting::new(32, 32))
        .unwrap_err();
    assert_eq!(e, RenderError::ViewportTooLarge);
    // Nothing behind the eye or an empty source draws nothing.
    let empty: IndexedMesh<u16> = IndexedMesh {
        vertices: &[],
        triangles: &[],
    };
    let stats = Renderer::new(&mut depth)
        .draw(&empty, &camera, &style, &mut Counting::new(32, 32))
        .unwrap();
    assert_eq!((stats.triangles, stats.pixels), (0, 0));
    let behind = Camera::new(
        Vec3::Z * 4.0,
        Vec3::Z * 8.0,
        Vec3::Y,
        Projection::Perspective {
            fov_y_degrees: 60.0,
        },
        0.1,
        [32, 32],
    )
    .unwrap();
    let stats = Renderer::new(&mut depth)
        .draw(&mesh, &behind, &style, &mut Counting::new(32, 32))
        .unwrap();
    assert_eq!(stats.pixels, 0);
}

/// A display that takes whole windows only and records each pixel's colour and how often it
/// was sent.
struct Windows {
    counting: Counting,
    windows: Vec<Rectangle>,
}

impl OriginDimensions for Windows {
    fn size(&self) -> Size {
        self.counting.size
    }
}

impl DrawTarget for Windows {
    type Color = Rgb888;
    type Error = Infallible;

    fn draw_iter<I: IntoIterator<Item = Pixel<Rgb888>>>(&mut self, _: I) -> Result<(), Infallible> {
        panic!("band output sends whole windows, not single pixels")
    }

    fn fill_contiguous<I: IntoIterator<Item = Rgb888>>(
        &mut self,
        area: &Rectangle,
        colors: I,
    ) -> Result<(), Infallible> {
        self.windows.push(*area);
        let pixels: Vec<_> = area
            .points()
            .zip(colors)
            .map(|(p, c)| Pixel(p, c))
            .collect();
        assert_eq!(pixels.len() as u32, area.size.width * area.size.height);
        self.counting.draw_iter(pixels)
    }
}

#[test]
fn band_buffers_push_each_pixel_once_with_the_framebuffer_colours() {
    let (_, baked) = teapot();
    let tree = baked.tree();
    let mut storage = VecStorage::new(&tree, 1 << 12, 1 << 14);
    let mut tess = storage.tessellator(tree);
    let (w, h) = (200u32, 150u32);
    for (k, eye) in EYES.iter().enumerate() {
        let camera = camera(*eye, [w, h]);
        tess.update(&View::Screen {
            camera,
            tolerance_px: 1.0,
        })
        .unwrap();
        let style = Style {
            shading: if k % 2 == 0 {
                Shading::Gouraud
            } else {
                Shading::Flat
            },
            wireframe: (k % 3 == 0).then_some(Wireframe {
                color: Rgb888::BLACK,
                half_width: 0.4,
            }),
            background: (k != 1).then_some(Rgb888::BLUE),
            ..Style::default()
        };
        // What a framebuffer holds after `draw` (run by run, background included).
        let mut depth = vec![0u16; (w * 16) as usize];
        let mut framebuffer = Counting::new(w, h);
        let runs = Renderer::new(&mut depth)
            .draw(&tess, &camera, &style, &mut framebuffer)
            .unwrap();
        let bg = style.background.unwrap_or(Rgb888::BLACK);
        let expected: Vec<Rgb888> = framebuffer.color.iter().map(|c| c.unwrap_or(bg)).collect();

        let mut colors = vec![Rgb888::BLACK; (w * 16) as usize];
        let mut banded = |list: &mut [ListSlot], rows: u32| {
            let mut depth = vec![0u16; (w * rows) as usize];
            let mut target = Windows {
                counting: Counting::new(w, h),
                windows: Vec::new(),
            };
            let stats = Renderer::with_triangle_list(&mut depth, list)
                .draw_bands(&tess, &camera, &style, &mut colors, &mut target)
                .unwrap();
            assert!(
                target.counting.hits.iter().all(|&n| n == 1),
                "eye {eye:?}: every pixel pushed once"
            );
            let mut next = 0;
            for r in &target.windows {
                assert_eq!((r.top_left, r.size.width), (Point::new(0, next), w));
                next += r.size.height as i32;
            }
            assert_eq!(stats.pushed, w * h);
            assert_eq!(stats.bands as usize, target.windows.len());
            assert_eq!(
                stats.pixels, runs.pixels,
                "eye {eye:?}: same triangle pixels"
            );
            let got: Vec<Rgb888> = target.counting.color.iter().map(|c| c.unwrap()).collect();
            (stats, got)
        };
        // Bands of 16 rows, as many as the colour buffer holds (the depth buffer is larger).
        let (streamed, pixels) = banded(&mut [], 40);
        assert_eq!(streamed.bands, h.div_ceil(16));
        assert_eq!((streamed.passes, streamed.listed), (streamed.bands, 0));
        assert!(
            pixels == expected,
            "eye {eye:?}: bands differ from the framebuffer"
        );

        let mut list = vec![ListSlot::default(); 20_000];
        let (listed, from_list) = banded(&mut list, 16);
        assert_eq!(listed.passes, 1, "eye {eye:?}: one pass with a list");
        let frame = tess.stats().triangles as u32;
        assert!(listed.listed > 0 && listed.listed >= frame / 2);
        // Triangles share their corners' slots: well under the four slots each would take
        // with corners of its own.
        assert!(
            listed.list_slots <= 2 * listed.listed,
            "eye {eye:?}: {} slots for {} triangles",
            listed.list_slots,
            listed.listed
        );
        assert!(
            from_list == expected,
            "eye {eye:?}: the list draws differently"
        );

        // A list that holds part of the frame keeps whole patches and streams the rest.
        let short = listed.listed as usize / 2;
        let (partial, again) = banded(&mut list[..short], 16);
        assert!(partial.listed > 0 && partial.listed as usize <= short);
        assert_eq!(partial.passes, 1 + partial.bands);
        assert!(
            again == expected,
            "eye {eye:?}: the partial list draws differently"
        );

        // A source whose patches do not come in increasing order is streamed whole when the
        // list cannot hold it: the written mesh, triangles reversed.
        let mesh = indexed(&mut tess);
        let reversed: Vec<[u32; 3]> = mesh.triangles.iter().rev().copied().collect();
        let backwards = IndexedMesh {
            vertices: &mesh.vertices,
            triangles: &reversed,
        };
        for (len, whole) in [(list.len(), true), (short, false)] {
            let mut depth = vec![0u16; (w * 16) as usize];
            let mut target = Windows {
                counting: Counting::new(w, h),
                windows: Vec::new(),
            };
            let stats = Renderer::with_triangle_list(&mut depth, &mut list[..len])
                .draw_bands(&backwards, &camera, &style, &mut colors, &mut target)
                .unwrap();
            if whole {
                assert_eq!(stats.passes, 1);
                assert!(stats.listed as usize >= reversed.len() / 2);
            } else {
                assert_eq!((stats.passes, stats.listed), (1 + stats.bands, 0));
            }
            assert!(target.counting.hits.iter().all(|&n| n == 1));
        }

        // The same pixels as big-endian Rgb565 bytes, band by band.
        let mut depth = vec![0u16; (w * 8) as usize];
        let mut bytes = vec![0u8; (2 * w * 8) as usize];
        let mut sent = Vec::new();
        let stats = Renderer::with_triangle_list(&mut depth, &mut list)
            .draw_bands_rgb565(&tess, &camera, &style, &mut bytes, |area, band| {
                assert_eq!(area.top_left.y as usize, sent.len() / (2 * w as usize));
                sent.extend_from_slice(band);
                Ok::<(), Infallible>(())
            })
            .unwrap();
        assert_eq!(stats.bands, h.div_ceil(8));
        let want: Vec<u8> = expected
            .iter()
            .flat_map(|c| {
                use embedded_graphics::pixelcolor::raw::{RawData, RawU16};
                RawU16::from(Rgb565::from(*c)).into_inner().to_be_bytes()
            })
            .collect();
        assert!(sent == want, "eye {eye:?}: the bytes differ");
    }
}

#[test]
fn band_buffer_errors_are_typed() {
    let vs = [
        vertex([-1.0, -1.0, 0.0], [0.0, 0.0, 1.0]),
        vertex([1.0, -1.0, 0.0], [0.0, 0.0, 1.0]),
        vertex([0.0, 1.0, 0.0], [0.0, 0.0, 1.0]),
    ];
    let mesh = IndexedMesh {
        vertices: &vs,
        triangles: &[[0u16, 1, 2]],
    };
    let camera = Camera::new(
        Vec3::Z * 4.0,
        Vec3::ZERO,
        Vec3::Y,
        Projection::Orthographic { height: 3.0 },
        0.1,
        [32, 32],
    )
    .unwrap();
    let style = Style::default();
    let mut depth = [0u16; 32 * 4];
    let mut colors = [Rgb565::BLACK; 31];
    let e = Renderer::new(&mut depth)
        .draw_bands(&mesh, &camera, &style, &mut colors, &mut Failing(100))
        .unwrap_err();
    assert_eq!(e, RenderError::ColorsTooSmall { needed: 32 });
    assert!(e.to_string().contains("32"));
    let mut bytes = [0u8; 63];
    let e = Renderer::new(&mut depth)
        .draw_bands_rgb565(&mesh, &camera, &style, &mut bytes, |_, _| Ok::<(), ()>(()))
        .unwrap_err();
    assert_eq!(e, RenderError::ColorsTooSmall { needed: 32 });
    // A failing push stops the frame with its error.
    let mut bytes = [0u8; 2 * 32 * 4];
    let mut pushes = 0;
    let e = Renderer::new(&mut depth)
        .draw_bands_rgb565(&mesh, &camera, &style, &mut bytes, |_, _| {
            pushes += 1;
            if pushes == 3 {
                Err("dma")
            } else {
                Ok(())
            }
        })
        .unwrap_err();
    assert_eq!((e, pushes), (RenderError::Target("dma"), 3));
}

/// A source that draws both sides of every triangle: the tessellator it wraps, but never
/// [`one_sided`](TriangleSource::one_sided).
struct TwoSided<'a, 'b, 'c>(&'a spline_tess::Tessellator<'b, 'c>);

impl TriangleSource for TwoSided<'_, '_, '_> {
    fn bound(&self) -> Option<BoundingSphere> {
        self.0.bound()
    }

    fn stream_rows(
        &self,
        camera: &Camera,
        rows: std::ops::Range<u32>,
        sink: &mut impl spline_tess::TriangleSink,
    ) {
        self.0.stream_rows(camera, rows, sink);
    }

    fn vertex_numbers(&self) -> Option<usize> {
        self.0.vertex_numbers()
    }
}

/// A closed model seen from outside (the rational torus: every patch has a cone) is drawn
/// from the triangles that face the eye alone, and the pixels are those of drawing both
/// sides, streamed and listed, at every view: the triangles left out were all behind others.
/// With the eye inside the model's sphere nothing is left out; the teapot (open: no cones)
/// leaves nothing out.
#[test]
fn a_closed_model_draws_only_what_faces_the_eye_and_the_same_pixels() {
    let path = models_dir().join("nurbs/rational_torus.json");
    let file = ModelFile::read(path.to_str().unwrap()).unwrap();
    let baked = BakedHierarchy::bake(&file, &BAKE).unwrap();
    let tree = baked.tree();
    let mut storage = VecStorage::new(&tree, 1 << 12, 1 << 14);
    let mut tess = storage.tessellator(tree);
    let (w, h) = (160u32, 120u32);
    let sphere = file
        .with_model(|m| BoundingSphere::of_points(m.patches.points()).unwrap())
        .unwrap();
    let (c, r) = (sphere.center, sphere.radius);
    // Around, above, grazing, close, and one with the eye inside the sphere.
    let eyes = [
        c + Vec3::new(1.4, -1.8, 1.0) * r,
        c + Vec3::new(-2.2, 0.4, 0.2) * r,
        c + Vec3::new(0.1, 0.2, 2.2) * r,
        c + Vec3::new(1.1, -0.9, 0.3) * r,
        c + Vec3::new(0.3, -0.4, 0.2) * r,
    ];
    let style = Style {
        wireframe: Some(Wireframe {
            color: Rgb888::BLACK,
            half_width: 0.4,
        }),
        ..Style::default()
    };
    for (k, eye) in eyes.iter().enumerate() {
        let camera = Camera::new(
            *eye,
            c,
            Vec3::Z,
            Projection::Perspective {
                fov_y_degrees: 50.0,
            },
            0.01 * r,
            [w, h],
        )
        .unwrap();
        tess.update(&View::Screen {
            camera,
            tolerance_px: 1.0,
        })
        .unwrap();
        let inside = (eye - c).length() < r;
        let mut depth = vec![0u16; (w * 16) as usize];
        let mut both = Counting::new(w, h);
        let drawn_both = Renderer::new(&mut depth)
            .draw(&TwoSided(&tess), &camera, &style, &mut both)
            .unwrap();
        assert_eq!(drawn_both.culled, 0);
        let mut fronts = Counting::new(w, h);
        let drawn = Renderer::new(&mut depth)
            .draw(&tess, &camera, &style, &mut fronts)
            .unwrap();
        let covered = both.hits.iter().filter(|&&n| n > 0).count();
        assert!(covered > 1000, "view {k}: {covered} pixels");
        assert_eq!(fronts.color, both.color, "view {k}: the same pixels");
        if inside {
            assert_eq!(drawn.culled, 0, "view {k}: the eye inside culls nothing");
        } else {
            // About half the triangles face away.
            assert!(
                drawn.culled * 3 > drawn.triangles,
                "view {k}: {} of {} left out",
                drawn.culled,
                drawn.triangles
            );
            assert!(drawn.pixels < drawn_both.pixels, "view {k}");
        }
        // Listed: the list leaves them out too, and draws the same.
        let mut list = vec![ListSlot::default(); 4000];
        let mut colors = vec![Rgb888::BLACK; (w * 16) as usize];
        let mut target = Windows {
            counting: Counting::new(w, h),
            windows: Vec::new(),
        };
        let listed = Renderer::with_triangle_list(&mut depth, &mut list)
            .draw_bands(&tess, &camera, &style, &mut colors, &mut target)
            .unwrap();
        assert_eq!(listed.passes, 1, "view {k}: the list holds the frame");
        assert_eq!(listed.culled > 0, !inside, "view {k}");
        let bg = Rgb888::BLACK;
        let want: Vec<Rgb888> = both.color.iter().map(|c| c.unwrap_or(bg)).collect();
        let got: Vec<Rgb888> = target.counting.color.iter().map(|c| c.unwrap()).collect();
        assert_eq!(got, want, "view {k}: listed");
    }
    // The teapot is open: nothing of it is one-sided.
    let (_, teapot) = teapot();
    let tree = teapot.tree();
    let mut storage = VecStorage::new(&tree, 1 << 12, 0);
    let tess = storage.tessellator(tree);
    let camera = camera(EYES[0], [w, h]);
    assert!((0..tree.patch_count() as u32).all(|p| !tess.one_sided(&camera, p)));
}
