//! MESHGEN end to end on the paper's regions.
use cvtmesh_meshgen::Meshgen;
use testkit::*;

#[test]
fn circle_medium_mesh() {
    let r = mesh_and_check(&Meshgen, "circle", 88);
    // Converged or not (a closed loop lets the mesh turn slowly), the shape is good and the
    // approximate CVT energy went down from the jittered lattice.
    assert!(
        r.mesh.min_angle_deg() > 30.0,
        "min angle {}",
        r.mesh.min_angle_deg()
    );
    assert!(r.energy_history.last() < r.energy_history.first());
}

#[test]
fn square_with_a_hole_converges() {
    let r = mesh_and_check(&Meshgen, "square_hole", 194);
    assert!(
        r.converged,
        "last moves {:?}",
        &r.move_history[r.move_history.len() - 3..]
    );
    assert!(r.iterations < 1000);
}

#[test]
fn capped_run_reports_not_converged() {
    capped_run_is_not_converged(&Meshgen);
}

#[test]
fn same_seed_same_mesh() {
    seed_determines_the_mesh(&Meshgen);
}

#[test]
fn impossible_requests() {
    bad_requests_are_errors(&Meshgen);
}

/// The paper's K of each region, in `Region::builtin_names()` order (largest where several).
const PAPER_K: [usize; 10] = [362, 303, 194, 240, 138, 505, 136, 287, 203, 1109];

#[test]
fn every_paper_region_after_forty_iterations() {
    // Conformity, exact K, corners and markers hold at every iterate, not only at convergence.
    for (name, k) in geometry::Region::builtin_names().iter().zip(PAPER_K) {
        let r = mesh_and_check_with(&Meshgen, name, &mesh::MeshRequest::points(k).max_iter(40));
        assert_eq!(
            r.iterations, 40,
            "{name} cannot converge to 1e-4 in 40 iterations"
        );
    }
}

#[test]
#[ignore = "slow: every paper region at its paper K to convergence (run with --release -- --ignored)"]
fn all_paper_regions() {
    for (name, k) in geometry::Region::builtin_names().iter().zip(PAPER_K) {
        let r = mesh_and_check(&Meshgen, name, k);
        eprintln!(
            "{name} K={k}: {} iterations, converged {}",
            r.iterations, r.converged
        );
    }
}
