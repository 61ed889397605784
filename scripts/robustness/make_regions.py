#!/usr/bin/env python3
"""Write the awkward regions of the robustness sweep and their manifest.

    python3 scripts/robustness/make_regions.py [--out DIR]     (default target/robustness)

Files go to DIR/regions/, with DIR/regions/manifest.json holding one entry per region:

    file      the region file (.txt loop list, .geojson, .poly)
    expect    "mesh", "error" or "either" (either a mesh or a clean refusal is acceptable)
    parts     [[outer, [hole, ...]], ...]: what a mesh must cover, or null for invalid input
    graded    whether the sweep also runs a graded mesh toward loop 0
    area_tol  {"rel": t}: |mesh area / region area - 1| <= t
              {"c_over_K": c}: the same with t = max(1e-3, c / K)
              {"rel": t, "c_over_K2": c}: the same with max(t, c / K²)
    chord     true where mesh edges may cut across a curved or finely digitized boundary;
              a triangle centroid may then lie outside by 0.13 of its longest edge (the
              mesher's own conformity allowance), unless its corners lie on two loops
    note      what the region is, and why its tolerance is what it is

Pure standard library; the output is the same on every run.
"""
import argparse
import json
import math
import os
import random

DEFAULT_TOL = 1e-3


def circle(cx, cy, r, n, start=0.0):
    return [(cx + r * math.cos(start + 2 * math.pi * i / n), cy + r * math.sin(start + 2 * math.pi * i / n))
            for i in range(n)]


def linspace(a, b, n):
    return [a + (b - a) * i / (n - 1) for i in range(n)]


def gradient(v):
    """numpy.gradient with unit spacing: central differences inside, one-sided at the ends."""
    n = len(v)
    return [v[1] - v[0]] + [(v[i + 1] - v[i - 1]) / 2 for i in range(1, n - 1)] + [v[n - 1] - v[n - 2]]


def rev(loop):
    return list(reversed(loop))


def sarea(loop):
    # Relative to the first vertex, so that a region at (1e6, 1e6) keeps its digits.
    x0, y0 = loop[0]
    n = len(loop)
    return 0.5 * math.fsum((loop[i][0] - x0) * (loop[(i + 1) % n][1] - y0)
                           - (loop[(i + 1) % n][0] - x0) * (loop[i][1] - y0) for i in range(n))


def ccw(loop):
    return loop if sarea(loop) > 0 else rev(loop)


def cw(loop):
    return loop if sarea(loop) < 0 else rev(loop)


def fmt(v):
    return repr(float(v))


def ring(loop, close=True):
    r = [[float(x), float(y)] for x, y in loop]
    if close:
        r.append(r[0])
    return r


def poly_geom(outer, holes=(), close=True):
    return {"type": "Polygon", "coordinates": [ring(outer, close)] + [ring(h, close) for h in holes]}


class Writer:
    def __init__(self, out):
        self.out = out
        self.manifest = {}
        os.makedirs(out, exist_ok=True)

    def _path(self, name):
        return os.path.join(self.out, name)

    def txt(self, name, loops=None, raw=None):
        # newline="" keeps raw CRLF bytes as written.
        with open(self._path(name), "w", newline="") as f:
            if raw is not None:
                f.write(raw)
            else:
                f.write("\n\n".join("\n".join(f"{fmt(x)} {fmt(y)}" for x, y in l) for l in loops) + "\n")
        return name

    def geojson(self, name, obj):
        with open(self._path(name), "w") as f:
            json.dump(obj, f)
        return name

    def poly(self, name, loops, hole_points, base=1):
        """Triangle .poly: every loop a closed chain of segments, hole points listed."""
        verts, segs = [], []
        for li, l in enumerate(loops):
            s = len(verts)
            verts.extend(l)
            segs.extend((s + i, s + (i + 1) % len(l), li + 1) for i in range(len(l)))
        lines = [f"{len(verts)} 2 0 1"]
        lines += [f"{i + base} {fmt(x)} {fmt(y)} 0" for i, (x, y) in enumerate(verts)]
        lines.append(f"{len(segs)} 1")
        lines += [f"{i + base} {a + base} {b + base} {m}" for i, (a, b, m) in enumerate(segs)]
        lines.append(f"{len(hole_points)}")
        lines += [f"{i + base} {fmt(x)} {fmt(y)}" for i, (x, y) in enumerate(hole_points)]
        with open(self._path(name), "w") as f:
            f.write("\n".join(lines) + "\n")
        return name

    def add(self, key, file, expect, parts, graded=False, note="", area_tol=None, chord=False):
        if parts is not None:
            parts = [[[[float(x), float(y)] for x, y in o], [[[float(x), float(y)] for x, y in h] for h in hs]]
                     for o, hs in parts]
        assert key not in self.manifest, key
        self.manifest[key] = dict(file=file, expect=expect, parts=parts, graded=graded,
                                  area_tol=area_tol or {"rel": DEFAULT_TOL}, chord=chord, note=note)


def build(w):
    sq = [(0, 0), (1, 0), (1, 1), (0, 1)]
    h = [(0.3, 0.3), (0.7, 0.3), (0.7, 0.7), (0.3, 0.7)]

    # Thin wedges: the tip is narrower than any spacing.
    for deg, ext in ((1, "txt"), (5, "geojson")):
        a = math.radians(deg)
        wedge = [(0.0, 0.0), (1.0, 0.0), (math.cos(a), math.sin(a))]
        name = f"wedge{deg}.{ext}"
        if ext == "txt":
            w.txt(name, [wedge])
        else:
            w.geojson(name, poly_geom(wedge))
        w.add(f"wedge{deg}", name, "either", [[wedge, []]], graded=True, note=f"{deg} deg wedge, length 1")

    r20 = [(0, 0), (20, 0), (20, 1), (0, 1)]
    w.add("rect20", w.poly("rect20.poly", [r20], []), "mesh", [[r20, []]], note="20:1")
    r1000 = [(0, 0), (10, 0), (10, 0.01), (0, 0.01)]
    w.add("rect1000", w.txt("rect1000.txt", [r1000]), "either", [[r1000, []]], note="1000:1, 10 x 0.01")

    s = 5e-5
    ls = [(0, 0), (0.5 - s, 0), (0.5 - s, 0.6), (0.5 + s, 0.6), (0.5 + s, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]
    w.add("L_slit", w.txt("L_slit.txt", [ls]), "either", [[ls, []]], graded=True,
          note="L with a slit 1e-4 wide, 0.6 deep")

    comb = [(0, 0), (1, 0), (1, 0.2)]
    for i in reversed(range(20)):
        xl, xr = i * 0.05 + 0.015, i * 0.05 + 0.035
        comb += [(xr, 0.2), (xr, 1.0), (xl, 1.0), (xl, 0.2)]
    comb += [(0, 0.2)]
    w.add("comb20", w.geojson("comb20.geojson", {"type": "Feature", "properties": {}, "geometry": poly_geom(comb)}),
          "mesh", [[comb, []]], graded=True, note="20 teeth 0.02 x 0.8, a GeoJSON Feature")

    star = [(math.cos(2 * math.pi * i / 100) * (1.0 if i % 2 == 0 else 0.4),
             math.sin(2 * math.pi * i / 100) * (1.0 if i % 2 == 0 else 0.4)) for i in range(100)]
    w.add("star50", w.txt("star50.txt", [star]), "mesh", [[star, []]], graded=True, note="50 spikes")

    outer = [(0, 0), (1.6, 0), (1.6, 1), (0, 1)]
    holes, hp = [], []
    for i in range(8):
        for j in range(5):
            cx, cy = 0.1 + 0.2 * i, 0.1 + 0.2 * j
            holes.append(cw(circle(cx, cy, 0.03, 6, 0.3)))
            hp.append((cx, cy))
    w.add("holes40", w.poly("holes40.poly", [outer] + holes, hp), "mesh", [[outer, holes]], graded=True,
          note="40 hexagonal holes r=0.03")

    g = 1e-4
    ha = [(0.2, 0.4), (0.4, 0.4), (0.4, 0.6), (0.2, 0.6)]
    hb = [(0.4 + g, 0.4), (0.6, 0.4), (0.6, 0.6), (0.4 + g, 0.6)]
    hc = [(0.7, g), (0.9, g), (0.9, 0.2), (0.7, 0.2)]
    w.add("holes_touch", w.geojson("holes_touch.geojson", poly_geom(sq, [rev(ha), rev(hb), rev(hc)])),
          "either", [[sq, [ha, hb, hc]]], note="holes 1e-4 apart and 1e-4 from the outer boundary")

    ao, ai = circle(0, 0, 1.0, 256), cw(circle(0, 0, 0.999, 256))
    w.add("thin_annulus", w.txt("thin_annulus.txt", [ao, ai]), "either", [[ao, [ai]]],
          area_tol={"rel": 3e-3, "c_over_K2": round(2000 * math.pi ** 2)}, chord=True,
          note="ring 1e-3 wide between 256-gons whose corners turn 1.4 deg and are not kept; where the ring "
               "holds only boundary vertices (4 pi / K apart), chords across those corners change the area "
               "by up to 2000 pi^2 / K^2: 2.2e-3 at K = 3000, 0.22 at K = 300 (1.3e-2 measured)")

    base = [(0, 0), (1, 0), (1.2, 0.7), (0.5, 1), (-0.1, 0.6)]
    huge = [(x + 1e6, y + 1e6) for x, y in base]
    w.add("huge_offset", w.txt("huge_offset.txt", [huge]), "mesh", [[huge, []]], graded=True,
          note="pentagon of size 1 at (1e6, 1e6)")
    lb = [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]
    tiny = [(x * 1e-6, y * 1e-6) for x, y in lb]
    w.add("tiny", w.geojson("tiny.geojson", poly_geom(tiny)), "mesh", [[tiny, []]], note="L of size 2e-6")

    # A star-shaped noisy coastline: radius = a random Fourier series with a k^-1.1 spectrum.
    rng = random.Random(12345)
    n = 5000
    modes = [(0.25 * k ** -1.1 * rng.gauss(0, 1), k, rng.uniform(0, 2 * math.pi)) for k in range(1, 1200)]
    ts = [2 * math.pi * i / n for i in range(n)]
    rs = [1 + math.fsum(a * math.sin(k * t + p) for a, k, p in modes) for t in ts]
    lo, hi = min(rs), max(rs)
    rs = [0.3 + 0.7 * (r - lo) / (hi - lo) for r in rs]
    coast = [(r * math.cos(t), r * math.sin(t)) for r, t in zip(rs, ts)]
    w.add("coast5000", w.txt("coast5000.txt", [coast]), "mesh", [[coast, []]], graded=True,
          area_tol={"rel": 3e-3}, chord=True,
          note="5000-point noisy coastline; about 1600 corners turn by more than 30 deg and are kept, chords "
               "cut across the other points (1.5e-3 of the area at K = 3000); K < 1600 is refused")

    m = 100
    beta = linspace(0, math.pi, m + 1)
    xc = [0.5 * (1 - math.cos(b)) for b in beta]
    yt = [0.6 * (0.2969 * math.sqrt(x) - 0.1260 * x - 0.3516 * x ** 2 + 0.2843 * x ** 3 - 0.1036 * x ** 4)
          for x in xc]
    upper = list(zip(xc[::-1], yt[::-1]))  # trailing edge to leading edge over the top
    lower = list(zip(xc[1:-1], [-y for y in yt[1:-1]]))  # back underneath, no repeated point
    foil = [(1.0, 0.0)] + upper[1:] + lower
    box = [(-1, -1), (2, -1), (2, 1), (-1, 1)]
    share = abs(sarea(foil)) / (abs(sarea(box)) - abs(sarea(foil)))
    w.add("naca0012_box", w.poly("naca0012_box.poly", [box, cw(foil)], [(0.3, 0.0)]), "mesh", [[box, [foil]]],
          graded=True, area_tol={"rel": round(0.5 * share, 5)}, chord=True,
          note=f"NACA 0012 hole with a sharp trailing edge in a 3 x 2 box; the 200-point foil is {share:.2%} of "
               "the area and is followed by chords (coarsely in graded runs, which refine toward the box), "
               "so the tolerance is half the foil's share")

    dup = [(0, 0), (0, 0), (0.5, 0), (1, 0), (1, 0), (1, 0.5), (1, 1), (0.5, 1), (0.25, 1), (0, 1), (0, 1),
           (0, 0.5), (0, 0)]
    w.add("dup_collinear", w.txt("dup_collinear.txt", [dup]), "error", None,
          note="repeated and collinear points, closing point repeated: a repeated consecutive point is "
               "refused with its position")

    w.add("orient_cw_cw", w.txt("orient_cw_cw.txt", [cw(sq), cw(h)]), "mesh", [[sq, [h]]], note="outer CW, hole CW")
    w.add("orient_ccw_ccw", w.txt("orient_ccw_ccw.txt", [ccw(sq), ccw(h)]), "mesh", [[sq, [h]]],
          note="outer CCW, hole CCW")
    w.add("orient_cw_geo", w.geojson("orient_cw.geojson", poly_geom(cw(sq), [ccw(h)])), "mesh", [[sq, [h]]],
          note="GeoJSON against the right-hand rule")

    # Spiral corridor: offset an Archimedean spiral by half the width along its normal.
    th = linspace(0, 6 * math.pi, 700)
    a0, b0, width = 0.15, 0.12 / (2 * math.pi), 0.04
    cx = [(a0 + b0 * t) * math.cos(t) for t in th]
    cy = [(a0 + b0 * t) * math.sin(t) for t in th]
    dx, dy = gradient(cx), gradient(cy)
    left, right = [], []
    for x, y, u, v in zip(cx, cy, dx, dy):
        nn = math.hypot(u, v)
        nx, ny = -v / nn, u / nn
        left.append((x + nx * width / 2, y + ny * width / 2))
        right.append((x - nx * width / 2, y - ny * width / 2))
    spiral = ccw(left + right[::-1])
    w.add("spiral", w.geojson("spiral.geojson", poly_geom(spiral)), "mesh", [[spiral, []]], graded=True,
          area_tol={"c_over_K": 1.0}, chord=True,
          note="3 turns, width 0.04, pitch 0.12, 1400 points; edges cut across the digitized curve")

    p1 = [(0, 0), (1, 0), (1, 1), (0, 1)]
    p2 = [(2, 0), (2.1, 0), (2.1, 0.1), (2, 0.1)]
    p3 = [(3, 0), (3.01, 0), (3.01, 0.01), (3, 0.01)]
    multi = [[p1, []], [p2, []], [p3, []]]
    w.add("multi3_geo", w.geojson("multi3.geojson", {"type": "MultiPolygon", "coordinates": [[ring(p)] for p in (p1, p2, p3)]}),
          "mesh", multi, note="three parts of areas 1, 1e-2, 1e-4")
    w.add("multi3_poly", w.poly("multi3.poly", [p1, p2, p3], []), "mesh", multi,
          note="three parts of areas 1, 1e-2, 1e-4")

    big = [(0, 0), (10, 0), (10, 10), (0, 10)]
    lake = [(3, 3), (7, 3), (7, 7), (3, 7)]
    isl = [(4, 4), (6, 4), (6, 6), (4, 6)]
    w.add("island_lake", w.geojson("island_lake.geojson", {"type": "MultiPolygon", "coordinates": [
        [ring(big), ring(rev(lake))], [ring(isl)]]}), "mesh", [[big, [lake]], [isl, []]])
    w.add("island_lake_txt", w.txt("island_lake.txt", [big, lake, isl]), "mesh", [[big, [lake]], [isl, []]],
          note="loop list; nesting decides which loop is a hole")

    fig8 = [(0, 0), (1, -1), (1, 1), (0, 0), (-1, 1), (-1, -1)]
    w.add("fig8", w.txt("fig8.txt", [fig8]), "either",
          [[[(0, 0), (1, -1), (1, 1)], []], [[(0, 0), (-1, 1), (-1, -1)], []]],
          note="one loop: two triangles meeting at a vertex")
    hv = [(0, 0.5), (0.5, 0.3), (0.5, 0.7)]
    sqm = [(0, 0), (1, 0), (1, 1), (0, 1), (0, 0.5)]
    w.add("hole_touch_vertex", w.txt("hole_touch_vertex.txt", [sqm, hv]), "either", [[sqm, [hv]]],
          note="hole sharing a vertex with the outer loop")
    w.add("bowtie", w.geojson("bowtie.geojson", poly_geom([(0, 0), (1, 1), (1, 0), (0, 1)])), "error", None,
          note="self-intersecting")
    ov2 = [(0.5, 0.5), (1.5, 0.5), (1.5, 1.5), (0.5, 1.5)]
    w.add("overlap", w.txt("overlap.txt", [sq, ov2]), "error", None, note="two loops crossing")

    w.add("twopoint", w.txt("twopoint.txt", [[(0, 0), (1, 1)]]), "error", None)
    w.add("collinear", w.txt("collinear.txt", [[(0, 0), (1, 1), (2, 2), (3, 3)]]), "error", None)
    w.add("square_plus_2pt", w.txt("square_plus_2pt.txt", [sq, [(0.3, 0.3), (0.6, 0.6)]]), "error", None,
          note="valid outer loop and a 2-point 'hole'")
    w.add("nan", w.txt("nan.txt", raw="0 0\n1 0\nnan 1\n0 1\n"), "error", None)
    w.add("inf", w.txt("inf.txt", raw="0 0\n1 0\ninf 1\n0 1\n"), "error", None)
    w.add("empty", w.txt("empty.txt", raw=""), "error", None)
    w.add("linestring", w.geojson("linestring.geojson", {"type": "LineString", "coordinates": [[0, 0], [1, 0], [1, 1], [0, 0]]}),
          "error", None)
    w.add("point", w.geojson("point.geojson", {"type": "Point", "coordinates": [0, 0]}), "error", None)
    w.add("garbage_json", w.txt("garbage.geojson", raw='{"type": "Polygon", "coordinates": [[[0,0],[1,0],[1,1]'),
          "error", None, note="truncated JSON")

    w.add("crlf", w.txt("crlf.txt", raw="0 0\r\n1 0\r\n1 1\r\n0 1\r\n"), "mesh", [[sq, []]], note="Windows line endings")
    w.add("comma", w.txt("comma.txt", raw="0,0\n1,0\n1,1\n0,1\n"), "either", [[sq, []]], note="x,y separated by commas")
    w.add("header", w.txt("header.txt", raw="# my square\nx y\n0 0\n1 0\n1 1\n0 1\n"), "either", [[sq, []]],
          note="comment and header line")
    w.add("blank_lines_split", w.txt("tabs_trailing.txt", raw="  0\t0  \n1\t0\n\n\n1 1\n"), "error", None,
          note="tabs; blank lines split a 3-point loop into 2 + 1")
    fc = {"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {"name": "a"}, "geometry": poly_geom(sq, [rev(h)])},
        {"type": "Feature", "properties": {"name": "b"}, "geometry": poly_geom([(2, 0), (3, 0), (3, 1), (2, 1)])}]}
    w.add("featurecoll", w.geojson("featurecoll.geojson", fc), "mesh",
          [[sq, [h]], [[(2, 0), (3, 0), (3, 1), (2, 1)], []]], note="FeatureCollection of 2 polygons")
    w.add("geo3d", w.geojson("geo3d.geojson", {"type": "Polygon", "coordinates": [[[x, y, 5.0] for x, y in ring(sq)]]}),
          "either", [[sq, []]], note="coordinates with z")
    w.add("unclosed_geo", w.geojson("unclosed.geojson", poly_geom(sq, close=False)), "either", [[sq, []]],
          note="ring whose first point is not repeated last")

    d = math.tan(math.radians(0.5)) * 0.6
    notch = [(0, 0), (1, 0), (1, 1), (0.5 + d, 1), (0.5, 0.4), (0.5 - d, 1), (0, 1)]
    w.add("notch1", w.poly("notch1.poly", [notch], []), "mesh", [[notch, []]], note="1 deg re-entrant notch 0.6 deep")
    w.add("poly0based", w.poly("poly0based.poly", [sq, cw(h)], [(0.5, 0.5)], base=0), "mesh", [[sq, [h]]],
          note="0-based indices")
    w.add("poly_nohole", w.poly("poly_nohole.poly", [sq, cw(h)], []), "error", None,
          note="inner loop without a hole point")

    dc = circle(0, 0, 1, 20000)
    w.add("circle20k", w.txt("circle20k.txt", [dc]), "mesh", [[dc, []]], area_tol={"c_over_K": 1.5}, chord=True,
          note="20000-gon; no corner is kept, so the mesh is a polygon inscribed in it, about pi/(3 sqrt(3) K) "
               "short of its area (more where the boundary spacing is coarser)")
    saw = [(0, 0)] + [((i + 0.5) / 200, -0.002 if i % 2 == 0 else 0.0) for i in range(200)] + [(1, 0), (1, 0.3), (0, 0.3)]
    w.add("sawtooth", w.txt("sawtooth.txt", [ccw(saw)]), "mesh", [[saw, []]], note="100 teeth 0.002 deep on one side")


def write_regions(out_dir):
    """Write every region into out_dir/regions; return (regions directory, manifest)."""
    reg = os.path.join(out_dir, "regions")
    w = Writer(reg)
    build(w)
    with open(os.path.join(reg, "manifest.json"), "w") as f:
        json.dump(w.manifest, f, indent=1)
    return reg, w.manifest


def repo_root():
    return os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default=os.path.join(repo_root(), "target", "robustness"),
                    help="scratch directory; regions go to OUT/regions (default target/robustness)")
    a = ap.parse_args()
    reg, man = write_regions(os.path.abspath(a.out))
    print(f"{len(man)} regions written to {reg}")


if __name__ == "__main__":
    main()
