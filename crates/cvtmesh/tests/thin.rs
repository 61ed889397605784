//! Regions far thinner than the spacing: a mesh with every triangle inside, or an error that
//! names the thin place; never a mesh reaching into a hole.
use cvtmesh::geometry::LoopRole;
use cvtmesh::{DVec2, MeshError, MeshRequest, Method, Region};

/// The region between two 128-gons of radii 1 and 0.999: a ring 1e-3 wide, no corner kept.
fn thin_ring() -> Region {
    let circle = |r: f64| {
        (0..128)
            .map(|i| {
                let t = std::f64::consts::TAU * i as f64 / 128.0;
                DVec2::new(r * t.cos(), r * t.sin())
            })
            .collect::<Vec<_>>()
    };
    Region::from_loops(
        "ring",
        vec![
            (LoopRole::Outer, circle(1.0)),
            (LoopRole::Hole, circle(0.999)),
        ],
    )
    .unwrap()
    .with_default_corners()
}

/// At K = 300 the spacing is about five times the ring's width. The chords of the inner loop
/// sag into the hole by half the width, so a triangle from the inner loop to the outer one had
/// its centroid in the hole, and the CCVT and MESHGEN meshes were handed back with that
/// triangle and only a warning.
#[test]
fn a_ring_thinner_than_the_spacing_is_never_meshed_into_its_hole() {
    let ring = thin_ring();
    let request = MeshRequest::points(300).max_iter(2000);
    let thin = cvtmesh::thin_feature(&ring, &request).expect("a thin ring");
    assert!(thin.spacing / thin.width > 4.0, "{thin}");
    for m in [Method::Ccvt, Method::Meshgen] {
        match m.run(&ring, &request) {
            Err(MeshError::NotConforming { hint, .. }) => {
                assert!(hint.contains("would resolve it"), "{m}: {hint}")
            }
            Err(e) => panic!("{m}: {e}"),
            Ok(r) => {
                for t in 0..r.mesh.triangles.len() {
                    let [a, b, c] = r.mesh.triangle(t);
                    let centroid = (a + b + c) / 3.0;
                    assert!(
                        ring.signed_distance(centroid) <= 1e-9,
                        "{m}: triangle {t} has its centroid at {centroid} outside the ring"
                    );
                }
            }
        }
    }
}

/// At K = 30 the spacing is fifteen times the ring's width, far too coarse to put three
/// vertices on each loop: CCVT and DistMesh refuse, naming what failed and that a larger K
/// would mesh the ring.
#[test]
fn a_ring_far_thinner_than_the_spacing_at_a_small_k_is_refused_saying_what_would_mesh_it() {
    let ring = thin_ring();
    let request = MeshRequest::points(30).max_iter(3000);
    let e = Method::Ccvt.run(&ring, &request).unwrap_err().to_string();
    assert!(
        e.contains("boundary loop 1 has") && e.contains("a larger K would follow it"),
        "{e}"
    );
    let e = Method::Distmesh
        .run(&ring, &request)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("too coarse for it") && e.contains("a larger K would mesh it"),
        "{e}"
    );
}
