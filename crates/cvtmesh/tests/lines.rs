//! Lines embedded in a region (a material interface, a crack, an inclusion's outline) are
//! followed by the edges of every mesh the methods that keep them make: no triangle crosses
//! one, and each side's triangles cover exactly its share of the region.
use cvtmesh::geometry::predicates::orient;
use cvtmesh::geometry::{LoopRole, SizeField, Threshold};
use cvtmesh::{
    check_conforming, line_edges, polish, DVec2, EmbeddedLine, MeshRequest, Method, Region,
};

fn square() -> Region {
    let pts = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)].map(DVec2::from);
    Region::from_loops("square", vec![(LoopRole::Outer, pts.to_vec())]).unwrap()
}

/// A wall-to-wall interface at x = 0.4 that bends at (0.6, 0.5), and a square inclusion.
fn two_materials_and_an_inclusion() -> Region {
    let interface = EmbeddedLine {
        points: [(0.4, 0.0), (0.6, 0.5), (0.4, 1.0)]
            .map(DVec2::from)
            .to_vec(),
        marker: 7,
    };
    let inclusion = EmbeddedLine {
        points: [
            (0.75, 0.4),
            (0.9, 0.4),
            (0.9, 0.6),
            (0.75, 0.6),
            (0.75, 0.4),
        ]
        .map(DVec2::from)
        .to_vec(),
        marker: 8,
    };
    square()
        .with_embedded_lines([interface, inclusion])
        .unwrap()
}

/// The area of the triangles whose centroid satisfies `side`.
fn area_where(mesh: &cvtmesh::Mesh, side: impl Fn(DVec2) -> bool) -> f64 {
    mesh.triangles
        .iter()
        .map(|t| t.map(|v| mesh.points[v as usize]))
        .filter(|p| side((p[0] + p[1] + p[2]) / 3.0))
        .map(|p| 0.5 * orient(p[0], p[1], p[2]))
        .sum()
}

/// The length of the mesh's edges along the region's lines, or where a line has none.
fn length_along_lines(mesh: &cvtmesh::Mesh, region: &Region) -> Result<f64, cvtmesh::MeshError> {
    Ok(line_edges(mesh, region)?
        .iter()
        .map(|&([a, b], _)| mesh.points[a as usize].distance(mesh.points[b as usize]))
        .sum())
}

fn left_of_interface(c: DVec2) -> bool {
    // Left of the polyline (0.4, 0) → (0.6, 0.5) → (0.4, 1).
    let x = if c.y < 0.5 {
        0.4 + 0.4 * c.y
    } else {
        0.6 - 0.4 * (c.y - 0.5)
    };
    c.x < x
}

fn in_inclusion(c: DVec2) -> bool {
    (0.75..0.9).contains(&c.x) && (0.4..0.6).contains(&c.y)
}

fn assert_follows(mesh: &cvtmesh::Mesh, region: &Region, what: &str) {
    check_conforming(mesh, region).unwrap_or_else(|e| panic!("{what}: {e}"));
    let edges = line_edges(mesh, region).unwrap_or_else(|e| panic!("{what}: {e}"));
    let length = |m: i64| -> f64 {
        edges
            .iter()
            .filter(|e| e.1 == m)
            .map(|&([a, b], _)| mesh.points[a as usize].distance(mesh.points[b as usize]))
            .sum()
    };
    let interface = 2.0 * (0.2f64.powi(2) + 0.5f64.powi(2)).sqrt();
    assert!(
        (length(7) - interface).abs() < 1e-12,
        "{what}: {}",
        length(7)
    );
    assert!((length(8) - 0.7).abs() < 1e-12, "{what}: {}", length(8));
    // No triangle straddles a line: each side's triangles tile exactly its area.
    let left = area_where(mesh, left_of_interface);
    let left_exact = 0.5 * (0.4 + 0.6) * 0.5 * 2.0;
    assert!(
        (left - left_exact).abs() < 1e-12,
        "{what}: left {left} of {left_exact}"
    );
    let inside = area_where(mesh, in_inclusion);
    assert!((inside - 0.03).abs() < 1e-12, "{what}: inclusion {inside}");
}

#[test]
fn every_method_that_keeps_lines_follows_them_and_the_others_refuse() {
    let region = two_materials_and_an_inclusion();
    for method in Method::ALL {
        for k in [200, 2000] {
            let result = method.run(&region, &MeshRequest::points(k).seed(3));
            if matches!(method, Method::Meshgen | Method::Vtm) {
                let e = result.map(|_| ()).unwrap_err().to_string();
                assert!(e.contains("embeds 2 lines"), "{method}: {e}");
                continue;
            }
            let r = result.unwrap_or_else(|e| panic!("{method} at {k}: {e}"));
            assert_follows(&r.mesh, &region, &format!("{method} at {k}"));
        }
    }
}

#[test]
fn a_graded_mesh_follows_the_lines_at_the_local_spacing() {
    let region = two_materials_and_an_inclusion();
    // Fine near the left wall, four times coarser at the right.
    let field = SizeField::from_expr("0.01 + 0.03 * x").unwrap();
    let request = MeshRequest::size_field(&field, &region, None).unwrap();
    let r = Method::Ccvt.run(&region, &request).unwrap();
    assert_follows(&r.mesh, &region, "graded");
    // The inclusion's edges (x ≥ 0.75) are longer than the interface's near its ends
    // (x ≈ 0.4), as the field asks.
    let edges = line_edges(&r.mesh, &region).unwrap();
    let mean = |m: i64| {
        let e: Vec<f64> = edges
            .iter()
            .filter(|e| e.1 == m)
            .map(|&([a, b], _)| r.mesh.points[a as usize].distance(r.mesh.points[b as usize]))
            .collect();
        e.iter().sum::<f64>() / e.len() as f64
    };
    let (h7, h8) = (mean(7), mean(8));
    assert!(h8 > 1.2 * h7, "interface {h7}, inclusion {h8}");
}

#[test]
fn a_mesh_refined_toward_a_line_has_its_short_edges_along_it() {
    let region = two_materials_and_an_inclusion();
    // 0.01 along the interface (line 0), 0.08 from 0.3 away.
    let t = Threshold {
        size_min: 0.01,
        size_max: 0.08,
        dist_min: 0.0,
        dist_max: 0.3,
    };
    let field = SizeField::threshold(&region, &["line:0".parse().unwrap()], t).unwrap();
    let request = MeshRequest::size_field(&field, &region, None).unwrap();
    let r = Method::Ccvt.run(&region, &request).unwrap();
    assert_follows(&r.mesh, &region, "toward the interface");
    let along: Vec<f64> = line_edges(&r.mesh, &region)
        .unwrap()
        .iter()
        .filter(|e| e.1 == 7)
        .map(|&([a, b], _)| r.mesh.points[a as usize].distance(r.mesh.points[b as usize]))
        .collect();
    let mean_along = along.iter().sum::<f64>() / along.len() as f64;
    // Edges along the interface follow its 0.01 (within the unit mesh's √2); those by the left
    // wall, 0.4 from it, the 0.08 far away.
    assert!(
        (0.01 / 2f64.sqrt()..0.01 * 2f64.sqrt()).contains(&mean_along),
        "{mean_along}"
    );
    let by_wall: Vec<f64> = r
        .mesh
        .triangles
        .iter()
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .map(|(a, b)| (r.mesh.points[a as usize], r.mesh.points[b as usize]))
        .filter(|(p, q)| p.x.max(q.x) < 0.05)
        .map(|(p, q)| p.distance(q))
        .collect();
    let mean_by_wall = by_wall.iter().sum::<f64>() / by_wall.len() as f64;
    assert!(
        mean_by_wall > 5.0 * mean_along,
        "{mean_by_wall} by the wall, {mean_along} along"
    );
}

#[test]
fn the_polish_slides_a_line_s_vertices_along_it_and_keeps_its_own() {
    // Delaunay refinement's mesh, unpolished: its worst triangles lean on the lines.
    let region = two_materials_and_an_inclusion();
    let r = Method::Refine
        .run(&region, &MeshRequest::points(600).polish(0.0))
        .unwrap();
    let mut mesh = r.mesh.clone();
    let on_line: Vec<u32> = line_edges(&mesh, &region)
        .unwrap()
        .iter()
        .flat_map(|(e, _)| *e)
        .collect();
    let before_deg = mesh.min_angle_deg();
    let p = polish(&mut mesh, &region, 40.0);
    // The lines' own vertices stay; the others move along their lines only.
    let own: Vec<DVec2> = region
        .embedded_lines()
        .iter()
        .flat_map(|l| l.points.iter().copied())
        .collect();
    let mut slid = 0;
    for &v in &on_line {
        let (a, b) = (r.mesh.points[v as usize], mesh.points[v as usize]);
        if own.contains(&a) {
            assert_eq!(a, b);
        } else if a != b {
            slid += 1;
        }
    }
    assert!(slid > 10, "{slid} line vertices slid");
    assert_follows(&mesh, &region, "polished");
    assert!(p.after_deg > 33.0, "{before_deg}° -> {}°", p.after_deg);
}

#[test]
fn a_crack_inside_and_lines_meeting_at_a_point_are_followed() {
    // A crack from the middle of the left wall into the square, and three lines meeting at
    // an inner point.
    let crack = EmbeddedLine {
        points: vec![DVec2::new(0.0, 0.5), DVec2::new(0.3, 0.5)],
        marker: 1,
    };
    let star: Vec<EmbeddedLine> = [(0.6, 0.2), (0.9, 0.8), (0.5, 0.9)]
        .iter()
        .enumerate()
        .map(|(i, &q)| EmbeddedLine {
            points: vec![DVec2::new(0.65, 0.6), DVec2::from(q)],
            marker: 2 + i as i64,
        })
        .collect();
    let region = square()
        .with_embedded_lines(std::iter::once(crack).chain(star))
        .unwrap();
    let r = cvtmesh::mesh(&region, 800).unwrap();
    check_conforming(&r.mesh, &region).unwrap();
    let edges = line_edges(&r.mesh, &region).unwrap();
    let total: f64 = edges
        .iter()
        .map(|&([a, b], _)| r.mesh.points[a as usize].distance(r.mesh.points[b as usize]))
        .sum();
    let exact: f64 = region
        .embedded_lines()
        .iter()
        .map(EmbeddedLine::length)
        .sum();
    assert!((total - exact).abs() < 1e-12, "{total} of {exact}");
    assert!((r.mesh.area() - 1.0).abs() < 1e-12);
}

#[test]
fn the_same_seed_gives_the_same_mesh() {
    let region = two_materials_and_an_inclusion();
    let a = Method::Ccvt
        .run(&region, &MeshRequest::points(500).seed(9))
        .unwrap();
    let b = Method::Ccvt
        .run(&region, &MeshRequest::points(500).seed(9))
        .unwrap();
    assert_eq!(a.mesh, b.mesh);
}

#[test]
fn the_files_keep_the_lines_as_segments_and_physical_curves() {
    let region = two_materials_and_an_inclusion();
    let r = cvtmesh::mesh(&region, 700).unwrap();
    let mut edges: Vec<[u32; 2]> = line_edges(&r.mesh, &region)
        .unwrap()
        .iter()
        .map(|&([a, b], _)| [a.min(b), a.max(b)])
        .collect();
    edges.sort_unstable();
    let dir = std::env::temp_dir().join(format!("cvtmesh-lines-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for name in ["m.msh", "m.node"] {
        let path = dir.join(name);
        cvtmesh::io::write_mesh_on(&r.mesh, &region, &path).unwrap();
        // Read back, the lines are the edges the file keeps inside the mesh (Triangle's in
        // the .poly beside the .node).
        let (back, walls) = cvtmesh::io::read_mesh_with_walls(&path).unwrap();
        assert_eq!(back.points, r.mesh.points, "{name}");
        assert_eq!(walls.inner, edges, "{name}");
    }
    let msh = std::fs::read_to_string(dir.join("m.msh")).unwrap();
    assert!(msh.contains("1 7 \"marker7\"") && msh.contains("1 8 \"marker8\""));
    // Six-node triangles: the lines get their middle nodes too (three-node lines, type 8).
    let q = cvtmesh::Quadratic::new(&r.mesh, Some(&region));
    cvtmesh::io::write_quadratic(&q, &dir.join("q.msh")).unwrap();
    let (_, walls) = cvtmesh::io::read_mesh_with_walls(&dir.join("q.msh")).unwrap();
    assert_eq!(walls.inner, edges);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_t_whose_stem_stops_at_the_bar_is_followed() {
    let bar = EmbeddedLine {
        points: vec![DVec2::new(0.0, 0.5), DVec2::new(1.0, 0.5)],
        marker: 1,
    };
    let stem = EmbeddedLine {
        points: vec![DVec2::new(0.4, 0.5), DVec2::new(0.4, 0.9)],
        marker: 2,
    };
    let region = square().with_embedded_lines([bar, stem]).unwrap();
    for method in [Method::Ccvt, Method::Refine, Method::Distmesh] {
        let r = method.run(&region, &MeshRequest::points(600)).unwrap();
        let edges = line_edges(&r.mesh, &region).unwrap();
        let length: f64 = edges
            .iter()
            .map(|&([a, b], _)| r.mesh.points[a as usize].distance(r.mesh.points[b as usize]))
            .sum();
        assert!((length - 1.4).abs() < 1e-12, "{method}: {length}");
        assert!(
            (area_where(&r.mesh, |c| c.y < 0.5) - 0.5).abs() < 1e-12,
            "{method}"
        );
    }
}

#[test]
fn a_laminate_whose_interfaces_meet_the_walls_at_three_and_seven_tenths_is_meshed_by_algorithm_2() {
    // The walls' pieces end at x = 0.3 and 0.7, where the offsets of Ω_ε's pieces meet 10⁻¹⁷
    // apart (0.7 − 0.3 rounds its unit normal below 1): Algorithm 2 once projected the cells
    // of a whole piece onto the end of its neighbour and lost its generators there.
    let line = |x: f64| EmbeddedLine {
        points: vec![DVec2::new(x, 0.0), DVec2::new(x, 1.0)],
        marker: 5,
    };
    let region = square()
        .with_embedded_lines([line(0.3), line(0.7)])
        .unwrap();
    for method in [Method::Ccvt, Method::Ccvt2] {
        for k in [500, 2000] {
            let r = method
                .run(&region, &MeshRequest::points(k))
                .unwrap_or_else(|e| panic!("{method} at {k}: {e}"));
            let what = format!("{method} at {k}");
            assert!(r.converged, "{what}: {:?}", r.notes);
            assert_eq!(r.mesh.points.len(), k, "{what}");
            check_conforming(&r.mesh, &region).unwrap_or_else(|e| panic!("{what}: {e}"));
            let smallest = r.mesh.min_angle_deg();
            assert!(smallest > 30.0, "{what}: smallest angle {smallest}°");
            let along =
                length_along_lines(&r.mesh, &region).unwrap_or_else(|e| panic!("{what}: {e}"));
            assert!((along - 2.0).abs() < 1e-12, "{what}: lines {along} long");
        }
    }
}

#[test]
fn a_chord_of_a_disc_ending_inside_its_arc_is_followed_whatever_the_corner_angle() {
    // One arc round the whole disc, and a chord ending at 30° and 150°: the arc is split at
    // each end, where it runs smoothly on, and both ends stay corners of the default angle.
    let json = r#"{"loops": [{"segments": [{"kind": "arc", "center": [0, 0], "radius": 1,
        "from_deg": -90, "to_deg": 270}]}],
        "lines": [{"points": [[0.8660254037844387, 0.5], [-0.8660254037844387, 0.5]]}]}"#;
    let region = Region::from_json_str(json, "chord")
        .unwrap()
        .with_default_corners();
    assert_eq!(region.corners().len(), 2);
    let ends = region.embedded_lines()[0].points.clone();
    assert!(ends
        .iter()
        .all(|p| region.corners().iter().any(|c| c.pos == *p)));
    for method in [Method::Ccvt, Method::Refine, Method::Distmesh] {
        let r = method
            .run(&region, &MeshRequest::points(1000))
            .unwrap_or_else(|e| panic!("{method}: {e}"));
        check_conforming(&r.mesh, &region).unwrap_or_else(|e| panic!("{method}: {e}"));
        let along = length_along_lines(&r.mesh, &region).unwrap();
        assert!(
            (along - ends[0].distance(ends[1])).abs() < 1e-12,
            "{method}: {along}"
        );
    }
}

#[test]
fn cracks_ending_on_a_circle_loop_are_followed_and_split_the_disc_at_their_ends() {
    // Two radial cracks of the unit disc from the circle, one at 90°, one at 233.13°, and one
    // from the hole of the annulus to its outer circle: every circle is cut at the cracks'
    // ends, which stay mesh vertices at corners.
    let crack = |from: (f64, f64), to: (f64, f64)| EmbeddedLine {
        points: vec![DVec2::from(from), DVec2::from(to)],
        marker: 5,
    };
    let disc = Region::builtin("circle")
        .unwrap()
        .with_embedded_lines([
            crack((0.0, 1.0), (0.0, 0.3)),
            crack((-0.6, -0.8), (-0.3, -0.4)),
        ])
        .unwrap();
    let ring = Region::builtin("annulus")
        .unwrap()
        .with_embedded_lines([crack((0.0, -0.4), (0.0, -1.0))])
        .unwrap();
    for (region, length) in [(&disc, 0.7 + 0.5), (&ring, 0.6)] {
        for method in [Method::Ccvt, Method::Refine, Method::Distmesh] {
            let r = method
                .run(region, &MeshRequest::points(800).seed(2))
                .unwrap_or_else(|e| panic!("{method}: {e}"));
            check_conforming(&r.mesh, region).unwrap_or_else(|e| panic!("{method}: {e}"));
            let along = length_along_lines(&r.mesh, region).unwrap();
            assert!((along - length).abs() < 1e-12, "{method}: {along}");
            for line in region.embedded_lines() {
                let end = line.points[0];
                let v = r.mesh.points.iter().position(|&p| p == end);
                let marker = v.map(|v| r.mesh.markers[v]);
                assert!(
                    matches!(marker, Some(cvtmesh::VertexMarker::Corner { .. })),
                    "{method}: {end} {marker:?}"
                );
            }
        }
    }
}

#[test]
fn crossing_lines_are_followed_through_their_crossings() {
    // A fracture network: two wall-to-wall interfaces crossing at the centre, and three cracks
    // inside crossing at one point of the vertical interface, as a `.poly`'s crossing segments
    // or Gmsh's fragmented curves give it.
    let line = |a: (f64, f64), b: (f64, f64), marker| EmbeddedLine {
        points: vec![DVec2::from(a), DVec2::from(b)],
        marker,
    };
    let c = DVec2::new(0.5, 0.3);
    let crack = |angle: f64| {
        let d = 0.15 * DVec2::from_angle(angle);
        line((c - d).into(), (c + d).into(), 3)
    };
    let region = square()
        .with_embedded_lines([
            line((0.5, 0.0), (0.5, 1.0), 1),
            line((0.0, 0.5), (1.0, 0.5), 2),
            crack(0.3),
            crack(1.1),
        ])
        .unwrap();
    let length: f64 = region
        .embedded_lines()
        .iter()
        .map(|l| l.length())
        .sum::<f64>();
    assert!((length - 2.6).abs() < 1e-12, "{length}");
    for method in [Method::Ccvt, Method::Refine, Method::Distmesh] {
        let r = method
            .run(&region, &MeshRequest::points(1500))
            .unwrap_or_else(|e| panic!("{method}: {e}"));
        let what = method.to_string();
        check_conforming(&r.mesh, &region).unwrap_or_else(|e| panic!("{what}: {e}"));
        // Both crossings are vertices of the mesh, once each.
        for x in [DVec2::splat(0.5), c] {
            let at = r
                .mesh
                .points
                .iter()
                .filter(|p| p.distance(x) < 1e-12)
                .count();
            assert_eq!(at, 1, "{what}: {at} vertices at {x}");
        }
        let along = length_along_lines(&r.mesh, &region).unwrap_or_else(|e| panic!("{what}: {e}"));
        assert!((along - length).abs() < 1e-9, "{what}: lines {along} long");
        // The interfaces cut the square into its four quarters, each a subdomain.
        let parts = cvtmesh::subdomains(&r.mesh, &region).unwrap();
        let mut areas = [0.0; 5];
        for (t, &s) in r.mesh.triangles.iter().zip(&parts) {
            let p = t.map(|v| r.mesh.points[v as usize]);
            areas[s as usize] += 0.5 * orient(p[0], p[1], p[2]);
        }
        assert_eq!(areas[0], 0.0, "{what}");
        for a in &areas[1..] {
            assert!((a - 0.25).abs() < 1e-12, "{what}: quarter areas {areas:?}");
        }
    }
}

#[test]
fn a_triangle_mesh_s_interface_vertices_slide_along_it_in_the_polish() {
    // Triangle's `-pq30a0.01` mesh of a square with a slanted interface, its segments in the
    // `.poly` beside it: polished as `cvtmesh polish` polishes a file, the interface's
    // vertices slide along it, and no Delaunay test is asked across it (holding them, and
    // testing across the interface, stopped the polish at 31.6°).
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/slant_interface_triangle.node");
    let file = cvtmesh::io::read_mesh_file(&path).unwrap();
    let region = cvtmesh::region_of_mesh(&file.mesh, &file.walls, &path).unwrap();
    assert_eq!(region.embedded_lines().len(), 1);
    let mut mesh = file.mesh.clone();
    let before = mesh.min_angle_deg();
    let held = file.walls.inner_vertices();
    let report = cvtmesh::polish_restored_holding(&mut mesh, &region, 40.0, &held).unwrap();
    assert!(report.kept, "{report}");
    let after = mesh.min_angle_deg();
    assert!(after > 37.0, "{before}° -> {after}°");
    // The interface is where it was: its edges run from wall to wall along it, and the
    // triangles left of it cover exactly its trapezoid.
    let length = length_along_lines(&mesh, &region).unwrap();
    assert!((length - 1.16f64.sqrt()).abs() < 1e-12, "{length}");
    let left = area_where(&mesh, |c| c.x < 0.2 + 0.4 * c.y);
    assert!((left - 0.4).abs() < 1e-12, "{left}");
}

#[test]
fn many_crossing_lines_give_the_same_mesh_every_run() {
    // 25 fractures from a fixed sequence: many crossings, and segments a point off the line
    // crowds, which flips restore; which crossing edge a flip took once followed a hash map's
    // order, different from run to run.
    let mut state: u64 = 1;
    let mut next = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        0.05 + 0.9 * ((state >> 11) as f64 / (1u64 << 53) as f64)
    };
    let lines: Vec<EmbeddedLine> = (0..25)
        .map(|i| EmbeddedLine {
            points: vec![DVec2::new(next(), next()), DVec2::new(next(), next())],
            marker: 1 + i % 3,
        })
        .collect();
    let region = square().with_embedded_lines(lines).unwrap();
    for method in [Method::Refine, Method::Ccvt] {
        let run = || {
            method
                .run(&region, &MeshRequest::points(1500))
                .unwrap_or_else(|e| panic!("{method}: {e}"))
                .mesh
        };
        let first = run();
        line_edges(&first, &region).unwrap_or_else(|e| panic!("{method}: {e}"));
        for _ in 0..3 {
            let again = run();
            assert_eq!(first.points, again.points, "{method}");
            assert_eq!(first.triangles, again.triangles, "{method}");
        }
    }
}

#[test]
fn a_line_crossing_itself_is_followed_through_its_crossing_and_simplified_around_it() {
    // A figure of eight: the crossing is a vertex visited twice, as Triangle splits a .poly's
    // crossing segments.
    let eight = EmbeddedLine {
        points: [(0.2, 0.2), (0.8, 0.8), (0.8, 0.2), (0.2, 0.8), (0.2, 0.2)]
            .map(DVec2::from)
            .to_vec(),
        marker: 4,
    };
    let length = eight.length();
    let region = square().with_embedded_lines([eight]).unwrap();
    assert_eq!(region.embedded_lines()[0].points.len(), 7);
    for method in [Method::Ccvt, Method::Refine] {
        let r = method.run(&region, &MeshRequest::points(800)).unwrap();
        let along = length_along_lines(&r.mesh, &region).unwrap();
        assert!(
            (along - length).abs() < 1e-12,
            "{method}: {along} of {length}"
        );
        // The two loops of the eight and the rest of the square: three parts.
        let parts = cvtmesh::subdomains(&r.mesh, &region).unwrap();
        let mut numbers = parts.clone();
        numbers.sort_unstable();
        numbers.dedup();
        assert_eq!(numbers, [1, 2, 3], "{method}");
    }
    // Simplified, the crossing stays.
    let simplified = region.simplified(0.01).unwrap();
    let kept = &simplified.region.embedded_lines()[0].points;
    assert_eq!(
        kept.iter()
            .filter(|p| p.distance(DVec2::splat(0.5)) < 1e-12)
            .count(),
        2
    );
}

#[test]
fn refinement_keeps_a_fracture_network_s_lines_as_segments_and_its_angles_as_triangle_does() {
    // 60 fractures from a fixed sequence, crossing each other at angles down to a few degrees.
    let mut rng = cvtmesh::geometry::Rng::new(7);
    let (lo, hi) = (DVec2::splat(0.01), DVec2::splat(0.99));
    let lines: Vec<EmbeddedLine> = (0..60)
        .map(|i| {
            let c = DVec2::new(rng.range(0.1, 0.9), rng.range(0.1, 0.9));
            let a = rng.range(0.0, std::f64::consts::PI);
            let d = rng.range(0.05, 0.2) * DVec2::new(a.cos(), a.sin());
            EmbeddedLine {
                points: vec![(c - d).clamp(lo, hi), (c + d).clamp(lo, hi)],
                marker: 1 + i % 3,
            }
        })
        .collect();
    let region = square().with_embedded_lines(lines).unwrap();
    // The smallest angle between two pieces of lines that meet (four at each crossing).
    let mut directions: std::collections::HashMap<(u64, u64), Vec<DVec2>> = Default::default();
    for line in region.embedded_lines() {
        for (a, b) in line.segments() {
            directions
                .entry((a.x.to_bits(), a.y.to_bits()))
                .or_default()
                .push(b - a);
            directions
                .entry((b.x.to_bits(), b.y.to_bits()))
                .or_default()
                .push(a - b);
        }
    }
    let smallest = directions
        .values()
        .flat_map(|d| {
            (0..d.len()).flat_map(move |i| (i + 1..d.len()).map(move |j| d[i].angle_to(d[j])))
        })
        .map(|a| a.abs().to_degrees())
        .fold(180.0, f64::min);
    assert!((1.0..20.0).contains(&smallest), "{smallest}°");
    let r = Method::Refine
        .run(&region, &MeshRequest::points(4000).polish(0.0))
        .unwrap();
    check_conforming(&r.mesh, &region).unwrap();
    let total: f64 = region.embedded_lines().iter().map(|l| l.length()).sum();
    let along = length_along_lines(&r.mesh, &region).unwrap();
    assert!((along - total).abs() < 1e-9 * total, "{along} of {total}");
    // As in Triangle, the 20° bound gives way only near the small angles the lines make: no
    // sliver where lines cross at a small angle or pass close by each other. (Triangle's
    // `-pq` gives this network 8.30°, where three lines cross within 0.03 of each other.)
    let angles: Vec<f64> = r
        .mesh
        .triangles
        .iter()
        .map(|t| {
            let p = t.map(|v| r.mesh.points[v as usize]);
            (0..3)
                .map(|j| {
                    (p[(j + 1) % 3] - p[j])
                        .angle_to(p[(j + 2) % 3] - p[j])
                        .abs()
                })
                .fold(f64::INFINITY, f64::min)
                .to_degrees()
        })
        .collect();
    let min = angles.iter().copied().fold(180.0, f64::min);
    assert!(
        min >= 0.5 * smallest,
        "{min}° against the lines' {smallest}°"
    );
    let below = angles.iter().filter(|&&a| a < 20.0 - 1e-9).count();
    assert!(
        below * 200 < angles.len(),
        "{below} of {} below 20°",
        angles.len()
    );
}

#[test]
fn lines_crossing_at_a_small_angle_leave_refinement_that_angle_and_no_smaller() {
    // Two fractures crossing at 2.86°: the split pieces either side of the crossing meet
    // there, and Triangle's exemption for the triangles between them holds along the whole
    // of each line, whatever the pieces it was split into first (Triangle `-pq`: 2.857°).
    let line = |a: (f64, f64), b: (f64, f64)| EmbeddedLine {
        points: vec![DVec2::from(a), DVec2::from(b)],
        marker: 1,
    };
    let region = square()
        .with_embedded_lines([line((0.1, 0.5), (0.9, 0.52)), line((0.1, 0.52), (0.9, 0.5))])
        .unwrap();
    let crossing = (2.0f64 * 0.01 / 0.4).atan().to_degrees();
    let r = Method::Refine
        .run(&region, &MeshRequest::points(1000).polish(0.0))
        .unwrap();
    check_conforming(&r.mesh, &region).unwrap();
    let min = r.mesh.min_angle_deg();
    // 2.857° here, as Triangle's; 1.93° when each split piece counted as a segment of its own.
    assert!(
        min > 0.99 * crossing,
        "{min}° against the crossing's {crossing}°"
    );
}

#[test]
fn a_json_region_s_named_lines_and_walls_are_physical_curves_of_those_names() {
    // A wall named with its marker, an interface named with none (it gets the next number
    // past the file's markers, 10), and two fractures sharing the name "fault".
    let json = r#"{"loops": [{"segments": [
            {"kind": "polyline", "points": [[0, 0], [1, 0]], "marker": 9, "name": "bottom"},
            {"kind": "polyline", "points": [[1, 0], [1, 1], [0, 1], [0, 0]], "marker": 2}]}],
        "lines": [{"points": [[0.5, 0], [0.5, 1]], "name": "interface"},
                  {"points": [[0.1, 0.2], [0.3, 0.4]], "name": "fault"},
                  {"points": [[0.7, 0.2], [0.9, 0.5]], "name": "fault"},
                  {"points": [[0.7, 0.8], [0.9, 0.9]], "marker": 4}]}"#;
    let region = Region::from_json_str(json, "named").unwrap();
    let names: Vec<(i64, &str)> = region
        .marker_names()
        .iter()
        .map(|(m, n)| (*m, n.as_str()))
        .collect();
    assert_eq!(names, [(9, "bottom"), (10, "interface"), (11, "fault")]);
    let markers: Vec<i64> = region.embedded_lines().iter().map(|l| l.marker).collect();
    assert_eq!(markers, [10, 11, 11, 4]);
    let r = cvtmesh::mesh(&region, 800).unwrap();
    let dir = std::env::temp_dir().join(format!("cvtmesh-named-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("m.msh");
    cvtmesh::io::write_mesh_on(&r.mesh, &region, &path).unwrap();
    let msh = std::fs::read_to_string(&path).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    for group in [
        "1 9 \"bottom\"",
        "1 10 \"interface\"",
        "1 11 \"fault\"",
        "1 4 \"marker4\"",
    ] {
        assert!(
            msh.contains(group),
            "{group} not in\n{}",
            &msh[..msh.len().min(600)]
        );
    }
    // One marker with two names is refused, naming both.
    let clash = json.replace(
        r#""name": "interface""#,
        r#""marker": 9, "name": "interface""#,
    );
    let e = Region::from_json_str(&clash, "clash")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("names marker 9 \"interface\"") && e.contains("\"bottom\""),
        "{e}"
    );
}

#[test]
fn fractures_enclosing_a_triangle_a_ten_millionth_across_are_refined_as_triangle_refines_them() {
    // Three fractures at 0°, 60° and 120° bounding an equilateral triangle of side 10⁻⁷, and
    // a fourth stopping 10⁻⁷ short of the first: triangles of 10⁻¹⁴ in area there, well
    // shaped (Triangle `-pq`: 21.2° with 147 vertices). They were refused as degenerate
    // against the mesh's mean area.
    let s = 1e-7;
    let c = DVec2::new(0.5, 0.5);
    let corners: Vec<DVec2> = (0..3)
        .map(|k| c + s / 3f64.sqrt() * DVec2::from_angle(std::f64::consts::TAU * k as f64 / 3.0))
        .collect();
    let mut lines: Vec<EmbeddedLine> = (0..3)
        .map(|k| {
            let (p, q) = (corners[k], corners[(k + 1) % 3]);
            let (m, d) = (0.5 * (p + q), (q - p).normalize());
            EmbeddedLine {
                points: vec![m - 0.3 * d, m + 0.3 * d],
                marker: 1 + k as i64,
            }
        })
        .collect();
    let (p, q) = (corners[0], corners[1]);
    let (m, normal) = (0.5 * (p + q), (q - p).normalize().perp());
    let side = if normal.dot(corners[2] - m) > 0.0 {
        -normal
    } else {
        normal
    };
    let foot = m + 0.1 * (q - p).normalize();
    lines.push(EmbeddedLine {
        points: vec![foot + s * side, foot + 0.2 * side],
        marker: 4,
    });
    let region = square().with_embedded_lines(lines).unwrap();
    let r = Method::Refine
        .run(&region, &MeshRequest::points(800))
        .unwrap_or_else(|e| panic!("{e}"));
    check_conforming(&r.mesh, &region).unwrap();
    let total: f64 = region.embedded_lines().iter().map(|l| l.length()).sum();
    let along = length_along_lines(&r.mesh, &region).unwrap();
    assert!((along - total).abs() < 1e-12, "{along} of {total}");
    assert!(r.mesh.min_angle_deg() > 20.0, "{}°", r.mesh.min_angle_deg());
    let smallest_area = r
        .mesh
        .triangles
        .iter()
        .map(|t| {
            let p = t.map(|v| r.mesh.points[v as usize]);
            0.5 * orient(p[0], p[1], p[2])
        })
        .fold(f64::INFINITY, f64::min);
    assert!(smallest_area < 1e-13, "{smallest_area}");
}
