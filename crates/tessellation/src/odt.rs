//! The optimal-Delaunay-triangulation (ODT) update of VTM (Alliez, Cohen-Steiner, Yvinec,
//! Desbrun 2005; L. Chen's ODT relaxation in 2D) on any triangle list: the target of every
//! vertex and the energy it descends. The `vtm` method and CCVT's ODT update (`Update::Odt` in
//! the `ccvt` crate) both use these.
use geometry::predicates::{circumcenter, triangle_signed_area};
use geometry::{DVec2, Density};
use std::collections::HashSet;

/// For each triangle: does one of its edges lie on the boundary of the triangle set (no
/// triangle across it)?
pub fn odt_boundary_triangles(triangles: &[[u32; 3]]) -> Vec<bool> {
    let edges: HashSet<(u32, u32)> = triangles
        .iter()
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .collect();
    triangles
        .iter()
        .map(|t| {
            [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])]
                .iter()
                .any(|&(a, b)| !edges.contains(&(b, a)))
        })
        .collect()
}

/// VTM's target for every point: Σ w_T c_T / Σ w_T over the triangles around it, with
/// w_T = |T|·ρ(barycentre of T) and c_T the circumcentre of T, or its barycentre for a triangle
/// with an edge on the boundary of the triangle set (a flat boundary triangle's circumcentre lies
/// far outside the region and would drag its vertices out). This is the minimiser of the ODT
/// energy ([`odt_energy`]) of the point's patch. A point in no triangle (or only in triangles
/// that are not counter-clockwise) keeps its position.
///
/// ```
/// use cvtmesh::tessellation::odt_targets;
/// use cvtmesh::geometry::{DVec2, Density};
///
/// // A regular hexagon around the origin: its centre is a fixed point.
/// let mut points = vec![DVec2::new(0.1, -0.05)];
/// points.extend((0..6).map(|k| DVec2::from_angle(k as f64 * std::f64::consts::FRAC_PI_3)));
/// let triangles: Vec<[u32; 3]> = (0..6).map(|k| [0, 1 + k, 1 + (k + 1) % 6]).collect();
/// let t = odt_targets(&points, &triangles, &Density::Uniform);
/// assert!(t[0].length() < 1e-12);
/// ```
pub fn odt_targets(points: &[DVec2], triangles: &[[u32; 3]], density: &Density) -> Vec<DVec2> {
    let mut num = vec![DVec2::ZERO; points.len()];
    let mut den = vec![0.0; points.len()];
    for (tri, on_boundary) in triangles.iter().zip(odt_boundary_triangles(triangles)) {
        let [a, b, c] = tri.map(|v| points[v as usize]);
        let area = triangle_signed_area(a, b, c);
        if area <= 0.0 {
            continue; // not a valid CCW triangle: no weight
        }
        let g = (a + b + c) / 3.0;
        let w = area * density.at(g);
        let centre = if on_boundary {
            g
        } else {
            circumcenter(a, b, c)
        };
        for &v in tri {
            num[v as usize] += w * centre;
            den[v as usize] += w;
        }
    }
    points
        .iter()
        .zip(num.iter().zip(&den))
        .map(|(p, (n, &d))| if d > 0.0 { *n / d } else { *p })
        .collect()
}

/// The ODT energy ∫ (u_I − u) for u = |x|², u_I its piecewise-linear interpolant on the
/// triangles: Σ_T ρ_T |T| (ℓ₁² + ℓ₂² + ℓ₃²) / 12 (ℓ the edge lengths, ρ_T the density at the
/// barycentre).
///
/// ```
/// use cvtmesh::tessellation::odt_energy;
/// use cvtmesh::geometry::{DVec2, Density};
///
/// // ∫_T (u_I − u) on the unit right triangle is 1/3 − 1/6.
/// let points = [DVec2::ZERO, DVec2::X, DVec2::Y];
/// let e = odt_energy(&points, &[[0, 1, 2]], &Density::Uniform);
/// assert!((e - 1.0 / 6.0).abs() < 1e-15);
/// ```
pub fn odt_energy(points: &[DVec2], triangles: &[[u32; 3]], density: &Density) -> f64 {
    triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| points[v as usize]);
            let area = triangle_signed_area(a, b, c);
            let l2 = (b - a).length_squared() + (c - b).length_squared() + (a - c).length_squared();
            density.at((a + b + c) / 3.0) * area * l2 / 12.0
        })
        .sum()
}
