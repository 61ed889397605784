#!/usr/bin/env bash
# Rerun the whole study (release build) and rewrite results/ — including the CI regression
# baseline results/csv/metrics.csv that study/tests/golden.rs compares against — on purpose.
# Extra arguments go to `study` (e.g. --jobs 4). Review `git diff --stat results/` and commit.
set -euo pipefail
cd "$(dirname "$0")/.."
status=0
cargo run --release -p study -- --fresh --out results "$@" || status=$?
if [ "$status" -ne 0 ]; then
    echo "refresh_baseline: study exited with status $status (2 = some jobs failed; see results/csv/failures.csv)" >&2
    exit "$status"
fi
echo "refresh_baseline: rewrote results/ (baseline: results/csv/metrics.csv); review with git diff --stat results/ and commit"
