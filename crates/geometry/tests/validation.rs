//! Invalid regions and region files give clear errors (never panics); valid oddities are
//! normalised.
use cvtmesh_geometry::{DVec2, GeometryError, LoopRole, Piece, Region};

fn v(x: f64, y: f64) -> DVec2 {
    DVec2::new(x, y)
}

/// Closed polyline loop of lines.
fn poly(pts: &[(f64, f64)]) -> Vec<Piece> {
    (0..pts.len())
        .map(|i| {
            let (a, b) = (pts[i], pts[(i + 1) % pts.len()]);
            Piece::Line {
                a: v(a.0, a.1),
                b: v(b.0, b.1),
            }
        })
        .collect()
}

fn square(lo: f64, hi: f64) -> Vec<Piece> {
    poly(&[(lo, lo), (hi, lo), (hi, hi), (lo, hi)])
}

fn invalid(r: Result<Region, GeometryError>) -> String {
    match r {
        Err(e @ GeometryError::Invalid { .. }) => e.to_string(),
        Err(e) => panic!("expected Invalid, got {e}"),
        Ok(_) => panic!("expected an error"),
    }
}

#[test]
fn figure_eight_reports_the_crossing_point() {
    let e = invalid(Region::new(
        "bow",
        vec![(
            LoopRole::Outer,
            poly(&[(0.0, 0.0), (1.0, 1.0), (1.0, 0.0), (0.0, 1.0)]),
        )],
        None,
    ));
    assert!(
        e.contains("bow") && e.contains("crosses itself") && e.contains("(0.5, 0.5)"),
        "{e}"
    );
}

#[test]
fn open_loop_is_rejected_with_the_gap() {
    let mut p = square(0.0, 1.0);
    p.pop();
    let e = invalid(Region::new("open", vec![(LoopRole::Outer, p)], None));
    assert!(
        e.contains("not closed") && e.contains("(0, 1)") && e.contains("(0, 0)"),
        "{e}"
    );
    // A gap of 1e-12 is closed silently.
    let mut p = square(0.0, 1.0);
    if let Piece::Line { b, .. } = &mut p[3] {
        b.x += 1e-12;
    }
    let r = Region::new("snap", vec![(LoopRole::Outer, p)], None).unwrap();
    assert!((r.area() - 1.0).abs() < 1e-11);
}

#[test]
fn holes_outside_crossing_nested_or_touching_are_rejected() {
    let outer = || (LoopRole::Outer, square(0.0, 4.0));
    let e = invalid(Region::new(
        "r",
        vec![outer(), (LoopRole::Hole, square(5.0, 6.0))],
        None,
    ));
    assert!(
        e.contains("loop 1 (hole) is not inside the outer loop"),
        "{e}"
    );
    let e = invalid(Region::new(
        "r",
        vec![outer(), (LoopRole::Hole, square(3.0, 5.0))],
        None,
    ));
    assert!(
        e.contains("cross") && e.contains("loop 0 (outer)") && e.contains("loop 1 (hole)"),
        "{e}"
    );
    let e = invalid(Region::new(
        "r",
        vec![
            outer(),
            (LoopRole::Hole, square(1.0, 3.0)),
            (LoopRole::Hole, square(1.5, 2.5)),
        ],
        None,
    ));
    assert!(e.contains("lies inside"), "{e}");
    // A hole touching the outer boundary at a vertex.
    let e = invalid(Region::new(
        "r",
        vec![
            outer(),
            (LoopRole::Hole, poly(&[(0.0, 2.0), (1.0, 1.0), (1.0, 3.0)])),
        ],
        None,
    ));
    assert!(e.contains("touch") || e.contains("cross"), "{e}");
    // A circular hole crossing the outer square.
    let e = invalid(Region::new(
        "r",
        vec![
            outer(),
            (
                LoopRole::Hole,
                vec![Piece::Circle {
                    center: v(3.5, 2.0),
                    radius: 1.0,
                    ccw: false,
                }],
            ),
        ],
        None,
    ));
    assert!(e.contains("cross"), "{e}");
}

#[test]
fn bad_numbers_and_degenerate_pieces_are_rejected() {
    let mut p = square(0.0, 1.0);
    p[1] = Piece::Line {
        a: v(1.0, 0.0),
        b: v(f64::NAN, 1.0),
    };
    let e = invalid(Region::new("nan", vec![(LoopRole::Outer, p)], None));
    assert!(e.contains("non-finite"), "{e}");
    let e = invalid(Region::new(
        "dup",
        vec![(
            LoopRole::Outer,
            poly(&[(0.0, 0.0), (1.0, 0.0), (1.0, 0.0), (1.0, 1.0)]),
        )],
        None,
    ));
    assert!(
        e.contains("duplicate consecutive vertices at (1, 0)"),
        "{e}"
    );
    let e = invalid(Region::new(
        "flat",
        vec![(LoopRole::Outer, poly(&[(0.0, 0.0), (1.0, 0.0), (2.0, 0.0)]))],
        None,
    ));
    assert!(e.contains("folds back") || e.contains("no area"), "{e}");
    let e = invalid(Region::new(
        "none",
        vec![(LoopRole::Hole, square(0.0, 1.0))],
        None,
    ));
    assert!(e.contains("no outer loop"), "{e}");
    // Two outer loops side by side are two parts; an outer loop inside another, with no hole
    // between them, is refused naming both loops.
    let two = Region::new(
        "two",
        vec![
            (LoopRole::Outer, square(0.0, 1.0)),
            (LoopRole::Outer, square(2.0, 3.0)),
        ],
        None,
    )
    .unwrap();
    assert_eq!((two.num_parts(), two.area()), (2, 2.0));
    let e = invalid(Region::new(
        "nested",
        vec![
            (LoopRole::Outer, square(0.0, 4.0)),
            (LoopRole::Outer, square(1.0, 2.0)),
        ],
        None,
    ));
    assert!(
        e.contains("loop 1 (outer) lies inside loop 0 (outer)") && e.contains("one of its holes"),
        "{e}"
    );
    let mut p = square(0.0, 1.0);
    p.push(Piece::Circle {
        center: v(0.5, 0.5),
        radius: 0.1,
        ccw: true,
    });
    let e = invalid(Region::new("mix", vec![(LoopRole::Outer, p)], None));
    assert!(e.contains("on its own"), "{e}");
    let e = invalid(Region::new(
        "sq",
        vec![(LoopRole::Outer, square(0.0, 1.0))],
        Some(vec![v(0.5, 0.0)]),
    ));
    assert!(e.contains("corner (0.5, 0) is not at a junction"), "{e}");
    let e = invalid(Region::new(
        "se",
        vec![(
            LoopRole::Outer,
            vec![Piece::SuperEllipse {
                center: v(0.0, 0.0),
                a: 1.0,
                b: 1.0,
                n: 1.0,
                ccw: true,
            }],
        )],
        None,
    ));
    assert!(e.contains("exponent"), "{e}");
}

#[test]
fn orientation_is_normalised_and_outer_goes_first() {
    // Outer given clockwise, hole counter-clockwise, hole listed first.
    let outer_cw: Vec<Piece> = square(0.0, 2.0)
        .iter()
        .rev()
        .map(|p| match p {
            Piece::Line { a, b } => Piece::Line { a: *b, b: *a },
            _ => unreachable!(),
        })
        .collect();
    let hole_ccw = vec![Piece::Circle {
        center: v(1.0, 1.0),
        radius: 0.5,
        ccw: true,
    }];
    let r = Region::new(
        "r",
        vec![(LoopRole::Hole, hole_ccw), (LoopRole::Outer, outer_cw)],
        None,
    )
    .unwrap();
    assert_eq!(r.loops()[0].role, LoopRole::Outer);
    assert!((r.area() - (4.0 - std::f64::consts::PI * 0.25)).abs() < 1e-12);
    let poly = r.polygonize(1e-3);
    let signed = |pts: &[DVec2]| {
        (0..pts.len())
            .map(|i| pts[i].perp_dot(pts[(i + 1) % pts.len()]))
            .sum::<f64>()
    };
    assert!(signed(&poly.rings[0].points) > 0.0 && signed(&poly.rings[1].points) < 0.0);
    assert!(matches!(
        r.pieces()[r.loops()[1].pieces[0]],
        Piece::Circle { ccw: false, .. }
    ));
    assert!(r.contains(v(0.2, 0.2)) && !r.contains(v(1.0, 1.0)) && !r.contains(v(3.0, 1.0)));
    // Corners computed: the four square corners.
    assert_eq!(r.corners().len(), 4);
    // The same from a file whose outer loop runs clockwise.
    let text = r#"{"loops": [{"role": "outer", "segments": [{"kind": "polyline", "points": [[0,0],[0,1],[1,1],[1,0],[0,0]]}]}]}"#;
    let r = Region::from_json_str(text, "cw.json").unwrap();
    assert!((r.area() - 1.0).abs() < 1e-15);
    assert_eq!(r.name(), "cw.json");
}

fn parse_err(text: &str) -> String {
    match Region::from_json_str(text, "test.json") {
        Err(e @ GeometryError::Parse { .. }) => e.to_string(),
        Err(e) => panic!("expected Parse, got {e}"),
        Ok(_) => panic!("expected an error"),
    }
}

#[test]
fn region_file_errors_name_the_file_and_the_problem() {
    let e = parse_err("{\"loops\": [\n  {\"segments\": [}\n]}");
    assert!(e.contains("test.json") && e.contains("line 2"), "{e}");
    let e = parse_err(r#"{"name": "x"}"#);
    assert!(e.contains("missing field 'loops'"), "{e}");
    let e = parse_err(r#"{"loops": [{"segments": [{"kind": "spline", "points": []}]}]}"#);
    assert!(
        e.contains("unknown segment kind 'spline'") && e.contains("polyline"),
        "{e}"
    );
    let e = parse_err(r#"{"loops": [{"segments": [{"kind": "circle", "center": [0, 0]}]}]}"#);
    assert!(
        e.contains("loops[0].segments[0] (circle): missing field 'radius'"),
        "{e}"
    );
    let e = parse_err(
        r#"{"loops": [{"role": "hole", "segments": [{"kind": "circle", "center": [0, 0], "radius": 1}]}]}"#,
    );
    assert!(e.contains("no loop has role 'outer'"), "{e}");
    // Two outer loops are two parts; the same circle twice crosses itself.
    let c = r#"{"kind": "circle", "center": [0, 0], "radius": 1}"#;
    let d = r#"{"kind": "circle", "center": [3, 0], "radius": 1}"#;
    let text = format!(
        r#"{{"loops": [{{"role": "outer", "segments": [{c}]}}, {{"role": "outer", "segments": [{c}]}}]}}"#
    );
    let e = Region::from_json_str(&text, "test.json")
        .unwrap_err()
        .to_string();
    assert!(e.contains("loop 0 (outer) and loop 1 (outer) cross"), "{e}");
    let text = format!(r#"{{"loops": [{{"segments": [{c}]}}, {{"segments": [{d}]}}]}}"#);
    let r = Region::from_json_str(&text, "test.json").unwrap();
    assert_eq!(r.num_parts(), 2);
    assert!((r.area() - 2.0 * std::f64::consts::PI).abs() < 1e-12);
    let e = parse_err(
        r#"{"loops": [{"segments": [{"kind": "polyline", "points": [[0, 0], [1, "a"]]}]}]}"#,
    );
    assert!(e.contains("points[1]") && e.contains("[x, y]"), "{e}");
    let e = parse_err(
        r#"{"loops": [{"segments": [{"kind": "arc", "center": [0, 0], "radius": 1, "from_deg": 0, "to_deg": 90, "start": [2, 0]}]}]}"#,
    );
    assert!(
        e.contains("start (2, 0) is not the arc's start point"),
        "{e}"
    );
    // Geometry errors from a file name the file too.
    let text = r#"{"name": "bow", "loops": [{"segments": [{"kind": "polyline", "points": [[0,0],[1,1],[1,0],[0,1],[0,0]]}]}]}"#;
    let e = Region::from_json_str(text, "bow.json")
        .unwrap_err()
        .to_string();
    assert!(e.contains("bow.json") && e.contains("(0.5, 0.5)"), "{e}");
}

#[test]
fn from_file_reads_and_reports_io_errors() {
    let dir = std::env::temp_dir().join(format!("geometry-validation-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("tri.json");
    std::fs::write(
        &path,
        r#"{"loops": [{"segments": [{"kind": "polyline", "points": [[0,0],[2,0],[0,2],[0,0]]}]}]}"#,
    )
    .unwrap();
    let r = Region::from_file(&path).unwrap();
    assert_eq!(r.name(), "tri");
    assert!((r.area() - 2.0).abs() < 1e-15);
    assert_eq!(r.corners().len(), 3);
    let bad = dir.join("bad.json");
    std::fs::write(&bad, "{ not json").unwrap();
    let e = Region::from_file(&bad).unwrap_err().to_string();
    assert!(e.contains("bad.json") && e.contains("line 1"), "{e}");
    let e = Region::from_file(&dir.join("missing.json")).unwrap_err();
    assert!(
        matches!(e, GeometryError::Io { .. }) && e.to_string().contains("missing.json"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn unknown_builtin_lists_the_names() {
    let e = Region::builtin("triangle").unwrap_err();
    assert!(matches!(e, GeometryError::UnknownBuiltin(..)));
    let s = e.to_string();
    assert!(
        s.contains("'triangle'") && s.contains("lake") && s.contains("circle"),
        "{s}"
    );
    assert_eq!(Region::builtin_names().len(), 10);
}

#[test]
fn an_empty_corner_list_means_no_corners() {
    let text = r#"{"corners": [], "loops": [{"segments": [{"kind": "polyline", "points": [[0,0],[1,0],[1,1],[0,0]]}]}]}"#;
    assert!(Region::from_json_str(text, "t")
        .unwrap()
        .corners()
        .is_empty());
    let text =
        r#"{"loops": [{"segments": [{"kind": "polyline", "points": [[0,0],[1,0],[1,1],[0,0]]}]}]}"#;
    assert_eq!(Region::from_json_str(text, "t").unwrap().corners().len(), 3);
}

#[test]
fn queries_on_non_finite_points_do_not_panic() {
    let r = Region::builtin("horn").unwrap();
    let p = v(f64::NAN, 0.5);
    assert!(r.signed_distance(p).is_nan());
    assert!(!r.contains(p));
    let b = r.project(p);
    assert!(b.distance.is_nan() || b.point.is_nan());
    let _ = r.project_onto_piece(v(f64::INFINITY, 0.0), 0);
    assert!(r.polygonize(f64::NAN).rings[0].points.len() > 10);
    assert_eq!(r.expand(f64::NAN, 1e-3), r.polygonize(1e-3));
}

#[test]
fn regions_are_shareable_across_threads() {
    fn send_sync<T: Send + Sync + Clone>() {}
    send_sync::<Region>();
    let r = Region::builtin("lake").unwrap();
    let c = r.clone();
    let h = std::thread::spawn(move || c.signed_distance(v(300.0, 400.0)));
    assert_eq!(h.join().unwrap(), r.signed_distance(v(300.0, 400.0)));
}
