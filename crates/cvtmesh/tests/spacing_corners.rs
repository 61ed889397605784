//! Regions whose boundary is finer than the mesh: an airfoil in a box and digitized coastlines
//! at spacings far above their vertex spacing. `Mesher::mesh_parts` adds the corners the
//! spacing needs (`Region::with_spacing_corners`) and hands back a mesh whose markers speak of
//! the region as given.
use cvtmesh::geometry::{LoopRole, Rng};
use cvtmesh::{check_conforming, DVec2, Mesh, MeshRequest, Method, Region, VertexMarker};
use std::f64::consts::TAU;

/// NACA 0012 (chord 1, 201 points, cosine spacing, a sharp trailing edge) as a hole in the box
/// [-2, 3] × [-2, 2], with the default corners: the box's four and the trailing edge.
fn airfoil_in_a_box() -> Region {
    let m = 100;
    let half: Vec<DVec2> = (0..=m)
        .map(|i| {
            let x = 0.5 * (1.0 - (std::f64::consts::PI * i as f64 / m as f64).cos());
            let t = 0.6
                * (0.2969 * x.sqrt() - 0.1260 * x - 0.3516 * x * x + 0.2843 * x.powi(3)
                    - 0.1036 * x.powi(4));
            DVec2::new(x, t)
        })
        .collect();
    let mut foil: Vec<DVec2> = half.iter().rev().copied().collect();
    foil.extend(half[1..m].iter().map(|p| DVec2::new(p.x, -p.y)));
    let bx = [(-2.0, -2.0), (3.0, -2.0), (3.0, 2.0), (-2.0, 2.0)].map(|(x, y)| DVec2::new(x, y));
    Region::from_loops(
        "naca0012",
        vec![(LoopRole::Outer, bx.to_vec()), (LoopRole::Hole, foil)],
    )
    .unwrap()
    .with_default_corners()
}

/// A star-shaped coastline of `n` vertices, radius 10 ± 30 %, with fractal noise whose
/// harmonic k has amplitude k^`exponent` (-1.5 is a natural coastline's roughness, -0.9 is
/// rough at every scale).
fn coastline(n: usize, exponent: f64) -> Region {
    let kmax = n / 2 - 1;
    let mut rng = Rng::new(7);
    let phases: Vec<f64> = (0..kmax).map(|_| rng.range(0.0, TAU)).collect();
    let noise: Vec<f64> = (0..n)
        .map(|i| {
            let t = TAU * i as f64 / n as f64;
            (1..=kmax)
                .map(|k| (k as f64).powf(exponent) * (k as f64 * t + phases[k - 1]).sin())
                .sum()
        })
        .collect();
    let top = noise.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let pts = noise
        .iter()
        .enumerate()
        .map(|(i, v)| {
            let t = TAU * i as f64 / n as f64;
            10.0 * (1.0 + 0.3 * v / top) * DVec2::new(t.cos(), t.sin())
        })
        .collect();
    Region::from_loops("coast", vec![(LoopRole::Outer, pts)])
        .unwrap()
        .with_default_corners()
}

/// The mesh conforms to `region` as given, and its markers speak of it: corner markers name
/// its corners, boundary markers a piece of the right loop that the vertex lies on.
fn assert_speaks_of(mesh: &Mesh, region: &Region) {
    check_conforming(mesh, region).unwrap();
    let mut corners = vec![0; region.corners().len()];
    for (p, m) in mesh.points.iter().zip(&mesh.markers) {
        match *m {
            VertexMarker::Interior => {}
            VertexMarker::Corner { corner, .. } => {
                assert_eq!(region.corners()[corner].pos, *p);
                corners[corner] += 1;
            }
            VertexMarker::Boundary {
                loop_index, piece, ..
            } => {
                assert_eq!(region.piece_loop(piece), loop_index);
                let (foot, _) = region.pieces()[piece].closest_point(*p);
                assert!(foot.distance(*p) < 1e-9 * region.diameter(), "{p}");
            }
        }
    }
    assert!(corners.iter().all(|&n| n == 1), "{corners:?}");
}

fn added_corners(notes: &[String]) -> bool {
    notes.iter().any(|n| n.starts_with("corners: "))
}

#[test]
fn an_airfoil_meshes_at_spacings_near_its_thickness_by_every_method() {
    let foil = airfoil_in_a_box();
    assert_eq!(foil.corners().len(), 5);
    // At K = 1000 the spacing (0.15) exceeds the airfoil's thickness (0.12): without corners
    // along its trailing half and on its nose, the default method was refused.
    for m in Method::ALL {
        let request = MeshRequest::points(1000).max_iter(2000);
        let r = m
            .run(&foil, &request)
            .unwrap_or_else(|e| panic!("{m}: {e}"));
        assert_speaks_of(&r.mesh, &foil);
        assert!(added_corners(&r.notes), "{m}: {:?}", r.notes);
    }
    let r = Method::Ccvt.run(&foil, &MeshRequest::points(3000)).unwrap();
    assert_speaks_of(&r.mesh, &foil);
    assert!(r.mesh.min_angle_deg() > 5.0, "{}", r.mesh.min_angle_deg());
}

#[test]
fn a_natural_coastline_meshes_at_every_spacing() {
    let coast = coastline(5000, -1.5);
    assert!(coast.corners().len() < 200, "{}", coast.corners().len());
    for k in [300, 3000] {
        let r = Method::Ccvt
            .run(&coast, &MeshRequest::points(k))
            .unwrap_or_else(|e| panic!("K = {k}: {e}"));
        assert_speaks_of(&r.mesh, &coast);
        assert_eq!(r.mesh.num_vertices(), k);
    }
}

#[test]
fn corners_far_denser_than_the_spacing_each_get_a_vertex() {
    // Rough at every scale: most vertices turn by more than 30°, about 1300 corners on a
    // boundary that K = 3000 spaces at only about 350 vertices.
    let coast = coastline(2000, -0.9);
    assert!(coast.corners().len() > 1000, "{}", coast.corners().len());
    let r = Method::Ccvt
        .run(&coast, &MeshRequest::points(3000))
        .unwrap();
    assert_speaks_of(&r.mesh, &coast);
}

#[test]
fn regions_without_polyline_pieces_are_meshed_as_they_are() {
    for name in ["circle", "annulus", "superellipse"] {
        let region = Region::builtin(name).unwrap();
        let r = Method::Ccvt
            .run(&region, &MeshRequest::points(300))
            .unwrap();
        assert!(!added_corners(&r.notes), "{name}: {:?}", r.notes);
    }
}

#[test]
fn a_small_polygonal_hole_is_followed_across_its_start() {
    // A 24-gon of radius 0.2 in the square [-1, 1]²: no vertex turns by 30°, so the hole is
    // one closed chain starting at (0.2, 0). At K = 60 and 100 chords span 60° of it, and the
    // one across its start, which no stretch of the chain examined, left the region.
    let mut text = String::from("-1 -1\n1 -1\n1 1\n-1 1\n\n");
    for i in 0..24 {
        let p = 0.2 * DVec2::from_angle(TAU * i as f64 / 24.0);
        text += &format!("{} {}\n", p.x, p.y);
    }
    let region = cvtmesh::geometry::formats::loops_from_str(&text, "ring", "ring")
        .unwrap()
        .with_default_corners();
    assert_eq!(region.corners().len(), 4);
    for k in [60, 100] {
        let r = Method::Ccvt
            .run(&region, &MeshRequest::points(k))
            .unwrap_or_else(|e| panic!("K = {k}: {e}"));
        assert_speaks_of(&r.mesh, &region);
        assert!(added_corners(&r.notes), "{:?}", r.notes);
    }
}

#[test]
fn holes_too_many_for_k_say_how_many_vertices_their_bends_need() {
    // 25 holes of radius 0.02 (16-gons) in the unit square: at K = 120 (spacing 0.1) each
    // needs about eight corners to be followed, 204 boundary vertices in all.
    let mut text = String::from("0 0\n1 0\n1 1\n0 1\n");
    for i in 0..5 {
        for j in 0..5 {
            text += "\n";
            let c = DVec2::new(0.1 + 0.2 * i as f64, 0.1 + 0.2 * j as f64);
            for k in 0..16 {
                let p = c + 0.02 * DVec2::from_angle(TAU * k as f64 / 16.0);
                text += &format!("{} {}\n", p.x, p.y);
            }
        }
    }
    let region = cvtmesh::geometry::formats::loops_from_str(&text, "holes", "holes")
        .unwrap()
        .with_default_corners();
    let e = Method::Ccvt
        .run(&region, &MeshRequest::points(120))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("bends and gaps need") && e.contains("--simplify auto"),
        "{e}"
    );
    let r = Method::Ccvt
        .run(&region, &MeshRequest::points(400))
        .unwrap();
    assert_speaks_of(&r.mesh, &region);
    // Simplified to a quarter of the spacing, each hole keeps three of its 16 vertices, and
    // K = 120 has room for them.
    let request = MeshRequest::points(120);
    let s = region
        .simplified(request.simplify_tolerance(&region))
        .unwrap();
    assert_eq!(s.vertices, (4 + 25 * 16, 4 + 25 * 3));
    let simple = s.region.with_default_corners();
    let r = Method::Ccvt.run(&simple, &request).unwrap();
    assert_speaks_of(&r.mesh, &simple);
}

#[test]
fn a_rough_coastline_simplified_to_the_spacing_meshes_far_below_its_corner_count() {
    // About 1300 corners: K = 300 is refused, and the refusal names the way out.
    let coast = coastline(2000, -0.9);
    let request = MeshRequest::points(300).max_iter(2000);
    let refused = Method::Ccvt.run(&coast, &request).unwrap_err().to_string();
    assert!(refused.contains("--simplify auto"), "{refused}");
    let tol = request.simplify_tolerance(&coast);
    let s = coast.simplified(tol).unwrap();
    assert!(s.deviation <= tol, "{s:?}");
    assert!(
        s.vertices.0 == 2000 && s.vertices.1 < 200,
        "{:?}",
        s.vertices
    );
    assert!(s.to_string().contains("stays within"), "{s}");
    let simple = s.region.with_default_corners();
    // The simplified region differs from the given one only in a band as wide as the
    // deviation along the boundary.
    assert!((simple.area() - coast.area()).abs() <= s.deviation * coast.perimeter());
    for m in Method::ALL {
        let r = m
            .run(&simple, &request)
            .unwrap_or_else(|e| panic!("{m}: {e}"));
        assert_speaks_of(&r.mesh, &simple);
        // Refinement inserts vertices until its triangles are small enough: K is approximate.
        let k = r.mesh.num_vertices();
        assert!(
            k == 300 || (m.name() == "refine" && k.abs_diff(300) < 60),
            "{m}: {k}"
        );
        for p in &r.mesh.points {
            let d = coast.signed_distance(*p);
            assert!(d <= s.deviation * (1.0 + 1e-9), "{m}: {p} is {d} outside");
        }
    }
}

#[test]
fn refinement_keeps_its_boundary_edges_on_a_coastlines_dents() {
    // Halving a chord that hugs a digitized shore can leave a half over a dent deeper than a
    // boundary edge may stray; such halves are split at the dent.
    for (n, exponent) in [(2000, -1.2), (4000, -1.5)] {
        let coast = coastline(n, exponent);
        let r = Method::Refine
            .run(&coast, &MeshRequest::points(1000))
            .unwrap_or_else(|e| panic!("{n} vertices, exponent {exponent}: {e}"));
        assert_speaks_of(&r.mesh, &coast);
    }
}
