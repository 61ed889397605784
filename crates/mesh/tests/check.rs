//! The conformity check catches the ways a mesh can fail its region.
use cvtmesh_mesh::{
    check_conforming, slivers, triangle_min_angle_deg, ConformityError, Mesh, VertexMarker,
    SLIVER_ANGLE_DEG,
};
use geometry::{DVec2, LoopRole, Piece, Region};

#[path = "support/square.rs"]
mod structured;
use structured::unit_square_mesh;

fn square(lo: f64, hi: f64) -> Vec<DVec2> {
    vec![
        DVec2::new(lo, lo),
        DVec2::new(hi, lo),
        DVec2::new(hi, hi),
        DVec2::new(lo, hi),
    ]
}

fn lines(p: &[DVec2]) -> Vec<Piece> {
    (0..p.len())
        .map(|i| Piece::Line {
            a: p[i],
            b: p[(i + 1) % p.len()],
        })
        .collect()
}

/// [0,4]² minus [1,3]².
fn frame_region() -> Region {
    let mut hole = square(1.0, 3.0);
    hole.reverse();
    Region::new(
        "frame",
        vec![
            (LoopRole::Outer, lines(&square(0.0, 4.0))),
            (LoopRole::Hole, lines(&hole)),
        ],
        None,
    )
    .unwrap()
}

fn on(loop_index: usize) -> VertexMarker {
    VertexMarker::Boundary {
        loop_index,
        piece: 0,
        loop_param: 0.0,
    }
}

/// Eight vertices, eight triangles around the hole.
fn frame_mesh() -> Mesh {
    let mut points = square(0.0, 4.0);
    points.extend(square(1.0, 3.0));
    let mut triangles = Vec::new();
    for i in 0..4u32 {
        let (o0, o1, h0, h1) = (i, (i + 1) % 4, 4 + i, 4 + (i + 1) % 4);
        triangles.push([o0, o1, h1]);
        triangles.push([o0, h1, h0]);
    }
    let markers = (0..8).map(|i| on(usize::from(i >= 4))).collect();
    Mesh {
        points,
        triangles,
        markers,
    }
}

#[test]
fn a_frame_around_the_hole_conforms() {
    check_conforming(&frame_mesh(), &frame_region()).unwrap();
}

#[test]
fn triangles_across_the_hole_are_caught() {
    let m = Mesh {
        points: square(0.0, 4.0),
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        markers: vec![on(0); 4],
    };
    let e = check_conforming(&m, &frame_region()).unwrap_err();
    assert!(
        matches!(
            e,
            ConformityError::LoopUncovered(1, 0) | ConformityError::TriangleOutside(..)
        ),
        "{e}"
    );
}

#[test]
fn a_missing_triangle_is_caught() {
    let mut m = frame_mesh();
    let [a, b, c] = m.triangles.pop().unwrap();
    // Its edge across the frame, from the outer loop to the hole, is left on one triangle:
    // a boundary edge between two loops.
    let e = check_conforming(&m, &frame_region()).unwrap_err();
    match e {
        ConformityError::CrossLoopEdge(u, w) => {
            assert!([a, b, c].contains(&u) && [a, b, c].contains(&w), "{e}");
        }
        _ => panic!("expected a boundary edge across the loops, got {e}"),
    }
}

#[test]
fn an_inverted_triangle_is_caught() {
    let mut m = frame_mesh();
    m.triangles[0].swap(1, 2);
    assert!(matches!(
        check_conforming(&m, &frame_region()),
        Err(ConformityError::Degenerate(0, _))
    ));
}

#[test]
fn marker_count_and_interior_markers_on_the_hull_are_caught() {
    let mut m = frame_mesh();
    m.markers.pop();
    assert_eq!(
        check_conforming(&m, &frame_region()),
        Err(ConformityError::MarkerCount(7, 8))
    );
    let mut m = frame_mesh();
    m.markers[0] = VertexMarker::Interior;
    assert!(matches!(
        check_conforming(&m, &frame_region()),
        Err(ConformityError::OpenBoundary(..))
    ));
}

#[test]
fn a_repeated_edge_is_reported_where_its_second_copy_comes() {
    let mut m = frame_mesh();
    // Copies of triangles 5 ([2, 7, 6]) and 0, in that order: the first edge seen twice, in
    // triangle order, is triangle 5's first.
    m.triangles.push(m.triangles[5]);
    m.triangles.push(m.triangles[0]);
    assert_eq!(m.triangles[5], [2, 7, 6]);
    assert_eq!(
        check_conforming(&m, &frame_region()),
        Err(ConformityError::NonManifold(2, 7))
    );
}

#[test]
fn a_vertex_in_no_triangle_is_caught() {
    let mut m = frame_mesh();
    m.points.push(DVec2::new(0.5, 0.5));
    m.markers.push(VertexMarker::Interior);
    assert_eq!(
        check_conforming(&m, &frame_region()),
        Err(ConformityError::Orphan(8))
    );
}

#[test]
fn a_triangle_across_a_hole_is_caught_however_deep_its_corners() {
    // The square [0, 40]² with a hole [12, 28]², and a triangle (5, 5), (35, 5), (35, 35)
    // whose corners are 5 deep and whose long side passes over the hole.
    let mut hole = square(12.0, 28.0);
    hole.reverse();
    let region = Region::new(
        "square with a hole",
        vec![
            (LoopRole::Outer, lines(&square(0.0, 40.0))),
            (LoopRole::Hole, lines(&hole)),
        ],
        None,
    )
    .unwrap();
    let mut points = square(0.0, 40.0);
    points.extend(square(12.0, 28.0));
    points.extend([(5.0, 5.0), (35.0, 5.0), (35.0, 35.0)].map(|(x, y)| DVec2::new(x, y)));
    let mut markers: Vec<VertexMarker> = (0..4).map(|_| on(0)).collect();
    markers.extend((0..4).map(|_| on(1)));
    markers.extend((0..3).map(|_| VertexMarker::Interior));
    let m = Mesh {
        points,
        triangles: vec![[8, 9, 10]],
        markers,
    };
    assert!(matches!(
        check_conforming(&m, &region),
        Err(ConformityError::TriangleOutside(0, ..))
    ));
}

#[test]
fn the_reported_problem_does_not_depend_on_hash_order() {
    let mut m = frame_mesh();
    for k in 0..8 {
        m.markers[k] = VertexMarker::Interior;
    }
    let first = check_conforming(&m, &frame_region()).unwrap_err();
    for _ in 0..5 {
        assert_eq!(check_conforming(&m, &frame_region()).unwrap_err(), first);
    }
}

#[test]
fn rounding_at_large_coordinates_is_not_a_vertex_outside() {
    // The frame shrunk to 0.04 across and moved to (10⁶, 10⁶): a vertex one rounding step
    // (1.2e-10) outside its boundary, where 1e-9 of the diameter is 5.7e-11.
    let at = |p: DVec2| DVec2::splat(1e6) + 0.01 * p;
    let mut hole = square(1.0, 3.0);
    hole.reverse();
    let outer: Vec<DVec2> = square(0.0, 4.0).into_iter().map(at).collect();
    let hole: Vec<DVec2> = hole.into_iter().map(at).collect();
    let region = Region::new(
        "far",
        vec![
            (LoopRole::Outer, lines(&outer)),
            (LoopRole::Hole, lines(&hole)),
        ],
        None,
    )
    .unwrap();
    let mut mesh = frame_mesh();
    for p in &mut mesh.points {
        *p = at(*p);
    }
    check_conforming(&mesh, &region).unwrap();
    let ulp = 1e6f64.next_up() - 1e6;
    mesh.points[0].x -= ulp;
    assert!(region.signed_distance(mesh.points[0]) > 1e-9 * region.diameter());
    check_conforming(&mesh, &region).unwrap();
    // A real excursion is still caught.
    mesh.points[0].x -= 1e-6;
    assert!(matches!(
        check_conforming(&mesh, &region),
        Err(ConformityError::VertexOutside(0, ..))
    ));
}

#[test]
fn slivers_are_counted_and_located_at_the_short_side_of_the_flattest() {
    // The frame's triangles have angles of 45° and more: none reported.
    assert_eq!(slivers(&frame_mesh()), None);
    let p = |x: f64, y: f64| DVec2::new(x, y);
    // An equilateral triangle; a flat cap of 0.05° with a triangle on one of its short sides,
    // so that its smallest angle lies between a boundary edge and an inner one; a lone wedge
    // of 0.29°, whose smallest angle lies between two boundary edges (forced by the boundary,
    // not counted).
    let mesh = Mesh {
        points: vec![
            p(0.0, 0.0),
            p(1.0, 0.0),
            p(0.5, 0.75f64.sqrt()),
            p(20.0, 0.0),
            p(22.0, 0.0),
            p(21.2, 0.001),
            p(21.0, 1.0),
            p(30.0, 0.0),
            p(40.0, 0.0),
            p(40.0, 0.05),
        ],
        triangles: vec![[0, 1, 2], [3, 4, 5], [3, 5, 6], [7, 8, 9]],
        markers: vec![VertexMarker::Interior; 10],
    };
    let s = slivers(&mesh).expect("the cap");
    assert_eq!((s.count, s.triangles, s.points), (1, 4, 10));
    let cap = 0.001f64.atan2(1.2).to_degrees();
    assert!((s.smallest_deg - cap).abs() < 1e-9, "{}", s.smallest_deg);
    assert!(s.smallest_deg < SLIVER_ANGLE_DEG);
    // The cap's shortest side runs from (22, 0) to its apex.
    assert!((s.at - p(21.6, 0.0005)).length() < 1e-9, "{:?}", s.at);
    let text = s.to_string();
    assert!(
        text.starts_with("1 of 4 triangles have an angle under 1°"),
        "{text}"
    );
    // Rotated by an arbitrary angle, the same count and angle.
    let (c, sn) = (0.3f64.cos(), 0.3f64.sin());
    let rotated = Mesh {
        points: mesh
            .points
            .iter()
            .map(|q| p(c * q.x - sn * q.y, sn * q.x + c * q.y))
            .collect(),
        ..mesh.clone()
    };
    let r = slivers(&rotated).expect("still the cap");
    assert_eq!(r.count, 1);
    assert!((r.smallest_deg - s.smallest_deg).abs() < 1e-6);
    // Without the triangle on its side, the cap's angles lie between boundary edges too.
    let lone = Mesh {
        triangles: vec![[0, 1, 2], [3, 4, 5], [7, 8, 9]],
        ..mesh
    };
    assert_eq!(slivers(&lone), None);
}

#[test]
fn the_first_open_edge_in_vertex_order_is_reported_from_a_large_mesh() {
    // 10 000 vertices: the edges are checked in runs of tails in parallel. Two triangles
    // removed, one among the last vertices and one among the first: the edge reported is the
    // first by its tail, the same every time.
    let (square, mut mesh) = unit_square_mesh(100);
    let by_least_vertex = |mesh: &Mesh, low: bool| {
        let keys = (0..mesh.triangles.len()).filter(|&t| {
            mesh.triangles[t]
                .iter()
                .all(|&v| mesh.markers[v as usize] == VertexMarker::Interior)
        });
        let key = |t: &usize| *mesh.triangles[*t].iter().min().expect("three");
        if low {
            keys.min_by_key(key)
        } else {
            keys.max_by_key(key)
        }
        .expect("an interior triangle")
    };
    let late = by_least_vertex(&mesh, false);
    mesh.triangles.remove(late);
    let early = by_least_vertex(&mesh, true);
    let first = *mesh.triangles[early].iter().min().expect("three");
    mesh.triangles.remove(early);
    for _ in 0..5 {
        match check_conforming(&mesh, &square) {
            Err(ConformityError::OpenBoundary(a, _)) => assert_eq!(a, first),
            other => panic!("{other:?}"),
        }
    }
}

/// The sliver rule restated on every triangle's exact angles, independently of the library's
/// boundary-edge and cosine shortcuts: the reference the library's `slivers` must agree with.
fn slivers_by_every_angle(mesh: &Mesh) -> Option<(usize, f64)> {
    let boundary: std::collections::HashSet<(u32, u32)> = mesh
        .boundary_edges()
        .iter()
        .map(|e| (e.a.min(e.b), e.a.max(e.b)))
        .collect();
    let on = |a: u32, b: u32| boundary.contains(&(a.min(b), a.max(b)));
    let mut found: Vec<f64> = Vec::new();
    for (t, v) in mesh.triangles.iter().enumerate() {
        let p = mesh.triangle(t);
        let (i, a) = (0..3)
            .map(|i| {
                let a = (p[(i + 1) % 3] - p[i])
                    .angle_to(p[(i + 2) % 3] - p[i])
                    .abs()
                    .to_degrees();
                (i, if a.is_nan() { 0.0 } else { a })
            })
            .min_by(|x, y| x.1.total_cmp(&y.1))
            .expect("three");
        let forced = on(v[i], v[(i + 1) % 3]) && on(v[i], v[(i + 2) % 3]);
        if a < SLIVER_ANGLE_DEG && !forced {
            found.push(a);
        }
    }
    let least = found.iter().copied().min_by(f64::total_cmp)?;
    Some((found.len(), least))
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(128))]

    /// The smallest angle and the slivers, found by the cosines first, are those of every
    /// triangle's angles, bit for bit: on meshes whose vertices are pushed toward a line (flat
    /// and zero-area triangles), merged (sides of length zero) or sent to infinity.
    #[test]
    fn angles_found_by_their_cosines_are_those_of_every_triangle(
        m in 3usize..9,
        seed in 0u64..u64::MAX,
        flatten in 0.0f64..1.0,
    ) {
        let (_, mut mesh) = unit_square_mesh(m);
        let mut rng = geometry::Rng::new(seed);
        let n = mesh.points.len();
        for k in 0..n {
            match rng.below(8) {
                0 => mesh.points[k].y *= 1.0 - flatten,
                1 => mesh.points[k].y = mesh.points[k].x * 1e-7,
                2 => mesh.points[k] = mesh.points[rng.below(n)],
                3 if rng.below(4) == 0 => mesh.points[k].x = f64::INFINITY,
                _ => {}
            }
        }
        let every = (0..mesh.triangles.len())
            .map(|t| triangle_min_angle_deg(mesh.triangle(t)))
            .fold(f64::INFINITY, f64::min);
        proptest::prop_assert_eq!(mesh.min_angle_deg().to_bits(), every.to_bits());
        let found = slivers(&mesh).map(|s| (s.count, s.smallest_deg));
        proptest::prop_assert_eq!(found, slivers_by_every_angle(&mesh));
    }

    /// A conforming mesh passes in any triangle order and from any corner of each triangle; one
    /// triangle removed, repeated or turned over, or a vertex in no triangle, never passes.
    #[test]
    fn the_verdict_follows_the_mesh_not_its_order(
        m in 3usize..12,
        seed in 0u64..u64::MAX,
        kind in 0usize..4,
        pick in 0usize..10_000,
    ) {
        let (square, mut mesh) = unit_square_mesh(m);
        let mut rng = geometry::Rng::new(seed);
        for t in (1..mesh.triangles.len()).rev() {
            mesh.triangles.swap(t, rng.below(t + 1));
        }
        for tri in mesh.triangles.iter_mut() {
            tri.rotate_left(rng.below(3));
        }
        proptest::prop_assert_eq!(check_conforming(&mesh, &square), Ok(()));
        let t = pick % mesh.triangles.len();
        match kind {
            0 => {
                mesh.triangles.remove(t);
            }
            1 => mesh.triangles.push(mesh.triangles[t]),
            2 => mesh.triangles[t].swap(0, 1),
            _ => {
                mesh.points.push(DVec2::new(0.5, 0.5) / (m - 1) as f64);
                mesh.markers.push(VertexMarker::Interior);
            }
        }
        proptest::prop_assert!(check_conforming(&mesh, &square).is_err(), "mutation {}", kind);
    }
}

/// From 20 000 vertices the deep ones take a bound on their depth from a grid instead of a
/// distance query of their own: the check reports what exact distances report, a deep vertex
/// moved outside, a deep vertex marked as a boundary one (with its exact distance) and a deep
/// triangle turned over.
#[test]
fn a_large_mesh_is_checked_as_exactly_in_its_depths() {
    let m = 160;
    let (square, mesh) = unit_square_mesh(m);
    assert!(mesh.points.len() >= 25_000);
    check_conforming(&mesh, &square).unwrap();
    let centre = (m / 2) * m + m / 2;

    let mut outside = mesh.clone();
    outside.points[centre] = DVec2::new(1.5, 0.5);
    match check_conforming(&outside, &square) {
        Err(ConformityError::VertexOutside(i, ..)) => assert_eq!(i, centre),
        other => panic!("{other:?}"),
    }

    let mut marked = mesh.clone();
    marked.markers[centre] = VertexMarker::on_piece(&square, DVec2::new(1.0, 0.5), 1);
    match check_conforming(&marked, &square) {
        Err(ConformityError::MarkerOffBoundary(i, d)) => {
            assert_eq!(i, centre);
            let p = mesh.points[centre];
            let exact = p.x.min(p.y).min(1.0 - p.x).min(1.0 - p.y);
            assert!((d - exact).abs() < 1e-12, "the exact distance {exact}, {d}");
        }
        other => panic!("{other:?}"),
    }

    // A deep triangle flipped over: degenerate (negative area), found whatever the bounds.
    let mut flipped = mesh.clone();
    let t = flipped
        .triangles
        .iter()
        .position(|t| t.contains(&(centre as u32)))
        .unwrap();
    flipped.triangles[t].swap(0, 1);
    assert!(matches!(
        check_conforming(&flipped, &square),
        Err(ConformityError::Degenerate(i, _)) if i == t
    ));
}
