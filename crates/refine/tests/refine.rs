//! End-to-end tests of the Delaunay refinement (TRIANGLE) method.
use cvtmesh_refine::{CurveStart, Refine};
use geometry::{Density, Region};
use mesh::{
    check_conforming, triangle_min_angle_deg, Mesh, MeshError, MeshRequest, MeshResult, Mesher,
};

fn run(m: &Refine, name: &str, k: usize) -> (Region, MeshResult) {
    let region = Region::builtin(name).unwrap();
    let r = m
        .mesh(&region, &MeshRequest::points(k), &mut |_| {})
        .unwrap();
    (region, r)
}

/// Smallest angle (degrees) over triangles, ignoring those Triangle leaves alone because a
/// small input angle forces them: the shortest edge joins two boundary vertices (not along the
/// boundary) at equal distances (0.1%, squared) from a region corner.
fn min_angle_unforced(mesh: &Mesh, region: &Region) -> f64 {
    let mut worst = f64::INFINITY;
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let p = mesh.triangle(t);
        let a = triangle_min_angle_deg(p);
        let s = (0..3).min_by(|&i, &j| {
            let li = (p[(i + 1) % 3] - p[i]).length_squared();
            let lj = (p[(j + 1) % 3] - p[j]).length_squared();
            li.total_cmp(&lj)
        });
        let s = s.unwrap();
        let (u, v) = (tri[s] as usize, tri[(s + 1) % 3] as usize);
        let forced = mesh.markers[u].on_boundary()
            && mesh.markers[v].on_boundary()
            && region.corners().iter().any(|c| {
                let (du, dv) = (
                    (mesh.points[u] - c.pos).length_squared(),
                    (mesh.points[v] - c.pos).length_squared(),
                );
                du < 1.001 * dv && du > 0.999 * dv
            });
        if !forced {
            worst = worst.min(a);
        }
    }
    worst
}

fn assert_good(region: &Region, r: &MeshResult, k: usize, angle: f64) {
    let mesh = &r.mesh;
    check_conforming(mesh, region).unwrap_or_else(|e| panic!("{}: {e}", region.name()));
    let got = mesh.num_vertices();
    assert!(
        got.abs_diff(k) as f64 <= 0.03 * k as f64 + 1.0,
        "{}: K {got} vs {k}",
        region.name()
    );
    let a = min_angle_unforced(mesh, region);
    assert!(
        a >= angle - 1e-9,
        "{}: min angle {a} < {angle}",
        region.name()
    );
    testkit::assert_corners_and_area(mesh, region, k);
    assert!(r
        .notes
        .iter()
        .any(|n| n.contains(&format!("K reached {got}"))));
}

#[test]
fn circle_88() {
    let (region, r) = run(&Refine::default(), "circle", 88);
    assert_good(&region, &r, 88, 20.0);
    assert!(r.iterations >= 1);
}

#[test]
fn square_two_hex_203() {
    let (region, r) = run(&Refine::default(), "square_two_hex", 203);
    assert_good(&region, &r, 203, 20.0);
}

#[test]
fn annulus_303() {
    let (region, r) = run(&Refine::default(), "annulus", 303);
    assert_good(&region, &r, 303, 20.0);
}

#[test]
fn thirty_degrees() {
    let m = Refine {
        min_angle_deg: 30.0,
        ..Refine::default()
    };
    let (region, r) = run(&m, "hex_hole", 240);
    assert_good(&region, &r, 240, 30.0);
    assert!(r.mesh.min_angle_deg() >= 30.0);
    // The pie's 30° apex forces a few smaller angles next to it (Triangle's shell exemption).
    let (region, r) = run(&m, "pie_hole", 287);
    assert_good(&region, &r, 287, 30.0);
    assert!(r.mesh.min_angle_deg() > 20.0);
}

#[test]
fn fixed_area_bound_is_met_by_every_triangle() {
    let region = Region::builtin("square_hole").unwrap();
    let a = 0.02;
    let r = Refine::default()
        .refine_with_area(&region, a, &Density::Uniform, 1_000_000)
        .unwrap();
    assert!(r.complete);
    assert_eq!(r.given_up, 0);
    check_conforming(&r.mesh, &region).unwrap();
    for t in 0..r.mesh.num_triangles() {
        let [p, q, s] = r.mesh.triangle(t);
        assert!(
            0.5 * (q - p).perp_dot(s - p) <= a,
            "triangle {t} above the area bound"
        );
    }
    // A smaller bound gives more vertices.
    let finer = Refine::default()
        .refine_with_area(&region, a / 4.0, &Density::Uniform, 1_000_000)
        .unwrap();
    assert!(finer.mesh.num_vertices() > 2 * r.mesh.num_vertices());
}

#[test]
fn deterministic() {
    let (_, a) = run(&Refine::default(), "horn", 138);
    let region = Region::builtin("horn").unwrap();
    let b = Refine::default()
        .mesh(&region, &MeshRequest::points(138).seed(99), &mut |_| {})
        .unwrap();
    assert_eq!(a.mesh, b.mesh);
    assert_eq!(a.notes, b.notes);
}

#[test]
fn a_seeded_curve_start_varies_the_mesh_by_seed_only() {
    let region = Region::builtin("annulus").unwrap();
    let seeded = Refine {
        curve_start: CurveStart::Seeded,
        ..Refine::default()
    };
    let mesh = |seed| {
        let r = seeded
            .mesh(&region, &MeshRequest::points(303).seed(seed), &mut |_| {})
            .unwrap();
        assert_good(&region, &r, 303, 20.0);
        assert!(r.notes.iter().any(|n| n.contains("seeded start")));
        r.mesh
    };
    let (a, b) = (mesh(1), mesh(2));
    assert_ne!(
        a.points, b.points,
        "another seed, another start of the circles' chords"
    );
    assert_eq!(mesh(1), a, "the same seed, the same mesh");
    // The phases are a function of the seed, one per loop, in [0, 1).
    let p = CurveStart::Seeded.phases(&region, 1);
    assert_eq!(p.len(), 2);
    assert!(p.iter().all(|x| (0.0..1.0).contains(x)));
    assert_eq!(p, CurveStart::Seeded.phases(&region, 1));
    assert_eq!(CurveStart::PieceStart.phases(&region, 1), vec![0.0, 0.0]);
}

#[test]
fn bad_requests_are_errors() {
    let region = Region::builtin("square_two_hex").unwrap();
    let e = Refine::default()
        .mesh(&region, &MeshRequest::points(5), &mut |_| {})
        .unwrap_err();
    assert!(matches!(e, MeshError::TooFewPoints { .. }), "{e:?}");
    let m = Refine {
        min_angle_deg: 75.0,
        ..Refine::default()
    };
    let e = m
        .mesh(&region, &MeshRequest::points(200), &mut |_| {})
        .unwrap_err();
    assert!(matches!(e, MeshError::InvalidSetting { .. }), "{e:?}");
    let e = Refine::default()
        .refine_with_area(&region, -1.0, &Density::Uniform, 100)
        .unwrap_err();
    assert!(matches!(e, MeshError::BadRequest(_)));
}

#[test]
fn progress_once_per_search_step() {
    let region = Region::builtin("circle").unwrap();
    let mut calls = 0;
    let r = Refine::default()
        .mesh(&region, &MeshRequest::points(19), &mut |_| calls += 1)
        .unwrap();
    assert_eq!(calls, r.iterations);
    check_conforming(&r.mesh, &region).unwrap();
}

#[test]
fn graded_density_refines_where_dense() {
    testkit::graded_density_puts_more_points_where_dense(&Refine::default());
}

/// All ten paper regions at the paper's K, at Triangle's default 20° (no small input angles
/// there, so no exemptions are needed).
#[test]
fn all_paper_regions() {
    for (name, k) in Region::paper_cases() {
        let (region, r) = run(&Refine::default(), name, k);
        assert_good(&region, &r, k, 20.0);
        assert!(
            r.mesh.min_angle_deg() >= 20.0,
            "{name}: {}",
            r.mesh.min_angle_deg()
        );
        eprintln!(
            "{name} K={k}: reached {} in {} steps, converged {}",
            r.mesh.num_vertices(),
            r.iterations,
            r.converged
        );
    }
}

#[test]
fn a_run_that_reaches_its_step_cap_returns_its_mesh_not_converged() {
    let region = Region::builtin("square_hole").unwrap();
    // A fixed area bound that asks for ~10⁵ vertices, stopped after 500 steps.
    let m = Refine {
        max_area: Some(1e-4),
        max_steps: Some(500),
        ..Refine::default()
    };
    let r = m
        .mesh(&region, &MeshRequest::points(100), &mut |_| {})
        .unwrap();
    assert!(!r.converged);
    assert!(r.mesh.num_vertices() < 1000, "{}", r.mesh.num_vertices());
    check_conforming(&r.mesh, &region).unwrap();
    // Searching for K with a cap too small for any run to finish fails with a message,
    // rather than running on.
    let m = Refine {
        max_steps: Some(10),
        ..Refine::default()
    };
    let e = m
        .mesh(&region, &MeshRequest::points(500), &mut |_| {})
        .unwrap_err();
    assert!(e.to_string().contains("no complete refinement"), "{e}");
}

/// Found by the `mesh_loops` fuzz target: a pentagon whose default corners merge a bend of
/// 28° into one polyline piece. At the coarse area bounds a search for K = 8 tries, that
/// piece's single chord cuts across the neighbouring side, and the initial triangulation
/// panicked on the crossing constraints. Chords now follow the polyline's bends.
#[test]
fn a_chord_crossing_the_boundary_at_a_coarse_bound_shrinks_the_bound_not_panics() {
    let pts = [(2, 5), (11, 6), (15, 1), (12, 7), (2, 14)]
        .map(|(x, y)| geometry::DVec2::new(x as f64, y as f64))
        .to_vec();
    let raw = Region::from_loops("pentagon", vec![(geometry::LoopRole::Outer, pts)]).unwrap();
    let region = raw.with_default_corners();
    assert_eq!(region.corners().len(), 4);
    let m = Refine::default();
    for max_iter in [10, 20, 60] {
        let request = MeshRequest::points(8).tol(1e-2).max_iter(max_iter);
        let r = m.mesh(&region, &request, &mut |_| {}).unwrap();
        check_conforming(&r.mesh, &raw).unwrap();
    }
    // At a fixed bound that coarse the chord would cross the neighbouring side; it strays
    // from its polyline by far more than a chord may, so the bend's vertex is kept and the
    // refinement completes.
    let r = m
        .refine_with_area(&region, 100.0, &Density::Uniform, 1000)
        .unwrap();
    assert!(r.complete);
    check_conforming(&r.mesh, &raw).unwrap();
    assert!(r.mesh.points.contains(&geometry::DVec2::new(12.0, 7.0)));
}

/// Found by the `mesh_loops` fuzz target as a hang: a hexagon whose default corners merge
/// (15, 15), (2, 8), (0, 5) into one polyline piece. At a coarse bound that piece is one chord
/// from (15, 15) to (0, 5), which runs exactly through the vertex (9, 11) and along the side
/// from there to (0, 5). spade split the chord at the vertex without a word, and the
/// refinement chased the sliver of zero width until its vertex budget ran out: 1100 boundary
/// vertices and 2 s for each such step of the search at K = 10.
#[test]
fn a_chord_through_a_vertex_of_another_piece_is_too_coarse_not_refined_to_the_budget() {
    let pts = [(15, 15), (3, 0), (0, 0), (9, 11), (0, 5), (2, 8)]
        .map(|(x, y)| geometry::DVec2::new(x as f64, y as f64))
        .to_vec();
    let raw = Region::from_loops("hexagon", vec![(geometry::LoopRole::Outer, pts)]).unwrap();
    let region = raw.with_default_corners();
    assert_eq!(region.corners().len(), 5);
    let m = Refine::default();
    let e = m
        .refine_with_area(&region, 150.0, &Density::Uniform, 1100)
        .unwrap_err();
    assert!(e.to_string().contains("runs through its vertex"), "{e}");
    for max_iter in [4, 5, 20] {
        let request = MeshRequest::points(10).tol(1e-2).max_iter(max_iter);
        let r = m.mesh(&region, &request, &mut |_| {}).unwrap();
        check_conforming(&r.mesh, &raw).unwrap();
        assert!(r.mesh.num_vertices() < 50, "{}", r.mesh.num_vertices());
    }
}

/// Found by fuzzing (`mesh_loops`, seed `refine_budget_twice.bin`): a 7° sliver of a triangle
/// beside a larger one, K = 28 with a cap of 7 search steps. The sliver's third corner is a
/// dropped bend, and at coarse bounds its bent side became one chord along its straight side:
/// a loop of no area, which the refinement chased to its vertex budget on every step of the
/// search (1040 vertices each, 13 s with debug assertions). Such a bound is too coarse now,
/// and the sliver's part ends with a few dozen vertices.
#[test]
fn a_sliver_beside_a_triangle_is_meshed_without_running_to_the_budget() {
    use geometry::{DVec2, LoopRole};
    let v = |x: f64, y: f64| DVec2::new(x, y);
    let region = Region::from_loops(
        "sliver_and_triangle",
        vec![
            (
                LoopRole::Outer,
                vec![v(7.0, 13.0), v(3.0, 7.0), v(5.0, 11.0)],
            ),
            (
                LoopRole::Outer,
                vec![v(11.0, 3.0), v(11.0, 11.0), v(4.0, 8.0)],
            ),
        ],
    )
    .unwrap()
    .with_default_corners();
    let request = MeshRequest::points(28).max_iter(7);
    let r = Refine::default()
        .mesh_parts(&region, &request, &mut |_| {})
        .unwrap();
    check_conforming(&r.mesh, &region).unwrap();
    assert!(r.mesh.num_vertices() < 100, "{}", r.mesh.num_vertices());
}

/// Two holes 1e-4 apart along their whole height: the 20° bound grades the mesh down to the
/// gap, which no refinement does within the vertex budget of K = 30. The search gives up with
/// a message that says why and what would help, not a bare count of search steps, and as soon
/// as a coarser bound runs out of budget exactly as the last one did (two steps, not the cap).
#[test]
fn holes_a_hair_apart_at_a_small_k_are_refused_with_the_budget_named() {
    use geometry::{DVec2, LoopRole};
    let square = |x0: f64, y0: f64, x1: f64, y1: f64| {
        vec![
            DVec2::new(x0, y0),
            DVec2::new(x1, y0),
            DVec2::new(x1, y1),
            DVec2::new(x0, y1),
        ]
    };
    let region = Region::from_loops(
        "hair",
        vec![
            (LoopRole::Outer, square(0.0, 0.0, 1.0, 1.0)),
            (LoopRole::Hole, square(0.2, 0.4, 0.4, 0.6)),
            (LoopRole::Hole, square(0.4001, 0.4, 0.6, 0.6)),
        ],
    )
    .unwrap();
    let e = Refine::default()
        .mesh(&region, &MeshRequest::points(30), &mut |_| {})
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("budget of 1300 vertices (2 search steps)")
            && e.contains("a larger K would mesh it"),
        "{e}"
    );
}

/// A chain with a cusp inside it (two arcs meeting almost head-on, their corner dropped by a
/// corner angle of 180°): no equal steps along the chain put a point on the cusp, so the
/// chord over it always strayed more than a quarter of its length, and the curve's split was
/// doubled to 2¹⁷ points. At K = 17 every area bound of the search built a boundary of 131 075
/// vertices (over two minutes in release). A chain's bends are followed at its own vertices
/// instead, and the search reaches K.
#[test]
fn a_chain_with_a_cusp_is_split_at_its_bends_not_doubled_to_the_cap() {
    let region = Region::from_json_str(
        r#"{"loops": [{"segments": [
            {"kind": "polyline", "points": [[7, 7], [10, 10]]},
            {"kind": "arc", "center": [9.295249570449217, 5.0], "radius": 5.049423052978629,
             "from_deg": 81.9770071061092, "to_deg": -81.9770071061092},
            {"kind": "arc", "center": [5.0, -1.5680693154002652], "radius": 5.240118450750885,
             "from_deg": 17.412147932935145, "to_deg": -197.41214793293517},
            {"kind": "polyline", "points": [[0, 0], [0, 12], [7, 7]]}]}]}"#,
        "cusp",
    )
    .unwrap()
    .with_corner_angle(180.0);
    let r = Refine::default()
        .mesh(&region, &MeshRequest::points(17), &mut |_| {})
        .unwrap();
    assert!(r.converged, "{:?}", r.notes);
    let k = r.mesh.num_vertices();
    assert!((12..=24).contains(&k), "{k} vertices for K = 17");
    check_conforming(&r.mesh, &region).unwrap();
}

/// A thin triangle (a 7.8° corner at (15, 3)) whose third corner, a 16° bend at (8, 1), the
/// default corner angle drops: its two sides from (1, 1) to (15, 3) become one polyline piece,
/// which a coarse area bound cuts to one chord lying along the straight side. At K = 10 the
/// search stopped at the first such bound ("boundary loop with only 2 vertices"); beside a
/// second triangle, where the gap between them adds a corner on the straight side, the loop
/// became three collinear vertices and the mesh a triangle of zero area, refused as not
/// conforming at K = 40 and 50. Both are bounds too coarse for the loop, which the search
/// shrinks.
#[test]
fn a_loop_whose_chords_enclose_no_area_is_too_coarse_not_meshed() {
    use geometry::{DVec2, LoopRole};
    let v = |x: f64, y: f64| DVec2::new(x, y);
    let thin = vec![v(8.0, 1.0), v(15.0, 3.0), v(1.0, 1.0)];
    let one = Region::from_loops("thin", vec![(LoopRole::Outer, thin.clone())])
        .unwrap()
        .with_default_corners();
    assert_eq!(one.corners().len(), 2);
    let m = Refine::default();
    for k in [5, 10, 14] {
        let r = m
            .mesh_parts(&one, &MeshRequest::points(k), &mut |_| {})
            .unwrap();
        check_conforming(&r.mesh, &one).unwrap();
        // The bent side's chords cut its 16° bend by up to a tenth of their length.
        assert!(
            (r.mesh.area() / 7.0 - 1.0).abs() < 0.01,
            "area {}",
            r.mesh.area()
        );
    }
    let e = m
        .refine_with_area(&one, 100.0, &Density::Uniform, 1000)
        .unwrap_err();
    assert!(e.to_string().contains("no area"), "{e}");
    let two = Region::from_loops(
        "thin_and_triangle",
        vec![
            (LoopRole::Outer, thin),
            (
                LoopRole::Outer,
                vec![v(15.0, 7.0), v(12.0, 3.0), v(3.0, 13.0)],
            ),
        ],
    )
    .unwrap()
    .with_default_corners();
    for k in [40, 50] {
        let r = m
            .mesh_parts(&two, &MeshRequest::points(k), &mut |_| {})
            .unwrap();
        check_conforming(&r.mesh, &two).unwrap();
        assert!(
            (r.mesh.area() / 40.0 - 1.0).abs() < 0.01,
            "area {}",
            r.mesh.area()
        );
    }
}
