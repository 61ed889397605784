//! A structured mesh of an annulus for pictures and tests: concentric rings of points with
//! spacing close to `h`, neighbouring rings zipped into triangles in angular order.
use geometry::DVec2;
use mesh::{Mesh, VertexMarker};
use std::f64::consts::TAU;

/// Mesh of the annulus `r0 < |x - c| < r1` with edge length about `h` (CCW triangles; every
/// vertex marked interior, since only the drawing uses it).
pub fn annulus_mesh(c: DVec2, r0: f64, r1: f64, h: f64) -> Mesh {
    let nr = ((r1 - r0) / h).ceil().max(1.0) as usize;
    let mut points = Vec::new();
    let mut rings = Vec::new();
    for i in 0..=nr {
        let r = r0 + (r1 - r0) * i as f64 / nr as f64;
        let n = ((TAU * r / h).round() as usize).max(3);
        rings.push((points.len(), n));
        // Stagger alternate rings by half a step for near-equilateral triangles.
        let off = if i % 2 == 0 { 0.0 } else { 0.5 };
        points.extend((0..n).map(|k| {
            let a = TAU * (k as f64 + off) / n as f64;
            c + r * DVec2::new(a.cos(), a.sin())
        }));
    }
    let mut triangles = Vec::new();
    for w in rings.windows(2) {
        let ((sa, na), (sb, nb)) = (w[0], w[1]);
        let ang = |k: usize, s: usize, n: usize| {
            let d = points[s + k % n] - c;
            d.y.atan2(d.x).rem_euclid(TAU) + TAU * (k / n) as f64
        };
        // Walk both rings once around, always advancing the one whose next point comes
        // first in angle; each step adds one triangle.
        let (mut i, mut j) = (0, 0);
        while i < na || j < nb {
            let (a, b) = ((sa + i % na) as u32, (sb + j % nb) as u32);
            if j >= nb || (i < na && ang(i + 1, sa, na) < ang(j + 1, sb, nb)) {
                triangles.push([a, b, (sa + (i + 1) % na) as u32]);
                i += 1;
            } else {
                triangles.push([a, b, (sb + (j + 1) % nb) as u32]);
                j += 1;
            }
        }
    }
    let markers = vec![VertexMarker::Interior; points.len()];
    Mesh {
        points,
        triangles,
        markers,
    }
}
