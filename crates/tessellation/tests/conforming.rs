//! Conforming meshes of the paper's regions from lattice points plus boundary points.
use cvtmesh_tessellation::{conforming_mesh, conforming_mesh_from, mark_vertices, Delaunay};
use geometry::{DVec2, LoopRole, Piece, Region, Rng};
use mesh::{check_conforming, MeshError, VertexMarker};

/// Boundary points about `h` apart (the polygonized rings resampled and projected back onto
/// the boundary; corners included) and hexagonal-lattice points at least `gap·h` inside.
fn sample(region: &Region, h: f64, gap: f64) -> Vec<DVec2> {
    let poly = region.polygonize(1e-3 * h);
    let mut pts: Vec<DVec2> = region.corners().iter().map(|c| c.pos).collect();
    for ring in &poly.rings {
        let n = ring.points.len();
        let mut carry = 0.0;
        for i in 0..n {
            let (a, b) = (ring.points[i], ring.points[(i + 1) % n]);
            let len = a.distance(b);
            let mut t = carry;
            while t < len {
                pts.push(region.project(a.lerp(b, t / len)).point);
                t += h;
            }
            carry = t - len;
        }
    }
    // Keep every corner; drop boundary samples that crowd a corner or each other.
    let ncorners = region.corners().len();
    let mut kept: Vec<DVec2> = pts[..ncorners].to_vec();
    for p in pts.into_iter().skip(ncorners) {
        if kept.iter().all(|q| q.distance(p) > 0.5 * h) {
            kept.push(p);
        }
    }
    let (lo, hi) = region.bbox();
    let dy = h * 0.75f64.sqrt();
    let mut j = 0;
    let mut y = lo.y;
    while y <= hi.y {
        let mut x = lo.x + if j % 2 == 1 { 0.5 * h } else { 0.0 };
        while x <= hi.x {
            let p = DVec2::new(x, y);
            if region.signed_distance(p) < -gap * h {
                kept.push(p);
            }
            x += h;
        }
        y += dy;
        j += 1;
    }
    kept
}

fn mesh_and_check(region: &Region, pts: &[DVec2]) -> mesh::Mesh {
    let tol = 1e-9 * region.diameter();
    let markers = mark_vertices(pts, region, tol);
    let mesh =
        conforming_mesh(pts, &markers, region).unwrap_or_else(|e| panic!("{}: {e}", region.name()));
    check_conforming(&mesh, region).unwrap_or_else(|e| panic!("{}: {e}", region.name()));
    same_from_a_triangulation(region, pts, &markers, &mesh);
    mesh
}

/// Each triangle from its smallest index, the list sorted: the triangles as a set.
fn triangle_set(mesh: &mesh::Mesh) -> Vec<[u32; 3]> {
    let mut t: Vec<[u32; 3]> = mesh
        .triangles
        .iter()
        .map(|t| {
            let k = (0..3).min_by_key(|&k| t[k]).unwrap();
            [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
        })
        .collect();
    t.sort_unstable();
    t
}

/// `conforming_mesh_from` gives `conforming_mesh`'s mesh (its points, markers and triangles,
/// in some order) from a fresh triangulation of the points, and from a framed one of the
/// points moved a little, which it repairs.
fn same_from_a_triangulation(
    region: &Region,
    pts: &[DVec2],
    markers: &[VertexMarker],
    mesh: &mesh::Mesh,
) {
    let (lo, hi) = region.bbox();
    let mut rng = Rng::new(9);
    let step = 1e-4 * region.diameter() / (pts.len() as f64).sqrt();
    let moved: Vec<DVec2> = pts
        .iter()
        .map(|&p| p + DVec2::new(rng.range(-step, step), rng.range(-step, step)))
        .collect();
    let mut framed = Delaunay::framed(lo, hi);
    framed.rebuild(&moved);
    for mut del in [Delaunay::new(pts), framed] {
        let from = conforming_mesh_from(&mut del, pts, markers, region)
            .unwrap_or_else(|e| panic!("{}: {e}", region.name()));
        assert_eq!(from.points, mesh.points, "{}", region.name());
        assert_eq!(from.markers, mesh.markers, "{}", region.name());
        assert_eq!(triangle_set(&from), triangle_set(mesh), "{}", region.name());
    }
}

#[test]
fn every_paper_region_meshes_conformingly() {
    for name in Region::builtin_names() {
        let region = Region::builtin(name).unwrap();
        let h = region.diameter() / 30.0;
        let pts = sample(&region, h, 0.4);
        let mesh = mesh_and_check(&region, &pts);
        // Nothing is dropped when interior points keep clear of the boundary.
        assert_eq!(mesh.num_vertices(), pts.len(), "{name}");
        // The mesh covers the region up to the chord error of curved pieces.
        let rel = (mesh.area() - region.area()).abs() / region.area();
        assert!(
            rel < 0.02,
            "{name}: mesh area {} vs {}",
            mesh.area(),
            region.area()
        );
        assert!(
            mesh.min_angle_deg() > 1.0,
            "{name}: min angle {}",
            mesh.min_angle_deg()
        );
    }
}

#[test]
fn markers_distinguish_corners_boundary_and_interior() {
    let region = Region::builtin("lake").unwrap();
    let h = region.diameter() / 40.0;
    let pts = sample(&region, h, 0.4);
    let markers = mark_vertices(&pts, &region, 1e-9 * region.diameter());
    let ncorners = region.corners().len();
    // The corners come first in `sample`.
    for (k, m) in markers.iter().take(ncorners).enumerate() {
        let VertexMarker::Corner { corner, .. } = *m else {
            panic!("{k}: {m:?}")
        };
        assert_eq!(region.corners()[corner].pos, pts[k]);
    }
    for (p, m) in pts.iter().zip(&markers) {
        let sd = region.signed_distance(*p);
        assert_eq!(m.on_boundary(), sd.abs() < 1e-6 * h, "{p}: {m:?}, sd {sd}");
        if let VertexMarker::Boundary {
            loop_index,
            loop_param,
            ..
        } = *m
        {
            assert!(
                loop_index < 2
                    && loop_param >= 0.0
                    && loop_param <= region.loops()[loop_index].length + 1e-9
            );
        }
    }
}

#[test]
fn interior_points_outside_the_chords_are_dropped() {
    // A coarse circle: 24 boundary points, and interior points between chords and the arc.
    let region = Region::builtin("circle").unwrap();
    let mut pts: Vec<DVec2> = (0..24)
        .map(|i| DVec2::from_angle(std::f64::consts::TAU * i as f64 / 24.0))
        .collect();
    let mut rng = Rng::new(4);
    for _ in 0..300 {
        let p = DVec2::from_angle(rng.range(0.0, 6.3)) * rng.uniform().sqrt() * 0.85;
        pts.push(p);
    }
    // Just inside the arc, halfway between two boundary points: outside their chord.
    let outside_chord: Vec<DVec2> = (0..24)
        .map(|i| DVec2::from_angle(std::f64::consts::TAU * (i as f64 + 0.5) / 24.0) * 0.999)
        .collect();
    pts.extend(&outside_chord);
    let mesh = mesh_and_check(&region, &pts);
    assert_eq!(mesh.num_vertices(), 24 + 300);
    assert!(outside_chord.iter().all(|p| !mesh.points.contains(p)));
}

#[test]
fn interior_points_on_or_hugging_a_chord_are_dropped() {
    // Four boundary points of the unit circle; (0.5, 0.5) lies exactly on the chord from
    // (1, 0) to (0, 1), and another point a hair inside the chord to (−1, 0) would make a
    // sliver triangle.
    let region = Region::builtin("circle").unwrap();
    let mut pts = vec![
        DVec2::new(1.0, 0.0),
        DVec2::new(0.0, 1.0),
        DVec2::new(-1.0, 0.0),
        DVec2::new(0.0, -1.0),
    ];
    for i in -3..=3 {
        for j in -3..=3 {
            let p = DVec2::new(i as f64, j as f64) * 0.15 + DVec2::new(0.01, 0.02);
            pts.push(p);
        }
    }
    let on_chord = DVec2::new(0.5, 0.5);
    let hugging = DVec2::new(-0.5, 0.5) + DVec2::new(1.0, -1.0) * 1e-15;
    pts.extend([on_chord, hugging]);
    let mesh = mesh_and_check(&region, &pts);
    assert_eq!(mesh.num_vertices(), pts.len() - 2);
    assert!(!mesh.points.contains(&on_chord) && !mesh.points.contains(&hugging));
}

#[test]
fn nearly_collinear_boundary_points_make_no_slivers() {
    // Slanted straight sides sampled densely: consecutive boundary points are collinear only up
    // to rounding, which would otherwise leave zero-area triangles along the sides.
    let c = [
        DVec2::new(0.0, 0.0),
        DVec2::new(1.0, 0.3),
        DVec2::new(0.7, 1.1),
        DVec2::new(-0.2, 0.8),
    ];
    let pieces = (0..4)
        .map(|i| Piece::Line {
            a: c[i],
            b: c[(i + 1) % 4],
        })
        .collect();
    let region = Region::new("slanted", vec![(LoopRole::Outer, pieces)], None).unwrap();
    let mut pts = Vec::new();
    for i in 0..4 {
        for k in 0..97 {
            pts.push(c[i].lerp(c[(i + 1) % 4], k as f64 / 97.0));
        }
    }
    let mut rng = Rng::new(8);
    while pts.len() < 3000 {
        let p = DVec2::new(rng.range(-0.2, 1.0), rng.range(0.0, 1.1));
        if region.signed_distance(p) < -0.01 {
            pts.push(p);
        }
    }
    let mesh = mesh_and_check(&region, &pts);
    assert_eq!(mesh.num_vertices(), pts.len());
    assert!((mesh.area() - region.area()).abs() < 1e-12 * region.area());
}

#[test]
fn bad_requests_are_errors() {
    let region = Region::builtin("annulus").unwrap();
    let pts = sample(&region, 0.1, 0.4);
    let markers = mark_vertices(&pts, &region, 1e-9);
    let err = conforming_mesh(&pts, &markers[1..], &region).unwrap_err();
    assert!(matches!(err, MeshError::BadRequest(_)));
    // Only two boundary vertices on the hole.
    let mut p2: Vec<DVec2> = (0..pts.len())
        .filter(|&i| markers[i].loop_index() != Some(1))
        .map(|i| pts[i])
        .collect();
    p2.extend([DVec2::new(0.4, 0.0), DVec2::new(-0.4, 0.0)]);
    let m2 = mark_vertices(&p2, &region, 1e-9);
    assert_eq!(m2.iter().filter(|m| m.loop_index() == Some(1)).count(), 2);
    let err = conforming_mesh(&p2, &m2, &region).unwrap_err();
    assert!(err.to_string().contains("loop 1"), "{err}");
    // A reflex corner of the lake skipped by the boundary vertices: the chord leaves the region.
    let lake = Region::builtin("lake").unwrap();
    let pts = sample(&lake, lake.diameter() / 30.0, 0.4);
    let markers = mark_vertices(&pts, &lake, 1e-9 * lake.diameter());
    let skip = (0..lake.corners().len())
        .find(|&c| {
            let p = lake.corners()[c].pos;
            // Reflex: a point just beyond the corner, away from the centroid of its neighbours, is inside.
            let n = lake.corners().len();
            let mid = (lake.corners()[(c + 1) % n].pos + lake.corners()[(c + n - 1) % n].pos) * 0.5;
            let chord = lake.corners()[(c + 1) % n]
                .pos
                .distance(lake.corners()[(c + n - 1) % n].pos);
            lake.corners()[c].loop_index == 0
                && lake.signed_distance(mid) > 0.2 * chord
                && lake.signed_distance(p + (p - mid) * 0.01) < 0.0
        })
        .expect("the lake has reflex corners");
    let (p3, m3): (Vec<DVec2>, Vec<VertexMarker>) = pts
        .iter()
        .zip(&markers)
        .enumerate()
        .filter(|(i, _)| *i != skip)
        .map(|(_, (p, m))| (*p, *m))
        .unzip();
    let Err(err) = conforming_mesh(&p3, &m3, &lake) else {
        panic!("skipping corner {skip} was accepted")
    };
    assert!(err.to_string().contains("leaves the region"), "{err}");
    // Three outer boundary points: their chords (at radius 0.5) cut through a hole of radius 0.6.
    let hole = Piece::Circle {
        center: DVec2::ZERO,
        radius: 0.6,
        ccw: false,
    };
    let outer = Piece::Circle {
        center: DVec2::ZERO,
        radius: 1.0,
        ccw: true,
    };
    let region = Region::new(
        "thin",
        vec![(LoopRole::Outer, vec![outer]), (LoopRole::Hole, vec![hole])],
        None,
    )
    .unwrap();
    let mut pts: Vec<DVec2> = (0..3)
        .map(|i| DVec2::from_angle(std::f64::consts::TAU * i as f64 / 3.0))
        .collect();
    pts.extend((0..40).map(|i| DVec2::from_angle(-std::f64::consts::TAU * i as f64 / 40.0) * 0.6));
    let markers = mark_vertices(&pts, &region, 1e-9);
    let err = conforming_mesh(&pts, &markers, &region).unwrap_err();
    assert!(err.to_string().contains("crosses"), "{err}");
    // A non-finite point.
    pts[5] = DVec2::NAN;
    assert!(conforming_mesh(&pts, &markers, &region).is_err());
}

#[test]
fn a_boundary_point_within_rounding_of_another_is_dropped() {
    // The unit square's bottom side carries (0.5, 0) and a second point 1e-12 to its right:
    // every triangle on the pair is a sliver. Dropping the interior points it meets, one after
    // another, never ended; one of the pair goes instead.
    let pieces = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)].map(|(x, y)| DVec2::new(x, y));
    let region = Region::new(
        "square",
        vec![(
            LoopRole::Outer,
            (0..4)
                .map(|i| Piece::Line {
                    a: pieces[i],
                    b: pieces[(i + 1) % 4],
                })
                .collect(),
        )],
        None,
    )
    .unwrap();
    let mut pts = sample(&region, 0.1, 0.3);
    assert!(pts.contains(&DVec2::new(0.5, 0.0)));
    pts.push(DVec2::new(0.5 + 1e-12, 0.0));
    let mesh = mesh_and_check(&region, &pts);
    assert_eq!(mesh.num_vertices(), pts.len() - 1);
    assert!((mesh.area() - 1.0).abs() < 1e-12);
}
