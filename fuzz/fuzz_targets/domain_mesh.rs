//! Any sequence of insertions and removals: typed errors only, and the Euler count holds.
#![no_main]

use libfuzzer_sys::fuzz_target;
use spline_tess::{DomainMesh, GridPoint, MeshTriangle, MeshVertex};

fuzz_target!(|data: &[u8]| {
    let mut vs = [MeshVertex::default(); 24];
    let mut ts = [MeshTriangle::default(); 42];
    let Ok(mut mesh) = DomainMesh::new(&mut vs, &mut ts) else {
        return;
    };
    for op in data.chunks_exact(5) {
        if op[0] & 1 == 0 {
            // Coarse coordinates now and then, so cocircular ties are common.
            let coarse = op[0] & 2 != 0;
            let q = |a: u8, b: u8| {
                if coarse {
                    ((a % 9) as u32 * 65535 / 8) as u16
                } else {
                    u16::from_le_bytes([a, b])
                }
            };
            let _ = mesh.insert(GridPoint::new(q(op[1], op[2]), q(op[3], op[4])));
        } else {
            let _ = mesh.remove(u16::from(op[1]) % 24);
        }
        let boundary = mesh.vertices().filter(|(_, p)| p.on_boundary()).count();
        let interior = mesh.vertex_count() - boundary;
        assert_eq!(mesh.triangle_count(), 2 * interior + boundary - 2);
    }
});
