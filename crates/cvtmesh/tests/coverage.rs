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

/// A coarse mesh of a region with a round hole has chords that cut across the hole by more
/// than a fine mesh's, as any mesher's do: square_hole at K = 40 (six vertices around its hole,
/// chords straying 0.134 of their length) and the superellipse at K = 120–140 (its hole's
/// tight bends) are meshes of their regions, conforming, their chords within the chord
/// allowance. A chord that skips a corner keeps the stricter edge allowance (the tessellation
/// tests skip one of the lake's reflex corners).
#[test]
fn coarse_meshes_of_round_holes_conform() {
    for (name, ks) in [
        ("square_hole", &[30, 40, 46][..]),
        ("superellipse", &[120, 125, 130, 140]),
    ] {
        let region = Region::builtin(name).unwrap();
        for &k in ks {
            for seed in 1..=2 {
                let r = Method::Ccvt.run(&region, &MeshRequest::points(k).seed(seed));
                let mesh = r
                    .unwrap_or_else(|e| panic!("{name} at {k}, seed {seed}: {e}"))
                    .mesh;
                cvtmesh::check_conforming(&mesh, &region).unwrap();
                let hole: Vec<_> = mesh
                    .boundary_edges()
                    .into_iter()
                    .filter(|e| e.loop_index == 1)
                    .collect();
                assert!(hole.len() >= 3);
                // Every hole chord sags less than the chord allowance.
                let sag = |e: &cvtmesh::BoundaryEdge| {
                    let (a, b) = (mesh.points[e.a as usize], mesh.points[e.b as usize]);
                    (1..8)
                        .map(|s| region.signed_distance(a.lerp(b, s as f64 / 8.0)))
                        .fold(0.0, f64::max)
                        / a.distance(b)
                };
                assert!(
                    hole.iter().all(|e| sag(e) <= cvtmesh::CHORD_ALLOWANCE),
                    "{name} at {k}"
                );
            }
        }
    }
}
