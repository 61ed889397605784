"""Does the real Triangle's mesh depend on the order of its input vertices?

For each table of the paper (region, K), the input `study --real-peers` gives Triangle (curves
split at the hexagonal spacing of K, straight edges whole, `-pq30a<A>` with A searched to K) is
meshed again with its vertices in random orders (segments renumbered to match), and the distinct
meshes are counted: the same vertex set and the same triangles, whatever their numbering.

    scripts/.venv/bin/python scripts/triangle_order.py [--orders 20] [--seed 1]

Run from the repository root; scripts/compare_tools.sh makes scripts/.venv.
"""
import argparse
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

# The paper's tables: (number, region, K), as in study/src/paper.rs.
TABLES = [(1, "circle", 19), (2, "circle", 88), (3, "circle", 362), (4, "annulus", 303),
          (5, "square_hole", 194), (6, "hex_hole", 240), (7, "horn", 138),
          (8, "superellipse", 505), (9, "bike_seat", 136), (10, "pie_hole", 287),
          (11, "square_two_hex", 203), (12, "lake", 1109)]
MIN_ANGLE = 30  # study/src/methods.rs, TRIANGLE_MIN_ANGLE_DEG


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
    a = ap.parse_args()
    rng = np.random.default_rng(a.seed)
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    print("| table | region | K | K reached | switches | distinct meshes over orders |")
    print("| ---: | :--- | ---: | ---: | :--- | ---: |")
    for number, region, k in TABLES:
        f = os.path.join(root, "crates", "geometry", "regions", f"{region}.json")
        area = json.load(open(f))["area"]
        info = {}
        ct.run_triangle(f, k, area, min_angle=MIN_ANGLE, split_boundary=True, info=info, tries=30)
        switches = info["switches"]
        h = math.sqrt(2 * area / (math.sqrt(3) * k))
        d, loops = ct.loops_of(f, h)
        verts, segs, off = [], [], 0
        for lp in loops:
            n = len(lp)
            verts += lp.tolist()
            segs += [[off + j, off + (j + 1) % n] for j in range(n)]
            off += n
        keys, reached = set(), None
        for o in range(a.orders):
            perm = rng.permutation(len(verts)) if o else np.arange(len(verts))
            new_index = np.empty_like(perm)
            new_index[perm] = np.arange(len(perm))
            geom = {"vertices": [verts[i] for i in perm],
                    "segments": [[int(new_index[s]), int(new_index[e])] for s, e in segs]}
            if d.get("hole_points"):
                geom["holes"] = d["hole_points"]
            m = triangle.triangulate(geom, switches)
            reached = len(m["vertices"])
            keys.add(mesh_key(m))
        print(f"| {number} | {region} | {k} | {reached} | `{switches}` | {len(keys)} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
