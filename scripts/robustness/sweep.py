#!/usr/bin/env python3
"""Robustness sweep: run `cvtmesh mesh` on awkward regions with several methods and sizes,
check every mesh it writes against the region, and classify each run.

    python3 scripts/robustness/sweep.py --quick      # ccvt and refine at K 30 and 300
    python3 scripts/robustness/sweep.py              # the full matrix, graded runs included

Classes:
    OK           exit 0; the mesh reads back (here and with `cvtmesh measure`); no inverted
                 triangle; every part of the region holds a triangle; the total triangle area
                 is within the region's tolerance of its area (1e-3 relative unless the manifest
                 states another); no triangle centroid outside the region (beyond the chord
                 allowance of regions marked "chord" in the manifest)
    CLEAN ERROR  non-zero exit, a stderr line starting with "error:", no output file left
    BUG          anything else: a panic (or exit 101), a timeout, output left after a failure,
                 a failure without an "error:" message, a mesh of a region that must be
                 refused, or a mesh failing a check above

Writes OUT/results.jsonl (one record per run) and OUT/summary.md; exits 1 if any run is a BUG.
Pure standard library.
"""
import argparse
import json
import math
import os
import re
import shlex
import subprocess
import sys
import threading
import time
from collections import Counter, defaultdict
from concurrent.futures import ThreadPoolExecutor

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_regions  # noqa: E402

ROOT = make_regions.repo_root()
CHORD_ALLOWANCE = 0.13  # the mesher's own allowance for a straight chord of a curved piece
FULL_METHODS = ("ccvt", "refine", "distmesh", "meshgen", "vtm")
QUICK_METHODS = ("ccvt", "refine")


# ----------------------------------------------------------------------------- plan

def graded_threshold(parts):
    xs = [p[0] for o, _ in parts for p in o]
    ys = [p[1] for o, _ in parts for p in o]
    d = math.hypot(max(xs) - min(xs), max(ys) - min(ys))
    return ",".join(f"{v:.6g}" for v in (d / 400, d / 20, d / 100, d / 5))


def plan(manifest, quick):
    runs = []
    for name, r in manifest.items():
        for m in QUICK_METHODS if quick else FULL_METHODS:
            for k in (30, 300) if quick else (30, 300, 3000):
                # The peers' iterations cost minutes at K 3000 and add no new geometry.
                if k == 3000 and m not in ("ccvt", "refine"):
                    continue
                runs.append(dict(id=f"{name}__{m}__{k}", region=name, method=m, K=k, graded=False, extra=[]))
        if r["graded"] and not quick:
            thr = graded_threshold(r["parts"])
            for k in (300, 3000):
                runs.append(dict(id=f"{name}__ccvt-graded__{k}", region=name, method="ccvt", K=k, graded=True,
                                 extra=["--size-toward", "loop:0", "--size-threshold", thr]))
    return runs


# ----------------------------------------------------------------------------- geometry

def shoelace(loop, ref):
    n = len(loop)
    x0, y0 = ref
    return 0.5 * math.fsum((loop[i][0] - x0) * (loop[(i + 1) % n][1] - y0)
                           - (loop[(i + 1) % n][0] - x0) * (loop[i][1] - y0) for i in range(n))


class Loop:
    """A closed polygon with its edges bucketed into horizontal bands, so that an even-odd ray
    test looks at a few edges instead of all 20000 of a digitized circle."""

    def __init__(self, pts):
        self.pts = pts
        n = len(pts)
        self.edges = [(pts[i][0], pts[i][1], pts[(i + 1) % n][0], pts[(i + 1) % n][1]) for i in range(n)]
        ys = [p[1] for p in pts]
        self.y0, y1 = min(ys), max(ys)
        self.nb = max(1, min(4096, n // 2))
        self.dy = (y1 - self.y0) / self.nb or 1.0
        self.bands = [[] for _ in range(self.nb)]
        for e in self.edges:
            if e[1] == e[3]:
                continue  # a horizontal edge is never crossed by a horizontal ray
            lo, hi = sorted((e[1], e[3]))
            for b in range(self._band(lo), self._band(hi) + 1):
                self.bands[b].append(e)

    def _band(self, y):
        return min(self.nb - 1, max(0, int((y - self.y0) / self.dy)))

    def contains(self, px, py):
        inside = False
        for x1, y1, x2, y2 in self.bands[self._band(py)]:
            if (y1 > py) != (y2 > py) and px < (x2 - x1) * (py - y1) / (y2 - y1) + x1:
                inside = not inside
        return inside

    def distance(self, px, py):
        best = math.inf
        for x1, y1, x2, y2 in self.edges:
            ex, ey = x2 - x1, y2 - y1
            ll = ex * ex + ey * ey
            t = 0.0 if ll == 0 else max(0.0, min(1.0, ((px - x1) * ex + (py - y1) * ey) / ll))
            best = min(best, math.hypot(px - x1 - t * ex, py - y1 - t * ey))
        return best


def read_node_ele(node):
    def rows(path):
        with open(path) as f:
            return [l.split() for l in (raw.split("#")[0].strip() for raw in f) if l]

    nr = rows(node)
    n, _, nattr, nmark = (int(v) for v in nr[0][:4])
    base = int(nr[1][0])
    xy = [(float(a[1]), float(a[2])) for a in nr[1:1 + n]]
    marker = [int(a[3 + nattr]) if nmark else 0 for a in nr[1:1 + n]]
    er = rows(node[:-len(".node")] + ".ele")
    tri = [(int(a[1]) - base, int(a[2]) - base, int(a[3]) - base) for a in er[1:1 + int(er[0][0])]]
    return xy, marker, tri



def area_tolerance(tol, k):
    """The relative area tolerance of a region's manifest entry at K (make_regions.py's docstring)."""
    if "rel" in tol and "c_over_K2" not in tol:
        return tol["rel"]
    floor = tol.get("rel", make_regions.DEFAULT_TOL)
    if "c_over_K2" in tol:
        return max(floor, tol["c_over_K2"] / k ** 2)
    return max(floor, tol["c_over_K"] / k)


def area_tolerance_text(tol):
    if "c_over_K2" in tol:
        return f"max({tol.get('rel', make_regions.DEFAULT_TOL):g}, {tol['c_over_K2']:g}/K²)"
    if "rel" in tol:
        return f"{tol['rel']:g}"
    return f"max({make_regions.DEFAULT_TOL:g}, {tol['c_over_K']:g}/K)"

def analyse(node, reg, k):
    """Area, inverted triangles, parts covered and centroids outside, relative to the region."""
    xy, marker, tri = read_node_ele(node)
    parts = reg["parts"]
    # Coordinates relative to a region vertex, so that a region at (1e6, 1e6) keeps its digits.
    ref = tuple(parts[0][0][0]) if parts else xy[0]
    p = [(x - ref[0], y - ref[1]) for x, y in xy]
    sa, cen, longest = [], [], []
    for a, b, c in tri:
        (ax, ay), (bx, by), (cx, cy) = p[a], p[b], p[c]
        sa.append(0.5 * ((bx - ax) * (cy - ay) - (by - ay) * (cx - ax)))
        cen.append(((ax + bx + cx) / 3, (ay + by + cy) / 3))
        longest.append(max(math.hypot(bx - ax, by - ay), math.hypot(cx - bx, cy - by), math.hypot(ax - cx, ay - cy)))
    used = set(v for t in tri for v in t)
    out = dict(nv=len(xy), nt=len(tri), mesh_area=math.fsum(sa), n_inverted=sum(1 for s in sa if s <= 0),
               unused_vertices=len(xy) - len(used))
    if not parts:
        return out
    loops = [[Loop([(x - ref[0], y - ref[1]) for x, y in o]), [Loop([(x - ref[0], y - ref[1]) for x, y in h]) for h in hs]]
             for o, hs in parts]
    claimed = [False] * len(tri)
    per = []
    for (o, hs), (lo, lhs) in zip(parts, loops):
        area = abs(shoelace(o, ref)) - math.fsum(abs(shoelace(h, ref)) for h in hs)
        idx = [i for i, (x, y) in enumerate(cen)
               if not claimed[i] and lo.contains(x, y) and not any(h.contains(x, y) for h in lhs)]
        for i in idx:
            claimed[i] = True
        per.append(dict(area=area, mesh=math.fsum(sa[i] for i in idx), ntri=len(idx)))
    region_area = math.fsum(q["area"] for q in per)
    outside = [i for i in range(len(tri)) if not claimed[i]]
    all_loops = [l for lo, lhs in loops for l in [lo] + lhs]
    bad = []
    for i in outside:
        if reg["chord"]:
            on = {marker[v] for v in tri[i] if marker[v] > 0}
            # No allowance for a triangle spanning two loops: that is how a ring narrower than
            # the spacing gets meshed across its hole.
            if len(on) < 2:
                d = min(l.distance(*cen[i]) for l in all_loops)
                if d <= CHORD_ALLOWANCE * longest[i]:
                    continue
        bad.append(i)
    rel_tol = area_tolerance(reg["area_tol"], k)
    out.update(region_area=region_area, rel_area_diff=(out["mesh_area"] - region_area) / region_area,
               area_tol=rel_tol, n_outside=len(bad), n_outside_allowed=len(outside) - len(bad),
               outside_area=math.fsum(abs(sa[i]) for i in bad), parts=per)
    if bad:
        out["first_outside"] = [cen[bad[0]][0] + ref[0], cen[bad[0]][1] + ref[1]]
    return out


# ----------------------------------------------------------------------------- runs

def show(path):
    rel = os.path.relpath(path, ROOT)
    return path if rel.startswith("..") else rel


def run_one(r, reg, ctx):
    region = os.path.join(ctx.regions, reg["file"])
    stem = os.path.join(ctx.runs, r["id"])
    outs = [stem + e for e in (".node", ".ele", ".poly")]
    for q in outs:
        if os.path.exists(q):
            os.remove(q)
    cmd = [ctx.bin, "mesh", region, "-n", str(r["K"]), "-m", r["method"], "-q", "-o", stem + ".node"] + r["extra"]
    env = dict(os.environ, RAYON_NUM_THREADS="1")
    t0 = time.monotonic()
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, errors="replace", env=env)
    try:
        _, err = proc.communicate(timeout=ctx.timeout)
        timed_out = False
    except subprocess.TimeoutExpired:
        proc.kill()
        _, err = proc.communicate()
        timed_out = True
    secs = time.monotonic() - t0
    with open(stem + ".err", "w") as f:
        f.write(err)
    # Messages without the scratch path, so that the same message from two regions reads alike.
    lines = [l.replace(ctx.regions + os.sep, "") for l in err.splitlines() if l.strip()]
    rec = dict(r, cmd="RAYON_NUM_THREADS=1 " + " ".join(shlex.quote(show(c)) if c.startswith("/") else shlex.quote(c)
                                                        for c in cmd),
               rc=proc.returncode, timed_out=timed_out, secs=round(secs, 3), stderr_tail=lines[-2:],
               files_after=[os.path.basename(q) for q in outs if os.path.exists(q)],
               error_line=next((l for l in lines if l.startswith("error:")), None),
               panic_line=next((l for l in lines if "panicked" in l), None),
               warnings=[l for l in lines if l.lower().startswith("warning")],
               not_converged="not converged" in err.lower())
    if proc.returncode == 0 and not timed_out and os.path.exists(stem + ".node"):
        try:
            q = subprocess.run([ctx.bin, "measure", stem + ".node", "-r", region, "--csv"], capture_output=True,
                               text=True, errors="replace", env=env, timeout=ctx.timeout)
            rows = q.stdout.strip().splitlines()
            if q.returncode == 0 and len(rows) >= 2:
                d = dict(zip(rows[0].split(","), rows[1].split(",")))
                rec["measure"] = {k: d[k] for k in ("K", "Ktilde", "alpha") if k in d}
            else:
                rec["measure_err"] = [l for l in q.stderr.splitlines() if l.strip()][-2:] or [f"exit {q.returncode}"]
        except subprocess.TimeoutExpired:
            rec["measure_err"] = [f"measure took over {ctx.timeout} s"]
        try:
            rec["check"] = analyse(stem + ".node", reg, r["K"])
        except Exception as e:  # a mesh that cannot be read back is itself the finding
            rec["check_err"] = repr(e)
    rec["class"], rec["kind"], rec["why"] = classify(rec, reg)
    return rec


def classify(r, reg):
    if r["timed_out"]:
        return "BUG", "timeout", f"still running after {r['secs']:.0f} s"
    if r["rc"] == 101 or r["panic_line"]:
        return "BUG", "panic", r["panic_line"] or "exit 101"
    if r["rc"] != 0:
        if r["files_after"]:
            return "BUG", "output after failure", f"exit {r['rc']} left " + ", ".join(r["files_after"])
        if not r["error_line"]:
            last = (r["stderr_tail"] or ["(no stderr)"])[-1]
            return "BUG", "unclear failure", f"exit {r['rc']} without an 'error:' line: {last}"
        return "CLEAN ERROR", "", r["error_line"]
    if reg["expect"] == "error":
        return "BUG", "accepted invalid input", f"exit 0 on a region that must be refused ({reg['note'] or r['region']})"
    if "check" not in r:
        return "BUG", "unreadable mesh", r.get("check_err", "exit 0 but no .node written")
    probs = []
    if "measure_err" in r:
        probs.append("cvtmesh measure failed: " + " | ".join(r["measure_err"]))
    c = r["check"]
    if c["n_inverted"]:
        probs.append(f"{c['n_inverted']} inverted or zero-area triangles")
    for i, p in enumerate(c.get("parts", [])):
        if p["ntri"] == 0:
            probs.append(f"part {i} (area {p['area']:.3g}) has no triangle")
    if "rel_area_diff" in c and abs(c["rel_area_diff"]) > c["area_tol"]:
        probs.append(f"area off by {c['rel_area_diff']:+.2e} (tolerance {c['area_tol']:.1e})")
    if c.get("n_outside"):
        x, y = c["first_outside"]
        probs.append(f"{c['n_outside']} triangle centroids outside the region, first at ({x:.6g}, {y:.6g})")
    if probs:
        return "BUG", "bad mesh", "; ".join(probs)
    return "OK", "", ""


# ----------------------------------------------------------------------------- report

def method_label(r):
    return "ccvt-graded" if r["graded"] else r["method"]


def count_table(recs):
    classes = ("OK", "CLEAN ERROR", "BUG")
    by = defaultdict(Counter)
    for r in recs:
        by[(method_label(r), r["K"])][r["class"]] += 1
    head = ["method", "K"] + list(classes) + ["runs", "seconds"]
    secs = defaultdict(float)
    for r in recs:
        secs[(method_label(r), r["K"])] += r["secs"]
    rows = [[m, str(k)] + [str(by[(m, k)][c]) for c in classes] + [str(sum(by[(m, k)].values())), f"{secs[(m, k)]:.0f}"]
            for m, k in sorted(by, key=lambda x: (FULL_METHODS.index(x[0]) if x[0] in FULL_METHODS else 9, x[1]))]
    tot = Counter(r["class"] for r in recs)
    rows.append(["all", ""] + [str(tot[c]) for c in classes] + [str(len(recs)), f"{sum(r['secs'] for r in recs):.0f}"])
    return head, rows


def text_table(head, rows):
    w = [max(len(x) for x in col) for col in zip(head, *rows)]

    def fmt(row):
        return "  ".join(v.ljust(n) if i < 2 else v.rjust(n) for i, (v, n) in enumerate(zip(row, w)))

    return "\n".join([fmt(head), fmt(["-" * n for n in w])] + [fmt(r) for r in rows])


def md_table(head, rows):
    return "\n".join(["| " + " | ".join(head) + " |", "|" + "---|" * len(head)] + ["| " + " | ".join(r) + " |" for r in rows])


def summary_md(recs, manifest, args, wall):
    out = [f"# cvtmesh robustness sweep ({'quick' if args.quick else 'full'})", "",
           f"{len(recs)} runs over {len({r['region'] for r in recs})} regions in {wall:.0f} s wall time, "
           f"timeout {args.timeout:g} s, {args.jobs} job(s), RAYON_NUM_THREADS=1.", ""]
    head, rows = count_table(recs)
    out += [md_table(head, rows), ""]
    bugs = [r for r in recs if r["class"] == "BUG"]
    out += ["## BUG", ""] + (["None."] if not bugs else [])
    for r in bugs:
        out += [f"- **{r['region']}** {method_label(r)} K={r['K']}: {r['kind']}: {r['why']}",
                f"  `{r['cmd']}`"]
    refused = [r for r in recs if r["class"] == "CLEAN ERROR" and manifest[r["region"]]["expect"] == "mesh"]
    out += ["", "## Refused although a mesh was expected (not counted as BUG)", ""] + (["None."] if not refused else [])
    out += [f"- {r['region']} {method_label(r)} K={r['K']}: {r['why']}" for r in refused]
    msgs = defaultdict(list)
    for r in recs:
        if r["class"] == "CLEAN ERROR":
            msgs[re.sub(r"[-+]?\d[\d.eE+-]*", "#", r["why"])[:160]].append(r["id"])
    out += ["", "## Distinct error messages (numbers as #)", ""]
    out += [f"- {len(ids)}x {m} (e.g. {ids[0]})" for m, ids in sorted(msgs.items(), key=lambda x: -len(x[1]))]
    off = [r for r in recs if r["class"] == "OK" and abs(r["check"]["nv"] - r["K"]) > max(2, 0.05 * r["K"])]
    out += ["", "## OK runs whose vertex count is more than 5 % from K", ""] + (["None."] if not off else [])
    out += [f"- {r['region']} {method_label(r)} K={r['K']}: {r['check']['nv']} vertices" for r in off]
    sliver = [(r, w) for r in recs if r["class"] == "OK" for w in r["warnings"] if "under 1°" in w]
    out += ["", "## OK runs with triangles under 1° (the warning, shortened)", ""] + (["None."] if not sliver else [])
    out += [f"- {r['region']} {method_label(r)} K={r['K']}: " + re.sub(r"^warning: | near .*$", "", w) + ")"
            for r, w in sliver]
    slow = sorted(recs, key=lambda r: -r["secs"])[:8]
    out += ["", "## Slowest runs", ""] + [f"- {r['id']}: {r['secs']:.1f} s ({r['class']})" for r in slow]
    out += ["", "## Regions", "", "| region | file | expect | area tolerance | note |", "|---|---|---|---|---|"]
    for name, m in manifest.items():
        if any(r["region"] == name for r in recs):
            t = area_tolerance_text(m["area_tol"])
            out.append(f"| {name} | {m['file']} | {m['expect']} | {t}{' +chord' if m['chord'] else ''} | {m['note']} |")
    return "\n".join(out) + "\n"


# ----------------------------------------------------------------------------- main

class Ctx:
    pass


def main():
    ap = argparse.ArgumentParser(description="Robustness sweep of `cvtmesh mesh` over awkward regions.")
    ap.add_argument("--quick", action="store_true", help="ccvt and refine at K 30 and 300, no graded runs")
    ap.add_argument("--bin", default=os.path.join(ROOT, "target", "release", "cvtmesh"),
                    help="cvtmesh binary (default target/release/cvtmesh)")
    ap.add_argument("--out", default=os.path.join(ROOT, "target", "robustness"),
                    help="scratch directory for regions, meshes and reports (default target/robustness)")
    ap.add_argument("--timeout", type=float, default=120, help="seconds per run (default 120)")
    ap.add_argument("--only", help="comma-separated region names")
    ap.add_argument("--jobs", type=int, default=1, help="runs at a time (default 1)")
    args = ap.parse_args()

    ctx = Ctx()
    ctx.bin = os.path.abspath(args.bin)
    ctx.timeout = args.timeout
    out = os.path.abspath(args.out)
    if not os.access(ctx.bin, os.X_OK):
        sys.exit(f"error: no executable at {ctx.bin} (build with `cargo build --release` or pass --bin)")
    # Never write into the tracked tree: inside the repository the directory must be ignored.
    if not os.path.relpath(out, ROOT).startswith(".."):
        ok = subprocess.run(["git", "-C", ROOT, "check-ignore", "-q", out], capture_output=True).returncode == 0
        if not ok:
            sys.exit(f"error: {show(out)} is inside the repository and not ignored by git; pick another --out")

    ctx.regions, manifest = make_regions.write_regions(out)
    ctx.runs = os.path.join(out, "runs")  # apart from regions/, so an output never names a region file
    os.makedirs(ctx.runs, exist_ok=True)
    runs = plan(manifest, args.quick)
    if args.only:
        names = args.only.split(",")
        unknown = [n for n in names if n not in manifest]
        if unknown:
            sys.exit(f"error: unknown region(s) {', '.join(unknown)}; known: {', '.join(manifest)}")
        runs = [r for r in runs if r["region"] in names]

    print(f"{len(runs)} runs, {args.jobs} at a time, timeout {args.timeout:g} s; output in {show(out)}", flush=True)
    t0 = time.monotonic()
    lock = threading.Lock()
    done = [0]

    def job(r):
        rec = run_one(r, manifest[r["region"]], ctx)
        with lock:
            done[0] += 1
            flag = rec["class"] if rec["class"] != "OK" else "ok"
            print(f"[{done[0]:4d}/{len(runs)} {time.monotonic() - t0:5.0f}s] {r['id']:42s} {flag:11s} "
                  f"{rec['secs']:6.2f}s {(rec['why'] or '')[:90]}", flush=True)
        return rec

    with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as ex:
        recs = list(ex.map(job, runs))
    wall = time.monotonic() - t0

    with open(os.path.join(out, "results.jsonl"), "w") as f:
        for rec in recs:
            f.write(json.dumps(rec) + "\n")
    with open(os.path.join(out, "summary.md"), "w") as f:
        f.write(summary_md(recs, manifest, args, wall))

    head, rows = count_table(recs)
    print()
    print(text_table(head, rows))
    bugs = [r for r in recs if r["class"] == "BUG"]
    for r in bugs:
        print(f"\nBUG {r['region']} {method_label(r)} K={r['K']}: {r['kind']}: {r['why']}\n    {r['cmd']}")
    print(f"\n{len(bugs)} BUG, wall time {wall:.0f} s; details in {show(os.path.join(out, 'summary.md'))} "
          f"and results.jsonl")
    sys.exit(1 if bugs else 0)


if __name__ == "__main__":
    main()
