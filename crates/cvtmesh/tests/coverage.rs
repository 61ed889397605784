//! A mesh covers its region: a method that ends with its boundary vertices bunched on part of
//! a loop (its chords cutting across most of the region) is refused, not handed back as a
//! converged mesh.
use cvtmesh::{MeshError, MeshRequest, Method, Region};

#[test]
fn boundary_vertices_bunched_on_one_arc_are_refused_not_converged() {
    let disc = Region::builtin("circle").unwrap();
    let request = MeshRequest::points(6).seed(2);
    // MESHGEN and VTM at K = 6 end with every boundary vertex on one arc of the disc.
    for method in [Method::Meshgen, Method::Vtm] {
        match method.run(&disc, &request) {
            Err(MeshError::Failed { message, .. }) => {
                assert!(
                    message.contains("bunched on part of loop 0"),
                    "{method}: {message}"
                )
            }
            Err(e) => panic!("{method}: {e}"),
            Ok(r) => panic!("{method}: covers {:.3}", r.mesh.area() / disc.area()),
        }
    }
    // The default method's mesh at the same K, and a triangle at K = 3 (its vertices spread),
    // are meshes of the disc, however coarse.
    for (method, k) in [(Method::Ccvt, 6), (Method::Meshgen, 3), (Method::Vtm, 3)] {
        let r = method.run(&disc, &MeshRequest::points(k).seed(2)).unwrap();
        assert!(r.mesh.area() > 0.4 * disc.area(), "{method} at {k}");
    }
}
