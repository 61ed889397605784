//! What the regression tests share: where a committed baseline lives and when two values agree.
//!
//! Tolerance: |now − committed| ≤ 1e-6 · max(|now|, |committed|) + 1e-15. Every method is
//! deterministic for a seed and Rust does no floating-point contraction, so on one platform
//! the numbers are normally bit-identical whatever the optimisation level; the slack absorbs
//! reduction-order differences of parallel sums when the thread count differs.
use std::path::PathBuf;

pub const REL_TOL: f64 = 1e-6;
pub const ABS_TOL: f64 = 1e-15;

/// `results/csv/NAME` of the repository.
pub fn baseline_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join("results")
        .join("csv")
        .join(name)
}

/// Equal within the tolerance (NaN agrees with NaN).
pub fn close(a: f64, b: f64) -> bool {
    a == b
        || (a.is_nan() && b.is_nan())
        || (a - b).abs() <= REL_TOL * a.abs().max(b.abs()) + ABS_TOL
}
