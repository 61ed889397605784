//! CI regression: re-run a fast subset of the study and compare it with the committed
//! baseline `results/csv/metrics.csv` (rewrite it on purpose with `scripts/refresh_baseline.sh`).
//!
//! Subset: circle K = 19 and K = 88 and square_two_hex K = 203 (Tables 1, 2, 11: a smooth
//! boundary, and corners with two holes), every method, seed 1, both exact and sampled rows.
//!
//! Tolerances, per value:
//! - K, K̃, iterations, converged: equal.
//! - the 12 measures: |now − committed| ≤ 1e-6 · max(|now|, |committed|) + 1e-15. Every method
//!   is deterministic for a seed and Rust does no floating-point contraction, so on this
//!   platform the numbers are normally bit-identical whatever the optimisation level; the
//!   slack absorbs reduction-order differences of parallel sums when the thread count differs.
//! - `seconds` is not compared.
mod common;
use common::{baseline_path, close, ABS_TOL, REL_TOL};
use std::collections::BTreeMap;
use std::fmt::Write;
use study::{job_list, run, Kind, Measure, MethodId, Row};

fn rel_diff(a: f64, b: f64) -> f64 {
    if a == b || (a.is_nan() && b.is_nan()) {
        return 0.0;
    }
    (a - b).abs() / a.abs().max(b.abs())
}

#[test]
fn fast_subset_matches_the_committed_baseline() {
    let path = baseline_path("metrics.csv");
    let committed: Vec<Row> = study::record::read_csv(&path).unwrap_or_else(|e| {
        panic!(
            "cannot read the baseline {} ({e}); create it with scripts/refresh_baseline.sh",
            path.display()
        )
    });
    let committed: BTreeMap<String, Row> = committed.into_iter().map(|r| (r.key(), r)).collect();

    let mut jobs = job_list(&["circle"], &MethodId::ALL, 1);
    jobs.retain(|j| j.k() <= 88);
    jobs.extend(job_list(&["square_two_hex"], &MethodId::ALL, 1));
    let regions = run::load_regions(&["circle", "square_two_hex"]).unwrap();
    let results = run::run_jobs(&jobs, &regions, None, &|_| {}).unwrap();

    let mut report = String::new();
    let mut compared = 0;
    for r in &results {
        let out = match &r.outcome {
            Ok(o) => o,
            Err(e) => {
                let _ = writeln!(report, "{}: the job failed now: {e}", r.job.label());
                continue;
            }
        };
        for now in &out.rows {
            let Some(old) = committed.get(&now.key()) else {
                let _ = writeln!(
                    report,
                    "{}: no committed row (refresh the baseline?)",
                    now.key()
                );
                continue;
            };
            compared += 1;
            let who = format!(
                "{} K={} {} {:?}",
                now.region, now.K_requested, now.method, now.kind
            )
            .to_lowercase();
            for m in Measure::ALL {
                let (a, b) = (old.value(m), now.value(m));
                let ok = if m.is_count() { a == b } else { close(a, b) };
                if !ok {
                    let _ = writeln!(
                        report,
                        "{who:<40} {:<7} committed {a:<24e} now {b:<24e} rel. diff {:.2e}",
                        m.csv_name(),
                        rel_diff(a, b)
                    );
                }
            }
            if (old.iterations, old.converged) != (now.iterations, now.converged) {
                let _ = writeln!(
                    report,
                    "{who:<40} iterations/converged: committed {}/{} now {}/{}",
                    old.iterations, old.converged, now.iterations, now.converged
                );
            }
        }
    }
    assert_eq!(results.len(), 3 * MethodId::ALL.len());
    assert!(
        report.is_empty(),
        "the fast subset differs from {} (tolerance: rel {REL_TOL:e} + abs {ABS_TOL:e}; counts exact).\n\
         If the change is intended, rerun scripts/refresh_baseline.sh and commit the new CSV.\n\n{report}",
        path.display()
    );
    assert_eq!(compared, results.len() * Kind::ALL.len());
}
