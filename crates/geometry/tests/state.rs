//! A region written down by `Region::to_state` and read back by `Region::from_state` is the
//! same region to the bit: loops, pieces, corners, markers and names, embedded points and
//! lines, subdomains, notes.
use cvtmesh_geometry::{DVec2, EmbeddedLine, Region};

/// Everything a region answers that a mesher or a file writer reads, by bits where numbers.
fn fingerprint(r: &Region) -> String {
    let b = |x: f64| x.to_bits();
    let p = |q: DVec2| (q.x.to_bits(), q.y.to_bits());
    format!(
        "{} {:?} {:?} {:?} {:?} {:?} {:?} {:?} {:?} {:?} {:?} {:?} {:?}",
        r.name(),
        b(r.area()),
        r.pieces(),
        r.corners()
            .iter()
            .map(|c| (
                p(c.pos),
                c.loop_index,
                c.piece_in,
                c.piece_out,
                b(c.loop_param)
            ))
            .collect::<Vec<_>>(),
        r.piece_markers(),
        (1..40).map(|m| r.marker_name(m)).collect::<Vec<_>>(),
        r.vertex_markers(),
        r.embedded_points(),
        r.embedded_lines(),
        r.subdomain_points(),
        (0..10).map(|m| r.subdomain_name(m)).collect::<Vec<_>>(),
        r.notes(),
        [0.1, 0.37, 0.9].map(|t| b(r.signed_distance(DVec2::new(t, 0.5 * t)))),
    )
}

fn assert_round_trip(r: &Region, what: &str) {
    let state = r.to_state();
    let back = Region::from_state(&state).unwrap_or_else(|e| panic!("{what}: {e}"));
    assert_eq!(fingerprint(&back), fingerprint(r), "{what}");
    assert_eq!(back.to_state(), state, "{what}");
}

#[test]
fn every_built_in_region_comes_back_to_the_bit() {
    for name in Region::builtin_names() {
        let r = Region::builtin(name).unwrap();
        assert_round_trip(&r, name);
        assert_round_trip(&r.clone().with_corner_angle(30.0), name);
        assert_round_trip(&r.with_default_corners(), name);
    }
}

#[test]
fn a_poly_s_markers_names_points_lines_and_subdomains_come_back() {
    // Two walls numbered 3 and 5, a marked vertex, a segment inside (a crack) marked 7, an
    // embedded point marked 9, two regional attributes.
    let dir = std::env::temp_dir().join(format!("geometry-state-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let poly = dir.join("marked.poly");
    std::fs::write(
        &poly,
        "7 2 0 1\n1 0 0 0\n2 2 0 0\n3 2 1 0\n4 0 1 4\n5 0.5 0.2 0\n6 0.5 0.8 0\n7 1.5 0.5 9\n\
         5 1\n1 1 2 3\n2 2 3 5\n3 3 4 3\n4 4 1 3\n5 5 6 7\n0\n2\n1 0.2 0.5 1 0\n2 1.8 0.5 2 0\n",
    )
    .unwrap();
    let r = Region::from_file(&poly).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(r.piece_markers().is_some() && !r.embedded_lines().is_empty());
    assert_round_trip(&r, "marked.poly");
    // A JSON region with named walls and lines, and a circle a crack ends on.
    let json = r#"{"loops": [{"segments": [{"kind": "circle", "center": [0, 0], "radius": 1,
        "marker": 2, "name": "rim"}]}],
        "lines": [{"points": [[0, 1], [0, 0.2]], "marker": 6, "name": "crack"}]}"#;
    let r = Region::from_json_str(json, "disc").unwrap();
    assert_eq!(r.marker_name(6), Some("crack"));
    assert_round_trip(&r, "disc");
    let more = r
        .with_embedded_lines([EmbeddedLine {
            points: vec![DVec2::new(-0.6, -0.8), DVec2::new(-0.3, -0.3)],
            marker: 0,
        }])
        .unwrap();
    assert_round_trip(&more, "disc with two cracks");
}

#[test]
fn text_that_is_no_saved_region_is_refused_naming_it() {
    for text in ["", "{}", "[1, 2]", "not json"] {
        let e = Region::from_state(text).unwrap_err().to_string();
        assert!(e.contains("not a region's saved state"), "{text}: {e}");
    }
    let state = Region::builtin("lake").unwrap().to_state();
    let other = state.replacen("\"version\":1", "\"version\":99", 1);
    assert_ne!(other, state);
    let e = Region::from_state(&other).unwrap_err().to_string();
    assert!(e.contains("layout 99"), "{e}");
}
