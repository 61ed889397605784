//! Helpers shared by the tests and examples of the `meshgen` and `vtm` crates (the two
//! relaxation methods built on `meshgen::relax`): end-to-end checks of a method's result, a
//! regular hexagonal patch for unit tests of the vertex targets, and the examples' timed run;
//! the `distmesh` and `refine` tests use its corner and area and graded-density checks. A
//! dev-dependency only; not published.
use geometry::DVec2;
pub use geometry::Region;
pub use mesh::MeshRequest;
use mesh::{check_conforming, Mesh, MeshResult, Mesher, VertexMarker};
use std::collections::HashMap;
use std::time::Instant;

/// Mesh a built-in region with K points; assert everything a method's result must satisfy.
pub fn mesh_and_check(method: &dyn Mesher, name: &str, k: usize) -> MeshResult {
    mesh_and_check_with(method, name, &MeshRequest::points(k))
}

/// [`mesh_and_check`] with a given request.
pub fn mesh_and_check_with(method: &dyn Mesher, name: &str, request: &MeshRequest) -> MeshResult {
    let region = Region::builtin(name).unwrap();
    let k = request.size.points(&region);
    let mut calls = 0;
    let result = method
        .mesh(&region, request, &mut |p| {
            calls += 1;
            assert_eq!(p.iteration, calls);
            assert!(p.max_move.is_finite() && p.max_move >= 0.0);
        })
        .unwrap_or_else(|e| panic!("{} on {name} K={k}: {e}", method.name()));
    let mesh = &result.mesh;
    if let Err(e) = check_conforming(mesh, &region) {
        panic!("{} on {name} K={k}: not conforming: {e}", method.name());
    }
    assert_eq!(mesh.num_vertices(), k, "{name}: exactly K vertices");
    assert_eq!(mesh.markers.len(), k);
    // The triangles tile Ω up to the chords of curved sides.
    let rel = (mesh.area() - region.area()).abs() / region.area();
    assert!(
        rel < 0.02,
        "{name}: mesh area {} vs region {}",
        mesh.area(),
        region.area()
    );
    // Every corner is a vertex, marked as that corner, exactly at its position.
    for (ci, c) in region.corners().iter().enumerate() {
        let hits: Vec<usize> = (0..k)
            .filter(
                |&v| matches!(mesh.markers[v], VertexMarker::Corner { corner, .. } if corner == ci),
            )
            .collect();
        assert_eq!(
            hits.len(),
            1,
            "{name}: corner {ci} must be exactly one vertex"
        );
        assert_eq!(mesh.points[hits[0]], c.pos, "{name}: corner {ci} moved");
    }
    // Boundary vertices lie on the piece their marker names; interior ones strictly inside.
    let eps = 1e-9 * region.diameter();
    let mut on_loop = vec![0usize; region.loops().len()];
    for (p, m) in mesh.points.iter().zip(&mesh.markers) {
        match *m {
            VertexMarker::Boundary {
                piece, loop_index, ..
            } => {
                assert!(
                    region.project_onto_piece(*p, piece).distance < eps,
                    "{name}: off its piece"
                );
                assert_eq!(region.piece_loop(piece), loop_index);
                on_loop[loop_index] += 1;
            }
            VertexMarker::Corner { loop_index, .. } => on_loop[loop_index] += 1,
            VertexMarker::Interior => assert!(
                region.signed_distance(*p) < -eps,
                "{name}: interior vertex on ∂Ω"
            ),
        }
    }
    assert!(
        on_loop.iter().all(|&n| n >= 3),
        "{name}: every loop carries vertices {on_loop:?}"
    );
    // Reporting: one progress call and one move per iteration; converged means below tol.
    assert_eq!(calls, result.iterations);
    assert_eq!(result.move_history.len(), result.iterations);
    let last = *result.move_history.last().unwrap();
    assert_eq!(
        result.converged,
        last < request.tol,
        "{name}: converged flag vs last move {last}"
    );
    assert!(result.converged || result.iterations == request.max_iter);
    assert!(
        mesh.min_angle_deg() > 10.0,
        "{name}: min angle {}",
        mesh.min_angle_deg()
    );
    result
}

/// Every corner of `region` is a vertex of `mesh` carrying its corner marker, and the
/// triangles tile Ω up to the chords of curved pieces (which cut off up to ~6% of the unit
/// circle at K = 19).
pub fn assert_corners_and_area(mesh: &Mesh, region: &Region, k: usize) {
    for (ci, c) in region.corners().iter().enumerate() {
        let v = mesh
            .points
            .iter()
            .position(|p| *p == c.pos)
            .unwrap_or_else(|| panic!("corner {ci} missing"));
        assert!(matches!(mesh.markers[v], VertexMarker::Corner { corner, .. } if corner == ci));
    }
    let rel = (mesh.area() - region.area()).abs() / region.area();
    assert!(
        rel < if k < 50 { 0.08 } else { 0.02 },
        "{}: area {} vs {}",
        region.name(),
        mesh.area(),
        region.area()
    );
}

/// Mesh the square with a hole at K = 300 under a density 16× larger where x > 0: the mesh
/// conforms and, since the spacing goes as ρ^(-1/4), holds about 4× the points per area on
/// the dense side (more than 2.5× asserted).
pub fn graded_density_puts_more_points_where_dense(method: &dyn Mesher) -> MeshResult {
    let region = Region::builtin("square_hole").unwrap();
    let rho = geometry::Density::Function(std::sync::Arc::new(
        |p: DVec2| {
            if p.x > 0.0 {
                16.0
            } else {
                1.0
            }
        },
    ));
    let r = method
        .mesh(&region, &MeshRequest::points(300).density(rho), &mut |_| {})
        .unwrap();
    check_conforming(&r.mesh, &region).unwrap();
    let right = r.mesh.points.iter().filter(|p| p.x > 0.05).count();
    let left = r.mesh.points.iter().filter(|p| p.x < -0.05).count();
    assert!(
        right as f64 > 2.5 * left as f64,
        "right {right}, left {left}"
    );
    r
}

/// `max_iter = 2` cannot reach tol = 1e-4 from the jittered lattice: reported as such.
/// A digitized coastline (2000 vertices, a star with fractal radius noise, corners where it
/// turns by more than 30°) at K = 3000, one iteration: sides between corners shorter than the
/// gap kept at their ends once made the side slots' clamp panic. Any result is fine but a
/// panic; a mesh returned must conform.
pub fn rough_coastline_does_not_panic(method: &dyn Mesher) {
    let n = 2000;
    let kmax = n / 2 - 1;
    let mut rng = geometry::Rng::new(7);
    let phases: Vec<f64> = (0..kmax)
        .map(|_| rng.range(0.0, std::f64::consts::TAU))
        .collect();
    let noise: Vec<f64> = (0..n)
        .map(|i| {
            let t = std::f64::consts::TAU * i as f64 / n as f64;
            (1..=kmax)
                .map(|k| (k as f64).powf(-0.9) * (k as f64 * t + phases[k - 1]).sin())
                .sum()
        })
        .collect();
    let top = noise.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let text: String = noise
        .iter()
        .enumerate()
        .map(|(i, v)| {
            let t = std::f64::consts::TAU * i as f64 / n as f64;
            let r = 10.0 * (1.0 + 0.3 * v / top);
            format!("{} {}\n", r * t.cos(), r * t.sin())
        })
        .collect();
    let region = geometry::formats::loops_from_str(&text, "coast", "coast")
        .unwrap()
        .with_default_corners();
    let request = MeshRequest::points(3000).max_iter(1);
    if let Ok(r) = method.mesh(&region, &request, &mut |_| {}) {
        check_conforming(&r.mesh, &region).unwrap();
    }
}

pub fn capped_run_is_not_converged(method: &dyn Mesher) {
    let region = Region::builtin("circle").unwrap();
    let r = method
        .mesh(&region, &MeshRequest::points(88).max_iter(2), &mut |_| {})
        .unwrap();
    assert!(!r.converged);
    assert_eq!(r.iterations, 2);
    assert_eq!(r.move_history.len(), 2);
    assert!(r.move_history[1] > 1e-4);
    check_conforming(&r.mesh, &region).unwrap();
    assert_eq!(r.mesh.num_vertices(), 88);
}

/// Same seed, same bytes; another seed, another mesh.
pub fn seed_determines_the_mesh(method: &dyn Mesher) {
    let region = Region::builtin("square_hole").unwrap();
    let run = |seed| {
        method
            .mesh(
                &region,
                &MeshRequest::points(120).seed(seed).max_iter(30),
                &mut |_| {},
            )
            .unwrap()
    };
    let (a, b, c) = (run(4), run(4), run(5));
    let bits = |r: &MeshResult| {
        r.mesh
            .points
            .iter()
            .flat_map(|p| [p.x.to_bits(), p.y.to_bits()])
            .collect::<Vec<_>>()
    };
    assert_eq!(bits(&a), bits(&b));
    assert_eq!(a.mesh.triangles, b.mesh.triangles);
    assert_eq!(a.move_history, b.move_history);
    assert_ne!(bits(&a), bits(&c));
}

/// Requests that cannot be met are errors, not panics.
pub fn bad_requests_are_errors(method: &dyn Mesher) {
    let region = Region::builtin("square_two_hex").unwrap();
    assert!(method
        .mesh(&region, &MeshRequest::points(10), &mut |_| {})
        .is_err());
    assert!(method
        .mesh(&region, &MeshRequest::points(2), &mut |_| {})
        .is_err());
    assert!(method
        .mesh(
            &region,
            &MeshRequest::points(200).tol(f64::NAN),
            &mut |_| {}
        )
        .is_err());
}

/// K at the method's least boundary: where the spacing that gives K points puts more than K
/// on the boundary, a coarser boundary that fits is taken and the interior drawn at random;
/// below [`Mesher::min_boundary_points`] the refusal names it.
pub fn least_boundary_is_met_or_named(method: &dyn Mesher) {
    // The hole's chords may not cut into it: more than the 3 + 3 every method needs.
    let annulus = Region::builtin("annulus").unwrap();
    let least = method.min_boundary_points(&annulus);
    assert!(least > mesh::boundary_points_needed(&annulus), "{least}");
    let e = method
        .mesh(&annulus, &MeshRequest::points(least - 1), &mut |_| {})
        .unwrap_err()
        .to_string();
    assert!(e.contains(&format!("needs {least} vertices")), "{e}");
    // hex_hole's twelve corners fit K = 14, although a boundary at the spacing of 14 points
    // has 18.
    let hex = Region::builtin("hex_hole").unwrap();
    assert_eq!(method.min_boundary_points(&hex), 12);
    for k in [13, 14, 16] {
        let r = method
            .mesh(&hex, &MeshRequest::points(k), &mut |_| {})
            .unwrap_or_else(|e| panic!("K = {k}: {e}"));
        assert_eq!(r.mesh.num_vertices(), k);
        check_conforming(&r.mesh, &hex).unwrap();
    }
}

/// A regular hexagonal patch: `rings` rings of equilateral triangles of side 1 around the
/// origin (vertex 0), CCW, every vertex marked interior.
pub fn hex_patch(rings: i32) -> Mesh {
    let a = DVec2::new(1.0, 0.0);
    let b = DVec2::new(0.5, 3f64.sqrt() / 2.0);
    let mut coords: Vec<(i32, i32)> = vec![(0, 0)];
    for i in -rings..=rings {
        for j in -rings..=rings {
            if (i, j) != (0, 0) && i.abs().max(j.abs()).max((i + j).abs()) <= rings {
                coords.push((i, j));
            }
        }
    }
    let idx: HashMap<(i32, i32), u32> = coords
        .iter()
        .enumerate()
        .map(|(k, &c)| (c, k as u32))
        .collect();
    let points = coords
        .iter()
        .map(|&(i, j)| a * i as f64 + b * j as f64)
        .collect();
    let mut triangles = Vec::new();
    for &(i, j) in &coords {
        for t in [
            [(i, j), (i + 1, j), (i, j + 1)],
            [(i, j), (i, j + 1), (i - 1, j + 1)],
        ] {
            if let (Some(&p), Some(&q), Some(&r)) = (idx.get(&t[0]), idx.get(&t[1]), idx.get(&t[2]))
            {
                triangles.push([p, q, r]);
            }
        }
    }
    let markers = vec![VertexMarker::Interior; coords.len()];
    Mesh {
        points,
        triangles,
        markers,
    }
}

/// The examples' body: mesh the built-in region named by the first command-line argument
/// (default `circle`) with K points (second, default 88) and at most `max_iter` iterations
/// (third, default 1000), check the mesh and print its statistics and the wall time.
pub fn timed_run(method: &dyn Mesher) -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let name = args.first().map(String::as_str).unwrap_or("circle");
    let k: usize = args.get(1).map(|s| s.parse()).transpose()?.unwrap_or(88);
    let max_iter: usize = args.get(2).map(|s| s.parse()).transpose()?.unwrap_or(1000);
    let region = Region::builtin(name)?;
    let start = Instant::now();
    let r = method.mesh(
        &region,
        &MeshRequest::points(k).max_iter(max_iter),
        &mut |_| {},
    )?;
    let secs = start.elapsed().as_secs_f64();
    check_conforming(&r.mesh, &region)?;
    println!(
        "{} {name}: K {} K~ {} min angle {:.2} iterations {} converged {} last move {:.2e} seconds {secs:.3}",
        method.name(),
        r.mesh.num_vertices(),
        r.mesh.num_triangles(),
        r.mesh.min_angle_deg(),
        r.iterations,
        r.converged,
        r.move_history.last().copied().unwrap_or(f64::NAN)
    );
    for n in &r.notes {
        println!("  {n}");
    }
    Ok(())
}

/// The end-to-end test suite of a relaxation method: `relaxation_tests!(Meshgen);` in a test
/// file defines, for that [`Mesher`], a medium circle mesh that keeps its shape and lowers its
/// energy, convergence on square_hole, a capped run, seed determinism, bad requests, every
/// paper region after 40 iterations, and (ignored: slow) every paper region to convergence.
#[macro_export]
macro_rules! relaxation_tests {
    ($method:expr) => {
        use $crate::*;

        #[test]
        fn circle_medium_mesh() {
            let r = mesh_and_check(&$method, "circle", 88);
            // The mesh keeps turning slowly on the disc; the stopping rule does not count a
            // rotation of the whole set, so the run converges all the same.
            assert!(
                r.converged && r.iterations < 2000,
                "{} iterations",
                r.iterations
            );
            // The shape is good and the method's energy went down from the jittered lattice.
            assert!(
                r.mesh.min_angle_deg() > 30.0,
                "min angle {}",
                r.mesh.min_angle_deg()
            );
            assert!(r.energy_history.last() < r.energy_history.first());
        }

        #[test]
        fn square_with_a_hole_converges() {
            let r = mesh_and_check(&$method, "square_hole", 194);
            assert!(
                r.converged,
                "last moves {:?}",
                &r.move_history[r.move_history.len() - 3..]
            );
            assert!(r.iterations < 1000);
        }

        #[test]
        fn rough_coastline_with_short_sides() {
            rough_coastline_does_not_panic(&$method);
        }

        #[test]
        fn capped_run_reports_not_converged() {
            capped_run_is_not_converged(&$method);
        }

        #[test]
        fn same_seed_same_mesh() {
            seed_determines_the_mesh(&$method);
        }

        #[test]
        fn impossible_requests() {
            bad_requests_are_errors(&$method);
        }

        #[test]
        fn least_boundary() {
            least_boundary_is_met_or_named(&$method);
        }

        /// Each built-in region at the paper's K (the largest where it has several).
        fn paper_regions() -> impl Iterator<Item = (&'static str, usize)> {
            $crate::Region::builtin_names().iter().map(|&name| {
                let k = $crate::Region::paper_k(name).iter().max();
                (name, *k.expect("every built-in region has a paper K"))
            })
        }

        #[test]
        fn every_paper_region_after_forty_iterations() {
            // Conformity, exact K, corners and markers hold at every iterate, not only at
            // convergence.
            for (name, k) in paper_regions() {
                let request = $crate::MeshRequest::points(k).max_iter(40);
                let r = mesh_and_check_with(&$method, name, &request);
                assert_eq!(
                    r.iterations, 40,
                    "{name} cannot converge to 1e-4 in 40 iterations"
                );
            }
        }

        #[test]
        #[ignore = "slow: every paper region at its paper K to convergence \
                    (run with --release -- --ignored)"]
        fn all_paper_regions() {
            for (name, k) in paper_regions() {
                let r = mesh_and_check(&$method, name, k);
                eprintln!(
                    "{name} K={k}: {} iterations, converged {}",
                    r.iterations, r.converged
                );
            }
        }
    };
}
