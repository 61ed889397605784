#!/usr/bin/env bash
# Side-by-side: cvtmesh vs Triangle, Gmsh (Delaunay, Frontal-Delaunay) and DistMesh (distmeshpy)
# on the same regions at the same K, scored by `cvtmesh measure`, timed per mesher call.
# Needs the network once (PyPI) for its own virtual environment; not part of CI.
#   scripts/compare_tools.sh [--sizes 10000,100000] [--regions circle,lake] [--timeout 600]
#     [--tools triangle,gmsh-delaunay,gmsh-frontal,distmeshpy,cvtmesh] [--cvtmesh-max-iter N]
#     [--repeat N]   (the fastest of N timings of Triangle, Gmsh and cvtmesh at the K found)
#     [--pairs N]    (N more timings of Triangle and cvtmesh in alternation; the median ratio)
#     [--name compare] [--update]   (--update keeps the rows of results/compare/NAME.csv not redone)
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
top="$(dirname "$here")"
venv="$here/.venv"
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv"
  "$venv/bin/pip" install --quiet numpy triangle gmsh distmeshpy
fi
cargo build --release -p cvtmesh-cli --manifest-path "$top/Cargo.toml"
exec "$venv/bin/python" "$here/compare_tools.py" --cvtmesh "$top/target/release/cvtmesh" --domains "$top/crates/geometry/regions" --out "$top/results/compare" "$@"
