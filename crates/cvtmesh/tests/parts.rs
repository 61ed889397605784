//! Regions of several parts, meshed end to end: every part meshed with its share of K, the
//! meshes merged into one that conforms to the whole region.
use cvtmesh::geometry::formats::{geojson_from_str, loops_from_str};
use cvtmesh::{check_conforming, Density, MeshError, MeshRequest, Mesher, Method, Region};
use std::sync::Arc;

/// A unit square; a 3 × 2 rectangle with a 1 × 1 hole; an island inside that hole. A loop
/// list cannot say which loop is a hole, so nesting decides.
const THREE_PARTS: &str = "\
0 0\n1 0\n1 1\n0 1\n\n\
2 0\n5 0\n5 2\n2 2\n\n\
3 0.5\n4 0.5\n4 1.5\n3 1.5\n\n\
3.3 0.8\n3.7 0.8\n3.7 1.2\n3.3 1.2\n";

fn three_parts() -> Region {
    loops_from_str(THREE_PARTS, "three", "three").unwrap()
}

/// Vertices of the mesh in each part (by the part a vertex lies in).
fn per_part(region: &Region, mesh: &cvtmesh::Mesh) -> Vec<usize> {
    let parts = region.parts();
    let mut n = vec![0; parts.len()];
    for p in &mesh.points {
        let i = parts
            .iter()
            .position(|part| part.region.signed_distance(*p) <= 1e-9)
            .expect("every vertex lies in a part");
        n[i] += 1;
    }
    n
}

#[test]
fn nesting_makes_three_parts_of_four_loops() {
    let r = three_parts();
    assert_eq!(r.num_parts(), 3);
    assert_eq!(r.loops().len(), 4);
    assert!((r.area() - (1.0 + 5.0 + 0.16)).abs() < 1e-12);
    let areas: Vec<f64> = r.parts().iter().map(|p| p.region.area()).collect();
    assert!((areas[0] - 1.0).abs() < 1e-12 && (areas[1] - 5.0).abs() < 1e-12);
    assert!((areas[2] - 0.16).abs() < 1e-12);
}

#[test]
fn every_part_is_meshed_in_proportion_to_its_area() {
    let r = three_parts();
    let k = 600;
    let result = cvtmesh::mesh(&r, k).unwrap();
    assert!(result.converged);
    check_conforming(&result.mesh, &r).unwrap();
    assert_eq!(result.mesh.num_vertices(), k);
    // Straight boundaries: the triangles tile the region exactly.
    assert!((result.mesh.area() - r.area()).abs() < 1e-9 * r.area());
    for t in 0..result.mesh.num_triangles() {
        let [a, b, c] = result.mesh.triangle(t);
        assert!(r.contains((a + b + c) / 3.0), "triangle {t}");
    }
    // Each part within one vertex of its share of K (largest remainders).
    let n = per_part(&r, &result.mesh);
    for (part, &ni) in r.parts().iter().zip(&n) {
        let want = k as f64 * part.region.area() / r.area();
        assert!(
            (ni as f64 - want).abs() <= 1.0,
            "{n:?}: {ni} against {want}"
        );
    }
    // Markers name the whole region's loops: every loop carries boundary edges.
    let mut loops: Vec<usize> = result
        .mesh
        .boundary_edges()
        .iter()
        .map(|e| e.loop_index)
        .collect();
    loops.dedup();
    assert_eq!(loops, [0, 1, 2, 3]);
    assert!(result.notes.iter().any(|n| n.starts_with("part 2: K = ")));
}

#[test]
fn the_last_energy_of_a_region_of_parts_is_the_sum_of_its_parts() {
    let r = three_parts();
    let whole = cvtmesh::mesh(&r, 600).unwrap();
    let n = per_part(&r, &whole.mesh);
    let mut sum = 0.0;
    let mut runs = 0;
    for (part, &ni) in r.parts().iter().zip(&n) {
        let alone = Method::Ccvt
            .run(&part.region, &MeshRequest::points(ni))
            .unwrap();
        sum += alone.energy_history.last().unwrap();
        runs += alone.energy_history.len();
    }
    assert_eq!(whole.energy_history.len(), runs);
    let last = *whole.energy_history.last().unwrap();
    assert!(
        (last - sum).abs() <= 1e-12 * sum,
        "{last:e} against {sum:e}"
    );
}

#[test]
fn every_method_meshes_every_part() {
    let r = three_parts();
    for m in Method::ALL {
        let req = MeshRequest::points(300).tol(1e-3).max_iter(2000);
        let result = m.run(&r, &req).unwrap_or_else(|e| panic!("{m}: {e}"));
        check_conforming(&result.mesh, &r).unwrap_or_else(|e| panic!("{m}: {e}"));
        assert!(
            (result.mesh.area() - r.area()).abs() < 1e-9 * r.area(),
            "{m}"
        );
        let n = per_part(&r, &result.mesh);
        assert!(n.iter().all(|&ni| ni >= 7), "{m}: {n:?}");
    }
}

#[test]
fn a_density_shares_k_by_the_count_it_asks_for() {
    // Two unit squares; ρ = 16 on the right one, so it asks for √16 = 4 times the vertices.
    let r = loops_from_str("0 0\n1 0\n1 1\n0 1\n\n2 0\n3 0\n3 1\n2 1\n", "two", "two").unwrap();
    let rho = Density::Function(Arc::new(
        |p: cvtmesh::DVec2| if p.x > 1.5 { 16.0 } else { 1.0 },
    ));
    let result = Method::Ccvt
        .run(&r, &MeshRequest::points(250).density(rho))
        .unwrap();
    check_conforming(&result.mesh, &r).unwrap();
    assert_eq!(per_part(&r, &result.mesh), [50, 200]);
}

#[test]
fn a_geojson_multipolygon_is_meshed_whole() {
    let a = "[[[0,0],[1,0],[1,1],[0,1],[0,0]]]";
    let b =
        "[[[2,0],[4,0],[4,1],[2,1],[2,0]],[[2.5,0.25],[2.5,0.75],[3,0.75],[3,0.25],[2.5,0.25]]]";
    let text = format!("{{\"type\":\"MultiPolygon\",\"coordinates\":[{a},{b}]}}");
    let r = geojson_from_str(&text, "m.geojson", "m").unwrap();
    assert_eq!((r.num_parts(), r.loops().len()), (2, 3));
    let result = cvtmesh::mesh(&r, 400).unwrap();
    check_conforming(&result.mesh, &r).unwrap();
    assert!((result.mesh.area() - 2.75).abs() < 1e-9);
    let n = per_part(&r, &result.mesh);
    assert_eq!(n.iter().sum::<usize>(), 400);
    assert!((n[0] as f64 - 400.0 / 2.75).abs() <= 1.0, "{n:?}");
}

#[test]
fn too_few_points_for_all_parts_is_refused_before_any_work() {
    // Every loop a square: its 4 corners each.
    let e = cvtmesh::mesh(&three_parts(), 15).unwrap_err();
    assert!(e.to_string().contains("at least 16 vertices"), "{e}");
    // A method on its own refuses several parts rather than mesh one.
    let e = cvtmesh::Ccvt::fast()
        .mesh(&three_parts(), &MeshRequest::points(300), &mut |_| {})
        .unwrap_err();
    assert!(
        matches!(e, cvtmesh::MeshError::SeveralParts { parts: 3, .. }),
        "{e}"
    );
}

/// A digitized coastline: 3000 points around a wavy disc; no vertex turns by more than a few
/// degrees, so by default none is a corner.
fn coastline() -> Region {
    let pts = (0..3000)
        .map(|i| {
            let t = std::f64::consts::TAU * i as f64 / 3000.0;
            let r = 1.0 + 0.05 * (7.0 * t).sin() + 0.003 * (53.0 * t).sin();
            cvtmesh::DVec2::new(r * t.cos(), r * t.sin())
        })
        .collect();
    Region::from_loops("coast", vec![(cvtmesh::geometry::LoopRole::Outer, pts)]).unwrap()
}

#[test]
fn a_coastline_meshes_at_k_far_below_its_vertex_count_by_every_method() {
    let raw = coastline();
    assert_eq!(raw.corners().len(), 3000);
    // Every one of its 3000 vertices a corner: K = 300 is too few, and the error says so.
    let e = cvtmesh::mesh(&raw, 300).unwrap_err();
    assert!(
        matches!(e, MeshError::TooFewPoints { corners: 3000, .. }),
        "{e}"
    );
    let coast = raw.with_default_corners();
    assert!(coast.corners().is_empty());
    for m in Method::ALL {
        let req = MeshRequest::points(300).max_iter(500);
        let result = m.run(&coast, &req).unwrap_or_else(|e| panic!("{m}: {e}"));
        check_conforming(&result.mesh, &raw).unwrap_or_else(|e| panic!("{m}: {e}"));
        let k = result.mesh.num_vertices();
        assert!((270..=330).contains(&k), "{m}: K = {k}");
        assert!(
            result.mesh.min_angle_deg() > 20.0,
            "{m}: {}",
            result.mesh.min_angle_deg()
        );
    }
}

/// A method that needs many boundary vertices on small parts: 40 on any part of area below 1.
struct Greedy;

impl Mesher for Greedy {
    fn name(&self) -> &'static str {
        "greedy"
    }
    fn mesh(
        &self,
        region: &Region,
        request: &MeshRequest,
        progress: &mut dyn FnMut(cvtmesh::Progress),
    ) -> Result<cvtmesh::MeshResult, cvtmesh::MeshError> {
        let k = request.validate(region)?;
        if k < self.min_boundary_points(region) {
            return Err(cvtmesh::MeshError::BadRequest(format!(
                "share {k} too small"
            )));
        }
        Method::Ccvt.mesher().mesh(region, request, progress)
    }
    fn min_boundary_points(&self, region: &Region) -> usize {
        if region.area() < 1.0 {
            40
        } else {
            cvtmesh::boundary_points_needed(region)
        }
    }
}

#[test]
fn a_part_gets_at_least_the_boundary_its_method_needs() {
    // The island (area 0.16) would get 400 · 0.16 / 6.16 ≈ 10 by area; Greedy needs 40 there.
    let region = three_parts();
    let r = Greedy
        .mesh_parts(&region, &MeshRequest::points(400), &mut |_| {})
        .unwrap();
    check_conforming(&r.mesh, &region).unwrap();
    let n = per_part(&region, &r.mesh);
    assert_eq!(n.iter().sum::<usize>(), 400);
    assert_eq!(n[2], 40, "{n:?}");
    // Below the parts' needs together, a refusal naming each, before any work (the others'
    // needs include the corners their spacing adds at this K).
    let e = Greedy
        .mesh_parts(&region, &MeshRequest::points(51), &mut |_| {})
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("K = 51 is too small") && e.contains("with greedy") && e.contains(" + 40)"),
        "{e}"
    );
}
