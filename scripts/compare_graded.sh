#!/usr/bin/env bash
# Graded meshes: cvtmesh against Gmsh Frontal-Delaunay with the same Distance + Threshold size
# field at the same vertex count (scripts/compare_graded.py). Needs the network once (PyPI) for
# its own virtual environment; not part of CI.
#   scripts/compare_graded.sh [--sizes 10000,100000] [--cases circle-point,l-corner,square_hole-hole,lake-shores]
#     [--seeds N] [--cvtmesh-args "--tol 1e-3"] [--out DIR]
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
top="$(dirname "$here")"
venv="$here/.venv"
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv"
  "$venv/bin/pip" install --quiet numpy triangle gmsh distmeshpy
fi
cargo build --release -p cvtmesh-cli --manifest-path "$top/Cargo.toml"
exec "$venv/bin/python" "$here/compare_graded.py" --cvtmesh "$top/target/release/cvtmesh" \
  --domains "$top/crates/geometry/regions" --regions-extra "$here/regions" \
  --out "$top/results/compare/graded" "$@"
