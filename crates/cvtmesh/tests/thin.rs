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

/// A comb: a base [0, 1] × [0, 0.2] with 20 teeth 0.02 wide and 0.8 long.
fn comb() -> Region {
    let mut outer = vec![
        DVec2::new(0.0, 0.0),
        DVec2::new(1.0, 0.0),
        DVec2::new(1.0, 0.2),
    ];
    for i in (0..20).rev() {
        let x = 0.015 + 0.05 * i as f64;
        outer.extend([
            DVec2::new(x + 0.02, 0.2),
            DVec2::new(x + 0.02, 1.0),
            DVec2::new(x, 1.0),
            DVec2::new(x, 0.2),
        ]);
    }
    outer.push(DVec2::new(0.0, 0.2));
    Region::from_loops("comb", vec![(LoopRole::Outer, outer)])
        .unwrap()
        .with_default_corners()
}

/// The K the warning advises puts one edge across the teeth, and the default method meshes
/// them there without a sliver (at half an edge across, where a tooth stops counting as thin,
/// it left 144 triangles under 1°).
#[test]
fn the_advised_k_meshes_a_comb_without_slivers() {
    let comb = comb();
    assert!((comb.area() - 0.52).abs() < 1e-12);
    let thin = cvtmesh::thin_feature(&comb, &MeshRequest::points(300)).expect("thin teeth");
    assert!((thin.width - 0.02).abs() < 1e-9, "{thin}");
    assert!((1400..1600).contains(&thin.points_needed), "{thin}");
    let request = MeshRequest::points(thin.points_needed);
    assert_eq!(cvtmesh::thin_feature(&comb, &request), None);
    let r = Method::Ccvt.run(&comb, &request).unwrap();
    assert!(r.converged);
    assert_eq!(cvtmesh::slivers(&r.mesh), None);
    assert!(r.mesh.min_angle_deg() > 20.0, "{}", r.mesh.min_angle_deg());
}
