//! Graded meshes follow their size field: the edges' lengths in the field's metric cluster
//! around 1, and the vertex count is the one the field asks for.
use cvtmesh::metrics::size_conformity;
use cvtmesh::{check_conforming, MeshRequest, Method, Region, SizeField};

fn graded(region: &str, field: &str, method: Method) -> cvtmesh::metrics::SizeConformity {
    let region = Region::builtin(region).unwrap();
    let h = SizeField::from_expr(field).unwrap();
    let request = MeshRequest::size_field(&h, &region, None)
        .unwrap()
        .tol(1e-3);
    let r = method.run(&region, &request).unwrap();
    check_conforming(&r.mesh, &region).unwrap();
    let c = size_conformity(&r.mesh, &h, &region).unwrap();
    println!("{method} {c:?}");
    c
}

#[test]
fn a_point_source_in_the_circle_is_followed() {
    // h from 0.03 at the centre to 0.15 on the rim: a spacing ratio of 5.
    let c = graded("circle", "0.03 + 0.12 * sqrt(x^2 + y^2)", Method::Ccvt);
    assert!((c.vertices as f64 - c.predicted_vertices).abs() <= 0.5);
    // The targets of mesh adaptation tools: a unit mesh share of 0.95, efficiency 0.9, and
    // no angle below 30°.
    assert!(c.unit_share >= 0.95, "{c:?}");
    assert!(c.efficiency >= 0.9, "{c:?}");
    assert!(c.min_angle_deg >= 30.0, "{c:?}");
}

#[test]
fn a_uniform_field_is_a_uniform_mesh() {
    let c = graded("square_hole", "0.08", Method::Ccvt);
    assert!(c.unit_share > 0.97, "{c:?}");
    assert!((c.mean_length - 1.0).abs() < 0.1, "{c:?}");
}
