"""Does the real Triangle's mesh depend on the order of its input vertices?

For each table of the paper (region, K), the input `study --real-peers` gives Triangle (curves
split at the hexagonal spacing of K, straight edges whole, `-pq30a<A>` with A searched to K) is
meshed again with its vertices in random orders (segments renumbered to match), and the distinct
meshes are counted: the same vertex set and the same triangles, whatever their numbering.

    scripts/.venv/bin/python scripts/triangle_order.py [--orders 20] [--seed 1] [--min-angle 30]

Run from the repository root; scripts/compare_tools.sh makes scripts/.venv.
"""
import argparse
import csv
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


def paper_tables(root):
    """(table, region, K) of the paper's twelve tables, from the study's copy of them."""
    seen = {}
    with open(os.path.join(root, "study", "data", "paper_tables.csv")) as f:
        for row in csv.DictReader(f):
            seen[int(row["table"])] = (row["domain"], int(row["paper_K"]))
    return [(n, *seen[n]) for n in sorted(seen)]


def mesh_key(m):
    """The mesh as a set of triangles, each a sorted triple of vertex coordinates."""
    p, t = m["vertices"], m["triangles"]
    return frozenset(tuple(sorted(tuple(p[i]) for i in tri)) for tri in t)


def main():
    import numpy as np
    import triangle
    import compare_tools as ct

    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--orders", type=int, default=20, help="random orders per table")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--min-angle", type=float, default=30.0,
                    help="Triangle's -q bound (the study's TRIANGLE_MIN_ANGLE_DEG)")
    a = ap.parse_args()
    rng = np.random.default_rng(a.seed)
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    print("| table | region | K | K reached | switches | distinct meshes over orders |")
    print("| ---: | :--- | ---: | ---: | :--- | ---: |")
    for number, region, k in paper_tables(root):
        f = os.path.join(root, "crates", "geometry", "regions", f"{region}.json")
        area = json.load(open(f))["area"]
        info = {}
        ct.run_triangle(f, k, area, min_angle=a.min_angle, split_boundary=True, info=info, tries=30)
        switches = info["switches"]
        geom = ct.triangle_input(f, math.sqrt(2 * area / (math.sqrt(3) * k)))
        verts, segs = geom["vertices"], geom["segments"]
        keys, reached = set(), None
        for o in range(a.orders):
            perm = rng.permutation(len(verts)) if o else np.arange(len(verts))
            new_index = np.empty_like(perm)
            new_index[perm] = np.arange(len(perm))
            permuted = dict(geom, vertices=[verts[i] for i in perm],
                            segments=[[int(new_index[s]), int(new_index[e])] for s, e in segs])
            m = triangle.triangulate(permuted, switches)
            reached = len(m["vertices"])
            keys.add(mesh_key(m))
        print(f"| {number} | {region} | {k} | {reached} | `{switches}` | {len(keys)} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
