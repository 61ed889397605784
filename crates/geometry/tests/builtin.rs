//! The ten paper regions: loading, areas, corners, lengths, queries.
use geometry::{DVec2, Region, Rng};

/// The file's stated values (read at test time from the embedded copy via the JSON text).
fn stated(name: &str) -> serde_json::Value {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../domains").join(format!("{name}.json"));
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
        assert!((r.area() - area).abs() <= rel * area, "{name}: area {} vs {}", r.area(), area);
        for (l, lv) in v["loops"].as_array().unwrap().iter().enumerate() {
            let len = lv["length"].as_f64().unwrap();
            let rel = if name == "bike_seat" { 1e-4 } else { 1e-9 };
            assert!((r.loops()[l].length - len).abs() <= rel * len, "{name} loop {l}: {} vs {len}", r.loops()[l].length);
        }
        let bb = v["bbox"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect::<Vec<_>>();
        let (lo, hi) = r.bbox();
        for (a, b) in [lo.x, lo.y, hi.x, hi.y].iter().zip(&bb) {
            assert!((a - b).abs() < 1e-12 * r.diameter(), "{name} bbox {lo} {hi} vs {bb:?}");
        }
        let corners = v["corners"].as_array().unwrap();
        assert_eq!(r.corners().len(), corners.len(), "{name}");
        for c in r.corners() {
            assert!(r.signed_distance(c.pos).abs() <= 1e-12 * r.diameter(), "{name}: corner off the boundary");
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
        let dense: Vec<DVec2> = r.polygonize(2e-4 * d).rings.iter().flat_map(|x| x.points.clone()).collect();
        for _ in 0..400 {
            let p = DVec2::new(rng.range(lo.x - 0.1 * d, hi.x + 0.1 * d), rng.range(lo.y - 0.1 * d, hi.y + 0.1 * d));
            let sd = r.signed_distance(p);
            assert_eq!(r.contains(p), sd <= 0.0);
            if sd.abs() > 1e-4 * d {
                assert_eq!(poly.contains(p), sd < 0.0, "{name}: {p} sd {sd}");
            }
            let b = r.project(p);
            assert!((b.distance - sd.abs()).abs() <= 1e-12 * d, "{name}: {} vs {sd}", b.distance);
            assert!(r.signed_distance(b.point).abs() <= 1e-12 * d, "{name}: projection off the boundary");
            // No boundary sample is nearer than the projection.
            let nearest = dense.iter().map(|q| q.distance(p)).fold(f64::INFINITY, f64::min);
            assert!(b.distance <= nearest + 1e-12 * d, "{name}: {} > {nearest}", b.distance);
            let lp = &r.loops()[b.loop_index];
            assert!(b.loop_param >= 0.0 && b.loop_param < lp.length);
            assert_eq!(r.piece_loop(b.piece), b.loop_index);
            // Own-piece projection agrees on the nearest piece.
            let own = r.project_onto_piece(p, b.piece);
            assert!((own.distance - b.distance).abs() <= 1e-12 * d, "{name}");
        }
    }
}
