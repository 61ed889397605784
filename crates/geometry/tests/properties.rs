//! Property tests on random star-shaped regions (with an optional circular hole and an
//! optional arc edge): rigid-motion invariance, sign and projection consistency, Ω_ε,
//! simplification.
use cvtmesh_geometry::predicates::segments_cross;
use cvtmesh_geometry::{DVec2, EmbeddedLine, LoopRole, Piece, Region};
use proptest::prelude::*;
use std::f64::consts::TAU;

#[derive(Clone, Debug)]
struct Shape {
    radii: Vec<f64>,
    jitter: Vec<f64>,
    hole: Option<f64>,
    /// Replace the first edge by a circular arc bulging outwards.
    arc: bool,
}

fn shape() -> impl Strategy<Value = Shape> {
    (6usize..40)
        .prop_flat_map(|n| {
            (
                prop::collection::vec(0.5f64..1.5, n),
                prop::collection::vec(-0.4f64..0.4, n),
                prop::option::of(0.05f64..0.2),
                any::<bool>(),
            )
        })
        .prop_map(|(radii, jitter, hole, arc)| Shape {
            radii,
            jitter,
            hole,
            arc,
        })
}

/// The region moved by rotation `theta` and translation `t`.
fn build(s: &Shape, theta: f64, t: DVec2) -> Option<Region> {
    let rot = DVec2::from_angle(theta);
    let map = |p: DVec2| rot.rotate(p) + t;
    let n = s.radii.len();
    let pts: Vec<DVec2> = (0..n)
        .map(|i| {
            let a = (i as f64 + s.jitter[i]) * TAU / n as f64;
            s.radii[i] * DVec2::new(a.cos(), a.sin())
        })
        .collect();
    let mut outer: Vec<Piece> = (0..n)
        .map(|i| Piece::Line {
            a: map(pts[i]),
            b: map(pts[(i + 1) % n]),
        })
        .collect();
    if s.arc {
        // A circular arc through pts[0] and pts[1], bulging outwards (centre on the inner side).
        let (a, b) = (pts[0], pts[1]);
        let m = 0.5 * (a + b);
        let half = 0.5 * a.distance(b);
        let inward = (b - a).perp().normalize(); // left of a→b, i.e. towards the inside
        let center = m + inward * (half / 10f64.to_radians().tan()); // sweep 20°
        let radius = center.distance(a);
        let from = (a - center).to_angle();
        let mut to = (b - center).to_angle();
        if to < from {
            to += TAU;
        }
        outer[0] = Piece::Arc {
            center: map(center),
            radius,
            from: from + theta,
            to: to + theta,
        };
    }
    let mut loops = vec![(LoopRole::Outer, outer)];
    if let Some(r) = s.hole {
        loops.push((
            LoopRole::Hole,
            vec![Piece::Circle {
                center: t,
                radius: r,
                ccw: false,
            }],
        ));
    }
    // The arc may cross a neighbouring edge at a sharp vertex; such shapes are skipped.
    Region::new("random", loops, None).ok()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn area_and_distances_are_invariant_under_rigid_motions(
        s in shape(), theta in 0.0f64..TAU, tx in -50.0f64..50.0, ty in -50.0f64..50.0,
        probes in prop::collection::vec((-2.0f64..2.0, -2.0f64..2.0), 20)
    ) {
        let r0 = build(&s, 0.0, DVec2::ZERO);
        prop_assume!(r0.is_some());
        let r0 = r0.unwrap();
        let t = DVec2::new(tx, ty);
        let r1 = build(&s, theta, t).expect("a rigid motion keeps the region valid");
        prop_assert!((r0.area() - r1.area()).abs() <= 1e-12 * (1.0 + t.length()) * r0.area().max(1.0) * 10.0,
            "{} vs {}", r0.area(), r1.area());
        prop_assert!((r0.perimeter() - r1.perimeter()).abs() <= 1e-12 * r0.perimeter());
        prop_assert_eq!(r0.corners().len(), r1.corners().len());
        let rot = DVec2::from_angle(theta);
        for &(x, y) in &probes {
            let p = DVec2::new(x, y);
            let (d0, d1) = (r0.signed_distance(p), r1.signed_distance(rot.rotate(p) + t));
            prop_assert!((d0 - d1).abs() <= 1e-12 * (10.0 + t.length()), "{d0} vs {d1}");
        }
    }

    #[test]
    fn sign_projection_and_polygon_agree(
        s in shape(),
        probes in prop::collection::vec((-1.7f64..1.7, -1.7f64..1.7), 60)
    ) {
        let r = build(&s, 0.0, DVec2::ZERO);
        prop_assume!(r.is_some());
        let r = r.unwrap();
        let poly = r.polygonize(1e-6);
        let d = r.diameter();
        for &(x, y) in &probes {
            let p = DVec2::new(x, y);
            let sd = r.signed_distance(p);
            prop_assert_eq!(r.contains(p), sd <= 0.0);
            if sd.abs() > 1e-5 {
                prop_assert_eq!(poly.contains(p), sd < 0.0, "{} sd {}", p, sd);
            }
            let b = r.project(p);
            prop_assert!((b.distance - sd.abs()).abs() <= 1e-13 * d);
            prop_assert!(r.signed_distance(b.point).abs() <= 1e-12 * d);
            prop_assert!(b.loop_param >= 0.0 && b.loop_param < r.loops()[b.loop_index].length);
            // The point at that loop parameter is the projected point (pieces are lines/arcs/circle).
            let lp = &r.loops()[b.loop_index];
            let k = lp.pieces.iter().position(|&q| q == b.piece).unwrap();
            let (_, s_on) = r.pieces()[b.piece].closest_point(b.point);
            let expect = lp.offsets[k] + s_on;
            let diff = (b.loop_param - expect).abs();
            prop_assert!(diff <= 1e-9 * lp.length || (diff - lp.length).abs() <= 1e-9 * lp.length, "{} vs {}", b.loop_param, expect);
        }
    }

    #[test]
    fn distance_to_chosen_loops_is_the_nearest_of_their_pieces(
        s in shape(),
        probes in prop::collection::vec((-1.7f64..1.7, -1.7f64..1.7), 30)
    ) {
        let r = build(&s, 0.0, DVec2::ZERO);
        prop_assume!(r.is_some());
        let r = r.unwrap();
        for chosen in r.loops() {
            let mine = |piece: usize| chosen.pieces.contains(&piece);
            for &(x, y) in &probes {
                let p = DVec2::new(x, y);
                let direct = chosen
                    .pieces
                    .iter()
                    .map(|&q| r.project_onto_piece(p, q).distance)
                    .fold(f64::INFINITY, f64::min);
                let d = r.distance_where(p, mine);
                prop_assert!((d - direct).abs() <= 1e-13 * r.diameter(), "{} vs {}", d, direct);
            }
        }
        prop_assert!(r.distance_where(DVec2::ZERO, |_| false).is_infinite());
    }

    #[test]
    fn simplification_stays_within_its_deviation(s in shape(), tol in 0.001f64..0.5) {
        let r = build(&s, 0.3, DVec2::new(2.0, -1.0));
        prop_assume!(r.is_some());
        let r = r.unwrap();
        let simple = r.simplified(tol).unwrap();
        let t = &simple.region;
        prop_assert!(simple.tolerance <= tol && simple.deviation <= simple.tolerance);
        prop_assert!(simple.vertices.1 <= simple.vertices.0);
        prop_assert_eq!(t.loops().len(), r.loops().len());
        let slack = 1e-12 * r.diameter();
        // Each boundary within the deviation of the other: the given one's vertices near the
        // simplified boundary, the simplified one's vertices on the given boundary.
        for ring in r.polygonize(1e-4).rings {
            for v in ring.points {
                prop_assert!(t.signed_distance(v).abs() <= simple.deviation + 1e-4 + slack);
            }
        }
        for ring in t.polygonize(1e-4).rings {
            for v in ring.points {
                prop_assert!(r.signed_distance(v).abs() <= 1e-4 + slack);
            }
        }
        prop_assert!((t.area() - r.area()).abs() <= simple.deviation * r.perimeter() + slack);
    }

    #[test]
    fn expansion_is_simple_and_at_distance_eps(s in shape(), eps in 0.005f64..0.6) {
        let r = build(&s, 0.0, DVec2::ZERO);
        prop_assume!(r.is_some());
        let r = r.unwrap();
        let tol = 1e-3;
        let p = r.expand(eps, tol);
        prop_assert!(!p.rings.is_empty() && !p.rings[0].hole);
        prop_assert!(p.area() >= r.area());
        for ring in &p.rings {
            for v in &ring.points {
                let d = r.signed_distance(*v);
                prop_assert!((d - eps).abs() <= tol, "vertex at {} for ε {}", d, eps);
            }
        }
        // Simple: no two non-adjacent edges cross.
        let edges: Vec<(usize, usize, DVec2, DVec2)> = p.rings.iter().enumerate().flat_map(|(k, ring)| {
            let n = ring.points.len();
            (0..n).map(move |i| (k, i, ring.points[i], ring.points[(i + 1) % n]))
        }).collect();
        for (x, &(ka, ia, a0, a1)) in edges.iter().enumerate() {
            let na = p.rings[ka].points.len();
            for &(kb, ib, b0, b1) in &edges[x + 1..] {
                if ka == kb && (ib == ia + 1 || (ia == 0 && ib == na - 1)) {
                    continue;
                }
                let cross = segments_cross(a0, a1, b0, b1);
                prop_assert!(!cross, "edges cross near {}", a0);
            }
        }
        // The hole survives exactly when ε is below its radius.
        if let Some(h) = s.hole {
            if eps < h - 2.0 * tol {
                prop_assert_eq!(p.rings.len(), 2);
            } else if eps > h + 2.0 * tol {
                prop_assert_eq!(p.rings.len(), 1);
            }
        }
    }
}

/// The unit square, and a line (marked by its index) from each pair of ends.
fn square_with(ends: &[[(f64, f64); 2]]) -> (Region, Vec<EmbeddedLine>) {
    let square = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
        .map(DVec2::from)
        .to_vec();
    let region = Region::from_loops("square", vec![(LoopRole::Outer, square)]).unwrap();
    let lines = ends
        .iter()
        .enumerate()
        .map(|(i, [a, b])| EmbeddedLine {
            points: vec![DVec2::from(*a), DVec2::from(*b)],
            marker: i as i64,
        })
        .collect();
    (region, lines)
}

/// Straight lines (two points each) inside the unit square, from random end points.
fn straight_lines() -> impl Strategy<Value = Vec<[(f64, f64); 2]>> {
    prop::collection::vec(
        [
            (0.05f64..0.95, 0.05f64..0.95),
            (0.05f64..0.95, 0.05f64..0.95),
        ],
        1..12,
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Crossing lines are split, not refused: each line keeps its ends and runs through the
    /// same points, no two segments cross any more, and every crossing is a vertex of both
    /// lines with the same bits.
    #[test]
    fn crossing_lines_become_lines_that_share_their_crossings(ends in straight_lines()) {
        let (region, lines) = square_with(&ends);
        // Near-parallel or near-touching pairs may still be refused (overlap, a touch without
        // a shared vertex); what is accepted must hold the properties.
        let Ok(r) = region.with_embedded_lines(lines.clone()) else { return Ok(()) };
        let got = r.embedded_lines();
        prop_assert_eq!(got.len(), lines.len());
        for (line, given) in got.iter().zip(&lines) {
            let (a, b) = (given.points[0], given.points[1]);
            prop_assert_eq!(line.points[0], a);
            prop_assert_eq!(*line.points.last().unwrap(), b);
            for p in &line.points {
                let t = (*p - a).dot(b - a) / a.distance_squared(b);
                prop_assert!((a + (b - a) * t).distance(*p) < 1e-12);
            }
            let length: f64 = line.segments().map(|(p, q)| p.distance(q)).sum();
            prop_assert!((length - a.distance(b)).abs() < 1e-12);
        }
        let segments: Vec<(usize, DVec2, DVec2)> = got
            .iter()
            .enumerate()
            .flat_map(|(i, l)| l.segments().map(move |(a, b)| (i, a, b)))
            .collect();
        // Segments of one straight line are collinear, where the (inexact) orientation signs
        // are noise: only segments whose boxes overlap can cross.
        let boxes_meet = |a: DVec2, b: DVec2, c: DVec2, d: DVec2| {
            a.min(b).cmple(c.max(d)).all() && c.min(d).cmple(a.max(b)).all()
        };
        for (s, &(i, a, b)) in segments.iter().enumerate() {
            for &(j, c, d) in &segments[s + 1..] {
                prop_assert!(
                    !(boxes_meet(a, b, c, d) && segments_cross(a, b, c, d)),
                    "lines {} and {} still cross", i, j
                );
            }
        }
        // Every pair of given lines that crossed shares a vertex now.
        for (i, li) in lines.iter().enumerate() {
            for (j, lj) in lines.iter().enumerate().skip(i + 1) {
                let (a, b, c, d) = (li.points[0], li.points[1], lj.points[0], lj.points[1]);
                if segments_cross(a, b, c, d) {
                    prop_assert!(got[i].points.iter().any(|p| got[j].points.contains(p)));
                }
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Lines drawn in a box three times the square's keep exactly their parts inside it: each
    /// kept line lies in the square, runs along its given line, and the kept lengths add up to
    /// the clipped lengths (Liang–Barsky); what is kept is a valid set of lines.
    #[test]
    fn lines_from_a_larger_box_keep_exactly_their_parts_inside(
        ends in prop::collection::vec([(-1.0f64..2.0, -1.0f64..2.0), (-1.0f64..2.0, -1.0f64..2.0)], 1..10)
    ) {
        let (region, lines) = square_with(&ends);
        let kept = region.lines_inside(lines.clone());
        let clipped = |a: DVec2, b: DVec2| {
            let d = b - a;
            let (mut t0, mut t1) = (0.0f64, 1.0f64);
            for (p, q) in [(-d.x, a.x), (d.x, 1.0 - a.x), (-d.y, a.y), (d.y, 1.0 - a.y)] {
                if p == 0.0 {
                    if q < 0.0 { return 0.0; }
                } else if p < 0.0 {
                    t0 = t0.max(q / p);
                } else {
                    t1 = t1.min(q / p);
                }
            }
            (t1 - t0).max(0.0) * d.length()
        };
        for line in &lines {
            let (a, b) = (line.points[0], line.points[1]);
            let length: f64 = kept
                .iter()
                .filter(|l| l.marker == line.marker)
                .map(|l| l.length())
                .sum();
            prop_assert!((length - clipped(a, b)).abs() < 1e-9, "{} against {}", length, clipped(a, b));
            for l in kept.iter().filter(|l| l.marker == line.marker) {
                for p in &l.points {
                    prop_assert!(p.cmpge(DVec2::splat(-1e-12)).all() && p.cmple(DVec2::splat(1.0 + 1e-12)).all());
                    let t = (*p - a).dot(b - a) / a.distance_squared(b);
                    prop_assert!((a + (b - a) * t).distance(*p) < 1e-9);
                }
            }
        }
        // A line wholly inside comes back as it was, to the bit (its ends are other lines'
        // crossings and junctions).
        for line in lines.iter().filter(|l| l.points.iter().all(|p| p.cmpgt(DVec2::ZERO).all() && p.cmplt(DVec2::ONE).all())) {
            prop_assert!(kept.iter().any(|k| k.points == line.points), "{:?} changed", line.points);
        }
        // Kept lines that run along a wall, cross or touch may be refused; none may panic.
        let _ = region.with_embedded_lines(kept);
    }
}
