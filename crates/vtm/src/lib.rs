//! VTM, variational tetrahedral meshing (Alliez, Cohen-Steiner, Yvinec, Desbrun 2005) in 2D:
//! the optimal-Delaunay-triangulation (ODT) relaxation of L. Chen.
//!
//! Instead of a Voronoi cell, each vertex i looks at the patch Ω_i of Delaunay triangles around
//! it (patches overlap, unlike CVT cells). The vertex moves to the position minimising the ODT
//! energy of its patch, which has the closed form
//!
//! x_i ← Σ_{T ∋ i} |T| c_T / Σ_{T ∋ i} |T|,
//!
//! c_T the circumcenter of T; then the vertices are retriangulated (Delaunay) and the step is
//! repeated. A triangle with an edge on the mesh boundary uses its barycenter instead of its
//! circumcenter: a flat boundary triangle's circumcenter lies far outside the region and would
//! drag its vertices out. With a density ρ the weights are |T|·ρ(barycenter of T).
//!
//! The paper does not say how the original treats the boundary; [`Vtm::boundary`] offers two
//! rules:
//!
//! - [`VtmBoundary::Sliding`] (the default): as in CCVT's constraint, corners are fixed and
//!   boundary vertices slide on their own boundary side, taking the same weighted average
//!   projected onto that side. The initial points, boundary rules and convergence test are
//!   those of [`meshgen::relax`], so the number of boundary vertices is set by the start.
//! - [`VtmBoundary::Voronoi`]: CCVT's Algorithm 1 with VTM's update for the vertices inside
//!   ([`ccvt::Update::Odt`]): from CCVT's lattice start, every iteration, a vertex whose Voronoi
//!   cell meets ∂Ω goes to its cell's centroid projected onto ∂Ω (to the corner its cell holds),
//!   every other vertex to its VTM target. This is the rule that reproduces the paper's VTM
//!   column (its triangle counts, hence its boundary vertex counts, match its CCVT(1) column's;
//!   its worst boundary cells are CCVT's, its worst triangles poor on the complex regions), and
//!   the study runs it; its meshes' worst triangles are worse than the sliding rule's.
//!
//! On corner-free boundaries (circle, annulus, super-ellipse) the sliding iteration can settle
//! into a slow rigid rotation (the mesh keeps its shape while all vertices turn by a few
//! 1e-4·h per step): nothing pins the vertices along a closed loop and the boundary rule is not
//! the gradient of the ODT energy. Its convergence test takes the best-fitting rotation out of
//! the moves on a disc or annulus.
#![forbid(unsafe_code)]
#![warn(missing_docs)]
#![deny(rustdoc::broken_intra_doc_links)]

use geometry::{DVec2, Density, Region};
use mesh::{Mesh, MeshError, MeshRequest, MeshResult, Mesher, Progress};
use meshgen::relax;

/// How VTM treats vertices on ∂Ω (module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum VtmBoundary {
    /// Boundary vertices from the shared start of [`meshgen::relax`], sliding along their side.
    #[default]
    Sliding,
    /// CCVT's Algorithm 1 on ∂Ω: a vertex whose Voronoi cell meets ∂Ω goes to its projected
    /// centroid; VTM's update inside.
    Voronoi,
}

/// The VTM method.
///
/// ```
/// use cvtmesh::vtm::{Vtm, VtmBoundary};
/// use cvtmesh::geometry::Region;
/// use cvtmesh::{check_conforming, MeshRequest, Mesher};
///
/// let region = Region::builtin("square_hole")?;
/// for boundary in [VtmBoundary::Sliding, VtmBoundary::Voronoi] {
///     let vtm = Vtm { boundary };
///     let result = vtm.mesh(&region, &MeshRequest::points(194).seed(1), &mut |_| {})?;
///     assert_eq!(result.mesh.num_vertices(), 194);
///     check_conforming(&result.mesh, &region)?;
/// }
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, Default)]
pub struct Vtm {
    /// The boundary rule (module docs).
    pub boundary: VtmBoundary,
}

impl Mesher for Vtm {
    fn follows_size_fields(&self) -> bool {
        false
    }

    fn name(&self) -> &'static str {
        "vtm"
    }

    /// The coarsest boundary of the shared relaxation ([`relax::min_boundary_points`]), or of
    /// CCVT under [`VtmBoundary::Voronoi`].
    fn min_boundary_points(&self, region: &Region) -> usize {
        match self.boundary {
            VtmBoundary::Sliding => relax::min_boundary_points(region),
            VtmBoundary::Voronoi => odt_ccvt().min_boundary_points(region),
        }
    }

    /// Relax until the largest move is below `tol · h`. `energy_history` holds
    /// [`odt_energy`].
    fn mesh(
        &self,
        region: &Region,
        request: &MeshRequest,
        progress: &mut dyn FnMut(Progress),
    ) -> Result<MeshResult, MeshError> {
        match self.boundary {
            VtmBoundary::Sliding => relax::relax(
                "vtm",
                region,
                request,
                progress,
                &|mesh: &Mesh, density: &Density| {
                    (odt_targets(mesh, density), odt_energy(mesh, density))
                },
            ),
            VtmBoundary::Voronoi => odt_ccvt().mesh(region, request, progress),
        }
    }
}

/// CCVT's Algorithm 1 with Lloyd iteration and VTM's update.
fn odt_ccvt() -> ccvt::Ccvt {
    ccvt::Ccvt {
        update: ccvt::Update::Odt,
        ..ccvt::Ccvt::algorithm1()
    }
}

/// VTM's target for every vertex of `mesh` ([`tessellation::odt_targets`] on its triangles):
/// Σ w_T c_T / Σ w_T over its triangles, with w_T = |T|·ρ at the barycenter and c_T the
/// circumcenter (the barycenter for triangles on the mesh boundary). A vertex in no triangle
/// keeps its position.
pub fn odt_targets(mesh: &Mesh, density: &Density) -> Vec<DVec2> {
    tessellation::odt_targets(&mesh.points, &mesh.triangles, density)
}

/// The ODT energy of `mesh` ([`tessellation::odt_energy`]): ∫ (u_I − u) for u = |x|², u_I its
/// piecewise-linear interpolant, Σ_T ρ_T |T| (ℓ₁² + ℓ₂² + ℓ₃²) / 12. Chen's update moves each
/// vertex to the minimiser of this energy over its patch.
pub fn odt_energy(mesh: &Mesh, density: &Density) -> f64 {
    tessellation::odt_energy(&mesh.points, &mesh.triangles, density)
}

#[cfg(test)]
mod tests {
    use super::*;
    use mesh::VertexMarker;
    use testkit::hex_patch;

    #[test]
    fn boundary_triangles_are_found() {
        let m = hex_patch(2);
        assert_eq!(m.num_triangles(), 24);
        // The 12 outer edges of a two-ring hexagon each bound one triangle of ring 2.
        assert_eq!(
            tessellation::odt_boundary_triangles(&m.triangles)
                .iter()
                .filter(|&&b| b)
                .count(),
            12
        );
        assert!((m.area() - 24.0 * 3f64.sqrt() / 4.0).abs() < 1e-12);
    }

    #[test]
    fn centre_of_regular_patch_is_a_fixed_point() {
        for rings in [1, 2, 3] {
            let m = hex_patch(rings);
            let t = odt_targets(&m, &Density::Uniform);
            assert!(
                t[0].length() < 1e-14,
                "rings {rings}: centre moved to {}",
                t[0]
            );
        }
    }

    /// A patch whose centre is displaced and whose other vertices are jittered.
    fn jittered(seed: u64) -> Mesh {
        let mut m = hex_patch(2);
        let mut rng = geometry::Rng::new(seed);
        for p in m.points.iter_mut() {
            *p += DVec2::new(rng.range(-0.15, 0.15), rng.range(-0.15, 0.15));
        }
        m
    }

    #[test]
    fn target_minimises_the_patch_energy_and_is_a_fixed_point() {
        for seed in 1..6 {
            let mut m = jittered(seed);
            let x = odt_targets(&m, &Density::Uniform)[0];
            assert!(
                (x - m.points[0]).length() > 1e-6,
                "jittered centre should move"
            );
            m.points[0] = x;
            // The closed form does not depend on where x_0 is inside its patch.
            let again = odt_targets(&m, &Density::Uniform)[0];
            assert!((again - x).length() < 1e-12, "{again} vs {x}");
            let e = odt_energy(&m, &Density::Uniform);
            for k in 0..8 {
                let dir = DVec2::from_angle(k as f64 * std::f64::consts::FRAC_PI_4);
                let mut p = m.clone();
                p.points[0] = x + 0.02 * dir;
                assert!(
                    odt_energy(&p, &Density::Uniform) > e,
                    "seed {seed}, direction {k}"
                );
            }
        }
    }

    #[test]
    fn energy_matches_interpolation_error() {
        // ∫_T (u_I − u) for u = |x|² on the triangle (0,0),(1,0),(0,1): ∫u_I = |T|/3·Σ|x_v|² = 1/3,
        // ∫u = 1/6, so 1/6; the edge formula gives (1/2)(1 + 2 + 1)/12 = 1/6.
        let points = vec![DVec2::ZERO, DVec2::X, DVec2::Y];
        let m = Mesh {
            points,
            triangles: vec![[0, 1, 2]],
            markers: vec![VertexMarker::Interior; 3],
        };
        assert!((odt_energy(&m, &Density::Uniform) - 1.0 / 6.0).abs() < 1e-15);
    }

    #[test]
    fn targets_follow_translation_and_rotation() {
        let m = jittered(11);
        let t0 = odt_targets(&m, &Density::Uniform);
        let (shift, rot) = (DVec2::new(-2.0, 7.5), DVec2::from_angle(0.7));
        let mut moved = m.clone();
        moved
            .points
            .iter_mut()
            .for_each(|p| *p = rot.rotate(*p) + shift);
        let t1 = odt_targets(&moved, &Density::Uniform);
        for (a, b) in t0.iter().zip(&t1) {
            assert!((rot.rotate(*a) + shift - *b).length() < 1e-12);
        }
    }

    #[test]
    fn density_pulls_the_target() {
        let m = hex_patch(2);
        let rho = Density::Function(std::sync::Arc::new(|p: DVec2| (2.0 * p.x).exp()));
        let t = odt_targets(&m, &rho)[0];
        assert!(t.x > 0.01 && t.y.abs() < 1e-12, "target {t}");
    }
}
