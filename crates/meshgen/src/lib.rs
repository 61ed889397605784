//! MESHGEN (Section 4 of the paper, refs. \[14, 16\]): a CVT-like relaxation in which each
//! vertex's Voronoi region is approximated from the current Delaunay triangulation.
//!
//! In every triangle T = (i, j, k), vertex i owns the quadrilateral
//! (x_i, midpoint of ij, p_T, midpoint of ik), where p_T is the circumcenter of T if T is not
//! obtuse and otherwise the midpoint of T's longest side (the "mixed Voronoi area" of Meyer,
//! Desbrun, Schröder and Barr 2002). These pieces tile T exactly, and the union over a vertex's
//! triangles is the region "formed by joining the circumcenters of acute triangles and the
//! mid-sides of the longest sides of obtuse triangles" the paper describes. Each iteration moves
//! every vertex to the centroid of its region (with a density ρ: the ρ-weighted centroid, ρ
//! taken at each quadrilateral's centroid) and retriangulates.
//!
//! The paper does not say how the original treats the boundary. Here, as in CCVT's
//! constraint (so comparisons are fair), corners are fixed and boundary vertices slide on their
//! own boundary side: they move to their region's centroid projected onto that side. The
//! initial points, boundary rules and convergence test are shared with the `vtm` crate and
//! documented in the module [`relax`].
//!
//! On corner-free boundaries (circle, annulus, super-ellipse) the iteration can settle into a
//! slow rigid rotation (the mesh keeps its shape while all vertices turn by a few 1e-4·h per step),
//! because nothing pins the vertices along a closed loop and the approximate regions are not
//! the gradient of an energy; the move-based test then reports `converged = false`.
#![forbid(unsafe_code)]
#![warn(missing_docs)]
#![deny(rustdoc::broken_intra_doc_links)]

pub mod relax;

use geometry::predicates::{circumcenter, orient};
use geometry::{DVec2, Density, Region};
use mesh::{Mesh, MeshError, MeshRequest, MeshResult, Mesher, Progress};

/// The MESHGEN method. It has no parameters beyond the [`MeshRequest`].
#[derive(Clone, Copy, Debug, Default)]
pub struct Meshgen;

impl Mesher for Meshgen {
    fn follows_size_fields(&self) -> bool {
        false
    }

    fn name(&self) -> &'static str {
        "meshgen"
    }

    /// The coarsest boundary of the shared relaxation ([`relax::min_boundary_points`]).
    fn min_boundary_points(&self, region: &Region) -> usize {
        relax::min_boundary_points(region)
    }

    /// Relax from the shared initial points until the largest move is below `tol · h`.
    /// `energy_history` holds [`mixed_energy`], the CVT energy (4) with the approximate regions.
    fn mesh(
        &self,
        region: &Region,
        request: &MeshRequest,
        progress: &mut dyn FnMut(Progress),
    ) -> Result<MeshResult, MeshError> {
        relax::relax(
            "meshgen",
            region,
            request,
            progress,
            &|mesh: &Mesh, density: &Density| {
                let regions = mixed_regions(mesh, density);
                let energy = regions.iter().map(|r| r.energy).sum();
                let targets = regions
                    .iter()
                    .zip(&mesh.points)
                    .map(|(r, &x)| if r.mass > 0.0 { r.moment / r.mass } else { x })
                    .collect();
                (targets, energy)
            },
        )
    }
}

/// Moments of one vertex's mixed region.
#[derive(Clone, Copy, Debug, Default)]
struct MixedRegion {
    /// Area.
    area: f64,
    /// Σ ρ(c_q)|q| over its quadrilaterals q.
    mass: f64,
    /// Σ ρ(c_q)|q| c_q.
    moment: DVec2,
    /// Σ ρ(c_q) ∫_q |x − x_i|² dx.
    energy: f64,
}

/// The point p_T of triangle (a, b, c): its circumcenter if no angle exceeds 90°, otherwise
/// the midpoint of its longest side.
fn voronoi_point(a: DVec2, b: DVec2, c: DVec2) -> DVec2 {
    let (la, lb, lc) = (
        (b - c).length_squared(),
        (c - a).length_squared(),
        (a - b).length_squared(),
    );
    if la > lb + lc {
        0.5 * (b + c)
    } else if lb > lc + la {
        0.5 * (c + a)
    } else if lc > la + lb {
        0.5 * (a + b)
    } else {
        circumcenter(a, b, c)
    }
}

/// Area, centroid and polar second moment about `origin` of a simple polygon.
fn polygon_moments(poly: &[DVec2], origin: DVec2) -> (f64, DVec2, f64) {
    let (mut a2, mut c, mut j) = (0.0, DVec2::ZERO, 0.0);
    for k in 0..poly.len() {
        let (p, q) = (poly[k] - origin, poly[(k + 1) % poly.len()] - origin);
        let w = p.perp_dot(q);
        a2 += w;
        c += (p + q) * w;
        j += w * (p.length_squared() + p.dot(q) + q.length_squared());
    }
    let area = 0.5 * a2;
    let centroid = if area != 0.0 {
        origin + c / (3.0 * a2)
    } else {
        origin
    };
    (area, centroid, j / 12.0)
}

/// Each vertex's mixed region, accumulated over its triangles.
fn mixed_regions(mesh: &Mesh, density: &Density) -> Vec<MixedRegion> {
    let mut out = vec![MixedRegion::default(); mesh.points.len()];
    for tri in &mesh.triangles {
        let x = tri.map(|v| mesh.points[v as usize]);
        if orient(x[0], x[1], x[2]) <= 0.0 {
            continue; // not a valid CCW triangle: it owns nothing
        }
        let p = voronoi_point(x[0], x[1], x[2]);
        for r in 0..3 {
            let (xi, xj, xk) = (x[r], x[(r + 1) % 3], x[(r + 2) % 3]);
            let quad = [xi, 0.5 * (xi + xj), p, 0.5 * (xi + xk)];
            let (area, centroid, second) = polygon_moments(&quad, xi);
            let rho = density.at(centroid);
            let reg = &mut out[tri[r] as usize];
            reg.area += area;
            reg.mass += rho * area;
            reg.moment += rho * area * centroid;
            reg.energy += rho * second;
        }
    }
    out
}

/// Area of each vertex's mixed region; they tile the mesh, so the sum is the mesh area.
pub fn mixed_areas(mesh: &Mesh) -> Vec<f64> {
    mixed_regions(mesh, &Density::Uniform)
        .iter()
        .map(|r| r.area)
        .collect()
}

/// MESHGEN's target for every vertex: the (ρ-weighted) centroid of its mixed region. A vertex
/// in no triangle keeps its position.
pub fn mixed_centroids(mesh: &Mesh, density: &Density) -> Vec<DVec2> {
    mixed_regions(mesh, density)
        .iter()
        .zip(&mesh.points)
        .map(|(r, &x)| if r.mass > 0.0 { r.moment / r.mass } else { x })
        .collect()
}

/// The CVT energy (4) with the mixed regions in place of the Voronoi cells:
/// Σ_i ∫_{region i} ρ |x − x_i|² dx (ρ taken at each quadrilateral's centroid).
pub fn mixed_energy(mesh: &Mesh, density: &Density) -> f64 {
    mixed_regions(mesh, density).iter().map(|r| r.energy).sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use mesh::VertexMarker;
    use testkit::hex_patch;

    #[test]
    fn patch_is_built_as_intended() {
        let m = hex_patch(2);
        assert_eq!(m.num_vertices(), 19);
        assert_eq!(m.num_triangles(), 24);
        assert!((m.area() - 24.0 * 3f64.sqrt() / 4.0).abs() < 1e-12);
    }

    #[test]
    fn centre_of_regular_patch_is_a_fixed_point() {
        for rings in [1, 2] {
            let m = hex_patch(rings);
            let c = mixed_centroids(&m, &Density::Uniform);
            assert!(c[0].length() < 1e-14, "centre moved to {}", c[0]);
            // The centre's region is the hexagonal Voronoi cell: area √3/2 for unit spacing.
            assert!((mixed_areas(&m)[0] - 3f64.sqrt() / 2.0).abs() < 1e-14);
        }
    }

    #[test]
    fn displaced_centre_is_pulled_back() {
        let mut m = hex_patch(2);
        m.points[0] = DVec2::new(0.2, -0.1);
        let c = mixed_centroids(&m, &Density::Uniform)[0];
        // Lloyd-like contraction towards the centre, without overshooting it.
        assert!(c.length() < 0.7 * m.points[0].length(), "target {c}");
        assert!(c.dot(m.points[0]) > 0.0, "target {c}");
    }

    #[test]
    fn mixed_regions_tile_the_mesh() {
        let mut m = hex_patch(3);
        let mut rng = geometry::Rng::new(5);
        // Jitter the interior so that both acute and obtuse triangles occur.
        let k = m.points.len();
        for p in m.points.iter_mut().take(k / 2) {
            *p += DVec2::new(rng.range(-0.25, 0.25), rng.range(-0.25, 0.25));
        }
        let obtuse = (0..m.num_triangles())
            .filter(|&t| {
                let [a, b, c] = m.triangle(t);
                voronoi_point(a, b, c) != circumcenter(a, b, c)
            })
            .count();
        assert!(obtuse > 0, "jitter should produce obtuse triangles");
        let areas = mixed_areas(&m);
        assert!(areas.iter().all(|&a| a > 0.0));
        let total: f64 = areas.iter().sum();
        assert!(
            (total - m.area()).abs() < 1e-12 * m.area(),
            "{total} vs {}",
            m.area()
        );
    }

    #[test]
    fn targets_and_energy_follow_translation() {
        let mut m = hex_patch(2);
        let mut rng = geometry::Rng::new(9);
        for p in m.points.iter_mut().take(7) {
            *p += DVec2::new(rng.range(-0.2, 0.2), rng.range(-0.2, 0.2));
        }
        let shift = DVec2::new(3.5, -1.25);
        let mut moved = m.clone();
        moved.points.iter_mut().for_each(|p| *p += shift);
        let (c0, c1) = (
            mixed_centroids(&m, &Density::Uniform),
            mixed_centroids(&moved, &Density::Uniform),
        );
        for (a, b) in c0.iter().zip(&c1) {
            assert!((*a + shift - *b).length() < 1e-12);
        }
        let (e0, e1) = (
            mixed_energy(&m, &Density::Uniform),
            mixed_energy(&moved, &Density::Uniform),
        );
        assert!((e0 - e1).abs() < 1e-12 * e0);
    }

    #[test]
    fn energy_of_a_right_triangle_by_hand() {
        // Right triangle (0,0),(2,0),(0,2): p_T is the hypotenuse midpoint (1,1). The right-angle
        // vertex owns the unit square [0,1]², whose polar moment about the origin is 2/3; each
        // other vertex owns the triangle (x, (1,1), midpoint of its leg to the origin).
        let points = vec![DVec2::ZERO, DVec2::new(2.0, 0.0), DVec2::new(0.0, 2.0)];
        let m = Mesh {
            points,
            triangles: vec![[0, 1, 2]],
            markers: vec![VertexMarker::Interior; 3],
        };
        let areas = mixed_areas(&m);
        assert!((areas[0] - 1.0).abs() < 1e-14 && (areas[1] - 0.5).abs() < 1e-14);
        let c = mixed_centroids(&m, &Density::Uniform);
        assert!((c[0] - DVec2::splat(0.5)).length() < 1e-14);
        // Triangle (2,0),(1,1),(1,0): centroid (4/3, 1/3).
        assert!((c[1] - DVec2::new(4.0 / 3.0, 1.0 / 3.0)).length() < 1e-14);
        // About (2,0) that triangle is (0,0),(-1,1),(-1,0): ∫x²+y² = 1/4 + 1/12 = 1/3.
        let e = mixed_energy(&m, &Density::Uniform);
        assert!((e - (2.0 / 3.0 + 2.0 / 3.0)).abs() < 1e-14, "energy {e}");
    }

    #[test]
    fn density_pulls_the_centroid() {
        let m = hex_patch(2);
        let rho = Density::Function(std::sync::Arc::new(|p: DVec2| 1.0 + p.x.max(-0.9)));
        let c = mixed_centroids(&m, &rho)[0];
        assert!(c.x > 0.01 && c.y.abs() < 1e-12, "target {c}");
    }
}
