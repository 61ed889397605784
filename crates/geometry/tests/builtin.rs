//! The ten paper regions: loading, areas, corners, lengths, queries.
use cvtmesh_geometry::{DVec2, Region, Rng};

/// The file's stated values (read at test time from the embedded copy via the JSON text).
fn stated(name: &str) -> serde_json::Value {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("regions")
        .join(format!("{name}.json"));
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

#[test]
fn all_builtins_load_with_the_stated_areas_lengths_and_corners() {
    for &name in Region::builtin_names() {
        let r = Region::builtin(name).unwrap();
        let v = stated(name);
        assert_eq!(r.name(), name);
        let area = v["area"].as_f64().unwrap();
        // The bike seat's chains are a 401-point sampling of the curves, so its polygon area
        // is slightly below the analytic 2 + 20π.
        let rel = if name == "bike_seat" { 2e-4 } else { 1e-9 };
        assert!(
            (r.area() - area).abs() <= rel * area,
            "{name}: area {} vs {}",
            r.area(),
            area
        );
        for (l, lv) in v["loops"].as_array().unwrap().iter().enumerate() {
            let len = lv["length"].as_f64().unwrap();
            let rel = if name == "bike_seat" { 1e-4 } else { 1e-9 };
            assert!(
                (r.loops()[l].length - len).abs() <= rel * len,
                "{name} loop {l}: {} vs {len}",
                r.loops()[l].length
            );
        }
        let bb = v["bbox"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect::<Vec<_>>();
        let (lo, hi) = r.bbox();
        for (a, b) in [lo.x, lo.y, hi.x, hi.y].iter().zip(&bb) {
            assert!(
                (a - b).abs() < 1e-12 * r.diameter(),
                "{name} bbox {lo} {hi} vs {bb:?}"
            );
        }
        let corners = v["corners"].as_array().unwrap();
        assert_eq!(r.corners().len(), corners.len(), "{name}");
        for c in r.corners() {
            assert!(
                r.signed_distance(c.pos).abs() <= 1e-12 * r.diameter(),
                "{name}: corner off the boundary"
            );
            assert_eq!(r.pieces()[c.piece_out].start(), c.pos);
            assert!((r.pieces()[c.piece_in].end() - c.pos).length() <= 1e-12 * r.diameter());
        }
    }
}

#[test]
fn every_corner_is_reported_by_project() {
    for &name in Region::builtin_names() {
        let r = Region::builtin(name).unwrap();
        for (i, c) in r.corners().iter().enumerate() {
            for off in [DVec2::ZERO, DVec2::new(1e-14, -1e-14) * r.diameter()] {
                let b = r.project(c.pos + off);
                assert_eq!(b.corner, Some(i), "{name} corner {i} at {}", c.pos);
                assert_eq!(b.point, c.pos);
                assert_eq!(b.loop_param, c.loop_param);
                assert_eq!(b.loop_index, c.loop_index);
            }
        }
    }
}

#[test]
fn sign_agrees_with_the_polygonization_and_projection_is_exact() {
    let mut rng = Rng::new(42);
    for &name in Region::builtin_names() {
        let r = Region::builtin(name).unwrap();
        let d = r.diameter();
        let poly = r.polygonize(1e-5 * d);
        let (lo, hi) = r.bbox();
        let dense: Vec<DVec2> = r
            .polygonize(2e-4 * d)
            .rings
            .iter()
            .flat_map(|x| x.points.clone())
            .collect();
        for _ in 0..400 {
            let p = DVec2::new(
                rng.range(lo.x - 0.1 * d, hi.x + 0.1 * d),
                rng.range(lo.y - 0.1 * d, hi.y + 0.1 * d),
            );
            let sd = r.signed_distance(p);
            assert_eq!(r.contains(p), sd <= 0.0);
            if sd.abs() > 1e-4 * d {
                assert_eq!(poly.contains(p), sd < 0.0, "{name}: {p} sd {sd}");
            }
            let b = r.project(p);
            assert!(
                (b.distance - sd.abs()).abs() <= 1e-12 * d,
                "{name}: {} vs {sd}",
                b.distance
            );
            assert!(
                r.signed_distance(b.point).abs() <= 1e-12 * d,
                "{name}: projection off the boundary"
            );
            // No boundary sample is nearer than the projection.
            let nearest = dense
                .iter()
                .map(|q| q.distance(p))
                .fold(f64::INFINITY, f64::min);
            assert!(
                b.distance <= nearest + 1e-12 * d,
                "{name}: {} > {nearest}",
                b.distance
            );
            let lp = &r.loops()[b.loop_index];
            assert!(b.loop_param >= 0.0 && b.loop_param < lp.length);
            assert_eq!(r.piece_loop(b.piece), b.loop_index);
            // Own-piece projection agrees on the nearest piece.
            let own = r.project_onto_piece(p, b.piece);
            assert!((own.distance - b.distance).abs() <= 1e-12 * d, "{name}");
        }
        // The point alone is the whole projection's point on every piece, a corner met within
        // 1e-12·diameter reported exactly by both.
        let near_corners = r.corners().iter().map(|c| c.pos + DVec2::splat(1e-14 * d));
        let mut some = Vec::new();
        for _ in 0..50 {
            some.push(DVec2::new(
                rng.range(lo.x - 0.1 * d, hi.x + 0.1 * d),
                rng.range(lo.y - 0.1 * d, hi.y + 0.1 * d),
            ));
        }
        for p in some.into_iter().chain(near_corners) {
            for piece in 0..r.pieces().len() {
                assert_eq!(
                    r.project_point_onto_piece(p, piece),
                    r.project_onto_piece(p, piece).point,
                    "{name}: {p} onto piece {piece}"
                );
            }
        }
    }
}

#[test]
fn polygonize_converges_to_the_exact_area_with_bounded_chord_error() {
    for &name in Region::builtin_names() {
        let r = Region::builtin(name).unwrap();
        let d = r.diameter();
        let mut last_err = f64::INFINITY;
        for k in [2, 3, 4, 5] {
            let tol = d * 10f64.powi(-k);
            let p = r.polygonize(tol);
            let err = (p.area() - r.area()).abs();
            // Chord error ≤ tol bounds the area error by tol × perimeter.
            assert!(
                err <= tol * r.perimeter() + 1e-12 * r.area(),
                "{name} tol {tol}: area error {err}"
            );
            assert!(err <= last_err + 1e-12 * r.area(), "{name}: not converging");
            last_err = err;
            // Ring structure: outer CCW first, holes CW; one ring per loop; edge pieces on the loop.
            assert_eq!(p.rings.len(), r.loops().len());
            for (l, ring) in p.rings.iter().enumerate() {
                assert_eq!(ring.loop_index, l);
                assert_eq!(ring.hole, l > 0);
                assert_eq!(ring.points.len(), ring.pieces.len());
                assert!(ring.pieces.iter().all(|&pc| r.piece_loop(pc) == l));
            }
            // Every corner is a polygon vertex.
            for c in r.corners() {
                assert!(
                    p.rings[c.loop_index].points.contains(&c.pos),
                    "{name}: corner {} not a vertex",
                    c.pos
                );
            }
            // Chord error: exact boundary samples are within tol of their piece's edges.
            for ring in &p.rings {
                let n = ring.points.len();
                for (i, &pc) in ring.pieces.iter().enumerate() {
                    let (a, b) = (ring.points[i], ring.points[(i + 1) % n]);
                    for s in 1..8 {
                        // The exact point on the piece nearest to a point of the edge.
                        let x = a.lerp(b, s as f64 / 8.0);
                        let (q, _) = r.pieces()[pc].closest_point(x);
                        assert!(
                            q.distance(x) <= tol * (1.0 + 1e-9),
                            "{name}: chord error {} > {tol}",
                            q.distance(x)
                        );
                    }
                }
            }
        }
        assert!(last_err <= 1e-4 * r.area(), "{name}: {last_err}");
    }
}

#[test]
fn corner_angle_threshold_merges_nearly_straight_junctions() {
    let lake = Region::builtin("lake").unwrap();
    assert_eq!(lake.corners().len(), 101);
    let all = lake.with_corner_angle(0.0);
    assert_eq!(all.corners().len(), 101);
    assert_eq!(all.pieces().len(), 101);
    assert_eq!(all.corner_threshold(), Some(0.0));
    let few = lake.with_corner_angle(30.0);
    assert!(
        few.corners().len() < 60 && !few.corners().is_empty(),
        "{}",
        few.corners().len()
    );
    assert!((few.area() - lake.area()).abs() <= 1e-12 * lake.area());
    assert!((few.perimeter() - lake.perimeter()).abs() <= 1e-9 * lake.perimeter());
    assert_eq!(few.pieces().len(), few.corners().len());
    // The kept corners are exactly the lake corners turning by more than 30°.
    let turn = |c: &cvtmesh_geometry::Corner, r: &Region| {
        let (t1, t2) = (
            r.pieces()[c.piece_in].end_tangents().1,
            r.pieces()[c.piece_out].end_tangents().0,
        );
        t1.perp_dot(t2).atan2(t1.dot(t2)).abs().to_degrees()
    };
    let expected = lake
        .corners()
        .iter()
        .filter(|c| turn(c, &lake) > 30.0)
        .count();
    assert_eq!(few.corners().len(), expected);
    for c in few.corners() {
        assert!(lake.corners().iter().any(|o| o.pos == c.pos));
        assert!(turn(c, &few) > 30.0);
        assert_eq!(
            few.project(c.pos).corner.map(|k| few.corners()[k].pos),
            Some(c.pos)
        );
    }
    // Queries are unchanged by merging.
    let mut rng = Rng::new(5);
    let (lo, hi) = lake.bbox();
    for _ in 0..500 {
        let p = DVec2::new(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y));
        assert!((few.signed_distance(p) - lake.signed_distance(p)).abs() < 1e-9);
        let b = few.project(p);
        assert!((b.point - few.project_onto_piece(p, b.piece).point).length() < 1e-9);
    }
    // Loop params of the merged region increase along each loop.
    for (l, lp) in few.loops().iter().enumerate() {
        assert!(lp.offsets.windows(2).all(|w| w[0] < w[1]));
        assert!(few.corners().iter().filter(|c| c.loop_index == l).count() <= lp.pieces.len());
    }
    // A threshold above every turn leaves one closed chain per loop and no corners.
    let none = lake.with_corner_angle(179.0);
    assert!(none.corners().is_empty());
    assert_eq!(none.pieces().len(), 2);
    assert!((none.area() - lake.area()).abs() <= 1e-12 * lake.area());
    // Curved pieces: the pie's arcs merge with the notch lines into sampled chains.
    let pie = Region::builtin("pie_hole").unwrap();
    let merged = pie.with_corner_angle(60.0);
    assert!(merged.corners().len() < pie.corners().len());
    // Arcs in a merged run are sampled with chord error 1e-7·diameter.
    assert!((merged.area() - pie.area()).abs() <= 1e-7 * pie.diameter() * pie.perimeter());
    assert!(merged
        .pieces()
        .iter()
        .any(|p| matches!(p, cvtmesh_geometry::Piece::Chain(_))));
}

#[test]
fn chain_vertex_between_finds_the_first_bend_on_the_way() {
    let seat = Region::builtin("bike_seat").unwrap();
    let (j, pts) = seat
        .pieces()
        .iter()
        .enumerate()
        .find_map(|(j, p)| match p {
            cvtmesh_geometry::Piece::Chain(pts) => Some((j, pts.clone())),
            _ => None,
        })
        .expect("bike_seat's curves are sampled chains");
    let mid = |i: usize| 0.5 * (pts[i] + pts[i + 1]);
    let v = |a, b| seat.chain_vertex_between(a, b, j);
    // Going forward from segment 9 to segment 11 the first vertex is 10; backward it is 11.
    assert_eq!(v(mid(9), mid(11)), Some(pts[10]));
    assert_eq!(v(mid(11), mid(9)), Some(pts[11]));
    // Within one segment there is none; at a vertex, that vertex.
    assert_eq!(v(mid(9), 0.7 * pts[9] + 0.3 * pts[10]), None);
    assert_eq!(v(pts[10], pts[10]), Some(pts[10]));
    assert_eq!(v(pts[10], mid(12)), Some(pts[10]));
    // Off-piece points count by their nearest point on it.
    let n = (pts[10] - pts[9]).perp().normalize() * 1e-3;
    assert_eq!(v(mid(9) + n, mid(11) - n), Some(pts[10]));
    // The chain's end points are junctions, not bends of the piece.
    assert_eq!(v(pts[0], mid(0)), None);
    // Smooth pieces have no such vertices.
    let circle = Region::builtin("circle").unwrap();
    let q = |t: f64| DVec2::new(t.cos(), t.sin());
    assert_eq!(circle.chain_vertex_between(q(0.1), q(2.0), 0), None);
}

#[test]
fn paper_k_lists_the_twelve_tables_in_order() {
    for &name in Region::builtin_names() {
        let k = Region::paper_k(name);
        assert!(!k.is_empty(), "{name}");
        assert!(k.windows(2).all(|w| w[0] < w[1]), "{name}: {k:?}");
    }
    let cases: Vec<(&str, usize)> = Region::paper_cases().collect();
    assert_eq!(cases.len(), 12);
    assert_eq!(cases[0], ("circle", 19));
    assert_eq!(cases[11], ("lake", 1109));
    assert!(Region::paper_k("triangle").is_empty());
}

#[test]
fn a_regular_polygon_keeps_all_its_corners_or_none_whatever_the_rounding() {
    use cvtmesh_geometry::LoopRole;
    // Turns of 30° (a dodecagon) meet the default threshold and stay corners, all twelve;
    // turns of 15° (a 24-gon) do not, none. Rotated and scaled so that the turns computed
    // from the rounded vertices straddle the exact angle.
    for (n, kept) in [(12, 12), (24, 0), (6, 6)] {
        for (phase, radius) in [(0.0, 1.0), (0.1, 3.7), (0.377, 0.013), (1.3, 250.0)] {
            let pts: Vec<DVec2> = (0..n)
                .map(|i| {
                    let t = phase + std::f64::consts::TAU * i as f64 / n as f64;
                    DVec2::new(radius * t.cos() + 0.3, radius * t.sin() - 0.2)
                })
                .collect();
            let r = Region::from_loops("ngon", vec![(LoopRole::Outer, pts)])
                .unwrap()
                .with_default_corners();
            assert_eq!(r.corners().len(), kept, "{n}-gon at {phase}, {radius}");
        }
    }
}
