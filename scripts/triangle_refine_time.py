"""The real Triangle's time per vertex for one refinement, the peer of
`cargo bench -p cvtmesh-refine --bench refine` (run the two in the same minutes).

Triangle (the Python package) meshes the input `scripts/compare_tools.py` builds for the circle
and the lake (curves sampled at the hexagonal spacing of n vertices) with `-pq20a<A>`, A that
spacing's equilateral area ×1.1, best of 3 calls. Prints the bench's Markdown columns.

    scripts/.venv/bin/python scripts/triangle_refine_time.py [--sizes 10000,100000]

Run from the repository root; scripts/compare_tools.sh makes scripts/.venv.
"""
import argparse
import json
import math
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import compare_tools  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="10000,100000")
    args = ap.parse_args()
    import triangle
    here = os.path.dirname(os.path.abspath(__file__))
    regions = os.path.join(os.path.dirname(here), "crates", "geometry", "regions")
    print("| region | mesher | vertices | s | µs per vertex |")
    print("|---|---|---|---|---|")
    for name in ("circle", "lake"):
        path = os.path.join(regions, f"{name}.json")
        area = json.load(open(path))["area"]
        for n in (int(s) for s in args.sizes.split(",")):
            h = math.sqrt(2 * area / (math.sqrt(3) * n))
            geom = compare_tools.triangle_input(path, h)
            a = 1.1 * math.sqrt(3) / 4 * h * h
            best, m = math.inf, None
            for _ in range(3):
                t0 = time.perf_counter()
                m = triangle.triangulate(geom, f"pq20a{a:.20f}")
                best = min(best, time.perf_counter() - t0)
            v = len(m["vertices"])
            print(f"| {name} | Triangle -pq20a | {v} | {best:.3f} | {1e6 * best / v:.2f} |")


if __name__ == "__main__":
    main()
