//! Regions of several parts: nesting decides holes and islands where a format cannot say,
//! contradictions are refused naming the loops, and parts map back to the whole region.
use cvtmesh_geometry::formats::{geojson_from_str, loops_from_str, poly_from_str};
use cvtmesh_geometry::{DVec2, LoopRole, Region};

fn square(x0: f64, y0: f64, s: f64) -> Vec<DVec2> {
    [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
        .map(|(a, b)| DVec2::new(x0 + s * a, y0 + s * b))
        .to_vec()
}

fn text(loops: &[Vec<DVec2>]) -> String {
    loops
        .iter()
        .map(|l| {
            l.iter()
                .map(|p| format!("{} {}\n", p.x, p.y))
                .collect::<String>()
        })
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn nesting_makes_holes_of_loops_in_outer_loops_and_parts_of_loops_in_holes() {
    // Listed inside out: an island in a hole in a square, and a second square beside it.
    let loops = [
        square(0.4, 0.4, 0.2),
        square(0.2, 0.2, 0.6),
        square(0.0, 0.0, 1.0),
        square(2.0, 0.0, 1.0),
    ];
    let r = loops_from_str(&text(&loops), "nest", "nest").unwrap();
    assert_eq!(r.num_parts(), 3);
    let roles: Vec<LoopRole> = r.loops().iter().map(|l| l.role).collect();
    // Part by part, each outer loop (in the order given) followed by its holes.
    assert_eq!(
        roles,
        [
            LoopRole::Outer,
            LoopRole::Outer,
            LoopRole::Hole,
            LoopRole::Outer
        ]
    );
    assert!((r.area() - (0.04 + (1.0 - 0.36) + 1.0)).abs() < 1e-12);
    assert!(r.contains(DVec2::new(0.5, 0.5)));
    assert!(!r.contains(DVec2::new(0.3, 0.3)));
    assert!(r.contains(DVec2::new(0.1, 0.1)));
    let parts = r.parts();
    assert_eq!(parts.len(), 3);
    assert_eq!(parts[1].loops, [1, 2]);
    let total: f64 = parts.iter().map(|p| p.region.area()).sum();
    assert!((total - r.area()).abs() < 1e-12);
    for p in &parts {
        assert_eq!(p.region.num_parts(), 1);
        assert_eq!(p.region.loops()[0].role, LoopRole::Outer);
        for (i, c) in p.region.corners().iter().enumerate() {
            assert_eq!(r.corners()[p.corners[i]].pos, c.pos);
            assert_eq!(r.corners()[p.corners[i]].loop_index, p.loops[c.loop_index]);
        }
        for (i, piece) in p.region.pieces().iter().enumerate() {
            assert_eq!(piece, &r.pieces()[p.pieces[i]]);
        }
    }
}

#[test]
fn roles_that_contradict_nesting_are_refused_naming_the_loops() {
    let outer = |p: Vec<DVec2>| (LoopRole::Outer, p);
    let hole = |p: Vec<DVec2>| (LoopRole::Hole, p);
    let e = Region::from_loops(
        "r",
        vec![outer(square(0.0, 0.0, 1.0)), hole(square(2.0, 0.0, 1.0))],
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("loop 1 (hole) is not inside the outer loop"),
        "{e}"
    );
    let e = Region::from_loops(
        "r",
        vec![outer(square(0.0, 0.0, 1.0)), outer(square(0.25, 0.25, 0.5))],
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("loop 1 (outer) lies inside loop 0 (outer)"),
        "{e}"
    );
    let e = Region::from_loops(
        "r",
        vec![
            outer(square(0.0, 0.0, 1.0)),
            hole(square(0.2, 0.2, 0.6)),
            hole(square(0.4, 0.4, 0.2)),
        ],
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("loop 2 (hole) lies inside loop 1 (hole)"), "{e}");
    // GeoJSON says which ring is a hole: a hole ring outside its polygon is refused.
    let g = r#"{"type":"Polygon","coordinates":[[[0,0],[1,0],[1,1],[0,1],[0,0]],[[2,0],[3,0],[3,1],[2,1],[2,0]]]}"#;
    let e = geojson_from_str(g, "g.geojson", "g")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("g.geojson") && e.contains("loop 1 (hole)"),
        "{e}"
    );
}

#[test]
fn a_poly_island_is_a_part_unless_a_hole_point_eats_it() {
    // A square with a square hole (hole point inside) and an island in the hole.
    let head = "12 2 0 0\n1 0 0\n2 4 0\n3 4 4\n4 0 4\n5 1 1\n6 3 1\n7 3 3\n8 1 3\n\
                9 1.5 1.5\n10 2.5 1.5\n11 2.5 2.5\n12 1.5 2.5\n\
                12 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n5 5 6\n6 6 7\n7 7 8\n8 8 5\n\
                9 9 10\n10 10 11\n11 11 12\n12 12 9\n";
    let r = poly_from_str(&format!("{head}1\n1 1.2 1.2\n"), "i.poly", "i").unwrap();
    assert_eq!(r.num_parts(), 2);
    assert!((r.area() - (16.0 - 4.0 + 1.0)).abs() < 1e-12);
    // A hole point in the island too has Triangle eat it: the island's segments are in no
    // triangle, which a note says.
    let r = poly_from_str(&format!("{head}2\n1 1.2 1.2\n2 2 2\n"), "i.poly", "i").unwrap();
    assert_eq!((r.num_parts(), r.area()), (1, 12.0));
    assert!(
        r.notes().iter().any(|n| n.contains("4 segments")),
        "{:?}",
        r.notes()
    );
    // Without a hole point the hole's loop and the island's are lines inside the square, kept
    // as edges (an inclusion within an inclusion), as Triangle keeps them.
    let r = poly_from_str(&format!("{head}0\n"), "i.poly", "i").unwrap();
    assert_eq!((r.num_parts(), r.area()), (1, 16.0));
    assert_eq!(r.embedded_lines().len(), 2);
    assert!(r.embedded_lines().iter().all(|l| l.is_closed()));
}
