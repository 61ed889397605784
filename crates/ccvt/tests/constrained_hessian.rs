//! The matrix Newton solves for a boundary generator is the second derivative of the energy
//! along its piece: moved along the tangent of [`piece_tangent`] and projected back onto the
//! piece, the energy curves as tᵀ H t + g · γ'' (H from `tessellation::energy_hessian`, g the
//! gradient 2m(z − c), γ'' the curvature vector), checked against finite differences of the
//! energy on converged meshes of curved regions. The curvature term is a few per cent of the
//! whole there, so a term left out or with the wrong sign fails.
use cvtmesh_ccvt::{piece_tangent, Ccvt};
use geometry::{DVec2, Density, Region};
use mesh::{MeshRequest, VertexMarker};
use tessellation::{clipped_cells, energy_hessian, BlockMatrix, Delaunay};

#[test]
fn a_boundary_generator_moved_along_its_piece_curves_as_newton_assumes() {
    for (name, k) in [("circle", 400), ("annulus", 600), ("superellipse", 500)] {
        let region = Region::builtin(name).unwrap();
        let request = MeshRequest::points(k).seed(1);
        let ccvt = Ccvt::default();
        let g = ccvt.generators(&region, &request, &mut |_| {}).unwrap();
        let spacing = request.spacing(&region);
        let omega = region.polygonize(ccvt.polygon_tol * spacing);
        let energy = |p: &[DVec2]| -> f64 {
            let d = Delaunay::new(p);
            clipped_cells(p, &d, &omega, &Density::Uniform).energy()
        };
        let z = &g.points;
        let del = Delaunay::new(z);
        let cells = clipped_cells(z, &del, &omega, &Density::Uniform);
        let mut hessian = BlockMatrix::default();
        energy_hessian(&del, &omega, &Density::Uniform, &cells, &mut hessian);
        let e0 = energy(z);
        let (mut checked, mut worst, mut curvature_share) = (0, 0.0f64, 0.0f64);
        for (i, marker) in g.markers.iter().enumerate() {
            let VertexMarker::Boundary { piece, .. } = *marker else {
                continue;
            };
            let (t, curve) = piece_tangent(&region, z[i], piece, spacing);
            let grad = 2.0 * cells.cells[i].mass * (z[i] - cells.cells[i].mass_centroid);
            let v = del.vertex_index(i).unwrap();
            let model = t.dot(hessian.get(v, v) * t) + grad.dot(curve);
            let along = |s: f64| {
                let mut p = z.clone();
                p[i] = region.project_onto_piece(z[i] + t * s, piece).point;
                energy(&p)
            };
            let d = 1e-3 * spacing;
            let differences = (along(d) - 2.0 * e0 + along(-d)) / (d * d);
            worst = worst.max((differences - model).abs() / model.abs());
            curvature_share = curvature_share.max(grad.dot(curve).abs() / model.abs());
            checked += 1;
            if checked == 16 {
                break;
            }
        }
        assert_eq!(checked, 16, "{name}: too few boundary generators");
        // The term the test is about must matter at this size.
        assert!(
            curvature_share > 0.01,
            "{name}: g · γ'' only {curvature_share:e} of the whole"
        );
        assert!(
            worst < 1e-3,
            "{name}: the curvature along the piece differs from finite differences by {worst:e} of itself"
        );
    }
}
