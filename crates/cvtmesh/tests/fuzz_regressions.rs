//! Inputs the fuzz targets in `fuzz/` found, each named after what it caught.
use cvtmesh::geometry::{LoopRole, Threshold, Toward};
use cvtmesh::{check_conforming, DVec2, MeshRequest, Method, Region, SizeField};

/// `mesh_loops`: two needles joined at the top, 1e-4 wide at their tips, with a 19° bend that
/// the default corners drop; CCVT at K = 20 returned a triangle outside the region. Since the
/// needles' sides, which face each other across a gap, get corners one spacing apart, it is
/// meshed; the thin feature is still reported.
#[test]
fn a_needle_far_thinner_than_the_spacing_is_never_meshed_outside() {
    let pts = [(11, 15), (14, 15), (11, 0), (12, 6), (11, 12), (6, 1)]
        .map(|(x, y)| DVec2::new(x as f64, y as f64))
        .to_vec();
    let raw = Region::from_loops("needles", vec![(LoopRole::Outer, pts)]).unwrap();
    let region = raw.with_default_corners();
    assert_eq!(region.corners().len(), 5);
    let request = MeshRequest::points(20).tol(1e-2).max_iter(200);
    // The needles' tips are sharp corners, which no K resolves; the place reported is the
    // narrowest one a larger K does resolve, 0.2 wide between them.
    let thin = cvtmesh::thin_feature(&region, &request).expect("a thin feature");
    assert!(thin.spacing / thin.width > 5.0, "{thin}");
    assert_eq!(thin.corner, None, "{thin}");
    let r = Method::Ccvt.run(&region, &request).unwrap();
    check_conforming(&r.mesh, &raw).unwrap();
    // Every method gives a conforming mesh or an error, never a mesh outside the region.
    for m in Method::ALL {
        if let Ok(r) = m.run(&region, &request) {
            check_conforming(&r.mesh, &raw).unwrap_or_else(|e| panic!("{m}: {e}"));
        }
    }
}

/// `mesh_graded`: a 1 × 12 sliver and a small triangle, the field toward a side of the small
/// one growing 27×, K = 16 by Algorithm 2 (Lloyd): the sliver's part gets only its three
/// corners, every cell of its CVTs of Ω_ε reaches ∂Ω_ε, and Algorithm 2's ε grew without a
/// fixed point to 5 230 spacings, Ω_ε reaching where the field is fine, each ε-phase slower
/// than the last (over ten minutes in all without an iteration cap). Its steps (0.90, then
/// 1.94 spacings) stop shrinking, so ε is held after one step, and the part's note says so. The
/// small triangle's cells all reach ∂Ω_ε too, but its ε settles (at 1.59 spacings).
#[test]
fn a_part_that_gets_only_its_corners_holds_algorithm_2s_epsilon_after_one_step() {
    let at = |pts: &[(f64, f64)]| pts.iter().map(|&(x, y)| DVec2::new(x, y)).collect();
    let region = Region::from_loops(
        "fuzz",
        vec![
            (LoopRole::Outer, at(&[(0.0, 0.0), (0.0, 12.0), (1.0, 0.0)])),
            (LoopRole::Outer, at(&[(10.0, 2.0), (10.0, 1.0), (8.0, 4.0)])),
        ],
    )
    .unwrap()
    .with_default_corners();
    let threshold = Threshold {
        size_min: 1.0,
        size_max: 27.0,
        dist_min: 1.25,
        dist_max: 2.0,
    };
    let field = SizeField::threshold(&region, &[Toward::Piece(3)], threshold).unwrap();
    let request = MeshRequest::size_field(&field, &region, Some(16))
        .unwrap()
        .tol(1e-2)
        .max_iter(8);
    let r = Method::Ccvt2.run(&region, &request).unwrap();
    check_conforming(&r.mesh, &region).unwrap();
    let sliver = r
        .notes
        .iter()
        .find(|n| n.starts_with("part 0: epsilon = "))
        .expect("the sliver's epsilon note");
    assert!(sliver.contains("held where every cell reaches"), "{sliver}");
    let rel: f64 = sliver
        .split_once('(')
        .and_then(|(_, r)| r.split_whitespace().next()?.parse().ok())
        .expect("ε in spacings");
    assert!(rel < 3.0, "{sliver}");
    let triangle = r
        .notes
        .iter()
        .find(|n| n.starts_with("part 1: epsilon = "))
        .expect("the triangle's epsilon note");
    assert!(!triangle.contains("not settled"), "{triangle}");
}

/// `poly`: a segment count of 177 777 777 777 777 776 in the header of a `.poly`'s segments
/// was an allocation of that many entries before the first one was read, an abort.
#[test]
fn a_poly_segment_count_beyond_any_file_is_an_error_not_an_abort() {
    let text = "6 2 0 1\n1 0 0 1\n2 1 0 1\n3 1 1 1\n4 0 1 1\n5 0.5 0 0\n6 0.5 1 0\n\
                177777777777777776 1\n1 1 2 1\n2 2 3 1\n0\n";
    let e = cvtmesh::geometry::formats::poly_from_str(text, "t.poly", "t").unwrap_err();
    assert!(e.to_string().contains("t.poly"), "{e}");
}

/// `poly`: a vertex on no segment at (6, 5·10¹⁰⁴), far above a polygon, was kept as a point
/// inside: every piece was as near as rounding could tell, and the side of the bottom edge,
/// which won, said inside.
#[test]
fn a_point_far_outside_is_outside_however_near_rounding_makes_every_piece() {
    let pts = [(0.0, 0.0), (2.5, 0.0), (40.0, 0.0), (4.0, 9.0), (0.0, 1.0)]
        .map(DVec2::from)
        .to_vec();
    let r = Region::from_loops("c", vec![(LoopRole::Outer, pts)]).unwrap();
    for p in [
        DVec2::new(6.0, 5e104),
        DVec2::new(-3e200, 1.0),
        DVec2::new(1e20, -1e20),
    ] {
        assert!(r.signed_distance(p) > 0.0 && !r.contains(p), "{p}");
    }
    assert!(r.contains(DVec2::new(3.0, 0.5)));
}

/// `mesh_lines`: a line running along a wall of a thin triangle, from a corner to a point the
/// line makes a corner. Delaunay refinement took the line's piece as a segment of its own on
/// top of the wall's, and never finished (over two minutes at K = 39); a line's piece along
/// a wall is the wall's segment.
#[test]
fn a_line_along_a_wall_is_the_wall_s_segment_for_delaunay_refinement() {
    let pts = [(12.0, 1.0), (0.0, 0.0), (15.0, 0.0)]
        .map(DVec2::from)
        .to_vec();
    let region = Region::from_loops("sliver", vec![(LoopRole::Outer, pts)])
        .unwrap()
        .with_default_corners()
        .with_embedded_lines([cvtmesh::EmbeddedLine {
            points: vec![DVec2::new(4.25, 0.0), DVec2::new(0.0, 0.0)],
            marker: 1,
        }])
        .unwrap();
    let request = MeshRequest::points(39).tol(1e-2).max_iter(8);
    for m in Method::ALL {
        if let Ok(r) = m.run(&region, &request) {
            check_conforming(&r.mesh, &region).unwrap_or_else(|e| panic!("{m}: {e}"));
            cvtmesh::line_edges(&r.mesh, &region).unwrap_or_else(|e| panic!("{m}: {e}"));
        }
    }
    let r = Method::Refine.run(&region, &request).unwrap();
    assert!(r.mesh.min_angle_deg() > 1.0);
}
