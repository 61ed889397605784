//! CI regression of the graded comparison: re-run a fast subset and compare it with the
//! committed `results/csv/graded.csv` (rewrite it on purpose with `scripts/refresh_baseline.sh`,
//! which reruns the default study and with it the graded part).
//!
//! Subset: the L-shape (a re-entrant corner, ratio 30) and square_hole (a curved hole) cases
//! with every default graded method, seed 1. The circle case is left out because its CCVT
//! run alone takes as long as the rest together.
//!
//! Tolerances, per value, as for the paper's baseline (`golden.rs`):
//! - K, triangles, edges, iterations, converged, K_requested: equal.
//! - h_min, predicted_K and the measures (unit_share, efficiency, mean_length, the two
//!   angles): |now − committed| ≤ 1e-6 · max(|now|, |committed|) + 1e-15. Every method is
//!   deterministic for a seed; the slack absorbs reduction-order differences of parallel
//!   sums when the thread count differs.
//! - `seconds` is not compared.
mod common;
use common::{baseline_path, close, ABS_TOL, REL_TOL};
use std::collections::BTreeMap;
use std::fmt::Write;
use study::graded::{self, GradedRow, GRADED_METHODS};

#[test]
fn graded_subset_matches_the_committed_baseline() {
    let path = baseline_path("graded.csv");
    let bytes = std::fs::read(&path)
        .unwrap_or_else(|e| panic!("cannot read the baseline {} ({e})", path.display()));
    let committed: Vec<GradedRow> =
        study::record::from_csv(&bytes, &path.display().to_string()).unwrap();
    let committed: BTreeMap<String, GradedRow> =
        committed.into_iter().map(|r| (r.key(), r)).collect();

    let mut jobs = graded::graded_jobs(&GRADED_METHODS, 1);
    jobs.retain(|j| j.case.name != "circle_point");
    assert_eq!(jobs.len(), 2 * GRADED_METHODS.len());
    let results = graded::run_graded(&jobs, None, &|_| {}).unwrap();

    let mut report = String::new();
    let mut compared = 0;
    for r in &results {
        let now = match &r.outcome {
            Ok((row, _)) => row,
            Err(e) => {
                let _ = writeln!(report, "{}: the job failed now: {e}", r.job.label());
                continue;
            }
        };
        let Some(old) = committed.get(&now.key()) else {
            let _ = writeln!(report, "{}: no committed row", now.key());
            continue;
        };
        compared += 1;
        let counts = [
            ("K_requested", old.K_requested, now.K_requested),
            ("K", old.K, now.K),
            ("triangles", old.triangles, now.triangles),
            ("edges", old.edges, now.edges),
            ("iterations", old.iterations, now.iterations),
            (
                "converged",
                usize::from(old.converged),
                usize::from(now.converged),
            ),
        ];
        for (name, a, b) in counts {
            if a != b {
                let _ = writeln!(report, "{:<36} {name:<17} committed {a} now {b}", now.key());
            }
        }
        let values = [
            ("h_min", old.h_min, now.h_min),
            ("predicted_K", old.predicted_K, now.predicted_K),
            ("unit_share", old.unit_share, now.unit_share),
            ("efficiency", old.efficiency, now.efficiency),
            ("mean_length", old.mean_length, now.mean_length),
            ("min_angle_deg", old.min_angle_deg, now.min_angle_deg),
            (
                "min_angle_p1_deg",
                old.min_angle_p1_deg,
                now.min_angle_p1_deg,
            ),
        ];
        for (name, a, b) in values {
            if !close(a, b) {
                let _ = writeln!(
                    report,
                    "{:<36} {name:<17} committed {a:<24e} now {b:<24e}",
                    now.key()
                );
            }
        }
    }
    assert!(
        report.is_empty(),
        "the graded subset differs from {} (tolerance: rel {REL_TOL:e} + abs {ABS_TOL:e}; counts exact).\n\
         If the change is intended, rerun scripts/refresh_baseline.sh and commit the new CSV.\n\n{report}",
        path.display()
    );
    assert_eq!(compared, jobs.len());
}
