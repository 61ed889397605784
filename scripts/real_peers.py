"""Mesh one region at one K with the real Triangle or the real Gmsh (Frontal-Delaunay), for
`study --real-peers`; the meshing itself is scripts/compare_tools.py's.

    real_peers.py --check
        prints `real_peers: ok triangle=<version> gmsh=<version> numpy=<version>` and exits 0,
        or one line naming what is missing and exits 3.
    real_peers.py --tool triangle|gmsh-frontal --region REGION.json --k K --out BASE
                  [--min-angle DEG] [--split-boundary] [--sample-straight]
        writes BASE.node and BASE.ele (1-based, Triangle's format) and prints one line
        `real_peers: tool=<tool> K=<vertices> triangles=<n> seconds=<mesher time> params=<...>`;
        on failure one line `real_peers: error <message>` and exit 1.

Both tools are deterministic, so there is no seed.
"""
import argparse
import importlib.metadata
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

MISSING_EXIT = 3
# More steps of the size searches than compare_tools' defaults: the study compares at the
# paper's K, and K(size) jumps, so the fixed-point steps can cycle before settling.
TRIANGLE_TRIES = 30
GMSH_TRIES = 12
SETUP = "scripts/compare_tools.sh makes scripts/.venv with them"


def check():
    versions, missing = {}, []
    for name in ("numpy", "triangle", "gmsh"):
        try:
            __import__(name)
            versions[name] = importlib.metadata.version(name)
        except Exception:  # an absent package, or one that fails to load its library
            missing.append(name)
    if missing:
        print(f"real_peers: missing Python package(s) {', '.join(missing)} in {sys.executable}; {SETUP}")
        return MISSING_EXIT
    print("real_peers: ok " + " ".join(f"{k}={v}" for k, v in sorted(versions.items())))
    return 0


def run(a):
    import compare_tools as ct

    area = json.load(open(a.region))["area"]
    info = {}
    if a.tool == "triangle":
        p, t, sec = ct.run_triangle(a.region, a.k, area, min_angle=a.min_angle,
                                    split_boundary=a.split_boundary, info=info, tries=TRIANGLE_TRIES,
                                    split_lines=a.sample_straight)
        params = info.get("switches", "")
    else:
        # Gmsh's algorithm 6 is Frontal-Delaunay.
        p, t, sec = ct.run_gmsh(a.region, a.k, area, 6, info=info, tries=GMSH_TRIES,
                                size_from_boundary=False)
        params = (f"Mesh.Algorithm=6,MeshSizeExtendFromBoundary=0,"
                  f"MeshSize={info.get('size', float('nan')):.17g}")
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    ct.write_node_ele(a.out, p, t)
    print(f"real_peers: tool={a.tool} K={len(p)} triangles={len(t)} seconds={sec!r} params={params}")
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--check", action="store_true", help="report whether numpy, triangle and gmsh import")
    ap.add_argument("--tool", choices=["triangle", "gmsh-frontal"])
    ap.add_argument("--region", help="region file (the JSON schema of crates/geometry/regions)")
    ap.add_argument("--k", type=int, help="vertices wanted")
    ap.add_argument("--out", help="output base name: BASE.node and BASE.ele")
    ap.add_argument("--min-angle", type=float, default=20.0, help="Triangle's -q bound in degrees")
    ap.add_argument("--split-boundary", action="store_true",
                    help="let Triangle split boundary segments (without it, -Y keeps them as sampled)")
    ap.add_argument("--sample-straight", action="store_true",
                    help="give Triangle straight edges split at the spacing of K, as curves are")
    a = ap.parse_args()
    if a.check:
        return check()
    if not (a.tool and a.region and a.k and a.out):
        ap.error("--tool, --region, --k and --out are needed (or --check)")
    if check_quiet():
        return MISSING_EXIT
    try:
        return run(a)
    except (Exception, SystemExit) as e:  # one line for the study, whatever went wrong
        print(f"real_peers: error {type(e).__name__}: {str(e).splitlines()[0] if str(e) else ''}")
        return 1


def check_quiet():
    """Print the missing-package line, if any, and say whether something is missing."""
    for name in ("numpy", "triangle", "gmsh"):
        try:
            __import__(name)
        except Exception:
            return check() == MISSING_EXIT
    return False


if __name__ == "__main__":
    sys.exit(main())
