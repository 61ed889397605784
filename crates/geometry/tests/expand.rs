//! Ω_ε (Algorithm 2): exact areas of simple cases, simplicity, distance property.
use cvtmesh_geometry::predicates::{ring_signed_area, segments_cross};
use cvtmesh_geometry::{DVec2, LoopRole, Piece, Polygon, Region, Rng};
use std::f64::consts::PI;

fn polyline(pts: &[(f64, f64)]) -> Vec<Piece> {
    let p: Vec<DVec2> = pts.iter().map(|&(x, y)| DVec2::new(x, y)).collect();
    (0..p.len())
        .map(|i| Piece::Line {
            a: p[i],
            b: p[(i + 1) % p.len()],
        })
        .collect()
}

/// No two non-adjacent edges of the polygon meet (O(n²), test sizes only).
fn assert_simple(p: &Polygon, what: &str) {
    let segs: Vec<(usize, usize, DVec2, DVec2)> = p
        .rings
        .iter()
        .enumerate()
        .flat_map(|(r, ring)| {
            let n = ring.points.len();
            (0..n).map(move |i| (r, i, ring.points[i], ring.points[(i + 1) % n]))
        })
        .collect();
    for (x, &(ra, ia, a0, a1)) in segs.iter().enumerate() {
        let na = p.rings[ra].points.len();
        for &(rb, ib, b0, b1) in &segs[x + 1..] {
            if ra == rb && (ib == ia + 1 || (ia == 0 && ib == na - 1)) {
                continue;
            }
            let cross = segments_cross(a0, a1, b0, b1);
            assert!(
                !cross,
                "{what}: edges {ra}/{ia} and {rb}/{ib} cross near {a0}"
            );
        }
    }
    assert!(!p.rings.is_empty());
    assert!(
        !p.rings[0].hole && ring_signed_area(&p.rings[0].points) > 0.0,
        "{what}: outer ring not CCW"
    );
    for r in &p.rings[1..] {
        assert!(
            r.hole && ring_signed_area(&r.points) < 0.0,
            "{what}: hole ring not CW"
        );
    }
    for r in &p.rings {
        assert_eq!(r.points.len(), r.pieces.len());
    }
}

/// Every vertex of Ω_ε is at distance ε from Ω (to tol), Ω_ε contains what is within ε − tol
/// of Ω and excludes what is farther than ε + tol; each edge's piece is near the edge.
fn assert_distance_property(r: &Region, p: &Polygon, eps: f64, tol: f64, seed: u64) {
    for ring in &p.rings {
        for (i, v) in ring.points.iter().enumerate() {
            let d = r.signed_distance(*v);
            assert!(
                (d - eps).abs() <= tol,
                "{}: vertex {v} at distance {d}, ε = {eps}",
                r.name()
            );
            let b = r.project_onto_piece(*v, ring.pieces[i]);
            assert!(
                b.distance <= eps + 2.0 * tol,
                "{}: edge piece is not the nearest ({} vs {eps})",
                r.name(),
                b.distance
            );
            // Along the edge too: Algorithm 2 projects a cell on this edge onto its piece.
            let m = 0.5 * (*v + ring.points[(i + 1) % ring.points.len()]);
            let (own, nearest) = (
                r.project_onto_piece(m, ring.pieces[i]).distance,
                r.signed_distance(m),
            );
            assert!(
                own <= nearest + 2.0 * tol,
                "{}: the edge from {v} is on piece {}, {own} from its midpoint, but Ω is \
                 {nearest} from it",
                r.name(),
                ring.pieces[i]
            );
        }
    }
    let (lo, hi) = p.bbox();
    let mut rng = Rng::new(seed);
    for _ in 0..2000 {
        let x = DVec2::new(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y));
        let d = r.signed_distance(x).max(0.0);
        if d <= eps - tol {
            assert!(
                p.contains(x),
                "{}: {x} at distance {d} not in Ω_ε",
                r.name()
            );
        } else if d >= eps + tol {
            assert!(!p.contains(x), "{}: {x} at distance {d} in Ω_ε", r.name());
        }
    }
}

#[test]
fn circle_grows_to_radius_r_plus_eps() {
    let r = Region::builtin("circle").unwrap();
    for (eps, tol) in [(0.05, 1e-4), (0.3, 1e-5), (2.0, 1e-4)] {
        let p = r.expand(eps, tol);
        assert_eq!(p.rings.len(), 1);
        let exact = PI * (1.0 + eps) * (1.0 + eps);
        assert!(
            (p.area() - exact).abs() <= 2.0 * PI * (1.0 + eps) * tol,
            "ε {eps}: {} vs {exact}",
            p.area()
        );
        assert_simple(&p, "circle");
        assert_distance_property(&r, &p, eps, tol, 1);
    }
}

#[test]
fn square_becomes_a_rounded_square() {
    let s = 1.5;
    let r = Region::new(
        "sq",
        vec![(
            LoopRole::Outer,
            polyline(&[(0.0, 0.0), (s, 0.0), (s, s), (0.0, s)]),
        )],
        None,
    )
    .unwrap();
    for eps in [0.01, 0.2, 1.0] {
        let tol = 1e-5;
        let p = r.expand(eps, tol);
        let exact = s * s + 4.0 * s * eps + PI * eps * eps;
        assert!(
            (p.area() - exact).abs() <= 10.0 * tol,
            "ε {eps}: {} vs {exact}",
            p.area()
        );
        assert_simple(&p, "square");
        assert_distance_property(&r, &p, eps, tol, 2);
    }
}

#[test]
fn annulus_hole_shrinks_then_vanishes() {
    let r = Region::builtin("annulus").unwrap();
    let tol = 1e-5;
    for eps in [0.1, 0.3, 0.39] {
        let p = r.expand(eps, tol);
        assert_eq!(p.rings.len(), 2, "ε {eps}");
        let hole = -ring_signed_area(&p.rings[1].points);
        let r_hole = 0.4 - eps;
        assert!(
            (hole - PI * r_hole * r_hole).abs() <= 2.0 * PI * r_hole * tol + 1e-12,
            "ε {eps}: hole {hole}"
        );
        assert_eq!(p.rings[1].loop_index, 1);
        assert!(p.rings[1].pieces.iter().all(|&k| r.piece_loop(k) == 1));
        assert_simple(&p, "annulus");
        assert_distance_property(&r, &p, eps, tol, 3);
    }
    let p = r.expand(0.41, tol);
    assert_eq!(p.rings.len(), 1);
    assert!((p.area() - PI * 1.41 * 1.41).abs() <= 2.0 * PI * 1.41 * tol);
}

/// Area of the dent that a gap of width w leaves in a straight boundary expanded by ε ≥ w/2.
fn dimple(w: f64, eps: f64) -> f64 {
    let u = w / 2.0;
    w * eps - 2.0 * (u / 2.0 * (eps * eps - u * u).sqrt() + eps * eps / 2.0 * (u / eps).asin())
}

#[test]
fn a_narrow_slot_closes_and_a_lagoon_becomes_a_hole() {
    // A 4×4 square with a 2×2 inner room reached from the top by a slot of width 0.2.
    let outer = polyline(&[
        (0.0, 0.0),
        (4.0, 0.0),
        (4.0, 4.0),
        (2.1, 4.0),
        (2.1, 3.0),
        (3.0, 3.0),
        (3.0, 1.0),
        (1.0, 1.0),
        (1.0, 3.0),
        (1.9, 3.0),
        (1.9, 4.0),
        (0.0, 4.0),
    ]);
    let r = Region::new("lagoon", vec![(LoopRole::Outer, outer)], None).unwrap();
    let (eps, tol) = (0.2, 1e-5);
    let p = r.expand(eps, tol);
    assert_simple(&p, "lagoon");
    assert_eq!(p.rings.len(), 2, "the room becomes a hole");
    let hole = -ring_signed_area(&p.rings[1].points);
    let dent = dimple(0.2, eps);
    assert!((hole - (1.6 * 1.6 + dent)).abs() < 1e-4, "hole {hole}");
    let exact = 16.0 + 16.0 * eps + PI * eps * eps - 2.0 * dent - 1.6 * 1.6;
    assert!((p.area() - exact).abs() < 1e-4, "{} vs {exact}", p.area());
    assert_distance_property(&r, &p, eps, tol, 4);
    // Wider than the room's inradius: everything closes.
    let p = r.expand(1.05, tol);
    assert_eq!(p.rings.len(), 1);
    assert_simple(&p, "lagoon closed");
}

#[test]
fn a_wall_split_into_pieces_keeps_each_piece_on_its_own_offset() {
    // The bottom of the unit square in three pieces (wall markers that change at x = a and b):
    // where a piece's length rounds its unit normal to 1 − 2⁻⁵³ (0.7 − 0.3), the offsets of two
    // pieces meet 10⁻¹⁷ apart, and each offset edge must still carry its own piece.
    let splits = (1..10)
        .map(|i| f64::from(i) / 10.0)
        .chain((1..20).map(|i| f64::from(i) / 20.0));
    let splits: Vec<f64> = splits.collect();
    for &a in &splits {
        for &b in splits.iter().filter(|&&b| b > a) {
            let r = Region::new(
                "split bottom",
                vec![(
                    LoopRole::Outer,
                    polyline(&[
                        (0.0, 0.0),
                        (a, 0.0),
                        (b, 0.0),
                        (1.0, 0.0),
                        (1.0, 1.0),
                        (0.0, 1.0),
                    ]),
                )],
                None,
            )
            .unwrap();
            for eps in [0.0343, 0.1] {
                let p = r.expand(eps, 1e-4);
                assert_distance_property(&r, &p, eps, 1e-4, 7);
            }
        }
    }
}

#[test]
fn every_builtin_expands_to_a_simple_polygon() {
    for &name in Region::builtin_names() {
        let r = Region::builtin(name).unwrap();
        let d = r.diameter();
        for f in [0.003, 0.02, 0.1] {
            let (eps, tol) = (f * d, 1e-3 * d);
            let p = r.expand(eps, tol);
            assert_simple(&p, name);
            assert!(p.area() > r.area());
            assert_distance_property(&r, &p, eps, tol, 5);
        }
        // ε = 0 is the polygonization itself.
        assert_eq!(r.expand(0.0, 1e-3 * d), r.polygonize(1e-3 * d));
    }
}

#[test]
fn a_convex_hole_whose_short_edge_is_swallowed_shrinks_to_its_offset_then_closes() {
    // A triangular hole with its apex cut off by an edge 0.024 long: from ε ≈ 0.021 on, that
    // edge's offset lies beyond its neighbours' crossing, and the hole is the triangle's own
    // inward offset, similar to it with inradius r − ε.
    let xc = 0.02 / 1.7;
    let outer = polyline(&[(-2.0, -2.0), (2.0, -2.0), (2.0, 2.0), (-2.0, 2.0)]);
    let hole = polyline(&[(-xc, 0.98), (xc, 0.98), (1.0, -0.7), (-1.0, -0.7)]);
    let r = Region::new(
        "cut triangle",
        vec![(LoopRole::Outer, outer), (LoopRole::Hole, hole)],
        None,
    )
    .unwrap();
    let (area, inradius) = (1.7, 3.4 / (2.0 + 2.0 * 3.89f64.sqrt()));
    let tol = 1e-6;
    for eps in [0.03, 0.2, 0.5, 0.57] {
        let p = r.expand(eps, tol);
        assert_eq!(p.rings.len(), 2, "ε {eps}");
        let hole = -ring_signed_area(&p.rings[1].points);
        let exact = area * ((inradius - eps) / inradius).powi(2);
        assert!(
            (hole - exact).abs() <= 1e-9,
            "ε {eps}: hole {hole} against {exact}"
        );
        assert!(p.rings[1].pieces.iter().all(|&k| r.piece_loop(k) == 1));
        assert_simple(&p, "cut triangle");
        assert_distance_property(&r, &p, eps, tol, 6);
    }
    for eps in [inradius * (1.0 + 1e-9), 0.6] {
        let p = r.expand(eps, tol);
        assert_eq!(p.rings.len(), 1, "ε {eps}: the hole has closed");
        assert_simple(&p, "cut triangle, closed");
    }
}
