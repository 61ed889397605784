//! End-to-end tests of DistMesh.
use cvtmesh_distmesh::{initial_points, DistMesh, GridOrigin};
use geometry::{DVec2, Density, Region};
use mesh::{check_conforming, MeshError, MeshRequest, MeshResult, Mesher};

fn run(name: &str, k: usize, req: MeshRequest) -> (Region, MeshResult) {
    let region = Region::builtin(name).unwrap();
    let r = DistMesh::default()
        .mesh(
            &region,
            &MeshRequest {
                size: mesh::Size::Points(k),
                ..req
            },
            &mut |_| {},
        )
        .unwrap();
    (region, r)
}

fn assert_good(region: &Region, r: &MeshResult, k: usize) {
    let mesh = &r.mesh;
    check_conforming(mesh, region).unwrap_or_else(|e| panic!("{}: {e}", region.name()));
    assert_eq!(mesh.num_vertices(), k, "{}", region.name());
    testkit::assert_corners_and_area(mesh, region, k);
    assert_eq!(r.move_history.len(), r.iterations);
    assert!(r.energy_history.is_empty());
    // DistMesh meshes are nearly equilateral; a sliver would mean a broken truss.
    assert!(
        mesh.min_angle_deg() > 15.0,
        "{}: min angle {}",
        region.name(),
        mesh.min_angle_deg()
    );
}

#[test]
fn circle_88() {
    let (region, r) = run("circle", 88, MeshRequest::points(88));
    assert_good(&region, &r, 88);
    assert!(r.converged, "{:?}", r.notes);
    assert!(*r.move_history.last().unwrap() < 0.001);
}

#[test]
fn square_two_hex_203() {
    let (region, r) = run("square_two_hex", 203, MeshRequest::points(203));
    assert_good(&region, &r, 203);
}

#[test]
fn iteration_cap_is_not_convergence() {
    let (region, r) = run(
        "square_two_hex",
        203,
        MeshRequest::points(203).max_iter(100),
    );
    assert_eq!(r.iterations, 100);
    assert_eq!(r.move_history.len(), 100);
    assert!(!r.converged);
    check_conforming(&r.mesh, &region).unwrap();
    // Stopped long before the boundary is resolved: an error, never a non-conforming mesh.
    let region = Region::builtin("annulus").unwrap();
    for cap in [1, 5, 30] {
        match DistMesh::default().mesh(
            &region,
            &MeshRequest::points(303).max_iter(cap),
            &mut |_| {},
        ) {
            Ok(r) => {
                assert!(!r.converged);
                check_conforming(&r.mesh, &region).unwrap();
            }
            Err(e) => assert!(
                matches!(
                    e,
                    MeshError::Failed { .. } | MeshError::NotConforming { .. }
                ),
                "{e}"
            ),
        }
    }
}

#[test]
fn same_seed_same_mesh() {
    let (_, a) = run("horn", 138, MeshRequest::points(138).seed(7));
    let (_, b) = run("horn", 138, MeshRequest::points(138).seed(7));
    assert_eq!(a.mesh, b.mesh);
    assert_eq!(a.move_history, b.move_history);
}

#[test]
fn surplus_removal_follows_the_seed() {
    // square_two_hex: the grid count jumps over K = 203, so points are removed at random.
    let (_, a) = run("square_two_hex", 203, MeshRequest::points(203).seed(1));
    let (_, b) = run("square_two_hex", 203, MeshRequest::points(203).seed(2));
    assert!(a.notes.iter().any(|n| n.contains("removed at random")));
    assert_ne!(a.mesh.points, b.mesh.points);
    assert_eq!(a.mesh.num_vertices(), b.mesh.num_vertices());
}

#[test]
fn graded_density_puts_more_points_where_dense() {
    let r = testkit::graded_density_puts_more_points_where_dense(&DistMesh::default());
    assert_eq!(r.mesh.num_vertices(), 300);
}

#[test]
fn progress_once_per_iteration() {
    let region = Region::builtin("circle").unwrap();
    let mut its = Vec::new();
    let r = DistMesh::default()
        .mesh(&region, &MeshRequest::points(19), &mut |p| {
            its.push(p.iteration)
        })
        .unwrap();
    assert_eq!(its, (1..=r.iterations).collect::<Vec<_>>());
}

#[test]
fn initial_grid_is_equilateral_and_inside() {
    let region = Region::builtin("square_hole").unwrap();
    let h0 = 0.2;
    let p = initial_points(&region, h0, 0.001, &Density::Uniform, 1, DVec2::ZERO);
    let nfix = region.corners().len();
    assert_eq!(
        &p[..nfix],
        &region.corners().iter().map(|c| c.pos).collect::<Vec<_>>()[..]
    );
    assert!(p.iter().all(|q| region.signed_distance(*q) < 0.001 * h0));
    // Nearest-neighbour distance of grid points is h0 (equilateral lattice).
    let g = &p[nfix..];
    for q in g.iter().take(50) {
        let d = g
            .iter()
            .filter(|r| *r != q)
            .map(|r| (*r - *q).length())
            .fold(f64::INFINITY, f64::min);
        assert!((d - h0).abs() < 1e-12, "{d}");
    }
    // About |Ω| / (√3/2 h0²) lattice points.
    let expect = region.area() / (3f64.sqrt() / 2.0 * h0 * h0);
    assert!(
        (g.len() as f64 - expect).abs() < 0.15 * expect,
        "{} vs {expect}",
        g.len()
    );
}

#[test]
fn a_shifted_grid_is_the_same_lattice_moved() {
    let region = Region::builtin("circle").unwrap();
    let h0 = 0.1;
    let plain = initial_points(&region, h0, 0.001, &Density::Uniform, 1, DVec2::ZERO);
    let shift = GridOrigin::Seeded.shift(7);
    assert!(shift.x > 0.0 && shift.x < 1.0 && shift.y > 0.0 && shift.y < 1.0);
    assert_eq!(
        GridOrigin::Seeded.shift(7),
        shift,
        "the shift is a function of the seed"
    );
    assert_ne!(GridOrigin::Seeded.shift(8), shift);
    assert_eq!(GridOrigin::BoxCorner.shift(7), DVec2::ZERO);
    let moved = initial_points(&region, h0, 0.001, &Density::Uniform, 1, shift);
    // Every point of the shifted grid is a point of the plain lattice moved by the shift
    // (modulo one period), so it is the same lattice translated; and it still covers Ω.
    let (lo, _) = region.bbox();
    let dy = h0 * 3f64.sqrt() / 2.0;
    let t = DVec2::new(shift.x * h0, shift.y * 2.0 * dy);
    for q in &moved {
        let j = ((q.y - (lo.y - t.y)) / dy).round();
        assert!(
            ((q.y - (lo.y - t.y)) / dy - j).abs() < 1e-9,
            "{q} is off the rows"
        );
        let x0 = lo.x - t.x + if j as i64 % 2 == 1 { h0 / 2.0 } else { 0.0 };
        let i = (q.x - x0) / h0;
        assert!((i - i.round()).abs() < 1e-9, "{q} is off its row's points");
        assert!(region.signed_distance(*q) < 0.001 * h0);
    }
    let expect = region.area() / (3f64.sqrt() / 2.0 * h0 * h0);
    for p in [&plain, &moved] {
        assert!(
            (p.len() as f64 - expect).abs() < 0.05 * expect,
            "{}",
            p.len()
        );
    }
    assert_ne!(plain, moved);
}

#[test]
fn a_seeded_grid_origin_varies_the_mesh_by_seed_only() {
    let region = Region::builtin("circle").unwrap();
    let seeded = DistMesh {
        grid_origin: GridOrigin::Seeded,
        ..DistMesh::default()
    };
    let mesh = |m: &DistMesh, seed| {
        let r = m
            .mesh(&region, &MeshRequest::points(88).seed(seed), &mut |_| {})
            .unwrap();
        assert!(r.converged);
        assert_eq!(r.mesh.num_vertices(), 88);
        check_conforming(&r.mesh, &region).unwrap();
        r.mesh
    };
    let (a, b) = (mesh(&seeded, 1), mesh(&seeded, 2));
    assert_ne!(a.points, b.points, "another seed, another grid");
    assert_eq!(
        mesh(&seeded, 1).points,
        a.points,
        "the same seed, the same mesh"
    );
    // The original's grid does not depend on the seed when no surplus point is removed.
    let plain = DistMesh::default();
    assert_eq!(mesh(&plain, 1).points, mesh(&plain, 2).points);
}

#[test]
fn constants_out_of_range_are_refused() {
    let region = Region::builtin("circle").unwrap();
    let base = DistMesh::default();
    for (name, m) in [
        (
            "fscale",
            DistMesh {
                fscale: 0.0,
                ..base.clone()
            },
        ),
        (
            "deltat",
            DistMesh {
                deltat: -0.2,
                ..base.clone()
            },
        ),
        (
            "geps",
            DistMesh {
                geps: f64::NAN,
                ..base.clone()
            },
        ),
        (
            "ttol",
            DistMesh {
                ttol: f64::INFINITY,
                ..base.clone()
            },
        ),
        (
            "dptol",
            DistMesh {
                dptol: 0.0,
                ..base.clone()
            },
        ),
    ] {
        let e = m
            .mesh(&region, &MeshRequest::points(88), &mut |_| {})
            .unwrap_err();
        assert!(
            matches!(e, MeshError::InvalidSetting { setting, .. } if setting == name),
            "{name}: {e:?}"
        );
    }
    assert!(base.validate().is_ok());
}

#[test]
fn too_few_points_is_an_error() {
    let region = Region::builtin("square_two_hex").unwrap();
    let e = DistMesh::default()
        .mesh(&region, &MeshRequest::points(4), &mut |_| {})
        .unwrap_err();
    assert!(
        matches!(e, MeshError::TooFewPoints { requested: 4, .. }),
        "{e:?}"
    );
}

/// All ten paper regions at the paper's K.
#[test]
fn all_paper_regions() {
    for (name, k) in Region::paper_cases() {
        let (region, r) = run(name, k, MeshRequest::points(k));
        assert_good(&region, &r, k);
        eprintln!(
            "{name} K={k}: {} iterations, converged {}, notes {:?}",
            r.iterations, r.converged, r.notes
        );
    }
}

#[test]
fn a_small_region_far_from_the_origin_meshes_as_at_the_origin() {
    // A 0.03-wide hexagon with a square hole, at the origin and at (10⁶, 10⁶): there √ε·h0 is
    // a tenth of the coordinates' rounding step, and the boundary gradient was noise.
    let shape = |at: geometry::DVec2| {
        let hex = (0..6)
            .map(|k| {
                at + 0.015 * geometry::DVec2::from_angle(k as f64 * std::f64::consts::TAU / 6.0)
            })
            .collect();
        let hole = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
            .map(|(x, y)| at + 0.004 * geometry::DVec2::new(x, y))
            .to_vec();
        Region::from_loops(
            "far",
            vec![
                (geometry::LoopRole::Outer, hex),
                (geometry::LoopRole::Hole, hole),
            ],
        )
        .unwrap()
    };
    let request = MeshRequest::points(300);
    let mut angles = Vec::new();
    for at in [geometry::DVec2::ZERO, geometry::DVec2::splat(1e6)] {
        let region = shape(at);
        let r = DistMesh::default()
            .mesh(&region, &request, &mut |_| {})
            .unwrap();
        check_conforming(&r.mesh, &region).unwrap();
        assert_eq!(r.mesh.num_vertices(), 300);
        assert!(r.converged, "at {at}: {:?}", r.notes);
        angles.push(r.mesh.min_angle_deg());
    }
    assert!(
        angles[1] > 20.0 && (angles[0] - angles[1]).abs() < 5.0,
        "{angles:?}"
    );
}
