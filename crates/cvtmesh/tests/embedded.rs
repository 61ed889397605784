//! Points embedded in a region (a source, a probe, a `.poly` vertex on no segment) are vertices
//! of every mesh the methods that keep them make, and the others refuse such a region.
use cvtmesh::{check_conforming, polish, DVec2, MeshRequest, Method, Region};

/// The square with a hole, two points embedded: one near the hole, one near a corner.
fn region() -> Region {
    Region::builtin("square_hole")
        .unwrap()
        .with_embedded_points([(DVec2::new(0.3, 0.27), 4), (DVec2::new(0.9, 0.93), 0)])
        .unwrap()
}

#[test]
fn every_method_that_keeps_embedded_points_has_a_vertex_on_each() {
    let region = region();
    let area: f64 = region.area();
    for method in Method::ALL {
        for k in [150, 1500] {
            let request = MeshRequest::points(k);
            let result = method.run(&region, &request);
            if matches!(method, Method::Meshgen | Method::Vtm) {
                let e = result.map(|_| ()).unwrap_err().to_string();
                assert!(e.contains("embeds 2 points"), "{method}: {e}");
                continue;
            }
            let r = result.unwrap_or_else(|e| panic!("{method} at {k}: {e}"));
            check_conforming(&r.mesh, &region).unwrap_or_else(|e| panic!("{method}: {e}"));
            for &(p, _) in region.embedded_points() {
                assert!(
                    r.mesh.points.contains(&p),
                    "{method} at {k}: no vertex at {p}"
                );
            }
            let covered = r.mesh.area();
            assert!(
                (covered - area).abs() < 1e-2 * area,
                "{method}: {covered} of {area}"
            );
        }
    }
}

#[test]
fn the_polish_leaves_an_embedded_point_where_it_is() {
    let region = region();
    let mut mesh = Method::Ccvt
        .run(&region, &MeshRequest::points(400))
        .unwrap()
        .mesh;
    // Every vertex may move, up to a polish at 60° (every triangle is "bad").
    let polished = polish(&mut mesh, &region, 60.0);
    assert!(polished.moved > 0, "the polish moved nothing");
    for &(p, _) in region.embedded_points() {
        assert!(
            mesh.points.contains(&p),
            "no vertex at {p} after the polish"
        );
    }
}

#[test]
fn too_few_points_for_the_embedded_ones_is_refused_by_name() {
    // One vertex per embedded point on top of what the boundary needs.
    let region = region();
    let needed = cvtmesh::boundary_points_needed(&region) + 2;
    let e = Method::Ccvt
        .run(&region, &MeshRequest::points(needed - 1))
        .map(|_| ())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("2 embedded points") && e.contains(&format!("at least {needed}")),
        "{e}"
    );
}

#[test]
fn a_point_by_a_curved_boundary_is_kept_or_refused_by_name() {
    // 0.001 inside the unit circle: at 200 vertices the boundary's chords pass inside it, so a
    // mesh either has a boundary vertex right by it or cannot keep it, and says so.
    let region = Region::builtin("circle")
        .unwrap()
        .with_embedded_points([(DVec2::new(0.999, 0.0), 1)])
        .unwrap();
    for method in [Method::Ccvt, Method::Refine, Method::Distmesh] {
        match method.run(&region, &MeshRequest::points(200)) {
            Ok(r) => {
                check_conforming(&r.mesh, &region).unwrap_or_else(|e| panic!("{method}: {e}"));
                assert!(r.mesh.points.contains(&DVec2::new(0.999, 0.0)), "{method}");
            }
            Err(e) => {
                let e = e.to_string();
                assert!(
                    e.contains("(0.999, 0)")
                        && (e.contains("between a curved boundary") || e.contains("not a vertex")),
                    "{method}: {e}"
                );
            }
        }
    }
}
