//! Every method stops within a few iterations of its request's cancel flag being set. (CCVT
//! solves on rayon's pool and hands reports to the caller's thread through a channel, so the
//! solve may be an iteration or two ahead of the report that sets the flag.) A deadline stops
//! every method too, with a conforming mesh marked not converged.
use cvtmesh::{check_conforming, MeshError, MeshRequest, Method, Region};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

#[test]
fn every_method_hands_back_a_conforming_mesh_at_its_deadline() {
    let region = Region::builtin("lake").unwrap();
    // CCVT from the lattice below 3000 generators, from the outer row at 3000.
    for (method, k) in Method::ALL
        .iter()
        .map(|&m| (m, 2000))
        .chain([(Method::Ccvt, 3000)])
    {
        let request = MeshRequest::points(k).time_limit(Duration::ZERO);
        let r = method
            .run(&region, &request)
            .unwrap_or_else(|e| panic!("{method}: {e}"));
        check_conforming(&r.mesh, &region).unwrap_or_else(|e| panic!("{method}: {e}"));
        assert!(!r.converged, "{method}");
        // CCVT: one evaluation per phase (an ε-phase and the constrained one).
        assert!(
            r.iterations <= 2,
            "{method} at {k}: {} iterations",
            r.iterations
        );
        assert!(
            r.notes.iter().any(|n| n.contains("time limit")),
            "{method}: {:?}",
            r.notes
        );
    }
}

#[test]
fn every_method_stops_when_its_cancel_flag_is_set() {
    let region = Region::builtin("lake").unwrap();
    for method in Method::ALL {
        let stop = Arc::new(AtomicBool::new(false));
        let request = MeshRequest::points(2000).cancel_flag(stop.clone());
        let mut reports = 0;
        let result = method.mesher().mesh(&region, &request, &mut |_| {
            reports += 1;
            if reports == 2 {
                stop.store(true, Ordering::Relaxed);
            }
        });
        match result {
            Err(MeshError::Cancelled {
                method: name,
                iterations,
            }) => {
                assert_eq!(name, method.name());
                assert!(iterations <= 6, "{method}: {iterations} iterations");
                assert!(reports <= 6, "{method}: {reports} reports");
            }
            other => panic!("{method}: {other:?}"),
        }
    }
}

#[test]
fn an_unset_flag_changes_nothing() {
    let region = Region::builtin("square_hole").unwrap();
    let plain = MeshRequest::points(194).seed(2);
    let flagged = plain.clone().cancel_flag(Arc::new(AtomicBool::new(false)));
    let a = Method::Ccvt.run(&region, &plain).unwrap();
    let b = Method::Ccvt.run(&region, &flagged).unwrap();
    assert_eq!(a.mesh, b.mesh);
    assert_eq!(a.iterations, b.iterations);
}
