//! Helpers for checking bakes: the dense `f64` deviation of a domain triangle, and the boundary
//! points a baked patch's triangulation starts from (mapped here independently of the kernel).

use spline_tess::bake::{BakedModel, BakedPatch};
use spline_tess::{EdgeLink, GridPoint, Side};

use crate::reference::{add, dist, scale, sub, RefPatch};

/// Largest distance between the patch and the linear interpolant of the triangle with
/// parameters `uv`, at `dense x dense` barycentric points (the corners included).
pub fn triangle_max(r: &RefPatch, uv: [(f64, f64); 3], dense: usize) -> f64 {
    let pos = uv.map(|(u, v)| r.point(u, v));
    let (d1, d2) = (sub(pos[1], pos[0]), sub(pos[2], pos[0]));
    let mut best = 0.0f64;
    for i in 0..=dense {
        for j in 0..=dense - i {
            let (s, t) = (i as f64 / dense as f64, j as f64 / dense as f64);
            let u = uv[0].0 + s * (uv[1].0 - uv[0].0) + t * (uv[2].0 - uv[0].0);
            let v = uv[0].1 + s * (uv[1].1 - uv[0].1) + t * (uv[2].1 - uv[0].1);
            let linear = add(pos[0], add(scale(d1, s), scale(d2, t)));
            best = best.max(dist(r.point(u.clamp(0.0, 1.0), v.clamp(0.0, 1.0)), linear));
        }
    }
    best
}

/// A grid point's parameters in `f64`.
pub fn unit(p: GridPoint) -> (f64, f64) {
    let m = GridPoint::MAX as f64;
    (p.u as f64 / m, p.v as f64 / m)
}

/// Where curve parameter `t` lands on `side`, for an edge running `reversed`.
pub fn on_side(side: Side, t: u16, reversed: bool) -> GridPoint {
    let e = if reversed { GridPoint::MAX - t } else { t };
    match side {
        Side::V0 => GridPoint::new(e, 0),
        Side::U1 => GridPoint::new(GridPoint::MAX, e),
        Side::V1 => GridPoint::new(e, GridPoint::MAX),
        Side::U0 => GridPoint::new(0, e),
    }
}

/// Every curve sample of `patch`'s edges, as points of its domain.
pub fn boundary_points(baked: &BakedModel<'_>, patch: &BakedPatch<'_>) -> Vec<GridPoint> {
    let mut points = Vec::new();
    for (side, link) in Side::ALL.into_iter().zip(patch.edges) {
        if let EdgeLink::Curve { curve, reversed } = link {
            let samples = baked.curve(curve as usize).expect("linked curve").samples;
            points.extend(samples.iter().map(|s| on_side(side, s.t, reversed)));
        }
    }
    points
}
