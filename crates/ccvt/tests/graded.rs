//! Graded CCVT meshes from size fields: the default method starts from a graded point set and
//! converges by the same rule as uniform runs, with edges that follow the field.
use cvtmesh_ccvt::Ccvt;
use geometry::{DVec2, LoopRole, Region, SizeField, Threshold, Toward};
use mesh::{check_conforming, MeshRequest, Mesher};
use metrics::size_conformity;

/// Run the default method on `field` (K from the field) and check convergence, conformity to
/// the region and to the field (smallest angle at least `min_angle`); returns the evaluations
/// it took.
fn graded_run(region: &Region, field: &SizeField, seed: u64, min_angle: f64) -> usize {
    let request = MeshRequest::size_field(field, region, None)
        .unwrap()
        .seed(seed);
    let k = request.validate(region).unwrap();
    let r = Ccvt::default()
        .mesh(region, &request, &mut |_| {})
        .expect("mesh");
    assert!(
        r.converged,
        "{}: not converged in {} evaluations",
        region.name(),
        r.iterations
    );
    assert_eq!(r.mesh.num_vertices(), k);
    check_conforming(&r.mesh, region).unwrap();
    let c = size_conformity(&r.mesh, field, region).unwrap();
    assert!(
        c.unit_share >= 0.95,
        "{}: unit share {}",
        region.name(),
        c.unit_share
    );
    assert!(
        c.efficiency >= 0.9,
        "{}: efficiency {}",
        region.name(),
        c.efficiency
    );
    assert!(
        c.min_angle_deg >= min_angle,
        "{}: min angle {}",
        region.name(),
        c.min_angle_deg
    );
    // Boundary edges as long, relative to the field, as the interior's: an over-populated
    // boundary (interior generators of the start that joined it) gave 0.78 on the L-shape.
    let ratio = boundary_to_interior(&r.mesh, field);
    assert!(
        ratio >= 0.9,
        "{}: boundary edges {ratio} of the interior's",
        region.name()
    );
    r.iterations
}

/// The median of l / h(midpoint) over the boundary edges of `mesh`, over the same median for
/// its interior edges.
fn boundary_to_interior(mesh: &mesh::Mesh, field: &SizeField) -> f64 {
    use std::collections::HashSet;
    let key = |a: u32, b: u32| (a.min(b), a.max(b));
    let boundary: HashSet<(u32, u32)> = mesh
        .boundary_edges()
        .iter()
        .map(|e| key(e.a, e.b))
        .collect();
    let (mut on, mut inside) = (Vec::new(), Vec::new());
    let mut seen = HashSet::new();
    for t in &mesh.triangles {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            if !seen.insert(key(a, b)) {
                continue;
            }
            let (p, q) = (mesh.points[a as usize], mesh.points[b as usize]);
            let l = (q - p).length() / field.at(0.5 * (p + q));
            if boundary.contains(&key(a, b)) {
                on.push(l);
            } else {
                inside.push(l);
            }
        }
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    median(&mut on) / median(&mut inside)
}

#[test]
fn refined_toward_a_hole_converges_and_follows_the_field() {
    // Gmsh's Distance + Threshold toward the hole: a flat band of h_min along it, so the field
    // has a kink on the hole's loop; the grid holds the loop's size inside the hole.
    let region = Region::builtin("square_hole").unwrap();
    let t = Threshold {
        size_min: 0.02,
        size_max: 0.2,
        dist_min: 0.04,
        dist_max: 1.2,
    };
    let field = SizeField::threshold(&region, &[Toward::Loop(1)], t).unwrap();
    let evaluations = graded_run(&region, &field, 1, 30.0);
    // Thousands of evaluations (capped runs) were the failure this guards against.
    assert!(evaluations < 1000, "{evaluations} evaluations");
}

#[test]
fn refined_toward_a_reentrant_corner_converges_and_follows_the_field() {
    let region = Region::from_loops(
        "l_shape",
        vec![(
            LoopRole::Outer,
            vec![
                DVec2::new(0.0, 0.0),
                DVec2::new(1.0, 0.0),
                DVec2::new(1.0, 0.5),
                DVec2::new(0.5, 0.5),
                DVec2::new(0.5, 1.0),
                DVec2::new(0.0, 1.0),
            ],
        )],
    )
    .unwrap();
    let t = Threshold {
        size_min: 0.006,
        size_max: 0.06,
        dist_min: 0.0,
        dist_max: 0.7,
    };
    let field = SizeField::threshold(&region, &[Toward::Point(DVec2::new(0.5, 0.5))], t).unwrap();
    // 36.7° since the start's boundary is resampled; 30.9° before, with flat triangles along
    // an over-populated boundary.
    let evaluations = graded_run(&region, &field, 2, 33.0);
    assert!(evaluations < 1000, "{evaluations} evaluations");
}

#[test]
fn refined_toward_the_outer_loop_from_the_loop_converges() {
    // A boundary layer: h_min on the loop itself, ρ halving across a boundary cell. With one
    // 7-point rule per fan triangle in the boundary cells both runs hit the cap.
    for (name, k) in [("circle", 1000), ("square_hole", 2000)] {
        let region = Region::builtin(name).unwrap();
        let t = Threshold {
            size_min: 0.01,
            size_max: 0.1,
            dist_min: 0.0,
            dist_max: 0.5,
        };
        let field = SizeField::threshold(&region, &[Toward::Loop(0)], t)
            .unwrap()
            .bounded(&region, None, None, Some(0.3))
            .unwrap();
        let request = MeshRequest::size_field(&field, &region, Some(k))
            .unwrap()
            .max_iter(2000);
        let r = Ccvt::default()
            .mesh(&region, &request, &mut |_| {})
            .expect("mesh");
        assert!(
            r.converged,
            "{name}: not converged in {} evaluations",
            r.iterations
        );
        check_conforming(&r.mesh, &region).unwrap();
        assert!(r.iterations < 1000, "{name}: {} evaluations", r.iterations);
    }
}

#[test]
fn graded_runs_are_reproducible() {
    let region = Region::builtin("circle").unwrap();
    let field = SizeField::from_expr("0.03 + 0.1 * sqrt(x^2 + y^2)").unwrap();
    let request = MeshRequest::size_field(&field, &region, Some(600)).unwrap();
    let a = Ccvt::default()
        .mesh(&region, &request, &mut |_| {})
        .unwrap();
    let b = Ccvt::default()
        .mesh(&region, &request, &mut |_| {})
        .unwrap();
    assert_eq!(a.mesh.points, b.mesh.points);
    assert_eq!(a.mesh.triangles, b.mesh.triangles);
}

#[test]
fn a_prolongated_coarse_level_gives_a_converged_mesh_of_exactly_k() {
    let region = Region::builtin("square_hole").unwrap();
    // At 2500 generators a tenth of them lie on ∂Ω, where levels are not taken by default;
    // forced here, to test the levels themselves at a size that runs in a second.
    let ccvt = Ccvt {
        multilevel_from: 1500,
        levels_max_boundary_share: f64::MAX,
        ..Ccvt::default()
    };
    let request = MeshRequest::points(2500);
    let r = ccvt.mesh(&region, &request, &mut |_| {}).unwrap();
    assert!(r.converged);
    assert_eq!(r.mesh.num_vertices(), 2500);
    check_conforming(&r.mesh, &region).unwrap();
    assert!(r
        .notes
        .iter()
        .any(|n| n.contains("every edge of its mesh split")));
    assert!(r.mesh.min_angle_deg() >= 25.0, "{}", r.mesh.min_angle_deg());
}

/// `graded_multilevel_from` decides the levels of a graded run and `multilevel_from` those of a
/// uniform one: the same settings give a graded mesh from a coarser level that follows its
/// field (from two, the coarser taking its own, when the threshold lies below K/4), a uniform
/// mesh without one, and a graded mesh below the threshold without one.
#[test]
fn graded_runs_take_levels_from_their_own_threshold() {
    let region = Region::builtin("circle").unwrap();
    let field = SizeField::from_expr("0.01 + 0.04 * sqrt(x^2 + y^2)").unwrap();
    let request = MeshRequest::size_field(&field, &region, None).unwrap();
    let k = request.validate(&region).unwrap();
    let levels = |notes: &[String]| {
        notes
            .iter()
            .any(|n| n.contains("every edge of its mesh split"))
    };
    // Levels forced at a boundary share they are not taken at by default (see
    // `Ccvt::levels_max_boundary_share`), to test them at a size that runs in seconds.
    let ccvt = Ccvt {
        graded_multilevel_from: k / 2,
        levels_max_boundary_share: f64::MAX,
        ..Ccvt::default()
    };
    let r = ccvt.mesh(&region, &request, &mut |_| {}).unwrap();
    assert!(levels(&r.notes), "{:?}", r.notes);
    assert!(r.converged);
    assert_eq!(r.mesh.num_vertices(), k);
    check_conforming(&r.mesh, &region).unwrap();
    let c = size_conformity(&r.mesh, &field, &region).unwrap();
    assert!(c.unit_share >= 0.95 && c.efficiency >= 0.9, "{c:?}");
    let ratio = boundary_to_interior(&r.mesh, &field);
    assert!(ratio >= 0.9, "{ratio}");
    // A coarser level takes levels of its own by the same rule: K → K/4 → K/16 when the
    // threshold lies below K/4.
    let nested = Ccvt {
        graded_multilevel_from: k / 8,
        ..ccvt.clone()
    };
    let n = nested.mesh(&region, &request, &mut |_| {}).unwrap();
    let starts = n
        .notes
        .iter()
        .filter(|n| n.contains("every edge of its mesh split"))
        .count();
    assert_eq!(starts, 2, "{:?}", n.notes);
    assert!(n.converged);
    assert_eq!(n.mesh.num_vertices(), k);
    check_conforming(&n.mesh, &region).unwrap();
    let uniform = ccvt
        .mesh(&region, &MeshRequest::points(k), &mut |_| {})
        .unwrap();
    assert!(!levels(&uniform.notes), "{:?}", uniform.notes);
    let above = Ccvt {
        graded_multilevel_from: k + 1,
        ..ccvt.clone()
    };
    let r = above.mesh(&region, &request, &mut |_| {}).unwrap();
    assert!(!levels(&r.notes), "{:?}", r.notes);
}

/// Active-set steps start at `Ccvt::active_from` (3000) generators: at about 4300 generators
/// the graded circle and the uniform circle both take them by default and converge, the
/// graded mesh following its field.
#[test]
fn runs_take_active_set_steps_from_3000_generators() {
    let region = Region::builtin("circle").unwrap();
    let field = SizeField::from_expr("0.005 + 0.05 * sqrt(x^2 + y^2)").unwrap();
    let request = MeshRequest::size_field(&field, &region, None).unwrap();
    let k = request.validate(&region).unwrap();
    let ccvt = Ccvt::default();
    assert!(ccvt.active_from <= k && k < 10_000, "{k}");
    let g = ccvt.generators(&region, &request, &mut |_| {}).unwrap();
    assert!(g.converged, "{:?}", g.notes);
    assert!(g.profile.local_evaluations > 0, "no active-set step taken");
    let r = ccvt.mesh(&region, &request, &mut |_| {}).unwrap();
    assert!(r.converged);
    assert_eq!(r.mesh.num_vertices(), k);
    check_conforming(&r.mesh, &region).unwrap();
    let c = size_conformity(&r.mesh, &field, &region).unwrap();
    assert!(c.unit_share >= 0.95 && c.efficiency >= 0.9, "{c:?}");
    let uniform = ccvt
        .generators(&region, &MeshRequest::points(k), &mut |_| {})
        .unwrap();
    assert!(uniform.converged);
    assert!(
        uniform.profile.local_evaluations > 0,
        "no active-set step taken"
    );
}

/// A region from a loop list, its corners by the default angle, and a request for K vertices
/// refined toward its outline as the robustness sweep asks: Threshold sizes `[h_min, h_max,
/// d_min, d_max]`, gradation 0.3.
fn toward_the_outline(text: &str, sizes: [f64; 4], k: usize) -> (Region, MeshRequest) {
    let raw = geometry::formats::loops_from_str(text, "outline", "outline").unwrap();
    let region = raw.with_default_corners();
    let [size_min, size_max, dist_min, dist_max] = sizes;
    let t = Threshold {
        size_min,
        size_max,
        dist_min,
        dist_max,
    };
    let field = SizeField::threshold(&region, &[Toward::Loop(0)], t)
        .unwrap()
        .bounded(&region, None, None, Some(0.3))
        .unwrap();
    let request = MeshRequest::size_field(&field, &region, Some(k)).unwrap();
    (region, request)
}

/// The robustness sweep's comb of twenty teeth 0.02 wide refined toward its outline at
/// K = 20 000, seed 2, the sizes the sweep gives it.
fn comb_at_20000() -> (Region, MeshRequest) {
    let sizes = [0.00353553, 0.0707107, 0.0141421, 0.282843];
    let (region, request) = toward_the_outline(include_str!("data/comb20.txt"), sizes, 20_000);
    (region, request.seed(2))
}

/// A fractal coastline of 5000 vertices (1597 corners kept, 1235 added along its gaps) meshed
/// toward its shore at K = 3000: 168 free generators among 2832 corners. From evaluation 136
/// the iterate cycles and the largest move never again reaches its low; the phase stops
/// unconverged after the work of 300 evaluations without a new low (3193 evaluations, most of
/// them active-set steps counted a tenth each), with a note, instead of running to the cap.
/// About 30 s in release: run with `--ignored`.
#[test]
#[ignore]
fn a_cycling_graded_run_stops_with_a_note_well_before_the_cap() {
    let sizes = [0.00586405, 0.117281, 0.0234562, 0.469124];
    let (region, request) = toward_the_outline(include_str!("data/coast5000.txt"), sizes, 3000);
    let request = request.max_iter(10_000);
    let r = Ccvt::default()
        .mesh_parts(&region, &request, &mut |_| {})
        .unwrap();
    assert!(!r.converged);
    assert!(r.iterations < 5000, "{}", r.iterations);
    assert!(
        r.notes
            .iter()
            .any(|n| n.contains("no new low in the work of 300 evaluations")),
        "{:?}",
        r.notes
    );
}

/// A run from a coarser level that cycles is solved again without levels. The robustness
/// sweep's comb of twenty teeth refined toward its outline at K = 20 000, seed 2, its levels
/// forced from 5000 generators on (by default a graded run takes them from 20 000, but not
/// at the comb's boundary share): the relaxation from the coarser levels stops unconverged
/// (no new low in the work of 300 evaluations), and the single level, solved again, converges
/// (3383 evaluations in all); the default run, one level, converges in fewer. About 60 s in
/// release: run with `--ignored`.
#[test]
#[ignore]
fn a_graded_run_whose_levels_cycle_still_converges() {
    let (region, request) = comb_at_20000();
    let forced = Ccvt {
        levels_max_boundary_share: f64::MAX,
        graded_multilevel_from: 5000,
        ..Ccvt::default()
    };
    let r = forced.mesh(&region, &request, &mut |_| {}).unwrap();
    assert!(r.converged, "{:?}", r.notes);
    // The premise: this case takes the second run (if a change to the solver lets its levels
    // converge, it no longer tests the fallback and wants replacing).
    assert!(
        r.notes
            .iter()
            .any(|n| n.contains("solved again without levels")),
        "{:?}",
        r.notes
    );
    assert_eq!(r.mesh.num_vertices(), 20_000);
    check_conforming(&r.mesh, &region).unwrap();
    let single = Ccvt::default()
        .mesh(&region, &request, &mut |_| {})
        .unwrap();
    assert!(single.converged, "{:?}", single.notes);
    assert!(
        !single
            .notes
            .iter()
            .any(|n| n.contains("every edge of its mesh split")),
        "{:?}",
        single.notes
    );
    assert!(single.iterations < r.iterations);
    check_conforming(&single.mesh, &region).unwrap();
}

/// A graded run converges through hundreds of cheap active-set steps, which the stall rule
/// must not take for cycling. A comb of twenty teeth 0.02 wide (the robustness sweep's
/// `comb20`) refined toward its outline at K = 20 000, seed 2: it ended unconverged after 944
/// evaluations when each active-set step counted as a whole evaluation, and converges in about
/// 980 (14 s in a release build) when it counts the share of the generators it moves.
#[test]
#[ignore]
fn a_graded_run_of_many_active_set_steps_is_not_taken_for_a_cycle() {
    let (region, request) = comb_at_20000();
    let r = Ccvt::default()
        .mesh_parts(&region, &request, &mut |_| {})
        .unwrap();
    assert!(r.converged, "{} evaluations, {:?}", r.iterations, r.notes);
    check_conforming(&r.mesh, &region).unwrap();
}
