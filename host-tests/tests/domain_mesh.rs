//! The domain triangulation: structural invariants after every operation, Delaunay property
//! by an independent i128 in-circle test, and history independence (random insert/delete
//! sequences give the same triangles as a fresh build of the surviving points).

use std::collections::BTreeSet;

use host_tests::Rng;
use spline_tess::{
    DomainIndex, DomainMesh, GridPoint, InsertError, MeshStorageError, MeshTriangle, MeshVertex,
    Metric, RemoveError,
};

const M: i128 = GridPoint::MAX as i128;

type Tri = [(u16, u16); 3];

fn storage(vertices: usize) -> (Vec<MeshVertex>, Vec<MeshTriangle>) {
    (
        vec![MeshVertex::default(); vertices],
        vec![MeshTriangle::default(); DomainMesh::triangles_for(vertices)],
    )
}

fn orient(a: GridPoint, b: GridPoint, c: GridPoint) -> i128 {
    (b.u as i128 - a.u as i128) * (c.v as i128 - a.v as i128)
        - (b.v as i128 - a.v as i128) * (c.u as i128 - a.u as i128)
}

/// Plain in-circle determinant (no tie-break): > 0 when d is strictly inside.
fn in_circle_det(a: GridPoint, b: GridPoint, c: GridPoint, d: GridPoint) -> i128 {
    let r = |p: GridPoint| {
        let (x, y) = (p.u as i128 - d.u as i128, p.v as i128 - d.v as i128);
        (x, y, x * x + y * y)
    };
    let (a, b, c) = (r(a), r(b), r(c));
    a.2 * (b.0 * c.1 - b.1 * c.0) - b.2 * (a.0 * c.1 - a.1 * c.0) + c.2 * (a.0 * b.1 - a.1 * b.0)
}

/// Checks every structural invariant; returns the triangles as canonical coordinate triples.
fn check<Ix: DomainIndex>(mesh: &DomainMesh<'_, Ix>) -> BTreeSet<Tri> {
    let point = |v: u16| mesh.point(v).expect("triangle vertex is live");
    let tris: Vec<(u16, [u16; 3], [Option<u16>; 3])> = mesh.triangles_with_neighbors().collect();
    assert_eq!(tris.len(), mesh.triangle_count());
    let mut area2 = 0i128;
    for &(t, v, n) in &tris {
        let [a, b, c] = v.map(point);
        let o = orient(a, b, c);
        assert!(o > 0, "triangle {t} {v:?} is not counter-clockwise");
        assert!(
            a < b && a < c,
            "triangle {t} {v:?} does not start at its smallest point"
        );
        area2 += o;
        for i in 0..3 {
            let (x, y) = (v[(i + 1) % 3], v[(i + 2) % 3]);
            match n[i] {
                Some(s) => {
                    let (_, w, wn) = tris.iter().find(|e| e.0 == s).expect("neighbour is live");
                    let j = (0..3)
                        .find(|&j| w[(j + 1) % 3] == y && w[(j + 2) % 3] == x)
                        .expect("neighbour shares the edge reversed");
                    assert_eq!(wn[j], Some(t), "neighbour pointers are symmetric");
                    // Local Delaunay: the far vertex is not strictly inside.
                    let far = point(w[j]);
                    assert!(
                        in_circle_det(a, b, c, far) <= 0,
                        "edge {x}-{y} is not Delaunay"
                    );
                }
                None => {
                    let (p, q) = (point(x), point(y));
                    let same_side = (p.u == q.u && (p.u == 0 || p.u == GridPoint::MAX))
                        || (p.v == q.v && (p.v == 0 || p.v == GridPoint::MAX));
                    assert!(
                        same_side,
                        "open edge {p:?}-{q:?} is not on the square's boundary"
                    );
                }
            }
        }
    }
    assert_eq!(area2, 2 * M * M, "triangles tile the square");
    // Every vertex's star is the triangles that hold it, each once, counter-clockwise: each
    // triangle's edge leaving the vertex is the next triangle's edge arriving at it.
    for (id, _) in mesh.vertices() {
        let star: Vec<u16> = mesh.star(id).collect();
        let mut holding: Vec<u16> = tris
            .iter()
            .filter(|e| e.1.contains(&id))
            .map(|e| e.0)
            .collect();
        let mut sorted = star.clone();
        sorted.sort();
        holding.sort();
        assert_eq!(sorted, holding, "star of vertex {id}");
        for pair in star.windows(2) {
            let [t0, t1] = [pair[0], pair[1]].map(|t| mesh.triangle(t).unwrap());
            let after =
                |t: [u16; 3], k: usize| t[(t.iter().position(|&x| x == id).unwrap() + k) % 3];
            assert_eq!(
                after(t0, 2),
                after(t1, 1),
                "star of vertex {id} is not in order"
            );
        }
    }
    let boundary = mesh.vertices().filter(|(_, p)| p.on_boundary()).count();
    let interior = mesh.vertex_count() - boundary;
    assert_eq!(
        tris.len(),
        2 * interior + boundary - 2,
        "2n + b - 2 triangles"
    );
    tris.iter()
        .map(|&(_, v, _)| {
            let mut t = v.map(|x| {
                let p = point(x);
                (p.u, p.v)
            });
            t.sort();
            t
        })
        .collect()
}

fn fresh(points: &[GridPoint]) -> BTreeSet<Tri> {
    let (mut vs, mut ts) = storage(points.len() + 4);
    let mut mesh = DomainMesh::new(&mut vs, &mut ts).unwrap();
    for &p in points {
        mesh.insert(p).unwrap();
    }
    check(&mesh)
}

/// Points that provoke ties: a coarse grid (squares are cocircular), the square's edges, and
/// random points.
fn candidates(rng: &mut Rng) -> Vec<GridPoint> {
    let mut set = BTreeSet::new();
    let coarse = |k: u32| (k * (GridPoint::MAX as u32) / 8) as u16;
    while set.len() < 48 {
        let p = match (rng.unit() * 4.0) as u32 {
            0 | 1 => GridPoint::new(
                coarse((rng.unit() * 9.0) as u32),
                coarse((rng.unit() * 9.0) as u32),
            ),
            2 => {
                let t = coarse((rng.unit() * 9.0) as u32);
                [
                    GridPoint::new(t, 0),
                    GridPoint::new(0, t),
                    GridPoint::new(t, GridPoint::MAX),
                ][(rng.unit() * 3.0) as usize]
            }
            _ => GridPoint::new((rng.unit() * 65535.0) as u16, (rng.unit() * 65535.0) as u16),
        };
        let corner = (p.u == 0 || p.u == GridPoint::MAX) && (p.v == 0 || p.v == GridPoint::MAX);
        if !corner {
            set.insert(p);
        }
    }
    set.into_iter().collect()
}

#[test]
fn random_histories_give_the_fresh_triangulation() {
    for seed in 0..60 {
        let mut rng = Rng::for_test(seed);
        let pool = candidates(&mut rng);
        let (mut vs, mut ts) = storage(pool.len() + 4);
        let mut mesh = DomainMesh::new(&mut vs, &mut ts).unwrap();
        // The same history in one-byte slots: the same slots, step by step.
        let mut vs8 = vec![MeshVertex::<u8>::default(); pool.len() + 4];
        let mut ts8 =
            vec![MeshTriangle::<u8>::default(); DomainMesh::triangles_for(pool.len() + 4)];
        let mut narrow = DomainMesh::indexed(&mut vs8, &mut ts8, Metric::ISOTROPIC).unwrap();
        let mut live: Vec<(GridPoint, u16)> = Vec::new();
        for step in 0..300 {
            let insert = live.is_empty() || (rng.unit() < 0.6 && live.len() < pool.len());
            if insert {
                let p = pool[(rng.unit() * pool.len() as f64) as usize];
                let before: BTreeSet<[u16; 3]> = mesh.triangles().collect();
                let inserted = mesh.insert(p);
                assert_eq!(
                    narrow.insert(p),
                    inserted,
                    "seed {seed} step {step}: u8 insert"
                );
                match inserted {
                    Ok(id) => {
                        live.push((p, id));
                        let created: BTreeSet<[u16; 3]> =
                            mesh.triangles().filter(|t| !before.contains(t)).collect();
                        let star: BTreeSet<[u16; 3]> =
                            mesh.star(id).map(|t| mesh.triangle(t).unwrap()).collect();
                        assert_eq!(
                            star, created,
                            "seed {seed} step {step}: star != new triangles"
                        );
                    }
                    Err(InsertError::Duplicate { vertex }) => {
                        assert!(
                            live.contains(&(p, vertex)),
                            "seed {seed} step {step}: bad duplicate"
                        )
                    }
                    Err(e) => panic!("seed {seed} step {step}: insert {p:?}: {e}"),
                }
            } else {
                let k = (rng.unit() * live.len() as f64) as usize;
                let (_, id) = live.swap_remove(k);
                mesh.remove(id)
                    .unwrap_or_else(|e| panic!("seed {seed} step {step}: remove: {e}"));
                narrow
                    .remove(id)
                    .unwrap_or_else(|e| panic!("seed {seed} step {step}: u8 remove: {e}"));
            }
            let now = check(&mesh);
            assert_eq!(check(&narrow), now, "seed {seed} step {step}: u8 triangles");
            assert!(
                narrow
                    .triangles_with_neighbors()
                    .eq(mesh.triangles_with_neighbors()),
                "seed {seed} step {step}: u8 slots differ"
            );
            if step % 25 == 24 {
                let mut points: Vec<GridPoint> = live.iter().map(|&(p, _)| p).collect();
                points.sort();
                assert_eq!(
                    now,
                    fresh(&points),
                    "seed {seed} step {step}: differs from a fresh build"
                );
                points.reverse();
                assert_eq!(
                    now,
                    fresh(&points),
                    "seed {seed} step {step}: insertion order matters"
                );
            }
        }
    }
}

#[test]
fn capacities_and_bad_requests_leave_the_mesh_unchanged() {
    let (mut vs, mut ts) = storage(5);
    let mut mesh = DomainMesh::new(&mut vs, &mut ts).unwrap();
    let centre = mesh.insert(GridPoint::from_unit(0.5, 0.5)).unwrap();
    let before = check(&mesh);
    assert_eq!(
        mesh.insert(GridPoint::from_unit(0.25, 0.5)),
        Err(InsertError::VerticesFull)
    );
    assert_eq!(
        mesh.insert(GridPoint::from_unit(0.5, 0.5)),
        Err(InsertError::Duplicate { vertex: centre })
    );
    assert_eq!(mesh.remove(0), Err(RemoveError::Corner));
    assert_eq!(mesh.remove(77), Err(RemoveError::NotAVertex));
    assert_eq!(check(&mesh), before);
    mesh.remove(centre).unwrap();
    assert_eq!(mesh.remove(centre), Err(RemoveError::NotAVertex));
    assert_eq!(check(&mesh).len(), 2);
    // Too few triangle slots: refused with the number needed, mesh unchanged.
    let mut vs = vec![MeshVertex::default(); 8];
    let mut ts = vec![MeshTriangle::default(); 3];
    let mut small = DomainMesh::new(&mut vs, &mut ts).unwrap();
    assert_eq!(
        small.insert(GridPoint::from_unit(0.3, 0.6)),
        Err(InsertError::TrianglesFull { needed: 2 })
    );
    assert_eq!(check(&small).len(), 2);
    let edge = small.insert(GridPoint::from_unit(0.5, 0.0)).unwrap();
    assert_eq!(small.triangle_count(), 3);
    assert_eq!(small.find(GridPoint::from_unit(0.5, 0.0)), Some(edge));
}

/// One-byte slots: a mesh of 255 slots of each kind is the largest, and it fills to its 130
/// vertices (254 triangles) with "no slot" (255) never taken for a slot number.
#[test]
fn one_byte_meshes_fill_to_their_last_slot() {
    let mut vs = vec![MeshVertex::<u8>::default(); 256];
    let mut ts = vec![MeshTriangle::<u8>::default(); 255];
    assert_eq!(
        DomainMesh::indexed(&mut vs, &mut ts, Metric::ISOTROPIC).err(),
        Some(MeshStorageError::TooLarge)
    );
    let mut vs = vec![MeshVertex::<u8>::default(); 130];
    let mut ts = vec![MeshTriangle::<u8>::default(); DomainMesh::triangles_for(130)];
    assert_eq!(ts.len(), 254);
    let mut mesh = DomainMesh::indexed(&mut vs, &mut ts, Metric::ISOTROPIC).unwrap();
    let mut rng = Rng::for_test(7);
    let mut ids = Vec::new();
    while mesh.vertex_count() < 130 {
        let p = GridPoint::new(
            1 + (rng.unit() * 65533.0) as u16,
            1 + (rng.unit() * 65533.0) as u16,
        );
        if let Ok(id) = mesh.insert(p) {
            ids.push(id);
        }
    }
    assert_eq!(mesh.triangle_count(), 254);
    assert_eq!(
        mesh.insert(GridPoint::from_unit(0.5, 0.5)),
        Err(InsertError::VerticesFull)
    );
    check(&mesh);
    // Removing in any order gives the two triangles back.
    for &id in ids.iter().rev().step_by(2).chain(ids.iter().step_by(2)) {
        mesh.remove(id).unwrap();
        check(&mesh);
    }
    assert_eq!(mesh.triangle_count(), 2);
}

/// Hundreds of boundary points and a few interior ones: vertices of degree in the hundreds,
/// which insertion and removal handle in place.
#[test]
fn high_degree_vertices_insert_and_remove_in_place() {
    let mut rng = Rng::for_test(7);
    let mut boundary = BTreeSet::new();
    for k in 1..200u32 {
        let t = (k * GridPoint::MAX as u32 / 200) as u16;
        boundary.insert(GridPoint::new(t, 0));
        boundary.insert(GridPoint::new(GridPoint::MAX, t));
        boundary.insert(GridPoint::new(t, GridPoint::MAX));
        boundary.insert(GridPoint::new(0, t));
    }
    let interior: Vec<GridPoint> = (0..12)
        .map(|_| {
            GridPoint::new(
                20000 + (rng.unit() * 25000.0) as u16,
                20000 + (rng.unit() * 25000.0) as u16,
            )
        })
        .collect();
    let n = boundary.len() + interior.len() + 4;
    let (mut vs, mut ts) = storage(n);
    let mut mesh = DomainMesh::new(&mut vs, &mut ts).unwrap();
    for &p in &boundary {
        mesh.insert(p).unwrap();
    }
    let mut live = Vec::new();
    for &p in &interior {
        live.push((p, mesh.insert(p).unwrap()));
        if live.len() == 1 {
            let degree = mesh.star(live[0].1).count();
            assert!(
                degree > 100,
                "the first interior point sees much of the boundary: {degree}"
            );
        }
        check(&mesh);
    }
    // Remove in a shuffled order, then the boundary points too, comparing with fresh builds.
    while let Some(k) = (!live.is_empty()).then(|| (rng.unit() * live.len() as f64) as usize) {
        let (_, id) = live.swap_remove(k);
        mesh.remove(id).unwrap();
        let mut points: Vec<GridPoint> = live
            .iter()
            .map(|&(p, _)| p)
            .chain(boundary.iter().copied())
            .collect();
        points.sort();
        assert_eq!(check(&mesh), fresh(&points));
    }
    let ids: Vec<u16> = mesh
        .vertices()
        .map(|(id, _)| id)
        .filter(|&id| id >= 4)
        .collect();
    for id in ids {
        mesh.remove(id).unwrap();
    }
    assert_eq!(mesh.triangle_count(), 2);
    check(&mesh);
}

/// Lattice points removed in random orders: a vertex may lie on the segment between two of its
/// link's vertices (here everywhere), where no ear of its link can be flipped without a flat
/// triangle. Every removal succeeds and leaves the fresh triangulation of the rest.
#[test]
fn lattice_points_remove_in_any_order() {
    for spacing in [8000u16, 6000, 4000] {
        let n = (GridPoint::MAX / spacing) as usize;
        for seed in 0..24 {
            let mut rng = Rng::for_test(seed);
            let mut points: Vec<GridPoint> = (0..=n)
                .flat_map(|i| (0..=n).map(move |j| (i, j)))
                .map(|(i, j)| GridPoint::new(i as u16 * spacing, j as u16 * spacing))
                .filter(|p| p.u != 0 || p.v != 0)
                .collect();
            let (mut vs, mut ts) = storage(points.len() + 8);
            let mut mesh = DomainMesh::new(&mut vs, &mut ts).unwrap();
            let mut live: Vec<(GridPoint, u16)> = Vec::new();
            for &p in &points {
                match mesh.insert(p) {
                    Ok(id) => live.push((p, id)),
                    Err(InsertError::Duplicate { .. }) => {}
                    Err(e) => panic!("insert {p:?}: {e}"),
                }
            }
            check(&mesh);
            let mut step = 0;
            while !live.is_empty() {
                let k = (rng.unit() * live.len() as f64) as usize;
                let (p, id) = live.swap_remove(k);
                mesh.remove(id).unwrap_or_else(|e| {
                    panic!("spacing {spacing} seed {seed} step {step}: remove {p:?}: {e}")
                });
                step += 1;
                let now = check(&mesh);
                if step % 7 == 0 || live.is_empty() {
                    points = live.iter().map(|&(p, _)| p).collect();
                    points.sort();
                    assert_eq!(
                        now,
                        fresh(&points),
                        "spacing {spacing} seed {seed} step {step}"
                    );
                }
            }
            assert_eq!(mesh.triangle_count(), 2);
        }
    }
}
